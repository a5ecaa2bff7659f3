/* raster.cl: the segment rasterizer (kernels/raster.h; C twin cpu/raster.c). The projection
 * kernel makes the records of a batch of lobes from the world points; then one work-item per
 * (lobe, segment record) walks its ribbon samples (the splat loop of kernels/splat.h, shared with
 * the twins) and splats them with exact 64-bit fixed-point atomics (cl_khr_int64_base_atomics; a
 * device without it fails to build and `auto` falls back to C). Pass 1 (sl_raster_z0) takes the first depth z0 per texel (atomic min of the depth's bits),
 * between them sl_raster_z0_min (rows, then columns) takes the minimum of z0 over a square window
 * so that a texel's layers start at the local hair surface (kernels/raster.h: sl_raster_z0_window),
 * and pass 2 (sl_raster_layers) adds each share to the deep-opacity layer its depth offset falls
 * in. Maps may be stacked for a batch of lobes: z0bits holds nl planes, bins nl * K planes. */
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL FP_CONTRACT OFF

#include "raster.h"
#include "splat.h"

/* Records of nl lobes x nseg segments (lobe-major) from the world points (sl_raster_project_seg):
 * the projection runs on the device, so the hair is uploaded once per batch of lobes. */
__kernel void sl_raster_project_k(__global const float *pos, __global const uint *seg,
                                  __global const float *hw, __global const float *views, uint nseg,
                                  uint nl, float mscale, __global float *recs) {
    const size_t g = get_global_id(0);
    if (g >= (size_t)nseg * nl) return;
    sl_raster_project_seg(pos, seg, hw, views, nseg, (uint)(g / nseg), (uint)(g % nseg), mscale,
                          recs);
}

/* Work-item g = l * nseg + s: record s of lobe l into plane l of z0bits. */
__kernel void sl_raster_z0(__global const float *recs, uint nseg, uint nl, int w, int h,
                           __global uint *z0bits) {
    const size_t g = get_global_id(0);
    if (g >= (size_t)nseg * nl) return;
    __global const float *rec = recs + g * SL_RASTER_REC;
    z0bits += (g / nseg) * (size_t)w * h;
    sl_splat it;
    sl_splat_begin(&it, rec, w, h, 1);
    int tx, ty;
    float share, z;
    while (sl_splat_next(&it, &tx, &ty, &share, &z)) {
        if (convert_ulong_rte(share) == 0) continue;
        atomic_min(&z0bits[(size_t)ty * w + tx], as_uint(z));
    }
}

/* One pass of the separable min filter of half-size m: dst[t] = min of src over the texels within
 * m along x (dx = 1) or y (dx = 0) in the same plane; nl stacked planes of w * h. */
__kernel void sl_raster_z0_min(__global const uint *src, __global uint *dst, int w, int h, uint nl,
                               int m, int dx) {
    const size_t t = get_global_id(0), plane = (size_t)w * h;
    if (t >= plane * nl) return;
    const size_t base = t - t % plane;
    const int x = (int)(t % plane % (size_t)w), y = (int)(t % plane / (size_t)w);
    dst[t] = sl_raster_z0_window(src + base, w, h, x, y, m, dx);
}

/* The column pass of a fractional window m + frac (sl_raster_z0_blend): dst[t] = the minimum of
 * rows_m over the texels within m along y, blended toward that of rows_m1 (the row pass at
 * m + 1) within m + 1. */
__kernel void sl_raster_z0_min_blend(__global const uint *rows_m, __global const uint *rows_m1,
                                     __global uint *dst, int w, int h, uint nl, int m,
                                     float frac) {
    const size_t t = get_global_id(0), plane = (size_t)w * h;
    if (t >= plane * nl) return;
    const size_t base = t - t % plane;
    const int x = (int)(t % plane % (size_t)w), y = (int)(t % plane / (size_t)w);
    dst[t] = sl_raster_z0_blend(sl_raster_z0_window(rows_m + base, w, h, x, y, m, 0),
                                sl_raster_z0_window(rows_m1 + base, w, h, x, y, m + 1, 0), frac);
}

/* Work-item g = l * nseg + s: record s of lobe l (first layer depth d[l]) into planes
 * l K .. l K + K - 1 of bins against plane l of z0bits. */
__kernel void sl_raster_layers(__global const float *recs, uint nseg, uint nl, int w, int h, uint K,
                               __global const float *dl, __global const uint *z0bits,
                               __global ulong *bins) {
    const size_t g = get_global_id(0);
    if (g >= (size_t)nseg * nl) return;
    __global const float *rec = recs + g * SL_RASTER_REC;
    const float d = dl[g / nseg];
    const size_t plane = (size_t)w * h;
    z0bits += (g / nseg) * plane;
    bins += (g / nseg) * K * plane;
    sl_splat it;
    sl_splat_begin(&it, rec, w, h, 1);
    int tx, ty;
    float share, z;
    while (sl_splat_next(&it, &tx, &ty, &share, &z)) {
        const ulong q = convert_ulong_rte(share);
        if (q == 0) continue;
        const size_t t = (size_t)ty * w + tx;
        const uint k = sl_raster_layer(z - as_float(z0bits[t]), d, K);
        atom_add(&bins[k * plane + t], q);
    }
}
