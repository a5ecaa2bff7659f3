/* chiang_fixture.h: model chiang for the tests -- materials spanning the parameter space, and a
 * brute-force double-precision SRBF response written from numerics.md sec. 3-4 over
 * cpu/reference/chiang_hit.c and nothing of the fast path:
 *  - N_p(psi) (p = 0, 1, 2) on a periodic grid of M points by a direct quadrature over the fiber
 *    offset (u = asin h, 10-point Gauss-Legendre panels of the logistic's scale, each node adding
 *    its trimmed logistic to the grid points within 40 s);
 *  - N'_p = int G_ph(phi_i) N_p(phi_o - phi_i) d phi_i by the periodic trapezoid rule on that grid
 *    (spectrally accurate: the grid resolves both the detector and the narrowest lobe);
 *  - I_p = int cos ti G_th M_p N'_p d ti by composite Gauss-Legendre with breakpoints on the
 *    lobe and on every M_p peak (geometric in their widths).
 * About 1e-5 relative (test_srbf_chiang.c checks it against the lambda -> 0 limit and against a
 * doubled resolution); 0.1-0.5 s per row. A test helper, not the contract's reference
 * (cpu/reference/srbf_ref.c). Static inline: every test file includes it into the one
 * unit_tests binary. */
#ifndef SL_TEST_CHIANG_FIXTURE_H
#define SL_TEST_CHIANG_FIXTURE_H

#include "test.h"

#include "chiang_hit.h"
#include "deon_ref.h"
#include "scene/material.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CHB_PI 3.14159265358979323846

/* Materials (JSON, numerics.md sec. 2) spanning chiang's parameters: typical, dark (sigma_a
 * ~ 5..17), blond and narrow, needle-sharp (roughness and radial roughness 0.1), wide (0.8 /
 * 0.9), coated with a large offset, white and maximally rough (sigma_a 0, s = 4.28), middle. */
#define CHB_NMAT 8
static const char *const chb_materials[CHB_NMAT] = {
    "{\"model\": \"chiang\"}",
    "{\"model\": \"chiang\", \"melanin\": 1.0, \"melanin_redness\": 0.3}",
    "{\"model\": \"chiang\", \"melanin\": 0.2, \"roughness\": 0.15, \"radial_roughness\": 0.2}",
    "{\"model\": \"chiang\", \"melanin\": 0.5, \"roughness\": 0.1, \"radial_roughness\": 0.1}",
    "{\"model\": \"chiang\", \"melanin\": 0.3, \"roughness\": 0.8, \"radial_roughness\": 0.9}",
    "{\"model\": \"chiang\", \"melanin\": 0.6, \"coat\": 0.7, \"offset_deg\": 5, \"eta\": 1.6}",
    "{\"model\": \"chiang\", \"sigma_a\": 0, \"roughness\": 1, \"radial_roughness\": 1}",
    "{\"model\": \"chiang\", \"melanin\": 0.4, \"roughness\": 0.5, \"radial_roughness\": 0.6}",
};

static inline int chb_material(int i, sl_material *m) {
    sl_err e = {{0}};
    const char *j = chb_materials[i % CHB_NMAT];
    int rc = sl_material_parse(j, strlen(j), "chiang_fixture", m, &e);
    CHECK_MSG(rc == 0, "%s", e.msg);
    return rc;
}

static inline double chb_wrap(double x) {
    x = fmod(x, 2.0 * CHB_PI);
    if (x > CHB_PI) x -= 2.0 * CHB_PI;
    if (x <= -CHB_PI) x += 2.0 * CHB_PI;
    return x;
}

/* 10-point Gauss-Legendre on [-1, 1]. */
static const double chb_gx[10] = {-0.9739065285171717, -0.8650633666889845, -0.6794095682990244,
                                  -0.4333953941292472, -0.1488743389816312, 0.1488743389816312,
                                  0.4333953941292472,  0.6794095682990244,  0.8650633666889845,
                                  0.9739065285171717};
static const double chb_gw[10] = {0.0666713443086881, 0.1494513491505806, 0.2190863625159820,
                                  0.2692667193099963, 0.2955242247147529, 0.2955242247147529,
                                  0.2692667193099963, 0.2190863625159820, 0.1494513491505806,
                                  0.0666713443086881};

/* N_p(psi_k), psi_k = -pi + k 2pi/M, into N[p * M + k] (p = 0, 1, 2), and E_3 =
 * 1/2 int A_3 dh. */
static inline void chb_np(const sl_material *m, int ch, double theta_o, int M, int res, double *N,
                          double *E3) {
    double s = m->logistic_s, d = 2.0 * CHB_PI / M;
    memset(N, 0, 3 * (size_t)M * sizeof *N);
    *E3 = 0.0;
    double w = fmin(s / 8.0, CHB_PI / 64.0) / res;
    int panels = (int)ceil(CHB_PI / w);
    int win = 40.0 * s < CHB_PI ? (int)ceil(40.0 * s / d) : M / 2;
    for (int q = 0; q < panels; q++) {
        double a = -0.5 * CHB_PI + CHB_PI * q / panels, b = a + CHB_PI / panels;
        for (int j = 0; j < 10; j++) {
            double u = 0.5 * (a + b) + 0.5 * (b - a) * chb_gx[j];
            double wt = 0.5 * (b - a) * chb_gw[j] * cos(u) * 0.5; /* 1/2 dh */
            slref_chiang_hit hk;
            slref_chiang_hit_init(m, ch, theta_o, sin(u), &hk);
            *E3 += wt * hk.A[3];
            for (int p = 0; p < 3; p++) {
                double ph = chb_wrap(slref_chiang_phi(p, hk.gamma_o, hk.gamma_t));
                int c = (int)floor((ph + CHB_PI) / d);
                for (int k = c - win; k <= c + win; k++) {
                    int kk = ((k % M) + M) % M;
                    if (win == M / 2 && k == c + win) break; /* the whole circle once */
                    double x = chb_wrap(-CHB_PI + kk * d - ph);
                    N[p * M + kk] += wt * hk.A[p] * slref_trimmed_logistic(x, s);
                }
            }
        }
    }
}

static int chb_cmp(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* out[0..4] = I_0, I_1, I_2, I_rest, I of channel ch; res 1 normal, 2 doubled resolution. */
static inline void chb_srbf(const sl_material *m, int ch, double theta_o, double phi_o,
                            double theta_j, double phi_j, double lambda, int res, double out[5]) {
    const int M = 4096 * res;
    double *N = malloc(3 * (size_t)M * sizeof *N), E3, d = 2.0 * CHB_PI / M;
    chb_np(m, ch, theta_o, M, res, N, &E3);
    /* breakpoints: the lobe and every M_p peak (-theta_o'_p), geometric in their widths */
    double bp[128];
    int nb = 0;
    static const double off[6] = {0, 0.5, 1, 2, 4, 8};
    bp[nb++] = -0.5 * CHB_PI;
    bp[nb++] = 0.5 * CHB_PI;
    for (int k = 0; k < 6; k++)
        for (int sg = -1; sg <= 1; sg += 2) {
            bp[nb++] = theta_j + sg * off[k] * lambda;
            for (int p = 0; p < 4; p++)
                bp[nb++] = -slref_chiang_theta_o_lobe(m, p, theta_o) +
                           sg * off[k] * sqrt(slref_chiang_v(m, p));
        }
    for (int k = 0; k < nb; k++)
        bp[k] = fmin(fmax(bp[k], -0.5 * CHB_PI), 0.5 * CHB_PI);
    qsort(bp, (size_t)nb, sizeof *bp, chb_cmp);
    memset(out, 0, 5 * sizeof *out);
    double phi0 = chb_wrap(phi_o - phi_j);
    double *cd = malloc((size_t)M * sizeof *cd); /* cos(phi0 - psi_k) - 1 */
    for (int i = 0; i < M; i++)
        cd[i] = cos(phi0 - (-CHB_PI + i * d)) - 1.0;
    for (int k = 0; k + 1 < nb; k++) {
        double a0 = bp[k], b0 = bp[k + 1];
        if (!(b0 > a0)) continue;
        int np = 2 * res + (int)ceil((b0 - a0) / 0.1) * res;
        for (int q = 0; q < np; q++) {
            double a = a0 + (b0 - a0) * q / np, b = a0 + (b0 - a0) * (q + 1) / np;
            for (int j = 0; j < 10; j++) {
                double ti = 0.5 * (a + b) + 0.5 * (b - a) * chb_gx[j], cti = cos(ti);
                if (!(cti > 0.0)) continue;
                double g = 0.5 * (b - a) * chb_gw[j] * cti *
                           exp(2.0 * (cos(ti - theta_j) - 1.0) / (lambda * lambda));
                double mp[4], big = 0.0;
                for (int p = 0; p < 4; p++) {
                    mp[p] = exp(slref_deon_log_mp(slref_chiang_v(m, p), ti,
                                                  slref_chiang_theta_o_lobe(m, p, theta_o)));
                    big = fmax(big, g * mp[p]);
                }
                if (!(big > 1e-300)) continue;
                double kappa = 2.0 * cti * fmax(cos(theta_j), 0.0) / (lambda * lambda);
                double conv[3] = {0, 0, 0}, z = 0.0;
                for (int i = 0; i < M; i++) {
                    double ex = kappa * cd[i];
                    if (ex < -745.0) continue; /* exp underflows to 0 */
                    double gp = exp(ex) * d;
                    z += gp;
                    for (int p = 0; p < 3; p++)
                        conv[p] += gp * N[p * M + i];
                }
                for (int p = 0; p < 3; p++)
                    out[p] += g * mp[p] * conv[p];
                out[3] += g * mp[3] * z * E3 / (2.0 * CHB_PI);
            }
        }
    }
    out[4] = out[0] + out[1] + out[2] + out[3];
    free(cd);
    free(N);
}

/* The width-averaged f (numerics.md sec. 3) of channel ch: out[0..4] = f_0, f_1, f_2, f_rest,
 * f (omega_i = (theta_i, phi_i) toward the light). */
static inline void chb_f(const sl_material *m, int ch, double theta_i, double phi_i, double theta_o,
                         double phi_o, double out[5]) {
    double s = m->logistic_s, w = fmin(s / 16.0, CHB_PI / 256.0);
    int panels = (int)ceil(CHB_PI / w);
    memset(out, 0, 5 * sizeof *out);
    double phi = chb_wrap(phi_o - phi_i);
    for (int q = 0; q < panels; q++) {
        double a = -0.5 * CHB_PI + CHB_PI * q / panels, b = a + CHB_PI / panels;
        for (int j = 0; j < 10; j++) {
            double u = 0.5 * (a + b) + 0.5 * (b - a) * chb_gx[j];
            double wt = 0.5 * (b - a) * chb_gw[j] * cos(u) * 0.5, fp[4];
            slref_chiang_hit hk;
            slref_chiang_hit_init(m, ch, theta_o, sin(u), &hk);
            slref_chiang_hit_f(m, &hk, theta_i, theta_o, phi, fp);
            for (int p = 0; p < 4; p++)
                out[p] += wt * fp[p];
        }
    }
    out[4] = out[0] + out[1] + out[2] + out[3];
}

#endif
