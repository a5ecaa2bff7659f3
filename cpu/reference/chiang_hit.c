/* chiang_hit.c: the Chiang 2016 fiber at one offset h in double (chiang_hit.h; numerics.md sec. 3
 * "chiang"). Written from the contract and pbrt-v4's published formulas, independently of the
 * float twin (kernels/fiber_chiang.h): the two are checked against each other through `eval`. */
#include "chiang_hit.h"

#include "deon_ref.h"
#include "fiber_common_d.h"

#include <math.h>

#define PI 3.14159265358979323846

static double wrap_pi(double x) {
    x = fmod(x, 2.0 * PI);
    if (x > PI) x -= 2.0 * PI;
    if (x <= -PI) x += 2.0 * PI;
    return x;
}

void slref_chiang_hit_init(const sl_material *m, int ch, double theta_o, double h,
                           slref_chiang_hit *out) {
    if (h > 1.0) h = 1.0;
    if (h < -1.0) h = -1.0;
    slref_chiang_hit_init_gamma(m, ch, theta_o, asin(h), out);
}

void slref_chiang_hit_init_gamma(const sl_material *m, int ch, double theta_o, double gamma_o,
                                 slref_chiang_hit *out) {
    double eta = m->eta;
    double h = sin(gamma_o), cos_go = cos(gamma_o);
    double so = sin(theta_o), co = cos(theta_o);
    /* eta' = sqrt(eta^2 - sin^2 theta_o) / cos theta_o; cos theta_o -> 0 sends eta' to infinity
     * and gamma_t to 0, which the limit of the formulas below handles (sin gamma_t = h / eta'). */
    double sin_gt = h * co / sqrt(eta * eta - so * so);
    double cos_gt = sqrt(fmax(0.0, 1.0 - sin_gt * sin_gt));
    double st = so / eta, ct = sqrt(fmax(0.0, 1.0 - st * st));
    double f = sld_fresnel_exact(eta, co * fabs(cos_go));
    double T = exp(-m->sigma_a[ch] * (2.0 * cos_gt / ct));
    out->gamma_o = gamma_o;
    out->gamma_t = asin(sin_gt);
    out->A[0] = f;
    out->A[1] = (1.0 - f) * (1.0 - f) * T;
    out->A[2] = out->A[1] * T * f;
    double den = 1.0 - T * f;
    out->A[3] = den > 0.0 ? out->A[2] * T * f / den : 0.0;
}

double slref_logistic(double x, double s) {
    x = fabs(x);
    double e = exp(-x / s);
    return e / (s * (1.0 + e) * (1.0 + e));
}

double slref_logistic_cdf(double x, double s) {
    return 1.0 / (1.0 + exp(-x / s));
}

double slref_trimmed_logistic(double x, double s) {
    /* 1 - 2 cdf(-pi) = tanh(pi / (2 s)): no cancellation for small s. */
    return slref_logistic(x, s) / tanh(PI / (2.0 * s));
}

double slref_sample_trimmed_logistic(double u, double s) {
    double a = slref_logistic_cdf(-PI, s);
    double k = 1.0 - 2.0 * a;
    double x = -s * log(1.0 / (u * k + a) - 1.0);
    if (!(x > -PI)) x = -PI;
    if (x > PI) x = PI;
    return x;
}

double slref_chiang_phi(int p, double gamma_o, double gamma_t) {
    return 2.0 * p * gamma_t - 2.0 * gamma_o + p * PI;
}

double slref_chiang_np(const sl_material *m, const slref_chiang_hit *hk, int p, double phi) {
    double d = wrap_pi(phi - slref_chiang_phi(p, hk->gamma_o, hk->gamma_t));
    return slref_trimmed_logistic(d, m->logistic_s);
}

double slref_chiang_theta_o_lobe(const sl_material *m, int p, double theta_o) {
    return p < 3 ? theta_o - 2.0 * m->alpha[p] : theta_o;
}

double slref_chiang_v(const sl_material *m, int p) {
    double b = m->beta[p < 3 ? p : 2];
    return b * b;
}

double slref_chiang_hit_f(const sl_material *m, const slref_chiang_hit *hk, double theta_i,
                          double theta_o, double phi, double out[4]) {
    double sum = 0.0;
    for (int p = 0; p < 4; p++) {
        double mp = exp(slref_deon_log_mp(slref_chiang_v(m, p), theta_i,
                                          slref_chiang_theta_o_lobe(m, p, theta_o)));
        double np = p < 3 ? slref_chiang_np(m, hk, p, phi) : 1.0 / (2.0 * PI);
        out[p] = mp * hk->A[p] * np;
        sum += out[p];
    }
    return sum;
}
