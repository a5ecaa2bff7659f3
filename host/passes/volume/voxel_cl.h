/* voxel_cl.h: enqueues kernels/voxel.cl (hair voxelization; C twin cpu/voxel_c.c). */
#ifndef SL_VOXEL_CL_H
#define SL_VOXEL_CL_H

#include "cl/clrt.h"

#include <stdint.h>

/* Both passes on nseg segment records: out gets SL_VOX_FIELDS floats per voxel of the
 * n[0] x n[1] x n[2] grid. *kernel_s (may be NULL): device time of the two passes.
 * Returns 0, -1 or SL_CL_EKERNEL. */
int slcl_voxelize(sl_cl *cl, const float *segs, size_t nseg, const int n[3], const float lo[3],
                  float h, float scale, float *out, double *kernel_s, sl_err *e);

#endif
