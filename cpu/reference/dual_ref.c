/* dual_ref.c: double reference of the dual-scattering material terms (see dual_ref.h and
 * docs/dual.md): the hemisphere integrals of Xu 2011 Eq. 32-33 reduced to one azimuthal
 * integral, 1/pi int_{-pi/2}^{pi/2} dphi_i int_{pi/2}^{3pi/2} dphi_o N(phi_o - phi_i)
 * = 2/pi int_0^pi phi N(phi) dphi (the measure of pairs with phi_o - phi_i = x is |x| for the
 * forward and pi - |x| for the backward pair of half circles; N is even), computed by adaptive
 * Gauss-Kronrod over phi of the reference N_t (marschner_ref.c: root sums, TRT convolution). */
#include "dual_ref.h"

#include <math.h>

#include "chiang_ref.h"
#include "deon_ref.h"
#include "fiber_common_d.h"
#include "marschner_ref.h"
#include "quad.h"

#define PI_D 3.14159265358979323846

typedef struct dual_ctx {
    const sl_material *m;
    int ch, t, backward;
    double eta, theta_d;
} dual_ctx;

static double weighted_n(double phi, void *p) {
    const dual_ctx *c = p;
    double w = c->backward ? PI_D - phi : phi;
    return w * slref_marschner_N(c->m, c->ch, c->t, c->eta, c->theta_d, phi);
}

void slref_dual_mode_ab(const sl_material *m, int ch, int t, double eta_t, double theta_d,
                        double *af, double *ab) {
    dual_ctx c = {m, ch, t, 0, eta_t, theta_d};
    double pts[16];
    size_t np = 0;
    double s = sin(theta_d), co = cos(theta_d), q = eta_t * eta_t - s * s;
    double etap = (q > 0.0 && co > 0.0) ? sqrt(q) / co : INFINITY;
    if (t == 1 && isfinite(etap)) {
        /* N_TT vanishes for |phi - pi| > pi - 2 asin(1/eta'): a kink at the support's edge. */
        pts[np++] = 2.0 * asin(1.0 / etap);
    }
    if (t == 2 && etap > 1.0 && etap < 2.0) {
        /* The caustic of TRT at h_c^2 = (4 - eta'^2)/3, spread by w_c: bracket its image. */
        double hc = sqrt((4.0 - etap * etap) / 3.0);
        double phic = fabs(sld_wrap_pi(4.0 * asin(hc / etap) - 2.0 * asin(hc)));
        const double offs[9] = {0.0, 0.5, -0.5, 1.0, -1.0, 2.0, -2.0, 4.0, -4.0};
        for (int k = 0; k < 9; k++)
            pts[np++] = phic + offs[k] * m->caustic_width;
    }
    double err;
    *af = 2.0 / PI_D * slq_integrate_pts(weighted_n, &c, 0.0, PI_D, pts, np, 1e-9, 1e-14, 40, &err);
    c.backward = 1;
    *ab = 2.0 / PI_D * slq_integrate_pts(weighted_n, &c, 0.0, PI_D, pts, np, 1e-9, 1e-14, 40, &err);
}

typedef struct roll_ctx {
    const sl_material *m;
    int ch, backward;
    double theta_d;
} roll_ctx;

/* a_{f or b,TRT} with eta* at roll angle s (s = phi_o + phi_i, numerics.md sec. 3). */
static double roll_integrand(double s, void *p) {
    const roll_ctx *c = p;
    double af, ab, eta = sld_eta_star(c->m->eta, c->m->eccentricity, s);
    slref_dual_mode_ab(c->m, c->ch, 2, eta, c->theta_d, &af, &ab);
    return c->backward ? ab : af;
}

void slref_dual_attenuations(const sl_material *m, int ch, double theta_d, double af[3],
                             double ab[3]) {
    for (int t = 0; t < 2; t++)
        slref_dual_mode_ab(m, ch, t, m->eta, theta_d, &af[t], &ab[t]);
    if (m->eccentricity == 1.0) {
        slref_dual_mode_ab(m, ch, 2, m->eta, theta_d, &af[2], &ab[2]);
        return;
    }
    /* Roll average: (1/pi) int_0^pi a_TRT(eta*(s)) ds, eta* smooth in s (docs/dual.md). */
    roll_ctx c = {m, ch, 0, theta_d};
    double err;
    af[2] = slq_integrate(roll_integrand, &c, 0.0, PI_D, 1e-7, 1e-13, 12, &err) / PI_D;
    c.backward = 1;
    ab[2] = slq_integrate(roll_integrand, &c, 0.0, PI_D, 1e-7, 1e-13, 12, &err) / PI_D;
}

void slref_dual_combine(const double af_t[3], const double ab_t[3], const double alpha[3],
                        const double beta[3], double out[9]) {
    double af = 0, ab = 0, waf = 0, wab = 0, wbf = 0, wbb = 0;
    for (int t = 0; t < 3; t++) {
        af += af_t[t];
        ab += ab_t[t];
        waf += af_t[t] * alpha[t];
        wab += ab_t[t] * alpha[t];
        wbf += af_t[t] * beta[t] * beta[t];
        wbb += ab_t[t] * beta[t] * beta[t];
    }
    double mean_a = (alpha[0] + alpha[1] + alpha[2]) / 3.0;
    double mean_b2 = (beta[0] * beta[0] + beta[1] * beta[1] + beta[2] * beta[2]) / 3.0;
    /* Xu Sec. 4.3.2: shifts and squared widths weighted by the per-mode attenuations. */
    double alpha_f = af > 0 ? waf / af : mean_a, alpha_b = ab > 0 ? wab / ab : mean_a;
    double beta_f = sqrt(af > 0 ? wbf / af : mean_b2), beta_b = sqrt(ab > 0 ? wbb / ab : mean_b2);
    /* Zinke 2008 local backscattering (A_1: one backward + two forward events, A_3: three
     * backward events), shift and width, as printed (docs/dual.md). */
    double af2 = fmin(af * af, 1.0 - 1e-12), ab2 = ab * ab, ab3 = ab2 * ab;
    double om = 1.0 - af2, om2 = om * om, om3 = om2 * om;
    double bf2 = beta_f * beta_f, bb2 = beta_b * beta_b;
    double den = ab + ab3 * (2.0 * beta_f + 3.0 * beta_b);
    out[SLREF_DUAL_AF] = af;
    out[SLREF_DUAL_AB] = ab;
    out[SLREF_DUAL_ALPHA_F] = alpha_f;
    out[SLREF_DUAL_ALPHA_B] = alpha_b;
    out[SLREF_DUAL_BETA_F] = beta_f;
    out[SLREF_DUAL_BETA_B] = beta_b;
    out[SLREF_DUAL_A_B] = ab * af2 / om + ab3 * af2 / om3;
    out[SLREF_DUAL_DELTA_B] =
        alpha_b * (1.0 - 2.0 * ab2 / om2) + alpha_f * (2.0 * om2 + 4.0 * af2 * ab2) / om3;
    out[SLREF_DUAL_SIGMA_B] =
        den > 0 ? (1.0 + SLREF_DUAL_DB * af2) *
                      (ab * sqrt(2.0 * bf2 + bb2) + ab3 * sqrt(2.0 * bf2 + 3.0 * bb2)) / den
                : (1.0 + SLREF_DUAL_DB * af2) * sqrt(2.0 * bf2 + bb2);
}

/* deon, chiang: the model's own N_p(phi) (deon_ref.c, chiang_ref.c), order p. */
typedef struct ec_ctx {
    const sl_material *m;
    int ch, p, backward;
    double theta_d;
} ec_ctx;

static double ec_weighted_n(double phi, void *p) {
    const ec_ctx *c = p;
    double w = c->backward ? PI_D - phi : phi;
    double n = c->m->model == SL_MODEL_DEON
                   ? slref_deon_np(c->m, c->ch, c->p, c->theta_d, phi)
                   : slref_chiang_azimuthal(c->m, c->ch, c->p, c->theta_d, phi);
    return w * n;
}

void slref_dual_ec_attenuations(const sl_material *m, int ch, double theta_d, double af[3],
                                double ab[3]) {
    int n = m->model == SL_MODEL_DEON ? m->orders : 2;
    /* Breakpoints every pi/32 so that the adaptive rule sees every narrow peak of N_p. */
    double pts[33];
    for (int k = 0; k <= 32; k++)
        pts[k] = PI_D * k / 32.0;
    for (int t = 0; t < 3; t++)
        af[t] = ab[t] = 0.0;
    for (int p = 0; p <= n; p++) {
        int t = p < 2 ? p : 2;
        ec_ctx c = {m, ch, p, 0, theta_d};
        double err;
        af[t] += 2.0 / PI_D *
                 slq_integrate_pts(ec_weighted_n, &c, 0.0, PI_D, pts, 33, 1e-8, 1e-13, 30, &err);
        c.backward = 1;
        ab[t] += 2.0 / PI_D *
                 slq_integrate_pts(ec_weighted_n, &c, 0.0, PI_D, pts, 33, 1e-8, 1e-13, 30, &err);
    }
    /* The orders above n: uniform in phi, half forward, half backward. */
    double rest = m->model == SL_MODEL_DEON ? slref_deon_energy_rest(m, ch, theta_d)
                                            : slref_chiang_energy(m, ch, 3, theta_d);
    af[2] += 0.5 * rest;
    ab[2] += 0.5 * rest;
}

void slref_dual_terms(const sl_material *m, int ch, double theta_d, double out[9]) {
    double af[3], ab[3];
    theta_d = fmin(fabs(theta_d), PI_D / 2); /* every term is even in theta_d */
    if (m->model == SL_MODEL_MARSCHNER) {
        slref_dual_attenuations(m, ch, theta_d, af, ab);
        slref_dual_combine(af, ab, m->alpha, m->beta, out);
        return;
    }
    /* deon, chiang: beta is the standard deviation of M_p in theta; the Marschner-form width
     * of the same spread is beta / sqrt(2) (docs/dual.md). */
    double beta[3];
    for (int t = 0; t < 3; t++)
        beta[t] = m->beta[t] / sqrt(2.0);
    slref_dual_ec_attenuations(m, ch, theta_d, af, ab);
    slref_dual_combine(af, ab, m->alpha, beta, out);
}
