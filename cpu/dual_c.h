/* dual_c.h: the C twin of the dual-scattering material terms (kernels/dual_material.h, float): the
 * per-channel 1-D tables over theta_d that the renderer uses, and the `ms-material` batch of
 * `strandlight eval --backend c` (a table lookup, exactly what a render sees). */
#ifndef SL_DUAL_C_H
#define SL_DUAL_C_H

#include <stddef.h>

#include "fiber_params.h"

/* Fills tab (SL_DUAL_TABLE_FLOATS floats, kernels/dual_material.h layout) for one channel: the nine
 * terms at SL_DUAL_N nodes over theta_d in [0, pi/2] and the SATs of Delta_b and sigma_b. Marschner
 * model only (fp->model 0). */
void slc_dual_table(const sl_fiber_params *fp, float *tab);

/* in: theta_d per row; out: 9 floats per row (a_f, a_b, alpha_f, alpha_b, beta_f, beta_b, A_b,
 * Delta_b, sigma_b), interpolated from the table built for fp. */
void slc_ms_material_batch(const sl_fiber_params *fp, size_t n, const float *in, float *out);
/* The same lookup in a table already built by slc_dual_table (eval keeps it across chunks). */
void slc_ms_material_lookup(const float *tab, size_t n, const float *in, float *out);

#endif
