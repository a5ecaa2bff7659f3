/* prefix_sum_cl.h: the OpenCL driver for kernels/prefix_sum.cl (inclusive 2-D prefix sum,
 * summed-area table) and a device-independent entry point that falls back to the C twin
 * (cpu/prefix_sum.h) when the kernels cannot be built under --device auto. */
#ifndef SL_PREFIX_SUM_CL_H
#define SL_PREFIX_SUM_CL_H

#include "cl/clrt.h"

/* Kernel variants, all bit-identical to the C twin: WORKGROUP scans a tile with a work-group in
 * local memory (GPUs), SERIAL runs a tile's tree in one work-item (CPU devices such as PoCL,
 * narrow rows). AUTO: SERIAL on CPU devices; on others WORKGROUP, but SERIAL for rows of at most
 * 64 elements (e.g. the scans of tile totals). */
typedef enum sl_ps_variant { SL_PS_AUTO = 0, SL_PS_WORKGROUP, SL_PS_SERIAL } sl_ps_variant;

/* out[y][x] = sum of in[j][i] over j <= y, i <= x, for a w x h row-major image, on the device:
 * bit-identical to slc_prefix_sum_2d. 1 <= w, h < 2^31. kernel_s (may be NULL) gets the device
 * time of the kernels (profiling events; wall clock if the driver has none), transfers excluded.
 * Returns 0, -1 or SL_CL_EKERNEL (kernels could not be built: see sl_device_try_fallback). */
int slcl_prefix_sum_2d(sl_cl *cl, const float *in, float *out, size_t w, size_t h, double *kernel_s,
                       sl_err *e);

/* The same with a chosen variant (tests, `strandlight kernels`). */
int slcl_prefix_sum_2d_variant(sl_cl *cl, const float *in, float *out, size_t w, size_t h,
                               sl_ps_variant variant, double *kernel_s, sl_err *e);

/* The same on device buffers of w * h floats (in == out allowed), for pipelines that keep data on
 * the device. Kernels are enqueued on sl_cl_queue(cl) in order; events go to timer (may be NULL).
 * Returns when enqueued (call clFinish or read out with a blocking read). */
int slcl_prefix_sum_2d_buf(sl_cl *cl, cl_mem in, cl_mem out, size_t w, size_t h, sl_cl_timer *timer,
                           sl_err *e);

/* On whatever dev is: OpenCL when dev->is_opencl (falling back to C, with a warning, when the
 * kernels cannot be built and dev came from "auto"), else the C twin. Returns 0 or -1. */
int sl_prefix_sum_2d(sl_device *dev, const float *in, float *out, size_t w, size_t h, sl_err *e);

#endif
