/* cmd_export.c: `strandlight export SCENE.json -o FILE.hair`: the scene's strands exactly as the
 * renderer sees them (scene_inputs.h: procedural generation, tfx_follow, the `up` axis, the
 * radius override; world coordinates, +Y up) as a cyHair .hair file, and beside it
 * FILE.hair.camera.json with what another renderer cannot work out from the scene file alone:
 * the resolved camera (framed from the hair's bounds when camera.eye is omitted), the image size
 * and the parsed material and environment. scripts/cycles/ renders both in Blender Cycles
 * (docs/validation.md). Exit 0, 1 on bad input or a failed write (one line), 2 on usage. */
#include "cli/cli.h"
#include "scene/scene_inputs.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *usage_text =
    "usage: strandlight export SCENE.json -o FILE.hair [--width W] [--height H]\n"
    "\n"
    "Writes the scene's strands as the renderer sees them (after procedural generation,\n"
    "hair.tfx_follow, hair.up and hair.radius; world coordinates, +Y up) to a cyHair .hair\n"
    "file (per-point thickness = 2 x radius), and FILE.hair.camera.json: the resolved camera\n"
    "(eye, target, up, vertical fov_deg, the orthonormal right/up/forward frame, focal length\n"
    "in pixels; framed from the hair's bounds when camera.eye is omitted), the image size, the\n"
    "environment (file, rotation_deg, intensity) and the material as parsed. Both files are\n"
    "written atomically. scripts/cycles/render.sh renders them in Blender Cycles.\n"
    "  -o, --output FILE   the .hair file to write (required)\n"
    "  --width W, --height H   image size the camera is resolved for (default: the scene's;\n"
    "                      the framing of an omitted camera.eye depends on it)\n";

static cJSON *vec3(const double v[3]) {
    double w[3] = {v[0], v[1], v[2]};
    return cJSON_CreateDoubleArray(w, 3);
}

static cJSON *vec3f(const float v[3]) {
    double w[3] = {v[0], v[1], v[2]};
    return cJSON_CreateDoubleArray(w, 3);
}

static const char *model_name(int model) {
    return model == SL_MODEL_CHIANG ? "chiang" : model == SL_MODEL_DEON ? "deon" : "marschner";
}

/* The material as parsed (defaults filled in), for the other renderer to check its own reading
 * of the scene file against. */
static cJSON *material_json(const sl_material *m) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "model", model_name(m->model));
    cJSON_AddNumberToObject(o, "eta", m->eta);
    cJSON_AddItemToObject(o, "sigma_a", vec3(m->sigma_a));
    if (m->model == SL_MODEL_CHIANG) {
        const sl_chiang *c = &m->chiang;
        cJSON_AddBoolToObject(o, "sigma_a_given", c->sigma_a_given);
        cJSON_AddNumberToObject(o, "melanin", c->melanin);
        cJSON_AddNumberToObject(o, "melanin_redness", c->melanin_redness);
        cJSON_AddItemToObject(o, "tint", vec3(c->tint));
        cJSON_AddNumberToObject(o, "roughness", c->roughness);
        cJSON_AddNumberToObject(o, "radial_roughness", c->radial_roughness);
        cJSON_AddNumberToObject(o, "coat", c->coat);
        cJSON_AddNumberToObject(o, "offset_deg", c->offset * 180.0 / M_PI);
    }
    return o;
}

/* The sidecar's text (caller frees). */
static char *sidecar_text(const sl_scene_inputs *in, const char *scene_path,
                          const char *hair_path) {
    const sl_scene *s = in->scene;
    const sl_camera *c = &in->cam;
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "written_by", "strandlight export " SL_VERSION);
    cJSON_AddStringToObject(root, "scene", scene_path);
    cJSON_AddStringToObject(root, "hair_file", hair_path);
    cJSON_AddNumberToObject(root, "strands", in->hair.num_strands);
    cJSON_AddNumberToObject(root, "points", in->hair.num_points);
    cJSON *b = cJSON_AddObjectToObject(root, "bounds");
    cJSON_AddItemToObject(b, "lo", vec3f(in->lo));
    cJSON_AddItemToObject(b, "hi", vec3f(in->hi));
    cJSON *img = cJSON_AddObjectToObject(root, "image");
    cJSON_AddNumberToObject(img, "width", c->width);
    cJSON_AddNumberToObject(img, "height", c->height);
    cJSON *cam = cJSON_AddObjectToObject(root, "camera");
    cJSON_AddItemToObject(cam, "eye", vec3(c->eye));
    cJSON_AddItemToObject(cam, "target", vec3(in->target));
    cJSON_AddItemToObject(cam, "up", vec3(s->up));
    cJSON_AddNumberToObject(cam, "fov_deg", s->fov_deg);
    cJSON_AddBoolToObject(cam, "framed", !s->has_eye);
    cJSON_AddItemToObject(cam, "right", vec3(c->right));
    cJSON_AddItemToObject(cam, "up_ortho", vec3(c->up));
    cJSON_AddItemToObject(cam, "forward", vec3(c->fwd));
    cJSON_AddNumberToObject(cam, "focal_px", c->focal);
    cJSON *env = cJSON_AddObjectToObject(root, "environment");
    char abs_env[4096] = "";
    if (s->env_file[0] && !realpath(s->env_file, abs_env))
        snprintf(abs_env, sizeof abs_env, "%s", s->env_file);
    cJSON_AddStringToObject(env, "file", abs_env);
    cJSON_AddNumberToObject(env, "rotation_deg", s->env_rotation_deg);
    cJSON_AddNumberToObject(env, "intensity", s->env_intensity);
    cJSON_AddItemToObject(root, "material", material_json(&s->material));
    cJSON_AddBoolToObject(root, "strand_sigma_a",
                          s->strand_sigma_a_colors || s->strand_sigma_a[0] != 0);
    char *text = cJSON_Print(root);
    cJSON_Delete(root);
    return text;
}

static int write_text(const char *path, const char *text, sl_err *e) {
    sl_atomic_file af;
    if (sl_atomic_open(&af, path, e)) return -1;
    fputs(text, af.fp);
    fputc('\n', af.fp);
    return sl_atomic_commit(&af, e);
}

int cmd_export(int argc, char **argv) {
    const char *scene_path = NULL, *out = NULL, *v;
    int missing = 0;
    long width = 0, height = 0;
    for (int i = 1; i < argc; i++) {
        if (cli_is_help(argv[i])) {
            fputs(usage_text, stdout);
            return 0;
        } else if (cli_opt(argc, argv, &i, "-o", &v, &missing) ||
                   cli_opt(argc, argv, &i, "--output", &v, &missing)) {
            if (missing) return 2;
            out = v;
        } else if (cli_opt(argc, argv, &i, "--width", &v, &missing)) {
            if (missing || cli_int("export", "--width", v, 1, 16384, &width)) return 2;
        } else if (cli_opt(argc, argv, &i, "--height", &v, &missing)) {
            if (missing || cli_int("export", "--height", v, 1, 16384, &height)) return 2;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            return cli_usage_error("export", "unknown option '%s'", argv[i]);
        } else if (!scene_path) {
            scene_path = argv[i];
        } else {
            return cli_usage_error("export", "unexpected argument '%s'", argv[i]);
        }
    }
    if (!scene_path) return cli_usage_error("export", "missing SCENE.json");
    if (!out) return cli_usage_error("export", "missing -o FILE.hair");
    char side[4200];
    if (snprintf(side, sizeof side, "%s.camera.json", out) >= (int)sizeof side)
        return cli_usage_error("export", "-o: path too long");

    sl_err e = {{0}};
    sl_scene_inputs_opts o = {.width = (int)width, .height = (int)height};
    sl_scene_inputs in;
    int rc = 1;
    char *text = NULL;
    if (sl_scene_inputs_load(scene_path, &o, &in, &e)) goto done;
    text = sidecar_text(&in, scene_path, out);
    char info[88];
    snprintf(info, sizeof info, "strandlight export of %s", scene_path);
    if (sl_hair_write_cyhair(out, &in.hair, info, &e)) goto done;
    if (write_text(side, text, &e)) {
        remove(out); /* a .hair without its camera would be rendered from the wrong place */
        goto done;
    }
    const sl_camera *c = &in.cam;
    printf("%u strands, %u points -> %s\n", in.hair.num_strands, in.hair.num_points, out);
    printf("camera%s: eye (%.6g, %.6g, %.6g) target (%.6g, %.6g, %.6g) up (%.6g, %.6g, %.6g) "
           "fov %.6g deg, %d x %d -> %s\n",
           in.scene->has_eye ? "" : " (framed)", c->eye[0], c->eye[1], c->eye[2], in.target[0],
           in.target[1], in.target[2], in.scene->up[0], in.scene->up[1], in.scene->up[2],
           in.scene->fov_deg, c->width, c->height, side);
    rc = 0;
done:
    if (rc) fprintf(stderr, "strandlight: %s\n", e.msg[0] ? e.msg : "export failed");
    free(text);
    sl_scene_inputs_free(&in);
    return rc;
}
