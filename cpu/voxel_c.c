/* voxel_c.c: the C twin of kernels/voxel.cl: the same pieces (kernels/voxel.h) added with plain
 * 64-bit integer additions, so the sums equal the kernel's atomics bit for bit whenever the float
 * pieces do. */
#include "voxel_c.h"

#include "voxel.h"

#include <math.h>
#include <string.h>

void slc_voxel_accumulate(const float *segs, size_t nseg, const int n[3], const float lo[3],
                          float h, float scale, uint64_t *acc) {
    for (size_t g = 0; g < nseg; g++) {
        const float *seg = segs + g * SL_VOX_SEG;
        float dx = seg[4] - seg[0], dy = seg[5] - seg[1], dz = seg[6] - seg[2];
        int ns = sl_vox_pieces(sqrtf(dx * dx + dy * dy + dz * dz), h);
        for (int s = 0; s < ns; s++) {
            int v;
            float q[SL_VOX_ACC];
            sl_vox_piece(seg, s, ns, n[0], n[1], n[2], lo[0], lo[1], lo[2], h, scale, &v, q);
            if (v < 0) continue;
            for (int k = 0; k < SL_VOX_ACC; k++) {
                int64_t x = (int64_t)llrintf(q[k]);
                acc[(size_t)v * SL_VOX_ACC + k] += (uint64_t)x;
            }
        }
    }
}

void slc_voxel_finalize(const uint64_t *acc, size_t nvox, float h, float inv_scale, float *out) {
    for (size_t v = 0; v < nvox; v++) {
        float s[SL_VOX_ACC];
        for (int k = 0; k < SL_VOX_ACC; k++) {
            int64_t x;
            memcpy(&x, &acc[v * SL_VOX_ACC + k], sizeof x);
            s[k] = (float)x * inv_scale;
        }
        sl_vox_finalize(s, h, out + v * SL_VOX_FIELDS);
    }
}
