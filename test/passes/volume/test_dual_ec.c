/* test_dual_ec.c: the dual-scattering and N^G terms of the energy-conserving models (deon,
 * chiang; kernels/dual_ec.h, docs/dual.md "Energy-conserving models"): the float form (Fourier
 * series of the weights over the width, in h) against the double reference (dual_ref.c: adaptive
 * quadrature over phi of the model's own reference N_p, deon_ref.c / chiang_ref.c), the energy
 * identity a_f + a_b = the model's albedo at sigma_a 0, and the N^G window integral against the
 * same reference N_p integrated over the window. */
#include "test.h"

#include "chiang_ref.h"
#include "deon_ref.h"
#include "dual_c.h"
#include "dual_ref.h"
#include "ms_response.h"
#include "quad.h"
#include "scene/material.h"

#include <math.h>
#include <stdlib.h>

#define EPI 3.14159265358979323846

/* Materials: typical, rough, and narrow enough that the kernel is taken as sharp. */
static void ec_material(int which, sl_material *m, double sigma_a) {
    sl_material_default(m);
    if (which < 3) {
        m->model = SL_MODEL_CHIANG;
        const double rough[3] = {0.3, 0.9, 0.02}, radial[3] = {0.3, 0.8, 0.01};
        m->chiang.roughness = rough[which];
        m->chiang.radial_roughness = radial[which];
        sl_chiang_derive(m);
    } else {
        m->model = SL_MODEL_DEON;
        const double b[3] = {6.0, 20.0, 0.8}; /* degrees; 0.8: a sharp detector */
        for (int p = 0; p < 3; p++)
            m->beta[p] = b[which - 3] * (p == 2 ? 2.0 : 1.0) * EPI / 180.0;
        m->orders = which == 4 ? 4 : 2;
    }
    for (int c = 0; c < 3; c++)
        m->sigma_a[c] = sigma_a;
    m->sigma_a_rgb = 0;
}

/* sigma_a = 0: every order's energy together is 1 (both models conserve energy), so
 * a_f + a_b = 1 at every theta_d. Float Gauss-Legendre over the width (96 nodes) on a smooth
 * A_p: 1e-4. */
TEST(dual_ec_energy_sigma0) {
    const float tds[] = {0.0f, 0.4f, 0.9f, 1.3f, 1.52f};
    for (int w = 0; w < 6; w++) {
        sl_material m;
        ec_material(w, &m, 0.0);
        sl_fiber_params fp;
        sl_material_to_fiber(&m, 0, &fp);
        sl_dual_kern *k = malloc(sizeof *k);
        sl_dual_kern_init(&fp, k);
        for (int i = 0; i < 5; i++) {
            float out[9];
            sl_dual_terms_k(&fp, tds[i], k, out);
            CHECK_MSG(fabs(out[0] + out[1] - 1.0) < 1e-4, "material %d td %g: a_f + a_b = %.7g", w,
                      (double)tds[i], (double)(out[0] + out[1]));
        }
        free(k);
    }
}

/* The C table (eval ms-material --backend c, the renderer) against the reference. Tolerances
 * as test_dual.c's for Marschner (table interpolation, float): attenuations and A_b 3e-3
 * relative + 1e-6; angles 3e-4 rad + 3e-3 relative. The sharp cases (kernel width 0.01-0.014
 * rad) drop the smoothing: a further kernel width / pi = 5e-3 on the attenuations. */
TEST(dual_ec_table_vs_reference) {
    const double tds[] = {0.0, 0.37, 0.81, 1.33, 1.55};
    const double sig[] = {0.0, 0.4, 2.0};
    for (int w = 0; w < 6; w++) {
        int sharp = w == 2 || w == 5;
        sl_material m;
        ec_material(w, &m, sig[w % 3]);
        sl_fiber_params fp;
        sl_material_to_fiber(&m, 0, &fp);
        float in[5], fo[5 * 9];
        for (int i = 0; i < 5; i++)
            in[i] = (float)tds[i];
        slc_ms_material_batch(&fp, 5, in, fo);
        for (int i = 0; i < 5; i++) {
            double out[9];
            slref_dual_terms(&m, 0, tds[i], out);
            for (int q = 0; q < 9; q++) {
                int angle = q >= 2 && q != 6;
                double rel = sharp ? 8e-3 : 3e-3;
                double tol = angle ? 3e-4 + rel * fabs(out[q]) : rel * fabs(out[q]) + 1e-6;
                CHECK_MSG(fabs(fo[i * 9 + q] - out[q]) <= tol,
                          "material %d td %g term %d: c %.9g ref %.9g", w, tds[i], q,
                          (double)fo[i * 9 + q], out[q]);
            }
        }
    }
}

/* N^G_t(D) = 1/pi integral_{D - pi/2}^{D + pi/2} N_t(x) dx by adaptive quadrature of the
 * reference N_p (every order folded into TRT, the uniform rest as E / 2 pi). */
typedef struct ng_ctx {
    const sl_material *m;
    int p;
    double td;
} ng_ctx;

static double ng_np(double x, void *v) {
    const ng_ctx *c = v;
    return c->m->model == SL_MODEL_DEON ? slref_deon_np(c->m, 0, c->p, c->td, x)
                                        : slref_chiang_azimuthal(c->m, 0, c->p, c->td, x);
}

static double ng_reference(const sl_material *m, int t, double td, double D) {
    int n = m->model == SL_MODEL_DEON ? m->orders : 2;
    double pts[17], err, sum = 0.0;
    for (int k = 0; k <= 16; k++)
        pts[k] = D - EPI / 2 + EPI * k / 16.0;
    for (int p = t; p <= (t < 2 ? t : n); p++) {
        ng_ctx c = {m, p, td};
        sum +=
            slq_integrate_pts(ng_np, &c, D - EPI / 2, D + EPI / 2, pts, 17, 1e-8, 1e-12, 30, &err);
    }
    if (t == 2) {
        double rest = m->model == SL_MODEL_DEON ? slref_deon_energy_rest(m, 0, td)
                                                : slref_chiang_energy(m, 0, 3, td);
        sum += rest / 2.0; /* uniform: half of it in a half circle */
    }
    return sum / EPI;
}

/* The float rows (sl_ec_NG_row, what the response table reads) against it: 2e-3 relative +
 * 1e-5 (float Fourier sums of up to 128 terms; the sharp case's window edges, a 32-panel
 * quadrature of a discontinuous weight: 2e-2 relative + 1e-4). */
TEST(dual_ec_ng_vs_reference) {
    const int nd = 9;
    const double tds[] = {0.1, 0.9, 1.4};
    for (int w = 0; w < 6; w += 1) {
        if (w == 1 || w == 4) continue; /* the typical and narrow cases of each model */
        int sharp = w == 2 || w == 5;
        sl_material m;
        ec_material(w, &m, 0.3);
        sl_fiber_params fp;
        sl_material_to_fiber(&m, 0, &fp);
        sl_dual_kern *k = malloc(sizeof *k);
        sl_dual_kern_init(&fp, k);
        for (int t = 0; t < 3; t++)
            for (int i = 0; i < 3; i++) {
                float row[9];
                sl_ec_NG_row(&fp, t, (float)tds[i], k->rho + t * SL_DUAL_MAXJ, k->nj[t], nd, row);
                for (int d = 0; d < nd; d += 2) {
                    double D = EPI * d / (nd - 1), ref = ng_reference(&m, t, tds[i], D);
                    double tol = sharp ? 2e-2 * ref + 1e-4 : 2e-3 * ref + 1e-5;
                    CHECK_MSG(fabs(row[d] - ref) <= tol,
                              "material %d mode %d td %g D %g: float %.7g ref %.7g", w, t, tds[i],
                              D, (double)row[d], ref);
                }
            }
        free(k);
    }
}
