/* lobe_subdivide.h: the broad SRBF lobes replaced, together, by narrower sub-lobes on one fixed
 * direction set (docs/shadow.md, "Broad lobes").
 *
 * The fast path shades lobe j as T_j x I_j(omega_o) (Ren 2010 / Xu 2011 factorisation). For a
 * broad lobe (lambda above ~0.3) that loses the correlation between the fiber function and the
 * transmittance across the lobe (TT comes from behind the fiber, through the head, where T ~ 0).
 * Here the sum of the broad lobes, per channel
 *   L_k(w) = sum_b rgb_b,k G(w; xi_b, lambda_b) ~= sum_s c_s,k G(w; d_s, lambda'),  c_s,k >= 0
 * (numerics.md sec. 4: G = exp(2 (w.xi - 1) / lambda^2)) is fitted as one function, and each
 * sub-lobe is shaded with its own transmittance and closed-form response. Why one function:
 * the fit then depends only on the light, not on how it was cut into lobes (one broad lobe and
 * two halves of it give the same sub-lobes, so the same image: issue 19's lobe-cut check).
 * Directions d_s: a spherical Fibonacci set of M points with its poles on the world's +-Y (the
 * same set for every light), kept where the broad light's rgb sum is >= SL_SUBDIV_CUT x its
 * largest value at a lobe axis (M the largest whose kept count fits the budget); lambda' =
 * SL_SUBDIV_RATIO x the set's spacing sqrt(4 pi / M); c_s,k by non-negative least squares
 * (Lawson-Hanson) per channel on equal-area sphere samples, in double, then scaled so each
 * channel's total power (integral of L_k) is exactly the lobes'. */
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
/* directions where the broad light is below this share of its peak are not used */
#define SL_SUBDIV_CUT 0.02
/* equal-area sphere samples of the least-squares fit (at least 8 per set direction) */
#define SL_SUBDIV_SAMPLES 4096
/* at most this many sub-lobes in all; fewer than SL_SUBDIV_MIN directions: nothing subdivided */
#define SL_SUBDIV_MAX 64
#define SL_SUBDIV_MIN 4
/* the sub-lobes' width: the set is fine enough that SL_SUBDIV_RATIO sqrt(4 pi / M) <= this, so a
 * broad light gets as many sub-lobes as its extent needs (the whole sphere: 35 at 0.3), whatever
 * the budget (`quality.sublobe_width`, docs/formats.md). Before (the set as large as a budget of 2
 * x (narrow lobes + 1), at least 12, allowed) a light of many broad lobes could get too few
 * sub-lobes for its lobes, which then stayed whole (SL_SUBDIV_MAX_WIDTH): the 24 lobes fitted to a
 * white map (lambda 0.54-1.0) kept one map each and single scattering in the white furnace came
 * out 1.68x the traced shadows' (docs/shadow.md, "Broad lobes"). Measured there: width 0.3, 1.05x;
 * 0.25, 1.03x (the default scene's frame 1.5x and 1.8x of before: more lobes to shade). */
#define SL_SUBDIV_WIDTH 0.3
/* the finest width quality.sublobe_width may ask (its set: SL_SUBDIV_SET_MAX directions) */
#define SL_SUBDIV_WIDTH_MIN 0.25
/* a broad lobe stays whole when the sub-lobes would be wider than this share of it */
#define SL_SUBDIV_MAX_WIDTH 0.8
/* the most sub-lobes SL_SUBDIV_WIDTH_MIN gives, ceil(4 pi (SL_SUBDIV_RATIO / 0.25)^2) (a broad
 * light over the whole sphere); the renderer's budget is the narrow lobes plus
 * sl_subdiv_set_size (host/plan/plan_lobes.c), so the sub-lobes depend only on the light */
#define SL_SUBDIV_SET_MAX 51

typedef struct sl_subdiv_params {
    double lambda_min; /* SL_SUBDIV_LAMBDA_MIN */
    double ratio;      /* SL_SUBDIV_RATIO */
    double cut;        /* SL_SUBDIV_CUT */
    int samples;       /* SL_SUBDIV_SAMPLES */
    double width;      /* SL_SUBDIV_WIDTH */
} sl_subdiv_params;
void sl_subdiv_params_default(sl_subdiv_params *p);
/* The set size of p's width, ceil(4 pi (ratio / width)^2), at most SL_SUBDIV_MAX: the sub-lobes
 * of a broad light over the whole sphere. */
int sl_subdiv_set_size(const sl_subdiv_params *p);
/* The renderer's budget of lobes after subdivision: narrow lobes (kept whole) plus the sub-lobes
 * of width (quality.sublobe_width) over the whole sphere. host/plan/plan_lobes.c subdivides within
 * it and sl_frame_estimate (host/plan/frame.c) sizes the frame's maps by it, so the two agree. */
int sl_subdiv_budget(int narrow, double width);

/* The renderer's use: the lobes in[idx[0..n-1]] into out (allocated; free with sl_lobes_free):
 * the lobes kept whole first, in input order (bit for bit), then the sub-lobes of the broad
 * ones, with out->count <= max(budget, n). Broad: lambda > p->lambda_min and lambda' <=
 * SL_SUBDIV_MAX_WIDTH x lambda. p may be NULL (defaults). *nbroad, *nsub: lobes replaced and
 * the sub-lobes they became (0, 0 when nothing was subdivided: out is then the input list).
 * *rel_l2 (may be NULL): the fit's relative L2 error over the sphere samples, the three
 * channels together (0 when nothing was subdivided). */
void sl_lobes_subdivide(const sl_lobes *in, const int *idx, int n, int budget,
                        const sl_subdiv_params *p, sl_lobes *out, int *nbroad, int *nsub,
                        double *rel_l2);

#endif
