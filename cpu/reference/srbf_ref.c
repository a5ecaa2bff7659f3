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
 * Nothing here uses an approximation of the model: only quadrature error, which is controlled. */
#include "srbf_ref.h"

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

/* ---- vector adaptive Gauss-Kronrod (G7/K15, QUADPACK error estimate per component) ---- */

typedef void (*vq_fn)(double x, void *ctx, double *out);

static const double xgk[8] = {
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.000000000000000000000000000000000};
static const double wgk[8] = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
    0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
    0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
static const double wg[4] = {
    0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
    0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

/* One interval: [a, b], and per component its value and error estimate. */
typedef struct vq_iv {
    double a, b;
    double *val, *err;
} vq_iv;

/* K15 on [a, b] for n components; fv is scratch of 15 n doubles. */
static void vq_gk15(vq_fn f, void *ctx, int n, double a, double b, double *fv, double *val,
                    double *err) {
    double c = 0.5 * (a + b), hl = 0.5 * (b - a), ahl = fabs(hl);
    f(c, ctx, fv);
    for (int j = 0; j < 7; j++) {
        f(c - hl * xgk[j], ctx, fv + (size_t)(1 + 2 * j) * (size_t)n);
        f(c + hl * xgk[j], ctx, fv + (size_t)(2 + 2 * j) * (size_t)n);
    }
    for (int k = 0; k < n; k++) {
        double fc = isfinite(fv[k]) ? fv[k] : 0.0;
        double rk = fc * wgk[7], rg = fc * wg[3], rabs = fabs(rk);
        double f1[7], f2[7];
        for (int j = 0; j < 7; j++) {
            f1[j] = fv[(size_t)(1 + 2 * j) * (size_t)n + (size_t)k];
            f2[j] = fv[(size_t)(2 + 2 * j) * (size_t)n + (size_t)k];
            if (!isfinite(f1[j])) f1[j] = 0.0;
            if (!isfinite(f2[j])) f2[j] = 0.0;
            rk += wgk[j] * (f1[j] + f2[j]);
            rabs += wgk[j] * (fabs(f1[j]) + fabs(f2[j]));
            if (j % 2 == 1) rg += wg[j / 2] * (f1[j] + f2[j]);
        }
        double mean = 0.5 * rk, asc = wgk[7] * fabs(fc - mean);
        for (int j = 0; j < 7; j++)
            asc += wgk[j] * (fabs(f1[j] - mean) + fabs(f2[j] - mean));
        double e = fabs((rk - rg) * hl);
        asc *= ahl;
        rabs *= ahl;
        if (asc != 0.0 && e != 0.0) {
            double r = pow(200.0 * e / asc, 1.5);
            e = asc * (r < 1.0 ? r : 1.0);
        }
        if (rabs > DBL_MIN / (50.0 * DBL_EPSILON)) e = fmax(e, 50.0 * DBL_EPSILON * rabs);
        val[k] = rk * hl;
        err[k] = e;
    }
}

static int cmp_dbl(const void *x, const void *y) {
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

/* Integrates the n-vector f over [a, b] split at pts (any order; outside points ignored), until
 * every component k has summed error <= max(rel |I_k|, abs_tol[k]) or max_iv intervals exist.
 * Bisects the interval with the largest error relative to its component's tolerance. */
static void vq_integrate(vq_fn f, void *ctx, int n, double a, double b, const double *pts,
                         size_t npts, double rel, const double *abs_tol, int max_iv, double *res) {
    for (int k = 0; k < n; k++)
        res[k] = 0.0;
    if (!(b > a)) return;
    double *cut = malloc((npts + 2) * sizeof *cut);
    size_t nc = 0;
    cut[nc++] = a;
    for (size_t i = 0; i < npts; i++)
        if (isfinite(pts[i]) && pts[i] > a && pts[i] < b) cut[nc++] = pts[i];
    qsort(cut + 1, nc - 1, sizeof *cut, cmp_dbl);
    size_t m = 1;
    for (size_t i = 1; i < nc; i++)
        if (cut[i] > cut[m - 1] + 1e-15 * (b - a)) cut[m++] = cut[i];
    nc = m;
    cut[nc++] = b;
    int cap = max_iv > (int)nc ? max_iv : (int)nc;
    vq_iv *iv = malloc((size_t)cap * sizeof *iv);
    double *store = malloc((size_t)cap * 2 * (size_t)n * sizeof *store);
    double *fv = malloc(15 * (size_t)n * sizeof *fv);
    double *tot = calloc((size_t)n, sizeof *tot), *terr = calloc((size_t)n, sizeof *terr);
    int niv = 0;
    for (size_t i = 0; i + 1 < nc; i++) {
        vq_iv *v = &iv[niv];
        v->a = cut[i];
        v->b = cut[i + 1];
        v->val = store + (size_t)niv * 2 * (size_t)n;
        v->err = v->val + n;
        vq_gk15(f, ctx, n, v->a, v->b, fv, v->val, v->err);
        for (int k = 0; k < n; k++) {
            tot[k] += v->val[k];
            terr[k] += v->err[k];
        }
        niv++;
    }
    while (niv + 1 < cap) {
        /* Done when every component meets its tolerance. */
        int done = 1;
        for (int k = 0; k < n && done; k++)
            if (terr[k] > fmax(rel * fabs(tot[k]), abs_tol[k])) done = 0;
        if (done) break;
        int best = -1;
        double bs = 0.0;
        for (int i = 0; i < niv; i++) {
            double s = 0.0;
            for (int k = 0; k < n; k++) {
                double t = fmax(rel * fabs(tot[k]), abs_tol[k]);
                s = fmax(s, iv[i].err[k] / t);
            }
            if (s > bs && 0.5 * (iv[i].a + iv[i].b) > iv[i].a &&
                0.5 * (iv[i].a + iv[i].b) < iv[i].b) {
                bs = s;
                best = i;
            }
        }
        if (best < 0) break;
        vq_iv *p = &iv[best], *q = &iv[niv];
        double mid = 0.5 * (p->a + p->b);
        q->val = store + (size_t)niv * 2 * (size_t)n;
        q->err = q->val + n;
        q->a = mid;
        q->b = p->b;
        for (int k = 0; k < n; k++) {
            tot[k] -= p->val[k];
            terr[k] -= p->err[k];
        }
        p->b = mid;
        vq_gk15(f, ctx, n, p->a, p->b, fv, p->val, p->err);
        vq_gk15(f, ctx, n, q->a, q->b, fv, q->val, q->err);
        for (int k = 0; k < n; k++) {
            tot[k] += p->val[k] + q->val[k];
            terr[k] += p->err[k] + q->err[k];
        }
        niv++;
    }
    /* Re-sum from the leaves (no drift from the running updates). */
    for (int i = 0; i < niv; i++)
        for (int k = 0; k < n; k++)
            res[k] += iv[i].val[k];
    free(cut);
    free(iv);
    free(store);
    free(fv);
    free(tot);
    free(terr);
}

/* Scalar convenience wrapper. */
static double sq_integrate(vq_fn f, void *ctx, double a, double b, const double *pts, size_t npts,
                           double rel, double abs_tol, int max_iv) {
    double r;
    vq_integrate(f, ctx, 1, a, b, pts, npts, rel, &abs_tol, max_iv, &r);
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
static int kd_coefs(double kappa, double beta, double *coef, int cap) {
    int nb = (int)ceil(8.0 / beta), nk = (int)ceil(8.0 * sqrt(kappa)) + 10;
    int n = nb < nk ? nb : nk;
    if (n > cap - 1) n = cap - 1;
    if (n < 1) n = 1;
    coef[0] = slref_i0e(kappa);
    if (!(kappa > 1e-300)) {
        for (int k = 1; k <= n; k++)
            coef[k] = 0.0;
        return n + 1;
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
        coef[k] = 2.0 * ie * exp(-0.5 * (double)k * (double)k * beta * beta);
    }
    free(r);
    return n + 1;
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
    int deon = m->model == SL_MODEL_DEON;
    c.nout = deon ? m->orders + 3 : 4;
    c.theta_o = theta_o;
    c.phi_o = phi_o;
    c.theta_j = theta_j;
    c.phi_j = phi_j;
    c.lambda = lambda;
    c.cos_tj = fmax(cos(theta_j), 0.0);
    c.inv_l2 = 1.0 / (lambda * lambda);
    int nm = c.nout - 1;
    double pts[128];
    size_t n = 0;
    /* G_th: exp(-(theta_i - theta_j)^2 / lambda^2) near its centre. */
    n = peak_points(theta_j, lambda, pts, n);
    for (int t = 0; t < 3; t++) {
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
        return;
    }
    vq_integrate(outer, &c, nm, -HALF_PI, HALF_PI, pts, n, OUTER_REL, tol, 600, out);
    free(tol);
    double total = 0.0;
    for (int k = 0; k < nm; k++) {
        if (!isfinite(out[k]) || out[k] < 0.0) out[k] = out[k] > 0.0 ? out[k] : 0.0;
        total += out[k];
    }
    out[nm] = total;
}
