/* test_srbf.c: the SRBF response (numerics.md sec. 4; docs/srbf.md). The exact reference is
 * checked against independent computations that share none of its machinery: a brute-force
 * tensor Gauss-Legendre product quadrature over the sphere of G times the reference scattering
 * function (slref_marschner_scatter / slref_deon_scatter, numerics.md sec. 3), the lambda -> 0
 * limit I -> (int G) f(omega_j, omega_o), and the pole, where the answer cannot depend on phi_j.
 * The tables are checked against closed forms (C_2 via Bessel ratios) and an independent
 * quadrature; Xu's closed form against the exact reference on a small stiff sample. */
#include "test.h"

#include "srbf_stiff_fixture.h"

#include "deon_ref.h"
#include "marschner_ref.h"
#include "scene/material.h"
#include "srbf_c.h"
#include "srbf_ref.h"
#include "passes/shade/srbf_tables.h"
#include "srbf_fast.h"
#include "srbf_xu.h"
#include "verify/report/report_srbf.h"

#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

static void gl_nodes(int n, double *x, double *w) {
    for (int i = 0; i < n; i++) {
        double z = cos(PI * (i + 0.75) / (n + 0.5)), pp = 1.0;
        for (int it = 0; it < 100; it++) {
            double p1 = 1.0, p2 = 0.0;
            for (int j = 1; j <= n; j++) {
                double p3 = p2;
                p2 = p1;
                p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
            }
            pp = n * (z * p1 - p2) / (z * z - 1.0);
            double z1 = z;
            z = z1 - p1 / pp;
            if (fabs(z - z1) < 1e-15) break;
        }
        x[i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * pp * pp);
    }
}

static double lobe_G(double ti, double pi_, double tj, double pj, double lambda) {
    double d = sin(ti) * sin(tj) + cos(ti) * cos(tj) * cos(pi_ - pj);
    return exp(2.0 * (d - 1.0) / (lambda * lambda));
}

/* Brute force: sum over a tensor grid (theta: nt equal panels, phi: np equal panels starting at
 * phi_o, so that phi = 0 and phi = pi, where R and TT have kinks, are panel ends) of
 * G f cos(theta_i), ng-point Gauss-Legendre per panel. nout outputs of the scatter function. */
static void brute(const sl_material *m, double to, double po, double tj, double pj, double lambda,
                  int nt, int np, int ng, int nout, double *res) {
    double gx[16], gw[16];
    gl_nodes(ng, gx, gw);
    double *f = malloc((size_t)nout * sizeof *f);
    for (int k = 0; k < nout; k++)
        res[k] = 0.0;
    for (int a = 0; a < nt; a++)
        for (int i = 0; i < ng; i++) {
            double h = 0.5 * PI / nt, ti = -0.5 * PI + h * (2 * a + 1) + h * gx[i];
            double wt = gw[i] * h * cos(ti);
            for (int b = 0; b < np; b++)
                for (int j = 0; j < ng; j++) {
                    double hp = PI / np, pi_ = po - PI + hp * (2 * b + 1) + hp * gx[j];
                    double w = wt * gw[j] * hp * lobe_G(ti, pi_, tj, pj, lambda);
                    double pw = pi_ > PI ? pi_ - 2 * PI : (pi_ <= -PI ? pi_ + 2 * PI : pi_);
                    if (m->model == SL_MODEL_DEON)
                        slref_deon_scatter(m, 0, ti, pw, to, po, f);
                    else
                        slref_marschner_scatter(m, 0, ti, pw, to, po, f);
                    for (int k = 0; k < nout; k++)
                        res[k] += w * f[k];
                }
        }
    free(f);
}

/* Wide lobes (lambda >= 0.8, beta_R = 15 deg) so the brute-force grid (20 x 24 panels of 8-point
 * Gauss-Legendre) is itself accurate to ~1e-4; tolerance 2e-3 in the error measure of
 * numerics.md sec. 5 leaves room for the brute force, not for a wrong formula (a missing
 * cos theta_i, a wrong lambda' or a mirrored phi change I by 10 % or more). */
TEST(srbf_ref_marschner_vs_bruteforce) {
    sl_material m;
    sl_material_default(&m);
    m.beta[0] = 15.0 * PI / 180.0;
    m.beta[1] = 7.5 * PI / 180.0;
    m.beta[2] = 30.0 * PI / 180.0;
    const double cases[2][5] = {{0.3, 0.5, 0.2, 0.4, 0.8}, {-0.6, 2.5, 0.9, -2.9, 1.2}};
    for (int c = 0; c < 2; c++) {
        const double *q = cases[c];
        double ex[4], bf[4];
        slref_srbf(&m, 0, q[0], q[1], q[2], q[3], q[4], ex);
        brute(&m, q[0], q[1], q[2], q[3], q[4], 20, 24, 8, 4, bf);
        for (int k = 0; k < 4; k++)
            CHECK_MSG(slref_srbf_error(ex[k], bf[k], q[4]) < 2e-3,
                      "case %d output %d: exact %.9g brute force %.9g", c, k, ex[k], bf[k]);
    }
}

/* d'Eon (orders 2, wide lobes): the exact path uses a Fourier series of the azimuthal kernel,
 * the brute force d'Eon's N_p by quadrature: nothing shared but A(p, h). Same tolerance. */
TEST(srbf_ref_deon_vs_bruteforce) {
    sl_material m;
    sl_material_default(&m);
    m.model = SL_MODEL_DEON;
    m.orders = 2;
    m.beta[0] = 20.0 * PI / 180.0;
    m.beta[1] = 15.0 * PI / 180.0;
    m.beta[2] = 25.0 * PI / 180.0;
    double q[5] = {0.4, -1.0, -0.1, 0.9, 1.0};
    double ex[5], bf[5];
    slref_srbf(&m, 0, q[0], q[1], q[2], q[3], q[4], ex);
    brute(&m, q[0], q[1], q[2], q[3], q[4], 8, 12, 8, 5, bf);
    for (int k = 0; k < 5; k++)
        CHECK_MSG(slref_srbf_error(ex[k], bf[k], q[4]) < 2e-3, "output %d: exact %.9g brute %.9g",
                  k, ex[k], bf[k]);
}

/* lambda -> 0: I_t / int G -> f_t(omega_j, omega_o). At lambda = 0.005 the O(lambda^2) bias is
 * about lambda^2/4 |f''/f| <= 1e-3 for these lobes (widths >= 0.13 rad): tolerance 3e-3. A lobe
 * this narrow (G falls to e^-1 within 0.3 degrees) is missed entirely by a quadrature that does
 * not place its nodes on it. */
TEST(srbf_ref_narrow_lobe_limit) {
    sl_material m;
    sl_material_default(&m);
    const double cases[2][4] = {{0.3, 0.5, -0.2, 0.5 - 0.35}, {0.2, 0.1, -0.1, 0.1 - 2.8}};
    double lambda = 0.005;
    for (int c = 0; c < 2; c++) {
        const double *q = cases[c];
        double ex[4], f[4];
        slref_srbf(&m, 0, q[0], q[1], q[2], q[3], lambda, ex);
        slref_marschner_scatter(&m, 0, q[2], q[3], q[0], q[1], f);
        double ig = slref_srbf_lobe_integral(lambda);
        for (int k = 0; k < 4; k++)
            if (f[k] > 1e-3 * f[3])
                CHECK_MSG(fabs(ex[k] / ig - f[k]) <= 3e-3 * f[k],
                          "case %d output %d: I/intG %.9g f %.9g", c, k, ex[k] / ig, f[k]);
    }
}

/* A lobe at the pole theta_j = pi/2: phi_j names no direction, so the answer must not depend on
 * it (to the quadrature's 1e-7), and a lobe 1e-7 rad off the pole gives the same to 1e-5. */
TEST(srbf_ref_pole) {
    sl_material m;
    sl_material_default(&m);
    double a[4], b[4], c[4];
    slref_srbf(&m, 0, -1.2, 0.5, 0.5 * PI, 0.3, 0.3, a);
    slref_srbf(&m, 0, -1.2, 0.5, 0.5 * PI, -2.0, 0.3, b);
    slref_srbf(&m, 0, -1.2, 0.5, 0.5 * PI - 1e-7, 2.9, 0.3, c);
    CHECK(a[3] > 0.0);
    for (int k = 0; k < 4; k++) {
        CHECK(isfinite(a[k]));
        CHECK_NEAR(a[k], b[k], 1e-7 * a[3]);
        CHECK_NEAR(a[k], c[k], 1e-5 * a[3]);
    }
}

/* Normalised C_2 = mean of cos^2((phi - x)/2) = (1 + cos(phi) I1(k)/I0(k)) / 2 under the von Mises
 * weight of concentration k = 2/lambda^2 (series for I0, I1: independent of the table code). */
static double bessel_ratio(double k) {
    double q = 0.25 * k * k, t0 = 1.0, s0 = 1.0, t1 = 0.5 * k, s1 = 0.5 * k;
    for (int j = 1; j < 400; j++) {
        t0 *= q / ((double)j * j);
        t1 *= q / ((double)j * (j + 1));
        s0 += t0;
        s1 += t1;
    }
    return s1 / s0;
}

TEST(srbf_tables_closed_forms) {
    const double lams[3] = {0.3, 1.0, 3.0}, phis[3] = {0.0, 1.1, 3.0};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double want = 0.5 * (1.0 + cos(phis[j]) * bessel_ratio(2.0 / (lams[i] * lams[i])));
            CHECK_NEAR(sl_srbf_C_exact(2, lams[i], phis[j]), want, 1e-10);
            CHECK_NEAR(sl_srbf_C_exact(0, lams[i], phis[j]), 1.0, 1e-12);
        }
    /* H_0^TT with Schlick at theta_d = 0: (1 - F)^2 with F = F0 + (1-F0)(1 - sqrt(1-h^2))^5, by
     * a midpoint rule in u = asin h with 200000 steps (error ~1e-10). */
    double eta = 1.55, f0 = pow((eta - 1) / (eta + 1), 2), s = 0.0;
    int n = 200000;
    for (int i = 0; i < n; i++) {
        double u = -0.5 * PI + PI * (i + 0.5) / n, c = cos(u);
        double F = f0 + (1 - f0) * pow(1 - c, 5);
        s += (1 - F) * (1 - F) * c * PI / n;
    }
    CHECK_NEAR(sl_srbf_H_exact(1, 0, 0, eta, 0.0), s, 1e-8);
}

/* The float tables (built here, not from the cache) interpolate the exact functions: 0.5 % of
 * C_k's range and the stated errors are honest (recomputed at a few off-grid points). */
TEST(srbf_tables_interpolation) {
    sl_srbf_tables t;
    sl_srbf_tables_build(&t);
    CHECK(t.err_C < 5e-3);
    CHECK(t.build_s_C > 0.0 && t.build_s_H > 0.0);
    const double pts[3][2] = {{0.05, 0.7}, {0.5, 2.0}, {2.2, 0.1}};
    for (int i = 0; i < 3; i++) {
        float got[7];
        sl_srbf_C(t.C, (float)pts[i][0], (float)pts[i][1], got);
        for (int k = 0; k < 7; k++)
            CHECK_NEAR(got[k], sl_srbf_C_exact(k, pts[i][0], pts[i][1]), t.err_C + 1e-5);
    }
    float h[3];
    sl_srbf_H(t.H, 0, 1, 1.55f, 0.4f, h);
    CHECK_NEAR(h[0], sl_srbf_H_exact(0, 1, 0, 1.55, 0.4),
               1e-3 * sl_srbf_H_exact(0, 1, 0, 1.55, 0.4));
    sl_srbf_tables_free(&t);
}

/* Xu's quadrature with m = 1 has its only nodes at +-pi/2 where cos^2 theta_i = 0: exactly 0
 * (the finding; a check that our node placement is the printed one). With m = 4 on easy
 * configurations (lambda 0.5-0.6, default hair) R is within 15 % (Schlick against the exact
 * Fresnel of the reference accounts for ~8 %) and the total within 30 % (TT's single Gaussian
 * leaks where the exact TT is ~0: 25 % on row 2): loose on purpose, these are Xu's own
 * approximations (docs/srbf.md); a factor-2 or mirrored-phi bug fails them. */
TEST(srbf_xu_vs_exact) {
    sl_srbf_tables t;
    sl_err e = {{0}};
    CHECK(sl_srbf_tables_get(&t, 0, &e) == 0); /* cached: the build is tested above */
    sl_material m;
    sl_material_default(&m);
    sl_fiber_params fp;
    sl_material_to_fiber(&m, 0, &fp);
    const float rows[3][5] = {{0.3f, 0.5f, 0.2f, 0.4f, 0.5f},
                              {0.1f, 0.2f, -0.3f, 2.9f, 0.5f},
                              {-0.4f, 1.0f, 0.3f, 0.1f, 0.6f}};
    float o1[12], o4[12];
    slc_srbf_batch(&fp, t.C, t.H, SL_SRBF_METHOD_XU, 1, 3, &rows[0][0], o1);
    slc_srbf_batch(&fp, t.C, t.H, SL_SRBF_METHOD_XU, 4, 3, &rows[0][0], o4);
    for (int r = 0; r < 3; r++) {
        for (int k = 0; k < 4; k++)
            CHECK(o1[4 * r + k] == 0.0f);
        double ex[4];
        slref_srbf(&m, 0, rows[r][0], rows[r][1], rows[r][2], rows[r][3], rows[r][4], ex);
        CHECK_MSG(slref_srbf_error(o4[4 * r + 3], ex[3], rows[r][4]) < 0.3,
                  "row %d: xu %.6g exact %.6g", r, o4[4 * r + 3], ex[3]);
        CHECK_MSG(slref_srbf_error(o4[4 * r], ex[0], rows[r][4]) < 0.15,
                  "row %d: xu R %.6g exact %.6g", r, o4[4 * r], ex[0]);
    }
    sl_srbf_tables_free(&t);
}

/* ---- the fast path (kernels/srbf_fast.h) ---- */

/* The W table (tabulated exact azimuthal convolutions, docs/srbf.md "fast") against a direct
 * quadrature of its definition that shares no code with the Fourier-space build (midpoint rule
 * in u, 0.4 M steps, exact int g^c): at lambda >= 0.3 (what TRT always uses, lambda3 >= w_c,
 * and TT's usual range), within 1.5 % of the largest weight at that point plus 2e-3 absolute --
 * the table's stated trilinear error is 13 % of max |W| overall but is reached only at lambda
 * 0.02-0.05 next to caustics. */
TEST(srbf_fast_W_table) {
    sl_srbf_tables t;
    sl_err e = {{0}};
    CHECK(sl_srbf_tables_get(&t, 0, &e) == 0);
    CHECK(t.err_W > 0.0 && t.err_W < 0.2);
    const double pts[4][4] = {
        {0, 0.6, 0.5, 3.0}, {0, 0.3, 1.0, 2.0}, {1, 0.55, 0.4, 1.2}, {1, 0.62, 0.3, 0.4}};
    for (int p = 0; p < 4; p++) {
        float got[SL_SRBF_W_NODES];
        sl_srbf_W(t.H, (int)pts[p][0], (float)pts[p][1], (float)pts[p][2], (float)pts[p][3], got);
        double want[SL_SRBF_W_NODES], big = 0.0;
        for (int i = 0; i < SL_SRBF_W_NODES; i++) {
            want[i] = sl_srbf_W_exact((int)pts[p][0], i, pts[p][1], pts[p][2], pts[p][3]);
            big = fmax(big, fabs(want[i]));
        }
        for (int i = 0; i < SL_SRBF_W_NODES; i++)
            CHECK_MSG(fabs(got[i] - want[i]) < 0.015 * big + 2e-3, "pt %d W_%d %.6g want %.6g", p,
                      i, got[i], want[i]);
    }
    sl_srbf_tables_free(&t);
}

/* The targets for --method fast on the stiff sample (host/verify/report/srbf_sample.c, seed
 * SL_SRBF_SAMPLE_SEED, 150 configurations): median <= 1 % and 95th percentile <= 10 % of the
 * error of numerics.md sec. 5 on the total I, against exact values that the double reference
 * (cpu/reference/srbf_ref.c, independent adaptive quadrature) wrote to test/test_srbf_stiff.csv
 * with `strandlight report --kernel srbf --device none --write-exact test/test_srbf_stiff.csv`
 * (eccentric rows take seconds each, hence the file). The file is first checked against the
 * reference recomputed here on four non-eccentric rows (1e-6 relative: the reference's own
 * tolerance is 1e-7, and it is deterministic). Measured: median 0.0051, p95 0.037, max 0.069;
 * above the floor (96 rows) median 0.0065, p95 0.047. Xu
 * as printed (m = 4) is checked to stay as measured (median 0.030, p95 0.227) within loose upper
 * bounds (0.05, 0.35): a regression detector, not a target. */
TEST(srbf_fast_targets_stiff_sample) {
    enum { N = SRBF_STIFF_N };
    sl_srbf_config *cfg;
    sl_srbf_exact *x;
    int rc = srbf_stiff_read(&cfg, &x);
    sl_err e = {{0}};
    sl_srbf_tables t;
    CHECK(sl_srbf_tables_get(&t, 0, &e) == 0);
    if (rc == 0) {
        const int spot[4] = {0, 11, 52, 133};
        for (int s = 0; s < 4; s++) {
            const sl_srbf_config *c = cfg + spot[s];
            CHECK(c->material != 4);
            sl_material m;
            sl_srbf_sample_material(c->material, &m);
            double ex[4];
            slref_srbf(&m, 0, c->theta_o, c->phi_o, c->theta_j, c->phi_j, c->lambda, ex);
            for (int k = 0; k < 4; k++)
                CHECK_NEAR(ex[k], x[spot[s]].v[k], 1e-6 * ex[3] + 1e-300);
        }
        float *out = malloc(N * 4 * sizeof *out);
        for (int method = 0; method < 2; method++) {
            for (int i = 0; i < N; i++) {
                sl_material m;
                sl_srbf_sample_material(cfg[i].material, &m);
                sl_fiber_params fp;
                sl_material_to_fiber(&m, 0, &fp);
                float in[5];
                sl_srbf_config_row(cfg + i, in);
                slc_srbf_batch(&fp, t.C, t.H, method == 0 ? SL_SRBF_METHOD_FAST : SL_SRBF_METHOD_XU,
                               4, 1, in, out + 4 * i);
            }
            sl_srbf_stats st;
            sl_srbf_stats_of(x, N, out, &st);
            if (method == 0) {
                CHECK_MSG(st.median[3] <= 0.01, "fast median %.4f", st.median[3]);
                CHECK_MSG(st.p95[3] <= 0.10, "fast p95 %.4f", st.p95[3]);
                for (int k = 0; k < 3; k++) /* every mode meets the p95 target too */
                    CHECK_MSG(st.p95[k] <= 0.10, "fast mode %d p95 %.4f", k, st.p95[k]);
                /* and so do the 96 rows above the error floor alone (the others are measured
                 * against the floor and are easy) */
                CHECK(st.n_above >= 90);
                CHECK_MSG(st.median_above <= 0.01, "fast median above floor %.4f", st.median_above);
                CHECK_MSG(st.p95_above <= 0.10, "fast p95 above floor %.4f", st.p95_above);
            } else {
                CHECK_MSG(st.median[3] <= 0.05, "xu median %.4f", st.median[3]);
                CHECK_MSG(st.p95[3] <= 0.35, "xu p95 %.4f", st.p95[3]);
                CHECK_MSG(st.p95[3] > 0.10, "xu p95 %.4f: better than measured?", st.p95[3]);
            }
        }
        free(out);
    }
    sl_srbf_tables_free(&t);
    free(cfg);
    free(x);
}
