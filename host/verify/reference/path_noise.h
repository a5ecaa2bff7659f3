/* path_noise.h: a path-traced image's own noise, from its two half-sample images (the even and
 * the odd samples of every pixel: independent estimates of the same image). With A, B the two
 * half means (n_e, n_o samples) and F the full mean, E (A - B)^2 = s^2 (1/n_e + 1/n_o) and
 * Var F = s^2 / n, so Var F = E (A - B)^2 n_e n_o / n^2 (a quarter of it for equal halves):
 *
 *   noise = mean over r, g, b of sqrt( sum_i (A_i - B_i)^2 n_e n_o / n^2 / sum_i F_i^2 )
 *
 * over hair pixels (F's coverage > 0): the expected numerics.md sec. 6 rel. RMSE of F against
 * the converged image. On b x b blocks (block means of A, B, F, partial blocks at the edges
 * included) it measures the noise of a comparison at that scale (sl_image_error_blocks). */
#ifndef SL_PATH_NOISE_H
#define SL_PATH_NOISE_H

#include "path_ref.h"

/* NaN when either half is empty (fewer than 2 samples) or no pixel is hair. */
double sl_path_noise(const slref_path_accum *a, int block);

#endif
