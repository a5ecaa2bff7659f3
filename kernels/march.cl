/* march.cl: shadow-path marching (kernels/march.h; C twin cpu/march_c.c). One work-item per
 * (active coarse vertex, lobe): all its paths, T_f, sigma_f and tilt2 for SL_MARCH_CH channels. */
#pragma OPENCL FP_CONTRACT OFF

#include "march.h"

__kernel void sl_march(__global const float *vox, int nx, int ny, int nz, float lox, float loy,
                       float loz, float h, __global const float *tabs, __global const float *verts,
                       uint nverts, __global const float *dirs, uint nlobes, int paths, uint seed,
                       __global const uint *vert_ids, __global float *outT, __global float *outS,
                       __global float *outG) {
    const uint g = get_global_id(0);
    if (g >= nverts * nlobes) return;
    const uint lobe = g / nverts, v = g % nverts;
    float lo[3] = {lox, loy, loz};
    float x[3] = {verts[3 * v], verts[3 * v + 1], verts[3 * v + 2]};
    float w[3] = {dirs[3 * lobe], dirs[3 * lobe + 1], dirs[3 * lobe + 2]};
    float Tf[SL_MARCH_CH], sf[SL_MARCH_CH], tg[SL_MARCH_CH];
    sl_march_vertex(vox, nx, ny, nz, lo, h, tabs, x, w, seed, vert_ids[v], lobe, paths, 0, Tf, sf,
                    tg);
    for (int c = 0; c < SL_MARCH_CH; c++) {
        outT[(size_t)g * SL_MARCH_CH + c] = Tf[c];
        outS[(size_t)g * SL_MARCH_CH + c] = sf[c];
        outG[(size_t)g * SL_MARCH_CH + c] = tg[c];
    }
}
