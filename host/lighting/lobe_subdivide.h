/* lobe_subdivide.h: a broad SRBF lobe replaced by narrower sub-lobes that sum to it
 * (docs/shadow.md, "Broad lobes").
 *
 * The fast path shades lobe j as T_j x I_j(omega_o) (Ren 2010 / Xu 2011 factorisation). For a
 * broad lobe (lambda above ~0.3) that loses the correlation between the fiber function and the
 * transmittance across the lobe (TT comes from behind the fiber, through the head, where T ~ 0).
 * Here such a lobe becomes
 *   G(w; xi, lambda) ~= sum_s c_s G(w; d_s, lambda'),  c_s >= 0,  rgb_s = c_s rgb
 * (numerics.md sec. 4: G = exp(2 (w.xi - 1) / lambda^2)), each sub-lobe shaded with its own
 * transmittance and closed-form response. Directions d_s: a spherical Fibonacci set of M points
 * with both poles on the lobe axis, kept where G(d_s) >= SL_SUBDIV_CUT (M the largest whose kept
 * count fits the allotment); lambda' = SL_SUBDIV_RATIO x the set's spacing sqrt(4 pi / M); c_s by
 * non-negative least squares (Lawson-Hanson) on SL_SUBDIV_SAMPLES equal-area sphere samples, in
 * double, then scaled so the total power (integral of G) is exactly the lobe's. */
#ifndef SL_LOBE_SUBDIVIDE_H
#define SL_LOBE_SUBDIVIDE_H

#include "lighting/lobes_json.h"

/* lobes with lambda above this are subdivided (the 1e-3 support then exceeds ~48 deg, past the
 * lookup's 30-degree cap: docs/shadow.md) */
#define SL_SUBDIV_LAMBDA_MIN 0.3
/* sub-lobe lambda' over the direction spacing sqrt(4 pi / M). Measured against the pixel
 * reference (docs/shadow.md, "Broad lobes"): 0.5 gives the lowest 4x4 image error of 0.5, 0.6,
 * 0.7 on all four test scenes; the fit's relative L2 is then 0.20-0.29 (0.4: 0.47) */
#define SL_SUBDIV_RATIO 0.5
/* directions where the lobe is below this share of its axis value are not used */
#define SL_SUBDIV_CUT 0.02
/* equal-area sphere samples of the least-squares fit */
#define SL_SUBDIV_SAMPLES 4096
/* at most this many sub-lobes per lobe, and a lobe allotted fewer than SL_SUBDIV_MIN stays whole */
#define SL_SUBDIV_MAX 16
#define SL_SUBDIV_MIN 4
/* a lobe is not subdivided when its sub-lobes would be wider than this share of it */
#define SL_SUBDIV_MAX_WIDTH 0.8
/* the renderer's budget of lobes after subdivision: SL_SHADOW_SPLIT_MAPS_PER_LOBE x the used
 * lobes (the split's map budget), at least this many (one broad lobe alone gets 12) */
#define SL_SUBDIV_MIN_BUDGET 12

typedef struct sl_subdiv_params {
    double lambda_min; /* SL_SUBDIV_LAMBDA_MIN */
    double ratio;      /* SL_SUBDIV_RATIO */
    double cut;        /* SL_SUBDIV_CUT */
    int samples;       /* SL_SUBDIV_SAMPLES */
} sl_subdiv_params;
void sl_subdiv_params_default(sl_subdiv_params *p);

/* Replaces lobe `in` by at most nmax sub-lobes written to out (room for min(nmax,
 * SL_SUBDIV_MAX)). Returns the count: 1 (out[0] = *in) when lambda <= lambda_min, fewer than
 * SL_SUBDIV_MIN directions fit, or the sub-lobes would be wider than SL_SUBDIV_MAX_WIDTH x
 * lambda. *rel_l2 (may be NULL): the fit's relative L2 error over the sphere samples (0 when
 * not subdivided). */
int sl_lobe_subdivide_one(const sl_lobe *in, int nmax, const sl_subdiv_params *p, sl_lobe *out,
                          double *rel_l2);

/* The renderer's use: the lobes in[idx[0..n-1]] into out (allocated; free with sl_lobes_free),
 * broad ones subdivided so that out->count <= max(budget, n). The extra lobes (budget - n) go
 * to the broad lobes in order of decreasing power (rgb sum x integral of G), each up to
 * SL_SUBDIV_MAX. parent (allocated, out->count entries; may be NULL): each output lobe's
 * position in idx. *nbroad, *nsub: lobes subdivided and the sub-lobes they became. */
void sl_lobes_subdivide(const sl_lobes *in, const int *idx, int n, int budget,
                        const sl_subdiv_params *p, sl_lobes *out, int **parent, int *nbroad,
                        int *nsub);

#endif
