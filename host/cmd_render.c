/* cmd_render.c: `strandlight render SCENE.json`: loads the scene, its hair and environment,
 * renders a frame and writes the EXR (+ PNG preview). Until the real passes land the frame comes
 * from the placeholder renderer (host/render_preview.h), and the command says so on stderr. */
#include "camera.h"
#include "cli.h"
#include "clrt.h"
#include "env_lighting.h"
#include "hair.h"
#include "image_write.h"
#include "lights.h"
#include "render_preview.h"
#include "scene.h"
#include "scene_hair.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *usage_text =
    "usage: strandlight render SCENE.json [options]\n"
    "\n"
    "Renders SCENE.json (format: ../shared/spec/scene.md, README) to an OpenEXR file and a PNG\n"
    "preview. Options override the scene's output and image settings:\n"
    "  --exr FILE          EXR output (default: output.exr of the scene, else out/frame.exr)\n"
    "  --png FILE          PNG preview (default: output.png of the scene, if any)\n"
    "  --width W, --height H   image size\n"
    "  --device SPEC       auto|gpu|pocl|c|opencl|P:D (default auto)\n"
    "  --clamp-nonfinite   replace NaN/Inf pixels of the environment map by 0 (else an error)\n"
    "\n"
    "NOTE: this version shades with a PLACEHOLDER renderer: the real fiber scattering function\n"
    "against the SRBF lobes taken as directional lights, without self-shadowing or multiple\n"
    "scattering. With only environment.file, quality.lobes lobes are fitted and cached.\n";


static int write_outputs(const sl_frame *f, const char *exr, const char *png, int use_float,
                         sl_err *e) {
    size_t n = (size_t)f->width * f->height;
    float *plane = sl_malloc(5 * n * sizeof(float));
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 4; c++) plane[c * n + i] = f->rgba[4 * i + c];
        plane[4 * n + i] = f->depth[i];
    }
    sl_exr_channel ch[5] = {{"R", plane}, {"G", plane + n}, {"B", plane + 2 * n},
                            {"A", plane + 3 * n}, {"Z", plane + 4 * n}};
    int rc = sl_exr_write(exr, f->width, f->height, ch, 5, use_float, e);
    free(plane);
    if (rc) return -1;
    if (png && png[0] && sl_png_write(png, f->width, f->height, f->rgba, 0.0f, e)) return -1;
    return 0;
}

int cmd_render(int argc, char **argv) {
    const char *scene_path = NULL, *exr = NULL, *png = NULL, *device = "auto", *v;
    long width = 0, height = 0;
    int clamp_nonfinite = 0, missing = 0;
    for (int i = 1; i < argc; i++) {
        if (cli_is_help(argv[i])) {
            fputs(usage_text, stdout);
            return 0;
        } else if (cli_opt(argc, argv, &i, "--exr", &exr, &missing) ||
                   cli_opt(argc, argv, &i, "--png", &png, &missing) ||
                   cli_opt(argc, argv, &i, "--device", &device, &missing)) {
            if (missing) return 2;
        } else if (cli_opt(argc, argv, &i, "--width", &v, &missing)) {
            if (missing || cli_int("render", "--width", v, 1, 16384, &width)) return 2;
        } else if (cli_opt(argc, argv, &i, "--height", &v, &missing)) {
            if (missing || cli_int("render", "--height", v, 1, 16384, &height)) return 2;
        } else if (strcmp(argv[i], "--clamp-nonfinite") == 0) {
            clamp_nonfinite = 1;
        } else if (argv[i][0] == '-') {
            return cli_usage_error("render", "unknown option %s", argv[i]);
        } else if (!scene_path) {
            scene_path = argv[i];
        } else {
            return cli_usage_error("render", "more than one scene given");
        }
    }
    if (!scene_path) return cli_usage_error("render", "no scene file given");

    sl_err e = {{0}};
    sl_scene *s = sl_malloc(sizeof *s);
    sl_hair h = {0};
    sl_lobes lobes = {0};
    sl_lights lights = {0};
    sl_frame frame = {0};
    sl_device dev = {0};
    int rc = 1;
    double t0 = sl_now();
    if (sl_scene_load(scene_path, s, &e)) goto done;
    if (width) s->width = (int)width;
    if (height) s->height = (int)height;
    if (sl_device_open(device, &dev, &e)) goto done;
    if (sl_scene_load_hair(s, &h, &e)) goto done;
    if (sl_scene_lobes(s, clamp_nonfinite, &lobes, &e)) goto done;
    sl_lobes_transform(&lobes, s->env_rotation_deg, s->env_intensity);
    if (sl_lights_from_lobes(&lobes, &lights, &e)) goto done;
    float lo[3], hi[3];
    sl_hair_bounds(&h, lo, hi);
    double target[3];
    for (int k = 0; k < 3; k++) target[k] = s->has_target ? s->target[k] : 0.5 * (lo[k] + hi[k]);
    sl_camera cam;
    sl_camera_setup(&cam, s->has_eye ? s->eye : NULL, target, s->up, s->fov_deg, s->width,
                    s->height, lo, hi);
    sl_warn("render: PLACEHOLDER shading (fiber function x %d SRBF lobes taken as directional "
            "lights, no shadows, no multiple scattering); %s is used for nothing yet",
            lights.count, dev.name);
    if (sl_render_preview(&s->material, &h, &lights, &cam, &frame, &e)) goto done;
    const char *exr_path = exr ? exr : (s->out_exr[0] ? s->out_exr : "out/frame.exr");
    const char *png_path = png ? png : s->out_png;
    if (write_outputs(&frame, exr_path, png_path, s->exr_float, &e)) goto done;
    sl_note("render: %u strands, %u points, %dx%d -> %s%s%s (%.2f s)", h.num_strands, h.num_points,
            s->width, s->height, exr_path, png_path && png_path[0] ? " + " : "",
            png_path ? png_path : "", sl_now() - t0);
    rc = 0;
done:
    if (rc) fprintf(stderr, "strandlight: %s\n", e.msg);
    sl_frame_free(&frame);
    sl_lights_free(&lights);
    sl_lobes_free(&lobes);
    sl_hair_free(&h);
    sl_device_close(&dev);
    free(s);
    return rc;
}
