/* srbf_deon.cl: the OpenCL kernel behind `strandlight eval srbf --method fast` for the
 * d'Eon model, one work-item per row; host side in host/passes/shade/srbf_deon_cl.c. The same float header
 * as the C twin (kernels/srbf_deon.h, cpu/srbf_deon_c.c), so both backends agree to rounding.
 *   sl_srbf_deon_eval: in theta_o, phi_o, theta_j, phi_j, lambda -> I_0..I_orders, I_rest, I
 *   (stride orders + 3). C, H, D: the tables of host/passes/shade/srbf_tables.h.
 *   sl_srbf_deon_rgb: the renderer's rows (sl_srbf_deon_rgb_row): in as above, sig 3 per row
 *   (or use_sig == 0: fp.sigma_a), out 9 per row (I_0 rgb, I_1 rgb, orders >= 2 + rest rgb). */
#include "srbf_deon.h"

__kernel void sl_srbf_deon_eval(const sl_fiber_params fp_arg, const uint n,
                                __global const float *in, __global float *out,
                                __global const float *C, __global const float *H,
                                __global const float *D) {
    size_t i = get_global_id(0);
    if (i >= n) return;
    sl_fiber_params fp = fp_arg;
    int no = sl_srbf_deon_orders(&fp);
    __global const float *r = in + 5 * i;
    float o[SL_SRBF_DEON_NOUT];
    sl_srbf_deon(&fp, C, H, D, r[0], r[1], r[2], r[3], r[4], o);
    for (int k = 0; k < no + 3; k++)
        out[(size_t)(no + 3) * i + k] = o[k];
}

__kernel void sl_srbf_deon_rgb(const sl_fiber_params fp_arg, const uint n, __global const float *in,
                               __global const float *sig, const int use_sig, __global float *out,
                               __global const float *C, __global const float *H,
                               __global const float *D) {
    size_t i = get_global_id(0);
    if (i >= n) return;
    sl_fiber_params fp = fp_arg;
    __global const float *r = in + 5 * i;
    float s[3], o[9];
    for (int k = 0; k < 3; k++)
        s[k] = use_sig ? sig[3 * i + k] : fp.sigma_a;
    sl_srbf_deon_rgb_row(&fp, C, H, D, r[0], r[1], r[2], r[3], r[4], s, o);
    for (int k = 0; k < 9; k++)
        out[9 * i + k] = o[k];
}
