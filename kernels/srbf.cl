/* srbf.cl: the OpenCL kernels behind `strandlight eval srbf` (--method xu and fast) and the
 * frame's shading pass, one work-item per row; host side in host/passes/shade/srbf_cl.c. They call the same
 * float headers as the C twin (cpu/srbf_c.c), so both backends agree to float rounding.
 *   sl_srbf_eval:     in theta_o, phi_o, theta_j, phi_j, lambda -> I_R, I_TT, I_TRT, I
 *   sl_srbf_eval_rgb: the same rows and 3 sigma_a per row (has_sigma = 0: fp's in all three)
 *                     -> I_R rgb, I_TT rgb, I_TRT rgb (sl_srbf_rgb_row)
 * C and H are the tables of host/passes/shade/srbf_tables.h (layout in kernels/srbf_xu.h).
 *
 * Specialisation (issue 9; host/passes/shade/srbf_cl.c builds one program per option set, cached by clrt):
 *   -DSL_SRBF_SPEC_METHOD=0|1   the method is a constant (the other one is not compiled)
 *   -DSL_SRBF_SPEC_SEGMENTS=m   Xu's m is a constant (its node loop unrolls)
 *   -DSL_SRBF_FAST_ONLY         with method 1: no Xu code at all
 *   -DSL_SRBF_ROUND_ONLY        eccentricity 1: no eccentric TRT code (averaged eta*)
 * Without options the kernels are generic (method, m and eccentricity at run time). */
#include "srbf_fast.h"

#ifdef SL_SRBF_SPEC_METHOD
#define SL_SRBF_METHOD_OF(m) SL_SRBF_SPEC_METHOD
#else
#define SL_SRBF_METHOD_OF(m) (m)
#endif
#ifdef SL_SRBF_SPEC_SEGMENTS
#define SL_SRBF_SEGMENTS_OF(m) SL_SRBF_SPEC_SEGMENTS
#else
#define SL_SRBF_SEGMENTS_OF(m) (m)
#endif

__kernel void sl_srbf_eval(const sl_fiber_params fp_arg, const uint n, __global const float *in,
                           __global float *out, __global const float *C, __global const float *H,
                           const int method, const int segments) {
    size_t i = get_global_id(0);
    if (i >= n) return;
    sl_fiber_params fp = fp_arg;
    __global const float *r = in + 5 * i;
    float o[4];
#ifndef SL_SRBF_FAST_ONLY
    if (SL_SRBF_METHOD_OF(method) != 1)
        sl_srbf_xu(&fp, C, H, SL_SRBF_SEGMENTS_OF(segments), r[0], r[1], r[2], r[3], r[4], o);
    else
#endif
        sl_srbf_fast(&fp, C, H, r[0], r[1], r[2], r[3], r[4], o);
    for (int k = 0; k < 4; k++)
        out[4 * i + k] = o[k];
}

__kernel void sl_srbf_eval_rgb(const sl_fiber_params fp_arg, const uint n, __global const float *in,
                               __global const float *sigma, const int has_sigma,
                               __global float *out, __global const float *C,
                               __global const float *H, const int method, const int segments) {
    size_t i = get_global_id(0);
    if (i >= n) return;
    sl_fiber_params fp = fp_arg;
    __global const float *r = in + 5 * i;
    float sig[3] = {fp.sigma_a, fp.sigma_a, fp.sigma_a};
    if (has_sigma) {
        sig[0] = sigma[3 * i];
        sig[1] = sigma[3 * i + 1];
        sig[2] = sigma[3 * i + 2];
    }
    float o[9];
    sl_srbf_rgb_row(&fp, C, H, SL_SRBF_METHOD_OF(method), SL_SRBF_SEGMENTS_OF(segments), r[0], r[1],
                    r[2], r[3], r[4], sig, o);
    for (int k = 0; k < 9; k++)
        out[9 * i + k] = o[k];
}
