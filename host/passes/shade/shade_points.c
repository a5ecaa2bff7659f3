/* shade_points.c: the frame's shading points and the map back from K-buffer entries
 * (shade_points.h). */
#include "passes/shade/shade_points.h"
#include "base/common.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void anchors_of(const sl_hair *h, const uint32_t *strand_of, uint32_t pt, int k,
                       uint32_t *lo, uint32_t *hi) {
    uint32_t s = strand_of[pt], a = h->strand_first[s], b = h->strand_first[s + 1];
    *lo = a + (pt - a) / (uint32_t)k * (uint32_t)k;
    *hi = *lo + (uint32_t)k < b - 1 ? *lo + (uint32_t)k : b - 1;
    if (*lo == b - 1 && *lo > a) { /* the last point: its own anchor */
        *hi = *lo;
    }
}

/* The point at parameter t of segment seg (points seg, seg + 1). */
static void segment_point(const sl_hair *h, uint32_t seg, double t, double x[3]) {
    for (int q = 0; q < 3; q++)
        x[q] = h->pos[3 * seg + q] + t * (h->pos[3 * seg + 3 + q] - h->pos[3 * seg + q]);
}

void sl_shade_points_build(const sl_hair *h, const sl_kbuf_view *kb, int k, sl_shade_map *m,
                           sl_shade_points *p) {
    size_t npx = (size_t)kb->w * kb->h;
    int K = kb->K;
    size_t cap = 1024, n = 0;
    p->pos = sl_malloc(cap * 3 * sizeof *p->pos);
    p->tan = sl_malloc(cap * 3 * sizeof *p->tan);
    p->strand = sl_malloc(cap * sizeof *p->strand);
#define ADD_POINT(X, T, S)                                                                         \
    do {                                                                                           \
        if (n == cap) {                                                                            \
            cap *= 2;                                                                              \
            p->pos = sl_realloc(p->pos, cap * 3 * sizeof *p->pos);                                 \
            p->tan = sl_realloc(p->tan, cap * 3 * sizeof *p->tan);                                 \
            p->strand = sl_realloc(p->strand, cap * sizeof *p->strand);                            \
        }                                                                                          \
        for (int q = 0; q < 3; q++)                                                                \
            p->pos[3 * n + q] = (X)[q], p->tan[3 * n + q] = (T)[q];                                \
        p->strand[n] = (S);                                                                        \
        n++;                                                                                       \
    } while (0)
    if (k == 0) {
        m->entry = sl_malloc(npx * K * sizeof *m->entry);
        for (size_t px = 0; px < npx; px++)
            for (int i = 0; i < kb->kcount[px]; i++) {
                const sl_kfrag *f = &kb->kbuf[px * K + i];
                uint32_t s = m->strand_of[f->seg];
                double x[3];
                segment_point(h, f->seg, (double)f->t, x);
                float t[3];
                sl_hair_tangent(h, s, f->seg - h->strand_first[s], t);
                m->entry[px * K + i] = (uint32_t)n;
                ADD_POINT(x, t, s);
            }
    } else {
        /* roles of each vertex: 1 = starts a pair the K-buffer uses, 2 = ends one */
        uint8_t *role = sl_calloc(h->num_points ? h->num_points : 1, sizeof *role);
        for (size_t px = 0; px < npx; px++)
            for (int i = 0; i < kb->kcount[px]; i++) {
                uint32_t seg = kb->kbuf[px * K + i].seg, lo, hi;
                anchors_of(h, m->strand_of, seg, k, &lo, &hi);
                role[lo] |= 1;
                role[hi] |= 2;
            }
        m->anchor = sl_malloc((size_t)h->num_points * sizeof *m->anchor);
        if (k == 1) m->anchor_end = sl_malloc((size_t)h->num_points * sizeof *m->anchor_end);
        const float cos_split = cosf(SL_SHADE_SPLIT_DEG * 3.14159265f / 180.0f);
        for (uint32_t i = 0; i < h->num_points; i++) {
            m->anchor[i] = UINT32_MAX;
            if (m->anchor_end) m->anchor_end[i] = UINT32_MAX;
            if (!role[i]) continue;
            uint32_t s = m->strand_of[i], a = h->strand_first[s], b = h->strand_first[s + 1];
            double x[3];
            for (int q = 0; q < 3; q++)
                x[q] = h->pos[3 * i + q];
            float t[3];
            if (m->anchor_end && i > a && i + 1 < b) {
                /* a bent vertex between two visible segments: each segment's end is shaded with
                 * its own tangent, as the fibers are cylinders along the segments */
                float tin[3], tout[3];
                sl_hair_tangent(h, s, i - 1 - a, tin);
                sl_hair_tangent(h, s, i - a, tout);
                if (tin[0] * tout[0] + tin[1] * tout[1] + tin[2] * tout[2] < cos_split) {
                    if (role[i] & 2) {
                        m->anchor_end[i] = (uint32_t)n;
                        ADD_POINT(x, tin, s);
                    }
                    if (role[i] & 1) {
                        m->anchor[i] = (uint32_t)n;
                        ADD_POINT(x, tout, s);
                    }
                    continue;
                }
            }
            sl_hair_point_tangent(h, s, i - a, t);
            m->anchor[i] = (uint32_t)n;
            if (m->anchor_end) m->anchor_end[i] = (uint32_t)n;
            ADD_POINT(x, t, s);
        }
        free(role);
    }
#undef ADD_POINT
    p->n = n;
}

/* The shading point that ends a pair at vertex hi. */
static uint32_t pair_end(const sl_shade_map *m, uint32_t hi) {
    return m->anchor_end ? m->anchor_end[hi] : m->anchor[hi];
}

/* Parts the pair (lo, hi) is cut into: D (the T- and share-weighted mean log ratio of the
 * lobes' transmittance at its two ends) over ln(ratio), rounded up. */
static int refine_parts(const float *T, size_t n, int nlobes, const double *share, uint32_t ilo,
                        uint32_t ihi, double ln_ratio, double gate) {
    double num = 0, den = 0;
    for (int j = 0; j < nlobes; j++) {
        const float a = T[(size_t)j * n + ilo], b = T[(size_t)j * n + ihi];
        const double ta = a > SL_SHADE_REFINE_TFLOOR ? a : SL_SHADE_REFINE_TFLOOR;
        const double tb = b > SL_SHADE_REFINE_TFLOOR ? b : SL_SHADE_REFINE_TFLOOR;
        const double wgt = share[j] * (ta > tb ? ta : tb);
        num += wgt * fabs(log(ta / tb));
        den += wgt;
    }
    /* a pair in deep shadow at both ends (den under gate = SL_SHADE_REFINE_GATE x the shares'
     * sum): its interpolation error is below the gate's share of a lit fiber's radiance, not
     * worth shading points */
    if (!(den > 0) || den < gate) return 1;
    const double parts = ceil(num / den / ln_ratio - 1e-9);
    return parts < 1 ? 1 : (parts > SL_SHADE_REFINE_MAX ? SL_SHADE_REFINE_MAX : (int)parts);
}

static void clear_refinement(sl_shade_map *m) {
    free(m->sub_m);
    free(m->sub_first);
    m->sub_m = NULL;
    m->sub_first = NULL;
}

size_t sl_shade_points_refine(const sl_hair *h, const sl_kbuf_view *kb, int k, sl_shade_map *m,
                              sl_shade_points *p, const float *T, int nlobes, const double *share,
                              double ratio) {
    clear_refinement(m);
    if (k < 1 || !(ratio > 1)) return 0;
    const size_t npx = (size_t)kb->w * kb->h, n0 = p->n;
    const double ln_ratio = log(ratio);
    double gate = 0;
    for (int j = 0; j < nlobes; j++)
        gate += share[j];
    gate *= SL_SHADE_REFINE_GATE;
    m->sub_m = sl_calloc(h->num_points ? h->num_points : 1, sizeof *m->sub_m);
    m->sub_first = sl_malloc((h->num_points ? h->num_points : 1) * sizeof *m->sub_first);
    size_t added = 0;
    /* pass 1: the parts of each pair the K-buffer uses (sub_m 0: not visited) */
    for (size_t px = 0; px < npx; px++)
        for (int i = 0; i < kb->kcount[px]; i++) {
            uint32_t lo, hi;
            anchors_of(h, m->strand_of, kb->kbuf[px * kb->K + i].seg, k, &lo, &hi);
            if (m->sub_m[lo]) continue;
            int parts = hi > lo ? refine_parts(T, n0, nlobes, share, m->anchor[lo], pair_end(m, hi),
                                               ln_ratio, gate)
                                : 1;
            m->sub_m[lo] = (uint8_t)parts;
            m->sub_first[lo] = (uint32_t)(n0 + added);
            added += (size_t)parts - 1;
        }
    if (!added) {
        clear_refinement(m);
        return 0;
    }
    p->pos = sl_realloc(p->pos, (n0 + added) * 3 * sizeof *p->pos);
    p->tan = sl_realloc(p->tan, (n0 + added) * 3 * sizeof *p->tan);
    p->strand = sl_realloc(p->strand, (n0 + added) * sizeof *p->strand);
    /* pass 2: the inner points, evenly in the strand's point parameter between the anchors
     * (the parameter sl_shade_entry interpolates in), on the polyline, with their segment's
     * tangent */
    for (uint32_t lo = 0; lo < h->num_points; lo++) {
        const int parts = m->sub_m[lo];
        if (parts < 2) continue;
        const uint32_t s = m->strand_of[lo];
        uint32_t lo2, hi;
        anchors_of(h, m->strand_of, lo, k, &lo2, &hi); /* lo starts its pair: lo2 == lo */
        for (int q = 1; q < parts; q++) {
            const double u = (double)(hi - lo) * q / parts;
            uint32_t seg = lo + (uint32_t)u;
            if (seg >= hi) seg = hi - 1;
            const size_t o = m->sub_first[lo] + (size_t)q - 1;
            segment_point(h, seg, u - (double)(seg - lo), p->pos + 3 * o);
            sl_hair_tangent(h, s, seg - h->strand_first[s], p->tan + 3 * o);
            p->strand[o] = s;
        }
    }
    p->n = n0 + added;
    return added;
}

void sl_shade_entry(const sl_hair *h, const sl_kbuf_view *kb, int k, const sl_shade_map *m,
                    const sl_shade_points *p, size_t px, int i, float *v) {
    const sl_kfrag *f = &kb->kbuf[px * kb->K + i];
    if (k == 0) {
        const size_t st = sl_shade_stride(p);
        memcpy(v, p->out + st * m->entry[px * kb->K + i], st * sizeof *v);
        return;
    }
    uint32_t lo, hi;
    anchors_of(h, m->strand_of, f->seg, k, &lo, &hi);
    float w = hi > lo ? ((float)(f->seg - lo) + f->t) / (float)(hi - lo) : 0.0f;
    w = w < 0 ? 0 : (w > 1 ? 1 : w);
    uint32_t ia = m->anchor[lo], ib = pair_end(m, hi);
    const int parts = m->sub_m ? m->sub_m[lo] : 1;
    if (parts > 1) { /* refined: the part w falls in, between its two ends */
        const float u = w * (float)parts;
        int q = (int)u;
        if (q > parts - 1) q = parts - 1;
        w = u - (float)q;
        if (q > 0) ia = m->sub_first[lo] + (uint32_t)q - 1;
        if (q < parts - 1) ib = m->sub_first[lo] + (uint32_t)q;
    }
    const size_t st = sl_shade_stride(p);
    const float *a = p->out + st * ia;
    const float *b = p->out + st * ib;
    for (size_t q = 0; q < st; q++)
        v[q] = a[q] + w * (b[q] - a[q]);
    const size_t e = p->nsharp ? p->entry_first[px] + (size_t)i : 0;
    for (int l = 0; l < p->nsharp; l++) {
        const float T = p->entry_T[(size_t)l * p->nentries + e];
        const float *s = v + SL_SHADE_BASE_FLOATS + 9 * l;
        for (int q = 0; q < 9; q++)
            v[q] += T * s[q];
        v[12] += p->sharp_share[l] * T;
    }
}

uint32_t *sl_shade_entry_first(const sl_kbuf_view *kb) {
    const size_t npx = (size_t)kb->w * kb->h;
    uint32_t *f = sl_malloc((npx + 1) * sizeof *f);
    size_t c = 0;
    for (size_t px = 0; px < npx; px++)
        f[px] = (uint32_t)c, c += kb->kcount[px];
    f[npx] = (uint32_t)c;
    return f;
}

void sl_shade_entry_positions(const sl_hair *h, const sl_kbuf_view *kb, size_t px0, size_t px1,
                              double *pos) {
    for (size_t px = px0; px < px1; px++)
        for (int i = 0; i < kb->kcount[px]; i++, pos += 3) {
            const sl_kfrag *k = &kb->kbuf[px * kb->K + i];
            segment_point(h, k->seg, (double)k->t, pos);
        }
}

void sl_shade_points_free(sl_shade_points *p) {
    free(p->pos);
    free(p->tan);
    free(p->strand);
    free(p->T);
    free(p->B);
    free(p->out);
    free(p->entry_first);
    free(p->entry_T);
    memset(p, 0, sizeof *p);
}

void sl_shade_map_free(sl_shade_map *m) {
    free(m->strand_of);
    free(m->anchor);
    free(m->entry);
    free(m->sub_first);
    free(m->sub_m);
    free(m->anchor_end);
    memset(m, 0, sizeof *m);
}
