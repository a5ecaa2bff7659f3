/* fiber_cl.h: OpenCL batch drivers for the fiber quantities of numerics.md sec. 5 (kernels in
 * kernels/fiber.cl); the same row shapes as the C twin in cpu/fiber_c.h. Each call
 * uploads the rows, runs one work-item per row and reads the results back (blocking).
 * Return 0, -1 (e set) or SL_CL_EKERNEL when the kernel could not be built (see clrt.h). */
#ifndef SL_FIBER_CL_H
#define SL_FIBER_CL_H

#include <stddef.h>

#include "cl/clrt.h"
#include "fiber_params.h"

/* in: 4 floats per row; out: slc_scatter_width(fp) floats per row (4, orders + 3 for deon, 5
 * for chiang). */
int slcl_scatter_batch(sl_cl *cl, const sl_fiber_params *fp, size_t n, const float *in, float *out,
                       sl_err *e);
/* The same with in_w (4 or 8) floats per row, as slc_scatter_rows (cpu/fiber_c.h). */
int slcl_scatter_rows(sl_cl *cl, const sl_fiber_params *fp, size_t n, const float *in, size_t in_w,
                      float *out, sl_err *e);
/* in: v, theta_i, theta_o; out: M, log_M. */
int slcl_deon_mp_batch(sl_cl *cl, size_t n, const float *in, float *out, sl_err *e);
/* in: theta_o, phi_o; out: albedo. */
int slcl_furnace_batch(sl_cl *cl, const sl_fiber_params *fp, size_t n, const float *in, float *out,
                       sl_err *e);

#endif
