/* dual_cl.h: enqueues kernels/dual.cl: the dual-scattering table of one channel on the device and
 * the `ms-material` batch of `strandlight eval --backend opencl` (C twin: cpu/dual_c.h). */
#ifndef SL_DUAL_CL_H
#define SL_DUAL_CL_H

#include "cl/clrt.h"
#include "fiber_params.h"

/* Fills tab (SL_DUAL_TABLE_FLOATS floats) for fp: nodes on the device, SATs on the host. Returns 0,
 * -1 or SL_CL_EKERNEL. */
int slcl_dual_table(sl_cl *cl, const sl_fiber_params *fp, float *tab, sl_err *e);
/* in: theta_d per row; out: 9 floats per row (the table built on the device, looked up there). */
int slcl_ms_material_batch(sl_cl *cl, const sl_fiber_params *fp, size_t n, const float *in,
                           float *out, sl_err *e);
/* The same lookup on the device in a table already built by slcl_dual_table (eval keeps it
 * across chunks). */
int slcl_ms_material_lookup(sl_cl *cl, const float *tab, size_t n, const float *in, float *out,
                            sl_err *e);

#endif
