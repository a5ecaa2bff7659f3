/* path_ref.h: the unbiased path tracer through the actual fibers (docs/reference.md, "Path
 * tracer"; `strandlight reference --path`), in double:
 *   camera rays through uniformly jittered positions in the pixel (box filter; the camera of
 *   scene/camera.h, as slref_render); the closest hit on the fibers (raytrace_ref.h: round
 *   linear curves of the scene radius); at each hit the offset h (fiber_hit.h) and the frame
 *   (slref_fiber_frame); the fiber sampled and evaluated per hit (fiber_bsdf.h);
 *   every event: a light sample from the map (env_ref.h) with a shadow ray through the fibers
 *   (opaque) and a fiber sample whose continuation ray finds the next fiber or leaves to the
 *   map, the two combined by multiple importance sampling (power heuristic); continuation and
 *   shadow rays skip the own fiber's segments (the segment and its two neighbours) and count
 *   only hits where they enter a fiber (a ray starting inside an interpenetrating fiber leaves
 *   it unhindered, raytrace_ref.h);
 *   Russian roulette from SLREF_PATH_RR_EVENTS events on with survival min(1, max_c beta_c)
 *   (beta /= survival: unbiased), and a safety cap of SLREF_PATH_MAX_EVENTS events (a path
 *   reaching it is cut and counted, the only bias).
 * Random numbers: one counter-based stream per (seed, pixel, sample) (path_rng.h), so the image
 * is the same for any thread count. */
#ifndef SL_PATH_REF_H
#define SL_PATH_REF_H

#include "env_ref.h"
#include "raytrace_ref.h"
#include "scene/camera.h"
#include "scene/material.h"

#include <signal.h>
#include <stdint.h>

#define SLREF_PATH_MAX_EVENTS 4096
#define SLREF_PATH_RR_EVENTS 3

typedef struct slref_path_ctx {
    const slref_rt *rt;
    const sl_material *m;
    /* per-strand sigma_a (3 per strand, material.strand_sigma_a) replacing m's at every event
     * on that strand, or NULL */
    const float *strand_sa;
    const slref_env *env;
    const sl_camera *cam;
    uint64_t seed;
    int max_events; /* SLREF_PATH_MAX_EVENTS */
    int rr_events;  /* SLREF_PATH_RR_EVENTS */
} slref_path_ctx;

/* One camera path. Radiance is split by how often the light scattered (direct: once; indirect:
 * more) and by the lobe of the first event (R, TT, TRT, rest; fiber_bsdf.h): the light sample
 * there by the lobes' own f_p, everything after the fiber sample by f_p / f of the sampled
 * direction, so each split is an unbiased estimate of its part and the parts sum to rgb. */
typedef struct slref_path_out {
    int hit;  /* the camera ray met a fiber (coverage) */
    double z; /* its view depth along the camera's fwd (+inf: none) */
    double rgb[3], direct[3], indirect[3], lobes[4][3];
    int events; /* scattering events */
    int capped; /* 1: cut at max_events */
} slref_path_out;

void slref_path_trace(const slref_path_ctx *c, int px, int py, uint32_t sample, slref_path_out *o);

enum { SLREF_PATH_AOV = 18 }; /* direct 3, indirect 3, lobes 4 x 3 */

/* Per-pixel sums over the samples done, in sample order (so the same for any thread count). */
typedef struct slref_path_accum {
    int w, h;
    uint32_t n[2];        /* samples summed into half[0] (even samples) and half[1] (odd) */
    double *half[2];      /* 4 per pixel: rgb and coverage sums of the even / odd samples */
    double *aov;          /* SLREF_PATH_AOV sums per pixel */
    float *depth;         /* nearest view depth, +inf where no ray hit */
    long long *row_stats; /* 3 per row: paths, scattering events, capped paths */
} slref_path_accum;

void slref_path_accum_init(slref_path_accum *a, int w, int h);
void slref_path_accum_free(slref_path_accum *a);

/* Adds sample `sample` (0, 1, 2, ... in order) of every pixel, rows on `threads` threads.
 * cancel (may be NULL): when it becomes non-zero the pass stops within a row and returns 1, the
 * sums then being incomplete; else 0. */
int slref_path_pass(const slref_path_ctx *c, slref_path_accum *a, uint32_t sample, int threads,
                    const volatile sig_atomic_t *cancel);

/* Totals of row_stats: paths traced, scattering events, paths cut at the cap. */
void slref_path_stats(const slref_path_accum *a, long long *paths, long long *events,
                      long long *capped);

#endif
