/* marschner_sample.c: see marschner_sample.h. */
#include "marschner_sample.h"

#include "fiber_common_d.h"
#include "marschner_ref.h"

#include <math.h>

#define PI 3.14159265358979323846

static const double VM_K[3] = {0.0, 0.75, 0.0}; /* von Mises share of each lobe's azimuth */
#define VM_KAPPA 4.0                            /* ~0.5 rad wide: TT's core for eta ~ 1.55 */
#define MAX_TRIES 256 /* rejection of theta_h out of range: the mass in range is >= ~0.4 */

double slref_von_mises_pdf(double x, double mu, double kappa) {
    /* exp(kappa cos) / (2 pi I0(kappa)) with the scaled Bessel function: no overflow */
    return exp(kappa * (cos(x - mu) - 1.0)) / (2.0 * PI * slref_i0e(kappa));
}

double slref_von_mises_sample(slref_rng *r, double mu, double kappa) {
    double tau = 1.0 + sqrt(1.0 + 4.0 * kappa * kappa);
    double rho = (tau - sqrt(2.0 * tau)) / (2.0 * kappa);
    double rr = (1.0 + rho * rho) / (2.0 * rho), f = 0;
    for (;;) {
        double u1 = slref_rng_unit(r), u2 = slref_rng_unit(r);
        double z = cos(PI * u1);
        f = (1.0 + rr * z) / (rr + z);
        double c = kappa * (rr - f);
        if (c * (2.0 - c) - u2 > 0.0 || log(c / u2) + 1.0 - c >= 0.0) break;
    }
    if (f > 1) f = 1;
    if (f < -1) f = -1;
    double x = slref_rng_unit(r) < 0.5 ? -acos(f) : acos(f);
    return sld_wrap_pi(x + mu);
}

/* The in-range mass of lobe t's theta_h Gaussian: theta_h in ((theta_o - pi/2)/2, (theta_o +
 * pi/2)/2) is |theta_i| < pi/2. (x - alpha) / beta is the erf argument (std beta / sqrt 2). */
static double range_mass(const sl_material *m, int t, double theta_o) {
    double lo = 0.5 * (theta_o - 0.5 * PI), hi = 0.5 * (theta_o + 0.5 * PI);
    double b = m->beta[t], a = m->alpha[t];
    return 0.5 * (erf((hi - a) / b) - erf((lo - a) / b));
}

void slref_marschner_bsdf_init(slref_bsdf *b) {
    const sl_material *m = b->m;
    double mx = 0, sum = 0;
    for (int t = 0; t < 3; t++) {
        double a = 0;
        for (int c = 0; c < b->nch; c++)
            a += slref_marschner_A(m, c, t, m->eta, b->theta_o, 0.0) / b->nch;
        b->mw[t] = a;
        mx = a > mx ? a : mx;
        b->mz[t] = range_mass(m, t, b->theta_o);
    }
    for (int t = 0; t < 3; t++) {
        if (b->mw[t] < 0.05 * mx || !(b->mw[t] > 0)) b->mw[t] = 0.05 * mx > 0 ? 0.05 * mx : 1.0;
        if (!(b->mz[t] > 1e-12)) b->mw[t] = 0; /* no mass in range: never sampled */
        sum += b->mw[t];
    }
    for (int t = 0; t < 3; t++)
        b->mw[t] = sum > 0 ? b->mw[t] / sum : 0;
}

void slref_marschner_bsdf_eval(const slref_bsdf *b, double theta_i, double phi_i, double f[3],
                               double lobes[SLREF_NLOBES][3]) {
    for (int c = 0; c < b->nch; c++) {
        double out[4];
        slref_marschner_scatter(b->m, c, theta_i, phi_i, b->theta_o, b->phi_o, out);
        f[c] = out[3];
        if (lobes) {
            for (int t = 0; t < 3; t++)
                lobes[t][c] = out[t];
            lobes[SLREF_LOBE_REST][c] = 0;
        }
    }
    for (int c = b->nch; c < 3; c++) {
        f[c] = f[0];
        if (lobes)
            for (int l = 0; l < SLREF_NLOBES; l++)
                lobes[l][c] = lobes[l][0];
    }
}

double slref_marschner_bsdf_pdf(const slref_bsdf *b, double theta_i, double phi_i) {
    double ci = cos(theta_i);
    if (!(ci > 1e-300) || fabs(theta_i) >= 0.5 * PI) return 0.0;
    double th = 0.5 * (theta_i + b->theta_o), phi = b->phi_o - phi_i, pdf = 0;
    for (int t = 0; t < 3; t++) {
        if (!(b->mw[t] > 0)) continue;
        double pphi = (1.0 - VM_K[t]) / (2.0 * PI);
        if (VM_K[t] > 0) pphi += VM_K[t] * slref_von_mises_pdf(phi, PI, VM_KAPPA);
        pdf += b->mw[t] * slref_marschner_M(b->m, t, th) / (2.0 * b->mz[t]) * pphi;
    }
    return pdf / ci;
}

int slref_marschner_bsdf_sample(const slref_bsdf *b, slref_rng *r, double *theta_i, double *phi_i) {
    double u = slref_rng_unit(r), acc = 0;
    int t = -1;
    for (int q = 0; q < 3; q++)
        if (b->mw[q] > 0) t = q;
    if (t < 0) return 0;
    for (int q = 0; q < 3; q++) {
        acc += b->mw[q];
        if (u < acc && b->mw[q] > 0) {
            t = q;
            break;
        }
    }
    const sl_material *m = b->m;
    int ok = 0;
    for (int k = 0; k < MAX_TRIES && !ok; k++) {
        double g = sqrt(-2.0 * log(1.0 - slref_rng_unit(r))) * cos(2.0 * PI * slref_rng_unit(r));
        double th = m->alpha[t] + m->beta[t] / sqrt(2.0) * g;
        double ti = 2.0 * th - b->theta_o;
        if (fabs(ti) < 0.5 * PI) *theta_i = ti, ok = 1;
    }
    if (!ok) return 0; /* probability <= 0.6^256: no measurable bias */
    double phi = slref_rng_unit(r) < VM_K[t] ? slref_von_mises_sample(r, PI, VM_KAPPA)
                                             : 2.0 * PI * slref_rng_unit(r) - PI;
    *phi_i = sld_wrap_pi(b->phi_o - phi);
    return 1;
}
