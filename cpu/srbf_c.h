/* srbf_c.h: batch driver of the C twin (float) for the SRBF response (`eval srbf` on the c
 * backend): runs kernels/srbf_xu.h (and the fast path) row by row, the same code as
 * kernels/srbf_eval.cl, so C and OpenCL agree to float rounding. */
#ifndef SL_SRBF_C_H
#define SL_SRBF_C_H

#include <stddef.h>

#include "fiber_params.h"

/* Methods of slc_srbf_batch. */
enum { SL_SRBF_METHOD_XU = 0, SL_SRBF_METHOD_FAST = 1 };

/* in: 5 floats per row (theta_o, phi_o, theta_j, phi_j, lambda); out: 4 per row (I_R, I_TT,
 * I_TRT, I). C, H: the tables of host/srbf_tables.h. segments: m of Xu Sec. 4.2.2 (1..8). */
void slc_srbf_batch(const sl_fiber_params *fp, const float *C, const float *H, int method,
                    int segments, size_t n, const float *in, float *out);

#endif
