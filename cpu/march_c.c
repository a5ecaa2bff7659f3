/* march_c.c: the C twin of kernels/march.cl: the same per-(vertex, lobe) loop over
 * sl_march_vertex (kernels/march.h), with the per-voxel event probabilities precomputed per lobe
 * and threads over voxels and vertices. */
#include "march_c.h"

#include "march.h"
#include "base/parallel.h"

#include <stdlib.h>

/* One thread's share of one lobe: the event probabilities of voxels a0 .. a1 - 1 (step 0), or
 * the vertices v0 .. v1 - 1 (step 1). */
typedef struct mjob {
    int step;
    const float *vox;
    const int *n;
    const float *lo;
    float h;
    const float *tabs, *verts;
    const uint32_t *vert_ids;
    size_t nverts, lobe;
    const float *w;
    int paths;
    uint32_t seed;
    float *ptab, *outT, *outS; /* outT, outS: this lobe's block (nverts * SL_MARCH_CH) */
    size_t a0, a1;
} mjob;

static void mjob_run(const mjob *j) {
    if (j->step == 0) {
        const float delta = 0.5f * j->h; /* as sl_march_path */
        for (size_t v = j->a0; v < j->a1; v++) {
            const float *vx = j->vox + v * SL_VOX_FIELDS;
            j->ptab[v] = vx[SL_VOX_SIGMA] > 0.0f ? sl_march_event_p(vx, j->w, delta) : 0.0f;
        }
        return;
    }
    for (size_t v = j->a0; v < j->a1; v++)
        sl_march_vertex(j->vox, j->n[0], j->n[1], j->n[2], j->lo, j->h, j->tabs, j->verts + 3 * v,
                        j->w, j->seed, j->vert_ids[v], (sl_uint)j->lobe, j->paths, j->ptab,
                        j->outT + v * SL_MARCH_CH, j->outS + v * SL_MARCH_CH);
}

static void mjob_part(void *arg, size_t begin, size_t end, int part) {
    (void)part;
    const mjob *job = arg;
    for (size_t t = begin; t < end; t++)
        mjob_run(&job[t]);
}

/* job[0 .. nt - 1], one a part (sl_parallel_parts): every output has one writer. */
static void mjobs_run(mjob *job, int nt) {
    sl_parallel_parts(nt, (size_t)nt, mjob_part, job);
}

/* Lobe by lobe: the lobe's event probability of every voxel (one exp per voxel instead of one per
 * path step through it; the same float expression, so the same events as the kernel's inline
 * one), then its vertices; threads split the voxels and the vertices into contiguous ranges. */
void slc_march_threads(const float *vox, const int n[3], const float lo[3], float h,
                       const float *tabs, const float *verts, const uint32_t *vert_ids,
                       size_t nverts, const float *dirs, size_t nlobes, int paths, uint32_t seed,
                       float *outT, float *outS, int nthreads) {
    enum { MAXT = 16 };
    if (nverts == 0 || nlobes == 0) return;
    const size_t nvox = (size_t)n[0] * n[1] * n[2];
    if (nthreads > MAXT) nthreads = MAXT;
    if ((size_t)nthreads > nverts) nthreads = (int)nverts;
    if (nthreads < 1) nthreads = 1;
    float *ptab = malloc((nvox ? nvox : 1) * sizeof *ptab);
    if (!ptab) abort();
    mjob job[MAXT];
    for (size_t l = 0; l < nlobes; l++) {
        for (int t = 0; t < nthreads; t++) {
            job[t] = (mjob){0,
                            vox,
                            n,
                            lo,
                            h,
                            tabs,
                            verts,
                            vert_ids,
                            nverts,
                            l,
                            dirs + 3 * l,
                            paths,
                            seed,
                            ptab,
                            outT + l * nverts * SL_MARCH_CH,
                            outS + l * nverts * SL_MARCH_CH,
                            nvox * t / nthreads,
                            nvox * (t + 1) / nthreads};
        }
        mjobs_run(job, nthreads);
        for (int t = 0; t < nthreads; t++) {
            job[t].step = 1;
            job[t].a0 = nverts * t / nthreads;
            job[t].a1 = nverts * (t + 1) / nthreads;
        }
        mjobs_run(job, nthreads);
    }
    free(ptab);
}

void slc_march(const float *vox, const int n[3], const float lo[3], float h, const float *tabs,
               const float *verts, const uint32_t *vert_ids, size_t nverts, const float *dirs,
               size_t nlobes, int paths, uint32_t seed, float *outT, float *outS) {
    slc_march_threads(vox, n, lo, h, tabs, verts, vert_ids, nverts, dirs, nlobes, paths, seed, outT,
                      outS, 1);
}
