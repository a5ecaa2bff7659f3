/* chiang_sample.c: see chiang_sample.h. */
#include "chiang_sample.h"

#include "deon_ref.h"
#include "fiber_common_d.h"
#include "mp_sample.h"

#include <math.h>

#define PI 3.14159265358979323846

void slref_chiang_bsdf_init(slref_bsdf *b) {
    double mean[4] = {0, 0, 0, 0}, sum = 0;
    for (int c = 0; c < b->nch; c++) {
        slref_chiang_hit_init(b->m, c, b->theta_o, b->h, &b->ck[c]);
        for (int p = 0; p < 4; p++)
            mean[p] += b->ck[c].A[p] / b->nch;
    }
    for (int p = 0; p < 4; p++)
        sum += mean[p];
    for (int p = 0; p < 4; p++) /* A_0 = Fresnel > 0 at every h, so sum > 0 */
        b->ap_pdf[p] = sum > 0 ? mean[p] / sum : (p == 0);
}

/* M_p and N_p of the four lobes at omega_i (the same for every channel). */
static void lobe_mn(const slref_bsdf *b, double theta_i, double phi_i, double mn[4]) {
    double phi = b->phi_o - phi_i;
    for (int p = 0; p < 4; p++) {
        double lm = slref_deon_log_mp(slref_chiang_v(b->m, p), theta_i,
                                      slref_chiang_theta_o_lobe(b->m, p, b->theta_o));
        double np = p < 3 ? slref_chiang_np(b->m, &b->ck[0], p, phi) : 1.0 / (2.0 * PI);
        mn[p] = exp(lm) * np;
    }
}

void slref_chiang_bsdf_eval(const slref_bsdf *b, double theta_i, double phi_i, double f[3],
                            double lobes[SLREF_NLOBES][3]) {
    double mn[4];
    lobe_mn(b, theta_i, phi_i, mn);
    for (int c = 0; c < 3; c++) {
        const slref_chiang_hit *k = &b->ck[c < b->nch ? c : 0];
        f[c] = 0;
        for (int p = 0; p < 4; p++) {
            double v = k->A[p] * mn[p];
            f[c] += v;
            if (lobes) lobes[p][c] = v;
        }
    }
}

double slref_chiang_bsdf_pdf(const slref_bsdf *b, double theta_i, double phi_i) {
    double mn[4], pdf = 0;
    lobe_mn(b, theta_i, phi_i, mn);
    for (int p = 0; p < 4; p++)
        pdf += b->ap_pdf[p] * mn[p];
    return pdf;
}

int slref_chiang_bsdf_sample(const slref_bsdf *b, slref_rng *r, double *theta_i, double *phi_i) {
    double u = slref_rng_unit(r), acc = 0;
    int p = 0; /* the last lobe of non-zero probability, should rounding leave u past the sum */
    for (int q = 0; q < 4; q++)
        if (b->ap_pdf[q] > 0) p = q;
    for (int q = 0; q < 4; q++) {
        acc += b->ap_pdf[q];
        if (u < acc && b->ap_pdf[q] > 0) {
            p = q;
            break;
        }
    }
    double u1 = slref_rng_unit(r), u2 = slref_rng_unit(r), u3 = slref_rng_unit(r);
    *theta_i = slref_mp_sample(slref_chiang_v(b->m, p),
                               slref_chiang_theta_o_lobe(b->m, p, b->theta_o), u1, u2);
    double phi; /* phi_o - phi_i */
    if (p < 3)
        phi = slref_chiang_phi(p, b->ck[0].gamma_o, b->ck[0].gamma_t) +
              slref_sample_trimmed_logistic(u3, b->m->logistic_s);
    else
        phi = 2.0 * PI * u3;
    *phi_i = sld_wrap_pi(b->phi_o - phi);
    return 1;
}
