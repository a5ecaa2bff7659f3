/* viewer_doc.c: the viewer's scene document. Every edit (script `set`, a panel widget, a dropped
 * file, environment rotation) changes the scene JSON and re-validates it with the scene loader,
 * so the viewer accepts exactly what `strandlight render` accepts and reports the same errors;
 * `save` writes that document back with the live camera, absolute paths and the painted
 * per-strand absorption (material.strand_sigma_a, host/scene/scene_strands.h). */
#include "viewer/viewer.h"

#include "scene/env_lighting.h"
#include "scene/scene_hair.h"
#include "scene/scene_inputs.h"
#include "scene/scene_strands.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Walks "a.b.c" below root, creating objects on the way; returns the parent object of the last
 * component (its name in *leaf), or NULL when a component exists and is not an object. */
static cJSON *walk(cJSON *root, const char *key, char *leaf, size_t n) {
    char buf[512];
    snprintf(buf, sizeof buf, "%s", key);
    cJSON *cur = root;
    char *part = buf, *dot;
    while ((dot = strchr(part, '.')) != NULL) {
        *dot = 0;
        cJSON *child = cJSON_GetObjectItemCaseSensitive(cur, part);
        if (!child) child = cJSON_AddObjectToObject(cur, part);
        if (!cJSON_IsObject(child)) return NULL;
        cur = child;
        part = dot + 1;
    }
    size_t len = strlen(part);
    if (len >= n) return NULL;
    memcpy(leaf, part, len + 1);
    return cur;
}

static void put(cJSON *obj, const char *name, cJSON *item) {
    if (cJSON_GetObjectItemCaseSensitive(obj, name))
        cJSON_ReplaceItemInObjectCaseSensitive(obj, name, item);
    else
        cJSON_AddItemToObject(obj, name, item);
}

static void del(cJSON *root, const char *obj_name, const char *key) {
    cJSON *o = cJSON_GetObjectItemCaseSensitive(root, obj_name);
    if (cJSON_IsObject(o)) cJSON_DeleteItemFromObjectCaseSensitive(o, key);
}

static int same_hair(const sl_scene *a, const sl_scene *b) {
    return strcmp(a->hair_file, b->hair_file) == 0 && a->hair_procedural == b->hair_procedural &&
           a->proc_style == b->proc_style && a->proc_strands == b->proc_strands &&
           a->proc_points == b->proc_points && a->proc_seed == b->proc_seed && a->up_z == b->up_z &&
           a->radius == b->radius && a->has_follow == b->has_follow &&
           a->follow_per_guide == b->follow_per_guide &&
           a->follow_root_radius == b->follow_root_radius &&
           a->follow_tip_spread == b->follow_tip_spread;
}

static int same_lobes(const sl_scene *a, const sl_scene *b) {
    return strcmp(a->env_file, b->env_file) == 0 && strcmp(a->env_lobes, b->env_lobes) == 0 &&
           (a->env_lobes[0] || a->lobes == b->lobes);
}

static int same_camera(const sl_scene *a, const sl_scene *b) {
    return a->has_eye == b->has_eye && a->has_target == b->has_target &&
           memcmp(a->eye, b->eye, sizeof a->eye) == 0 &&
           memcmp(a->target, b->target, sizeof a->target) == 0 &&
           memcmp(a->up, b->up, sizeof a->up) == 0 && a->fov_deg == b->fov_deg;
}

static int same_strand_key(const sl_scene *a, const sl_scene *b) {
    return a->strand_sigma_a_colors == b->strand_sigma_a_colors &&
           strcmp(a->strand_sigma_a, b->strand_sigma_a) == 0;
}

void sl_viewer_camera_from_scene(sl_viewer *v) {
    const sl_scene *s = &v->scene;
    double target[3];
    sl_camera c; /* framed as `strandlight render` frames it (scene_inputs.h) */
    sl_scene_camera(s, v->lo, v->hi, s->width, s->height, target, &c);
    for (int k = 0; k < 3; k++) {
        v->eye[k] = v->home_eye[k] = c.eye[k];
        v->target[k] = v->home_target[k] = target[k];
        v->up[k] = v->home_up[k] = s->up[k];
    }
}

int sl_viewer_load_hair(sl_viewer *v, sl_err *e) {
    sl_hair h;
    if (sl_scene_load_hair(&v->scene, &h, e)) return -1;
    sl_hair_free(&v->hair);
    v->hair = h;
    sl_hair_bounds(&v->hair, v->lo, v->hi);
    sl_paint_reset(&v->paint, v->hair.num_strands);
    return sl_viewer_paint_from_scene(v, e);
}

static void lobes_copy(const sl_lobes *src, sl_lobes *dst, int max) {
    memset(dst, 0, sizeof *dst);
    int n = src->count < max ? src->count : max;
    dst->count = n;
    dst->lobe = sl_malloc((size_t)(n ? n : 1) * sizeof *dst->lobe);
    if (n) memcpy(dst->lobe, src->lobe, (size_t)n * sizeof *dst->lobe);
}

static double lobe_power(const sl_lobe *l) {
    return (l->rgb[0] + l->rgb[1] + l->rgb[2]) * sl_lobe_integral(l->lambda);
}

void sl_viewer_transform_lobes(sl_viewer *v) {
    sl_lobes_free(&v->lobes);
    sl_lobes_free(&v->lobes_preview);
    lobes_copy(&v->lobes_raw, &v->lobes, v->lobes_raw.count);
    sl_lobes_transform(&v->lobes, v->scene.env_rotation_deg, v->scene.env_intensity);
    /* preview: the strongest lobes (selection sort; counts are small), dropped power not
     * redistributed: the preview is a little darker where weak lobes lit the hair */
    lobes_copy(&v->lobes, &v->lobes_preview, v->lobes.count);
    int keep = v->lobes.count < SL_VIEWER_PREVIEW_LOBES ? v->lobes.count : SL_VIEWER_PREVIEW_LOBES;
    for (int i = 0; i < keep; i++) {
        int best = i;
        for (int j = i + 1; j < v->lobes_preview.count; j++)
            if (lobe_power(&v->lobes_preview.lobe[j]) > lobe_power(&v->lobes_preview.lobe[best]))
                best = j;
        sl_lobe t = v->lobes_preview.lobe[i];
        v->lobes_preview.lobe[i] = v->lobes_preview.lobe[best];
        v->lobes_preview.lobe[best] = t;
    }
    v->lobes_preview.count = keep;
}

int sl_viewer_load_lobes(sl_viewer *v, sl_err *e) {
    sl_lobes l;
    if (sl_scene_lobes(&v->scene, 0, &l, e)) return -1;
    sl_lobes_free(&v->lobes_raw);
    v->lobes_raw = l;
    sl_viewer_transform_lobes(v);
    return 0;
}

/* Parses doc into a scene (with the --size override). */
static int parse_doc(const sl_viewer *v, const cJSON *doc, sl_scene *s, sl_err *e) {
    char *text = cJSON_PrintUnformatted(doc);
    if (!text) return sl_fail(e, "%s: cannot serialise the scene", v->scene_path);
    int rc = sl_scene_parse(text, strlen(text), v->scene_path, s, e);
    cJSON_free(text);
    if (rc) return -1;
    sl_scene_set_size(s, v->size_w, v->size_h);
    return 0;
}

int sl_viewer_parse_doc(sl_viewer *v, sl_err *e) {
    return parse_doc(v, v->doc, &v->scene, e);
}

/* Makes doc the viewer's document when it validates; reloads what changed. Takes doc. */
static int adopt(sl_viewer *v, cJSON *doc, sl_err *e) {
    sl_scene *ns = sl_malloc(sizeof *ns);
    if (parse_doc(v, doc, ns, e)) {
        cJSON_Delete(doc);
        free(ns);
        return -1;
    }
    sl_scene old = v->scene;
    v->scene = *ns;
    free(ns);
    int rc = 0;
    if (!same_hair(&old, &v->scene)) {
        rc = sl_viewer_load_hair(v, e);
        if (!rc) sl_viewer_camera_from_scene(v);
    } else if (!same_strand_key(&old, &v->scene)) {
        sl_paint_reset(&v->paint, v->hair.num_strands);
        rc = sl_viewer_paint_from_scene(v, e);
    }
    if (!rc && !same_lobes(&old, &v->scene)) rc = sl_viewer_load_lobes(v, e);
    if (!rc && (old.env_rotation_deg != v->scene.env_rotation_deg ||
                old.env_intensity != v->scene.env_intensity))
        sl_viewer_transform_lobes(v);
    if (!rc && (!same_camera(&old, &v->scene) || old.width != v->scene.width ||
                old.height != v->scene.height))
        sl_viewer_camera_from_scene(v);
    if (rc) {
        /* a file the scene names failed to load: keep the previous scene and inputs */
        cJSON_Delete(doc);
        v->scene = old;
        return -1;
    }
    cJSON_Delete(v->doc);
    v->doc = doc;
    v->dirty = 1;
    v->refined = 0;
    return 0;
}

/* After material.model was set to val: delete the material keys that model lacks. */
static void model_keys(cJSON *doc, const cJSON *val) {
    cJSON *mat = cJSON_GetObjectItemCaseSensitive(doc, "material");
    const cJSON *mel = cJSON_GetObjectItemCaseSensitive(mat, "melanin");
    int chiang = cJSON_IsString(val) && val->valuestring && strcmp(val->valuestring, "chiang") == 0;
    for (const char *const *k = chiang ? sl_material_lobe_keys : sl_material_chiang_keys; *k; k++)
        del(doc, "material", *k);
    /* melanin is an object (eumelanin, pheomelanin) for marschner / deon, a number for chiang */
    if (mel && (chiang ? !cJSON_IsNumber(mel) : cJSON_IsNumber(mel)))
        del(doc, "material", "melanin");
}

int sl_viewer_set(sl_viewer *v, const char *key, const char *value, sl_err *e) {
    cJSON *doc = cJSON_Duplicate(v->doc, 1);
    char leaf[128];
    cJSON *obj = walk(doc, key, leaf, sizeof leaf);
    if (!obj || !leaf[0] || strchr(key, '.') == NULL) {
        cJSON_Delete(doc);
        return sl_fail(e, "%s: set %s: expected a key like material.beta_R_deg", v->scene_path,
                       key);
    }
    cJSON *val = cJSON_Parse(value);
    if (!val) val = cJSON_CreateString(value);
    put(obj, leaf, val);
    /* keys that exclude each other: the newer one wins */
    if (strcmp(key, "material.sigma_a") == 0) {
        del(doc, "material", "melanin");
        del(doc, "material", "melanin_redness"); /* chiang's pigment keys */
        del(doc, "material", "tint");
    }
    if (strncmp(key, "material.melanin", 16) == 0 || strcmp(key, "material.tint") == 0)
        del(doc, "material", "sigma_a");
    /* a model switch drops the keys the new model does not have (numerics.md sec. 2: chiang's
     * keys and the marschner / deon lobe keys are errors in each other's materials) */
    if (strcmp(key, "material.model") == 0) model_keys(doc, val);
    if (strcmp(key, "hair.file") == 0) del(doc, "hair", "procedural");
    if (strncmp(key, "hair.procedural", 15) == 0) del(doc, "hair", "file");
    if (strcmp(key, "environment.file") == 0) del(doc, "environment", "lobes");
    return adopt(v, doc, e);
}

int sl_viewer_drop(sl_viewer *v, const char *path, sl_err *e) {
    char abs[PATH_MAX];
    if (!realpath(path, abs)) return sl_fail(e, "%s: cannot open the dropped file", path);
    char q[PATH_MAX + 8];
    cJSON *s = cJSON_CreateString(abs);
    char *js = cJSON_PrintUnformatted(s);
    snprintf(q, sizeof q, "%s", js);
    cJSON_free(js);
    cJSON_Delete(s);
    if (sl_ext_is(abs, "hair") || sl_ext_is(abs, "tfx") || sl_ext_is(abs, "tfxproj") ||
        sl_ext_is(abs, "data"))
        return sl_viewer_set(v, "hair.file", q, e);
    if (sl_ext_is(abs, "exr") || sl_ext_is(abs, "hdr"))
        return sl_viewer_set(v, "environment.file", q, e);
    return sl_fail(
        e, "%s: not a hair file (.hair .tfx .tfxproj .data) or environment map (.exr .hdr)", path);
}

/* An absolute form of a path the scene resolved (relative to the working directory). */
static cJSON *abs_path(const char *p) {
    char buf[8192], cwd[4096];
    if (p[0] == '/' || !getcwd(cwd, sizeof cwd))
        snprintf(buf, sizeof buf, "%s", p);
    else
        snprintf(buf, sizeof buf, "%s/%s", cwd, p);
    return cJSON_CreateString(buf);
}

static void put_path(cJSON *root, const char *obj_name, const char *key, const char *resolved) {
    cJSON *o = cJSON_GetObjectItemCaseSensitive(root, obj_name);
    if (cJSON_IsObject(o) && cJSON_GetObjectItemCaseSensitive(o, key) && resolved[0])
        put(o, key, abs_path(resolved));
}

static cJSON *vec3(const double *d) {
    return cJSON_CreateDoubleArray(d, 3);
}

int sl_viewer_save(sl_viewer *v, const char *path, sl_err *e) {
    cJSON *doc = cJSON_Duplicate(v->doc, 1);
    const sl_scene *s = &v->scene;
    put_path(doc, "hair", "file", s->hair_file);
    put_path(doc, "environment", "file", s->env_file);
    put_path(doc, "environment", "lobes", s->env_lobes);
    put_path(doc, "output", "exr", s->out_exr);
    put_path(doc, "output", "png", s->out_png);
    char leaf[64];
    cJSON *cam = walk(doc, "camera.eye", leaf, sizeof leaf);
    put(cam, "eye", vec3(v->eye));
    put(cam, "target", vec3(v->target));
    put(cam, "up", vec3(v->up));
    put(cam, "fov_deg", cJSON_CreateNumber(s->fov_deg));
    cJSON *img = walk(doc, "image.width", leaf, sizeof leaf);
    put(img, "width", cJSON_CreateNumber(s->width));
    put(img, "height", cJSON_CreateNumber(s->height));
    cJSON *mat = walk(doc, "material.strand_sigma_a", leaf, sizeof leaf);
    int rc = -1;
    char csv[4200] = "";
    float *sa = sl_viewer_paint_array(v);
    if (sa) {
        /* PATH's stem + .strands.csv, named relative to the saved scene (same directory) */
        const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
        if (!dot || (slash && dot < slash)) dot = path + strlen(path);
        snprintf(csv, sizeof csv, "%.*s.strands.csv", (int)(dot - path), path);
        const char *base = strrchr(csv, '/');
        put(mat, "strand_sigma_a", cJSON_CreateString(base ? base + 1 : csv));
        float b[3] = {(float)s->material.sigma_a[0], (float)s->material.sigma_a[1],
                      (float)s->material.sigma_a[2]};
        if (sl_strand_sigma_a_write_csv(csv, sa, v->hair.num_strands, b, e)) goto done;
    } else {
        cJSON_DeleteItemFromObjectCaseSensitive(mat, "strand_sigma_a");
    }
    char *text = cJSON_Print(doc);
    sl_atomic_file af;
    if (sl_make_parent_dirs(path, e) || sl_atomic_open(&af, path, e)) {
        cJSON_free(text);
        goto done;
    }
    fputs(text, af.fp);
    fputc('\n', af.fp);
    cJSON_free(text);
    rc = sl_atomic_commit(&af, e);
done:
    free(sa);
    cJSON_Delete(doc);
    return rc;
}
