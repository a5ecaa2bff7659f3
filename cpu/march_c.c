/* march_c.c: the C twin of kernels/march.cl: the same per-(vertex, lobe) loop over
 * sl_march_vertex (kernels/march.h). */
#include "march_c.h"

#include "march.h"

void slc_march(const float *vox, const int n[3], const float lo[3], float h, const float *tabs,
               const float *verts, const uint32_t *vert_ids, size_t nverts, const float *dirs,
               size_t nlobes, int paths, uint32_t seed, float *outT, float *outS) {
    for (size_t l = 0; l < nlobes; l++)
        for (size_t v = 0; v < nverts; v++) {
            size_t g = l * nverts + v;
            sl_march_vertex(vox, n[0], n[1], n[2], lo, h, tabs, verts + 3 * v, dirs + 3 * l, seed,
                            vert_ids[v], (sl_uint)l, paths, outT + g * SL_MARCH_CH,
                            outS + g * SL_MARCH_CH);
        }
}
