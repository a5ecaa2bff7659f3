/* march_c.c: the C twin of kernels/march.cl: the same per-(vertex, lobe) loop over
 * sl_march_vertex (kernels/march.h), with the per-voxel event probabilities precomputed per lobe,
 * and threads that take voxels and vertices in chunks from a shared counter (sl_parallel_for). */
#include "march_c.h"

#include "march.h"
#include "base/parallel.h"

#include <stdlib.h>

/* Chunks of the dynamic sharing: a vertex (16 paths of up to ~200 steps) costs ~10-50 us, so 8
 * of them amortise the counter and stay small against a lobe's ~1800 vertices (a thread that
 * finishes last waits at most one chunk); a voxel's probability is one exp. */
#define VERT_CHUNK 8
#define VOX_CHUNK 2048

/* One lobe's work: the event probabilities of the filled voxels, then the vertices. */
typedef struct mlobe {
    const float *vox;
    const int *n;
    const float *lo;
    float h;
    const float *tabs, *verts;
    const uint32_t *vert_ids;
    const uint32_t *filled; /* the voxels with sigma > 0 */
    const float *w;
    sl_uint lobe;
    int paths;
    uint32_t seed;
    float *ptab, *outT, *outS, *outG; /* out*: this lobe's block (nverts * SL_MARCH_CH) */
} mlobe;

/* Filled voxels begin .. end - 1 (of the list): their event probability toward the lobe. */
static void ptab_chunk(void *arg, size_t begin, size_t end, int worker) {
    (void)worker;
    const mlobe *j = arg;
    const float delta = 0.5f * j->h; /* as sl_march_path */
    for (size_t i = begin; i < end; i++) {
        const uint32_t v = j->filled[i];
        j->ptab[v] = sl_march_event_p(j->vox + (size_t)v * SL_VOX_FIELDS, j->w, delta);
    }
}

/* Vertices begin .. end - 1: each writes only its own outputs, so which thread runs it does
 * not matter. */
static void vert_chunk(void *arg, size_t begin, size_t end, int worker) {
    (void)worker;
    const mlobe *j = arg;
    for (size_t v = begin; v < end; v++)
        sl_march_vertex(j->vox, j->n[0], j->n[1], j->n[2], j->lo, j->h, j->tabs, j->verts + 3 * v,
                        j->w, j->seed, j->vert_ids[v], j->lobe, j->paths, j->ptab,
                        j->outT + v * SL_MARCH_CH, j->outS + v * SL_MARCH_CH,
                        j->outG + v * SL_MARCH_CH);
}

/* Lobe by lobe: the lobe's event probability of every filled voxel (one exp per voxel instead of
 * one per path step through it; the same float expression, so the same events as the kernel's
 * inline one; empty voxels keep the 0 of the calloc), then its vertices. The work of a vertex
 * varies with how much hair lies toward the lobe, so the threads share both loops dynamically
 * (a static split of the vertices left one of two threads idle for much of each lobe). */
void slc_march_threads(const float *vox, const int n[3], const float lo[3], float h,
                       const float *tabs, const float *verts, const uint32_t *vert_ids,
                       size_t nverts, const float *dirs, size_t nlobes, int paths, uint32_t seed,
                       float *outT, float *outS, float *outG, int nthreads) {
    if (nverts == 0 || nlobes == 0) return;
    const size_t nvox = (size_t)n[0] * n[1] * n[2];
    if (nthreads < 1) nthreads = 1;
    float *ptab = calloc(nvox ? nvox : 1, sizeof *ptab);
    uint32_t *filled = malloc((nvox ? nvox : 1) * sizeof *filled);
    if (!ptab || !filled) abort();
    size_t nfilled = 0;
    for (size_t v = 0; v < nvox; v++)
        if (vox[v * SL_VOX_FIELDS + SL_VOX_SIGMA] > 0.0f) filled[nfilled++] = (uint32_t)v;
    for (size_t l = 0; l < nlobes; l++) {
        mlobe job = {vox,
                     n,
                     lo,
                     h,
                     tabs,
                     verts,
                     vert_ids,
                     filled,
                     dirs + 3 * l,
                     (sl_uint)l,
                     paths,
                     seed,
                     ptab,
                     outT + l * nverts * SL_MARCH_CH,
                     outS + l * nverts * SL_MARCH_CH,
                     outG + l * nverts * SL_MARCH_CH};
        sl_parallel_for(nthreads, nfilled, VOX_CHUNK, ptab_chunk, &job);
        sl_parallel_for(nthreads, nverts, VERT_CHUNK, vert_chunk, &job);
    }
    free(filled);
    free(ptab);
}

void slc_march(const float *vox, const int n[3], const float lo[3], float h, const float *tabs,
               const float *verts, const uint32_t *vert_ids, size_t nverts, const float *dirs,
               size_t nlobes, int paths, uint32_t seed, float *outT, float *outS, float *outG) {
    slc_march_threads(vox, n, lo, h, tabs, verts, vert_ids, nverts, dirs, nlobes, paths, seed, outT,
                      outS, outG, 1);
}
