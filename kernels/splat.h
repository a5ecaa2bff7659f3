/* splat.h: the one ribbon splat loop, shared by kernels/raster.cl and its C twins (cpu/raster.c:
 * the deep opacity maps' two passes; cpu/view.c: the view pass's fragments).
 *
 * A segment record (kernels/raster.h) is a regular grid of na x nw samples tiling the ribbon;
 * each sample is tent-splatted onto its 4 nearest texels (the view pass: spread over its piece's
 * bounding box instead, sl_splat_begin_box, which also touches at most 2 x 2 pixels). Every user
 * of a record walks exactly this: every sample (along i, then across j), every tent corner (in
 * the order (ix, iy), (ix + 1, iy), (ix, iy + 1), (ix + 1, iy + 1)), the corners outside the
 * w x h map skipped, and each remaining corner's share (mass x tent weights) and the sample's
 * depth. Only what a texel does with its share differs (first depth, a deep-opacity layer, a
 * view fragment), so that stays with the caller: OpenCL C has no function pointers, so the loop
 * is an iterator instead of a callback:
 *
 *     sl_splat it;
 *     sl_splat_begin(&it, rec, w, h, 1);
 *     while (sl_splat_next(&it, &tx, &ty, &share, &z)) { ... texel (tx, ty) ... }
 *
 * The arithmetic is that of the loops it replaced, operation by operation (sl_raster_sample,
 * sl_raster_tent, then per corner sl_raster_share of the weights fx or 1 - fx, fy or 1 - fy), so
 * maps and fragments are bit-identical to before and the kernel stays bit-identical to its twins
 * (raster.cl turns FP contraction off; the C build uses -std=c11, whose default is no contraction
 * either). A sample's four shares and the mask of its corners inside the map are found when the
 * sample is loaded, so the step to the next corner is a bit scan, with no weight select or bounds
 * test per corner. Cost against the loops it replaced (C, -O2, a synthetic 40000-segment batch):
 * the first-depth pass, whose per-texel work is one compare, ~35 % slower than the C twin's
 * former hand-unrolled four corners; the layers pass and the view pass within ~3 %. */
#ifndef SL_SPLAT_H
#define SL_SPLAT_H

#include "raster.h"

/* The walk's state. Callers read only i (the current sample's index along the ribbon: the view
 * pass turns it into the parameter t along the segment); the rest is private. */
typedef struct sl_splat {
    const SL_GLOBAL float *rec;
    float m;        /* mass per sample (rec[8]) */
    sl_uint na, nw; /* samples along, across */
    sl_uint i, j;   /* current sample */
    int clip;       /* whether corners may fall outside the map (0: the caller proved not) */
    sl_int w, h;
    sl_int ix, iy; /* the current sample's lower-left tent texel */
    float z;       /* its depth */
    float sh[4];   /* its share at corner c = (ix + (c & 1), iy + (c >> 1)) */
    sl_uint left;  /* its corners not yet returned that lie in the map: bit c for corner c */
    int taken;     /* sl_splat_next_sample: the current sample was handed out */
    float hx, hy;  /* box footprint's half-extents (sl_splat_begin_box), hx < 0: the tent */
} sl_splat;

/* Index of the lowest set bit of l != 0 (OpenCL C 1.2 has popcount but no ctz; the C build is
 * gcc or clang). */
SL_INLINE int sl_splat_low_bit(sl_uint l) {
#if SL_OPENCL
    return (int)popcount((l & (0u - l)) - 1u);
#else
    return __builtin_ctz(l);
#endif
}

/* Sample (i, j): position, depth, tent, the four shares and which corners are in the map. */
SL_INLINE void sl_splat_load(sl_splat *it) {
    float x, y, fx, fy;
    sl_raster_sample(it->rec, it->i, it->j, &x, &y, &it->z);
    if (it->hx < 0.0f)
        sl_raster_tent(x, y, &it->ix, &it->iy, &fx, &fy);
    else
        sl_raster_box(x, y, it->hx, it->hy, &it->ix, &it->iy, &fx, &fy);
    const float gx = 1.0f - fx, gy = 1.0f - fy;
    it->sh[0] = sl_raster_share(it->m, gx, gy);
    it->sh[1] = sl_raster_share(it->m, fx, gy);
    it->sh[2] = sl_raster_share(it->m, gx, fy);
    it->sh[3] = sl_raster_share(it->m, fx, fy);
    if (!it->clip) {
        it->left = 15u;
        return;
    }
    /* corners in columns ix, ix + 1 and rows iy, iy + 1 */
    const sl_uint cx = (it->ix >= 0 && it->ix < it->w ? 1u : 0u) |
                       (it->ix + 1 >= 0 && it->ix + 1 < it->w ? 2u : 0u);
    const sl_uint cy = (it->iy >= 0 && it->iy < it->h ? 1u : 0u) |
                       (it->iy + 1 >= 0 && it->iy + 1 < it->h ? 2u : 0u);
    it->left = ((cy & 1u) ? cx : 0u) | ((cy & 2u) ? cx << 2 : 0u);
}

/* Starts the walk of record rec over a w x h map. clip = 0 skips the bounds checks, for a
 * caller that has shown every corner of every sample lies inside the map (cpu/raster.c:
 * rec_inside); which texels get what is the same either way. A record without samples (na or
 * nw = 0: no area) yields nothing. hx, hy: each sample's box footprint (sl_raster_box), or
 * hx < 0 for the tent (sl_raster_tent). */
SL_INLINE void sl_splat_begin_footprint(sl_splat *it, const SL_GLOBAL float *rec, sl_int w,
                                        sl_int h, int clip, float hx, float hy) {
    it->rec = rec;
    it->m = rec[8];
    it->na = (sl_uint)rec[9];
    it->nw = (sl_uint)rec[10];
    it->i = 0u;
    it->j = 0u;
    it->clip = clip;
    it->w = w;
    it->h = h;
    it->left = 0u;
    it->taken = 0;
    it->hx = hx;
    it->hy = hy;
    if (it->na == 0u || it->nw == 0u) {
        /* the first sl_splat_next steps past the last row at once */
        it->na = 0u;
        it->nw = 1u;
        return;
    }
    sl_splat_load(it);
}

/* The walk with the tent (the deep opacity maps: bit for bit the kernels'). */
SL_INLINE void sl_splat_begin(sl_splat *it, const SL_GLOBAL float *rec, sl_int w, sl_int h,
                              int clip) {
    sl_splat_begin_footprint(it, rec, w, h, clip, -1.0f, -1.0f);
}

/* The same walk with each sample's mass spread over the bounding box of the piece of ribbon it
 * stands for (half-extents (|a| + |w|) / 2 per axis from the record's steps along, a, and
 * across, w; at most 1/2 pixel) instead of the tent: sl_raster_box, the view pass's pixel
 * filter (docs/coverage.md, "Pixel filter"). */
SL_INLINE void sl_splat_begin_box(sl_splat *it, const SL_GLOBAL float *rec, sl_int w, sl_int h,
                                  int clip) {
    sl_splat_begin_footprint(it, rec, w, h, clip,
                             sl_minf(0.5f * (fabs(rec[3]) + fabs(rec[6])), 0.5f),
                             sl_minf(0.5f * (fabs(rec[4]) + fabs(rec[7])), 0.5f));
}

/* Moves to the next sample and loads it; 0 past the last one (then it stays done: a later call
 * steps past the last row again). */
SL_INLINE int sl_splat_step(sl_splat *it) {
    if (++it->j == it->nw) {
        it->j = 0u;
        if (++it->i >= it->na) {
            it->i = it->na;
            it->j = it->nw - 1u;
            it->left = 0u;
            return 0;
        }
    }
    sl_splat_load(it);
    return 1;
}

/* The next tent corner inside the map: texel (tx, ty), its share of the sample's mass and the
 * sample's depth z. Returns 0 when the record is done (and on every later call). */
SL_INLINE int sl_splat_next(sl_splat *it, sl_int *tx, sl_int *ty, float *share, float *z) {
    while (it->left == 0u)
        if (!sl_splat_step(it)) return 0;
    const sl_uint l = it->left;
    const int c = sl_splat_low_bit(l); /* the lowest corner left */
    it->left = l & (l - 1u);
    *tx = it->ix + (c & 1);
    *ty = it->iy + (c >> 1);
    *share = it->sh[c];
    *z = it->z;
    return 1;
}

/* The walk a sample at a time, for a caller whose work per texel is a compare (the first-depth
 * pass), where stepping corner by corner costs more than the work: the next sample (the first on
 * the first call), whose corners in the map are the bits c of it->left, texel
 * (it->ix + (c & 1), it->iy + (c >> 1)), share it->sh[c], depth it->z; visiting c = 0..3 in turn
 * gives the texels in sl_splat_next's order. Returns 0 past the last sample. A walk uses either
 * this or sl_splat_next, not both. */
SL_INLINE int sl_splat_next_sample(sl_splat *it) {
    if (it->taken && !sl_splat_step(it)) return 0;
    it->taken = 1;
    return it->i < it->na;
}

#endif
