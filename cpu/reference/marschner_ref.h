/* marschner_ref.h: the double-precision reference of the Marschner model as numerics.md sec. 3
 * defines it (Xu 2011 Eq. 6-10, eccentricity Eq. 24, TRT caustic convolution with a normalised
 * circular Gaussian of width w_c). Brute force and accurate (relative error <= 1e-6), not fast:
 * the TRT convolution is an adaptive Gauss-Kronrod integral over the offset h. */
#ifndef SL_MARSCHNER_REF_H
#define SL_MARSCHNER_REF_H

#include "scene/material.h"

/* out = f_R, f_TT, f_TRT, f for colour channel ch (sigma_a[ch]); angles in the fiber frame
 * (numerics.md sec. 1). Never NaN/Inf for inputs in range. */
void slref_marschner_scatter(const sl_material *m, int ch, double theta_i, double phi_i,
                             double theta_o, double phi_o, double out[4]);

/* The pieces, exposed for tests and for the SRBF exact integral. */

/* Every root h of Phi(p, h) = phi (mod 2 pi) on |h| <= min(1, eta'), ascending; returns the
 * count (<= max). Roots are accurate to ~1e-14 in Phi. */
int slref_marschner_roots(int p, double etap, double phi, double *h, int max);

/* A_t(h) for mode t (0 R, 1 TT, 2 TRT) with index eta_t (eta, or eta* for TRT) at theta_d. */
double slref_marschner_A(const sl_material *m, int ch, int t, double eta_t, double theta_d,
                         double h);

/* N_t(phi) at theta_d: the root sum for R and TT, the w_c-convolved root sum for TRT.
 * eta_t is the index used (eta, or eta* for an eccentric TRT). */
double slref_marschner_N(const sl_material *m, int ch, int t, double eta_t, double theta_d,
                         double phi);

/* M_t(theta_h) = exp(-(theta_h - alpha_t)^2 / beta_t^2) / (sqrt(pi) beta_t). */
double slref_marschner_M(const sl_material *m, int t, double theta_h);

/* The index TRT uses for this query: eta* of Xu Eq. 24 from phi_o + phi_i (eta when a = 1). */
double slref_marschner_eta_trt(const sl_material *m, double phi_i, double phi_o);

/* e^-x I0(x) for x >= 0 (series below 25, asymptotic expansion above; relative error ~1e-15). */
double slref_i0e(double x);

#endif
