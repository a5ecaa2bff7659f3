/* chiang_ref.c: the width-averaged Chiang 2016 fiber in double (chiang_ref.h; numerics.md sec. 3
 * "chiang"; derivations and measured accuracy: docs/numerics-chiang.md). The integrand at one
 * offset is chiang_hit.c; this file only integrates it. */
#include "chiang_ref.h"

#include "chiang_hit.h"
#include "deon_ref.h"
#include "quad.h"

#include <math.h>
#include <stdlib.h>

#define PI 3.14159265358979323846
#define TWO_PI 6.28318530717958647692
#define HALF_PI 1.57079632679489661923

double slref_chiang_log_mp(const sl_material *m, int p, double theta_i, double theta_o) {
    return slref_deon_log_mp(slref_chiang_v(m, p), theta_i,
                             slref_chiang_theta_o_lobe(m, p, theta_o));
}

/* 1/eta' = cos theta_o / sqrt(eta^2 - sin^2 theta_o): finite at grazing (0 there). */
static double inv_etap(const sl_material *m, double theta_o) {
    double so = sin(theta_o);
    return cos(theta_o) / sqrt(m->eta * m->eta - so * so);
}

/* Phi(p, gamma) = 2 p gamma_t - 2 gamma + p pi with sin gamma_t = sin gamma / eta'. */
static double phi_of(int p, double gamma, double ie) {
    double st = sin(gamma) * ie;
    st = st > 1.0 ? 1.0 : (st < -1.0 ? -1.0 : st);
    return 2.0 * p * asin(st) - 2.0 * gamma + p * PI;
}

/* gamma in [a, b] with Phi(gamma) = u, Phi monotone on [a, b], u between Phi(a) and Phi(b). */
typedef struct phi_ctx {
    int p;
    double ie;
} phi_ctx;

static double phi_fn(double gamma, void *v) {
    const phi_ctx *c = v;
    return phi_of(c->p, gamma, c->ie);
}

static double solve_phi(int p, double ie, double a, double b, double u) {
    phi_ctx c = {p, ie};
    return slq_bisect(phi_fn, &c, a, b, u);
}

typedef struct az_ctx {
    const sl_material *m;
    int ch, p;
    double theta_o, phi;
} az_ctx;

/* 1/2 A_p(sin g) cos g N_p(phi, sin g): dh = cos g dg removes the sqrt endpoint behaviour at
 * |h| = 1 and bounds dPhi/dg by 2, so every logistic peak is >= s/2 wide in g. */
static double az_integrand(double g, void *vctx) {
    const az_ctx *c = vctx;
    slref_chiang_hit hk;
    slref_chiang_hit_init_gamma(c->m, c->ch, c->theta_o, g, &hk);
    return 0.5 * hk.A[c->p] * cos(g) * slref_chiang_np(c->m, &hk, c->p, c->phi);
}

double *slref_chiang_gamma_points(const sl_material *m, int p, double theta_o, double phi,
                                  double width, size_t *count) {
    double ie = inv_etap(m, theta_o);
    /* Pieces on which Phi is monotone: dPhi/dg = 4 cos g / sqrt(eta'^2 - sin^2 g) - 2 for p = 2
     * vanishes at sin^2 g = (4 - eta'^2) / 3 when eta' < 2 (the TRT caustic); p = 0, 1 are
     * monotone for every eta' > 1. */
    double piece[4] = {-HALF_PI, HALF_PI, 0, 0};
    int npc = 2;
    if (p == 2 && ie > 0.5) {
        double gc = asin(sqrt((4.0 - 1.0 / (ie * ie)) / 3.0));
        piece[1] = -gc;
        piece[2] = gc;
        piece[3] = HALF_PI;
        npc = 4;
    }
    slq_pts pts = {0};
    for (int i = 0; i < npc; i++)
        slq_pts_push(&pts, piece[i]);
    /* Where phi - Phi is 0, +-k width (k = 1/2 .. 32: e^-32 of a logistic peak) or pi (the
     * trimming kink of the wrapped logistic), on every wrap. */
    static const double offs[15] = {0, 0.5, -0.5, 1, -1, 2, -2, 4, -4, 8, -8, 16, -16, 32, -32};
    for (int i = 0; i + 1 < npc; i++) {
        double a = piece[i], b = piece[i + 1];
        double fa = phi_of(p, a, ie), fb = phi_of(p, b, ie);
        double lo = fmin(fa, fb), hi = fmax(fa, fb);
        for (int j = 0; j < 16; j++) {
            double d = j < 15 ? offs[j] * width : PI;
            if (j < 15 && fabs(d) >= PI) continue;
            double base = phi + d;
            long k0 = (long)ceil((lo - base) / TWO_PI), k1 = (long)floor((hi - base) / TWO_PI);
            for (long k = k0; k <= k1; k++)
                slq_pts_push(&pts, solve_phi(p, ie, a, b, base + TWO_PI * (double)k));
        }
    }
    slq_pts_push(&pts, HALF_PI);
    slq_pts_sort(&pts);
    *count = pts.n;
    return pts.v;
}

double slref_chiang_integrate_pts(double (*f)(double, void *), void *ctx, const double *pts,
                                  size_t n, double rel, double abs_tol) {
    /* quad.h takes <= 64 breakpoints per call: chunks of 60 intervals */
    double total = 0.0;
    for (size_t a = 0; a + 1 < n; a += 60) {
        size_t b = a + 60 < n - 1 ? a + 60 : n - 1;
        if (pts[b] <= pts[a]) continue;
        total += slq_integrate_pts(f, ctx, pts[a], pts[b], pts + a + 1, b - a - 1, rel, abs_tol, 50,
                                   NULL);
    }
    return total;
}

double slref_chiang_azimuthal(const sl_material *m, int ch, int p, double theta_o, double phi) {
    az_ctx c = {m, ch, p, theta_o, phi};
    /* breakpoints at the logistic's centre and k s from it: the adaptive rule then sees peaks
     * far narrower than any fixed sampling would */
    size_t n;
    double *pts = slref_chiang_gamma_points(m, p, theta_o, phi, m->logistic_s, &n);
    double v = slref_chiang_integrate_pts(az_integrand, &c, pts, n, 1e-10, 1e-300);
    free(pts);
    return v;
}

typedef struct e_ctx {
    const sl_material *m;
    int ch, p;
    double theta_o;
} e_ctx;

static double e_integrand(double g, void *vctx) {
    const e_ctx *c = vctx;
    slref_chiang_hit hk;
    slref_chiang_hit_init_gamma(c->m, c->ch, c->theta_o, g, &hk);
    return hk.A[c->p] * cos(g);
}

/* A_p is even in h: 1/2 integral_{-1}^{1} = integral_0^{pi/2} A_p(sin g) cos g dg. */
double slref_chiang_energy(const sl_material *m, int ch, int p, double theta_o) {
    e_ctx c = {m, ch, p, theta_o};
    return slq_integrate(e_integrand, &c, 0.0, HALF_PI, 1e-12, 1e-300, 50, NULL);
}

void slref_chiang_scatter(const sl_material *m, int ch, double theta_i, double phi_i,
                          double theta_o, double phi_o, double out[5]) {
    double phi = phi_o - phi_i, s = m->logistic_s;
    /* Nbar_p <= max N_p = 1 / (4 s tanh(pi / 2s)): skip it when M_p times that underflows. */
    double lmax = -log(4.0 * s * tanh(PI / (2.0 * s)));
    double total = 0.0;
    for (int p = 0; p < 3; p++) {
        double lm = slref_chiang_log_mp(m, p, theta_i, theta_o), fp = 0.0;
        if (lm + lmax > -745.0) fp = exp(lm) * slref_chiang_azimuthal(m, ch, p, theta_o, phi);
        out[p] = fp;
        total += fp;
    }
    double lm = slref_chiang_log_mp(m, 3, theta_i, theta_o), fr = 0.0;
    if (lm > -745.0) fr = exp(lm) * slref_chiang_energy(m, ch, 3, theta_o) / TWO_PI;
    out[3] = fr;
    out[4] = total + fr;
}

double slref_trimmed_logistic_fourier(double s, int n) {
    if (n == 0) return 1.0;
    /* untrimmed: integral over R of L(x) cos(n x) = pi s n / sinh(pi s n) */
    double x = PI * s * n;
    double full = x < 700.0 ? x / sinh(x) : 0.0;
    /* tail: integral_pi^inf L cos(n x) dx with L(x) = (1/s) sum_k (-1)^(k+1) k e^(-k x / s)
     * (x > 0) and integral_pi^inf e^(-a x) cos(n x) dx = (-1)^n e^(-a pi) a / (a^2 + n^2) */
    double q = exp(-PI / s), qk = 1.0, tail = 0.0;
    for (int k = 1; k < 4000; k++) {
        qk *= q;
        if (qk == 0.0) break;
        double a = k / s;
        double term = (k % 2 ? 1.0 : -1.0) * k * qk * a / (a * a + (double)n * n);
        tail += term;
        if (fabs(term) < 1e-18 * fabs(tail) && k > 3) break;
    }
    tail *= (n % 2 ? -1.0 : 1.0) / s;
    return (full - 2.0 * tail) / tanh(PI / (2.0 * s));
}
