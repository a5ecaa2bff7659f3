/* deon_hit.h: d'Eon's fiber (numerics.md sec. 3 "deon") at ONE fiber offset h, for the path
 * tracer, and its importance sampling (fiber_bsdf.h):
 *
 *   f_h = sum_{p <= orders} M_p(beta_p^2, theta_i, theta_o - 2 alpha_p) A(p, h) D_{beta_p}(phi -
 *         Phi(p, h)) + M_TRT A_rest(h) / (2 pi)
 *
 * with A, Phi (through eta') at theta_d = (theta_o - theta_i) / 2 (deon_ref.h's functions) and
 * D the wrapped Gaussian detector. 1/2 integral over h in [-1, 1] of f_h is d'Eon's f exactly
 * (Eq. 10 is that integral; test path_deon_hit_average).
 *
 * Sampling, in two stages whose densities are both exact (so f / pdf is):
 *   longitudinal: one of the three M's (R, TT, and TRT's, which every order >= 2 and the rest
 *     share) with probabilities w_q from the channel mean of A at theta_d* = theta_o - alpha_q
 *     (the centre of that M: theta_i = -(theta_o - 2 alpha_q)), which depend on theta_o and h
 *     only; theta_i from M_q exactly (mp_sample.h). Density sum_q w_q M_q(theta_i).
 *   azimuthal, at the sampled theta_i (so theta_d is known): lobe p with probability c_p
 *     proportional to mean_c A(p, h, theta_d) M_p(theta_i), phi = Phi(p, h) + a Gaussian of
 *     std beta_p (wrapped: density D_beta_p), the rest uniform. Density sum_p c_p D_p(phi).
 * Then f / pdf = (f / f_mean) sum_p A_p M_p / sum_q w_q M_q: exactly 1 for a white fiber whose
 * orders share one lobe, and a smooth ratio otherwise (no azimuthal mismatch). Proposals that
 * fixed Phi at theta_d* instead gave weights of std ~0.7 at grazing angles, which a path
 * multiplies over its events (the dense white furnace fell 10 % short at 64 spp). */
#ifndef SL_DEON_HIT_H
#define SL_DEON_HIT_H

#include "fiber_bsdf.h"

/* f_h of channel ch (phi = phi_o - phi_i): out[p] for p = 0..orders, out[orders + 1] the rest
 * (out may be NULL); returns their sum. */
double slref_deon_hit_f(const sl_material *m, int ch, double h, double theta_i, double theta_o,
                        double phi, double *out);

void slref_deon_bsdf_init(slref_bsdf *b);
void slref_deon_bsdf_eval(const slref_bsdf *b, double theta_i, double phi_i, double f[3],
                          double lobes[SLREF_NLOBES][3]);
double slref_deon_bsdf_pdf(const slref_bsdf *b, double theta_i, double phi_i);
int slref_deon_bsdf_sample(const slref_bsdf *b, slref_rng *r, double *theta_i, double *phi_i);

#endif
