/* resolve.c: front-to-back compositing of the K-buffer into beauty + AOVs (resolve.h). */
#include "passes/resolve/resolve.h"

#include "base/common.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void sl_fbuf_free(sl_fbuf *f) {
    free(f->rgba);
    free(f->depth);
    for (int k = 0; k < 4; k++)
        free(f->mode[k]);
    free(f->shadow);
    free(f->lobes);
    memset(f, 0, sizeof *f);
}

static void alloc_fbuf(sl_fbuf *f, int w, int h) {
    memset(f, 0, sizeof *f);
    size_t n = (size_t)w * h;
    f->width = w, f->height = h;
    /* SL_FBUF_FLOATS per pixel (the estimate counts them): 4 + 1 + 4 x 3 + 1 + 1 */
    _Static_assert(SL_FBUF_FLOATS == 4 + 1 + 4 * 3 + 1 + 1, "sl_fbuf layout");
    f->rgba = sl_calloc(4 * n, sizeof(float));
    f->depth = sl_malloc(n * sizeof(float));
    for (int k = 0; k < 4; k++)
        f->mode[k] = sl_calloc(3 * n, sizeof(float));
    f->shadow = sl_calloc(n, sizeof(float));
    f->lobes = sl_calloc(n, sizeof(float));
    for (size_t i = 0; i < n; i++)
        f->depth[i] = INFINITY;
}

void sl_resolve(const sl_kbuf_view *kb, const sl_hair *h, int k, const sl_shade_map *sm,
                const sl_shade_points *pts, sl_fbuf *out) {
    int K = kb->K;
    alloc_fbuf(out, kb->w, kb->h);
    size_t npx = (size_t)kb->w * kb->h;
    for (size_t px = 0; px < npx; px++) {
        int n = kb->kcount[px];
        if (!n) continue;
        float wt[SL_KBUFFER_MAX], v[SL_SHADE_FLOATS];
        float alpha = sl_kbuffer_weights(kb->kbuf + px * K, n, wt);
        double acc[SL_SHADE_BASE_FLOATS] = {0};
        for (int i = 0; i < n; i++) {
            sl_shade_entry(h, kb, k, sm, pts, px, i, v);
            for (int q = 0; q < SL_SHADE_BASE_FLOATS; q++)
                acc[q] += (double)wt[i] * v[q];
        }
        for (int c = 0; c < 3; c++) {
            double sum = 0;
            for (int m = 0; m < 4; m++) {
                out->mode[m][3 * px + c] = (float)acc[3 * m + c];
                sum += acc[3 * m + c];
            }
            out->rgba[4 * px + c] = (float)sum;
        }
        out->rgba[4 * px + 3] = alpha;
        out->depth[px] = kb->kbuf[px * K].z;
        out->shadow[px] = alpha > 0 ? (float)(acc[12] / alpha) : 0.0f;
        out->lobes[px] = alpha > 0 ? (float)(acc[13] / alpha) : 0.0f;
    }
}
