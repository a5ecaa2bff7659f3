/* srbf_deon_cl.h: OpenCL batch driver of the d'Eon model's fast SRBF response
 * (kernels/srbf_deon.cl); the same row shapes as the C twin (cpu/srbf_deon_c.h). Uploads
 * the rows and the tables, runs one work-item per row, reads the results back (blocking). */
#ifndef SL_SRBF_DEON_CL_H
#define SL_SRBF_DEON_CL_H

#include <stddef.h>

#include "cl/clrt.h"
#include "fiber_params.h"
#include "passes/shade/srbf_tables.h"

/* in: 5 floats per row (theta_o, phi_o, theta_j, phi_j, lambda); out: orders + 3 per row
 * (I_0..I_orders, I_rest, I). Returns 0, -1 (e set) or SL_CL_EKERNEL. */
int slcl_srbf_deon_batch(sl_cl *cl, const sl_fiber_params *fp, const sl_srbf_tables *t, size_t n,
                         const float *in, float *out, sl_err *e);

/* The renderer's batch on the device (the shape of slcl_srbf_rgb_batch): sigma_a 3 per row or
 * NULL; out 9 per row as slc_srbf_deon_rgb_batch (cpu/srbf_deon_c.h). */
int slcl_srbf_deon_rgb_batch(sl_cl *cl, const sl_fiber_params *fp, const sl_srbf_tables *t,
                             size_t n, const float *in, const float *sigma_a, float *out,
                             sl_err *e);

#endif
