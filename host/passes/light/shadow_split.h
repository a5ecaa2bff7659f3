/* shadow_split.h: shadow directions of a broad SRBF lobe (docs/shadow.md, "Broad lobes").
 *
 * One deep opacity map looks along one direction; Ren 2010's convolution lookup widens the
 * filter box with the lobe's support, which works while the support is a cone of a few tens of
 * degrees. A broad lobe (lambda above ~0.3: an overcast sky, the ambient part of a fitted map)
 * sees the hair from every side, so its effective transmittance is split: T_j = sum_s w_s T_s
 * over directions d_s spread over the lobe, each with its own map and the capped support,
 * w_s proportional to G(d_s; xi_j, lambda_j) on equal-area cells. */
#ifndef SL_SHADOW_SPLIT_H
#define SL_SHADOW_SPLIT_H

#include "lighting/lobes_json.h"

/* Directions on the whole sphere before the cut (a spherical Fibonacci set with both poles on
 * the lobe axis): spacing ~sqrt(4 pi / 12) = 59 degrees, twice the capped 30-degree support. */
#define SL_SHADOW_SPLIT_N 12
/* Directions whose weight is below this share of the axis's are dropped (and the rest
 * renormalised). */
#define SL_SHADOW_SPLIT_CUT 0.05

/* Fills dirs (3 per direction, unit) and w (summing to 1) for the lobe (dir unit, toward the
 * light); returns the count, 1 (the lobe itself, w = 1) when its support fits the cap
 * (sl_shadow_support_angle uncapped <= SL_SHADOW_SUPPORT_MAX_DEG), at most SL_SHADOW_SPLIT_N. */
int sl_shadow_split(const double dir[3], double lambda, double *dirs, double *w);
/* The same, keeping at most max directions (those of largest weight, renormalised; max = 1:
 * the lobe's axis alone, the single capped map). */
int sl_shadow_split_max(const double dir[3], double lambda, int max, double *dirs, double *w);
/* The deep opacity maps of several lobes, the one expansion `eval transmittance`
 * (shadow_eval.c) and the renderer's light pass (frame.c) share: lobe j's maps are
 * first[j] .. first[j + 1] - 1, each with a direction, the lobe's lambda, its weight in the
 * lobe's T (T_j = sum w T_map) and its lobe j. */
typedef struct sl_shadow_maps {
    int n;
    double *dir;    /* 3 n, unit */
    double *lambda; /* n */
    double *w;      /* n */
    int *lobe;      /* n: the lobe's position in idx */
    int *first;     /* count + 1 */
} sl_shadow_maps;
/* The maps of lobes l->lobe[idx[0..count-1]]: lobe j gets sl_shadow_split_max(..., want[j])
 * directions, or every one (sl_shadow_split) when want is NULL. Free with sl_shadow_maps_free. */
void sl_shadow_maps_plan(const sl_lobes *l, const int *idx, int count, const int *want,
                         sl_shadow_maps *m);
void sl_shadow_maps_free(sl_shadow_maps *m);

/* The renderer's budget: at most this many maps per used lobe on average (frame.c gives the
 * extra maps to the broad lobes of largest power; sl_frame_estimate counts this many). */
#define SL_SHADOW_SPLIT_MAPS_PER_LOBE 2

#endif
