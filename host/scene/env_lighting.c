/* env_lighting.c: see env_lighting.h. */
#include "scene/env_lighting.h"

#include "base/disk_cache.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Layout of a fitted-lobes cache entry's payload (the lobes JSON text); bump when it changes. */
#define LOBES_FORMAT 1u

/* The "fit" record: everything needed to tell whether lobes are stale and how good they are. */
char *sl_envfit_record(const char *map_path, const sl_envmap *m, const sl_envfit_settings *s,
                       int clamp, const sl_envfit_report *r, int count) {
    cJSON *fit = cJSON_CreateObject();
    char hash[32];
    snprintf(hash, sizeof hash, "%016llx", (unsigned long long)m->hash);
    cJSON_AddStringToObject(fit, "map_hash", hash);
    cJSON_AddStringToObject(fit, "map", map_path);
    cJSON *size = cJSON_AddArrayToObject(fit, "map_size");
    cJSON_AddItemToArray(size, cJSON_CreateNumber(m->width));
    cJSON_AddItemToArray(size, cJSON_CreateNumber(m->height));
    cJSON *st = cJSON_AddObjectToObject(fit, "settings");
    if (s->lobes > 0)
        cJSON_AddNumberToObject(st, "lobes", s->lobes);
    else {
        cJSON_AddStringToObject(st, "lobes", "auto");
        cJSON_AddNumberToObject(st, "target_error", s->target_error);
        cJSON_AddNumberToObject(st, "max_lobes", s->max_lobes);
    }
    cJSON_AddNumberToObject(st, "lambda_min",
                            s->lambda_min > 0 ? s->lambda_min : 0.25 * M_PI / m->height);
    cJSON_AddNumberToObject(st, "lambda_max", s->lambda_max);
    cJSON_AddNumberToObject(st, "effort", s->effort);
    cJSON_AddNumberToObject(st, "conv_lambda_deg", s->conv_lambda * 180 / M_PI);
    cJSON_AddBoolToObject(st, "clamp_nonfinite", clamp);
    cJSON_AddStringToObject(fit, "method",
                            "greedy matching pursuit + coarse-to-fine bounded Levenberg-Marquardt");
    cJSON_AddNumberToObject(fit, "lobes", count);
    cJSON_AddNumberToObject(fit, "rel_l2", r->rel_l2);
    cJSON_AddNumberToObject(fit, "lobe_conv_rel_l2", r->lobe_conv_rel_l2);
    cJSON_AddNumberToObject(fit, "time_s", round(r->time_s * 1000) / 1000);
    cJSON_AddNumberToObject(fit, "iterations", r->iterations);
    cJSON_AddNumberToObject(fit, "levels", r->levels);
    cJSON_AddNumberToObject(fit, "sun_lobes", r->suns);
    cJSON_AddStringToObject(fit, "version", SL_VERSION);
    char *txt = cJSON_PrintUnformatted(fit);
    cJSON_Delete(fit);
    return txt;
}

int sl_scene_lobes(const sl_scene *s, int clamp_nonfinite, sl_lobes *out, sl_err *e) {
    memset(out, 0, sizeof *out);
    if (s->env_lobes[0]) {
        if (sl_lobes_load(s->env_lobes, out, e)) return -1;
        /* Both a map and lobes: the lobes must be the map's (the frame shades the lobes, the
         * references the map); a file fitted to another map is refused, not used silently. */
        if (s->env_file[0] && out->map_hash[0]) {
            sl_envmap map = {0};
            if (sl_envmap_load(s->env_file, clamp_nonfinite, &map, e)) {
                sl_lobes_free(out);
                return -1;
            }
            char hash[32];
            snprintf(hash, sizeof hash, "%016llx", (unsigned long long)map.hash);
            sl_envmap_free(&map);
            if (strcmp(hash, out->map_hash) != 0) {
                sl_fail(e,
                        "%s: environment.lobes: %s was fitted to another map (map_hash %s; "
                        "environment.file %s has %s): refit with `strandlight fit` or drop one key",
                        s->path, s->env_lobes, out->map_hash, s->env_file, hash);
                sl_lobes_free(out);
                return -1;
            }
        }
        return 0;
    }
    sl_envmap map = {0};
    if (sl_envmap_load(s->env_file, clamp_nonfinite, &map, e)) return -1;
    sl_envfit_settings set;
    sl_envfit_default_settings(&set);
    set.lobes = s->lobes;
    set.progress = 1;
    /* Cache key: the decoded pixels' hash, the lobe count and the program version (a newer
     * fitter may fit better). The entry's payload is the lobes file text sl_lobes_save writes. */
    char dir[4096], path[4600] = "", what[64];
    snprintf(what, sizeof what, "n%d-v%s-f%d", set.lobes, SL_VERSION, SL_ENVFIT_REVISION);
    sl_cache_key key = {map.hash, sl_hash64(what, strlen(what), 0x4c4f424553ull)};
    if (sl_cache_dir_find(dir, sizeof dir))
        sl_cache_path(path, sizeof path, dir, "lobes", key, LOBES_FORMAT);
    if (path[0]) {
        sl_err ce = {{0}};
        void *text = NULL;
        size_t n = 0;
        int rc = sl_cache_read(path, LOBES_FORMAT, key, (size_t)256 << 20, &text, &n, &ce);
        if (rc == 0) {
            rc = sl_lobes_parse(text, n, path, out, &ce);
            free(text);
            if (rc == 0) {
                sl_note("environment: %d lobes from the cache (%s)", out->count, path);
                sl_envmap_free(&map);
                return 0;
            }
        }
        if (rc < 0) sl_warn("ignoring a bad cache entry: %s", ce.msg);
    }
    sl_envfit_report rep;
    if (sl_envfit(&map, &set, out, &rep, e)) {
        sl_envmap_free(&map);
        return -1;
    }
    out->fit_json = sl_envfit_record(s->env_file, &map, &set, clamp_nonfinite, &rep, out->count);
    sl_note(
        "environment: fitted %d lobes to %s in %.2f s (rel_l2 %.3f, through a 10 deg lobe %.3f)",
        out->count, s->env_file, rep.time_s, rep.rel_l2, rep.lobe_conv_rel_l2);
    if (path[0]) {
        sl_err ce = {{0}};
        size_t n = 0;
        char *text = sl_lobes_format(out, path, &n, &ce);
        sl_cache_part part = {text, n};
        if (!text || sl_cache_write(path, LOBES_FORMAT, key, &part, 1, 0, &ce))
            sl_warn("cannot cache the fitted lobes: %s", ce.msg);
        free(text);
    }
    sl_envmap_free(&map);
    return 0;
}

void sl_lobes_transform(sl_lobes *l, double rotation_deg, double intensity) {
    double r = rotation_deg * M_PI / 180.0, c = cos(r), sn = sin(r);
    for (int i = 0; i < l->count; i++) {
        double *d = l->lobe[i].dir, x = d[0], z = d[2];
        d[0] = c * x + sn * z;
        d[2] = -sn * x + c * z;
        for (int k = 0; k < 3; k++)
            l->lobe[i].rgb[k] *= intensity;
    }
}
