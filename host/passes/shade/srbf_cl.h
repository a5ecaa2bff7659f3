/* srbf_cl.h: OpenCL batch driver for the SRBF response (kernels/srbf.cl); the same row
 * shapes as the C twin (cpu/srbf_c.h). Uploads the rows and the tables, runs one work-item per
 * row, reads the results back (blocking). Returns 0, -1 (e set) or SL_CL_EKERNEL. */
#ifndef SL_SRBF_CL_H
#define SL_SRBF_CL_H

#include <stddef.h>

#include "cl/clrt.h"
#include "fiber_params.h"
#include "passes/shade/srbf_tables.h"

/* in: 5 floats per row (theta_o, phi_o, theta_j, phi_j, lambda); out: I_R, I_TT, I_TRT, I.
 * method: SL_SRBF_METHOD_XU or _FAST (cpu/srbf_c.h); segments 1..8. */
int slcl_srbf_batch(sl_cl *cl, const sl_fiber_params *fp, const sl_srbf_tables *t, int method,
                    int segments, size_t n, const float *in, float *out, sl_err *e);

/* Three sigma_a per row at once (cpu/srbf_c.h slc_srbf_rgb_batch): sigma_a 3 floats per row or
 * NULL (fp->sigma_a in all three); out 9 per row (I_R rgb, I_TT rgb, I_TRT rgb). The kernel is
 * built specialised for fp and method (slcl_srbf_options); the build is cached per option set. */
int slcl_srbf_rgb_batch(sl_cl *cl, const sl_fiber_params *fp, const sl_srbf_tables *t, int method,
                        int segments, size_t n, const float *in, const float *sigma_a, float *out,
                        sl_err *e);
/* The same with generic = 1: the unspecialised build (run-time method, m, eccentricity), for
 * measuring the gain of the specialisation. */
int slcl_srbf_rgb_batch_ex(sl_cl *cl, const sl_fiber_params *fp, const sl_srbf_tables *t,
                           int method, int segments, size_t n, const float *in,
                           const float *sigma_a, float *out, int generic, sl_err *e);
/* The -D options of kernels/srbf.cl for fp and method (into buf). */
void slcl_srbf_options(const sl_fiber_params *fp, int method, int segments, char *buf, size_t size);

/* One batch of an SRBF kernel (kernels/srbf.cl, kernels/srbf_deon.cl). Every such
 * kernel takes (const sl_fiber_params, const uint rows) first, then the arguments `args` spells,
 * one letter each: 'b' the next float buffer (in the order of size/src), 'i' the next of ints (a
 * const int). A buffer with src[a] is a read-only copy of its size[a] floats; with NULL it is
 * written by the kernel (write-only). At most SLCL_SRBF_MAX_BUF buffers. */
enum { SLCL_SRBF_MAX_BUF = 8 };
typedef struct slcl_srbf_job {
    const char *file, *kernel, *options; /* sl_cl_get_kernel's; kernel also names errors */
    size_t n;                            /* rows: one work-item each */
    const char *args;
    const cl_int *ints;
    int res; /* the buffer read back into out: size[res] floats */
    const size_t *size;
    const float *const *src;
} slcl_srbf_job;

/* The one OpenCL launch path of the SRBF batch drivers (this file's and
 * host/passes/shade/srbf_deon_cl.c's): n == 0 does nothing; n > 2^32 - 1 fails naming the kernel.
 * Otherwise gets the kernel (built or cached), creates the buffers, sets the arguments, launches
 * one work-item per row (work groups of 64, or the device's maximum when smaller), reads buffer res
 * back into out (blocking) and releases the buffers whatever happened. Returns 0, -1 (e set) or
 * SL_CL_EKERNEL. */
int slcl_srbf_launch(sl_cl *cl, const sl_fiber_params *fp, const slcl_srbf_job *j, float *out,
                     sl_err *e);

#endif
