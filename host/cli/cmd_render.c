/* cmd_render.c: `strandlight render SCENE.json`: loads the scene, its hair and environment
 * lobes, renders the frame with the pass planner of host/plan/frame.h (view pass + K-buffer, light
 * pass per lobe, SRBF shading x transmittance, multiple scattering) and writes the EXR (beauty,
 * alpha, depth and the selected AOVs) + PNG preview. --orbit N renders N frames around the hair
 * reusing every light pass; --frames A:B renders a sub-range, bit-identical to the same frames
 * of a full run (each frame depends only on its own camera). */
#include "scene/camera.h"
#include "cli/cli.h"
#include "cl/clrt.h"
#include "plan/auto_device.h"
#include "plan/frame.h"
#include "io/hair/hair.h"
#include "io/image/image_write.h"
#include "base/output_set.h"
#include "scene/scene.h"
#include "scene/scene_inputs.h"
#include "passes/light/shadow.h"
#include "srbf_c.h"
#include "voxel.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *usage_text =
    "usage: strandlight render SCENE.json|- [options]   (-: the scene on standard input, relative\n"
    "       paths from the working directory)\n"
    "\n"
    "Renders SCENE.json (format: ../shared/spec/scene.md, README) to an OpenEXR file and a PNG\n"
    "preview (docs/frame.md). Options override the scene's settings:\n"
    "  -o, --exr FILE      EXR output (default: output.exr of the scene, else out/frame.exr)\n"
    "  --png FILE          PNG preview (default: output.png of the scene, if any, unless an\n"
    "                      EXR was named on the command line: -o alone writes only that EXR)\n"
    "  --exposure STOPS    PNG preview exposure in stops (default output.exposure, 0): the\n"
    "                      preview is 2^STOPS x linear radiance, ACES filmic tone map, sRGB;\n"
    "                      the EXR always holds linear radiance\n"
    "  --width W, --height H   image size\n"
    "  --device SPEC       auto|gpu|pocl|c|opencl|P:D (default auto)\n"
    "  --aov LIST          AOVs to add, comma-separated: R,TT,TRT,MS,shadow,lobes,depth,alpha\n"
    "                      or all (default: output.aovs of the scene). Channels: R_mode.R/G/B,\n"
    "                      TT.R/G/B, TRT.R/G/B, MS.R/G/B, shadow.Y, lobes.Y; depth is Z and\n"
    "                      alpha is A, always written with R, G, B.\n"
    "  --shading-rate R    auto|fragment|vertex|vertex:K (default quality.shading_rate)\n"
    "  --method M          SRBF response: auto (default: Ren's precomputed table when it is\n"
    "                      cached or pays for its build over the frames, else fast), fast, xu\n"
    "                      or table (docs/frame.md, \"SRBF method\")\n"
    "  --orbit N           N frames on a circle around the hair (about +Y), light passes\n"
    "                      reused; files get _NNNN before the extension\n"
    "  --frames A:B        with --orbit: only frames A..B-1 (same pixels as a full run)\n"
    "  --explain           print each frame's plan: every pass run / cached / skipped, why, time\n"
    "  --threads N         C threads (default: every CPU)\n"
    "  --clamp-nonfinite   replace NaN/Inf pixels of the environment map by 0 (else an error)\n"
    "\n"
    "Requests whose buffers exceed the host budget (SL_RENDER_MEM_MB, default half of physical\n"
    "memory) or one OpenCL allocation of the device are refused before any work, naming the\n"
    "setting to lower (docs/robustness.md).\n";

enum { AOV_R = 1, AOV_TT = 2, AOV_TRT = 4, AOV_MS = 8, AOV_SHADOW = 16, AOV_LOBES = 32 };

static int aov_bit(const char *name) {
    static const char *names[] = {"R", "TT", "TRT", "MS", "shadow", "lobes"};
    for (int i = 0; i < 6; i++)
        if (strcmp(name, names[i]) == 0) return 1 << i;
    if (strcmp(name, "depth") == 0 || strcmp(name, "alpha") == 0) return 0;
    return -1;
}

static int parse_aovs(const char *list, int *mask) {
    if (strcmp(list, "all") == 0) {
        *mask = 63;
        return 0;
    }
    char buf[256];
    snprintf(buf, sizeof buf, "%s", list);
    for (char *tok = strtok(buf, ","); tok; tok = strtok(NULL, ",")) {
        int b = aov_bit(tok);
        if (b < 0) return cli_usage_error("render", "--aov: unknown AOV \"%s\"", tok);
        *mask |= b;
    }
    return 0;
}

/* Resource limits (docs/robustness.md sec. 4). Before any work, the frame's largest buffers are
 * estimated from the scene's settings (sl_frame_estimate, host/plan/frame.h: the same size rules
 * the passes allocate with) and the request is refused, with the setting to lower, when they exceed
 * the host budget (SL_RENDER_MEM_MB, default half of physical memory) or, on OpenCL, when one
 * device buffer exceeds CL_DEVICE_MAX_MEM_ALLOC_SIZE. */
static double render_budget(const char **why) {
    const char *v = getenv("SL_RENDER_MEM_MB");
    if (v && *v) {
        char *end;
        double mb = strtod(v, &end);
        if (end != v && mb > 0) {
            *why = "SL_RENDER_MEM_MB";
            return mb * 1048576.0;
        }
    }
    long pages = sysconf(_SC_PHYS_PAGES), psz = sysconf(_SC_PAGE_SIZE);
    *why = "half of physical memory; SL_RENDER_MEM_MB overrides";
    if (pages <= 0 || psz <= 0) return 8.0 * 1073741824.0; /* unknown: assume 16 GB */
    return 0.5 * (double)pages * (double)psz;
}

/* "N.N GiB" above 1 GiB, else "N.N MiB". */
static const char *bytes_str(double b, char *buf, size_t n) {
    if (b >= 1073741824.0)
        snprintf(buf, n, "%.1f GiB", b / 1073741824.0);
    else
        snprintf(buf, n, "%.1f MiB", b / 1048576.0);
    return buf;
}

static int render_check_limits(const sl_scene *s, int shadow_size_opt, const sl_device *dev,
                               sl_err *e) {
    sl_frame_need n;
    sl_frame_estimate(s, shadow_size_opt, &n);
    const char *why;
    double budget = render_budget(&why);
    char a[32], b[32];
    if (n.host > budget)
        return sl_fail(e, "render: %dx%d needs about %s, over the host budget of %s (%s): lower %s",
                       s->width, s->height, bytes_str(n.host, a, sizeof a),
                       bytes_str(budget, b, sizeof b), why, n.host_setting);
    if (dev && dev->is_opencl && dev->cl) {
        double maxa = (double)sl_cl_max_alloc(dev->cl);
        if (maxa > 0 && n.largest > maxa)
            return sl_fail(e,
                           "render: %dx%d: the %s needs one %s buffer, over the device's max "
                           "allocation of %s (%s): lower %s",
                           s->width, s->height, n.largest_what, bytes_str(n.largest, a, sizeof a),
                           bytes_str(maxa, b, sizeof b), dev->name, n.setting);
    }
    return 0;
}

/* path with _NNNN inserted before the extension (or appended). */
static void frame_path(const char *path, int frame, char *out, size_t n) {
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    if (!dot || (slash && dot < slash)) dot = path + strlen(path);
    snprintf(out, n, "%.*s_%04d%s", (int)(dot - path), path, frame, dot);
}

static int write_outputs(const sl_fbuf *f, int aovs, const char *exr, const char *png,
                         int use_float, double exposure, sl_err *e) {
    size_t n = (size_t)f->width * f->height;
    sl_exr_channel ch[32];
    int nch = 0;
    float *planes = sl_malloc(5 * n * sizeof(float));
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 4; c++)
            planes[c * n + i] = f->rgba[4 * i + c];
        planes[4 * n + i] = f->depth[i];
    }
    static const char *base[5] = {"R", "G", "B", "A", "Z"};
    for (int c = 0; c < 5; c++)
        ch[nch++] = (sl_exr_channel){base[c], planes + c * n};
    static const char *mode_names[4][3] = {{"R_mode.R", "R_mode.G", "R_mode.B"},
                                           {"TT.R", "TT.G", "TT.B"},
                                           {"TRT.R", "TRT.G", "TRT.B"},
                                           {"MS.R", "MS.G", "MS.B"}};
    float *mp = sl_malloc(12 * n * sizeof(float));
    for (int m = 0; m < 4; m++) {
        if (!(aovs & (1 << m))) continue;
        for (int c = 0; c < 3; c++) {
            float *p = mp + (3 * m + c) * n;
            for (size_t i = 0; i < n; i++)
                p[i] = f->mode[m][3 * i + c];
            ch[nch++] = (sl_exr_channel){mode_names[m][c], p};
        }
    }
    if (aovs & AOV_SHADOW) ch[nch++] = (sl_exr_channel){"shadow.Y", f->shadow};
    if (aovs & AOV_LOBES) ch[nch++] = (sl_exr_channel){"lobes.Y", f->lobes};
    /* EXR and PNG are one set (issue 21): both written and fsynced under temporary names, then
     * renamed back to back with ^C held off, so a reader never sees a new EXR beside an old PNG
     * unless a SIGKILL lands between the two renames (docs/robustness.md section 5) */
    sl_atomic_file ax, ap;
    memset(&ap, 0, sizeof ap);
    int rc = sl_exr_write_temp(exr, f->width, f->height, ch, nch, use_float, &ax, e);
    free(planes);
    free(mp);
    if (rc) return -1;
    sl_kill_point("render: EXR complete under its temporary name");
    if (png && png[0] &&
        sl_png_write_temp(png, f->width, f->height, f->rgba, (float)exposure, &ap, e)) {
        remove(ax.tmp_path);
        return -1;
    }
    if (ap.tmp_path[0]) sl_kill_point("render: PNG complete under its temporary name");
    sl_atomic_file *set[2] = {&ax, &ap};
    return sl_output_set_commit(set, 2, e);
}

int cmd_render(int argc, char **argv) {
    const char *scene_path = NULL, *exr = NULL, *png = NULL, *device = "auto", *v;
    const char *rate = NULL, *frames = NULL;
    long width = 0, height = 0, orbit = 0, threads = 0;
    int clamp_nonfinite = 0, missing = 0, explain = 0, aovs = 0, aov_given = 0, exposure_given = 0;
    double exposure = 0.0;
    sl_render_opts ro;
    sl_render_opts_default(&ro);
    for (int i = 1; i < argc; i++) {
        if (cli_is_help(argv[i])) {
            fputs(usage_text, stdout);
            return 0;
        } else if (cli_opt(argc, argv, &i, "--exr", &exr, &missing) ||
                   cli_opt(argc, argv, &i, "-o", &exr, &missing) ||
                   cli_opt(argc, argv, &i, "--output", &exr, &missing) ||
                   cli_opt(argc, argv, &i, "--png", &png, &missing) ||
                   cli_opt(argc, argv, &i, "--device", &device, &missing) ||
                   cli_opt(argc, argv, &i, "--shading-rate", &rate, &missing) ||
                   cli_opt(argc, argv, &i, "--frames", &frames, &missing)) {
            if (missing) return 2;
        } else if (cli_opt(argc, argv, &i, "--aov", &v, &missing)) {
            if (missing || parse_aovs(v, &aovs)) return 2;
            aov_given = 1;
        } else if (cli_opt(argc, argv, &i, "--method", &v, &missing)) {
            if (missing) return 2;
            sl_err me;
            if (sl_render_method_parse(v, &ro.srbf_method, &me))
                return cli_usage_error("render", "--method: %s", me.msg);
        } else if (cli_opt(argc, argv, &i, "--exposure", &v, &missing)) {
            char *end = NULL;
            if (missing) return 2;
            exposure = strtod(v, &end);
            if (end == v || *end || !isfinite(exposure) || fabs(exposure) > 30)
                return cli_usage_error("render",
                                       "--exposure: expected stops in [-30, 30], got \"%s\"", v);
            exposure_given = 1;
        } else if (cli_opt(argc, argv, &i, "--width", &v, &missing)) {
            if (missing || cli_int("render", "--width", v, 1, 16384, &width)) return 2;
        } else if (cli_opt(argc, argv, &i, "--height", &v, &missing)) {
            if (missing || cli_int("render", "--height", v, 1, 16384, &height)) return 2;
        } else if (cli_opt(argc, argv, &i, "--orbit", &v, &missing)) {
            if (missing || cli_int("render", "--orbit", v, 1, 100000, &orbit)) return 2;
        } else if (cli_opt(argc, argv, &i, "--threads", &v, &missing)) {
            if (missing || cli_int("render", "--threads", v, 1, 16, &threads)) return 2;
        } else if (strcmp(argv[i], "--explain") == 0) {
            explain = 1;
        } else if (strcmp(argv[i], "--clamp-nonfinite") == 0) {
            clamp_nonfinite = 1;
        } else if (argv[i][0] == '-' && argv[i][1] != 0) {
            return cli_usage_error("render", "unknown option %s", argv[i]);
        } else if (!scene_path) {
            scene_path = argv[i];
        } else {
            return cli_usage_error("render", "more than one scene given");
        }
    }
    if (!scene_path) return cli_usage_error("render", "no scene file given");
    long fa = 0, fb = orbit > 0 ? orbit : 1;
    if (frames) {
        char *end;
        if (!orbit) return cli_usage_error("render", "--frames needs --orbit N");
        fa = strtol(frames, &end, 10);
        if (end == frames || *end != ':')
            return cli_usage_error("render", "--frames: expected A:B, got \"%s\"", frames);
        char *b = end + 1;
        fb = strtol(b, &end, 10);
        if (end == b || *end || fa < 0 || fb <= fa || fb > orbit)
            return cli_usage_error("render", "--frames %s: need 0 <= A < B <= %ld", frames, orbit);
    }
    ro.threads = (int)threads;
    /* the whole sequence (not this process's share of it): every process of a farm split
     * weighs the table build against the same frame count (docs/frame.md, "SRBF method") */
    ro.frames = orbit > 0 ? (int)orbit : 1;

    sl_err e = {{0}};
    sl_scene_inputs in = {0};
    sl_scene_inputs_opts io = {.width = (int)width,
                               .height = (int)height,
                               .lobes = 1,
                               .clamp_nonfinite = clamp_nonfinite,
                               .strand_sigma_a = 1};
    sl_device dev = {0};
    sl_renderer *r = NULL;
    int rc = 1;
    double t0 = sl_now();
    /* the scene, then its settings' checks and the device, then the files it names */
    if (sl_scene_inputs_open(scene_path, &io, &in, &e)) goto done;
    sl_scene *s = in.scene;
    if (rate) {
        int k;
        if (sl_shading_rate_parse(rate, &k, &e)) {
            sl_scene_inputs_free(&in);
            return cli_usage_error("render", "--shading-rate: %s", e.msg);
        }
        snprintf(s->shading_rate, sizeof s->shading_rate, "%s", rate);
    }
    if (!aov_given)
        for (int i = 0; i < s->num_aovs; i++)
            aovs |= aov_bit(s->aovs[i]) > 0 ? aov_bit(s->aovs[i]) : 0;
    if (render_check_limits(s, ro.shadow_size, NULL, &e)) goto done;
    /* The outputs first: a bad path is found now, not after the whole render. An EXR named on
     * the command line is this run's output: the scene's PNG would otherwise be overwritten by a
     * render that was asked for somewhere else (issue 22). */
    const char *exr_path = exr ? exr : (s->out_exr[0] ? s->out_exr : "out/frame.exr");
    const char *png_path = png ? png : (exr ? NULL : s->out_png);
    if (sl_output_precheck(exr_path, exr ? "--exr" : "output.exr", &e)) goto done;
    if (png_path && png_path[0] && sl_output_precheck(png_path, png ? "--png" : "output.png", &e))
        goto done;
    {
        /* never over one of this run's own inputs (issue 21), nor both outputs on one file */
        const char *inputs[SL_SCENE_FILES + 1];
        sl_scene_files(s, inputs);
        inputs[SL_SCENE_FILES] = png_path; /* the EXR may not be the PNG either */
        if (sl_output_not_input(exr_path, exr ? "--exr" : "output.exr", inputs, SL_SCENE_FILES + 1,
                                &e))
            goto done;
        if (png_path && png_path[0] &&
            sl_output_not_input(png_path, png ? "--png" : "output.png", inputs, SL_SCENE_FILES, &e))
            goto done;
        if (png_path && png_path[0] && strcmp(png_path, exr_path) == 0) {
            sl_fail(&e, "--png: %s: the same file as the EXR output", png_path);
            goto done;
        }
    }
    if (sl_device_open(device, &dev, &e)) goto done;
    if (render_check_limits(s, ro.shadow_size, &dev, &e)) goto done;
    if (sl_scene_inputs_finish(&in, &io, &e)) goto done;
    const sl_hair *h = &in.hair;
    const sl_lobes *lobes = &in.lobes;
    const double *target = in.target;
    const sl_camera cam0 = in.cam;
    /* --device auto on a CPU OpenCL device: C or the device, whichever a trial on a proxy of
     * this scene found faster (measured once, cached; host/plan/auto_device.h) */
    sl_auto_choice choice;
    sl_auto_device_settle(&dev, s, h, lobes, in.lo, in.hi, target, &ro, &choice);
    r = sl_renderer_create(&dev, &ro);
    /* material.strand_sigma_a: per-strand absorption (docs/formats.md) */
    if (in.strand_sigma_a &&
        sl_renderer_set_strand_sigma_a(r, in.strand_sigma_a, h->num_strands, &e))
        goto done;
    if (s->strand_sigma_a_colors && s->multiple_scattering == SL_MS_OFF)
        sl_note("%s: material.strand_sigma_a \"colors\": the file's colours are those of light "
                "scattered many times (Chiang 2016); with quality.multiple_scattering off the "
                "frame shows single scattering only, paler than the file",
                s->path);
    double tprev = sl_now(); /* start of the previous frame */
    for (long f = fa; f < fb; f++) {
        sl_camera cam = cam0;
        char exr_f[4200], png_f[4200] = "";
        snprintf(exr_f, sizeof exr_f, "%s", exr_path);
        if (png_path) snprintf(png_f, sizeof png_f, "%s", png_path);
        if (orbit) {
            /* rotate the eye about the +Y axis through the target: frame f at 360 f / N deg */
            double ang = 2.0 * 3.14159265358979323846 * (double)f / (double)orbit;
            double d[3], ca = cos(ang), sa = sin(ang);
            for (int k = 0; k < 3; k++)
                d[k] = cam0.eye[k] - target[k];
            double eye[3] = {target[0] + ca * d[0] + sa * d[2], target[1] + d[1],
                             target[2] - sa * d[0] + ca * d[2]};
            sl_camera_setup(&cam, eye, target, s->up, s->fov_deg, s->width, s->height, in.lo,
                            in.hi);
            frame_path(exr_path, (int)f, exr_f, sizeof exr_f);
            if (png_path && png_path[0]) frame_path(png_path, (int)f, png_f, sizeof png_f);
        }
        sl_fbuf fbuf;
        double tf = sl_now();
        /* the status line on a terminal: which frame, and (after the first) the time left at the
         * last frame's time (later frames reuse the first's light pass and tables, so the mean
         * so far would overestimate it) */
        char label[128];
        long done = f - fa, total = fb - fa;
        if (done > 0) {
            double left = (tf - tprev) * (double)(total - done);
            snprintf(label, sizeof label, "render: frame %ld of %ld, eta %ldm%02lds", done + 1,
                     total, (long)left / 60, (long)left % 60);
        } else
            snprintf(label, sizeof label, "render: frame %ld of %ld", done + 1, total);
        sl_renderer_set_status(r, label);
        tprev = tf;
        if (sl_renderer_frame(r, s, h, lobes, &cam, &fbuf, &e)) goto done;
        int wrc = write_outputs(&fbuf, aovs, exr_f, png_f, s->exr_float,
                                exposure_given ? exposure : s->exposure, &e);
        sl_fbuf_free(&fbuf);
        if (wrc) goto done;
        if (explain) {
            if (orbit) printf("frame %ld\n", f);
            if (f == fa && choice.why[0]) /* the device choice, once, as a row of the plan */
                printf("%-10s %-8s %8.3fs  %s\n", "device",
                       choice.state == SL_AUTO_CACHED ? "cached"
                       : choice.state == SL_AUTO_NONE ? "skipped"
                                                      : "run",
                       choice.seconds, choice.why);
            sl_renderer_explain(r, stdout);
            fflush(stdout);
        }
        sl_note("render: frame %ld: %u strands, %dx%d, model %s, %d of %d lobes -> %s%s%s (%.2f s)",
                f, h->num_strands, s->width, s->height, sl_material_model_name(s->material.model),
                sl_renderer_lobes_used(r), lobes->count, exr_f, png_f[0] ? " + " : "", png_f,
                sl_now() - tf);
    }
    sl_note("render: done in %.2f s on %s", sl_now() - t0, dev.name);
    rc = 0;
done:
    if (rc) fprintf(stderr, "strandlight: %s\n", e.msg);
    sl_renderer_free(r);
    sl_scene_inputs_free(&in);
    sl_device_close(&dev);
    return rc;
}
