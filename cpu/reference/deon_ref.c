/* deon_ref.c: d'Eon 2011 fiber model in double precision, the reference backend (see deon_ref.h,
 * numerics.md sec. 3, docs/numerics-deon.md). Everything is evaluated in log space or in a
 * cancellation-free form so that no input with v > 0 and |theta| <= pi/2 gives NaN or inf. */
#include "deon_ref.h"

#include "fiber_common_d.h"
#include "quad.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define TWO_PI 6.28318530717958647692

double slref_log_i0e(double x) {
    x = fabs(x);
    if (x < 25.0) {
        /* I0(x) = sum_k (x^2/4)^k / (k!)^2 (A&S 9.6.10): all terms positive, no cancellation. */
        double t = 0.25 * x * x, term = 1.0, sum = 1.0;
        for (int k = 1; k < 500; k++) {
            term *= t / ((double)k * (double)k);
            sum += term;
            if (term < 1e-17 * sum) break;
        }
        return log(sum) - x;
    }
    /* Hankel's asymptotic series (A&S 9.7.1): e^-x I0(x) ~ (2 pi x)^-1/2 sum_k a_k,
     * a_k = a_{k-1} (2k-1)^2 / (8 k x); truncated at its smallest term (~e^-2x < 1e-21). */
    double term = 1.0, sum = 1.0;
    for (int k = 1; k < 200; k++) {
        double next = term * (double)(2 * k - 1) * (double)(2 * k - 1) / (8.0 * k * x);
        if (next >= term || next < 1e-18) break;
        term = next;
        sum += term;
    }
    return log(sum) - 0.5 * log(TWO_PI * x);
}

double slref_deon_log_mp(double v, double theta_i, double theta_o) {
    /* d'Eon Eq. 7 with our sign convention (the paper's sin(-theta_i)): see docs/numerics-deon.md.
     * log M = -log(2v) + log csch(1/v) - sin ti sin to / v + log I0(|cos ti cos to| / v),
     * log csch(1/v) = log 2 - 1/v - log(1 - e^{-2/v}), log I0(x) = x + log i0e(x); the three
     * O(1/v) terms combine exactly into -2 sin^2((ti+to)/2)/v (or -2 cos^2((ti-to)/2)/v when
     * cos ti cos to < 0, which a shifted theta_o beyond +-pi/2 can give). */
    double cc = cos(theta_i) * cos(theta_o);
    double expo;
    if (cc >= 0.0) {
        double s = sin(0.5 * (theta_i + theta_o));
        expo = -2.0 * s * s / v;
    } else {
        double c = cos(0.5 * (theta_i - theta_o));
        expo = -2.0 * c * c / v;
    }
    double x = fabs(cc) / v;
    double r = -log(v) - log(-expm1(-2.0 / v)) + expo + slref_log_i0e(x);
    if (!(r > -DBL_MAX)) r = -DBL_MAX; /* only for denormal v: keep "always finite" */
    return r;
}

double slref_deon_detector(double beta, double x) {
    x = sld_wrap_pi(x);
    if (beta > 1.5) {
        /* Jacobi theta form (Poisson summation): (1 + 2 sum_n e^{-n^2 beta^2/2} cos(n x)) / 2pi;
         * for beta > 1.5 the terms fall below 1e-17 by n = 6. */
        double s = 1.0;
        for (int n = 1; n < 64; n++) {
            double w = exp(-0.5 * (double)n * (double)n * beta * beta);
            if (w < 1e-18) break;
            s += 2.0 * w * cos((double)n * x);
        }
        return s / TWO_PI;
    }
    /* x in (-pi, pi]: wraps |k| <= 2 cover 3 pi >= 6.3 beta; the next ones are < e^-55. */
    double s = 0.0, inv = 1.0 / (beta * sqrt(TWO_PI));
    for (int k = -2; k <= 2; k++) {
        double y = (x - TWO_PI * k) / beta;
        s += exp(-0.5 * y * y);
    }
    return s * inv;
}

/* The per-(material, theta_d) constants of A(p, h). */
typedef struct deon_geom {
    double eta, etap, cos_td, sig; /* sig = sigma_a' = sigma_a / cos theta_t */
} deon_geom;

static void geom_init(const sl_material *m, int ch, double theta_d, deon_geom *g) {
    g->eta = m->eta;
    g->etap = sld_eta_prime(m->eta, theta_d);
    g->cos_td = cos(theta_d);
    g->sig = m->sigma_a[ch] / sld_cos_theta_t(m->eta, theta_d);
}

/* Fresnel factor f and transmittance T at offset h (numerics.md sec. 3: f at cos i =
 * cos theta_d cos gamma_i; T = exp(-2 sigma_a' (1 + cos 2 gamma_t)) = exp(-4 sigma_a' cos^2 gt)).
 */
static void geom_fT(const deon_geom *g, double h, double *f, double *T) {
    double cos_gi = sqrt(fmax(0.0, 1.0 - h * h));
    *f = sld_fresnel_exact(g->eta, g->cos_td * cos_gi);
    double c2t = 1.0 - h * h / (g->etap * g->etap);
    *T = exp(-4.0 * g->sig * c2t);
}

static double A_of(const deon_geom *g, int p, double h) {
    double f, T;
    geom_fT(g, h, &f, &T);
    if (p == 0) return f;
    return (1.0 - f) * (1.0 - f) * pow(f, p - 1) * pow(T, p);
}

static double A_rest_of(const deon_geom *g, int n, double h) {
    double f, T;
    geom_fT(g, h, &f, &T);
    double den = 1.0 - f * T;
    if (!(den > 0.0)) return 0.0; /* f = T = 1 (grazing, no absorption): limit (1-f) = 0 */
    return (1.0 - f) * (1.0 - f) * pow(f, n) * pow(T, n + 1) / den;
}

double slref_deon_attenuation(const sl_material *m, int ch, int p, double theta_d, double h) {
    deon_geom g;
    geom_init(m, ch, theta_d, &g);
    return A_of(&g, p, h);
}

double slref_deon_attenuation_rest(const sl_material *m, int ch, int n, double theta_d, double h) {
    deon_geom g;
    geom_init(m, ch, theta_d, &g);
    return A_rest_of(&g, n, h);
}

void slref_deon_attenuations(const sl_material *m, int ch, int n, double theta_d, double h,
                             double *A) {
    deon_geom g;
    geom_init(m, ch, theta_d, &g);
    double f, T;
    geom_fT(&g, h, &f, &T);
    A[0] = f;
    double a = (1.0 - f) * (1.0 - f) * T; /* A(1); A(p + 1) = A(p) f T */
    for (int p = 1; p <= n; p++, a *= f * T)
        A[p] = a;
    double den = 1.0 - f * T; /* the rest: A(n + 1) / (1 - f T) */
    A[n + 1] = den > 0.0 ? a / den : 0.0;
}

static double order_beta(const sl_material *m, int p) {
    return m->beta[p < 2 ? p : 2];
}
static double order_alpha(const sl_material *m, int p) {
    return m->alpha[p < 2 ? p : 2];
}

/* Phi(p, gamma_i) = 2p gamma_t - 2 gamma_i + p pi with sin gamma_t = sin gamma_i / eta'. */
static double phi_of_gamma(int p, double gamma, double etap) {
    return 2.0 * p * asin(sin(gamma) / etap) - 2.0 * gamma + p * PI;
}

typedef struct np_ctx {
    deon_geom g;
    int p;
    double beta, phi;
} np_ctx;

/* Integrand of Eq. 10 after h = sin(gamma): dh = cos(gamma) d gamma removes the sqrt endpoint
 * behaviour at |h| = 1 and makes dPhi/dgamma bounded, so peaks have similar widths everywhere. */
static double np_integrand(double gamma, void *vctx) {
    const np_ctx *c = vctx;
    double h = sin(gamma);
    return 0.5 * A_of(&c->g, c->p, h) * cos(gamma) *
           slref_deon_detector(c->beta, c->phi - phi_of_gamma(c->p, gamma, c->g.etap));
}

/* gamma in [a, b] with Phi(gamma) = u, Phi monotone on [a, b] and u between Phi(a), Phi(b). */
typedef struct phi_ctx {
    int p;
    double etap;
} phi_ctx;

static double phi_fn(double gamma, void *v) {
    const phi_ctx *c = v;
    return phi_of_gamma(c->p, gamma, c->etap);
}

static double solve_phi(int p, double etap, double a, double b, double u) {
    phi_ctx c = {p, etap};
    return slq_bisect(phi_fn, &c, a, b, u);
}

double slref_deon_np(const sl_material *m, int ch, int p, double theta_d, double phi) {
    np_ctx c;
    geom_init(m, ch, theta_d, &c.g);
    c.p = p;
    c.beta = order_beta(m, p);
    c.phi = phi;
    /* Pieces on which Phi(gamma) is monotone: dPhi/dgamma = 0 at sin^2 gamma =
     * (p^2 - eta'^2)/(p^2 - 1) (p >= 2, p > eta'), the caustics. */
    double piece[4] = {-0.5 * PI, 0, 0, 0.5 * PI};
    int np_ = 2;
    double etap = c.g.etap;
    if (p >= 2 && (double)p > etap) {
        double gc = asin(sqrt(((double)p * p - etap * etap) / ((double)p * p - 1.0)));
        piece[1] = -gc;
        piece[2] = gc;
        piece[3] = 0.5 * PI;
        np_ = 4;
    } else {
        piece[1] = 0.5 * PI;
    }
    slq_pts pts = {0};
    for (int i = 0; i + 1 < np_; i++)
        slq_pts_push(&pts, piece[i]);
    /* Breakpoints where the detector is centred or 1, 2, 5, 10 sigma away, on every wrap: this
     * makes the adaptive rule see peaks narrower than any fixed sampling. Wide detectors
     * (beta >= 0.5) are smooth enough without. */
    static const double offs[9] = {-10, -5, -2, -1, 0, 1, 2, 5, 10};
    if (c.beta < 0.5) {
        for (int i = 0; i + 1 < np_; i++) {
            double a = piece[i], b = piece[i + 1];
            double fa = phi_of_gamma(p, a, etap), fb = phi_of_gamma(p, b, etap);
            double lo = fmin(fa, fb), hi = fmax(fa, fb);
            for (int j = 0; j < 9; j++) {
                double base = phi + offs[j] * c.beta;
                long k0 = (long)ceil((lo - base) / TWO_PI), k1 = (long)floor((hi - base) / TWO_PI);
                for (long k = k0; k <= k1; k++)
                    slq_pts_push(&pts, solve_phi(p, etap, a, b, base + TWO_PI * (double)k));
            }
        }
    }
    slq_pts_push(&pts, 0.5 * PI);
    slq_pts_sort(&pts);
    /* quad.h takes <= 64 breakpoints per call: integrate in chunks of 60 intervals. */
    double total = 0.0;
    for (size_t s = 0; s + 1 < pts.n; s += 60) {
        size_t e = s + 60 < pts.n - 1 ? s + 60 : pts.n - 1;
        if (pts.v[e] <= pts.v[s]) continue;
        total += slq_integrate_pts(np_integrand, &c, pts.v[s], pts.v[e], pts.v + s + 1, e - s - 1,
                                   1e-10, 1e-300, 50, NULL);
    }
    free(pts.v);
    return total;
}

typedef struct e_ctx {
    deon_geom g;
    int p; /* order, or -1 for the rest above n */
    int n;
} e_ctx;

static double e_integrand(double gamma, void *vctx) {
    const e_ctx *c = vctx;
    double h = sin(gamma);
    double a = c->p >= 0 ? A_of(&c->g, c->p, h) : A_rest_of(&c->g, c->n, h);
    return a * cos(gamma);
}

/* 1/2 integral_{-1}^{1} A dh = integral_0^{pi/2} A(sin g) cos g dg (A is even in h). */
double slref_deon_energy(const sl_material *m, int ch, int p, double theta_d) {
    e_ctx c;
    geom_init(m, ch, theta_d, &c.g);
    c.p = p;
    c.n = 0;
    return slq_integrate(e_integrand, &c, 0.0, 0.5 * PI, 1e-11, 1e-300, 50, NULL);
}

double slref_deon_energy_rest(const sl_material *m, int ch, double theta_d) {
    e_ctx c;
    geom_init(m, ch, theta_d, &c.g);
    c.p = -1;
    c.n = m->orders;
    return slq_integrate(e_integrand, &c, 0.0, 0.5 * PI, 1e-11, 1e-300, 50, NULL);
}

void slref_deon_scatter(const sl_material *m, int ch, double theta_i, double phi_i, double theta_o,
                        double phi_o, double *out) {
    int n = m->orders;
    double theta_d = 0.5 * (theta_o - theta_i);
    double phi = sld_wrap_pi(phi_o - phi_i);
    double total = 0.0;
    for (int p = 0; p <= n; p++) {
        double beta = order_beta(m, p);
        double lm = slref_deon_log_mp(beta * beta, theta_i, theta_o - 2.0 * order_alpha(m, p));
        /* N_p <= max D <= 1/(sqrt(2 pi) beta) + 1/pi: skip N_p when the product underflows. */
        double lmax = log(1.0 / (sqrt(TWO_PI) * beta) + 1.0);
        double fp = 0.0;
        if (lm + lmax > -750.0) fp = exp(lm) * slref_deon_np(m, ch, p, theta_d, phi);
        out[p] = fp;
        total += fp;
    }
    double bt = m->beta[2];
    double lm = slref_deon_log_mp(bt * bt, theta_i, theta_o - 2.0 * m->alpha[2]);
    double fr = 0.0;
    if (lm > -750.0) fr = exp(lm) * slref_deon_energy_rest(m, ch, theta_d) / TWO_PI;
    out[n + 1] = fr;
    out[n + 2] = total + fr;
}
