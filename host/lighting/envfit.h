/* envfit.h: fits SRBF lobes (numerics.md sec. 4) to an environment map, and measures errors.
 *
 * Method (docs/envfit.md has the details and measured figures):
 *  1. a solid-angle-weighted pyramid of the map (each coarser pixel is the solid-angle-weighted
 *     mean of its children, so radiant power is preserved at every level);
 *  2. greedy initialisation on the coarsest level: lobes are added one by one at the dictionary
 *     atom (pixel direction x bandwidth ladder) that best explains the current residual
 *     (matching pursuit with non-negative weights re-solved after each addition);
 *  3. coarse-to-fine bounded Levenberg-Marquardt over all directions, bandwidths and
 *     non-negative rgb weights: exact gradients of the pixel objective, Gauss-Newton matrix from
 *     the closed-form SRBF product integrals; the lower bandwidth bound follows the level's pixel
 *     size, so a sun thousands of times brighter than the sky narrows to its own lobe on the
 *     finest levels;
 *  4. errors on the full-resolution map: the solid-angle-weighted relative L2 of the radiance
 *     and of the map convolved with a fiber-like lobe.
 * Results are deterministic: threads split rows into fixed blocks reduced in a fixed order. */
#ifndef SL_ENVFIT_H
#define SL_ENVFIT_H

#include "io/envmap/envmap.h"
#include "lighting/lobes_json.h"

/* Most lobes `fit` will fit. The fit's cost grows about as n^3 (measured on data/env/city_256.hdr,
 * 2 cores: 64 lobes 3.9 s, 256 lobes 203 s, so 512 about 25 minutes and 1024 hours), and the frame
 * draws one deep opacity map per lobe; files with more lobes (up to SL_LOBES_MAX) still load. */
#define SL_FIT_LOBES_MAX 512
/* The fitter's revision: part of the fitted-lobes cache key (host/scene/env_lighting.c), so a
 * fit from an older fitter is not reused. 2: suns keep their exact power (envfit_sun.c). */
#define SL_ENVFIT_REVISION 2

typedef struct sl_envfit_settings {
    int lobes;           /* N >= 1; 0 = auto (grow until target_error is met) */
    double target_error; /* auto mode: stop when rel_l2 <= target_error */
    int max_lobes;       /* auto mode: upper bound on N */
    double lambda_min;   /* 0 = the finest level's pixel spacing (pi / height) */
    double lambda_max;   /* broadest lobe allowed */
    double effort;       /* multiplies iteration budgets, divides tolerances (1 = default) */
    int threads;         /* worker threads (results do not depend on it) */
    double conv_lambda;  /* lambda of the fiber-like lobe for the convolved error (radians) */
    int progress;        /* show a progress bar (sl_progress_*) */
    int verbose;         /* per-level figures on stderr */
} sl_envfit_settings;

void sl_envfit_default_settings(sl_envfit_settings *s);

typedef struct sl_envfit_report {
    double rel_l2;           /* solid-angle-weighted relative L2 of the radiance, full map */
    double lobe_conv_rel_l2; /* same for the map and the fit convolved with G(.; ., conv_lambda) */
    double time_s;           /* fitting time (errors included) */
    int iterations;          /* LM iterations over all levels */
    int levels;              /* pyramid levels used */
    int suns;                /* lobes given to suns (compact regions > 100x the mean) */
} sl_envfit_report;

/* Fits lobes to `map`. out->lobe gets s->lobes lobes (or the auto count), sorted by decreasing
 * power; out->fit_json is left NULL (the caller records settings). Returns 0 or -1 with e set. */
int sl_envfit(const sl_envmap *map, const sl_envfit_settings *s, sl_lobes *out,
              sl_envfit_report *rep, sl_err *e);

/* Solid-angle-weighted relative L2 error of the lobes against the map, over every pixel:
 * sqrt(sum_p Omega_p |L_p - M_p|^2 / sum_p Omega_p |L_p|^2), sums over the three channels.
 * A black map fitted by black lobes has error 0. */
double sl_envfit_rel_l2(const sl_envmap *map, const sl_lobe *lobes, int n, int threads);

/* The same error for the convolved quantity E(nu) = integral L(omega) G(omega; nu, conv_lambda)
 * on a grid of nu. Lobes with lambda == 0 are directional lights whose rgb is their power
 * (integral of radiance over solid angle): E(nu) = sum_i rgb_i G(omega_i; nu, conv_lambda). */
double sl_envfit_conv_rel_l2(const sl_envmap *map, const sl_lobe *lobes, int n, double conv_lambda,
                             int threads);

/* Writes original | reconstruction | |error| side by side (each w x h) to a PNG. */
int sl_envfit_preview(const char *path, const sl_envmap *map, const sl_lobe *lobes, int n,
                      double exposure, sl_err *e);

/* Evaluates sum_j rgb_j G(omega; dir_j, lambda_j) (lambda_j > 0 lobes only). */
void sl_lobes_eval(const sl_lobe *lobes, int n, const double omega[3], double rgb[3]);

#endif
