/* dual.cl: the dual-scattering material table on the device (kernels/dual_material.h; C twin
 * cpu/dual_c.c): one work-item per node computes the nine terms at that theta_d (the SAT rows are
 * added by the host, host/passes/volume/dual_cl.c, with the same sl_dual_build_sats as the twin),
 * and the `ms-material` lookups. */
#pragma OPENCL FP_CONTRACT OFF

#include "dual_material.h"

__kernel void sl_dual_table_nodes(const sl_fiber_params fp_arg, __global float *tab) {
    const int i = (int)get_global_id(0);
    if (i >= SL_DUAL_N) return;
    sl_fiber_params fp = fp_arg;
    float v[9];
    sl_dual_kern k;
    sl_dual_kern_init(&fp, &k);
    sl_dual_terms_k(&fp, sl_dual_node(i), &k, v);
    for (int r = 0; r < 9; r++)
        tab[r * SL_DUAL_N + i] = v[r];
}

__kernel void sl_dual_lookup_rows(__global const float *tab, const uint n, __global const float *in,
                                  __global float *out) {
    const size_t i = get_global_id(0);
    if (i >= n) return;
    for (int k = 0; k < 9; k++)
        out[9 * i + (size_t)k] = sl_dual_lookup(tab, k, in[i]);
}
