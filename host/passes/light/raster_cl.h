/* raster_cl.h: the OpenCL driver of kernels/raster.cl (segment rasterizer into a first-depth map
 * and K fixed-point layer planes; C twin cpu/raster.h). Results equal the C twin bit for bit. */
#ifndef SL_RASTER_CL_H
#define SL_RASTER_CL_H

#include "cl/clrt.h"

#include <stdint.h>

/* Records of nl lobes x nseg segments on the device (cpu/raster.h: slc_raster_project): pos
 * (3 floats per hair point), seg (uint first point of each segment), hw (float half-width in
 * texels), views (SL_RASTER_VIEW floats per lobe) -> recs (nl * nseg * SL_RASTER_REC floats). */
int slcl_raster_project_buf(sl_cl *cl, cl_mem pos, cl_mem seg, cl_mem hw, cl_mem views, size_t nseg,
                            unsigned nl, float mscale, cl_mem recs, sl_cl_timer *timer, sl_err *e);
/* On device buffers, nl lobes stacked: recs (nl * nseg * SL_RASTER_REC floats), d (nl floats:
 * each lobe's first layer depth), z0bits (nl * w * h uint, filled here and min-filtered over
 * (2 z0_radius + 1)^2 texels between the passes, or z0_frac > 0 the fractional window
 * z0_radius + z0_frac, cpu/raster.h), bins (nl * K * w * h ulong,
 * zeroed here). Enqueued in order on sl_cl_queue(cl); events go to timer (may be NULL). Returns
 * 0, -1 or SL_CL_EKERNEL (e.g. no cl_khr_int64_base_atomics). */
int slcl_raster_buf(sl_cl *cl, cl_mem recs, size_t nseg, unsigned nl, int w, int h, unsigned K,
                    cl_mem d, int z0_radius, float z0_frac, cl_mem z0bits, cl_mem bins,
                    sl_cl_timer *timer, sl_err *e);
/* One lobe from and to host memory; kernel_s (may be NULL) gets the kernel time. */
int slcl_raster(sl_cl *cl, const float *recs, size_t nseg, int w, int h, unsigned K, float d,
                int z0_radius, float z0_frac, uint32_t *z0bits, uint64_t *bins, double *kernel_s,
                sl_err *e);

#endif
