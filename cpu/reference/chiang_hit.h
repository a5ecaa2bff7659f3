/* chiang_hit.h: the Chiang 2016 fiber (numerics.md sec. 3 "chiang"; pbrt-v4's HairBxDF, Blender's
 * Principled Hair) at ONE fiber offset h, in double precision: the scattering a ray meets where it
 * hits a fiber at h. The width-averaged f of `eval` (chiang_ref.h) integrates this over h in
 * [-1, 1] with weight 1/2; the path tracer uses it per hit (h from the hit geometry), which is the
 * same model because h is uniform over the fiber's projected width.
 *
 *   f_h(omega_i, omega_o) = sum_{p=0..2} M_p(v_p, theta_i, theta_o'_p) A_p(h) N_p(phi, h)
 *                           + M(v_2, theta_i, theta_o) A_3(h) / (2 pi)
 *
 * in this page's measure (integral of f_h d omega_i = sum_p A_p(h) <= 1, = 1 at sigma_a = 0).
 * theta_o'_p = theta_o - 2 alpha[p] (material.h: alpha = offset, -offset/2, -2 offset); v_p =
 * beta[p]^2; N_p the logistic of scale s trimmed to (-pi, pi) around Phi(p, h) = 2 p gamma_t -
 * 2 gamma_o + p pi, phi = phi_o - phi_i wrapped. The Fresnel factor is at cos theta_o cos gamma_o
 * and eta' uses theta_o (pbrt), so f_h is not symmetric in i and o; the width average is what the
 * contract defines. */
#ifndef SL_CHIANG_HIT_H
#define SL_CHIANG_HIT_H

#include "scene/material.h"

/* The per-(theta_o, h) quantities of one colour channel. */
typedef struct slref_chiang_hit {
    double gamma_o, gamma_t; /* asin(h), asin(h / eta') */
    double A[4];             /* A_0, A_1, A_2 and A_3 = sum_{p >= 3} A_p */
} slref_chiang_hit;

/* A_p and the angles at offset h in [-1, 1] for outgoing inclination theta_o, channel ch. */
void slref_chiang_hit_init(const sl_material *m, int ch, double theta_o, double h,
                           slref_chiang_hit *out);
/* The same at gamma_o = asin(h) given directly (the width average integrates in gamma_o: exact
 * there, where asin(sin(gamma)) near |h| = 1 would lose half the digits). */
void slref_chiang_hit_init_gamma(const sl_material *m, int ch, double theta_o, double gamma_o,
                                 slref_chiang_hit *out);

/* Logistic density of scale s, its CDF, and the density trimmed to [-pi, pi] (normalised there). */
double slref_logistic(double x, double s);
double slref_logistic_cdf(double x, double s);
double slref_trimmed_logistic(double x, double s);
/* Inverse CDF of the trimmed logistic: u in [0, 1) -> x in [-pi, pi]. */
double slref_sample_trimmed_logistic(double u, double s);

/* Phi(p, h) = 2 p gamma_t - 2 gamma_o + p pi. */
double slref_chiang_phi(int p, double gamma_o, double gamma_t);

/* N_p(phi) of lobe p = 0, 1, 2 at the hit (phi = phi_o - phi_i, any real; wrapped inside). */
double slref_chiang_np(const sl_material *m, const slref_chiang_hit *hk, int p, double phi);

/* theta_o shifted for lobe p (p = 0, 1, 2; p = 3: unshifted) and the lobe's variance v_p. */
double slref_chiang_theta_o_lobe(const sl_material *m, int p, double theta_o);
double slref_chiang_v(const sl_material *m, int p);

/* f_h per lobe: out[p] for p = 0..3 (3 = the uniform-azimuth rest), returns their sum. */
double slref_chiang_hit_f(const sl_material *m, const slref_chiang_hit *hk, double theta_i,
                          double theta_o, double phi, double out[4]);

#endif
