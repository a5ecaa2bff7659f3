/* envsample.c: median-cut directional lights for an environment map (see envsample.h). */
#include "lighting/envsample.h"

#include "lighting/envfit.h"
#include "base/json_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct region {
    int x0, y0, x1, y1; /* [x0, x1) x [y0, y1) */
    double power;       /* sum of Omega * luminance */
} region;

typedef struct sat {
    int w, h;
    double *s; /* (w+1) x (h+1) summed-area table of Omega * luminance */
} sat;

static double lum(const float *p) {
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

static double sat_sum(const sat *t, int x0, int y0, int x1, int y1) {
    int W = t->w + 1;
    return t->s[(size_t)y1 * W + x1] - t->s[(size_t)y0 * W + x1] - t->s[(size_t)y1 * W + x0] +
           t->s[(size_t)y0 * W + x0];
}

static double rsum(const sat *t, const region *r) {
    return sat_sum(t, r->x0, r->y0, r->x1, r->y1);
}

/* Splits r at its power median across its angularly longer side; returns 0 if it is one pixel. */
static int split(const sat *t, const region *r, region *a, region *b) {
    int nw = r->x1 - r->x0, nh = r->y1 - r->y0;
    if (nw <= 1 && nh <= 1) return 0;
    double thm = M_PI * 0.5 * (r->y0 + r->y1) / t->h;
    double ang_w = nw * 2 * M_PI / t->w * sin(thm), ang_h = nh * M_PI / t->h;
    int horiz = nh <= 1 || (nw > 1 && ang_w >= ang_h); /* cut along x */
    *a = *b = *r;
    double half = 0.5 * r->power;
    if (horiz) {
        /* Smallest cut c in (x0, x1) with power of [x0, c) >= half. */
        int lo = r->x0 + 1, hi = r->x1 - 1, c = hi;
        while (lo <= hi) {
            int m = (lo + hi) / 2;
            if (sat_sum(t, r->x0, r->y0, m, r->y1) >= half) {
                c = m;
                hi = m - 1;
            } else {
                lo = m + 1;
            }
        }
        if (r->power <= 0) c = (r->x0 + r->x1) / 2;
        a->x1 = b->x0 = c;
    } else {
        int lo = r->y0 + 1, hi = r->y1 - 1, c = hi;
        while (lo <= hi) {
            int m = (lo + hi) / 2;
            if (sat_sum(t, r->x0, r->y0, r->x1, m) >= half) {
                c = m;
                hi = m - 1;
            } else {
                lo = m + 1;
            }
        }
        if (r->power <= 0) c = (r->y0 + r->y1) / 2;
        a->y1 = b->y0 = c;
    }
    a->power = fmax(0.0, rsum(t, a));
    b->power = fmax(0.0, rsum(t, b));
    return 1;
}

static double light_power(const sl_envlight *l) {
    return l->rgb[0] + l->rgb[1] + l->rgb[2];
}

static int cmp_light(const void *pa, const void *pb) {
    double a = light_power(pa), b = light_power(pb);
    return a > b ? -1 : a < b ? 1 : 0;
}

int sl_envsample(const sl_envmap *map, int n, double conv_lambda, int threads, sl_envlights *out,
                 double *rel_l2, double *conv_rel_l2, sl_err *e) {
    memset(out, 0, sizeof *out);
    int w = map->width, h = map->height;
    if (n < 1) return sl_fail(e, "sample: the number of lights must be >= 1");
    if (w < 1 || h < 1 || !map->rgb) return sl_fail(e, "sample: the environment map is empty");
    if ((long)n > (long)w * h) n = w * h;
    sat t = {w, h, sl_calloc((size_t)(w + 1) * (h + 1), sizeof(double))};
    for (int y = 0; y < h; y++) {
        double om = sl_envmap_pixel_solid_angle(w, h, y), row = 0;
        for (int x = 0; x < w; x++) {
            const float *p = map->rgb + ((size_t)y * w + x) * 3;
            double v = lum(p);
            row += om * (v > 0 && isfinite(v) ? v : 0);
            t.s[(size_t)(y + 1) * (w + 1) + x + 1] = t.s[(size_t)y * (w + 1) + x + 1] + row;
        }
    }
    region *R = sl_malloc(sizeof *R * (size_t)n);
    int nr = 1;
    R[0] = (region){0, 0, w, h, 0};
    R[0].power = rsum(&t, &R[0]);
    while (nr < n) {
        /* Most powerful splittable region; ties go to the larger region, then the first. */
        int best = -1;
        for (int i = 0; i < nr; i++) {
            int area = (R[i].x1 - R[i].x0) * (R[i].y1 - R[i].y0);
            if (area <= 1) continue;
            if (best < 0 || R[i].power > R[best].power ||
                (R[i].power == R[best].power &&
                 area > (R[best].x1 - R[best].x0) * (R[best].y1 - R[best].y0)))
                best = i;
        }
        if (best < 0) break;
        region a, b;
        if (!split(&t, &R[best], &a, &b)) break;
        R[best] = a;
        R[nr++] = b;
    }
    free(t.s);
    /* One light per region: power per channel and power-weighted mean direction. */
    out->light = sl_calloc((size_t)nr, sizeof *out->light);
    out->count = nr;
    double num = 0, den = 0;
    for (int i = 0; i < nr; i++) {
        const region *r = &R[i];
        sl_envlight *L = &out->light[i];
        double dsum[3] = {0, 0, 0}, om_sum = 0;
        for (int y = r->y0; y < r->y1; y++) {
            double om = sl_envmap_pixel_solid_angle(w, h, y);
            om_sum += om * (r->x1 - r->x0);
            for (int x = r->x0; x < r->x1; x++) {
                const float *p = map->rgb + ((size_t)y * w + x) * 3;
                double d[3], v = lum(p);
                sl_envmap_dir(w, h, x, y, d);
                for (int k = 0; k < 3; k++) {
                    L->rgb[k] += om * p[k];
                    dsum[k] += om * (v > 0 ? v : 0) * d[k];
                }
            }
        }
        L->solid_angle = om_sum;
        double nd = sqrt(dsum[0] * dsum[0] + dsum[1] * dsum[1] + dsum[2] * dsum[2]);
        if (!(nd > 0)) { /* black region: its centre */
            sl_envmap_dir(w, h, 0.5 * (r->x0 + r->x1) - 0.5, 0.5 * (r->y0 + r->y1) - 0.5, dsum);
            nd = 1;
        }
        for (int k = 0; k < 3; k++)
            L->dir[k] = dsum[k] / nd;
        if (rel_l2)
            for (int y = r->y0; y < r->y1; y++) {
                double om = sl_envmap_pixel_solid_angle(w, h, y);
                for (int x = r->x0; x < r->x1; x++) {
                    const float *p = map->rgb + ((size_t)y * w + x) * 3;
                    for (int k = 0; k < 3; k++) {
                        double m = L->rgb[k] / om_sum;
                        num += om * (m - p[k]) * (m - p[k]);
                        den += om * (double)p[k] * p[k];
                    }
                }
            }
    }
    free(R);
    qsort(out->light, (size_t)nr, sizeof *out->light, cmp_light);
    if (rel_l2) *rel_l2 = den > 0 ? sqrt(num / den) : (num > 0 ? INFINITY : 0);
    if (conv_rel_l2) {
        sl_lobe *lb = sl_malloc(sizeof *lb * (size_t)nr);
        for (int i = 0; i < nr; i++) {
            memcpy(lb[i].dir, out->light[i].dir, sizeof lb[i].dir);
            memcpy(lb[i].rgb, out->light[i].rgb, sizeof lb[i].rgb);
            lb[i].lambda = 0; /* directional */
        }
        *conv_rel_l2 = sl_envfit_conv_rel_l2(map, lb, nr, conv_lambda, threads);
        free(lb);
    }
    return 0;
}

void sl_envlights_free(sl_envlights *l) {
    if (!l) return;
    free(l->light);
    free(l->record_json);
    memset(l, 0, sizeof *l);
}

int sl_envlights_save(const char *path, const sl_envlights *l, sl_err *e) {
    if (l->count < 1) return sl_fail(e, "%s: no lights to write", path);
    cJSON *rec = NULL;
    if (l->record_json && !(rec = cJSON_Parse(l->record_json)))
        return sl_fail(e, "%s: internal: the \"sample\" record is not JSON", path);
    sl_atomic_file af;
    if (sl_make_parent_dirs(path, e) || sl_atomic_open(&af, path, e)) {
        cJSON_Delete(rec);
        return -1;
    }
    fprintf(af.fp, "{\n  \"lights\": [\n");
    for (int i = 0; i < l->count; i++) {
        const sl_envlight *L = &l->light[i];
        fprintf(
            af.fp,
            "    {\"dir\": [%.17g, %.17g, %.17g], \"rgb\": [%.9g, %.9g, %.9g], \"solid_angle\": "
            "%.9g}%s\n",
            L->dir[0], L->dir[1], L->dir[2], L->rgb[0], L->rgb[1], L->rgb[2], L->solid_angle,
            i + 1 < l->count ? "," : "");
    }
    fprintf(af.fp, "  ]");
    if (rec) {
        char *txt = cJSON_Print(rec);
        fprintf(af.fp, ",\n  \"sample\": ");
        for (const char *c = txt; *c; c++) {
            fputc(*c, af.fp);
            if (*c == '\n') fputs("  ", af.fp);
        }
        free(txt);
        cJSON_Delete(rec);
    }
    fprintf(af.fp, "\n}\n");
    return sl_atomic_commit(&af, e);
}

int sl_envlights_load(const char *path, sl_envlights *out, sl_err *e) {
    memset(out, 0, sizeof *out);
    unsigned char *data;
    size_t size;
    if (sl_read_file(path, &data, &size, (size_t)256 << 20, e)) return -1;
    int rc = sl_envlights_parse((const char *)data, size, path, out, e);
    free(data);
    return rc;
}

int sl_envlights_parse(const char *text, size_t len, const char *path, sl_envlights *out,
                       sl_err *e) {
    memset(out, 0, sizeof *out);
    cJSON *root = sl_json_parse(text, len, path, e);
    if (!root) return -1;
    int rc = -1;
    static const char *const top_keys[] = {"lights", "sample", NULL};
    static const char *const keys[] = {"dir", "rgb", "solid_angle", NULL};
    sl_json_ctx top = {path, ""};
    const cJSON *arr;
    if (!cJSON_IsObject(root)) {
        sl_fail(e, "%s: expected a JSON object with a \"lights\" array", path);
        goto done;
    }
    if (sl_json_check_keys(&top, root, top_keys, e)) goto done;
    arr = cJSON_GetObjectItemCaseSensitive(root, "lights");
    if (!cJSON_IsArray(arr) || cJSON_GetArraySize(arr) < 1 ||
        cJSON_GetArraySize(arr) > SL_LOBES_MAX) {
        sl_fail(e, "%s: lights: expected an array of 1 to %d lights", path, SL_LOBES_MAX);
        goto done;
    }
    out->count = cJSON_GetArraySize(arr);
    out->light = sl_calloc((size_t)out->count, sizeof *out->light);
    int i = 0;
    for (const cJSON *it = arr->child; it; it = it->next, i++) {
        char prefix[64];
        snprintf(prefix, sizeof prefix, "lights[%d]", i);
        sl_json_ctx c = {path, prefix};
        sl_envlight *L = &out->light[i];
        if (!cJSON_IsObject(it)) {
            sl_fail(e, "%s: %s: expected an object", path, prefix);
            goto done;
        }
        if (sl_json_check_keys(&c, it, keys, e) || sl_json_vec(&c, it, "dir", 1, 3, L->dir, e) ||
            sl_json_vec(&c, it, "rgb", 1, 3, L->rgb, e) ||
            sl_json_number(&c, it, "solid_angle", 0, &L->solid_angle, e))
            goto done;
        double nd = sqrt(L->dir[0] * L->dir[0] + L->dir[1] * L->dir[1] + L->dir[2] * L->dir[2]);
        if (fabs(nd - 1) > 1e-3) {
            sl_fail(e, "%s: %s.dir: expected a unit vector (length %.6g)", path, prefix, nd);
            goto done;
        }
        for (int k = 0; k < 3; k++) {
            L->dir[k] /= nd;
            if (L->rgb[k] < 0) {
                sl_fail(e, "%s: %s.rgb[%d]: expected a finite number >= 0", path, prefix, k);
                goto done;
            }
        }
    }
    const cJSON *rec = cJSON_GetObjectItemCaseSensitive(root, "sample");
    if (rec) out->record_json = cJSON_PrintUnformatted(rec);
    rc = 0;
done:
    cJSON_Delete(root);
    if (rc) sl_envlights_free(out);
    return rc;
}
