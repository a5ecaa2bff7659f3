/* hair.c: the format dispatch of sl_hair_load, the invariants every loader checks, and the
 * geometry helpers (bounds, up-axis, finite tangents). Parsers live in hair_<format>.c. */
#include "io/hair/hair.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Largest hair file we read into memory; larger ones are refused before allocating. */
#define SL_HAIR_MAX_FILE ((size_t)4 << 30)

uint32_t sl_rd_u32(const unsigned char *p) {
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

float sl_rd_f32(const unsigned char *p) {
    uint32_t u = sl_rd_u32(p);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

void sl_hair_alloc(sl_hair *h, uint32_t num_strands, uint32_t num_points) {
    h->num_strands = num_strands;
    h->num_points = num_points;
    h->guide_strands = num_strands;
    h->strand_first = sl_calloc((size_t)num_strands + 1, sizeof *h->strand_first);
    h->pos = sl_malloc((size_t)num_points * 3 * sizeof *h->pos);
}

void sl_hair_free(sl_hair *h) {
    if (!h) return;
    free(h->strand_first);
    free(h->pos);
    free(h->radius);
    free(h->transparency);
    free(h->color);
    memset(h, 0, sizeof *h);
}

int sl_hair_validate(const sl_hair *h, const char *name, sl_err *e) {
    if (h->num_strands == 0) return sl_fail(e, "%s: no strands", name);
    if (h->strand_first[0] != 0 || h->strand_first[h->num_strands] != h->num_points)
        return sl_fail(e, "%s: strand offsets do not cover the %u points", name, h->num_points);
    for (uint32_t s = 0; s < h->num_strands; s++) {
        uint32_t a = h->strand_first[s], b = h->strand_first[s + 1];
        if (b < a || b - a < 2)
            return sl_fail(e, "%s: strand %u has %u point%s, need at least 2", name, s,
                           b < a ? 0 : b - a, b - a == 1 ? "" : "s");
        int moved = 0;
        for (uint32_t i = a; i < b; i++) {
            for (int c = 0; c < 3; c++) {
                float v = h->pos[3 * (size_t)i + c];
                if (!isfinite(v))
                    return sl_fail(e, "%s: strand %u point %u: coordinate %c is not finite (%g)",
                                   name, s, i - a, "xyz"[c], (double)v);
                if (v != h->pos[3 * (size_t)a + c]) moved = 1;
            }
        }
        if (!moved)
            return sl_fail(e, "%s: strand %u has zero length (all %u points coincide)", name, s,
                           b - a);
    }
    for (uint32_t i = 0; i < h->num_points; i++) {
        if (h->radius && !(h->radius[i] >= 0 && isfinite(h->radius[i])))
            return sl_fail(e, "%s: point %u: radius %g is not a finite number >= 0", name, i,
                           (double)h->radius[i]);
        if (h->transparency && !(h->transparency[i] >= 0 && h->transparency[i] <= 1))
            return sl_fail(e, "%s: point %u: transparency %g is not in [0, 1]", name, i,
                           (double)h->transparency[i]);
        for (int c = 0; h->color && c < 3; c++)
            if (!(h->color[3 * (size_t)i + c] >= 0 && isfinite(h->color[3 * (size_t)i + c])))
                return sl_fail(e, "%s: point %u: color %g is not a finite number >= 0", name, i,
                               (double)h->color[3 * (size_t)i + c]);
    }
    if (!h->radius && !(h->default_radius > 0 && isfinite(h->default_radius)))
        return sl_fail(e, "%s: default radius %g is not a positive finite number", name,
                       (double)h->default_radius);
    if (!h->transparency && !(h->default_transparency >= 0 && h->default_transparency <= 1))
        return sl_fail(e, "%s: default transparency %g is not in [0, 1]", name,
                       (double)h->default_transparency);
    for (int c = 0; !h->color && c < 3; c++)
        if (!(h->default_color[c] >= 0 && isfinite(h->default_color[c])))
            return sl_fail(e, "%s: default color %g is not a finite number >= 0", name,
                           (double)h->default_color[c]);
    return 0;
}

void sl_hair_bounds(const sl_hair *h, float lo[3], float hi[3]) {
    for (int c = 0; c < 3; c++)
        lo[c] = hi[c] = 0;
    if (!h->num_points) return;
    for (int c = 0; c < 3; c++)
        lo[c] = hi[c] = h->pos[c];
    for (size_t i = 0; i < h->num_points; i++)
        for (int c = 0; c < 3; c++) {
            float v = h->pos[3 * i + c];
            if (v < lo[c]) lo[c] = v;
            if (v > hi[c]) hi[c] = v;
        }
}

void sl_hair_estimate_radius(sl_hair *h) {
    float lo[3], hi[3];
    sl_hair_bounds(h, lo, hi);
    double d2 = 0;
    for (int c = 0; c < 3; c++)
        d2 += ((double)hi[c] - lo[c]) * ((double)hi[c] - lo[c]);
    double r = SL_HAIR_RADIUS_SCALE * sqrt(d2);
    /* A zero-extent model is rejected by sl_hair_validate (zero-length strands); keep r > 0. */
    h->default_radius = r > 0 && r < FLT_MAX ? (float)r : 1.0f;
    h->radius_source = SL_RADIUS_ESTIMATED;
}

void sl_hair_z_up_to_y_up(sl_hair *h) {
    for (size_t i = 0; i < h->num_points; i++) {
        float y = h->pos[3 * i + 1], z = h->pos[3 * i + 2];
        h->pos[3 * i + 1] = z;
        h->pos[3 * i + 2] = -y;
    }
}

/* Direction of points a -> b in double, or 0 when the segment is shorter than 4 float ulps of
 * its largest coordinate (then its direction is rounding noise: Ratboy_mohawk.tfx has segments
 * of 1.3e-7 at coordinates ~0.5, i.e. 2 ulps) or not finite. */
static int seg_dir(const float *a, const float *b, float t[3]) {
    double d[3], len2 = 0, m = 0;
    for (int c = 0; c < 3; c++) {
        d[c] = (double)b[c] - (double)a[c];
        len2 += d[c] * d[c];
        m = fmax(m, fmax(fabs((double)a[c]), fabs((double)b[c])));
    }
    double len = sqrt(len2);
    if (!(len > 4.0 * FLT_EPSILON * m) || !(len >= FLT_MIN) || !isfinite(len)) return 0;
    for (int c = 0; c < 3; c++)
        t[c] = (float)(d[c] / len);
    return 1;
}

int sl_hair_segment_usable(const sl_hair *h, uint32_t strand, uint32_t seg) {
    if (strand >= h->num_strands) return 0;
    uint32_t first = h->strand_first[strand], n = h->strand_first[strand + 1] - first;
    if (n < 2 || seg >= n - 1) return 0;
    float t[3];
    return seg_dir(h->pos + 3 * ((size_t)first + seg), h->pos + 3 * ((size_t)first + seg + 1), t);
}

void sl_hair_tangent(const sl_hair *h, uint32_t strand, uint32_t seg, float t[3]) {
    t[0] = 0, t[1] = 1, t[2] = 0;
    if (strand >= h->num_strands) return;
    uint32_t first = h->strand_first[strand], n = h->strand_first[strand + 1] - first;
    if (n < 2) return;
    uint32_t nseg = n - 1;
    if (seg >= nseg) seg = nseg - 1;
    const float *p = h->pos + 3 * (size_t)first;
    /* The segment itself, then its neighbours at growing distance (the nearer one first,
     * towards the root on a tie). */
    for (uint32_t k = 0; k < nseg; k++) {
        if (seg >= k && seg - k < nseg && seg_dir(p + 3 * (seg - k), p + 3 * (seg - k + 1), t))
            return;
        if (k && seg + k < nseg && seg_dir(p + 3 * (seg + k), p + 3 * (seg + k + 1), t)) return;
    }
    t[0] = 0, t[1] = 1, t[2] = 0;
}

void sl_hair_point_tangent(const sl_hair *h, uint32_t strand, uint32_t point, float t[3]) {
    t[0] = 0, t[1] = 1, t[2] = 0;
    if (strand >= h->num_strands) return;
    uint32_t n = h->strand_first[strand + 1] - h->strand_first[strand];
    if (n < 2) return;
    if (point >= n) point = n - 1;
    float a[3], b[3];
    sl_hair_tangent(h, strand, point > 0 ? point - 1 : 0, a);
    sl_hair_tangent(h, strand, point < n - 1 ? point : n - 2, b);
    double s[3] = {(double)a[0] + b[0], (double)a[1] + b[1], (double)a[2] + b[2]};
    double len = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    if (len < 1e-3) { /* a hairpin: the two segments cancel; keep the incoming one */
        memcpy(t, a, sizeof a);
        return;
    }
    for (int c = 0; c < 3; c++)
        t[c] = (float)(s[c] / len);
}

int sl_hair_is_hair_path(const char *path) {
    return sl_ext_is(path, "hair") || sl_ext_is(path, "tfx") || sl_ext_is(path, "tfxproj") ||
           sl_ext_is(path, "data");
}

int sl_hair_load_memory(const unsigned char *data, size_t size, const char *name, sl_hair *out,
                        sl_err *e) {
    memset(out, 0, sizeof *out);
    if (size == 0) return sl_fail(e, "%s: empty file", name);
    int rc;
    if ((size >= 4 && memcmp(data, "HAIR", 4) == 0) || sl_ext_is(name, "hair")) {
        rc = sl_hair_parse_cyhair(data, size, name, out, e);
    } else if (sl_ext_is(name, "tfx")) {
        rc = sl_hair_parse_tfx(data, size, name, out, e);
    } else if (sl_ext_is(name, "data")) {
        rc = sl_hair_parse_usc(data, size, name, out, e);
    } else if (sl_ext_is(name, "tfxproj")) {
        return sl_fail(e, "%s: a TressFX project names other files: load it from disk", name);
    } else {
        /* No known extension: a TressFX file starts with its version float (3.x or 4.x). */
        float v = size >= 4 ? sl_rd_f32(data) : 0;
        if (v >= 2.5f && v < 5.0f)
            rc = sl_hair_parse_tfx(data, size, name, out, e);
        else
            return sl_fail(e, "%s: unknown hair format (expected .hair, .tfx, .tfxproj or .data)",
                           name);
    }
    if (rc == 0) rc = sl_hair_validate(out, name, e);
    if (rc != 0) sl_hair_free(out);
    return rc;
}

int sl_hair_load(const char *path, sl_hair *out, sl_err *e) {
    memset(out, 0, sizeof *out);
    if (sl_ext_is(path, "tfxproj")) return sl_hair_load_tfxproj(path, 1, out, e);
    unsigned char *data;
    size_t size;
    if (sl_read_file(path, &data, &size, SL_HAIR_MAX_FILE, e)) return -1;
    int rc = sl_hair_load_memory(data, size, path, out, e);
    free(data);
    if (rc == 0 && out->dropped_strands)
        sl_warn("%s: dropped %u strand%s with a single point", path, out->dropped_strands,
                out->dropped_strands == 1 ? "" : "s");
    return rc;
}

/* Fills a per-point float array of n*k values with the default v (k = 1 or 3). */
static float *filled(size_t n, int k, const float *v) {
    float *a = sl_malloc(n * k * sizeof *a);
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < k; c++)
            a[i * k + c] = v[c];
    return a;
}

/* Grows dst's per-point array *arr (n_dst points) by src's values (or defaults). */
static void append_array(float **arr, const float *dst_def, uint32_t n_dst, const float *src_arr,
                         const float *src_def, uint32_t n_src, int k) {
    if (!*arr && !src_arr && memcmp(dst_def, src_def, k * sizeof *dst_def) == 0) return;
    if (!*arr) *arr = filled(n_dst, k, dst_def);
    *arr = sl_realloc(*arr, ((size_t)n_dst + n_src) * k * sizeof **arr);
    if (src_arr)
        memcpy(*arr + (size_t)n_dst * k, src_arr, (size_t)n_src * k * sizeof **arr);
    else
        for (size_t i = 0; i < n_src; i++)
            for (int c = 0; c < k; c++)
                (*arr)[((size_t)n_dst + i) * k + c] = src_def[c];
}

int sl_hair_append(sl_hair *dst, const sl_hair *src, sl_err *e) {
    uint64_t S = (uint64_t)dst->num_strands + src->num_strands;
    uint64_t P = (uint64_t)dst->num_points + src->num_points;
    if (P > SL_HAIR_MAX_POINTS)
        return sl_fail(e, "hair: %llu points in all (limit %u)", (unsigned long long)P,
                       SL_HAIR_MAX_POINTS);
    uint32_t n0 = dst->num_points;
    append_array(&dst->radius, &dst->default_radius, n0, src->radius, &src->default_radius,
                 src->num_points, 1);
    append_array(&dst->transparency, &dst->default_transparency, n0, src->transparency,
                 &src->default_transparency, src->num_points, 1);
    append_array(&dst->color, dst->default_color, n0, src->color, src->default_color,
                 src->num_points, 3);
    dst->strand_first = sl_realloc(dst->strand_first, (S + 1) * sizeof *dst->strand_first);
    for (uint32_t s = 0; s <= src->num_strands; s++)
        dst->strand_first[dst->num_strands + s] = n0 + src->strand_first[s];
    dst->pos = sl_realloc(dst->pos, P * 3 * sizeof *dst->pos);
    memcpy(dst->pos + 3 * (size_t)n0, src->pos, 3 * (size_t)src->num_points * sizeof *dst->pos);
    dst->guide_strands += src->guide_strands;
    dst->dropped_strands += src->dropped_strands;
    dst->follow_added |= src->follow_added;
    dst->num_strands = (uint32_t)S, dst->num_points = (uint32_t)P;
    if (dst->radius) dst->radius_source = SL_RADIUS_PER_POINT;
    return 0;
}
