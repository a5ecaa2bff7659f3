/* marschner_sample.h: model marschner for fiber_bsdf.h. Its azimuthal factor N_t is a sum over
 * the roots of Phi(p, h) = phi (a delta in azimuth per h), so the fiber has no per-hit form: the
 * path tracer evaluates the width-averaged double f (marschner_ref.h) and samples a proposal:
 *   lobe t with probability w_t ~ the channel mean of A_t(h = 0) at theta_d = theta_o (floored
 *     at 5 % of the largest: no lobe is starved when the fiber is dark);
 *   theta_h = (theta_i + theta_o) / 2 from M_t, the Gaussian of mean alpha_t and std beta_t /
 *     sqrt(2), restricted to |theta_i| < pi/2 (rejection; its in-range mass Z_t enters the pdf);
 *   phi = phi_o - phi_i from (1 - k_t) uniform + k_t von Mises(mean pi, kappa 4): TT is peaked
 *     around the forward direction phi = pi (k_TT = 0.75), R and TRT are broad (k = 0).
 * pdf = sum_t w_t M_t(theta_h) / (2 Z_t) p_t(phi) / cos theta_i (solid angle; theta_i =
 * 2 theta_h - theta_o halves the density). The true f / pdf weighs every sample. */
#ifndef SL_MARSCHNER_SAMPLE_H
#define SL_MARSCHNER_SAMPLE_H

#include "fiber_bsdf.h"

void slref_marschner_bsdf_init(slref_bsdf *b);
void slref_marschner_bsdf_eval(const slref_bsdf *b, double theta_i, double phi_i, double f[3],
                               double lobes[SLREF_NLOBES][3]);
double slref_marschner_bsdf_pdf(const slref_bsdf *b, double theta_i, double phi_i);
int slref_marschner_bsdf_sample(const slref_bsdf *b, slref_rng *r, double *theta_i, double *phi_i);

/* The von Mises density of concentration kappa around mu, and a sample of it (Best and Fisher
 * 1979, rejection), in (-pi, pi]. */
double slref_von_mises_pdf(double x, double mu, double kappa);
double slref_von_mises_sample(slref_rng *r, double mu, double kappa);

#endif
