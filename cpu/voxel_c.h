/* voxel_c.h: the C twin of kernels/voxel.cl (hair voxelization for multiple scattering; the math
 * is kernels/voxel.h, definitions in docs/volume.md). */
#ifndef SL_VOXEL_C_H
#define SL_VOXEL_C_H

#include <stddef.h>
#include <stdint.h>

/* Pass 1: adds the pieces of nseg segment records (SL_VOX_SEG floats each) to acc
 * (SL_VOX_ACC int64 sums per voxel, two's complement in uint64, not cleared here). */
void slc_voxel_accumulate(const float *segs, size_t nseg, const int n[3], const float lo[3],
                          float h, float scale, uint64_t *acc);
/* Pass 2: nvox voxels' sums -> SL_VOX_FIELDS floats each. */
void slc_voxel_finalize(const uint64_t *acc, size_t nvox, float h, float inv_scale, float *out);

#endif
