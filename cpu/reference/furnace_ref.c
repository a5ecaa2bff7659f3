/* furnace_ref.c: double-precision white-furnace integral (see furnace_ref.h).
 *
 * d'Eon: the azimuthal integral is done exactly. f_p = M_p(theta_i) N_p(phi; theta_d) and the
 * Gaussian detector integrates to 1 over any full period, so integral N_p dphi = 1/2 integral
 * A(p,h) dh = E_p(theta_d) (d'Eon Eq. 10-11; test_deon checks this numerically). What is left is
 * integral cos(ti) [sum_p M_p E_p + M_TRT E_rest] d ti, done adaptively with breakpoints at the
 * specular peaks, each E_p itself adaptive (deon_ref.c).
 *
 * Marschner: f has no such structure in general (the eccentric TRT term depends on phi_o + phi_i)
 * so the sphere is integrated by brute force: adaptive in theta_i (breakpoints at the M_t peaks)
 * of adaptive in phi_i of slref_marschner_scatter. Slow (seconds per value).
 *
 * Chiang: f_p = M_p(theta_i) Nbar_p(phi) with Nbar_p = 1/2 integral A_p(h) L(phi - Phi(p, h)) dh,
 * where A_p and Phi depend on theta_o and h only (chiang_ref.h). By Fubini the sphere integral of
 * f_p is the product of three 1-D integrals, each done adaptively here (none of the model's
 * normalisations is assumed): integral M_p cos ti d ti (breakpoints at the lobe's peak and the
 * grazing boundary layers), E_p = 1/2 integral A_p dh, and integral_{-pi}^{pi} L(x) dx (the same
 * for every h: a full period of the wrapped logistic, whatever its centre). The rest term's
 * azimuth is uniform: its phi integral is E_3 exactly. */
#include "furnace_ref.h"

#include "chiang_ref.h"
#include "chiang_hit.h"
#include "deon_ref.h"
#include "fiber_common_d.h"
#include "marschner_ref.h"
#include "quad.h"

#include <math.h>
#include <stdlib.h>

#define PI 3.14159265358979323846
#define TWO_PI 6.28318530717958647692

typedef struct furn_ctx {
    const sl_material *m;
    int ch;
    double theta_o, phi_o, theta_i;
} furn_ctx;

static double deon_theta_integrand(double ti, void *vctx) {
    const furn_ctx *c = vctx;
    const sl_material *m = c->m;
    double td = 0.5 * (c->theta_o - ti), s = 0.0;
    for (int p = 0; p <= m->orders; p++) {
        int q = p < 2 ? p : 2;
        double lm = slref_deon_log_mp(m->beta[q] * m->beta[q], ti, c->theta_o - 2.0 * m->alpha[q]);
        if (lm > -750.0) s += exp(lm) * slref_deon_energy(m, c->ch, p, td);
    }
    double lm = slref_deon_log_mp(m->beta[2] * m->beta[2], ti, c->theta_o - 2.0 * m->alpha[2]);
    if (lm > -750.0) s += exp(lm) * slref_deon_energy_rest(m, c->ch, td);
    return s * cos(ti);
}

/* Breakpoints around the longitudinal peaks: centre c = -(theta_o - 2 alpha) (the specular cone)
 * and c +- 1, 3, 6, 12 widths, clipped; returns the count. */
static size_t peak_points(double centre, double width, double *pts, size_t n) {
    static const double offs[9] = {-12, -6, -3, -1, 0, 1, 3, 6, 12};
    for (int j = 0; j < 9; j++) {
        double x = centre + offs[j] * width;
        if (x > -0.5 * PI && x < 0.5 * PI) pts[n++] = x;
    }
    return n;
}

static double marschner_phi_integrand(double phi_i, void *vctx) {
    const furn_ctx *c = vctx;
    double out[4];
    slref_marschner_scatter(c->m, c->ch, c->theta_i, phi_i, c->theta_o, c->phi_o, out);
    return out[3];
}

static double marschner_theta_integrand(double ti, void *vctx) {
    furn_ctx c = *(const furn_ctx *)vctx;
    c.theta_i = ti;
    /* phi = phi_o - phi_i: breakpoints where phi = 0 and phi = pi (R/TT kinks). */
    double pts[2] = {sld_wrap_pi(c.phi_o), sld_wrap_pi(c.phi_o - PI)};
    double v =
        slq_integrate_pts(marschner_phi_integrand, &c, -PI, PI, pts, 2, 1e-8, 1e-300, 40, NULL);
    return v * cos(ti);
}

typedef struct chiang_mp_ctx {
    const sl_material *m;
    int p;
    double theta_o;
} chiang_mp_ctx;

static double chiang_mp_integrand(double ti, void *vctx) {
    const chiang_mp_ctx *c = vctx;
    double lm = slref_chiang_log_mp(c->m, c->p, ti, c->theta_o);
    return lm > -745.0 ? exp(lm) * cos(ti) : 0.0;
}

/* integral_{-pi/2}^{pi/2} M_p(theta_i) cos theta_i d theta_i of chiang lobe p. */
static double chiang_mp_integral(const sl_material *m, int p, double theta_o) {
    chiang_mp_ctx c = {m, p, theta_o};
    double w = sqrt(slref_chiang_v(m, p));
    /* The cone sits at theta_i = -theta_o'; a shifted theta_o' past +-pi/2 is the direction of
     * inclination +-pi - theta_o' (M depends on sin and |cos| only), so mirror the centre. */
    double c0 = -slref_chiang_theta_o_lobe(m, p, theta_o);
    if (c0 > 0.5 * PI) c0 = PI - c0;
    if (c0 < -0.5 * PI) c0 = -PI - c0;
    double pts[27];
    size_t n = peak_points(c0, w, pts, 0);
    n = peak_points(-0.5 * PI, w, pts, n);
    n = peak_points(0.5 * PI, w, pts, n);
    return slq_integrate_pts(chiang_mp_integrand, &c, -0.5 * PI, 0.5 * PI, pts, n, 1e-11, 1e-300,
                             50, NULL);
}

static double logistic_integrand(double x, void *vctx) {
    return slref_trimmed_logistic(x, *(const double *)vctx);
}

static double chiang_furnace(const sl_material *m, int ch, double theta_o) {
    double s = m->logistic_s;
    static const double offs[10] = {0.5, -0.5, 2, -2, 8, -8, 32, -32, 0, 0};
    double pts[10];
    size_t n = 0;
    for (int j = 0; j < 9; j++)
        if (fabs(offs[j] * s) < PI) pts[n++] = offs[j] * s;
    double lint =
        slq_integrate_pts(logistic_integrand, &s, -PI, PI, pts, n, 1e-12, 1e-300, 50, NULL);
    double albedo = 0.0;
    for (int p = 0; p < 4; p++) {
        double e = slref_chiang_energy(m, ch, p, theta_o);
        albedo += chiang_mp_integral(m, p, theta_o) * e * (p < 3 ? lint : 1.0);
    }
    return albedo;
}

double slref_furnace(const sl_material *m, int ch, double theta_o, double phi_o) {
    furn_ctx c = {m, ch, theta_o, phi_o, 0.0};
    if (m->model == SL_MODEL_CHIANG) return chiang_furnace(m, ch, theta_o);
    double pts[64];
    size_t n = 0;
    if (m->model == SL_MODEL_DEON) {
        for (int q = 0; q < 3; q++)
            n = peak_points(-(theta_o - 2.0 * m->alpha[q]), m->beta[q], pts, n);
        /* Near grazing the peak sits at the boundary with a width of ~v in sin(theta): add the
         * boundary layers. */
        for (int q = 0; q < 3; q++) {
            double w = m->beta[q];
            n = peak_points(-0.5 * PI, w, pts, n);
            n = peak_points(0.5 * PI, w, pts, n);
        }
        return slq_integrate_pts(deon_theta_integrand, &c, -0.5 * PI, 0.5 * PI, pts, n, 1e-9,
                                 1e-300, 50, NULL);
    }
    /* M_t = exp(-(theta_h - alpha)^2 / beta^2): in theta_i the peak is at 2 alpha - theta_o with
     * standard deviation sqrt(2) beta. */
    for (int q = 0; q < 3; q++)
        n = peak_points(2.0 * m->alpha[q] - theta_o, sqrt(2.0) * m->beta[q], pts, n);
    return slq_integrate_pts(marschner_theta_integrand, &c, -0.5 * PI, 0.5 * PI, pts, n, 1e-7,
                             1e-300, 40, NULL);
}
