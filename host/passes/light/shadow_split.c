/* shadow_split.c: shadow directions of a broad SRBF lobe (shadow_split.h). */
#include "passes/light/shadow_split.h"

#include "passes/light/shadow.h"
#include "lighting/sphere_points.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int sl_shadow_split(const double dir[3], double lambda, double *dirs, double *w) {
    if (sl_shadow_lobe_support(lambda) <= SL_SHADOW_SUPPORT_MAX_DEG * M_PI / 180.0) {
        for (int k = 0; k < 3; k++)
            dirs[k] = dir[k];
        w[0] = 1.0;
        return 1;
    }
    double u[3], v[3];
    sl_axis_frame(dir, u, v);
    int n = 0;
    double sum = 0;
    for (int i = 0; i < SL_SHADOW_SPLIT_N; i++) {
        double z = 1.0 - 2.0 * i / (SL_SHADOW_SPLIT_N - 1.0); /* both poles on the axis */
        /* G relative to the axis: exp(2 (z - 1) / lambda^2) */
        double g = exp(2.0 * (z - 1.0) / (lambda * lambda));
        if (g < SL_SHADOW_SPLIT_CUT) continue;
        /* equal-area bands in z (Archimedes); the two poles hold half a band each */
        double area = (i == 0 || i == SL_SHADOW_SPLIT_N - 1) ? 0.5 : 1.0;
        sl_fib_axis_point(i, SL_SHADOW_SPLIT_N, dir, u, v, dirs + 3 * n);
        w[n] = g * area;
        sum += w[n];
        n++;
    }
    for (int s = 0; s < n; s++)
        w[s] /= sum;
    return n;
}

int sl_shadow_split_max(const double dir[3], double lambda, int max, double *dirs, double *w) {
    int n = sl_shadow_split(dir, lambda, dirs, w);
    if (max < 1) max = 1;
    if (n <= max) return n;
    /* the points come in order of decreasing z, i.e. decreasing weight: keep the first max */
    double sum = 0;
    for (int s = 0; s < max; s++)
        sum += w[s];
    for (int s = 0; s < max; s++)
        w[s] /= sum;
    return max;
}

void sl_shadow_maps_plan(const sl_lobes *l, const int *idx, int count, const int *want,
                         sl_shadow_maps *m) {
    size_t cap = (size_t)(count ? count : 1) * SL_SHADOW_SPLIT_N;
    m->dir = sl_malloc(3 * cap * sizeof *m->dir);
    m->lambda = sl_malloc(cap * sizeof *m->lambda);
    m->w = sl_malloc(cap * sizeof *m->w);
    m->lobe = sl_malloc(cap * sizeof *m->lobe);
    m->first = sl_malloc(((size_t)count + 1) * sizeof *m->first);
    int n = 0;
    for (int j = 0; j < count; j++) {
        const sl_lobe *lb = &l->lobe[idx[j]];
        m->first[j] = n;
        int c = want ? sl_shadow_split_max(lb->dir, lb->lambda, want[j], m->dir + 3 * n, m->w + n)
                     : sl_shadow_split(lb->dir, lb->lambda, m->dir + 3 * n, m->w + n);
        for (int q = 0; q < c; q++) {
            m->lambda[n + q] = lb->lambda;
            m->lobe[n + q] = j;
        }
        n += c;
    }
    m->first[count] = n;
    m->n = n;
}

void sl_shadow_maps_free(sl_shadow_maps *m) {
    free(m->dir);
    free(m->lambda);
    free(m->w);
    free(m->lobe);
    free(m->first);
    memset(m, 0, sizeof *m);
}
