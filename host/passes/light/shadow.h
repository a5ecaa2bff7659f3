/* shadow.h: the light pass of self-shadowing (Ren 2010 Sec. 5; numerics.md sec. 7): for one SRBF
 * lobe, an orthographic light view along the lobe centre, the hair rasterized into a deep opacity
 * depth map (first depth z0 + K layers of optical depth = projected fiber area per unit area),
 * exact summed-area tables of every layer, and the convolution-optical-depth lookup that gives
 * the effective transmittance T_j(x) = exp(-tau) at any world point.
 *
 *   sl_shadow_opts o; sl_shadow_opts_default(&o);
 *   sl_dodm m;
 *   if (sl_shadow_build(&dev, hair, lobe_dir, lobe_lambda, &o, &m, &e)) ...;
 *   sl_shadow_lookup(&dev, &m, n, xyz, T, &e);        // n world points -> T
 *   sl_dodm_free(&m);
 *
 * Both run on the device (OpenCL kernels raster.cl, dodm.cl) or the C twins, with the usual
 * fallback under `auto` (docs/opencl.md). docs/shadow.md has the details and measured errors.
 *
 * Many lobes (the renderer): one build for all of them, SL_SHADOW_BATCH lobes per kernel launch
 * (Ren 2010 Sec. 5), the hair uploaded once and projected on the device, the maps left where
 * they were built (device memory, or host memory on the C path) for the lookups:
 *
 *   sl_shadow_batch b;
 *   if (sl_shadow_build_batch(&dev, hair, nlobes, dirs, lambdas, &o, &b, &e)) ...;
 *   sl_shadow_batch_lookup(&b, n, xyz, NULL, T, &e);  // T[i * nlobes + j]: every lobe
 *   sl_shadow_batch_lookup(&b, n, xyz, lobe, T, &e);  // T[i]: point i toward lobe[i]
 *   sl_shadow_batch_free(&b); */
#ifndef SL_SHADOW_H
#define SL_SHADOW_H

#include "cl/clrt.h"
#include "io/hair/hair.h"

#include <stdint.h>

#define SL_SHADOW_DEFAULT_SIZE 512
#define SL_SHADOW_DEFAULT_LAYERS 4
#define SL_SHADOW_MAX_LAYERS 64
#define SL_SHADOW_MAX_SIZE 8192
/* SRBF support threshold (Ren 2010 Sec. 5): G(alpha) = this defines the support angle alpha. */
#define SL_SHADOW_SUPPORT_G 1e-3
/* ... and at most this wide (degrees): wider boxes average the whole map (see shadow.c) */
#define SL_SHADOW_SUPPORT_MAX_DEG 30.0
/* Lobes rasterized per kernel launch (Ren 2010 uses 16). */
#define SL_SHADOW_BATCH 16
/* Most C-path threads of one build (sl_shadow_opts.threads). */
#define SL_SHADOW_MAX_THREADS 16
/* Automatic first-depth window (sl_shadow_opts.z0_radius = 0): the min filter of z0 spans about
 * this many fiber widths (2 r / kappa), so a texel's layers start where the first of the fibers
 * over that window lies; the optical depth missed above the layers is ~1 / (this + 1)
 * (docs/shadow.md). Capped at SL_SHADOW_Z0_MAX_RADIUS texels. */
#define SL_SHADOW_Z0_FIBERS 30.0
#define SL_SHADOW_Z0_MAX_RADIUS 32
/* For points on the fibers themselves (the renderer's shading points): a window of 30 fibers
 * pulls a surface fiber's first depth forward to neighbours that do not shadow it (on
 * straight.hair an oblique lobe's T was 0.345x the traced value at 300 fiber points; with 3
 * fibers 0.85x, the narrow lobe 0.89x -> 1.05x, wavy hair 0.92-0.95x -> 0.98-1.03x). Points
 * between fibers (a slab's interior, eval transmittance) keep the 30 (docs/shadow.md). Wider
 * windows for shading points were measured in session 14 and not taken (docs/shadow.md, "A
 * window of constant width in fibers": the references disagree on the best width). */
#define SL_SHADOW_Z0_FIBERS_SHADING 3.0

typedef struct sl_shadow_opts {
    int size;     /* map width = height in texels */
    int layers;   /* K */
    double kappa; /* stochastic simplification: the fraction of strands kept, (0, 1] */
    uint32_t seed;
    /* Half-size (texels) of the min filter applied to the first-depth map z0 before the layers
     * are filled: 0 = automatic (SL_SHADOW_Z0_FIBERS), < 0 = none (Ren's per-texel z0). */
    int z0_radius;
    /* The automatic window's width in fibers (0: SL_SHADOW_Z0_FIBERS). The renderer, which looks
     * up only points on fibers, uses SL_SHADOW_Z0_FIBERS_SHADING (docs/shadow.md, "The window for
     * shading points"). */
    double z0_fibers;
    /* C path: threads rasterizing each map (segments split in contiguous ranges; the fixed-point
     * sums are exact, so the maps are the same for any count). 0 = every CPU (at most 16). */
    int threads;
} sl_shadow_opts;

/* An orthographic light view: world p -> (u, v) texels = ((p - origin).ex, (p - origin).ey) /
 * texel and depth z = (p - origin).ez (world units, ez = the direction light travels). */
typedef struct sl_light_view {
    double origin[3], ex[3], ey[3], ez[3];
    double texel;
    int w, h;
} sl_light_view;

typedef struct sl_dodm {
    sl_light_view view;
    unsigned K;
    float d;         /* first layer depth: boundaries z0 + k (k + 1) d / 2 */
    float rfac;      /* tan(alpha) / (2 texel): box half-size in texels per unit depth below z0 */
    float inv_scale; /* fixed point -> optical depth */
    double scale;
    int z0_radius;             /* the min filter used on z0 (texels; 0 = none) */
    float z0_frac;             /* and its fractional part (kernels/raster.h: sl_raster_z0_blend) */
    uint32_t *z0bits;          /* w * h */
    uint64_t *sat;             /* K * w * h */
    size_t segments, samples;  /* rasterized (after simplification); samples: C path only */
    double raster_s, tables_s; /* device or C time of the two steps */
} sl_dodm;

void sl_shadow_opts_default(sl_shadow_opts *o);

/* Support angle alpha of G(omega; xi, lambda) = exp(2 (cos - 1) / lambda^2): G(alpha) =
 * SL_SHADOW_SUPPORT_G; pi when the lobe is wider than that everywhere. */
double sl_shadow_lobe_support(double lambda);
/* The same capped at SL_SHADOW_SUPPORT_MAX_DEG: the lookup's filter support (broad lobes are
 * split into several maps instead, host/passes/light/shadow_split.h). */
double sl_shadow_support_angle(double lambda);

/* The view along light direction -dir (dir points toward the light) that covers the bounding
 * sphere of [lo, hi] grown by margin (world units), size x size texels. */
void sl_light_view_setup(sl_light_view *v, const double dir[3], const float lo[3],
                         const float hi[3], double margin, int size);
void sl_light_view_project(const sl_light_view *v, const double p[3], double uvz[3]);

/* Strand kept by stochastic simplification (Ren 2010 Sec. 7): a fixed random value per strand
 * from seed, kept when it is below kappa. */
int sl_shadow_strand_kept(uint32_t strand, uint32_t seed, double kappa);

/* Light pass for one lobe (dir: unit vector toward the light, lambda: its bandwidth). */
int sl_shadow_build(sl_device *dev, const sl_hair *h, const double dir[3], double lambda,
                    const sl_shadow_opts *o, sl_dodm *m, sl_err *e);
/* The light pass of n lobes as n separate maps in host memory, each equal bit for bit to
 * sl_shadow_build's for its lobe, built as one batch (sl_shadow_build_batch): the segments are
 * prepared once, and on the C path every thread takes whole lobes. maps: n, each freed with
 * sl_dodm_free (all zero after a failure). */
int sl_shadow_build_maps(sl_device *dev, const sl_hair *h, int n, const double *dirs,
                         const double *lambdas, const sl_shadow_opts *o, sl_dodm *maps, sl_err *e);
/* T at n world points (xyz: 3 n doubles). */
int sl_shadow_lookup(sl_device *dev, const sl_dodm *m, size_t n, const double *xyz, double *T,
                     sl_err *e);
/* T, and (B not NULL) the optical depth of the hair behind each point, seen from the map's light
 * (kernels/dodm.h: sl_dodm_tau_split): the number of fibers a light ray crosses after the point.
 * One lookup of the map per point for both. */
int sl_shadow_lookup_both(sl_device *dev, const sl_dodm *m, size_t n, const double *xyz, double *T,
                          double *B, sl_err *e);
/* sl_shadow_lookup_both's C path on the calling thread (no threads of its own), the same values:
 * for callers that look up many maps in parallel (host/plan/run_shade.c). */
void sl_shadow_lookup_both_serial(const sl_dodm *m, size_t n, const double *xyz, double *T,
                                  double *B);
void sl_dodm_free(sl_dodm *m);

typedef struct sl_shadow_group sl_shadow_group; /* one launch's lobes and maps (shadow.c) */

typedef struct sl_shadow_batch {
    int n;        /* lobes */
    sl_dodm *map; /* n descriptions (view, K, d, rfac, z0_radius, ...); their z0bits and sat are
                     NULL: the maps live in the groups (on the device when on_device) */
    int ngroups;
    sl_shadow_group *group;
    int on_device; /* built and looked up with the OpenCL kernels on cl */
    sl_cl *cl;
    /* device time (profiling events; wall time on the C path) of each step, all groups */
    double upload_s, project_s, raster_s, tables_s;
} sl_shadow_batch;

/* Light pass of n lobes: dirs (3 n doubles, unit vectors toward the light), lambdas (n). On
 * dev (OpenCL, or C; `auto` falls back to C as for sl_shadow_build). Every lobe's map equals the
 * one sl_shadow_build gives for it alone. */
int sl_shadow_build_batch(sl_device *dev, const sl_hair *h, int n, const double *dirs,
                          const double *lambdas, const sl_shadow_opts *o, sl_shadow_batch *b,
                          sl_err *e);
/* T at n world points (xyz: 3 n doubles), where the batch was built. lobe == NULL: toward every
 * lobe, T[i * b->n + j] (n * b->n values); else point i toward lobe[i] (0 .. b->n - 1), T[i]. */
int sl_shadow_batch_lookup(const sl_shadow_batch *b, size_t n, const double *xyz, const int *lobe,
                           double *T, sl_err *e);
/* Copies lobe j's maps to host memory: z0bits (w * h), sat (K * w * h) (tests, debugging). */
int sl_shadow_batch_read(const sl_shadow_batch *b, int j, uint32_t *z0bits, uint64_t *sat,
                         sl_err *e);
void sl_shadow_batch_free(sl_shadow_batch *b);

#endif
