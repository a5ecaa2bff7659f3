/* march_c.h: the C twin of kernels/march.cl (shadow-path marching; math in kernels/march.h,
 * definitions in docs/volume.md). */
#ifndef SL_MARCH_C_H
#define SL_MARCH_C_H

#include <stddef.h>
#include <stdint.h>

/* For every (lobe l < nlobes, vertex v < nverts): out index g = l * nverts + v, SL_MARCH_CH floats
 * of T_f in outT, of sigma_f in outS and of tilt2 in outG (kernels/march.h). vox: the finalized
 * grid (n, lo, h); tabs: SL_MARCH_CH dual tables; verts: 3 floats per vertex, vert_ids: each
 * vertex's id in the coarse grid (the random stream); dirs: 3 floats per lobe (unit, toward the
 * light). */
void slc_march(const float *vox, const int n[3], const float lo[3], float h, const float *tabs,
               const float *verts, const uint32_t *vert_ids, size_t nverts, const float *dirs,
               size_t nlobes, int paths, uint32_t seed, float *outT, float *outS, float *outG);

/* The same outputs computed by nthreads threads (lobe by lobe, the threads take chunks of voxels
 * and then of vertices from a shared counter; every output depends only on its own (vertex, lobe)
 * stream, so the result is identical for any count and any sharing). slc_march is this with one
 * thread. Needs 8 bytes of scratch per voxel. */
void slc_march_threads(const float *vox, const int n[3], const float lo[3], float h,
                       const float *tabs, const float *verts, const uint32_t *vert_ids,
                       size_t nverts, const float *dirs, size_t nlobes, int paths, uint32_t seed,
                       float *outT, float *outS, float *outG, int nthreads);

#endif
