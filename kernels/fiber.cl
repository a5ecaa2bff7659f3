/* fiber.cl: OpenCL kernels behind `strandlight eval` for the fiber quantities
 * (numerics.md sec. 5), one work-item per row; host side in host/passes/shade/fiber_cl.c. They call
 * the same float headers as the C twin (cpu/fiber_c.c), so both backends agree to float rounding.
 *   sl_scatter_eval:  in theta_i, phi_i, theta_o, phi_o [, theta_i_lo, theta_o_lo, phi_i_lo,
 *                     phi_o_lo] (in_w = 4 or 8 floats; cpu/fiber_c.h slc_scatter_rows) -> f per
 * mode + total (width floats) sl_deon_mp_eval:  in v, theta_i, theta_o            -> M, log_M
 *   sl_furnace_eval:  in theta_o, phi_o                 -> albedo */
#include "fiber_chiang.h"
#include "fiber_deon.h"
#include "fiber_furnace.h"
#include "fiber_marschner.h"

__kernel void sl_scatter_eval(const sl_fiber_params fp_arg, const uint n, __global const float *in,
                              __global float *out, const uint width, const uint in_w) {
    size_t i = get_global_id(0);
    if (i >= n) return;
    sl_fiber_params fp = fp_arg;
    float o[SL_DEON_MAX_ORDERS + 3];
    __global const float *r = in + (size_t)in_w * i;
    for (uint k = 0; k < width && k < SL_DEON_MAX_ORDERS + 3; k++)
        o[k] = 0.0f;
    if (fp.model == 2 && in_w >= 8)
        sl_chiang_scatter_lo(&fp, r[0], r[1], r[2], r[5], r[3], o);
    else if (fp.model == 2)
        sl_chiang_scatter(&fp, r[0], r[1], r[2], r[3], o);
    else if (fp.model == 1 && in_w >= 8)
        sl_deon_scatter_lo(&fp, r[0], r[4], r[1], r[2], r[5], r[3], o);
    else if (fp.model == 1)
        sl_deon_scatter(&fp, r[0], r[1], r[2], r[3], o);
    else if (in_w >= 8)
        sl_marschner_scatter_lo(&fp, r[0], r[4], r[1], r[6], r[2], r[5], r[3], r[7], o);
    else
        sl_marschner_scatter(&fp, r[0], r[1], r[2], r[3], o);
    for (uint k = 0; k < width && k < SL_DEON_MAX_ORDERS + 3; k++)
        out[(size_t)width * i + k] = o[k];
}

__kernel void sl_deon_mp_eval(const uint n, __global const float *in, __global float *out) {
    size_t i = get_global_id(0);
    if (i >= n) return;
    float lm = sl_deon_log_mp(in[3 * i], in[3 * i + 1], in[3 * i + 2]);
    out[2 * i] = exp(lm); /* may underflow to 0; log_M stays finite */
    out[2 * i + 1] = lm;
}

__kernel void sl_furnace_eval(const sl_fiber_params fp_arg, const uint n, __global const float *in,
                              __global float *out) {
    size_t i = get_global_id(0);
    if (i >= n) return;
    sl_fiber_params fp = fp_arg;
    out[i] = sl_furnace(&fp, in[2 * i], in[2 * i + 1]);
}
