/* march_cl.h: enqueues kernels/march.cl (shadow-path marching; C twin cpu/march_c.c). */
#ifndef SL_MARCH_CL_H
#define SL_MARCH_CL_H

#include "cl/clrt.h"

#include <stdint.h>

/* The arguments of slc_march (cpu/march_c.h); nvox = n[0] n[1] n[2]. *kernel_s (may be NULL):
 * device time. Returns 0, -1 or SL_CL_EKERNEL. */
int slcl_march(sl_cl *cl, const float *vox, const int n[3], const float lo[3], float h,
               const float *tabs, const float *verts, const uint32_t *vert_ids, size_t nverts,
               const float *dirs, size_t nlobes, int paths, uint32_t seed, float *outT, float *outS,
               float *outG, double *kernel_s, sl_err *e);

#endif
