/* srbf_ren.cl: lookup in the precomputed SRBF response table of Ren 2010 Sec. 4, one work-item
 * per row; the twin of cpu/srbf_ren_c.c (same math, kernels/srbf_ren_lookup.h). Host side:
 * host/passes/shade/srbf_ren.c (slcl_srbf_ren_batch).
 *   sl_srbf_ren_eval: in theta_o, phi_o, theta_j, phi_j, lambda -> I_R rgb, I_TT rgb, I_TRT rgb */
#include "srbf_ren_lookup.h"

__kernel void sl_srbf_ren_eval(const sl_srbf_ren_dims d_arg, const uint n, __global const float *in,
                               __global float *out, __global const float *T) {
    size_t i = get_global_id(0);
    if (i >= n) return;
    sl_srbf_ren_dims d = d_arg;
    __global const float *r = in + 5 * i;
    float o[9];
    sl_srbf_ren_lookup(T, &d, r[0], r[1], r[2], r[3], r[4], o);
    for (int k = 0; k < 9; k++)
        out[9 * i + k] = o[k];
}
