/* reference_path_record.c: the path tracer's outputs (reference_path.h): the cache key, the EXR
 * (sl_exr_write: temporary name, then rename), the JSON record beside it with the EXR's digest
 * (ref_record.h), and the cache check; sl_path_run ties them to the render. */
#include "base/disk_cache.h"
#include "path_ref.h"
#include "verify/reference/ref_record.h"
#include "verify/reference/reference_path_parts.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Bump when the path tracer's output changes for the same inputs (invalidates caches). */
#define SL_PATH_VERSION "path-2" /* path-2: material.strand_sigma_a honoured */

uint64_t sl_path_key(const sl_scene *s, const sl_path_prep *p, int spp, uint64_t seed) {
    uint64_t h = sl_hash64(SL_PATH_VERSION, strlen(SL_PATH_VERSION), SL_HASH64_BASIS);
    h = sl_ref_content_hash(h, &p->hair, p->map.hash, &s->material, &p->cam);
    h = sl_ref_strand_hash(h, p->strand_sa, p->hair.num_strands);
    double v[] = {s->material.logistic_s, s->env_rotation_deg,   s->env_intensity,    spp,
                  (double)seed,           SLREF_PATH_MAX_EVENTS, SLREF_PATH_RR_EVENTS};
    return sl_ref_hash_doubles(h, v, sizeof v / sizeof v[0]);
}

enum { NCH = 26 };
static const char *const CH_NAMES[NCH] = {
    "R",        "G",          "B",          "A",          "Z",     "direct.R", "direct.G",
    "direct.B", "indirect.R", "indirect.G", "indirect.B", "MS.R",  "MS.G",     "MS.B",
    "R_mode.R", "R_mode.G",   "R_mode.B",   "TT.R",       "TT.G",  "TT.B",     "TRT.R",
    "TRT.G",    "TRT.B",      "rest.R",     "rest.G",     "rest.B"};

static int write_exr(const char *path, const sl_path_frame *f, sl_err *e) {
    size_t n = (size_t)f->width * f->height;
    float *pl = sl_malloc(NCH * n * sizeof(float));
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 4; c++)
            pl[c * n + i] = f->rgba[4 * i + c];
        pl[4 * n + i] = f->depth[i];
        for (int c = 0; c < 3; c++) {
            pl[(5 + c) * n + i] = f->direct[3 * i + c];
            pl[(8 + c) * n + i] = f->indirect[3 * i + c];
            pl[(11 + c) * n + i] = f->indirect[3 * i + c];
        }
        for (int c = 0; c < 12; c++)
            pl[(14 + c) * n + i] = f->lobes[12 * i + c];
    }
    return sl_ref_exr_write_planes(path, f->width, f->height, CH_NAMES, NCH, pl, e);
}

static void add_num(cJSON *o, const char *k, double v) {
    if (isfinite(v))
        cJSON_AddNumberToObject(o, k, v);
    else
        cJSON_AddNullToObject(o, k);
}

static int write_json(const char *path, const sl_scene *s, const sl_path_settings *set,
                      const sl_path_result *r, int w, int h, sl_ref_digest d, sl_err *e) {
    cJSON *ref, *root = sl_ref_record_begin(r->key, s->path, w, h, &ref);
    cJSON_AddBoolToObject(ref, "path", 1);
    cJSON_AddNumberToObject(ref, "spp", r->spp);
    cJSON_AddNumberToObject(ref, "spp_asked", set->spp);
    add_num(ref, "time_budget_s", set->time_s > 0 ? set->time_s : NAN);
    cJSON_AddNumberToObject(ref, "seed", (double)set->seed);
    /* what the pixel-mode record holds, for readers of either (sl_reference_load) */
    cJSON_AddNumberToObject(ref, "lights", 0);
    cJSON_AddBoolToObject(ref, "multiple_scattering", 1);
    cJSON_AddBoolToObject(ref, "fragments", 0);
    cJSON_AddNumberToObject(ref, "time_s", r->wall_s);
    cJSON_AddNumberToObject(ref, "cpu_s", r->cpu_s);
    cJSON_AddNumberToObject(ref, "threads", r->threads);
    cJSON_AddNumberToObject(ref, "paths", (double)r->paths);
    cJSON_AddNumberToObject(ref, "paths_per_s", r->paths_per_s);
    cJSON_AddNumberToObject(ref, "events_per_path", r->events_per_path);
    cJSON_AddNumberToObject(ref, "max_events", SLREF_PATH_MAX_EVENTS);
    cJSON_AddNumberToObject(ref, "rr_events", SLREF_PATH_RR_EVENTS);
    cJSON_AddNumberToObject(ref, "capped_paths", (double)r->capped);
    sl_ref_add_mean(ref, r->mean_rgb, r->coverage);
    cJSON *nz = cJSON_AddObjectToObject(ref, "noise");
    cJSON_AddStringToObject(nz, "from", "even vs odd samples");
    add_num(nz, "rel_rmse", r->noise);
    add_num(nz, "rel_rmse_4x4", r->noise_4x4);
    add_num(nz, "rel_rmse_8x8", r->noise_8x8);
    sl_ref_integrity_add(ref, d);
    return sl_ref_json_write(path, root, e);
}

static double num_of_item(const cJSON *v) {
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

static double num_of(const cJSON *o, const char *k) {
    return num_of_item(cJSON_GetObjectItemCaseSensitive(o, k));
}

/* 1 when json_path is a path record of this key whose EXR matches its digest; fills r. */
static int read_cached(const char *json_path, const char *exr_path, uint64_t key,
                       sl_path_result *r) {
    if (access(exr_path, R_OK) != 0) return 0;
    cJSON *root = sl_ref_json_read(json_path);
    if (!root) return 0;
    const cJSON *ref = cJSON_GetObjectItemCaseSensitive(root, "reference");
    int ok =
        cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(ref, "path")) && sl_ref_key_matches(ref, key);
    sl_ref_digest d;
    if (ok && (sl_cache_file_hash(exr_path, &d.hash, &d.bytes, NULL) != 0 ||
               !sl_ref_integrity_matches(ref, d))) {
        sl_warn("reference: %s does not match the digest in %s; rendering it again", exr_path,
                json_path);
        ok = 0;
    }
    if (ok) {
        r->cached = 1, r->key = key;
        r->spp = (int)num_of(ref, "spp");
        r->wall_s = num_of(ref, "time_s"), r->cpu_s = num_of(ref, "cpu_s");
        r->paths_per_s = num_of(ref, "paths_per_s");
        r->coverage = num_of(ref, "coverage");
        const cJSON *mv = cJSON_GetObjectItemCaseSensitive(ref, "mean_rgb");
        for (int c = 0; c < 3 && cJSON_GetArraySize(mv) == 3; c++)
            r->mean_rgb[c] = num_of_item(cJSON_GetArrayItem(mv, c));
        const cJSON *nz = cJSON_GetObjectItemCaseSensitive(ref, "noise");
        r->noise = num_of(nz, "rel_rmse");
        r->noise_4x4 = num_of(nz, "rel_rmse_4x4");
        r->noise_8x8 = num_of(nz, "rel_rmse_8x8");
    }
    cJSON_Delete(root);
    return ok;
}

int sl_path_run(const sl_scene *s, const sl_path_settings *set, const char *exr_path, int force,
                sl_path_result *r, sl_err *e) {
    memset(r, 0, sizeof *r);
    sl_path_prep p;
    if (sl_path_prepare(s, set, &p, e)) return -1;
    char json_path[4200];
    snprintf(json_path, sizeof json_path, "%s.json", exr_path);
    /* with a time budget the samples reached are not known before: never a cache hit */
    if (!(set->time_s > 0) && !force &&
        read_cached(json_path, exr_path, sl_path_key(s, &p, set->spp, set->seed), r)) {
        r->spp_asked = set->spp;
        sl_path_prep_free(&p);
        return 0;
    }
    sl_path_frame f;
    int rc = -1;
    if (sl_path_render_prepared(s, set, &p, &f, r, e)) goto done;
    r->key = sl_path_key(s, &p, r->spp, set->seed);
    if (write_exr(exr_path, &f, e)) goto done;
    sl_ref_digest d;
    if (sl_cache_file_hash(exr_path, &d.hash, &d.bytes, e)) goto done;
    if (write_json(json_path, s, set, r, f.width, f.height, d, e)) goto done;
    rc = 0;
done:
    sl_path_frame_free(&f);
    sl_path_prep_free(&p);
    return rc;
}
