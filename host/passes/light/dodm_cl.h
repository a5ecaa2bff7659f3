/* dodm_cl.h: the OpenCL driver of kernels/dodm.cl (cumulative layers, exact 64-bit summed-area
 * tables, convolution-optical-depth lookup; C twin cpu/dodm.h). */
#ifndef SL_DODM_CL_H
#define SL_DODM_CL_H

#include "cl/clrt.h"

#include <stdint.h>

/* On a device buffer of nl * K * w * h ulong (nl lobes' layers) straight from the rasterizer:
 * cumulate each lobe's layers, then make every plane a summed-area table (bit-identical to
 * slc_dodm_cumulate + slc_dodm_sat per lobe). */
int slcl_dodm_tables_buf(sl_cl *cl, cl_mem bins, int w, int h, unsigned K, unsigned nl,
                         sl_cl_timer *timer, sl_err *e);
/* Batch lookup on device buffers (cpu/dodm.h: slc_dodm_lookup_lobes; lobe may be NULL: every
 * lobe at every point). T (float) is written in place, other entries untouched. */
int slcl_dodm_lookup_lobes_buf(sl_cl *cl, cl_mem z0bits, cl_mem sat, int w, int h, unsigned K,
                               cl_mem params, cl_mem views, cl_mem pts, cl_mem lobe, size_t n,
                               unsigned nl, unsigned lobe0, size_t stride, cl_mem T,
                               sl_cl_timer *timer, sl_err *e);
/* Host-memory versions (tests, checks). */
int slcl_dodm_tables(sl_cl *cl, uint64_t *bins, int w, int h, unsigned K, double *kernel_s,
                     sl_err *e);
int slcl_dodm_lookup(sl_cl *cl, const uint32_t *z0bits, const uint64_t *sat, int w, int h,
                     unsigned K, float d, float rfac, float inv_scale, const float *pts, size_t n,
                     float *T, sl_err *e);
/* The same T, and B = the optical depth behind each point, in one launch (kernels/dodm.h:
 * sl_dodm_tau_split). */
int slcl_dodm_lookup_both(sl_cl *cl, const uint32_t *z0bits, const uint64_t *sat, int w, int h,
                          unsigned K, float d, float rfac, float inv_scale, const float *pts,
                          size_t n, float *T, float *B, sl_err *e);

#endif
