/* scene.c: loads and validates scene files (../shared/spec/scene.md); see scene.h. */
#include "scene/scene.h"

#include "base/json_util.h"
#include "lighting/lobe_subdivide.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The material loader (host/scene/material.c) reads the "material" object with the same key-path
 * conventions. */
int sl_material_from_json(const cJSON *obj, const char *file, const char *key_prefix,
                          sl_material *m, sl_err *e);

void sl_scene_default(sl_scene *s) {
    memset(s, 0, sizeof *s);
    s->hair_procedural = 1;
    s->proc_style = 1;
    s->proc_strands = 10000;
    s->proc_points = 16;
    s->proc_seed = 1;
    sl_material_default(&s->material);
    s->env_intensity = 1.0;
    s->target[0] = s->target[1] = s->target[2] = 0;
    s->up[1] = 1;
    s->fov_deg = 30;
    s->width = 720;
    s->height = 480;
    s->lobes = 40;
    s->layers = 4;
    s->segments_m = 4;
    s->kappa = 1.0;
    s->voxels = 64;
    s->multiple_scattering = SL_MS_AUTO;
    s->oit_layers = 8;
    s->shadow_size = 0; /* light-map size, texels; 0: the consumer's default (eval: 512) */
    snprintf(s->shading_rate, sizeof s->shading_rate, "auto");
    s->lobe_threshold = SL_FRAME_LOBE_THRESHOLD;
    s->point_threshold = SL_FRAME_POINT_THRESHOLD;
    s->shading_refine = SL_FRAME_SHADING_REFINE;
    s->sharp_shadows = SL_FRAME_SHARP_SHADOWS;
    s->ms_auto_threshold = SL_FRAME_MS_AUTO_THRESHOLD;
    s->auto_fragment_px = SL_FRAME_AUTO_FRAGMENT_PX;
    s->broad_lobes = SL_BROAD_SUBDIVIDE;
    s->sublobe_width = SL_SUBDIV_WIDTH;
}

/* Resolves a path from the scene against the scene file's directory. */
static void resolve(const char *scene_path, const char *rel, char *out, size_t n) {
    char dir[4096];
    sl_dirname(scene_path, dir, sizeof dir);
    sl_path_join(dir, rel, out, n);
}

static int read_hair(const sl_json_ctx *top, const cJSON *h, sl_scene *s, sl_err *e) {
    static const char *const keys[] = {"file",       "procedural",   "up", "radius",
                                       "tfx_follow", "transparency", NULL};
    sl_json_ctx c = {top->file, "hair"};
    if (sl_json_check_keys(&c, h, keys, e)) return -1;
    const cJSON *file = cJSON_GetObjectItemCaseSensitive(h, "file");
    const cJSON *proc = cJSON_GetObjectItemCaseSensitive(h, "procedural");
    if ((file != NULL) == (proc != NULL))
        return sl_fail(e, "%s: hair: give exactly one of 'file' and 'procedural'", top->file);
    if (file) {
        char rel[4096];
        if (sl_json_string(&c, h, "file", 1, rel, sizeof rel, e)) return -1;
        resolve(s->path, rel, s->hair_file, sizeof s->hair_file);
        s->hair_procedural = 0;
    } else {
        static const char *const pkeys[] = {"style", "strands", "points", "seed", NULL};
        sl_json_ctx pc = {top->file, "hair.procedural"};
        if (!cJSON_IsObject(proc))
            return sl_fail(e, "%s: hair.procedural: expected an object", top->file);
        if (sl_json_check_keys(&pc, proc, pkeys, e)) return -1;
        char style[32] = "wavy";
        if (sl_json_string(&pc, proc, "style", 0, style, sizeof style, e)) return -1;
        if (strcmp(style, "straight") == 0)
            s->proc_style = 0;
        else if (strcmp(style, "wavy") == 0)
            s->proc_style = 1;
        else if (strcmp(style, "curly") == 0)
            s->proc_style = 2;
        else
            return sl_fail(
                e, "%s: hair.procedural.style: expected \"straight\", \"wavy\" or \"curly\"",
                top->file);
        long v = s->proc_strands;
        if (sl_json_int(&pc, proc, "strands", 0, 1, 4000000, &v, e)) return -1;
        s->proc_strands = (uint32_t)v;
        v = s->proc_points;
        if (sl_json_int(&pc, proc, "points", 0, 2, 256, &v, e)) return -1;
        s->proc_points = (uint32_t)v;
        v = s->proc_seed;
        if (sl_json_int(&pc, proc, "seed", 0, 0, 4294967295L, &v, e)) return -1;
        s->proc_seed = (uint32_t)v;
        s->hair_procedural = 1;
    }
    char up[8] = "y";
    if (sl_json_string(&c, h, "up", 0, up, sizeof up, e)) return -1;
    if (strcmp(up, "y") && strcmp(up, "z"))
        return sl_fail(e, "%s: hair.up: expected \"y\" or \"z\"", top->file);
    s->up_z = up[0] == 'z';
    if (sl_json_number(&c, h, "radius", 0, &s->radius, e)) return -1;
    if (cJSON_GetObjectItemCaseSensitive(h, "radius") && !(s->radius > 0))
        return sl_fail(e, "%s: hair.radius: must be > 0", top->file);
    char tr[16] = "opaque";
    if (sl_json_string(&c, h, "transparency", 0, tr, sizeof tr, e)) return -1;
    if (strcmp(tr, "opaque") && strcmp(tr, "file"))
        return sl_fail(e, "%s: hair.transparency: expected \"opaque\" or \"file\"", top->file);
    s->file_transparency = tr[0] == 'f';
    const cJSON *f;
    if (sl_json_object(&c, h, "tfx_follow", 0, &f, e)) return -1;
    if (f) {
        static const char *const fkeys[] = {"per_guide", "root_radius", "tip_spread", NULL};
        sl_json_ctx fc = {top->file, "hair.tfx_follow"};
        if (sl_json_check_keys(&fc, f, fkeys, e)) return -1;
        long pg = 4;
        s->follow_root_radius = 0.4;
        s->follow_tip_spread = 5.0;
        if (sl_json_int(&fc, f, "per_guide", 0, 0, 64, &pg, e)) return -1;
        if (sl_json_number(&fc, f, "root_radius", 0, &s->follow_root_radius, e)) return -1;
        if (sl_json_number(&fc, f, "tip_spread", 0, &s->follow_tip_spread, e)) return -1;
        if (s->follow_root_radius < 0)
            return sl_fail(e, "%s: hair.tfx_follow.root_radius: must be >= 0", top->file);
        if (s->follow_tip_spread < 0)
            return sl_fail(e, "%s: hair.tfx_follow.tip_spread: must be >= 0", top->file);
        s->has_follow = 1;
        s->follow_per_guide = (int)pg;
    }
    return 0;
}

/* The material object: the numerics contract's keys (host/scene/material.c) plus our extension
 * strand_sigma_a, taken out of a copy before the contract's loader sees the rest. */
static int read_material(const sl_json_ctx *top, const cJSON *m, sl_scene *s, sl_err *e) {
    const cJSON *ss = cJSON_GetObjectItemCaseSensitive(m, "strand_sigma_a");
    if (!ss) return sl_material_from_json(m, top->file, "material", &s->material, e);
    if (!cJSON_IsString(ss) || !ss->valuestring[0])
        return sl_fail(e, "%s: material.strand_sigma_a: expected \"colors\" or a CSV path",
                       top->file);
    if (strcmp(ss->valuestring, "colors") == 0)
        s->strand_sigma_a_colors = 1;
    else
        resolve(s->path, ss->valuestring, s->strand_sigma_a, sizeof s->strand_sigma_a);
    cJSON *copy = cJSON_Duplicate(m, 1);
    if (!copy) return sl_fail(e, "%s: material: out of memory", top->file);
    cJSON_DeleteItemFromObjectCaseSensitive(copy, "strand_sigma_a");
    int rc = sl_material_from_json(copy, top->file, "material", &s->material, e);
    cJSON_Delete(copy);
    return rc;
}

static int read_environment(const sl_json_ctx *top, const cJSON *env, sl_scene *s, sl_err *e) {
    static const char *const keys[] = {"file", "lobes", "rotation_deg", "intensity", NULL};
    sl_json_ctx c = {top->file, "environment"};
    if (sl_json_check_keys(&c, env, keys, e)) return -1;
    char rel[4096] = "";
    if (sl_json_string(&c, env, "file", 0, rel, sizeof rel, e)) return -1;
    if (rel[0]) resolve(s->path, rel, s->env_file, sizeof s->env_file);
    rel[0] = 0;
    if (sl_json_string(&c, env, "lobes", 0, rel, sizeof rel, e)) return -1;
    if (rel[0]) resolve(s->path, rel, s->env_lobes, sizeof s->env_lobes);
    if (!s->env_file[0] && !s->env_lobes[0])
        return sl_fail(e, "%s: environment: give 'file' and/or 'lobes'", top->file);
    if (sl_json_number(&c, env, "rotation_deg", 0, &s->env_rotation_deg, e)) return -1;
    if (sl_json_number(&c, env, "intensity", 0, &s->env_intensity, e)) return -1;
    if (s->env_intensity < 0)
        return sl_fail(e, "%s: environment.intensity: must be >= 0", top->file);
    return 0;
}

static int read_camera(const sl_json_ctx *top, const cJSON *cam, sl_scene *s, sl_err *e) {
    static const char *const keys[] = {"eye", "target", "up", "fov_deg", NULL};
    sl_json_ctx c = {top->file, "camera"};
    if (sl_json_check_keys(&c, cam, keys, e)) return -1;
    s->has_eye = cJSON_GetObjectItemCaseSensitive(cam, "eye") != NULL;
    s->has_target = cJSON_GetObjectItemCaseSensitive(cam, "target") != NULL;
    if (sl_json_vec(&c, cam, "eye", 0, 3, s->eye, e)) return -1;
    if (sl_json_vec(&c, cam, "target", 0, 3, s->target, e)) return -1;
    if (sl_json_vec(&c, cam, "up", 0, 3, s->up, e)) return -1;
    if (sl_json_number(&c, cam, "fov_deg", 0, &s->fov_deg, e)) return -1;
    if (!(s->fov_deg > 0 && s->fov_deg < 180))
        return sl_fail(e, "%s: camera.fov_deg: must be in (0, 180)", top->file);
    double upl = s->up[0] * s->up[0] + s->up[1] * s->up[1] + s->up[2] * s->up[2];
    if (!(upl > 0)) return sl_fail(e, "%s: camera.up: must not be zero", top->file);
    if (s->has_eye) {
        double d[3] = {s->target[0] - s->eye[0], s->target[1] - s->eye[1],
                       s->target[2] - s->eye[2]};
        double dl = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        if (!(dl > 0))
            return sl_fail(e, "%s: camera.eye: must differ from camera.target", top->file);
        double cx = d[1] * s->up[2] - d[2] * s->up[1], cy = d[2] * s->up[0] - d[0] * s->up[2],
               cz = d[0] * s->up[1] - d[1] * s->up[0];
        if (!(cx * cx + cy * cy + cz * cz > 1e-12 * dl * upl))
            return sl_fail(e, "%s: camera.up: parallel to the view direction", top->file);
    }
    return 0;
}

static int read_quality(const sl_json_ctx *top, const cJSON *q, sl_scene *s, sl_err *e) {
    static const char *const keys[] = {"lobes",
                                       "layers",
                                       "segments_m",
                                       "kappa",
                                       "voxels",
                                       "multiple_scattering",
                                       "oit_layers",
                                       "shading_rate",
                                       "shadow_size",
                                       "lobe_threshold",
                                       "point_threshold",
                                       "shading_refine",
                                       "sharp_shadows",
                                       "ms_auto_threshold",
                                       "auto_fragment_px",
                                       "broad_lobes",
                                       "sublobe_width",
                                       NULL};
    sl_json_ctx c = {top->file, "quality"};
    if (sl_json_check_keys(&c, q, keys, e)) return -1;
    long v;
    v = s->lobes;
    if (sl_json_int(&c, q, "lobes", 0, 1, 512, &v, e)) return -1;
    s->lobes = (int)v;
    v = s->layers;
    if (sl_json_int(&c, q, "layers", 0, 1, 16, &v, e)) return -1;
    s->layers = (int)v;
    v = s->segments_m;
    if (sl_json_int(&c, q, "segments_m", 0, 1, 8, &v, e)) return -1;
    s->segments_m = (int)v;
    v = s->voxels;
    if (sl_json_int(&c, q, "voxels", 0, 4, 512, &v, e)) return -1;
    s->voxels = (int)v;
    v = s->oit_layers;
    if (sl_json_int(&c, q, "oit_layers", 0, 1, 64, &v, e)) return -1;
    s->oit_layers = (int)v;
    v = s->sharp_shadows;
    if (sl_json_int(&c, q, "sharp_shadows", 0, 0, 2, &v, e)) return -1;
    s->sharp_shadows = (int)v;
    v = s->shadow_size;
    if (sl_json_int(&c, q, "shadow_size", 0, 16, 8192, &v, e)) return -1;
    s->shadow_size = (int)v;
    if (sl_json_number(&c, q, "kappa", 0, &s->kappa, e)) return -1;
    if (!(s->kappa > 0 && s->kappa <= 1))
        return sl_fail(e, "%s: quality.kappa: must be in (0, 1]", top->file);
    /* planner thresholds: shares and a length, so each has a natural range */
    if (sl_json_number(&c, q, "lobe_threshold", 0, &s->lobe_threshold, e)) return -1;
    if (!(s->lobe_threshold >= 0 && s->lobe_threshold < 1))
        return sl_fail(e, "%s: quality.lobe_threshold: must be in [0, 1)", top->file);
    if (sl_json_number(&c, q, "point_threshold", 0, &s->point_threshold, e)) return -1;
    if (!(s->point_threshold >= 0 && s->point_threshold < 1))
        return sl_fail(e, "%s: quality.point_threshold: must be in [0, 1)", top->file);
    if (sl_json_number(&c, q, "shading_refine", 0, &s->shading_refine, e)) return -1;
    if (!(s->shading_refine == 0 || (s->shading_refine >= 1.05 && s->shading_refine <= 1e3)))
        return sl_fail(e, "%s: quality.shading_refine: must be 0 (off) or in [1.05, 1000]",
                       top->file);
    if (sl_json_number(&c, q, "ms_auto_threshold", 0, &s->ms_auto_threshold, e)) return -1;
    if (!(s->ms_auto_threshold >= 0 && s->ms_auto_threshold <= 1))
        return sl_fail(e, "%s: quality.ms_auto_threshold: must be in [0, 1]", top->file);
    if (sl_json_number(&c, q, "sublobe_width", 0, &s->sublobe_width, e)) return -1;
    if (!(s->sublobe_width >= SL_SUBDIV_WIDTH_MIN && s->sublobe_width <= 1))
        return sl_fail(e, "%s: quality.sublobe_width: must be in [%g, 1]", top->file,
                       SL_SUBDIV_WIDTH_MIN);
    if (sl_json_number(&c, q, "auto_fragment_px", 0, &s->auto_fragment_px, e)) return -1;
    if (!(s->auto_fragment_px > 0 && s->auto_fragment_px <= 1e6))
        return sl_fail(e, "%s: quality.auto_fragment_px: must be in (0, 1e6]", top->file);
    char ms[16] = "";
    if (sl_json_string(&c, q, "multiple_scattering", 0, ms, sizeof ms, e)) return -1;
    if (ms[0]) {
        if (strcmp(ms, "auto") == 0)
            s->multiple_scattering = SL_MS_AUTO;
        else if (strcmp(ms, "on") == 0)
            s->multiple_scattering = SL_MS_ON;
        else if (strcmp(ms, "off") == 0)
            s->multiple_scattering = SL_MS_OFF;
        else
            return sl_fail(e,
                           "%s: quality.multiple_scattering: expected \"on\", \"off\" or \"auto\"",
                           top->file);
    }
    if (sl_json_string(&c, q, "shading_rate", 0, s->shading_rate, sizeof s->shading_rate, e))
        return -1;
    if (strcmp(s->shading_rate, "auto") && strcmp(s->shading_rate, "fragment") &&
        strncmp(s->shading_rate, "vertex", 6))
        return sl_fail(e, "%s: quality.shading_rate: expected \"auto\", \"fragment\" or \"vertex\"",
                       top->file);
    char bl[16] = "";
    if (sl_json_string(&c, q, "broad_lobes", 0, bl, sizeof bl, e)) return -1;
    if (bl[0]) {
        if (strcmp(bl, "subdivide") == 0)
            s->broad_lobes = SL_BROAD_SUBDIVIDE;
        else if (strcmp(bl, "split") == 0)
            s->broad_lobes = SL_BROAD_SPLIT;
        else
            return sl_fail(e, "%s: quality.broad_lobes: expected \"subdivide\" or \"split\"",
                           top->file);
    }
    return 0;
}

static int read_output(const sl_json_ctx *top, const cJSON *o, sl_scene *s, sl_err *e) {
    static const char *const keys[] = {"exr", "png", "aovs", "float", "exposure", NULL};
    static const char *const known_aovs[] = {"R",      "TT",    "TRT",   "MS", "depth",
                                             "shadow", "lobes", "alpha", NULL};
    sl_json_ctx c = {top->file, "output"};
    if (sl_json_check_keys(&c, o, keys, e)) return -1;
    char rel[4096] = "";
    if (sl_json_string(&c, o, "exr", 0, rel, sizeof rel, e)) return -1;
    if (rel[0]) resolve(s->path, rel, s->out_exr, sizeof s->out_exr);
    rel[0] = 0;
    if (sl_json_string(&c, o, "png", 0, rel, sizeof rel, e)) return -1;
    if (rel[0]) resolve(s->path, rel, s->out_png, sizeof s->out_png);
    const cJSON *ex = cJSON_GetObjectItemCaseSensitive(o, "exposure");
    if (ex) {
        if (!cJSON_IsNumber(ex) || !isfinite(ex->valuedouble))
            return sl_fail(e, "%s: output.exposure: expected a number (stops)", top->file);
        if (fabs(ex->valuedouble) > 30)
            return sl_fail(e, "%s: output.exposure: must be in [-30, 30] stops", top->file);
        s->exposure = ex->valuedouble;
    }
    const cJSON *fl = cJSON_GetObjectItemCaseSensitive(o, "float");
    if (fl) {
        if (!cJSON_IsBool(fl))
            return sl_fail(e, "%s: output.float: expected true or false", top->file);
        s->exr_float = cJSON_IsTrue(fl);
    }
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(o, "aovs");
    if (a) {
        if (!cJSON_IsArray(a)) return sl_fail(e, "%s: output.aovs: expected an array", top->file);
        int i = 0;
        for (const cJSON *it = a->child; it; it = it->next, i++) {
            if (!cJSON_IsString(it))
                return sl_fail(e, "%s: output.aovs[%d]: expected a string", top->file, i);
            int ok = 0;
            for (const char *const *k = known_aovs; *k; k++)
                if (strcmp(*k, it->valuestring) == 0) ok = 1;
            if (!ok)
                return sl_fail(e,
                               "%s: output.aovs[%d]: unknown AOV \"%s\" (known: R TT TRT MS "
                               "depth shadow lobes alpha)",
                               top->file, i, it->valuestring);
            if (s->num_aovs >= 16) return sl_fail(e, "%s: output.aovs: too many", top->file);
            snprintf(s->aovs[s->num_aovs++], sizeof s->aovs[0], "%s", it->valuestring);
        }
    }
    return 0;
}

int sl_scene_parse(const char *text, size_t len, const char *file_name, sl_scene *s, sl_err *e) {
    sl_scene_default(s);
    snprintf(s->path, sizeof s->path, "%s", file_name);
    cJSON *root = sl_json_parse(text, len, file_name, e);
    if (!root) return -1;
    int rc = -1;
    sl_json_ctx top = {file_name, ""};
    static const char *const keys[] = {"hair",  "material", "environment", "camera",
                                       "image", "quality",  "output",      NULL};
    const cJSON *obj;
    if (!cJSON_IsObject(root)) {
        sl_fail(e, "%s: expected a JSON object at the top level", file_name);
        goto done;
    }
    if (sl_json_check_keys(&top, root, keys, e)) goto done;
    if (sl_json_object(&top, root, "hair", 1, &obj, e) || read_hair(&top, obj, s, e)) goto done;
    if (sl_json_object(&top, root, "material", 0, &obj, e)) goto done;
    if (obj && read_material(&top, obj, s, e)) goto done;
    if (sl_json_object(&top, root, "environment", 1, &obj, e) || read_environment(&top, obj, s, e))
        goto done;
    if (sl_json_object(&top, root, "camera", 0, &obj, e)) goto done;
    if (obj && read_camera(&top, obj, s, e)) goto done;
    if (sl_json_object(&top, root, "image", 0, &obj, e)) goto done;
    if (obj) {
        static const char *const ikeys[] = {"width", "height", NULL};
        sl_json_ctx c = {file_name, "image"};
        long w = s->width, h = s->height;
        if (sl_json_check_keys(&c, obj, ikeys, e) ||
            sl_json_int(&c, obj, "width", 0, 1, 16384, &w, e) ||
            sl_json_int(&c, obj, "height", 0, 1, 16384, &h, e))
            goto done;
        s->width = (int)w;
        s->height = (int)h;
    }
    if (sl_json_object(&top, root, "quality", 0, &obj, e)) goto done;
    if (obj && read_quality(&top, obj, s, e)) goto done;
    if (sl_json_object(&top, root, "output", 0, &obj, e)) goto done;
    if (obj && read_output(&top, obj, s, e)) goto done;
    rc = 0;
done:
    cJSON_Delete(root);
    return rc;
}

/* "-": the scene from standard input, named "<stdin>" in messages, relative paths from the
 * working directory. */
static int read_stdin(unsigned char **data, size_t *size, size_t max, sl_err *e) {
    size_t cap = 65536, n = 0;
    unsigned char *buf = sl_malloc(cap + 1);
    for (;;) {
        if (n == cap) {
            if (cap >= max) {
                free(buf);
                return sl_fail(e, "<stdin>: larger than %zu bytes", max);
            }
            cap *= 2;
            buf = sl_realloc(buf, cap + 1);
        }
        size_t got = fread(buf + n, 1, cap - n, stdin);
        n += got;
        if (got == 0) break;
    }
    if (ferror(stdin)) {
        free(buf);
        return sl_fail(e, "<stdin>: read error");
    }
    buf[n] = 0;
    *data = buf;
    *size = n;
    return 0;
}

void sl_scene_files(const sl_scene *s, const char *files[SL_SCENE_FILES]) {
    files[0] = s->path;
    files[1] = s->hair_file;
    files[2] = s->strand_sigma_a;
    files[3] = s->env_file;
    files[4] = s->env_lobes;
}

int sl_scene_load(const char *path, sl_scene *s, sl_err *e) {
    unsigned char *data;
    size_t n;
    if (strcmp(path, "-") == 0) {
        if (read_stdin(&data, &n, 16u << 20, e)) return -1;
        int rc = sl_scene_parse((const char *)data, n, "<stdin>", s, e);
        free(data);
        return rc;
    }
    if (sl_read_file(path, &data, &n, 16u << 20, e)) return -1;
    int rc = sl_scene_parse((const char *)data, n, path, s, e);
    free(data);
    return rc;
}
