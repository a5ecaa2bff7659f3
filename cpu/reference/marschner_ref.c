/* marschner_ref.c: double-precision reference of the Marschner scattering function exactly as
 * numerics.md sec. 3 writes it (Xu 2011 Eq. 6-10 and 24). See docs/numerics.md for the choices:
 *  - roots of Phi(p, h) = phi are found in u = asin(h), where Phi is smooth and dPhi/du is
 *    bounded, by safeguarded Newton on brackets between the caustic points (dPhi/dh = 0);
 *  - 1/|dPhi/dh| = cos(u)/|dPhi/du| is finite and -> 0 at |h| = 1 (no Inf/NaN there);
 *  - TRT: (N_TRT * G)(phi) = 1/2 int A(h) G(phi - Phi(2,h)) dh / Z over h, integrated in u
 *    (dh = cos u du) by adaptive Gauss-Kronrod with breakpoints at the caustic and at the
 *    preimages of phi + {0, +-w/2, +-w, +-2w, +-4w, +-8w}, so a narrow w_c is resolved;
 *  - an index eta* < 1 (strong eccentricity) gives total internal reflection (F = 1, so
 *    A_TRT = 0) for |h| >= eta': the integral runs over |h| < min(1, eta'). */
#include "marschner_ref.h"

#include <math.h>

#include "fiber_common_d.h"
#include "quad.h"

#define PI_D 3.14159265358979323846
#define TWO_PI_D 6.28318530717958647692

double slref_i0e(double x) {
    x = fabs(x);
    if (x < 25.0) {
        /* I0(x) = sum (x^2/4)^j / (j!)^2: positive terms, no cancellation. */
        double q = 0.25 * x * x, term = 1.0, sum = 1.0;
        for (int j = 1; j < 200; j++) {
            term *= q / ((double)j * (double)j);
            sum += term;
            if (term < 1e-17 * sum) break;
        }
        return sum * exp(-x);
    }
    /* I0(x) e^-x ~ (2 pi x)^-1/2 sum_j ((2j-1)!!)^2 / (j! (8x)^j) (A&S 9.7.1). */
    double term = 1.0, sum = 1.0;
    for (int j = 1; j < 60; j++) {
        double r = (2.0 * j - 1.0) * (2.0 * j - 1.0) / (8.0 * x * j);
        if (r >= 1.0) break;
        term *= r;
        sum += term;
        if (term < 1e-17 * sum) break;
    }
    return sum / sqrt(TWO_PI_D * x);
}

/* Phi(p, sin u) and its u-derivative 2p cos u / sqrt(eta'^2 - sin^2 u) - 2. */
static double phi_u(int p, double u, double etap) {
    double s = sin(u) / etap;
    if (s > 1.0) s = 1.0;
    if (s < -1.0) s = -1.0;
    return 2.0 * p * asin(s) - 2.0 * u + p * PI_D;
}
static double dphi_u(int p, double u, double etap) {
    double s = sin(u) / etap, q = 1.0 - s * s;
    if (p == 0) return -2.0;
    if (q <= 0.0) return INFINITY;
    return 2.0 * p * cos(u) / (etap * sqrt(q)) - 2.0;
}

/* u range and the caustic of mode p: |u| <= umax = asin(min(1, eta')); uc = asin(h_c) with
 * h_c^2 = (p^2 - eta'^2)/(p^2 - 1) where dPhi/dh = 0 (TRT with 1 < eta' < 2), else -1. */
static void u_domain(int p, double etap, double *umax, double *uc) {
    *umax = etap >= 1.0 ? 0.5 * PI_D : asin(etap);
    *uc = -1.0;
    if (p >= 2 && etap > 1.0 && etap < (double)p) {
        double hc = sqrt(((double)(p * p) - etap * etap) / ((double)(p * p) - 1.0));
        if (hc < 1.0) *uc = asin(hc);
    }
}

/* Solves phi_u(u) = t on [a, b] where phi_u is monotone and brackets t (rtsafe). */
static double solve_u(int p, double etap, double t, double a, double b) {
    double fa = phi_u(p, a, etap) - t, fb = phi_u(p, b, etap) - t;
    if (fa == 0.0) return a;
    if (fb == 0.0) return b;
    double lo = a, hi = b; /* f(lo) has fa's sign */
    double x = 0.5 * (a + b), dxold = fabs(b - a), dx = dxold;
    for (int it = 0; it < 200; it++) {
        double fx = phi_u(p, x, etap) - t;
        if (fx == 0.0) return x;
        if ((fx < 0.0) == (fa < 0.0))
            lo = x;
        else
            hi = x;
        double d = dphi_u(p, x, etap);
        double xn = x - fx / d;
        double mn = fmin(lo, hi), mx = fmax(lo, hi);
        if (!isfinite(xn) || xn <= mn || xn >= mx || fabs(2.0 * (xn - x)) > dxold) {
            dxold = dx;
            xn = 0.5 * (lo + hi);
            dx = fabs(xn - x);
        } else {
            dxold = dx;
            dx = fabs(xn - x);
        }
        if (dx <= 1e-17 || xn == x) return xn;
        x = xn;
        if (fabs(hi - lo) < 1e-16) return x;
    }
    return x;
}

/* Every u with phi_u(u) = phi (mod 2 pi), ascending. */
static int roots_u(int p, double etap, double phi, double *u, int max) {
    if (!(etap > 0.0) || !isfinite(etap)) return 0;
    double umax, uc;
    u_domain(p, etap, &umax, &uc);
    double cuts[4];
    int nc = 0;
    cuts[nc++] = -umax;
    if (uc > 0.0 && uc < umax) {
        cuts[nc++] = -uc;
        cuts[nc++] = uc;
    }
    cuts[nc++] = umax;
    int n = 0;
    for (int i = 0; i + 1 < nc; i++) {
        double a = cuts[i], b = cuts[i + 1];
        double ya = phi_u(p, a, etap), yb = phi_u(p, b, etap);
        double lo = fmin(ya, yb), hi = fmax(ya, yb);
        double kmin = ceil((lo - phi) / TWO_PI_D), kmax = floor((hi - phi) / TWO_PI_D);
        for (double k = kmin; k <= kmax && n < max; k += 1.0) {
            double r = solve_u(p, etap, phi + TWO_PI_D * k, a, b);
            if (n > 0 && r <= u[n - 1]) continue; /* shared piece end: count once */
            u[n++] = r;
        }
    }
    return n;
}

int slref_marschner_roots(int p, double etap, double phi, double *h, int max) {
    double u[8];
    int n = roots_u(p, etap, phi, u, max < 8 ? max : 8);
    for (int i = 0; i < n; i++)
        h[i] = sin(u[i]);
    return n;
}

typedef struct mode_ctx {
    const sl_material *m;
    int t;          /* 0 R, 1 TT, 2 TRT */
    double eta;     /* eta or eta* */
    double cos_td;  /* cos theta_d */
    double etap;    /* eta' */
    double sigma_p; /* sigma_a' = sigma_a / cos theta_t */
    double phi;     /* target azimuth */
    double inv_w2;  /* 1 / w_c^2 */
    double inv_z;   /* 1 / (2 pi i0e(2/w_c^2)) */
} mode_ctx;

static int mode_setup(mode_ctx *c, const sl_material *m, int ch, int t, double eta_t,
                      double theta_d) {
    c->m = m;
    c->t = t;
    c->eta = eta_t;
    double s = sin(theta_d), co = cos(theta_d);
    c->cos_td = co > 0.0 ? co : 0.0;
    double q = eta_t * eta_t - s * s;
    if (!(eta_t > 0.0) || !(q > 0.0) || !(co > 0.0)) return 0; /* total internal reflection */
    c->etap = sqrt(q) / co;
    double ctt = sqrt(q) / eta_t; /* cos theta_t = sqrt(1 - sin^2 td / eta^2) */
    c->sigma_p = m->sigma_a[ch < 0 || ch > 2 ? 0 : ch] / ctt;
    double w = m->caustic_width;
    c->inv_w2 = 1.0 / (w * w);
    c->inv_z = 1.0 / (TWO_PI_D * slref_i0e(2.0 * c->inv_w2));
    return 1;
}

/* F and 1 - F without cancellation at grazing incidence (1 - rs^2 = 4 ci a / (ci + a)^2 ...);
 * F is sld_fresnel_exact / sld_fresnel_schlick of fiber_common_d.h. */
static double fresnel_pair(const mode_ctx *c, double cos_i, double *tr) {
    double ci = fmin(fabs(cos_i), 1.0), eta = c->eta;
    if (c->m->fresnel == SL_FRESNEL_SCHLICK) {
        double f0 = (eta - 1.0) / (eta + 1.0), x = 1.0 - ci;
        f0 *= f0;
        *tr = (1.0 - f0) * ci * (1.0 + x + x * x + x * x * x + x * x * x * x);
        return sld_fresnel_schlick(eta, ci);
    }
    double s2t = (1.0 - ci) * (1.0 + ci) / (eta * eta);
    if (s2t >= 1.0) {
        *tr = 0.0;
        return 1.0;
    }
    double ct = sqrt(1.0 - s2t), a = eta * ct, b = eta * ci;
    *tr = 0.5 * (4.0 * ci * a / ((ci + a) * (ci + a)) + 4.0 * b * ct / ((b + ct) * (b + ct)));
    return sld_fresnel_exact(eta, ci);
}

/* A_t at u = asin(h) (cos gamma_i = cos u). */
static double mode_A(const mode_ctx *c, double u) {
    double tr;
    double F = fresnel_pair(c, c->cos_td * cos(u), &tr);
    if (c->t == 0) return F;
    double s = sin(u) / c->etap, q = 1.0 - s * s;
    double T = exp(-2.0 * c->sigma_p * sqrt(q > 0.0 ? q : 0.0));
    double g = tr * tr;
    return c->t == 1 ? g * T : g * F * T * T;
}

double slref_marschner_A(const sl_material *m, int ch, int t, double eta_t, double theta_d,
                         double h) {
    mode_ctx c;
    if (!mode_setup(&c, m, ch, t, eta_t, theta_d)) return t == 0 ? 1.0 : 0.0;
    if (h > 1.0) h = 1.0;
    if (h < -1.0) h = -1.0;
    return mode_A(&c, asin(h));
}

/* Root sum A / (2 |dPhi/dh|) with 1/|dPhi/dh| = cos u / |dPhi/du|. */
static double root_sum(const mode_ctx *c, int p, double phi) {
    double u[8];
    int n = roots_u(p, c->etap, phi, u, 8);
    double sum = 0.0;
    for (int i = 0; i < n; i++) {
        double d = fabs(dphi_u(p, u[i], c->etap));
        double cu = cos(u[i]);
        if (cu <= 0.0 || !isfinite(d)) continue; /* |h| = 1 or h = eta': contributes 0 */
        sum += mode_A(c, u[i]) * cu / (2.0 * d);
    }
    return sum;
}

/* Integrand of the TRT convolution in u: 1/2 A(sin u) cos u G(phi - Phi(2, sin u)) / Z,
 * G(x) = exp(2 (cos x - 1) / w^2) = exp(-4 sin^2(x/2) / w^2). */
static double trt_integrand(double u, void *ctx) {
    const mode_ctx *c = ctx;
    double x = c->phi - phi_u(2, u, c->etap);
    double sh = sin(0.5 * x);
    double g = exp(-4.0 * sh * sh * c->inv_w2);
    if (g == 0.0) return 0.0;
    return 0.5 * mode_A(c, u) * cos(u) * g * c->inv_z;
}

static double trt_convolved(mode_ctx *c, double phi) {
    double umax, uc;
    u_domain(2, c->etap, &umax, &uc);
    c->phi = phi;
    double pts[64];
    size_t np = 0;
    if (uc > 0.0) {
        pts[np++] = -uc;
        pts[np++] = uc;
    }
    const double offs[11] = {0.0, 0.5, -0.5, 1.0, -1.0, 2.0, -2.0, 4.0, -4.0, 8.0, -8.0};
    double w = c->m->caustic_width;
    for (int k = 0; k < 11; k++) {
        double d = offs[k] * w;
        if (fabs(d) >= PI_D) continue;
        double u[8];
        int n = roots_u(2, c->etap, phi + d, u, 8);
        for (int i = 0; i < n && np < 64; i++)
            pts[np++] = u[i];
    }
    double err;
    return slq_integrate_pts(trt_integrand, c, -umax, umax, pts, np, 1e-9, 1e-300, 45, &err);
}

double slref_marschner_N(const sl_material *m, int ch, int t, double eta_t, double theta_d,
                         double phi) {
    mode_ctx c;
    if (!mode_setup(&c, m, ch, t, eta_t, theta_d)) return 0.0;
    phi = sld_wrap_pi(phi);
    if (t == 2) return trt_convolved(&c, phi);
    return root_sum(&c, t, phi);
}

double slref_marschner_M(const sl_material *m, int t, double theta_h) {
    double b = m->beta[t], x = (theta_h - m->alpha[t]) / b;
    return exp(-x * x) / (sqrt(PI_D) * b);
}

double slref_marschner_eta_trt(const sl_material *m, double phi_i, double phi_o) {
    if (m->eccentricity == 1.0) return m->eta;
    return sld_eta_star(m->eta, m->eccentricity, phi_o + phi_i);
}

void slref_marschner_scatter(const sl_material *m, int ch, double theta_i, double phi_i,
                             double theta_o, double phi_o, double out[4]) {
    double td = 0.5 * (theta_o - theta_i), th = 0.5 * (theta_o + theta_i);
    double phi = sld_wrap_pi(phi_o - phi_i);
    double ctd = cos(td), cti = cos(theta_i);
    if (cti < 0.0) cti = 0.0;
    /* cos(theta_i) / cos^2(theta_d); |theta_d| <= pi/2 so ctd > 0 for doubles in range. */
    double geo = ctd > 0.0 ? (cti / ctd) / ctd : 0.0;
    double eta_trt = slref_marschner_eta_trt(m, phi_i, phi_o);
    double total = 0.0;
    for (int t = 0; t < 3; t++) {
        double M = slref_marschner_M(m, t, th);
        double f = 0.0;
        if (M > 0.0 && geo > 0.0) {
            double N = slref_marschner_N(m, ch, t, t == 2 ? eta_trt : m->eta, td, phi);
            f = M * N * geo;
            if (!isfinite(f)) f = 0.0;
        }
        out[t] = f;
        total += f;
    }
    out[3] = total;
}
