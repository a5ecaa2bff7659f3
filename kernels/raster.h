/* raster.h: the segment rasterizer shared by kernels/raster.cl and its C twin cpu/raster.c.
 *
 * A hair segment is drawn as a camera-facing ribbon of the fiber's width (2 r) in a 2-D raster
 * whose projection (orthographic light view: sl_raster_project_seg on the device or in C, or
 * later the perspective view pass) is already applied: every segment becomes a record of
 * SL_RASTER_REC floats (texel
 * coordinates x, y with texel centres at i + 0.5, and a depth z) describing a regular grid of
 * na x nw sample points that tile the ribbon (spacing <= 1/2 texel along and across), each
 * carrying the same share `mass` of the ribbon's area. Every sample is splatted with a tent
 * (bilinear) filter onto its 4 nearest texels, so the area a strand adds is conserved exactly
 * whatever its width: sub-pixel strands do not vanish, they add their true coverage.
 *
 * Mass is in FIXED POINT (the host multiplies by a power-of-two scale and the per-texel share is
 * rounded to a 64-bit integer) so accumulation by atomics is exact and order-independent: the
 * kernel and the C twin give bit-identical maps. The sampling uses only +, -, *, floor and
 * round-to-nearest conversions; the record builder also divides and takes a square root, which
 * raster.cl asks to be correctly rounded (-cl-fp32-correctly-rounded-divide-sqrt, as in C); and
 * raster.cl turns FP contraction off, so every float operation is the same in both languages. */
#ifndef SL_RASTER_H
#define SL_RASTER_H

#include "sl_compat.h"

#if !SL_OPENCL
#include <string.h>
#endif

/* A first depth's float from its order-preserving bits (z >= 0: the float's own bits), and
 * back; OpenCL's as_float / as_uint. */
#if SL_OPENCL
#define sl_raster_z_of(b) as_float(b)
#define sl_raster_bits_of(z) as_uint(z)
#else
SL_INLINE float sl_raster_z_of(sl_uint b) {
    float z;
    memcpy(&z, &b, sizeof z);
    return z;
}
SL_INLINE sl_uint sl_raster_bits_of(float z) {
    sl_uint b;
    memcpy(&b, &z, sizeof b);
    return b;
}
#endif

/* Record layout (floats): first sample x, y, z; step along x, y, z; step across x, y; mass per
 * sample (fixed-point units, before the tent weights); na; nw (small integers stored exactly);
 * one pad float. */
#define SL_RASTER_REC 12
#define SL_RASTER_MAX_SAMPLES 16777216.0f /* na, nw are stored as floats: exact below 2^24 */

/* Depth of a float z as an order-preserving uint (z >= 0 is guaranteed by the host): the
 * first-depth map is the atomic minimum of these. +inf (no hair) is 0x7f800000. */
#define SL_RASTER_Z_EMPTY 0x7f800000u

/* Light views for the device-side projection (sl_raster_project_seg): SL_RASTER_VIEW floats per
 * lobe: origin (3), ex / texel (3), ey / texel (3), ez (3): u = (p - o).ex', v = (p - o).ey',
 * z = (p - o).ez (host/passes/light/shadow.h: sl_light_view). */
#define SL_RASTER_VIEW 12
/* Samples at most 1/2 texel apart along and across a ribbon (the tent filter then reconstructs
 * a uniform line density with a ripple below 1 % of the texel value); caps bound one record's
 * work (a ribbon longer or wider than the map: mass is still conserved, sampling coarser). */
#define SL_RASTER_MAX_ALONG 65536.0f
#define SL_RASTER_MAX_ACROSS 4096.0f

/* World point p (3 floats) in light view `view`: u, v in texels and depth z. */
SL_INLINE void sl_raster_project(const SL_GLOBAL float *view, const SL_GLOBAL float *p, float *u,
                                 float *v, float *z) {
    const float qx = p[0] - view[0], qy = p[1] - view[1], qz = p[2] - view[2];
    *u = (qx * view[3] + qy * view[4]) + qz * view[5];
    *v = (qx * view[6] + qy * view[7]) + qz * view[8];
    *z = (qx * view[9] + qy * view[10]) + qz * view[11];
}

/* The record (layout below) of the ribbon from (x0, y0, z0) to (x1, y1, z1) (texels, depth) of
 * half-width hw texels: area 2 hw |p1 - p0|_xy (numerics.md sec. 7: 2 r l) times mscale
 * (fixed-point units per texel^2), spread over na x nw samples. No area (seen end-on, hw = 0):
 * all zero (no samples). Float operations only, sqrt and division included: raster.cl is built
 * with -cl-fp32-correctly-rounded-divide-sqrt so both languages round every step identically. */
SL_INLINE void sl_raster_record_f(float x0, float y0, float z0, float x1, float y1, float z1,
                                  float hw, float mscale, SL_GLOBAL float *rec) {
    for (int i = 0; i < 12; i++)
        rec[i] = 0.0f;
    const float dx = x1 - x0, dy = y1 - y0, dz = z1 - z0;
    const float len = sqrt(dx * dx + dy * dy);
    const float wid = 2.0f * hw, area = wid * len;
    if (!(area > 0.0f) || !(area < SL_FLT_MAX)) return;
    const float na = sl_minf(sl_maxf(1.0f, ceil(len * 2.0f)), SL_RASTER_MAX_ALONG);
    const float nw = sl_minf(sl_maxf(1.0f, ceil(wid * 2.0f)), SL_RASTER_MAX_ACROSS);
    const float ax = dx / na, ay = dy / na, az = dz / na;
    const float step = wid / nw;
    const float wx = (-dy / len) * step, wy = (dx / len) * step; /* across: the unit normal */
    const float off = -(nw - 1.0f) * 0.5f;
    rec[0] = (x0 + 0.5f * ax) + off * wx;
    rec[1] = (y0 + 0.5f * ay) + off * wy;
    rec[2] = z0 + 0.5f * az;
    rec[3] = ax;
    rec[4] = ay;
    rec[5] = az;
    rec[6] = wx;
    rec[7] = wy;
    rec[8] = (area * mscale) / (na * nw);
    rec[9] = na;
    rec[10] = nw;
}

/* Record of segment s of lobe l: points pos[3 i], pos[3 (i + 1)] with i = seg[s], half-width
 * hw[s] texels, written to recs + (l nseg + s) SL_RASTER_REC. */
SL_INLINE void sl_raster_project_seg(const SL_GLOBAL float *pos, const SL_GLOBAL sl_uint *seg,
                                     const SL_GLOBAL float *hw, const SL_GLOBAL float *views,
                                     sl_uint nseg, sl_uint l, sl_uint s, float mscale,
                                     SL_GLOBAL float *recs) {
    const SL_GLOBAL float *view = views + (sl_ulong)l * SL_RASTER_VIEW;
    const SL_GLOBAL float *p = pos + (sl_ulong)seg[s] * 3u;
    float x0, y0, z0, x1, y1, z1;
    sl_raster_project(view, p, &x0, &y0, &z0);
    sl_raster_project(view, p + 3, &x1, &y1, &z1);
    sl_raster_record_f(x0, y0, z0, x1, y1, z1, hw[s], mscale,
                       recs + ((sl_ulong)l * nseg + s) * SL_RASTER_REC);
}

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

/* The box footprint instead of the tent (the view pass, docs/coverage.md "Pixel filter"): the
 * sample stands for a piece of ribbon whose bounding box has half-extents hx, hy (<= 1/2 pixel),
 * its mass spread uniformly over that box, and a pixel is the cell [i, i + 1) x [j, j + 1), so
 * what a pixel gets is the box's overlap with it: the pixel filter of a path tracer's jittered
 * subpixel rays (a box of one pixel), not a tent of two. The lower-left cell of the <= 2 x 2 the
 * box overlaps, and the fraction of the mass in the column (row) after it. hx = 0 is a point:
 * all of it in the cell that holds x. */
SL_INLINE void sl_raster_box(float x, float y, float hx, float hy, sl_int *ix, sl_int *iy,
                             float *fx, float *fy) {
    const float flx = floor(x - hx), fly = floor(y - hy);
    *ix = (sl_int)flx;
    *iy = (sl_int)fly;
    const float ox = x + hx - (flx + 1.0f), oy = y + hy - (fly + 1.0f); /* reach past the cell */
    *fx = hx > 0.0f ? sl_clampf(ox / (2.0f * hx), 0.0f, 1.0f) : 0.0f;
    *fy = hy > 0.0f ? sl_clampf(oy / (2.0f * hy), 0.0f, 1.0f) : 0.0f;
}

/* Fixed-point share of one tent corner (weights wx, wy of a sample of mass m). */
SL_INLINE float sl_raster_share(float m, float wx, float wy) {
    return (m * wx) * wy;
}

/* Minimum of the first-depth bits over the texels (x - m .. x + m, y) (dx = 1) or (x, y - m ..
 * y + m) (dx = 0), clipped to the map. Two passes (rows, then columns) give the minimum over the
 * (2m + 1)^2 window. Why: a texel's own first fiber lies below the hair's surface by about the
 * depth at which the first fiber crosses its footprint; in sparse hair that depth carries an
 * optical depth of ~2r / (W + 2r) (W = footprint width, 2r = fiber width), all of it missing
 * from every lookup below (docs/shadow.md). The window widens W so the layers start near the
 * local surface. Unsigned min of the order-preserving bits: exact, same in C and OpenCL. */
SL_INLINE sl_uint sl_raster_z0_window(const SL_GLOBAL sl_uint *z0bits, sl_int w, sl_int h, sl_int x,
                                      sl_int y, sl_int m, sl_int dx) {
    const sl_int n = dx ? w : h, c = dx ? x : y;
    const sl_int a = c - m < 0 ? 0 : c - m, b = c + m > n - 1 ? n - 1 : c + m;
    sl_uint v = SL_RASTER_Z_EMPTY;
    for (sl_int i = a; i <= b; i++) {
        const sl_uint q = z0bits[dx ? (sl_ulong)y * (sl_ulong)w + (sl_ulong)i
                                    : (sl_ulong)i * (sl_ulong)w + (sl_ulong)x];
        v = q < v ? q : v;
    }
    return v;
}

/* The first depth over a window of fractional half-size m + frac (0 <= frac < 1): a = the
 * minimum over the window of half-size m, b = over m + 1 (b <= a), interpolated linearly in
 * depth, so the window's width follows the fibers' width in texels continuously instead of in
 * steps of two texels (docs/shadow.md, "A window of constant width in fibers"). An empty a (no
 * hair within m) takes b. Same float operations in C and OpenCL. */
SL_INLINE sl_uint sl_raster_z0_blend(sl_uint a, sl_uint b, float frac) {
    if (a == SL_RASTER_Z_EMPTY) return b;
    if (!(frac > 0.0f)) return a;
    const float za = sl_raster_z_of(a), zb = sl_raster_z_of(b);
    return sl_raster_bits_of(za + frac * (zb - za));
}

#endif
