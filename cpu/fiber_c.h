/* fiber_c.h: batch drivers of the C twin (float) for the fiber quantities of numerics.md sec. 5:
 * they run the same kernels/ headers as the OpenCL kernels (kernels/fiber.cl), row by
 * row, so C and OpenCL agree to float rounding. Rows are packed floats. */
#ifndef SL_FIBER_C_H
#define SL_FIBER_C_H

#include <stddef.h>

#include "fiber_params.h"

/* in: 4 floats per row (theta_i, phi_i, theta_o, phi_o); out: 4 per row (marschner: f_R, f_TT,
 * f_TRT, f), orders + 3 per row (deon: f_0..f_orders, f_rest, f) or 5 (chiang: f_0, f_1, f_2,
 * f_rest, f). */
void slc_scatter_batch(const sl_fiber_params *fp, size_t n, const float *in, float *out);
/* The same with in_w floats per row (4 or 8): with 8, floats 4..7 are theta_i_lo, theta_o_lo,
 * phi_i_lo, phi_o_lo, what rounding the double inputs to float took off (|lo| <= 2.4e-7). Near a
 * pole cos theta is below one float spacing of theta, and near phi = +-pi so is marschner's
 * N_R ~ cos(phi/2); there the lo parts decide the value (docs/numerics.md "Poles and tails").
 * deon reads the theta lo parts, chiang theta_o_lo. */
void slc_scatter_rows(const sl_fiber_params *fp, size_t n, const float *in, size_t in_w,
                      float *out);
/* Number of output floats per row of slc_scatter_batch for this material. */
size_t slc_scatter_width(const sl_fiber_params *fp);
/* in: v, theta_i, theta_o per row; out: M, log_M (d'Eon 2011 Eq. 7, no shift). */
void slc_deon_mp_batch(size_t n, const float *in, float *out);
/* in: theta_o, phi_o per row; out: albedo = integral of f over the sphere (either model). */
void slc_furnace_batch(const sl_fiber_params *fp, size_t n, const float *in, float *out);

#endif
