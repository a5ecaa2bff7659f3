/* volume.h: the hair volume passes of multiple scattering (issue 8; Ren 2010 Sec. 6, Xu 2011
 * Sec. 4.3/5): voxelization, the shadow-path march that gives the forward-scattering
 * transmittance T_f and spread sigma_f per lobe as 3-D textures, and their lookup. Each pass runs
 * on the OpenCL kernels (voxel.cl, march.cl) or the C twins with the usual fallback under `auto`
 * (docs/opencl.md). Definitions and measurements: docs/volume.md.
 *
 *   sl_voxel_grid g;
 *   if (sl_voxelize(&dev, &hair, scene->voxels, &g, &e)) ...;
 *   sl_dual_tables dt; sl_dual_tables_build(&material, &dt, &e); (host/passes/volume/dual.h)
 *   sl_march_opts mo; sl_march_opts_default(&mo);
 *   sl_ftex f;
 *   if (sl_march_build(&dev, &g, &dt, nlobes, dirs, &mo, &f, &e)) ...;      (dirs: 3 per lobe)
 *   float Tf[3], sf[3];
 *   sl_ftex_lookup(&f, lobe, p, Tf, sf);                 (trilinear; per colour channel)
 *   sl_ftex_free(&f); sl_voxel_grid_free(&g);
 *
 * The multiple-scattering response per fragment and lobe (Xu Eq. 27-31) is in
 * host/passes/volume/volume_ms.h. */
#ifndef SL_VOLUME_H
#define SL_VOLUME_H

#include "cl/clrt.h"
#include "passes/volume/dual.h"
#include "io/hair/hair.h"
#include "march.h" /* sl_ftex_corners */

#include <math.h>
#include <stdint.h>

typedef struct sl_voxel_grid {
    int n[3];       /* voxels per axis */
    float lo[3], h; /* corner and edge (world units) */
    float *vox;     /* SL_VOX_FIELDS floats per voxel (kernels/voxel.h); x fastest */
    size_t segments;
    double seconds; /* C time or device time of the two passes */
} sl_voxel_grid;

/* Grid layout for hair (no allocation): the bounding box grown by the largest radius plus 1e-3 of
 * its largest extent, `voxels` cells along the longest axis (cubic cells; the other axes get
 * ceil(extent / h)); voxels < 1 means 64. Empty hair: one unit cell at the origin. */
void sl_voxel_grid_layout(const sl_hair *hair, int voxels, sl_voxel_grid *g);
/* Segment records (SL_VOX_SEG floats each: p0, r0, p1, r1) of every strand; *nseg gets their
 * number. Free with free(). */
float *sl_voxel_segments(const sl_hair *hair, size_t *nseg);
/* The fixed-point scale of the accumulation (a power of two keeping every sum below 2^61). */
float sl_voxel_scale(const float *segs, size_t nseg);
/* Largest grid (voxels): the passes need 88 bytes per voxel (64-bit sums + the fields). */
#define SL_VOXEL_MAX (1 << 25)
/* Both passes on given segments into a laid-out grid g (allocates g->vox; a grid over
 * SL_VOXEL_MAX voxels is an error naming quality.voxels). */
int sl_voxelize_segments(sl_device *dev, const float *segs, size_t nseg, sl_voxel_grid *g,
                         sl_err *e);
/* Layout + segments + both passes. */
int sl_voxelize(sl_device *dev, const sl_hair *hair, int voxels, sl_voxel_grid *g, sl_err *e);
void sl_voxel_grid_free(sl_voxel_grid *g);

typedef struct sl_march_opts {
    int coarse;    /* voxels per coarse cell (Ren: 4) */
    int paths;     /* shadow paths per vertex and lobe */
    uint32_t seed; /* random streams: hash of (seed, vertex, lobe, path, step) */
    int threads;   /* C path threads; 0 = every CPU (the textures do not depend on it) */
} sl_march_opts;
void sl_march_opts_default(sl_march_opts *o); /* coarse 4, paths 16, seed 1, threads 0 */

/* Per-lobe 3-D textures of T_f and sigma_f (SL_MARCH_CH = 3 channels per vertex; a material with
 * one channel has three equal ones). Vertices m[0] x m[1] x m[2] at lo + k H (x fastest);
 * vertices with no hair within one coarse cell are not marched and hold T_f = 1, sigma_f = 0. */
typedef struct sl_ftex {
    int m[3];
    float lo[3], H;
    int nlobes;
    size_t active;    /* vertices marched (per lobe) */
    float *T, *sigma; /* nlobes * m[0] m[1] m[2] * SL_MARCH_CH each */
    float *tilt2;     /* the same: the fibers' tilt the light crossed (kernels/march.h) */
    float *dev2;      /* m[0] m[1] m[2] * SL_MARCH_CH (equal): the fibers' dev^2 near the vertex */
    float *logT;      /* ln(max(T, 1e-30)) per texel (sl_ftex_lookup's log-space T_f), or NULL */
    /* nlobes * m[0] m[1] m[2]: the deep opacity maps' optical depth -ln T_j at each vertex, or
     * NULL (sl_ftex_set_tau; the depth-guided lookup, sl_ftex_lookup_guided) */
    float *tau;
    double seconds; /* C time or device time of the march */
} sl_ftex;

/* Marches every active vertex toward each of nlobes lobe centres (dirs: 3 doubles per lobe,
 * unit, toward the light). */
int sl_march_build(sl_device *dev, const sl_voxel_grid *g, const sl_dual_tables *dt, int nlobes,
                   const double *dirs, const sl_march_opts *o, sl_ftex *f, sl_err *e);
/* T_f and sigma_f (3 channels each) of lobe at world point p (clamped to the grid): trilinear,
 * T_f in log space (kernels/march.h sl_ftex_sample). */
void sl_ftex_lookup(const sl_ftex *f, int lobe, const double p[3], float T[3], float sigma[3]);
/* The same in two steps: where p reads (the same for every lobe), then lobe's values there. */
void sl_ftex_at(const sl_ftex *f, const double p[3], sl_ftex_corners *cn);
void sl_ftex_lookup_at(const sl_ftex *f, int lobe, const sl_ftex_corners *cn, float T[3],
                       float sigma[3]);
/* At the same corners: lobe's tilt2 (per channel), and the fibers' spread dev^2 around the point
 * (lobe-independent; three equal values), both trilinear. */
void sl_ftex_tilt_at(const sl_ftex *f, int lobe, const sl_ftex_corners *cn, float tilt2[3]);
void sl_ftex_dev2_at(const sl_ftex *f, const sl_ftex_corners *cn, float dev2[3]);
/* T_f of lobe at the corners cn of a point whose own optical depth toward the lobe (the deep
 * opacity maps' -ln T_j, the same maps as sl_ftex_set_tau's) is tau_p, guided by that depth:
 *     ln T_f(p) = tau_p k,   k = sum_v w_v ln T_f(v) / sum_v w_v tau_v,   clamped to [-1, 0]
 * (k is the log attenuation per unit optical depth, -(1 - a_f) for Poisson crossings of fibers
 * of forward albedo a_f: a property of the material and the fibers' angles, smooth in space,
 * while T_f itself falls exponentially with depth). Vertices 4 voxels apart straddle the hair's
 * surface, where the visible fibers are: interpolating ln T_f there gives a lit surface the
 * T_f of the hair under it (docs/volume.md "Depth-guided T_f"). Where the corners hold almost
 * no depth (sum w tau < SL_FTEX_TAU_MIN) or f->tau is NULL: sl_ftex_lookup_at's T_f. sigma_f as
 * sl_ftex_lookup_at. */
#define SL_FTEX_TAU_MIN 0.1f
/* The optical depth -ln T of a transmittance (69, T ~ 1e-30, below that): tau_p of
 * sl_ftex_lookup_guided and the vertices' depths of sl_ftex_set_tau, one conversion for both. */
static inline float sl_ftex_tau_of(float T) {
    return T > 1e-30f ? -logf(T) : 69.0f;
}
void sl_ftex_lookup_guided(const sl_ftex *f, int lobe, const sl_ftex_corners *cn, float tau_p,
                           float T[3], float sigma[3]);
/* Sets f->tau (replacing any): tau[lobe nvert + v] for every vertex v, from T_j (nlobes x nvert,
 * the deep opacity maps' transmittance at the vertices lo + k H). The vertices not marched (their
 * T_f = 1 is a placeholder) are never corners of a point in the hair: every corner of a cell
 * with hair is marched (active_vertices). */
void sl_ftex_set_tau(sl_ftex *f, const float *Tj);
/* The vertex positions (3 doubles each, m[0] m[1] m[2] of them, x fastest), allocated. */
double *sl_ftex_vertex_positions(const sl_ftex *f);
void sl_ftex_free(sl_ftex *f);

#endif
