/* chiang_ref.h: the Chiang 2016 fiber (numerics.md sec. 3 "chiang"; pbrt-v4's HairBxDF) averaged
 * over the fiber's width, in double precision: the reference backend of `eval scatter` for model
 * chiang, and the pieces the furnace and SRBF references integrate (furnace_ref.c, srbf_ref.c).
 *
 *   f = sum_{p=0..2} M_p(v_p, theta_i, theta_o'_p) Nbar_p(phi) + M(v_2, theta_i, theta_o) E_3 / 2pi
 *   Nbar_p(phi) = 1/2 integral_{-1}^{1} A_p(h) N_p(phi, h) dh,   E_p = 1/2 integral A_p(h) dh
 *
 * (M_p, A_p and N_p at one h: chiang_hit.h). M_p does not depend on h, so it leaves the width
 * integral; A_p and N_p depend on theta_o and h only (pbrt evaluates Fresnel and eta' on the
 * outgoing side), never on theta_i. Nbar_p is integrated adaptively in gamma = asin(h) with
 * breakpoints wherever the logistic is centred, k s away from its centre (k up to 32) or at its
 * trimming kink (phi - Phi = +-pi), on every wrap, so arbitrarily small s is resolved. Relative
 * error <= 1e-6 (measured: docs/numerics-chiang.md). */
#ifndef SL_CHIANG_REF_H
#define SL_CHIANG_REF_H

#include "scene/material.h"

/* log M_p(theta_i, theta_o) of lobe p = 0, 1, 2 (theta_o shifted by -2 alpha[p], v_p =
 * beta[p]^2) and p = 3 (the rest: v_2, unshifted). Finite for every input. */
double slref_chiang_log_mp(const sl_material *m, int p, double theta_i, double theta_o);

/* Nbar_p(phi) for p = 0, 1, 2 at outgoing inclination theta_o, channel ch; phi any real. */
double slref_chiang_azimuthal(const sl_material *m, int ch, int p, double theta_o, double phi);

/* E_p = 1/2 integral_{-1}^{1} A_p(h) dh for p = 0..3 (3: sum_{p >= 3}), = integral of Nbar_p over
 * a period. With sigma_a = 0, E_0 + E_1 + E_2 + E_3 = 1. */
double slref_chiang_energy(const sl_material *m, int ch, int p, double theta_o);

/* The scattering function: out = f_0, f_1, f_2, f_rest, f (5 values). */
void slref_chiang_scatter(const sl_material *m, int ch, double theta_i, double phi_i,
                          double theta_o, double phi_o, double out[5]);

/* Breakpoints in gamma = asin(h) over [-pi/2, pi/2] (both ends included, sorted, malloc'd; *count
 * of them) for a width integral whose kernel is centred at Phi(p, gamma) = phi: the caustic of
 * p = 2, and where phi - Phi is 0, +-k width (k = 1/2 .. 32) or pi, on every wrap. */
double *slref_chiang_gamma_points(const sl_material *m, int p, double theta_o, double phi,
                                  double width, size_t *count);
/* Adaptive G7/K15 over [pts[0], pts[n-1]] split at every pts[i] (quad.h, in chunks of 60). */
double slref_chiang_integrate_pts(double (*f)(double, void *), void *ctx, const double *pts,
                                  size_t n, double rel, double abs_tol);

/* b_n = integral_{-pi}^{pi} L(x) cos(n x) dx for the logistic of scale s trimmed to (-pi, pi)
 * (b_0 = 1), in closed form: the untrimmed pi s n / sinh(pi s n) less the two tails, each a
 * geometric-type series in e^{-pi/s}. The SRBF reference convolves with it in Fourier space. */
double slref_trimmed_logistic_fourier(double s, int n);

#endif
