/* dodm.cl: deep opacity depth maps after the rasterizer (kernels/dodm.h; C twin cpu/dodm.c):
 * layers made cumulative, exact 64-bit summed-area tables (rows, then columns: one work-item per
 * row or column, linear work, neighbouring work-items on neighbouring columns), and the
 * convolution-optical-depth lookup giving T = exp(-tau) per point. */
#pragma OPENCL FP_CONTRACT OFF

#include "dodm.h"

/* Plane k becomes the sum of planes 0..k (per texel). */
__kernel void sl_dodm_cumulate(__global ulong *bins, uint plane, uint K) {
    const uint t = get_global_id(0);
    if (t >= plane) return;
    ulong s = 0;
    for (uint k = 0; k < K; k++) {
        s += bins[(size_t)k * plane + t];
        bins[(size_t)k * plane + t] = s;
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
