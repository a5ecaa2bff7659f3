/* ms.cl: the multiple-scattering response per fragment and lobe (kernels/ms_response.h; the C
 * side is host/passes/volume/volume_ms.c): one work-item per row (theta_o, phi_o, theta_j, phi_j, lambda,
 * sigma_f) -> (M^G, M^L) of one channel. sl_ms_table_rows reads the per-material response table
 * (kernels/ms_table.h), as the C side's sl_volume_ms_terms does; sl_ms_response_rows evaluates
 * the response directly (its reference). The renderer's view pass can call sl_ms_table_1 the
 * same way with its own fragment and lobe data. */
#pragma OPENCL FP_CONTRACT OFF

#include "ms_table.h"

__kernel void sl_ms_response_rows(const sl_fiber_params fp_arg, __global const float *tab,
                                  __global const float *ng, const uint n, __global const float *in,
                                  __global float *out) {
    const size_t i = get_global_id(0);
    if (i >= n) return;
    sl_fiber_params fp = fp_arg;
    __global const float *r = in + 6 * i;
    float mg, ml;
    sl_ms_response_1(&fp, tab, ng, r[0], r[1], r[2], r[3], r[4], r[5], &mg, &ml);
    out[2 * i] = mg;
    out[2 * i + 1] = ml;
}

__kernel void sl_ms_table_rows(const sl_fiber_params fp_arg, __global const float *mt, const uint n,
                               __global const float *in, __global float *out) {
    const size_t i = get_global_id(0);
    if (i >= n) return;
    sl_fiber_params fp = fp_arg;
    __global const float *r = in + 6 * i;
    float mg, ml;
    sl_ms_table_1(&fp, mt, r[0], r[1], r[2], r[3], r[4], r[5], &mg, &ml);
    out[2 * i] = mg;
    out[2 * i + 1] = ml;
}
