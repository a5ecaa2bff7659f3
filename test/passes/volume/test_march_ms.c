/* test_march_ms.c: the multiple-scattering response per fragment and lobe
 * (host/passes/volume/volume_ms.c, kernels/ms_response.h) against brute-force 2-D quadrature in
 * double of its definitions (docs/volume.md): M^G = int psi_f f d w_i with f the scattering
 * function of numerics.md sec. 3 (evaluated with the float C twin's sl_marschner_scatter,
 * 1e-5-accurate against the reference), M^L = int psi_f S_back cos theta_i d w_i with S_back of Xu
 * Sec. 4.3.2 taken at every theta_d from the dual tables (not Xu Eq. 31's means). */
#include "test.h"

#include "cl_fixture.h"

#include "fiber_marschner.h"
#include "dual_c.h"
#include "passes/volume/dual_cl.h"
#include "passes/volume/volume_ms.h"
#include "passes/volume/ms_cl.h"

#include <math.h>
#include <stdlib.h>
#include <stdint.h>
#include <string.h>

#define PI 3.14159265358979323846

static double gauss(double x, double m, double s) {
    double d = (x - m) / s;
    return exp(-d * d) / (sqrt(PI) * s);
}

static double wrap(double x) {
    while (x > PI)
        x -= 2 * PI;
    while (x <= -PI)
        x += 2 * PI;
    return x;
}

/* Midpoint sums over theta_i in theta_j +- 5 s_F (clipped to +-pi/2), 120 nodes, and phi_i over
 * the forward half circle phi_j +- pi/2, 180 nodes. */
static void brute(const sl_volume_ms *ms, double to, double po, double tj, double pj, double lam,
                  double sf, double *MG, double *ML) {
    double sF = sqrt(lam * lam + sf * sf);
    double a = fmax(tj - 5 * sF, -PI / 2), b = fmin(tj + 5 * sF, PI / 2);
    const int NT = 120, NP = 180;
    double dt = (b - a) / NT, dp = PI / NP, g = 0, l = 0;
    const float *tab = ms->dt.tab[0];
    for (int i = 0; i < NT; i++) {
        double ti = a + (i + 0.5) * dt, w = gauss(ti, tj, sF) / cos(tj);
        double td = 0.5 * (to - ti), ctd = cos(td);
        double Ab = sl_dual_lookup(tab, SL_DUAL_A_B, (float)td);
        double dB = sl_dual_lookup(tab, SL_DUAL_DELTA_B, (float)td);
        double sB = sl_dual_lookup(tab, SL_DUAL_SIGMA_B, (float)td);
        for (int k = 0; k < NP; k++) {
            double pi_ = pj - PI / 2 + (k + 0.5) * dp;
            float f[4];
            sl_marschner_scatter(&ms->fp[0], (float)ti, (float)wrap(pi_), (float)to, (float)po, f);
            double dw = cos(ti) * dt * dp, psi = w / PI;
            g += psi * f[3] * dw;
            /* S_back = 2 / cos^2 td A_b s_b g(theta_i + theta_o; Delta_b, sigma_b), s_b = 1/pi on
             * cos(phi_i - phi_o) > 0; times cos theta_i. */
            if (cos(pi_ - po) > 0)
                l += psi * 2 / (ctd * ctd) * Ab / PI * gauss(ti + to, dB, sB) * cos(ti) * dw;
        }
    }
    *MG = g;
    *ML = l;
}

TEST(march_ms_response_vs_bruteforce) {
    sl_err e = {{0}};
    sl_material m;
    sl_material_default(&m);
    sl_volume_ms ms;
    CHECK(sl_volume_ms_init(&m, &ms, &e) == 0);
    /* (theta_o, phi_o, theta_j, phi_j, lambda, sigma_f): front, back and side lit, narrow and
     * wide lobes, no spread and a large one. */
    const double cases[][6] = {{0.2, 0.3, -0.1, 2.8, 0.2, 0.0},
                               {0.1, 0.0, 0.3, 0.4, 0.3, 0.15},
                               {-0.4, 1.2, 0.2, -1.0, 0.15, 0.3},
                               {0.5, -2.0, -0.3, 1.9, 0.4, 0.1},
                               {0.0, 0.0, 0.0, 3.0, 0.1, 0.05}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const double *q = cases[i];
        float sf[3] = {(float)q[5], (float)q[5], (float)q[5]}, MG[3], ML[3];
        sl_volume_ms_terms(&ms, (float)q[0], (float)q[1], (float)q[2], (float)q[3], (float)q[4], sf,
                           MG, ML);
        double bg, bl;
        brute(&ms, q[0], q[1], q[2], q[3], q[4], q[5], &bg, &bl);
        if (getenv("SL_TEST_VERBOSE"))
            fprintf(stderr, "  case %zu: MG %.6g (brute %.6g), ML %.6g (brute %.6g)\n", i, MG[0],
                    bg, ML[0], bl);
        /* M^G: 6-point Gauss-Hermite of a smooth N^G and 96 midpoint nodes across the window
         * edges against a 120 x 180 midpoint sum: 3 % relative (or 1e-4 of the scale of f). */
        CHECK_MSG(fabs(MG[0] - bg) <= 0.03 * bg + 1e-4, "case %zu: MG %g vs %g", i, MG[0], bg);
        /* M^L: Xu Eq. 31 replaces Delta_b(theta_d), sigma_b(theta_d) by means over the lobe's
         * support; both vary slowly: 10 %. */
        CHECK_MSG(fabs(ML[0] - bl) <= 0.10 * bl + 1e-5, "case %zu: ML %g vs %g", i, ML[0], bl);
        CHECK(MG[1] == MG[0] && ML[2] == ML[0]); /* grey material */
    }
    sl_volume_ms_free(&ms);
}

TEST(march_ms_response_combination) {
    sl_err e = {{0}};
    sl_material m;
    sl_material_default(&m);
    sl_volume_ms ms;
    CHECK(sl_volume_ms_init(&m, &ms, &e) == 0);
    float Tf[3] = {0.6f, 0.6f, 0.6f}, sf[3] = {0.1f, 0.1f, 0.1f}, MG[3], ML[3], r[3], r0[3];
    sl_volume_ms_terms(&ms, 0.1f, 0.2f, -0.2f, 2.5f, 0.3f, sf, MG, ML);
    sl_volume_ms_response(&ms, 0.1f, 0.2f, -0.2f, 2.5f, 0.3f, Tf, sf, 0.4f, r);
    sl_volume_ms_response(&ms, 0.1f, 0.2f, -0.2f, 2.5f, 0.3f, Tf, sf, 0.0f, r0);
    double P = PI * 0.09 * (1 - exp(-4 / 0.09)); /* int G d w, numerics.md sec. 5 */
    CHECK_REL(r[0], P * (0.2 * MG[0] + 0.7 * 0.6 * ML[0]), 1e-5);
    CHECK_REL(r0[0], P * (0.6 * MG[0] + 0.7 * 0.6 * ML[0]), 1e-5);
    sl_volume_ms_free(&ms);
    /* Deon: its own terms now (kernels/dual_ec.h; this test expected a refusal before), the
     * same combination rule. */
    m.model = SL_MODEL_DEON;
    CHECK(sl_volume_ms_init(&m, &ms, &e) == 0);
    sl_volume_ms_terms(&ms, 0.1f, 0.2f, -0.2f, 2.5f, 0.3f, sf, MG, ML);
    sl_volume_ms_response(&ms, 0.1f, 0.2f, -0.2f, 2.5f, 0.3f, Tf, sf, 0.4f, r);
    CHECK(MG[0] > 0 && ML[0] > 0);
    CHECK_REL(r[0], P * (0.2 * MG[0] + 0.7 * 0.6 * ML[0]), 1e-5);
    sl_volume_ms_free(&ms);
}

/* `ms-material --backend opencl` (kernels/dual.cl, host/passes/volume/dual_cl.c) against the C
 * twin's table: the same float math per node on the device (its sin/cos/exp/asin within a few ulp),
 * the SATs by the same host code: 2e-5 relative or 1e-7 absolute (terms near 0 such as alpha). */
TEST(march_ms_material_opencl_vs_c) {
    sl_err e = {{0}};
    sl_device dev;
    SL_TEST_OPEN_CL(&dev, &e);
    unsigned long k0 = sl_cl_kernels_enqueued();
    sl_material m;
    sl_material_default(&m);
    for (int variant = 0; variant < 2; variant++) {
        if (variant == 1) {
            m.eccentricity = 0.85;
            m.sigma_a[0] = m.sigma_a[1] = m.sigma_a[2] = 1.3;
        }
        sl_fiber_params fp;
        sl_material_to_fiber(&m, 0, &fp);
        enum { N = 200 };
        float in[N], a[9 * N], b[9 * N];
        for (int i = 0; i < N; i++)
            in[i] = (float)(-1.5707963 + 3.1415926 * i / (N - 1));
        CHECK(slcl_ms_material_batch(dev.cl, &fp, N, in, a, &e) == 0);
        slc_ms_material_batch(&fp, N, in, b);
        double worst = 0;
        for (int i = 0; i < 9 * N; i++) {
            double d = fabs(a[i] - b[i]);
            if (d > 1e-7 && d / fabs(b[i]) > worst) worst = d / fabs(b[i]);
        }
        CHECK_CL_RAN(k0);
        CHECK_MSG(worst <= 2e-5, "variant %d: worst relative difference %g", variant, worst);
        /* And the device table's SAT rows equal the twin's sums of its own rows. */
        float ta[SL_DUAL_TABLE_FLOATS], tb[SL_DUAL_TABLE_FLOATS];
        CHECK(slcl_dual_table(dev.cl, &fp, ta, &e) == 0);
        slc_dual_table(&fp, tb);
        CHECK_NEAR(ta[SL_DUAL_SAT_SIGMA_B * SL_DUAL_N + SL_DUAL_N - 1],
                   tb[SL_DUAL_SAT_SIGMA_B * SL_DUAL_N + SL_DUAL_N - 1], 1e-5);
    }
    sl_device_close(&dev);
}

/* kernels/ms.cl against the C side on random rows (view, lobe, width, spread) of an rgb,
 * eccentric material: the same float math; the device's exp/cos/asin within a few ulp, which
 * move the tables' interpolation weights (node positions go through asin): 9.7e-5 measured by
 * `strandlight kernels --only ms` on PoCL, checked 5e-4 relative or 1e-7 absolute. */
TEST(march_ms_response_opencl_vs_c) {
    sl_err e = {{0}};
    sl_device dev;
    SL_TEST_OPEN_CL(&dev, &e);
    unsigned long k0 = sl_cl_kernels_enqueued();
    sl_material m;
    sl_material_default(&m);
    m.sigma_a_rgb = 1;
    m.sigma_a[0] = 0.2;
    m.sigma_a[1] = 0.5;
    m.sigma_a[2] = 1.2;
    m.eccentricity = 0.9;
    sl_volume_ms ms;
    CHECK(sl_volume_ms_init(&m, &ms, &e) == 0);
    enum { N = 300 };
    float in[6 * N], a[2 * N];
    uint64_t s = 3;
    for (int i = 0; i < N; i++) {
        float *r = in + 6 * i;
        for (int k = 0; k < 6; k++) {
            s = s * 6364136223846793005ull + 1442695040888963407ull;
            double u = (double)(s >> 11) * (1.0 / 9007199254740992.0);
            r[k] = (float)(k == 0 || k == 2   ? (u - 0.5) * 2.8
                           : k == 1 || k == 3 ? (u - 0.5) * 6.2
                           : k == 4           ? 0.05 + 0.5 * u
                                              : 0.4 * u);
        }
    }
    for (int ch = 0; ch < 3; ch++) {
        CHECK(slcl_ms_response_rows(dev.cl, &ms, ch, N, in, a, &e) == 0);
        double worst = 0;
        for (int i = 0; i < N; i++) {
            const float *r = in + 6 * i;
            float sf[3] = {r[5], r[5], r[5]}, MG[3], ML[3];
            sl_volume_ms_terms(&ms, r[0], r[1], r[2], r[3], r[4], sf, MG, ML);
            double d0 = fabs(a[2 * i] - MG[ch]), d1 = fabs(a[2 * i + 1] - ML[ch]);
            if (d0 > 1e-7 && d0 / fabs(MG[ch]) > worst) worst = d0 / fabs(MG[ch]);
            if (d1 > 1e-7 && d1 / fabs(ML[ch]) > worst) worst = d1 / fabs(ML[ch]);
        }
        CHECK_MSG(worst <= 5e-4, "channel %d: worst relative difference %g", ch, worst);
    }
    CHECK_CL_RAN(k0);
    sl_volume_ms_free(&ms);
    sl_device_close(&dev);
}
