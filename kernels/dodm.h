/* dodm.h: deep opacity depth maps (DODM) and their convolution lookup (Ren 2010 Sec. 5), shared
 * by kernels/dodm.cl and the C twin cpu/dodm.c.
 *
 * Maps (w x h texels, row-major, layer-major): z0 (first depth, as order-preserving uint bits,
 * raster.h) and K planes of 64-bit fixed-point optical depth. After the rasterizer's layer pass,
 * plane k holds the optical depth of the fragments whose depth offset z - z0 lies in layer k;
 * sl_dodm_cumulate makes it the optical depth of everything up to the layer's far boundary
 * b_{k+1} = (k+1)(k+2) d / 2 (Ren Eq. 10, numerics.md sec. 7: projected fiber area per unit area),
 * and the row and column scans turn each plane into a summed-area table (Crow 1984).
 *
 * PRECISION REMEDY: the tables are 64-bit integers (fixed point, scale a power of two chosen by
 * the host so the whole map's total stays below 2^61). Integer prefix sums are exact, so a box
 * sum S(x1,y1) - S(x0-1,y1) - S(x1,y0-1) + S(x0-1,y0-1) is exact too, whatever the map size
 * (a float SAT of a 2048 x 2048 map loses about 1e-2 relative on a 3 x 3 box mean: docs/shadow.md);
 * only the final conversion of the box sum to float rounds (relative 2^-24). Integer addition is
 * associative, so the kernel and the C twin agree bit for bit in any summation order. */
#ifndef SL_DODM_H
#define SL_DODM_H

#include "raster.h"
#include "sl_compat.h"

/* Layer boundary b_k = k (k + 1) d / 2 as the rasterizer computes it. */
SL_INLINE float sl_dodm_boundary(sl_uint k, float d) {
    return (float)(k * (k + 1u) / 2u) * d;
}

/* Sum of the cells x0..x1, y0..y1 (inclusive) of one summed-area table, exact in modular
 * 64-bit arithmetic, rounded once to float. */
SL_INLINE float sl_dodm_cells(const SL_GLOBAL sl_ulong *sat, sl_int w, sl_int x0, sl_int y0,
                              sl_int x1, sl_int y1) {
    sl_ulong v = sat[(sl_ulong)y1 * (sl_ulong)w + (sl_ulong)x1];
    if (x0 > 0) v -= sat[(sl_ulong)y1 * (sl_ulong)w + (sl_ulong)(x0 - 1)];
    if (y0 > 0) v -= sat[(sl_ulong)(y0 - 1) * (sl_ulong)w + (sl_ulong)x1];
    if (x0 > 0 && y0 > 0) v += sat[(sl_ulong)(y0 - 1) * (sl_ulong)w + (sl_ulong)(x0 - 1)];
    return (float)v;
}

/* Splits [a0, a1] (0 <= a0 < a1 <= n, cells [i, i+1)) into at most 3 runs of cells with the
 * fraction of each cell covered: a partial first cell, whole cells, a partial last cell.
 * Returns the number of runs. */
SL_INLINE sl_int sl_dodm_runs(float a0, float a1, sl_int n, sl_int *lo, sl_int *hi, float *wt) {
    sl_int i0 = (sl_int)floor(a0), i1 = (sl_int)floor(a1);
    if (i0 > n - 1) i0 = n - 1;
    if (i1 > n - 1) i1 = n - 1;
    if (i1 <= i0) {
        lo[0] = hi[0] = i0;
        wt[0] = a1 - a0;
        return 1;
    }
    sl_int c = 0;
    lo[c] = hi[c] = i0;
    wt[c++] = (float)(i0 + 1) - a0;
    if (i1 - 1 >= i0 + 1) {
        lo[c] = i0 + 1;
        hi[c] = i1 - 1;
        wt[c++] = 1.0f;
    }
    lo[c] = hi[c] = i1;
    wt[c++] = a1 - (float)i1;
    return c;
}

/* Integral of a piecewise-constant plane over the box [X0,X1] x [Y0,Y1] (inside the map), in
 * fixed-point units: area-weighted, so the box may have any real size and position. */
SL_INLINE float sl_dodm_box(const SL_GLOBAL sl_ulong *sat, sl_int w, sl_int h, float X0, float X1,
                            float Y0, float Y1) {
    sl_int xl[3], xh[3], yl[3], yh[3];
    float xw[3], yw[3];
    const sl_int nx = sl_dodm_runs(X0, X1, w, xl, xh, xw);
    const sl_int ny = sl_dodm_runs(Y0, Y1, h, yl, yh, yw);
    float s = 0.0f;
    for (sl_int b = 0; b < ny; b++)
        for (sl_int a = 0; a < nx; a++)
            s += (xw[a] * yw[b]) * sl_dodm_cells(sat, w, xl[a], yl[b], xh[a], yh[b]);
    return s;
}

/* Convolution optical depth at map position (u, v) (texels) and depth z (Ren 2010 Sec. 5, view
 * pass): the box of half-size R = max(1/2, rfac (z - z0)) texels around (u, v), with
 * rfac = tan(alpha) / (2 texel) from the SRBF support angle alpha (the effective occlusion plane
 * halfway between z0 and z), averaged over the box's full area (the map is zero outside), on the
 * two layer tables around z's depth offset and interpolated linearly in depth (tau = 0 at z0).
 * inv_scale converts fixed point to optical depth. A position off the map or in front of the
 * hair (z <= z0, including texels with no hair) has tau = 0.
 * With behind != NULL, also the optical depth of the hair behind the position, seen from
 * the light, into *behind: the whole column's (the last table, which holds every depth) over the
 * same box, less tau; >= 0. It is the expected number of fibers a ray from the light crosses
 * after z: the stack behind a shading point that its local backscattering comes from
 * (docs/volume.md, "The stack behind and in front of a fragment"). A position in front of z0 has
 * the whole column over a half-texel box behind it; off the map, nothing. One box for both, so a
 * caller that needs both pays for one lookup. */
SL_INLINE float sl_dodm_tau_split(const SL_GLOBAL sl_uint *z0bits, const SL_GLOBAL sl_ulong *sat,
                                  sl_int w, sl_int h, sl_uint K, float d, float rfac,
                                  float inv_scale, float u, float v, float z, float *behind) {
    if (behind) *behind = 0.0f;
    if (!(u >= 0.0f && v >= 0.0f && u < (float)w && v < (float)h)) return 0.0f;
    const sl_int tx = (sl_int)floor(u), ty = (sl_int)floor(v);
    const float z0 = sl_raster_z_of(z0bits[(sl_ulong)ty * (sl_ulong)w + (sl_ulong)tx]);
    if (!(z > z0) && !behind) return 0.0f;
    const float dz = z > z0 ? z - z0 : 0.0f;
    const float rmax = 2.0f * (float)(w > h ? w : h);
    float R = sl_maxf(0.5f, rfac * dz);
    if (!(R < rmax)) R = rmax; /* also catches rfac = inf (a lobe wider than a hemisphere) */
    const float X0 = sl_maxf(u - R, 0.0f), X1 = sl_minf(u + R, (float)w);
    const float Y0 = sl_maxf(v - R, 0.0f), Y1 = sl_minf(v + R, (float)h);
    const float norm = inv_scale / ((2.0f * R) * (2.0f * R));
    const sl_ulong plane = (sl_ulong)w * (sl_ulong)h;
    float tau = 0.0f;
    if (z > z0) {
        const sl_uint k = sl_raster_layer(dz, d, K);
        const float hi = sl_dodm_box(sat + (sl_ulong)k * plane, w, h, X0, X1, Y0, Y1) * norm;
        const float b0 = sl_dodm_boundary(k, d), b1 = sl_dodm_boundary(k + 1u, d);
        if (dz >= b1) { /* beyond the last boundary: everything */
            tau = hi;
        } else {
            const float lo =
                k > 0u ? sl_dodm_box(sat + (sl_ulong)(k - 1u) * plane, w, h, X0, X1, Y0, Y1) * norm
                       : 0.0f;
            tau = lo + (hi - lo) * ((dz - b0) / (b1 - b0));
        }
    }
    if (behind) {
        const float all =
            sl_dodm_box(sat + (sl_ulong)(K - 1u) * plane, w, h, X0, X1, Y0, Y1) * norm;
        *behind = all > tau ? all - tau : 0.0f;
    }
    return tau;
}

/* The convolution optical depth alone (above). */
SL_INLINE float sl_dodm_tau(const SL_GLOBAL sl_uint *z0bits, const SL_GLOBAL sl_ulong *sat,
                            sl_int w, sl_int h, sl_uint K, float d, float rfac, float inv_scale,
                            float u, float v, float z) {
    return sl_dodm_tau_split(z0bits, sat, w, h, K, d, rfac, inv_scale, u, v, z, (float *)0);
}

/* Per-lobe lookup parameters of a batch (SL_DODM_PARAMS floats per lobe): d, rfac, inv_scale. */
#define SL_DODM_PARAMS 4

/* tau at world point p (3 floats) for lobe l of a batch: maps stacked per lobe (z0: one plane,
 * tables: K planes), views as in kernels/raster.h (SL_RASTER_VIEW floats per lobe). */
SL_INLINE float sl_dodm_tau_lobe(const SL_GLOBAL sl_uint *z0bits, const SL_GLOBAL sl_ulong *sat,
                                 sl_int w, sl_int h, sl_uint K, const SL_GLOBAL float *params,
                                 const SL_GLOBAL float *views, sl_uint l,
                                 const SL_GLOBAL float *p) {
    const sl_ulong plane = (sl_ulong)w * (sl_ulong)h;
    const SL_GLOBAL float *q = params + (sl_ulong)l * SL_DODM_PARAMS;
    float u, v, z;
    sl_raster_project(views + (sl_ulong)l * SL_RASTER_VIEW, p, &u, &v, &z);
    return sl_dodm_tau(z0bits + l * plane, sat + (sl_ulong)l * K * plane, w, h, K, q[0], q[1], q[2],
                       u, v, z);
}

#endif
