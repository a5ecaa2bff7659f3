/* raster_cl.h: the OpenCL driver of kernels/raster.cl (segment rasterizer into a first-depth map
 * and K fixed-point layer planes; C twin cpu/raster.h). Results equal the C twin bit for bit. */
#ifndef SL_RASTER_CL_H
#define SL_RASTER_CL_H

#include "clrt.h"
#include "kernel_checks.h"

#include <stdint.h>

/* On device buffers: recs (nseg * SL_RASTER_REC floats), z0bits (w * h uint, filled here),
 * bins (K * w * h ulong, zeroed here). Enqueued in order on sl_cl_queue(cl); events go to timer
 * (may be NULL). Returns 0, -1 or SL_CL_EKERNEL (e.g. no cl_khr_int64_base_atomics). */
int slcl_raster_buf(sl_cl *cl, cl_mem recs, size_t nseg, int w, int h, unsigned K, float d,
                    cl_mem z0bits, cl_mem bins, sl_cl_timer *timer, sl_err *e);
/* The same from and to host memory; kernel_s (may be NULL) gets the kernel time. */
int slcl_raster(sl_cl *cl, const float *recs, size_t nseg, int w, int h, unsigned K, float d,
                uint32_t *z0bits, uint64_t *bins, double *kernel_s, sl_err *e);

/* `strandlight kernels` check: raster.cl vs cpu/raster.c on procedural hair (bit-identical). */
int slchk_raster(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r, sl_err *e);

#endif
