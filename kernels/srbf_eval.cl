/* srbf_eval.cl: the OpenCL kernel behind `strandlight eval srbf` (--method xu and fast), one
 * work-item per row; host side in host/srbf_cl.c. It calls the same float headers as the C twin
 * (cpu/srbf_c.c), so both backends agree to float rounding.
 *   sl_srbf_eval: in theta_o, phi_o, theta_j, phi_j, lambda -> I_R, I_TT, I_TRT, I
 * C and H are the tables of host/srbf_tables.h (layout in kernels/srbf_xu.h). */
#include "srbf_fast.h"

__kernel void sl_srbf_eval(const sl_fiber_params fp_arg, const uint n, __global const float *in,
                           __global float *out, __global const float *C, __global const float *H,
                           const int method, const int segments) {
    size_t i = get_global_id(0);
    if (i >= n) return;
    sl_fiber_params fp = fp_arg;
    __global const float *r = in + 5 * i;
    float o[4];
    if (method == 1)
        sl_srbf_fast(&fp, C, H, r[0], r[1], r[2], r[3], r[4], o);
    else
        sl_srbf_xu(&fp, C, H, segments, r[0], r[1], r[2], r[3], r[4], o);
    for (int k = 0; k < 4; k++)
        out[4 * i + k] = o[k];
}
