/* raster.cl: the segment rasterizer (kernels/raster.h; C twin cpu/raster.c). One work-item per
 * segment record walks its ribbon samples and splats them with exact 64-bit fixed-point atomics
 * (cl_khr_int64_base_atomics; a device without it fails to build and `auto` falls back to C).
 * Pass 1 (sl_raster_z0) takes the first depth z0 per texel (atomic min of the depth's bits),
 * pass 2 (sl_raster_layers) adds each share to the deep-opacity layer its depth offset falls in. */
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL FP_CONTRACT OFF

#include "raster.h"

__kernel void sl_raster_z0(__global const float *recs, uint nseg, int w, int h,
                           __global uint *z0bits) {
    const uint s = get_global_id(0);
    if (s >= nseg) return;
    __global const float *rec = recs + (size_t)s * SL_RASTER_REC;
    const uint na = (uint)rec[9], nw = (uint)rec[10];
    const float m = rec[8];
    for (uint i = 0; i < na; i++)
        for (uint j = 0; j < nw; j++) {
            float x, y, z, fx, fy;
            int ix, iy;
            sl_raster_sample(rec, i, j, &x, &y, &z);
            sl_raster_tent(x, y, &ix, &iy, &fx, &fy);
            for (int c = 0; c < 4; c++) {
                const int tx = ix + (c & 1), ty = iy + (c >> 1);
                if (tx < 0 || ty < 0 || tx >= w || ty >= h) continue;
                const float share =
                    sl_raster_share(m, (c & 1) ? fx : 1.0f - fx, (c >> 1) ? fy : 1.0f - fy);
                if (convert_ulong_rte(share) == 0) continue;
                atomic_min(&z0bits[(size_t)ty * w + tx], as_uint(z));
            }
        }
}

__kernel void sl_raster_layers(__global const float *recs, uint nseg, int w, int h, uint K, float d,
                               __global const uint *z0bits, __global ulong *bins) {
    const uint s = get_global_id(0);
    if (s >= nseg) return;
    __global const float *rec = recs + (size_t)s * SL_RASTER_REC;
    const uint na = (uint)rec[9], nw = (uint)rec[10];
    const float m = rec[8];
    const size_t plane = (size_t)w * h;
    for (uint i = 0; i < na; i++)
        for (uint j = 0; j < nw; j++) {
            float x, y, z, fx, fy;
            int ix, iy;
            sl_raster_sample(rec, i, j, &x, &y, &z);
            sl_raster_tent(x, y, &ix, &iy, &fx, &fy);
            for (int c = 0; c < 4; c++) {
                const int tx = ix + (c & 1), ty = iy + (c >> 1);
                if (tx < 0 || ty < 0 || tx >= w || ty >= h) continue;
                const float share =
                    sl_raster_share(m, (c & 1) ? fx : 1.0f - fx, (c >> 1) ? fy : 1.0f - fy);
                const ulong q = convert_ulong_rte(share);
                if (q == 0) continue;
                const size_t t = (size_t)ty * w + tx;
                const uint k = sl_raster_layer(z - as_float(z0bits[t]), d, K);
                atom_add(&bins[k * plane + t], q);
            }
        }
}
