/* dual_ref.h: the dual-scattering material terms (Zinke et al. 2008 as Xu 2011 Sec. 4.3.2 uses
 * them; numerics.md sec. 5 `ms-material`) in double, the reference backend: adaptive quadrature
 * (quad.h) over phi of the reference N_t of marschner_ref.c. Definitions: docs/dual.md.
 * Every model: deon and chiang integrate their own N_p (deon_ref.c, chiang_ref.c; docs/dual.md
 * "Energy-conserving models"). */
#ifndef SL_DUAL_REF_H
#define SL_DUAL_REF_H

#include "scene/material.h"

/* Output order of the nine terms (numerics.md sec. 5). */
enum {
    SLREF_DUAL_AF = 0,
    SLREF_DUAL_AB,
    SLREF_DUAL_ALPHA_F,
    SLREF_DUAL_ALPHA_B,
    SLREF_DUAL_BETA_F,
    SLREF_DUAL_BETA_B,
    SLREF_DUAL_A_B,
    SLREF_DUAL_DELTA_B,
    SLREF_DUAL_SIGMA_B
};

/* Zinke's backscattering density factor d_b (no material key; docs/dual.md). */
#define SLREF_DUAL_DB 0.7

/* Forward/backward attenuation of mode t (0 R, 1 TT, 2 TRT) with index eta_t at theta_d:
 * *af = 2/pi int_0^pi phi N_t(phi) dphi, *ab = 2/pi int_0^pi (pi - phi) N_t(phi) dphi
 * (Xu Eq. 33's azimuthal factor; docs/dual.md). Relative error <= ~1e-8. */
void slref_dual_mode_ab(const sl_material *m, int ch, int t, double eta_t, double theta_d,
                        double *af, double *ab);

/* The per-mode attenuations of the material (TRT averaged over the fiber's roll when
 * eccentricity != 1). */
void slref_dual_attenuations(const sl_material *m, int ch, double theta_d, double af[3],
                             double ab[3]);

/* deon, chiang: per-mode a_f, a_b (R, TT, TRT with every higher order folded into TRT) by
 * adaptive quadrature over phi of the model's N_p (A_p at the specular cone theta_o = theta_d). */
void slref_dual_ec_attenuations(const sl_material *m, int ch, double theta_d, double af[3],
                                double ab[3]);
/* The nine terms from per-mode attenuations and the material's alpha/beta (Zinke 2008). */
void slref_dual_combine(const double af_t[3], const double ab_t[3], const double alpha[3],
                        const double beta[3], double out[9]);

/* The nine terms a_f, a_b, alpha_f, alpha_b, beta_f, beta_b, A_b, Delta_b, sigma_b for colour
 * channel ch at theta_d (|theta_d| <= pi/2), any model. */
void slref_dual_terms(const sl_material *m, int ch, double theta_d, double out[9]);

#endif
