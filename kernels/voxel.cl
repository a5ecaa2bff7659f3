/* voxel.cl: hair voxelization (kernels/voxel.h; C twin cpu/voxel_c.c). Pass 1: one work-item per
 * segment adds its pieces to their voxels with exact 64-bit fixed-point atomics
 * (cl_khr_int64_base_atomics; a device without it fails to build and `auto` falls back to C).
 * Pass 2: one work-item per voxel turns the sums into density, direction and deviation. */
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL FP_CONTRACT OFF

#include "voxel.h"

__kernel void sl_voxel_accumulate(__global const float *segs, uint nseg, int nx, int ny, int nz,
                                  float lox, float loy, float loz, float h, float scale,
                                  __global ulong *acc) {
    const uint g = get_global_id(0);
    if (g >= nseg) return;
    __global const float *seg = segs + (size_t)g * SL_VOX_SEG;
    float dx = seg[4] - seg[0], dy = seg[5] - seg[1], dz = seg[6] - seg[2];
    const int ns = sl_vox_pieces(sqrt(dx * dx + dy * dy + dz * dz), h);
    for (int s = 0; s < ns; s++) {
        int v;
        float q[SL_VOX_ACC];
        sl_vox_piece(seg, s, ns, nx, ny, nz, lox, loy, loz, h, scale, &v, q);
        if (v < 0) continue;
        for (int k = 0; k < SL_VOX_ACC; k++) {
            const long x = convert_long_rte(q[k]);
            if (x != 0) atom_add(&acc[(size_t)v * SL_VOX_ACC + k], as_ulong(x));
        }
    }
}

__kernel void sl_voxel_finalize(__global const ulong *acc, uint nvox, float h, float inv_scale,
                                __global float *out) {
    const uint v = get_global_id(0);
    if (v >= nvox) return;
    float s[SL_VOX_ACC], o[SL_VOX_FIELDS];
    for (int k = 0; k < SL_VOX_ACC; k++)
        s[k] = (float)as_long(acc[(size_t)v * SL_VOX_ACC + k]) * inv_scale;
    sl_vox_finalize(s, h, o);
    for (int k = 0; k < SL_VOX_FIELDS; k++)
        out[(size_t)v * SL_VOX_FIELDS + k] = o[k];
}
