/* fiber_cl.h: OpenCL batch drivers for the fiber quantities of numerics.md sec. 5 (kernels in
 * kernels/fiber.cl); the same row shapes as the C twin in cpu/fiber_c.h. Each call
 * uploads the rows, runs one work-item per row and reads the results back (blocking); the
 * *_rows forms reuse buffers the caller keeps.
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
/* in: v, theta_i, theta_o; out: M, log_M. */
int slcl_deon_mp_batch(sl_cl *cl, size_t n, const float *in, float *out, sl_err *e);
/* in: theta_o, phi_o; out: albedo. */
int slcl_furnace_batch(sl_cl *cl, const sl_fiber_params *fp, size_t n, const float *in, float *out,
                       sl_err *e);

/* The row buffers a caller keeps between batches (eval's chunks) instead of creating and
 * releasing them per call: grown when a batch needs more, released by slcl_rows_bufs_release.
 * Zero-initialise it. */
typedef struct slcl_rows_bufs {
    cl_mem in, out;
    size_t in_bytes, out_bytes;
} slcl_rows_bufs;
void slcl_rows_bufs_release(slcl_rows_bufs *b);
/* The three batches above with kept buffers (b may be NULL: per-call buffers); the same
 * results. scatter: in_w (4 or 8) floats per row, as slc_scatter_rows (cpu/fiber_c.h: with 8,
 * each angle's float rounding remainder follows). */
int slcl_scatter_rows(sl_cl *cl, const sl_fiber_params *fp, size_t n, const float *in, size_t in_w,
                      float *out, slcl_rows_bufs *b, sl_err *e);
int slcl_deon_mp_rows(sl_cl *cl, size_t n, const float *in, float *out, slcl_rows_bufs *b,
                      sl_err *e);
int slcl_furnace_rows(sl_cl *cl, const sl_fiber_params *fp, size_t n, const float *in, float *out,
                      slcl_rows_bufs *b, sl_err *e);

#endif
