/* raster.h: the segment rasterizer shared by kernels/raster.cl and its C twin cpu/raster.c.
 *
 * A hair segment is drawn as a camera-facing ribbon of the fiber's width (2 r) in a 2-D raster
 * whose projection (orthographic light view, or later the perspective view pass) the host has
 * already applied: the host turns every segment into a record of SL_RASTER_REC floats (texel
 * coordinates x, y with texel centres at i + 0.5, and a depth z) describing a regular grid of
 * na x nw sample points that tile the ribbon (spacing <= 1/2 texel along and across), each
 * carrying the same share `mass` of the ribbon's area. Every sample is splatted with a tent
 * (bilinear) filter onto its 4 nearest texels, so the area a strand adds is conserved exactly
 * whatever its width: sub-pixel strands do not vanish, they add their true coverage.
 *
 * Mass is in FIXED POINT (the host multiplies by a power-of-two scale and the per-texel share is
 * rounded to a 64-bit integer) so accumulation by atomics is exact and order-independent: the
 * kernel and the C twin give bit-identical maps. Only +, -, *, floor and round-to-nearest
 * conversions appear here (no sqrt/division, whose OpenCL precision is looser than C's), and
 * raster.cl turns FP contraction off, so every float operation is the same in both languages. */
#ifndef SL_RASTER_H
#define SL_RASTER_H

#include "sl_compat.h"

/* Record layout (floats): first sample x, y, z; step along x, y, z; step across x, y; mass per
 * sample (fixed-point units, before the tent weights); na; nw (small integers stored exactly);
 * one pad float. */
#define SL_RASTER_REC 12
#define SL_RASTER_MAX_SAMPLES 16777216.0f /* na, nw are stored as floats: exact below 2^24 */

/* Depth of a float z as an order-preserving uint (z >= 0 is guaranteed by the host): the
 * first-depth map is the atomic minimum of these. +inf (no hair) is 0x7f800000. */
#define SL_RASTER_Z_EMPTY 0x7f800000u

/* Sample (i, j) of a record: position in texels and depth. */
SL_INLINE void sl_raster_sample(const SL_GLOBAL float *rec, sl_uint i, sl_uint j, float *x,
                                float *y, float *z) {
    const float fi = (float)i, fj = (float)j;
    *x = (rec[0] + fi * rec[3]) + fj * rec[6];
    *y = (rec[1] + fi * rec[4]) + fj * rec[7];
    *z = rec[2] + fi * rec[5];
}

/* The layer (0-based) that depth offset dz = z - z0 >= 0 falls in: layer k covers
 * (b_k, b_{k+1}] with b_k = k (k + 1) d / 2 (Ren 2010 Sec. 5); offsets beyond b_K go to the last
 * layer. */
SL_INLINE sl_uint sl_raster_layer(float dz, float d, sl_uint K) {
    sl_uint k = 0u;
    while (k + 1u < K && dz > (float)((k + 1u) * (k + 2u) / 2u) * d)
        k++;
    return k;
}

/* The tent weights of sample (x, y): texel (ix, iy) gets (1-fx)(1-fy), (ix+1, iy) fx(1-fy), ... */
SL_INLINE void sl_raster_tent(float x, float y, sl_int *ix, sl_int *iy, float *fx, float *fy) {
    const float gx = x - 0.5f, gy = y - 0.5f;
    const float flx = floor(gx), fly = floor(gy);
    *ix = (sl_int)flx;
    *iy = (sl_int)fly;
    *fx = gx - flx;
    *fy = gy - fly;
}

/* Fixed-point share of one tent corner (weights wx, wy of a sample of mass m). */
SL_INLINE float sl_raster_share(float m, float wx, float wy) {
    return (m * wx) * wy;
}

#endif
