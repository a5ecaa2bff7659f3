/* shade_points.c: the frame's shading points and the map back from K-buffer entries
 * (shade_points.h). */
#include "passes/shade/shade_points.h"
#include "base/common.h"

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
                for (int q = 0; q < 3; q++)
                    x[q] = h->pos[3 * f->seg + q] +
                           (double)f->t * (h->pos[3 * f->seg + 3 + q] - h->pos[3 * f->seg + q]);
                float t[3];
                sl_hair_tangent(h, s, f->seg - h->strand_first[s], t);
                m->entry[px * K + i] = (uint32_t)n;
                ADD_POINT(x, t, s);
            }
    } else {
        m->anchor = sl_malloc((size_t)h->num_points * sizeof *m->anchor);
        for (uint32_t i = 0; i < h->num_points; i++)
            m->anchor[i] = 0;
        for (size_t px = 0; px < npx; px++)
            for (int i = 0; i < kb->kcount[px]; i++) {
                uint32_t seg = kb->kbuf[px * K + i].seg, lo, hi;
                anchors_of(h, m->strand_of, seg, k, &lo, &hi);
                m->anchor[lo] = m->anchor[hi] = 1;
            }
        for (uint32_t i = 0; i < h->num_points; i++) {
            if (!m->anchor[i]) {
                m->anchor[i] = UINT32_MAX;
                continue;
            }
            uint32_t s = m->strand_of[i];
            double x[3];
            for (int q = 0; q < 3; q++)
                x[q] = h->pos[3 * i + q];
            float t[3];
            sl_hair_point_tangent(h, s, i - h->strand_first[s], t);
            m->anchor[i] = (uint32_t)n;
            ADD_POINT(x, t, s);
        }
    }
#undef ADD_POINT
    p->n = n;
}

void sl_shade_entry(const sl_hair *h, const sl_kbuf_view *kb, int k, const sl_shade_map *m,
                    const sl_shade_points *p, size_t px, int i, float *v) {
    const sl_kfrag *f = &kb->kbuf[px * kb->K + i];
    if (k == 0) {
        memcpy(v, p->out + (size_t)SL_SHADE_FLOATS * m->entry[px * kb->K + i],
               SL_SHADE_FLOATS * sizeof *v);
        return;
    }
    uint32_t lo, hi;
    anchors_of(h, m->strand_of, f->seg, k, &lo, &hi);
    float w = hi > lo ? ((float)(f->seg - lo) + f->t) / (float)(hi - lo) : 0.0f;
    w = w < 0 ? 0 : (w > 1 ? 1 : w);
    const float *a = p->out + (size_t)SL_SHADE_FLOATS * m->anchor[lo];
    const float *b = p->out + (size_t)SL_SHADE_FLOATS * m->anchor[hi];
    for (int q = 0; q < SL_SHADE_FLOATS; q++)
        v[q] = a[q] + w * (b[q] - a[q]);
}

void sl_shade_points_free(sl_shade_points *p) {
    free(p->pos);
    free(p->tan);
    free(p->strand);
    free(p->T);
    free(p->B);
    free(p->out);
    memset(p, 0, sizeof *p);
}

void sl_shade_map_free(sl_shade_map *m) {
    free(m->strand_of);
    free(m->anchor);
    free(m->entry);
    memset(m, 0, sizeof *m);
}
