/* deon_hit.c: see deon_hit.h. */
#include "deon_hit.h"

#include "deon_ref.h"
#include "fiber_common_d.h"
#include "mp_sample.h"

#include <math.h>

#define PI 3.14159265358979323846

/* Order p's width: orders >= 3 use TRT's shift and width (numerics.md sec. 3). */
static double lobe_beta(const sl_material *m, int p) {
    return m->beta[p < 2 ? p : 2];
}

/* Keeps a proposal's theta_d inside (-pi/2, pi/2), where eta' is finite. */
static double clamp_td(double td) {
    return td > 1.5 ? 1.5 : (td < -1.5 ? -1.5 : td);
}

/* gamma_i = asin h and gamma_t = asin(h / eta'(theta_d)) (shared by every order's Phi). */
static void gammas(const sl_material *m, double h, double td, double *gi, double *gt) {
    *gi = asin(sld_clamp_unit(h));
    *gt = asin(sld_clamp_unit(h / sld_eta_prime(m->eta, td)));
}

/* Phi(p, h) = 2 p gamma_t - 2 gamma_i + p pi (sld_phi_of_h with the asin's computed once). */
static double phi_p(int p, double gi, double gt) {
    return 2.0 * p * gt - 2.0 * gi + p * PI;
}

/* M_p of orders 0, 1 and 2 (orders >= 3 and the rest share TRT's lobe: computed once). */
static void lobe_m(const sl_material *m, double theta_i, double theta_o, double mp[3]) {
    for (int p = 0; p < 3; p++) {
        double beta = m->beta[p];
        mp[p] = exp(slref_deon_log_mp(beta * beta, theta_i, theta_o - 2.0 * m->alpha[p]));
    }
}

/* The channel-independent factors of lobe p at omega_i: M_p D_p (p <= orders) and M_TRT / 2pi
 * (the rest, index orders + 1). */
static void lobe_md(const sl_material *m, double h, double theta_i, double theta_o, double phi,
                    double *md) {
    int n = m->orders;
    double td = 0.5 * (theta_o - theta_i), mp[3], gi, gt;
    gammas(m, h, td, &gi, &gt);
    lobe_m(m, theta_i, theta_o, mp);
    for (int p = 0; p <= n; p++) {
        double mv = mp[p < 2 ? p : 2];
        md[p] = mv > 0 ? mv * slref_deon_detector(lobe_beta(m, p), phi - phi_p(p, gi, gt)) : 0.0;
    }
    md[n + 1] = mp[2] / (2.0 * PI);
}

static double hit_f(const sl_material *m, int ch, double h, double theta_i, double theta_o,
                    const double *md, double *out) {
    int n = m->orders;
    double td = 0.5 * (theta_o - theta_i), sum = 0, A[SLREF_DEON_LOBES_MAX];
    slref_deon_attenuations(m, ch, n, td, h, A);
    for (int p = 0; p <= n + 1; p++) {
        double v = md[p] > 0 ? A[p] * md[p] : 0.0;
        if (out) out[p] = v;
        sum += v;
    }
    return sum;
}

double slref_deon_hit_f(const sl_material *m, int ch, double h, double theta_i, double theta_o,
                        double phi, double *out) {
    double md[SLREF_DEON_LOBES_MAX];
    lobe_md(m, h, theta_i, theta_o, phi, md);
    return hit_f(m, ch, h, theta_i, theta_o, md, out);
}

void slref_deon_bsdf_init(slref_bsdf *b) {
    const sl_material *m = b->m;
    int n = m->orders;
    double w[3] = {0, 0, 0}, sum = 0, A[SLREF_DEON_LOBES_MAX];
    for (int q = 0; q < 3; q++) { /* lobe q's M, with TRT's holding orders >= 2 and the rest */
        double td = clamp_td(b->theta_o - m->alpha[q]);
        for (int c = 0; c < b->nch; c++) {
            slref_deon_attenuations(m, c, n, td, b->h, A);
            for (int p = 0; p <= n + 1; p++)
                if ((p < 2 ? p : 2) == q) w[q] += A[p] / b->nch;
        }
        sum += w[q];
    }
    for (int q = 0; q < 3; q++) /* A(0) = Fresnel > 0 at every h: sum > 0 */
        b->dw[q] = sum > 0 ? w[q] / sum : (q == 0);
}

/* The azimuth stage at a sampled theta_i: the lobes' weights c_p = mean_c A(p, h, theta_d)
 * M_p(theta_i) (normalised; index orders + 1 the rest) and their centres Phi(p, h) at the true
 * theta_d. Returns the sum of the unnormalised weights. */
static double azimuth_stage(const slref_bsdf *b, double theta_i, double *cw, double *ctr) {
    const sl_material *m = b->m;
    int n = m->orders;
    double td = 0.5 * (b->theta_o - theta_i), mp[3], sum = 0, gi, gt;
    double A[SLREF_DEON_LOBES_MAX], a[SLREF_DEON_LOBES_MAX] = {0};
    gammas(m, b->h, td, &gi, &gt);
    lobe_m(m, theta_i, b->theta_o, mp);
    for (int c = 0; c < b->nch; c++) {
        slref_deon_attenuations(m, c, n, td, b->h, A);
        for (int p = 0; p <= n + 1; p++)
            a[p] += A[p] / b->nch;
    }
    for (int p = 0; p <= n + 1; p++) {
        cw[p] = a[p] * mp[p < 2 ? p : 2];
        ctr[p] = p <= n ? phi_p(p, gi, gt) : 0.0;
        sum += cw[p];
    }
    for (int p = 0; p <= n + 1; p++)
        cw[p] = sum > 0 ? cw[p] / sum : 0;
    return sum;
}

/* The density of the longitudinal stage: sum_q w_q M_q(theta_i) (M_q cos theta_i integrates to
 * 1 over theta_i; per solid angle the azimuth stage's density in phi multiplies it). */
static double theta_density(const slref_bsdf *b, double theta_i) {
    double mp[3];
    lobe_m(b->m, theta_i, b->theta_o, mp);
    return b->dw[0] * mp[0] + b->dw[1] * mp[1] + b->dw[2] * mp[2];
}

void slref_deon_bsdf_eval(const slref_bsdf *b, double theta_i, double phi_i, double f[3],
                          double lobes[SLREF_NLOBES][3]) {
    const sl_material *m = b->m;
    double md[SLREF_DEON_LOBES_MAX], out[SLREF_DEON_LOBES_MAX];
    lobe_md(m, b->h, theta_i, b->theta_o, b->phi_o - phi_i, md);
    for (int c = 0; c < b->nch; c++) {
        f[c] = hit_f(m, c, b->h, theta_i, b->theta_o, md, out);
        if (!lobes) continue;
        for (int l = 0; l < SLREF_NLOBES; l++)
            lobes[l][c] = 0;
        for (int p = 0; p <= m->orders + 1; p++)
            lobes[p < 3 ? p : SLREF_LOBE_REST][c] += out[p];
    }
    for (int c = b->nch; c < 3; c++) {
        f[c] = f[0];
        if (lobes)
            for (int l = 0; l < SLREF_NLOBES; l++)
                lobes[l][c] = lobes[l][0];
    }
}

double slref_deon_bsdf_pdf(const slref_bsdf *b, double theta_i, double phi_i) {
    const sl_material *m = b->m;
    int n = m->orders;
    double cw[SLREF_DEON_LOBES_MAX], ctr[SLREF_DEON_LOBES_MAX];
    double pt = theta_density(b, theta_i);
    if (!(pt > 0) || !(azimuth_stage(b, theta_i, cw, ctr) > 0)) return 0;
    double phi = b->phi_o - phi_i, pp = 0;
    for (int p = 0; p <= n; p++)
        if (cw[p] > 0) pp += cw[p] * slref_deon_detector(lobe_beta(m, p), phi - ctr[p]);
    return pt * (pp + cw[n + 1] / (2.0 * PI));
}

/* Index of the interval of u in the normalised weights w[0..k-1]; the last non-zero one should
 * rounding leave u past their sum. */
static int pick(const double *w, int k, double u) {
    int last = 0;
    double acc = 0;
    for (int q = 0; q < k; q++) {
        if (!(w[q] > 0)) continue;
        last = q;
        acc += w[q];
        if (u < acc) return q;
    }
    return last;
}

int slref_deon_bsdf_sample(const slref_bsdf *b, slref_rng *r, double *theta_i, double *phi_i) {
    const sl_material *m = b->m;
    int n = m->orders;
    /* longitudinal stage: which M (R, TT, TRT and above), then theta_i from it exactly */
    int q = pick(b->dw, 3, slref_rng_unit(r));
    double beta = m->beta[q];
    double u1 = slref_rng_unit(r), u2 = slref_rng_unit(r);
    *theta_i = slref_mp_sample(beta * beta, b->theta_o - 2.0 * m->alpha[q], u1, u2);
    /* azimuth stage: a lobe by its true weight at this theta_i, phi around its true centre */
    double cw[SLREF_DEON_LOBES_MAX], ctr[SLREF_DEON_LOBES_MAX];
    if (!(azimuth_stage(b, *theta_i, cw, ctr) > 0)) return 0;
    int p = pick(cw, n + 2, slref_rng_unit(r));
    double phi; /* phi_o - phi_i */
    if (p <= n) {
        /* Box-Muller; 1 - u keeps the log finite */
        double g = sqrt(-2.0 * log(1.0 - slref_rng_unit(r))) * cos(2.0 * PI * slref_rng_unit(r));
        phi = ctr[p] + lobe_beta(m, p) * g;
    } else {
        phi = 2.0 * PI * slref_rng_unit(r);
    }
    *phi_i = sld_wrap_pi(b->phi_o - phi);
    return 1;
}
