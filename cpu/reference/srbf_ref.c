/* srbf_ref.c: exact SRBF response I_t (see srbf_ref.h, numerics.md sec. 4, docs/srbf.md).
 *
 * Write omega = (theta, phi) in the fiber frame. Xu 2011 appendix A splits the lobe exactly:
 *   G = G_th(theta_i) G_ph(phi_i),  G_th = exp(2 (cos(theta_i - theta_j) - 1) / lambda^2),
 *   G_ph = exp(kappa (cos(phi_i - phi_j) - 1)),  kappa = 2 cos theta_i cos theta_j / lambda^2,
 * and d omega = cos theta_i d theta_i d phi_i. So
 *   I_t = int d theta_i  G_th cos theta_i  M_t(theta_i)  geo  [int G_ph(phi_i) N_t(phi) d phi_i]
 * (marschner: geo = cos theta_i / cos^2 theta_d; deon: geo = 1). The outer integral is a vector
 * adaptive Gauss-Kronrod over theta_i (all modes at once) with breakpoints where G_th and M_t
 * peak; the inner azimuthal integral is done per mode:
 *  - marschner R, TT: N_t is a root sum over h with Phi(p, h) = phi, so the substitution
 *    phi = Phi(p, h) turns it into 1/2 int A_t(h) G_ph(phi_o - Phi(p, h)) dh (no 1/|dPhi/dh|
 *    singularities), integrated in u = asin h with breakpoints at the preimages of the lobe;
 *  - marschner TRT (round fiber): N_TRT = 1/2 int A(h) g_w(phi - Phi(2,h)) dh / Z, and the
 *    azimuthal product of the two circular Gaussians integrates in closed form:
 *    int exp(kappa (cos(x - phi_j) - 1) + k_w (cos(c - x) - 1)) dx = 2 pi i0e(R) e^(R - kappa -
 * k_w), R = |kappa e^(i phi_j) + k_w e^(i c)|, k_w = 2 / w_c^2;
 *  - marschner TRT with eccentricity (eta* varies with phi_i) and every d'Eon order: brute force
 *    int G_ph(phi_i) N_t(phi_o - phi_i) d phi_i over one period centred on the lobe, with the
 *    reference N_t of marschner_ref.c / deon_ref.c; d'Eon's rest term has a uniform azimuth:
 *    int G_ph E_rest / (2 pi) = E_rest i0e(kappa).
 *  - chiang (geo = 1): as d'Eon with the logistic L_s trimmed to (-pi, pi) for the detector:
 *    1/2 int A_p(h) K_L(phi_o - Phi(p, h)) dh, K_L(c) = int G_ph(x) L_s(c - x) dx in Fourier
 *    series with L_s's coefficients b_n (slref_trimmed_logistic_fourier, closed form), A_p and
 *    Phi from chiang_hit.c at theta_o (they do not depend on theta_i), integrated in
 *    u = asin h with chiang_ref.c's breakpoints; the rest term is E_3 i0e(kappa).
 * Nothing here uses an approximation of the model: only quadrature error, which is controlled. */
#include "srbf_ref.h"

#include "quad.h"

#include "chiang_hit.h"
#include "chiang_ref.h"
#include "deon_ref.h"
#include "fiber_common_d.h"
#include "marschner_ref.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define TWO_PI 6.28318530717958647692
#define HALF_PI 1.57079632679489661923

double slref_srbf_lobe_integral(double lambda) {
    return PI * lambda * lambda * -expm1(-4.0 / (lambda * lambda));
}

double slref_srbf_error(double x, double exact, double lambda) {
    double floor_ = 0.03 * slref_srbf_lobe_integral(lambda);
    return fabs(x - exact) / fmax(exact, floor_);
}

/* Scalar convenience wrapper. */
static double sq_integrate(slq_vfn f, void *ctx, double a, double b, const double *pts, size_t npts,
                           double rel, double abs_tol, int max_iv) {
    double r;
    slq_integrate_vec(f, ctx, 1, a, b, pts, npts, rel, &abs_tol, max_iv, &r);
    return r;
}

/* ---- the problem ---- */

typedef struct srbf_ctx {
    const sl_material *m;
    int ch, nout;
    double theta_o, phi_o, theta_j, phi_j, lambda;
    double cos_tj, inv_l2;
    /* per theta_i (inner integrals) */
    double theta_i, theta_d, kappa;
    int t;                       /* marschner mode of the inner integral */
    double etap;                 /* eta' of that mode */
    double kw, inv_z;            /* TRT: 2 / w_c^2 and 1 / (2 pi i0e(k_w)) */
    const unsigned char *active; /* d'Eon: orders whose M_p is not negligible */
    int p;                       /* d'Eon: order of the inner integral */
    const double *coef;          /* d'Eon: Fourier coefficients of K_d (see kd_coefs) */
    int ncoef;
    const double *bn; /* chiang: Fourier coefficients of the trimmed logistic, bn[0..nbn) */
    int nbn;
    double e_rest; /* chiang: E_3 (depends on theta_o only) */
} srbf_ctx;

/* G_ph at phi_i: exp(-2 kappa sin^2((phi_i - phi_j)/2)). */
static double g_ph(const srbf_ctx *c, double phi_i) {
    double s = sin(0.5 * (phi_i - c->phi_j));
    return exp(-2.0 * c->kappa * s * s);
}

/* Phi(p, sin u) (with the p pi). */
static double phi_u(int p, double u, double etap) {
    double s = sin(u) / etap;
    s = s > 1.0 ? 1.0 : (s < -1.0 ? -1.0 : s);
    return 2.0 * p * asin(s) - 2.0 * u + p * PI;
}

/* Breakpoints in u where Phi(p, sin u) = centre + k s for the offsets k (mod 2 pi), plus the
 * caustics; returns the new count. */
static size_t u_points(int p, double etap, double centre, double s, double *pts, size_t n,
                       size_t cap) {
    static const double offs[13] = {0, 0.5, -0.5, 1, -1, 2, -2, 4, -4, 8, -8, 16, -16};
    if (p >= 2 && etap > 1.0 && etap < 2.0) {
        double hc = sqrt((4.0 - etap * etap) / 3.0);
        if (hc < 1.0 && n + 2 <= cap) {
            pts[n++] = asin(hc);
            pts[n++] = -asin(hc);
        }
    }
    for (int k = 0; k < 13; k++) {
        double d = offs[k] * s;
        if (fabs(d) >= PI) continue;
        double h[8];
        int nr = slref_marschner_roots(p, etap, centre + d, h, 8);
        for (int i = 0; i < nr && n < cap; i++)
            pts[n++] = asin(h[i] > 1.0 ? 1.0 : (h[i] < -1.0 ? -1.0 : h[i]));
    }
    return n;
}

/* R, TT: 1/2 A_t(sin u) cos u G_ph(phi_o - Phi(p, sin u)). */
static void inner_rt(double u, void *vc, double *out) {
    const srbf_ctx *c = vc;
    double g = g_ph(c, c->phi_o - phi_u(c->t, u, c->etap));
    out[0] = g > 0.0 ? 0.5 * slref_marschner_A(c->m, c->ch, c->t, c->m->eta, c->theta_d, sin(u)) *
                           cos(u) * g
                     : 0.0;
}

/* TRT, round fiber: 1/2 A(sin u) cos u K(phi_o - Phi(2, sin u)) / Z with K the closed-form
 * azimuthal product integral of G_ph and g_w (header comment). */
static void inner_trt(double u, void *vc, double *out) {
    const srbf_ctx *c = vc;
    double cc = c->phi_o - phi_u(2, u, c->etap);
    double s = sin(0.5 * (c->phi_j - cc)), s2 = s * s;
    double ka = c->kappa, kw = c->kw;
    double r2 = (ka + kw) * (ka + kw) - 4.0 * ka * kw * s2;
    double r = sqrt(r2 > 0.0 ? r2 : 0.0);
    double expo = ka + kw + r > 0.0 ? -4.0 * ka * kw * s2 / (ka + kw + r) : 0.0;
    double K = TWO_PI * slref_i0e(r) * exp(expo);
    out[0] = 0.5 * slref_marschner_A(c->m, c->ch, 2, c->m->eta, c->theta_d, sin(u)) * cos(u) * K *
             c->inv_z;
}

/* TRT, eccentric: G_ph(phi_i) N_TRT(eta*(phi_o + phi_i), theta_d, phi_o - phi_i). */
static void inner_trt_ecc(double phi_i, void *vc, double *out) {
    const srbf_ctx *c = vc;
    double g = g_ph(c, phi_i);
    if (!(g > 0.0)) {
        out[0] = 0.0;
        return;
    }
    double eta = slref_marschner_eta_trt(c->m, phi_i, c->phi_o);
    out[0] = g * slref_marschner_N(c->m, c->ch, 2, eta, c->theta_d, c->phi_o - phi_i);
}

/* d'Eon: N_p = 1/2 int A(p,h) D_beta(phi - Phi(p,h)) dh (Eq. 10-11), so the azimuthal integral
 * is 1/2 int A(p,h) K_d(phi_o - Phi(p,h)) dh with K_d(c) = int G_ph(x) D_beta(c - x) dx. In
 * Fourier series (e^(k cos t) = sum I_n(k) e^(int), D_beta = 1/2pi sum e^(-n^2 beta^2/2) e^(int)):
 *   K_d(c) = sum_n e^-kappa I_n(kappa) e^(-n^2 beta^2 / 2) cos(n (c - phi_j)),
 * coef[n] = e^-kappa I_n(kappa) e^(-n^2 beta^2/2) (n >= 0, doubled for n >= 1); I_n / I_(n-1) by
 * the continued fraction at the top and the stable downward recurrence r_n = 1/(2n/k + r_(n+1)). */
/* coef[0] = e^-kappa I_0(kappa), coef[k] = 2 e^-kappa I_k(kappa) for k = 1..n: the Fourier
 * coefficients of G_ph, shared by every detector. */
static void bessel_coefs(double kappa, int n, double *coef) {
    coef[0] = slref_i0e(kappa);
    if (!(kappa > 1e-300)) {
        for (int k = 1; k <= n; k++)
            coef[k] = 0.0;
        return;
    }
    /* r_(n+1) = I_(n+1)/I_n by modified Lentz on 1/(b_(n+1) + 1/(b_(n+2) + ...)), b_k = 2k/kappa */
    double tiny = 1e-300, f = tiny, C = f, D = 0.0;
    for (int k = n + 1; k < n + 200000; k++) {
        double b = 2.0 * k / kappa;
        D = b + D;
        if (fabs(D) < tiny) D = tiny;
        C = b + 1.0 / C;
        if (fabs(C) < tiny) C = tiny;
        D = 1.0 / D;
        double delta = C * D;
        f *= delta;
        if (k == n + 1) f = D; /* first term: f = 1/b */
        if (fabs(delta - 1.0) < 1e-15) break;
    }
    double *r = malloc(((size_t)n + 2) * sizeof *r);
    r[n + 1] = f;
    for (int k = n; k >= 1; k--)
        r[k] = 1.0 / (2.0 * k / kappa + r[k + 1]);
    double ie = coef[0];
    for (int k = 1; k <= n; k++) {
        ie *= r[k];
        coef[k] = 2.0 * ie;
    }
    free(r);
}

static int kd_coefs(double kappa, double beta, double *coef, int cap) {
    int nb = (int)ceil(8.0 / beta), nk = (int)ceil(8.0 * sqrt(kappa)) + 10;
    int n = nb < nk ? nb : nk;
    if (n > cap - 1) n = cap - 1;
    if (n < 1) n = 1;
    bessel_coefs(kappa, n, coef);
    for (int k = 1; k <= n; k++)
        coef[k] *= exp(-0.5 * (double)k * (double)k * beta * beta);
    return n + 1;
}

/* Most Fourier terms of the chiang K_L: enough for lambda >= 0.003 (8 sqrt(kappa) + 10 terms). */
#define CHIANG_NCOEF 4096

/* Terms of K_L needed at kappa: those of G_ph (8 sqrt(kappa) + 10), or fewer where the
 * logistic's own b_n are below 1e-17 (b_n ~ 2 pi s n e^{-pi s n} when e^{-pi/s} < 1e-17, i.e.
 * s < 0.08; a larger s trims the logistic visibly, whose kink makes b_n fall only as 1/n^2). */
static int chiang_nterms(double kappa, double s) {
    double nk = ceil(8.0 * sqrt(kappa)) + 10.0;
    if (s < 0.0798) nk = fmin(nk, ceil(15.0 / s) + 10.0);
    return nk > CHIANG_NCOEF - 1 ? CHIANG_NCOEF - 1 : (int)nk;
}

static double kd_eval(const srbf_ctx *c, double cc) {
    double x = cc - c->phi_j, c1 = cos(x), cm = 1.0, cn = c1, s = c->coef[0];
    for (int k = 1; k < c->ncoef; k++) {
        s += c->coef[k] * cn;
        double nx = 2.0 * c1 * cn - cm;
        cm = cn;
        cn = nx;
    }
    return s;
}

static void inner_deon(double u, void *vc, double *out) {
    const srbf_ctx *c = vc;
    double k = kd_eval(c, c->phi_o - phi_u(c->p, u, c->etap));
    out[0] = 0.5 * slref_deon_attenuation(c->m, c->ch, c->p, c->theta_d, sin(u)) * cos(u) * k;
}

/* Breakpoints in phi_i over [phi_j - pi, phi_j + pi]: the lobe (width 1/sqrt(kappa)), the
 * azimuths where the material lobes sit (phi = 0, +-pi/2, pi) and a uniform net of 16. */
static size_t phi_points(const srbf_ctx *c, double *pts) {
    size_t n = 0;
    double s = c->kappa > 0.0 ? 1.0 / sqrt(c->kappa) : 10.0;
    static const double offs[12] = {0.5, -0.5, 1, -1, 2, -2, 4, -4, 8, -8, 16, -16};
    for (int k = 0; k < 12; k++)
        if (fabs(offs[k] * s) < PI) pts[n++] = c->phi_j + offs[k] * s;
    for (int k = 0; k < 4; k++) {
        double x = c->phi_o - 0.5 * PI * k; /* phi = 0, pi/2, pi, 3pi/2 */
        x = c->phi_j + sld_wrap_pi(x - c->phi_j);
        pts[n++] = x;
    }
    for (int k = 1; k < 16; k++)
        pts[n++] = c->phi_j - PI + TWO_PI * k / 16.0;
    return n;
}

/* Tolerances: the outer integral to 1e-7 relative and the inner ones to 1e-9, each with an
 * absolute floor far below the 0.03 int G floor of the error measure (numerics.md sec. 5). */
#define OUTER_REL 1e-7
#define INNER_REL 1e-9

static double inner_marschner(srbf_ctx *c, int t) {
    const sl_material *m = c->m;
    double scale = TWO_PI * slref_i0e(c->kappa); /* int G_ph d phi_i */
    double abs_tol = 1e-13 * scale;
    double pts[128];
    size_t n = 0;
    double eta = t == 2 ? slref_marschner_eta_trt(m, 0.0, 0.0) : m->eta;
    if (t == 2 && m->eccentricity != 1.0) {
        n = phi_points(c, pts);
        return sq_integrate(inner_trt_ecc, c, c->phi_j - PI, c->phi_j + PI, pts, n, INNER_REL,
                            abs_tol, 400);
    }
    c->t = t;
    c->etap = sld_eta_prime(eta, c->theta_d);
    double s = c->kappa > 0.0 ? 1.0 / sqrt(c->kappa) : 10.0;
    if (t == 2) {
        double w = m->caustic_width;
        c->kw = 2.0 / (w * w);
        c->inv_z = 1.0 / (TWO_PI * slref_i0e(c->kw));
        s = sqrt(s * s + 0.5 * w * w);
    }
    n = u_points(t, c->etap, c->phi_o - c->phi_j, s, pts, n, 128);
    return sq_integrate(t == 2 ? inner_trt : inner_rt, c, -HALF_PI, HALF_PI, pts, n, INNER_REL,
                        abs_tol, 400);
}

/* chiang: 1/2 A_p(sin u) cos u K_L(phi_o - Phi(p, sin u)). */
static double inner_chiang(double u, void *vc) {
    const srbf_ctx *c = vc;
    slref_chiang_hit hk;
    slref_chiang_hit_init_gamma(c->m, c->ch, c->theta_o, u, &hk);
    double k = kd_eval(c, c->phi_o - slref_chiang_phi(c->p, hk.gamma_o, hk.gamma_t));
    return 0.5 * hk.A[c->p] * cos(u) * k;
}

/* The chiang modes at one theta_i (outer() has set kappa, gth, cti into c). */
static void outer_chiang(srbf_ctx *c, double ti, double gth, double cti, double *out) {
    const sl_material *m = c->m;
    double s = m->logistic_s;
    int n = chiang_nterms(c->kappa, s);
    if (n > c->nbn - 1) n = c->nbn - 1;
    if (n < 1) n = 1;
    double coef[CHIANG_NCOEF];
    bessel_coefs(c->kappa, n, coef);
    for (int k = 1; k <= n; k++)
        coef[k] *= c->bn[k];
    c->coef = coef;
    c->ncoef = n + 1;
    double scale = TWO_PI * slref_i0e(c->kappa);
    double w = c->kappa > 0.0 ? 1.0 / sqrt(c->kappa) : 10.0;
    w = sqrt(w * w + s * s);
    for (int p = 0; p < 3; p++) {
        double lm = slref_chiang_log_mp(m, p, ti, c->theta_o);
        double mp = lm > -700.0 ? exp(lm) : 0.0;
        if (!(mp * gth > 1e-300)) continue;
        c->p = p;
        size_t np;
        double *pts = slref_chiang_gamma_points(m, p, c->theta_o, c->phi_o - c->phi_j, w, &np);
        double v = slref_chiang_integrate_pts(inner_chiang, c, pts, np, INNER_REL, 1e-13 * scale);
        free(pts);
        out[p] = gth * cti * mp * v;
    }
    double lm = slref_chiang_log_mp(m, 3, ti, c->theta_o);
    if (lm > -700.0) out[3] = gth * cti * exp(lm) * c->e_rest * slref_i0e(c->kappa);
    c->coef = NULL;
}

/* Outer integrand at theta_i: every output but the total. */
static void outer(double ti, void *vc, double *out) {
    srbf_ctx c = *(const srbf_ctx *)vc;
    const sl_material *m = c.m;
    int nmodes = c.nout - 1;
    for (int k = 0; k < nmodes; k++)
        out[k] = 0.0;
    double cti = cos(ti);
    if (!(cti > 0.0)) return;
    double sd = sin(0.5 * (ti - c.theta_j));
    double gth = exp(-4.0 * sd * sd * c.inv_l2);
    if (!(gth > 0.0)) return;
    c.theta_i = ti;
    c.theta_d = 0.5 * (c.theta_o - ti);
    c.kappa = 2.0 * cti * c.cos_tj * c.inv_l2;
    if (m->model == SL_MODEL_CHIANG) {
        outer_chiang(&c, ti, gth, cti, out);
        return;
    }
    if (m->model == SL_MODEL_DEON) {
        int no = m->orders;
        double coef[3][1200];
        int ncoef[3];
        for (int q = 0; q < 3; q++)
            ncoef[q] = kd_coefs(c.kappa, m->beta[q], coef[q], 1200);
        double etap = sld_eta_prime(m->eta, c.theta_d);
        double scale = TWO_PI * slref_i0e(c.kappa);
        for (int p = 0; p <= no; p++) {
            int q = p < 2 ? p : 2;
            double lm =
                slref_deon_log_mp(m->beta[q] * m->beta[q], ti, c.theta_o - 2.0 * m->alpha[q]);
            double mp = lm > -700.0 ? exp(lm) : 0.0;
            if (!(mp * gth > 1e-300)) continue;
            c.p = p;
            c.etap = etap;
            c.coef = coef[q];
            c.ncoef = ncoef[q];
            double s = c.kappa > 0.0 ? 1.0 / sqrt(c.kappa) : 10.0;
            s = sqrt(s * s + m->beta[q] * m->beta[q]);
            double pts[128];
            size_t n = u_points(p, etap, c.phi_o - c.phi_j, s, pts, 0, 128);
            double v = sq_integrate(inner_deon, &c, -HALF_PI, HALF_PI, pts, n, INNER_REL,
                                    1e-13 * scale, 400);
            out[p] = gth * cti * mp * v;
        }
        double lm = slref_deon_log_mp(m->beta[2] * m->beta[2], ti, c.theta_o - 2.0 * m->alpha[2]);
        if (lm > -700.0)
            out[no + 1] = gth * cti * exp(lm) * slref_deon_energy_rest(m, c.ch, c.theta_d) *
                          slref_i0e(c.kappa);
        return;
    }
    double ctd = cos(c.theta_d);
    if (!(ctd > 0.0)) return;
    double geo = cti * cti / (ctd * ctd);
    double th = 0.5 * (c.theta_o + ti);
    for (int t = 0; t < 3; t++) {
        double M = slref_marschner_M(m, t, th);
        if (!(M * gth > 1e-300)) continue;
        out[t] = gth * M * geo * inner_marschner(&c, t);
    }
}

/* Outer breakpoints around a peak at x0 of width w, clipped to the open range. */
static size_t peak_points(double x0, double w, double *pts, size_t n) {
    static const double offs[11] = {0, 0.5, -0.5, 1, -1, 2, -2, 4, -4, 8, -8};
    for (int k = 0; k < 11; k++) {
        double x = x0 + offs[k] * w;
        if (x > -HALF_PI && x < HALF_PI) pts[n++] = x;
    }
    return n;
}

void slref_srbf(const sl_material *m, int ch, double theta_o, double phi_o, double theta_j,
                double phi_j, double lambda, double *out) {
    srbf_ctx c;
    memset(&c, 0, sizeof c);
    c.m = m;
    c.ch = ch;
    int deon = m->model == SL_MODEL_DEON, chiang = m->model == SL_MODEL_CHIANG;
    c.nout = deon ? m->orders + 3 : chiang ? 5 : 4;
    c.theta_o = theta_o;
    c.phi_o = phi_o;
    c.theta_j = theta_j;
    c.phi_j = phi_j;
    c.lambda = lambda;
    c.cos_tj = fmax(cos(theta_j), 0.0);
    c.inv_l2 = 1.0 / (lambda * lambda);
    int nm = c.nout - 1;
    double pts[192]; /* G_th 11 + chiang 4 lobes x 33 */
    size_t n = 0;
    /* G_th: exp(-(theta_i - theta_j)^2 / lambda^2) near its centre. */
    n = peak_points(theta_j, lambda, pts, n);
    double *bn = NULL;
    if (chiang) {
        /* b_n up to the most terms any theta_i needs (kappa <= 2 cos theta_j / lambda^2) */
        c.nbn = chiang_nterms(2.0 * c.cos_tj * c.inv_l2, m->logistic_s) + 1;
        bn = malloc((size_t)c.nbn * sizeof *bn);
        for (int k = 0; k < c.nbn; k++)
            bn[k] = slref_trimmed_logistic_fourier(m->logistic_s, k);
        c.bn = bn;
        c.e_rest = slref_chiang_energy(m, ch, 3, theta_o);
        for (int p = 0; p < 4; p++) {
            /* M_p's cone at -theta_o', mirrored at a pole (M depends on sin, |cos| only) */
            double w = sqrt(slref_chiang_v(m, p));
            double c0 = -slref_chiang_theta_o_lobe(m, p, theta_o);
            if (c0 > HALF_PI) c0 = PI - c0;
            if (c0 < -HALF_PI) c0 = -PI - c0;
            n = peak_points(c0, w, pts, n);
            n = peak_points(-HALF_PI, w, pts, n);
            n = peak_points(HALF_PI, w, pts, n);
        }
    }
    for (int t = 0; t < 3 && !chiang; t++) {
        if (deon) {
            n = peak_points(-(theta_o - 2.0 * m->alpha[t]), m->beta[t], pts, n);
            n = peak_points(-HALF_PI, m->beta[t], pts, n); /* grazing boundary layers */
            n = peak_points(HALF_PI, m->beta[t], pts, n);
        } else {
            /* M_t in theta_i: centre 2 alpha - theta_o, Gaussian width 2 beta. */
            n = peak_points(2.0 * m->alpha[t] - theta_o, 2.0 * m->beta[t], pts, n);
        }
    }
    double lobe = slref_srbf_lobe_integral(lambda);
    double *tol = malloc((size_t)nm * sizeof *tol);
    for (int k = 0; k < nm; k++)
        tol[k] = 1e-10 * lobe;
    if (nm < 1) {
        free(tol);
        free(bn);
        return;
    }
    slq_integrate_vec(outer, &c, nm, -HALF_PI, HALF_PI, pts, n, OUTER_REL, tol, 600, out);
    free(tol);
    free(bn);
    double total = 0.0;
    for (int k = 0; k < nm; k++) {
        if (!isfinite(out[k]) || out[k] < 0.0) out[k] = out[k] > 0.0 ? out[k] : 0.0;
        total += out[k];
    }
    out[nm] = total;
}
