/* test_srbf_chiang.c: the Chiang fast SRBF path (kernels/srbf_chiang.h within the d'Eon fast
 * path, `eval srbf --method fast` with model chiang) against independent double-precision
 * computations: the contract's exact reference (cpu/reference/srbf_ref.c), the brute-force
 * response of test/chiang_fixture.h (numerics.md sec. 3-4 over cpu/reference/chiang_hit.c; the
 * two references against each other), the width-averaged f (lambda -> 0 limit), the exact
 * definitions of its tables; C twin against OpenCL; extreme inputs; the renderer's RGB rows.
 *
 * The Chiang sample (chiang_sample below, seeded): the materials of chiang_fixture.h (typical,
 * dark, blond narrow, needle, wide, coated, white and maximally rough, middle), a third of the
 * views grazing (|theta_o| 60..89 deg), 15 % of the lobes at a pole, the others on one lobe's
 * specular cone (R, TT, TRT or the rest term) within a few widths, lambda log-uniform in
 * [0.02, 1] (and 3 in a tenth of the rows). Measuring it (docs/srbf.md, "Chiang fast path"):
 *   SL_SRBF_CHIANG_MEASURE=160 build/unit_tests srbf_chiang_measure
 * prints median / p95 / max of the error of numerics.md sec. 5 against the exact reference
 * (cpu/reference/srbf_ref.c; SL_SRBF_CHIANG_BRUTE=1: against test/chiang_fixture.h's brute
 * force instead) per output and overall, per material, and the lobe evaluations per second of
 * chiang, d'Eon (3 orders) and the Marschner fast path on the same rows (C twin; PoCL when
 * present); SL_SRBF_CHIANG_SPEED_ONLY=1 skips the accuracy part. */
#include "test.h"

#include "cl_fixture.h"
#include "chiang_fixture.h"

#include "passes/shade/srbf_cl.h"
#include "passes/shade/srbf_deon_cl.h"
#include "passes/shade/srbf_tables.h"
#include "srbf_c.h"
#include "srbf_deon.h"
#include "srbf_deon_c.h"
#include "srbf_ref.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define DEG (PI / 180.0)

typedef struct ch_row {
    int material;
    double theta_o, phi_o, theta_j, phi_j, lambda;
} ch_row;

static double urand(unsigned *s) {
    *s = *s * 1664525u + 1013904223u;
    return ((*s >> 8) + 0.5) / 16777216.0;
}

/* The Chiang sample: row r uses material r % CHB_NMAT (so any prefix of 8k rows is balanced). */
static void chiang_sample(unsigned seed, int n, ch_row *rows) {
    unsigned s = seed;
    for (int r = 0; r < n; r++) {
        ch_row *c = rows + r;
        sl_material m;
        c->material = r % CHB_NMAT;
        chb_material(c->material, &m);
        double sg = urand(&s) < 0.5 ? -1.0 : 1.0;
        c->theta_o = urand(&s) < 1.0 / 3.0 ? sg * (60.0 + 29.0 * urand(&s)) * DEG
                                           : sg * 60.0 * DEG * urand(&s);
        c->phi_o = PI * (2.0 * urand(&s) - 1.0);
        c->lambda = urand(&s) < 0.1 ? 3.0 : exp(log(0.02) + (log(1.0) - log(0.02)) * urand(&s));
        double kind = urand(&s);
        if (kind < 0.15) {
            c->theta_j = (urand(&s) < 0.5 ? -0.5 : 0.5) * PI;
            c->phi_j = PI * (2.0 * urand(&s) - 1.0);
            continue;
        }
        int p = (int)(4.0 * urand(&s)); /* 0 R, 1 TT, 2 TRT, 3 rest */
        double tho = slref_chiang_theta_o_lobe(&m, p, c->theta_o);
        double w = c->lambda + sqrt(slref_chiang_v(&m, p));
        double tj = -tho + w * (2.0 * urand(&s) - 1.0) * 1.5;
        c->theta_j = fmin(fmax(tj, -0.5 * PI), 0.5 * PI);
        /* TT near forward scattering, the others anywhere in azimuth */
        double ph = p == 1 ? PI + 0.6 * (2.0 * urand(&s) - 1.0) : PI * (2.0 * urand(&s) - 1.0);
        c->phi_j = chb_wrap(c->phi_o - ph);
    }
}

static int get_tables(sl_srbf_tables *t) {
    sl_err e;
    return sl_srbf_tables_get(t, 0, &e);
}

/* The fast path at one configuration, channel ch, in out[0..4]. */
static void fast_one(const sl_srbf_tables *t, const sl_material *m, int ch, const ch_row *c,
                     float *out) {
    sl_fiber_params fp;
    sl_material_to_fiber(m, ch, &fp);
    float row[5] = {(float)c->theta_o, (float)c->phi_o, (float)c->theta_j, (float)c->phi_j,
                    (float)c->lambda};
    slc_srbf_deon_batch(&fp, t->C, t->H, t->D, 1, row, out);
}

static int cmp_d(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}
static double quantile(double *v, int n, double q) {
    if (n <= 0) return 0.0;
    qsort(v, (size_t)n, sizeof *v, cmp_d);
    int k = (int)ceil(q * n) - 1;
    return v[k < 0 ? 0 : (k >= n ? n - 1 : k)];
}

/* The tables' constants and slices against their definitions: the wide branch's nodes, the
 * root harmonics through the 1/eta' axis (linear, 256 points) at off-grid points, their n = 0
 * row (the nodes' uniform-azimuth weights, for every order the same), the detector's harmonics
 * through the log-s axis and below it. Scale of the root harmonics: the largest |h| of the point
 * (its n = 0 entries); measured worst 0.2 % (order 2, n = 16, x = 0.6); tolerance 0.5 %. The
 * detector measured 3e-4 (interpolation in log s); tolerance 1e-3; a wrong layout or order is
 * O(1) off. The build's own errors (err_Ch_x 0.0034 of max |h|, err_Ch_s 3.3e-4): < 0.01. */
TEST(srbf_chiang_tables) {
    sl_srbf_tables t;
    CHECK(get_tables(&t) == 0);
    if (sl_test_failed_now()) return;
    for (int i = 0; i < SL_SRBF_CH_NODES; i++) {
        double c = 0.5 * (1.0 - cos((2.0 * i + 1.0) * PI / (2.0 * SL_SRBF_CH_NODES)));
        CHECK_NEAR(sl_srbf_ch_c[i], c, 1e-7);
        CHECK_NEAR(sl_srbf_ch_s[i], sqrt(1.0 - c * c), 1e-7);
    }
    enum { NV = SL_SRBF_CH_NHV * SL_SRBF_CH_NODES };
    const double xs[4] = {0.0, 0.3137, 0.6001, 0.83};
    double ex[NV], worst = 0.0;
    for (int p = 1; p <= 2; p++)
        for (int k = 0; k < 4; k++) {
            sl_srbf_chiang_root_harmonics(p, xs[k], ex);
            int ix;
            float fx = sl_srbf_grid((float)xs[k], 0.0f, 1.0f, SL_SRBF_CH_NX, &ix);
            const float *h0 = t.D + SL_SRBF_CH_OFF + (p - 1) * SL_SRBF_CH_SLICE + ix * NV;
            double scale = 0.0;
            for (int i = 0; i < SL_SRBF_CH_NODES; i++)
                scale = fmax(scale, fabs(ex[i]));
            for (int j = 0; j < NV; j++) {
                double got = h0[j] + (h0[j + NV] - h0[j]) * fx;
                worst = fmax(worst, fabs(got - ex[j]) / scale);
                CHECK_MSG(fabs(got - ex[j]) <= 5e-3 * scale, "p %d x %g entry %d: %g vs %g", p,
                          xs[k], j, got, ex[j]);
            }
        }
    CHECK(worst > 0.0);
    printf("  root harmonics: worst %.4f of the point's largest |h|\n", worst);
    /* n = 0: the uniform weights, int_0^{pi/2} L_i(cos u) cos u du / 2 pi, equal for R, TT, TRT */
    sl_srbf_chiang_root_harmonics(0, 0.0, ex);
    double h2[NV];
    sl_srbf_chiang_root_harmonics(2, 0.5, h2);
    double sum = 0.0;
    for (int i = 0; i < SL_SRBF_CH_NODES; i++) {
        CHECK_REL(t.D[SL_SRBF_CH_R_OFF + i], ex[i], 1e-6);
        CHECK_NEAR(h2[i], ex[i], 1e-12);
        sum += ex[i];
    }
    CHECK_NEAR(sum, 1.0 / (2.0 * PI), 1e-12); /* the weights integrate 1: E of A = 1 is 1 */
    /* the detector */
    const double ss[5] = {0.001, 0.0241, 0.117, 1.087, 4.28};
    for (int k = 0; k < 5; k++) {
        sl_fiber_params fp;
        memset(&fp, 0, sizeof fp);
        float d[SL_SRBF_CH_NHV];
        sl_srbf_chiang_detector(t.D, (float)ss[k], d);
        for (int n = 0; n < SL_SRBF_CH_NHV; n++)
            CHECK_MSG(fabs(d[n] - sl_srbf_chiang_detector_exact(ss[k], n)) <= 1e-3,
                      "s %g n %d: %g vs %g", ss[k], n, (double)d[n],
                      sl_srbf_chiang_detector_exact(ss[k], n));
    }
    /* s -> 0: the untrimmed logistic's characteristic function x / sinh x, x = pi s n */
    CHECK_REL(sl_srbf_chiang_detector_exact(0.05, 3), (PI * 0.15) / sinh(PI * 0.15), 1e-9);
    CHECK(t.err_Ch_x >= 0.0 && t.err_Ch_x < 0.01);
    CHECK(t.err_Ch_s >= 0.0 && t.err_Ch_s < 0.01);
    sl_srbf_tables_free(&t);
}

/* I_n(k) / I_0(k) (n <= SL_SRBF_CH_NH) of the kernel's recurrence against double Miller
 * recurrence from far above, k from 1e-3 (wide lobe) to 1e5 (lambda 0.0045): 1e-5 relative
 * (float rounding through 16 products) plus 1e-7 absolute (of rho_0 = 1: what the harmonic sum
 * sees). */
TEST(srbf_chiang_vm_ratios) {
    const double ks[8] = {1e-3, 0.1, 1.0, 7.0, 30.0, 300.0, 3000.0, 1e5};
    for (int a = 0; a < 8; a++) {
        double k = ks[a], r[SL_SRBF_CH_NHV], ip1 = 0.0, in = 1e-300;
        int top = SL_SRBF_CH_NH + 200 + (int)(20.0 * sqrt(k) + k / 10.0);
        if (top > 200000) top = 200000;
        for (int n = top; n >= 1; n--) {
            double im1 = ip1 + 2.0 * n / k * in;
            ip1 = in;
            in = im1;
            if (n - 1 <= SL_SRBF_CH_NH) r[n - 1] = in;
            if (in > 1e250) { /* rescale what is kept so far, r[n - 1 .. NH] */
                for (int j = n - 1; j <= SL_SRBF_CH_NH; j++)
                    if (j >= 0) r[j] *= 1e-250;
                in *= 1e-250;
                ip1 *= 1e-250;
            }
        }
        float got[SL_SRBF_CH_NHV];
        sl_srbf_chiang_vm((float)k, got);
        for (int n = 0; n < SL_SRBF_CH_NHV; n++) {
            double want = r[n] / r[0];
            CHECK_MSG(fabs(got[n] - want) <= 1e-5 * want + 1e-7, "k %g n %d: %g vs %g", k, n,
                      (double)got[n], want);
        }
    }
}

/* The brute-force helper itself (test/chiang_fixture.h): lambda = 0.005 against the width
 * averaged f (I / int G -> f; the lobe averages f over ~0.3 deg, below these materials'
 * widths: measured 3e-4 of f), and a doubled resolution on two rows (measured 2e-7 relative):
 * tolerances 3e-3 of f and 1e-5 of I. A missing cos theta_i, a wrong normalisation of G_ph or
 * of the detector moves either by far more. */
TEST(srbf_chiang_brute_force_self_check) {
    const double q[3][4] = {{0.3, 0.5, -0.2, 2.9}, {0.3, 0.5, -0.3, 0.2}, {-0.6, 1.0, 0.55, -1.8}};
    const int mats[2] = {0, 7};
    for (int mi = 0; mi < 2; mi++)
        for (int k = 0; k < 3; k++) {
            sl_material m;
            chb_material(mats[mi], &m);
            double lam = 0.005, f[5], ir[5];
            chb_f(&m, 0, q[k][2], q[k][3], q[k][0], q[k][1], f);
            chb_srbf(&m, 0, q[k][0], q[k][1], q[k][2], q[k][3], lam, 1, ir);
            double ig = slref_srbf_lobe_integral(lam);
            for (int p = 0; p < 5; p++)
                CHECK_MSG(fabs(ir[p] / ig - f[p]) <= 3e-3 * f[4], "mat %d q %d out %d: %g vs f %g",
                          mats[mi], k, p, ir[p] / ig, f[p]);
        }
    const double rows[2][5] = {{0.2, 0.4, -0.1, 2.5, 0.05}, {-1.2, 2.0, 1.3, -1.0, 0.4}};
    const int rm[2] = {3, 6};
    for (int k = 0; k < 2; k++) {
        sl_material m;
        chb_material(rm[k], &m);
        double a[5], b[5];
        chb_srbf(&m, 0, rows[k][0], rows[k][1], rows[k][2], rows[k][3], rows[k][4], 1, a);
        chb_srbf(&m, 0, rows[k][0], rows[k][1], rows[k][2], rows[k][3], rows[k][4], 2, b);
        for (int p = 0; p < 5; p++)
            CHECK_MSG(fabs(a[p] - b[p]) <= 1e-5 * b[4], "row %d out %d: %g vs %g", k, p, a[p],
                      b[p]);
    }
}

/* The brute force of chiang_fixture.h against the contract's exact reference
 * (cpu/reference/srbf_ref.c, written independently: Fourier series of the trimmed logistic,
 * adaptive theta_i) on a row per material of the sample: the two agree to 1e-6 of
 * max(I, 0.03 int G) (measured 3.4e-10), so the fast path's figures hold against either. */
TEST(srbf_chiang_brute_force_vs_reference) {
    ch_row rows[CHB_NMAT];
    chiang_sample(20160701u, CHB_NMAT, rows);
    double worst = 0.0;
    for (int r = 0; r < CHB_NMAT; r++) {
        const ch_row *c = rows + r;
        sl_material m;
        chb_material(c->material, &m);
        double a[5], b[5];
        chb_srbf(&m, 1, c->theta_o, c->phi_o, c->theta_j, c->phi_j, c->lambda, 1, a);
        slref_srbf(&m, 1, c->theta_o, c->phi_o, c->theta_j, c->phi_j, c->lambda, b);
        for (int p = 0; p < 5; p++) {
            double er = slref_srbf_error(a[p], b[p], c->lambda);
            worst = fmax(worst, er);
            CHECK_MSG(er <= 1e-6, "row %d (material %d) output %d: brute %g, reference %g", r,
                      c->material, p, a[p], b[p]);
        }
    }
    printf("  brute force vs reference: worst %.2g\n", worst);
}

/* Rows of the Chiang sample (2 per material) and extreme rows (theta_o within 1e-3 of +-pi/2,
 * lambda 0.02 and 3, the needle and the maximally rough material, sigma_a ~ 17, lobes at the
 * poles) against the exact reference (cpu/reference/srbf_ref.c) in the error measure of
 * numerics.md sec. 5. The 160-row sample measured total median 0.0007, p95 0.0044, max 0.022
 * (docs/srbf.md); d'Eon's fast path on its own stiff sample: 0.0013, 0.014, 0.049. Tolerances:
 * 0.04 per row and output (2x the worst row), median <= 0.005. d'Eon's rule alone (the logistic
 * as one von Mises of its variance, no harmonic branch) measured p95 0.061, max 0.27 on the
 * sample; dropping a lobe or the rest term moves rows by more than 0.04. */
TEST(srbf_chiang_fast_vs_exact) {
    sl_srbf_tables t;
    CHECK(get_tables(&t) == 0);
    if (sl_test_failed_now()) return;
    enum { NS = 16, NX = 8, N = NS + NX };
    ch_row rows[N];
    ch_row sample[5 * CHB_NMAT];
    chiang_sample(20160701u, 5 * CHB_NMAT, sample);
    for (int k = 0; k < NS; k++) /* material k % 8, two different draws each */
        rows[k] = sample[k < CHB_NMAT ? k : 2 * CHB_NMAT + k];
    const double hp = 0.5 * PI - 1e-3;
    const ch_row extreme[NX] = {
        {3, hp, 0.3, -hp + 0.02, 0.4, 0.02}, {3, 0.1, -0.5, -0.05, -0.2, 0.02},
        {6, -hp, 1.0, 0.5, -2.0, 3.0},       {6, 0.4, 2.5, -0.4, -0.6, 0.02},
        {1, 0.5, 0.0, -0.5, 0.0, 0.3},       {5, 1.3, -2.0, -1.1, 1.1, 0.1},
        {4, 0.7, 3.0, 0.5 * PI, 0.0, 0.5},   {0, -0.2, 0.1, -0.5 * PI, 1.0, 0.2},
    };
    for (int k = 0; k < NX; k++)
        rows[NS + k] = extreme[k];
    double err[N];
    for (int r = 0; r < N; r++) {
        const ch_row *c = rows + r;
        sl_material m;
        chb_material(c->material, &m);
        int ch = r % 3;
        double ex[5];
        float got[SL_SRBF_DEON_NOUT];
        slref_srbf(&m, ch, c->theta_o, c->phi_o, c->theta_j, c->phi_j, c->lambda, ex);
        fast_one(&t, &m, ch, c, got);
        err[r] = slref_srbf_error(got[4], ex[4], c->lambda);
        CHECK_MSG(err[r] <= 0.04, "row %d (material %d, ch %d): I %g, exact %g, error %.3f", r,
                  c->material, ch, (double)got[4], ex[4], err[r]);
        for (int p = 0; p < 4; p++) /* each output, in the same measure */
            CHECK_MSG(slref_srbf_error(got[p], ex[p], c->lambda) <= 0.04,
                      "row %d output %d: %g vs %g", r, p, (double)got[p], ex[p]);
    }
    double med = quantile(err, N, 0.5);
    CHECK_MSG(med <= 0.005, "median error %.4f", med);
    sl_srbf_tables_free(&t);
}

/* lambda -> 0 against the width-averaged f: I / int G -> f(omega_j, omega_o) at lambda = 0.005,
 * where the lobe averages f over ~0.3 deg (at 0.02 the blond material's TT tail, 2 widths off
 * its cone, is already 6 % above f: exp(lambda^2/8 (d log M / d theta)^2)). The narrow branch's
 * 4 nodes in c are the fast path's own error here (TT and R have their kernel -> 0 error added
 * back, TRT, whose roots fold at caustics, not): measured worst 3.5 % of the total f (TRT of the
 * blond material at phi = 0.3); tolerance 5 % per output and total (d'Eon's test, at 0.02: 6 %). */
TEST(srbf_chiang_limit_small_lambda) {
    sl_srbf_tables t;
    CHECK(get_tables(&t) == 0);
    if (sl_test_failed_now()) return;
    const double q[4][4] = {{0.3, 0.5, -0.2, 2.9},
                            {0.3, 0.5, -0.3, 0.2},
                            {-0.6, 1.0, 0.55, -1.8},
                            {1.0, 0.0, -0.95, -3.0}}; /* theta_o, phi_o, theta_j, phi_j */
    const int mats[3] = {0, 2, 7};
    double worst = 0.0;
    char where[64] = "";
    for (int mi = 0; mi < 3; mi++)
        for (int k = 0; k < 4; k++) {
            sl_material m;
            chb_material(mats[mi], &m);
            double f[5];
            ch_row c = {mats[mi], q[k][0], q[k][1], q[k][2], q[k][3], 0.005};
            float got[SL_SRBF_DEON_NOUT];
            chb_f(&m, 1, q[k][2], q[k][3], q[k][0], q[k][1], f);
            fast_one(&t, &m, 1, &c, got);
            double ig = slref_srbf_lobe_integral(0.005);
            for (int p = 0; p < 5; p++) {
                if (fabs(got[p] / ig - f[p]) / f[4] > worst) {
                    worst = fabs(got[p] / ig - f[p]) / f[4];
                    snprintf(where, sizeof where, "material %d query %d output %d", mats[mi], k, p);
                }
                CHECK_MSG(fabs(got[p] / ig - f[p]) <= 0.05 * f[4],
                          "mat %d query %d output %d: I/intG %g, f %g (f total %g)", mats[mi], k, p,
                          got[p] / ig, f[p], f[4]);
            }
        }
    printf("  worst |I / int G - f| / f: %.4f (%s)\n", worst, where);
    sl_srbf_tables_free(&t);
}

/* Extreme inputs on every material: views and lobes at and next to the poles, lambda 0.005
 * (below the W tables) to 10, phi at 0 and +-pi: every output finite and >= 0, the total the
 * sum; at a pole the response cannot depend on phi_j (G is symmetric about the fiber axis
 * there): equal to float rounding (1e-5 relative). */
TEST(srbf_chiang_extreme_inputs) {
    sl_srbf_tables t;
    CHECK(get_tables(&t) == 0);
    if (sl_test_failed_now()) return;
    const double lams[5] = {0.005, 0.02, 0.3, 3.0, 10.0};
    const double ths[7] = {-PI / 2, -1.5707, -0.3, 0.0, 1.2, 1.5707, PI / 2};
    const double phs[3] = {0.0, PI, -2.0};
    for (int mi = 0; mi < CHB_NMAT; mi++) {
        sl_material m;
        chb_material(mi, &m);
        for (int a = 0; a < 7; a++)
            for (int b = 0; b < 7; b++)
                for (int l = 0; l < 5; l++)
                    for (int f = 0; f < 3; f++) {
                        ch_row c = {mi, ths[a], 0.7, ths[b], 0.7 - phs[f], lams[l]};
                        float got[SL_SRBF_DEON_NOUT];
                        fast_one(&t, &m, 2, &c, got);
                        double s = 0.0;
                        int ok = 1;
                        for (int p = 0; p <= 3; p++) {
                            ok &= isfinite(got[p]) && got[p] >= 0.0f;
                            s += got[p];
                        }
                        CHECK_MSG(ok && fabs(got[4] - s) <= 1e-5 * s + 1e-30,
                                  "mat %d to %g tj %g lam %g: not finite/negative or bad total", mi,
                                  ths[a], ths[b], lams[l]);
                    }
        for (int l = 0; l < 5; l++) {
            float a0[SL_SRBF_DEON_NOUT], a1[SL_SRBF_DEON_NOUT];
            ch_row c0 = {mi, 0.4, 0.3, PI / 2, 0.0, lams[l]}, c1 = c0;
            c1.phi_j = 2.5;
            fast_one(&t, &m, 0, &c0, a0);
            fast_one(&t, &m, 0, &c1, a1);
            CHECK_REL(a0[4], a1[4], 1e-5);
        }
    }
    sl_srbf_tables_free(&t);
}

/* C twin against the OpenCL kernel (PoCL here) on 200 rows of the sample for every material:
 * the same float header, so only device exp/log/asin ulps differ: 1e-3 relative of the row's
 * total, as for d'Eon. */
TEST(srbf_chiang_c_vs_opencl) {
    sl_device dev = {0};
    sl_err e;
    SL_TEST_OPEN_CL(&dev, &e);
    unsigned long k0 = sl_cl_kernels_enqueued();
    sl_srbf_tables t;
    CHECK(get_tables(&t) == 0);
    enum { N = 200 };
    ch_row *rows = malloc(N * sizeof *rows);
    chiang_sample(20160701u, N, rows);
    float *in = malloc(N * 5 * sizeof *in), *a = malloc(N * 5 * sizeof *a),
          *b = malloc(N * 5 * sizeof *b);
    for (int r = 0; r < N; r++) {
        float *x = in + 5 * r;
        x[0] = (float)rows[r].theta_o, x[1] = (float)rows[r].phi_o, x[2] = (float)rows[r].theta_j,
        x[3] = (float)rows[r].phi_j, x[4] = (float)rows[r].lambda;
    }
    for (int mi = 0; mi < CHB_NMAT && !sl_test_failed_now(); mi++) {
        sl_material m;
        chb_material(mi, &m);
        sl_fiber_params fp;
        sl_material_to_fiber(&m, 1, &fp);
        CHECK(slcl_srbf_deon_batch(dev.cl, &fp, &t, N, in, a, &e) == 0);
        slc_srbf_deon_batch(&fp, t.C, t.H, t.D, N, in, b);
        for (int r = 0; r < N; r++)
            for (int p = 0; p < 5; p++) {
                float x = a[5 * r + p], y = b[5 * r + p], tot = b[5 * r + 4];
                CHECK_MSG(fabsf(x - y) <= 1e-3f * tot + 1e-12f, "mat %d row %d out %d: cl %g c %g",
                          mi, r, p, (double)x, (double)y);
            }
    }
    free(rows);
    free(in);
    free(a);
    free(b);
    CHECK_CL_RAN(k0);
    sl_srbf_tables_free(&t);
    sl_device_close(&dev);
}

/* The renderer's RGB rows for chiang (sl_srbf_deon_rgb_row: I_0, I_1, I_2 + rest per channel)
 * against single-channel evaluations, whatever fp->orders says (chiang is always orders 2):
 * equal to 1e-6, except that a group is skipped by the largest energy of the row's channels,
 * whose skipped part is below 1e-4 of the error floor (0.03 int G); R (no sigma_a in it) to
 * 1e-6. And the OpenCL rgb kernel against the C batch (1e-3 of the row's total). */
TEST(srbf_chiang_rgb_rows) {
    sl_srbf_tables t;
    CHECK(get_tables(&t) == 0);
    if (sl_test_failed_now()) return;
    enum { N = 48 };
    ch_row rows[N];
    chiang_sample(7u, N, rows);
    float in[N * 5], sig[N * 3], rgb[N * 9], cl_rgb[N * 9];
    for (int r = 0; r < N; r++) {
        float *x = in + 5 * r;
        x[0] = (float)rows[r].theta_o, x[1] = (float)rows[r].phi_o, x[2] = (float)rows[r].theta_j,
        x[3] = (float)rows[r].phi_j, x[4] = (float)rows[r].lambda;
        sig[3 * r] = 0.1f + 0.05f * (float)(r % 7);
        sig[3 * r + 1] = r % 3 ? sig[3 * r] : 1.5f;
        sig[3 * r + 2] = 4.0f;
    }
    sl_material m;
    chb_material(2, &m);
    sl_fiber_params fp;
    sl_material_to_fiber(&m, 0, &fp);
    fp.orders = 7; /* ignored for chiang */
    slc_srbf_deon_rgb_batch(&fp, t.C, t.H, t.D, N, in, sig, rgb);
    for (int r = 0; r < N; r++)
        for (int ch = 0; ch < 3; ch++) {
            sl_fiber_params q = fp;
            q.sigma_a = sig[3 * r + ch];
            float o[SL_SRBF_DEON_NOUT];
            slc_srbf_deon_batch(&q, t.C, t.H, t.D, 1, in + 5 * r, o);
            double tol = 1e-4 * 0.03 * slref_srbf_lobe_integral(rows[r].lambda);
            CHECK_NEAR(rgb[9 * r + ch], o[0], 1e-6 * o[0]);
            CHECK_NEAR(rgb[9 * r + 3 + ch], o[1], 1e-6 * o[1] + tol);
            CHECK_NEAR(rgb[9 * r + 6 + ch], o[2] + o[3], 1e-6 * (o[2] + o[3]) + tol);
            CHECK_REL(o[4], o[0] + o[1] + o[2] + o[3], 1e-6);
        }
    sl_device dev = {0};
    sl_err e;
    int cl_rc = sl_test_open_cl(&dev, &e);
    CHECK_MSG(cl_rc >= 0, "an OpenCL device is listed but not usable: %s", e.msg);
    if (cl_rc == 0) {
        CHECK(slcl_srbf_deon_rgb_batch(dev.cl, &fp, &t, N, in, sig, cl_rgb, &e) == 0);
        for (int r = 0; r < N; r++) {
            float tot = 0.0f;
            for (int k = 0; k < 9; k++)
                tot += rgb[9 * r + k];
            for (int k = 0; k < 9; k++)
                CHECK(fabsf(cl_rgb[9 * r + k] - rgb[9 * r + k]) <= 1e-3f * tot + 1e-12f);
        }
        sl_device_close(&dev);
    }
    sl_srbf_tables_free(&t);
}

/* ---- measurement (not a check): SL_SRBF_CHIANG_MEASURE=<rows> ---- */

static double rate(const sl_srbf_tables *t, sl_device *dev, int model, const float *in, int n,
                   int reps) {
    sl_material m;
    if (model == SL_MODEL_CHIANG) {
        chb_material(0, &m);
    } else {
        sl_material_default(&m);
        m.model = model;
        m.orders = 3;
    }
    sl_fiber_params fp;
    sl_material_to_fiber(&m, 0, &fp);
    size_t big = (size_t)n * (size_t)reps;
    float *rows = malloc(big * 5 * sizeof *rows), *out = malloc(big * 11 * sizeof *out);
    for (size_t k = 0; k < big; k++)
        memcpy(rows + 5 * k, in + 5 * (k % (size_t)n), 5 * sizeof *rows);
    double best = INFINITY;
    sl_err e;
    for (int round = 0; round < 3; round++) {
        double t0 = sl_now();
        if (dev) {
            if (model != SL_MODEL_MARSCHNER)
                slcl_srbf_deon_batch(dev->cl, &fp, t, big, rows, out, &e);
            else
                slcl_srbf_batch(dev->cl, &fp, t, SL_SRBF_METHOD_FAST, 4, big, rows, out, &e);
        } else if (model != SL_MODEL_MARSCHNER)
            slc_srbf_deon_batch(&fp, t->C, t->H, t->D, big, rows, out);
        else
            slc_srbf_batch(&fp, t->C, t->H, SL_SRBF_METHOD_FAST, 4, big, rows, out);
        best = fmin(best, sl_now() - t0);
    }
    free(rows);
    free(out);
    return (double)big / best;
}

/* Rows per second of the renderer's RGB batch (three sigma_a per row) on the C twin. */
static double rate_rgb(const sl_srbf_tables *t, int model, const float *in, int n, int reps) {
    sl_material m;
    if (model == SL_MODEL_CHIANG) {
        chb_material(0, &m);
    } else {
        sl_material_default(&m);
        m.model = model;
        m.orders = 3;
    }
    sl_fiber_params fp;
    sl_material_to_fiber(&m, 0, &fp);
    size_t big = (size_t)n * (size_t)reps;
    float *rows = malloc(big * 5 * sizeof *rows), *sig = malloc(big * 3 * sizeof *sig),
          *out = malloc(big * 9 * sizeof *out);
    for (size_t k = 0; k < big; k++) {
        memcpy(rows + 5 * k, in + 5 * (k % (size_t)n), 5 * sizeof *rows);
        for (int c = 0; c < 3; c++) /* the chiang default's melanin 0.8 sigma_a */
            sig[3 * k + c] = (float)(c == 0 ? 0.55 : c == 1 ? 1.18 : 3.10);
    }
    double best = INFINITY;
    for (int round = 0; round < 3; round++) {
        double t0 = sl_now();
        slc_srbf_deon_rgb_batch(&fp, t->C, t->H, t->D, big, rows, sig, out);
        best = fmin(best, sl_now() - t0);
    }
    free(rows);
    free(sig);
    free(out);
    return (double)big / best;
}

TEST(srbf_chiang_measure) {
    const char *v = getenv("SL_SRBF_CHIANG_MEASURE");
    if (!v || atoi(v) <= 0) {
        SKIP("set SL_SRBF_CHIANG_MEASURE=<rows> to measure the Chiang sample");
        return;
    }
    int n = atoi(v);
    sl_srbf_tables t;
    CHECK(get_tables(&t) == 0);
    ch_row *rows = malloc((size_t)n * sizeof *rows);
    chiang_sample(20160701u, n, rows);
    double *err[5], *errm[CHB_NMAT];
    int cnt[5] = {0}, cntm[CHB_NMAT] = {0};
    for (int k = 0; k < 5; k++)
        err[k] = malloc((size_t)n * sizeof(double));
    for (int k = 0; k < CHB_NMAT; k++)
        errm[k] = malloc((size_t)n * sizeof(double));
    double t_ref = 0.0;
    int speed_only = getenv("SL_SRBF_CHIANG_SPEED_ONLY") != NULL;
    for (int r = 0; r < n && !speed_only; r++) {
        const ch_row *c = rows + r;
        sl_material m;
        chb_material(c->material, &m);
        int ch = r % 3;
        double ex[5];
        float got[SL_SRBF_DEON_NOUT];
        double t0 = sl_now();
        if (getenv("SL_SRBF_CHIANG_BRUTE"))
            chb_srbf(&m, ch, c->theta_o, c->phi_o, c->theta_j, c->phi_j, c->lambda, 1, ex);
        else
            slref_srbf(&m, ch, c->theta_o, c->phi_o, c->theta_j, c->phi_j, c->lambda, ex);
        t_ref += sl_now() - t0;
        fast_one(&t, &m, ch, c, got);
        for (int p = 0; p < 5; p++) {
            double er = slref_srbf_error(got[p], ex[p], c->lambda);
            err[p][cnt[p]++] = er;
            if (p == 4) errm[c->material][cntm[c->material]++] = er;
            if (p == 4 && er > 0.02)
                printf("  row %d mat %d ch %d to %.3f po %.3f tj %.3f pj %.3f lam %.3f: I %.6g "
                       "exact %.6g err %.3f (R %.3g/%.3g TT %.3g/%.3g TRT %.3g/%.3g)\n",
                       r, c->material, ch, c->theta_o, c->phi_o, c->theta_j, c->phi_j, c->lambda,
                       (double)got[4], ex[4], er, (double)got[0], ex[0], (double)got[1], ex[1],
                       (double)got[2], ex[2]);
        }
    }
    const char *names[5] = {"I_0 (R)", "I_1 (TT)", "I_2 (TRT)", "I_rest", "I"};
    printf("chiang fast vs %s, %d rows (%.1f s):\n",
           getenv("SL_SRBF_CHIANG_BRUTE") ? "the brute force" : "the exact reference", n, t_ref);
    for (int k = 0; k < 5 && !speed_only; k++)
        printf("  %-10s median %.4f  p95 %.4f  max %.4f\n", names[k], quantile(err[k], cnt[k], 0.5),
               quantile(err[k], cnt[k], 0.95), quantile(err[k], cnt[k], 1.0));
    for (int k = 0; k < CHB_NMAT && !speed_only; k++)
        printf("  material %d %-90s I median %.4f p95 %.4f max %.4f\n", k, chb_materials[k],
               quantile(errm[k], cntm[k], 0.5), quantile(errm[k], cntm[k], 0.95),
               quantile(errm[k], cntm[k], 1.0));
    float *in = malloc((size_t)n * 5 * sizeof *in);
    for (int r = 0; r < n; r++) {
        float *x = in + 5 * r;
        x[0] = (float)rows[r].theta_o, x[1] = (float)rows[r].phi_o, x[2] = (float)rows[r].theta_j,
        x[3] = (float)rows[r].phi_j, x[4] = (float)rows[r].lambda;
    }
    int reps = 20000 / n + 1;
    printf("lobe evaluations per second, C twin, 1 thread: chiang %.3g, deon (3 orders) %.3g, "
           "marschner fast %.3g\n",
           rate(&t, NULL, SL_MODEL_CHIANG, in, n, reps), rate(&t, NULL, SL_MODEL_DEON, in, n, reps),
           rate(&t, NULL, SL_MODEL_MARSCHNER, in, n, reps));
    printf("RGB rows per second (the renderer's batch, three sigma_a per row), C twin, 1 thread: "
           "chiang %.3g, deon (3 orders) %.3g\n",
           rate_rgb(&t, SL_MODEL_CHIANG, in, n, reps), rate_rgb(&t, SL_MODEL_DEON, in, n, reps));
    sl_device dev = {0};
    sl_err e;
    if (sl_test_open_cl(&dev, &e) == 0) {
        reps = 100000 / n + 1;
        for (int md = 0; md < 3; md++)
            rate(&t, &dev, md, in, n, 1); /* program builds */
        printf("lobe evaluations per second, OpenCL (%s, uploads included): chiang %.3g, deon "
               "%.3g, marschner fast %.3g\n",
               sl_cl_device_name(dev.cl), rate(&t, &dev, SL_MODEL_CHIANG, in, n, reps),
               rate(&t, &dev, SL_MODEL_DEON, in, n, reps),
               rate(&t, &dev, SL_MODEL_MARSCHNER, in, n, reps));
        sl_device_close(&dev);
    }
    for (int k = 0; k < 5; k++)
        free(err[k]);
    for (int k = 0; k < CHB_NMAT; k++)
        free(errm[k]);
    free(in);
    free(rows);
    sl_srbf_tables_free(&t);
}
