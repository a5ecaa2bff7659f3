/* deon_ref.h: the d'Eon 2011 energy-conserving fiber model in double precision, the reference
 * backend of `strandlight eval` (numerics.md sec. 3 "deon", sec. 5). Brute force where it matters:
 * N_p is integrated adaptively (quad.h) with breakpoints at every point where the detector
 * Gaussian is centred, so arbitrarily narrow roughness is resolved. Slow; not for rendering.
 * Derivations and measured accuracy: docs/numerics-deon.md. */
#ifndef SL_DEON_REF_H
#define SL_DEON_REF_H

#include "scene/material.h"

/* log of d'Eon Eq. 7 in our convention (omega_i toward the light, specular cone theta_o =
 * -theta_i): log[ csch(1/v)/(2v) exp(-sin ti sin to / v) I0(cos ti cos to / v) ], no shift.
 * Finite for every v > 0 and every angle (never NaN, never +-inf). */
double slref_deon_log_mp(double v, double theta_i, double theta_o);

/* log(e^-x I0(x)) for x >= 0 (exponentially scaled Bessel function, ~1e-15 relative). */
double slref_log_i0e(double x);

/* The Gaussian detector (d'Eon Eq. 11): sum_k g(beta; x - 2 pi k), g the normalised Gaussian of
 * standard deviation beta > 0. */
double slref_deon_detector(double beta, double x);

/* A(p, h) (numerics.md sec. 3) for channel ch at difference angle theta_d. */
double slref_deon_attenuation(const sl_material *m, int ch, int p, double theta_d, double h);

/* sum_{p > n} A(p, h) in closed form: (1-f)^2 f^n T^(n+1) / (1 - f T). */
double slref_deon_attenuation_rest(const sl_material *m, int ch, int n, double theta_d, double h);

/* A(p, h) for p = 0..n into A[0..n] and the rest sum_{p > n} A(p, h) into A[n + 1], with one
 * Fresnel and transmittance evaluation (the path tracer's per-hit fiber, deon_hit.h). */
void slref_deon_attenuations(const sl_material *m, int ch, int n, double theta_d, double h,
                             double *A);

/* N_p(phi) (d'Eon Eq. 10) with detector width beta = the model's beta for order p (p >= 3: TRT). */
double slref_deon_np(const sl_material *m, int ch, int p, double theta_d, double phi);

/* Energy of order p: 1/2 integral_{-1}^{1} A(p, h) dh (= integral of N_p over phi). */
double slref_deon_energy(const sl_material *m, int ch, int p, double theta_d);

/* E_rest = 1/2 integral of sum_{p > m->orders} A(p, h) dh. */
double slref_deon_energy_rest(const sl_material *m, int ch, double theta_d);

/* The scattering function f (numerics.md sec. 3): out[p] = f_p for p = 0..orders,
 * out[orders+1] = f_rest, out[orders+2] = f (orders+3 values; m->orders >= 2). */
void slref_deon_scatter(const sl_material *m, int ch, double theta_i, double phi_i, double theta_o,
                        double phi_o, double *out);

#endif
