/* dodm.cl: deep opacity depth maps after the rasterizer (kernels/dodm.h; C twin cpu/dodm.c):
 * layers made cumulative, exact 64-bit summed-area tables (rows, then columns: one work-item per
 * row or column, linear work, neighbouring work-items on neighbouring columns), and the
 * convolution-optical-depth lookup giving T = exp(-tau) per point. */
#pragma OPENCL FP_CONTRACT OFF

#include "dodm.h"

/* Plane k of every lobe's K planes becomes the sum of its planes 0..k (per texel); nl lobes. */
__kernel void sl_dodm_cumulate(__global ulong *bins, uint plane, uint K, uint nl) {
    const size_t g = get_global_id(0);
    if (g >= (size_t)plane * nl) return;
    bins += (g / plane) * K * plane + g % plane;
    ulong s = 0;
    for (uint k = 0; k < K; k++) {
        s += bins[(size_t)k * plane];
        bins[(size_t)k * plane] = s;
    }
}

/* Inclusive scan of each of nrows rows of w values (all planes stacked: nrows = K h). */
__kernel void sl_dodm_scan_rows(__global ulong *a, uint w, uint nrows) {
    const uint r = get_global_id(0);
    if (r >= nrows) return;
    __global ulong *p = a + (size_t)r * w;
    ulong s = 0;
    for (uint x = 0; x < w; x++) {
        s += p[x];
        p[x] = s;
    }
}

/* Inclusive scan down each column of every plane: work-item c = plane * w + x. */
__kernel void sl_dodm_scan_cols(__global ulong *a, uint w, uint h, uint K) {
    const uint c = get_global_id(0);
    if (c >= w * K) return;
    const uint k = c / w, x = c % w;
    __global ulong *p = a + (size_t)k * w * h + x;
    ulong s = 0;
    for (uint y = 0; y < h; y++) {
        s += p[(size_t)y * w];
        p[(size_t)y * w] = s;
    }
}

/* T = exp(-tau) at n points given as (u, v, z) in the light's map coordinates. */
__kernel void sl_dodm_lookup(__global const uint *z0bits, __global const ulong *sat, int w, int h,
                             uint K, float d, float rfac, float inv_scale,
                             __global const float *pts, uint n, __global float *T) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    const float tau = sl_dodm_tau(z0bits, sat, w, h, K, d, rfac, inv_scale, pts[3 * i],
                                  pts[3 * i + 1], pts[3 * i + 2]);
    T[i] = exp(-tau);
}

/* T as sl_dodm_lookup, and B = the optical depth of the hair behind each point (the stack a
 * fragment's local backscattering comes from, docs/volume.md), from one box (sl_dodm_tau_split). */
__kernel void sl_dodm_lookup_both(__global const uint *z0bits, __global const ulong *sat, int w,
                                  int h, uint K, float d, float rfac, float inv_scale,
                                  __global const float *pts, uint n, __global float *T,
                                  __global float *B) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    float behind;
    const float tau = sl_dodm_tau_split(z0bits, sat, w, h, K, d, rfac, inv_scale, pts[3 * i],
                                        pts[3 * i + 1], pts[3 * i + 2], &behind);
    T[i] = exp(-tau);
    B[i] = behind;
}

/* T = exp(-tau) at n world points (pts: 3 n floats) for a batch of nl lobes whose global indices
 * start at lobe0 (sl_dodm_tau_lobe). all != 0: every lobe at every point, T[i stride + lobe0 + l];
 * all = 0: point i for its own lobe lobe[i] (global index; other batches' points are skipped),
 * T[i]. */
__kernel void sl_dodm_lookup_lobes(__global const uint *z0bits, __global const ulong *sat, int w,
                                   int h, uint K, __global const float *params,
                                   __global const float *views, __global const float *pts,
                                   __global const uint *lobe, int all, uint n, uint nl, uint lobe0,
                                   uint stride, __global float *T) {
    const size_t g = get_global_id(0);
    size_t i, o;
    uint l;
    if (all) {
        if (g >= (size_t)n * nl) return;
        i = g / nl;
        l = (uint)(g % nl);
        o = i * stride + lobe0 + l;
    } else {
        if (g >= n) return;
        i = o = g;
        if (lobe[i] < lobe0 || lobe[i] - lobe0 >= nl) return;
        l = lobe[i] - lobe0;
    }
    T[o] = exp(-sl_dodm_tau_lobe(z0bits, sat, w, h, K, params, views, l, pts + 3 * i));
}
