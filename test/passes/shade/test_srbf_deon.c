/* test_srbf_deon.c: the d'Eon fast SRBF path (kernels/srbf_deon.h, `eval srbf --method fast`
 * with model deon) against independent double-precision computations: the exact reference
 * (cpu/reference/srbf_ref.c), the reference scattering function (lambda -> 0 limit), direct
 * quadratures of the table definitions; C twin against OpenCL; extreme inputs.
 *
 * The d'Eon stiff sample: the geometry of host/verify/report/srbf_sample.c (seeded; grazing views, poles,
 * lobes on the specular cones, lambda 0.05..1) with the d'Eon materials of deon_material()
 * below (beta 0.5..15 deg, dark / blond sigma_a, orders 3..8). Measuring the whole sample
 * (docs/srbf.md, "d'Eon fast path"):
 *   SL_SRBF_DEON_MEASURE=150 build/unit_tests srbf_deon_measure
 * prints median / p95 / max of the error of numerics.md sec. 5 per output and the lobe
 * evaluations per second of d'Eon and of the Marschner fast path (C; PoCL when present);
 * SL_SRBF_DEON_SPEED_ONLY=1 skips the exact values (the speed part alone). */
#include "test.h"

#include "cl_fixture.h"

#include "cl/clrt.h"
#include "deon_ref.h"
#include "scene/material.h"
#include "srbf_c.h"
#include "passes/shade/srbf_cl.h"
#include "srbf_deon.h"
#include "srbf_deon_c.h"
#include "passes/shade/srbf_deon_cl.h"
#include "srbf_ref.h"
#include "verify/report/srbf_sample.h"
#include "passes/shade/srbf_tables.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define DEG (PI / 180.0)

/* The d'Eon variants of the stiff sample (indexed like sl_srbf_sample's materials, which place
 * the lobes on the default alphas' cones; d'Eon's cones sit at the same theta_i = 2 alpha -
 * theta_o). */
static void deon_material(int i, sl_material *m) {
    sl_material_default(m);
    m->model = SL_MODEL_DEON;
    switch (i) {
    case 1: /* dark: TT and higher orders absorbed, R dominates */
        m->sigma_a[0] = m->sigma_a[1] = m->sigma_a[2] = 3.0;
        m->orders = 4;
        break;
    case 2: /* blond, sharp: beta 2.5 / 1.25 / 5 deg, all 8 tabulated orders */
        m->sigma_a[0] = m->sigma_a[1] = m->sigma_a[2] = 0.08;
        m->beta[0] = 2.5 * DEG;
        m->beta[1] = 1.25 * DEG;
        m->beta[2] = 5.0 * DEG;
        m->orders = 8;
        break;
    case 3: /* needle-sharp: beta 0.5 deg (v = 7.6e-5) */
        m->beta[0] = 0.5 * DEG;
        m->beta[1] = 0.5 * DEG;
        m->beta[2] = 1.0 * DEG;
        m->orders = 5;
        break;
    case 4: /* wide: beta 15 deg, little absorption */
        m->sigma_a[0] = m->sigma_a[1] = m->sigma_a[2] = 0.15;
        m->beta[0] = 15.0 * DEG;
        m->beta[1] = 10.0 * DEG;
        m->beta[2] = 15.0 * DEG;
        m->orders = 6;
        break;
    default: /* the defaults, 3 orders */
        m->orders = 3;
        break;
    }
}

static int get_tables(sl_srbf_tables *t) {
    sl_err e;
    return sl_srbf_tables_get(t, 0, &e);
}

/* The fast path at one configuration, in out[0..orders+2]. */
static void fast_one(const sl_srbf_tables *t, const sl_material *m, double to, double po, double tj,
                     double pj, double lam, float *out) {
    sl_fiber_params fp;
    sl_material_to_fiber(m, 0, &fp);
    float row[5] = {(float)to, (float)po, (float)tj, (float)pj, (float)lam};
    slc_srbf_deon_batch(&fp, t->C, t->H, t->D, 1, row, out);
}

static int cmp_d(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}
static double quantile(double *v, int n, double q) {
    qsort(v, (size_t)n, sizeof *v, cmp_d);
    int k = (int)ceil(q * n) - 1;
    return v[k < 0 ? 0 : (k >= n ? n - 1 : k)];
}

/* The uniform-azimuth constants of srbf_deon.h against a direct double quadrature of their
 * definitions (midpoint, 2e5 steps: error ~1e-11): U_i = int_0^{pi/2} L_i(cos u) cos u du / 2pi
 * with L_i the Lagrange basis on the Chebyshev nodes c_i, and the mean of |cos(x/2)|^k. The
 * constants are written to 15 digits and rounded to float: 1e-7 relative. */
TEST(srbf_deon_uniform_constants) {
    const double c[4] = {(1 - cos(PI / 8)) / 2, (1 - cos(3 * PI / 8)) / 2,
                         (1 - cos(5 * PI / 8)) / 2, (1 - cos(7 * PI / 8)) / 2};
    const int n = 200000;
    double om[4] = {0}, cu[7] = {0};
    for (int k = 0; k < n; k++) {
        double u = (k + 0.5) * 0.5 * PI / n, x = cos(u);
        for (int i = 0; i < 4; i++) {
            double L = 1.0;
            for (int j = 0; j < 4; j++)
                if (j != i) L *= (x - c[j]) / (c[i] - c[j]);
            om[i] += L * x * 0.5 * PI / n;
        }
        double y = -0.5 * PI + (k + 0.5) * PI / n, p = 1.0; /* y = x/2, x uniform on circle */
        for (int j = 0; j < 7; j++) {
            cu[j] += p / n;
            p *= fabs(cos(y));
        }
    }
    for (int i = 0; i < 4; i++) {
        CHECK_REL(sl_srbf_deon_u[i], om[i] / (2 * PI), 1e-6);
        CHECK_NEAR(sl_srbf_w_c[i], c[i], 1e-7);
    }
    for (int k = 0; k < 7; k++)
        CHECK_REL(sl_srbf_deon_cu[k], cu[k], 1e-6);
}

/* The d'Eon slices (orders 3..8) read through the kernel's lookup against a direct quadrature
 * of the definition (sl_srbf_W_exact_order, 4e5 steps in u), at off-grid points with width
 * >= 0.3 (the narrow end is a table-resolution matter, reported by the build as err_D). Scale:
 * the largest exact weight of that order over the points (near a zero of W a relative error
 * means nothing). Measured worst 2.3 % of it (order 8: Phi(p, h) moves with 1/eta' p times
 * faster than TT's, and the 1/eta' axis has 32 points); tolerance 3.5 %, 1.5x that. A slice of
 * the wrong order or a wrong layout is off by O(1).
 * err_D, the build's own trilinear error over the whole grid (narrow widths included), measured
 * 0.21 of max |W| (TT/TRT: 0.13): checked < 0.3. */
TEST(srbf_deon_tables_slices) {
    sl_srbf_tables t;
    CHECK(get_tables(&t) == 0);
    if (sl_test_failed_now()) return;
    enum { NPT = 5 };
    const double pts[NPT][3] = {
        {0.61, 0.37, 0.4}, {0.23, 1.3, 2.2}, {0.9, 0.55, 3.0}, {0.45, 4.0, 1.1}, {0.71, 0.8, 1.7}};
    const int orders[3] = {3, 5, 8};
    double worst = 0.0;
    for (int op = 0; op < 3; op++) {
        int p = orders[op];
        double ex[NPT][4], got[NPT][4], scale = 0.0;
        for (int k = 0; k < NPT; k++) {
            double x = pts[k][0], lam = pts[k][1], phi = pts[k][2];
            sl_srbf_deon_cell c;
            sl_srbf_deon_cell_init((float)x, (float)lam, (float)phi, &c);
            for (int i = 0; i < 4; i++) {
                float A[4] = {0, 0, 0, 0};
                A[i] = 1.0f;
                ex[k][i] = sl_srbf_W_exact_order(p, i, x, lam, phi);
                got[k][i] = sl_srbf_deon_cell_dot(t.D, p, &c, A);
                scale = fmax(scale, fabs(ex[k][i]));
            }
        }
        for (int k = 0; k < NPT; k++)
            for (int i = 0; i < 4; i++) {
                worst = fmax(worst, fabs(got[k][i] - ex[k][i]) / scale);
                CHECK_MSG(fabs(got[k][i] - ex[k][i]) <= 0.035 * scale,
                          "p %d point %d W_%d = %g, direct %g (scale %g)", p, k, i, got[k][i],
                          ex[k][i], scale);
            }
    }
    CHECK(worst > 0.0); /* the comparison ran */
    CHECK(t.err_D >= 0.0 && t.err_D < 0.3);
    sl_srbf_tables_free(&t);
}

/* A fixed subset of the d'Eon stiff sample against the exact reference (double adaptive
 * quadrature, 1e-4). Tolerance 0.10 per row on the total I in the error measure of numerics.md
 * sec. 5: the whole 150-row sample measured median 0.0013, p95 0.014 and max 0.049
 * (docs/srbf.md), so 0.10 is twice the worst row; and a median <= 0.01 over the subset (the
 * issue's target). Dropping R, TT or TRT, or a wrong normalisation, moves such rows by far more
 * than 0.10. */
TEST(srbf_deon_fast_vs_exact) {
    sl_srbf_tables t;
    CHECK(get_tables(&t) == 0);
    if (sl_test_failed_now()) return;
    enum { N = 40, STEP = 4 };
    sl_srbf_config cfg[N];
    sl_srbf_sample(SL_SRBF_SAMPLE_SEED, N, cfg);
    double err[N];
    int ne = 0;
    for (int r = 0; r < N; r += STEP) {
        const sl_srbf_config *c = cfg + r + (r / STEP) % STEP; /* every material, every kind */
        if (c >= cfg + N) continue;
        sl_material m;
        deon_material(c->material, &m);
        double ex[SL_MATERIAL_MAX_ORDERS + 3];
        float got[SL_SRBF_DEON_NOUT];
        slref_srbf(&m, 0, c->theta_o, c->phi_o, c->theta_j, c->phi_j, c->lambda, ex);
        fast_one(&t, &m, c->theta_o, c->phi_o, c->theta_j, c->phi_j, c->lambda, got);
        int no = m.orders;
        double er = slref_srbf_error(got[no + 2], ex[no + 2], c->lambda);
        CHECK_MSG(er <= 0.10, "row %d (material %d): I %g, exact %g, error %.3f", (int)(c - cfg),
                  c->material, (double)got[no + 2], ex[no + 2], er);
        err[ne++] = er;
    }
    CHECK(ne >= 8);
    double med = quantile(err, ne, 0.5);
    CHECK_MSG(med <= 0.01, "median error %.4f", med);
    sl_srbf_tables_free(&t);
}

/* lambda -> 0: G concentrates on omega_j with integral int G = pi lambda^2 (1 - e^(-4/lambda^2)),
 * so I / int G -> f(omega_j, omega_o), the reference scattering function (double, an
 * independent code path: adaptive N_p, exact M_p). At lambda = 0.02 the lobe still averages f
 * over ~1 deg, which against beta 5..15 deg moves the value by ~(0.02/beta)^2 ~ 1 %; the fast
 * path's own error here is R's: the exact Fresnel's residual over Schlick through 4 nodes in c
 * is off by up to 5 % of N_0 (checked against slref_deon_np at kappa -> infinity), TT's 2 %.
 * Measured worst 4.2 % of the total f (a query where R dominates); tolerance 6 % of the total
 * f, per output and total. Dropping an order, a width or the cos theta_i factor is >= 10 %. */
TEST(srbf_deon_limit_small_lambda) {
    sl_srbf_tables t;
    CHECK(get_tables(&t) == 0);
    if (sl_test_failed_now()) return;
    const double q[4][4] = {{0.3, 0.5, -0.2, 2.9},
                            {0.3, 0.5, -0.45, 0.6},
                            {-0.6, 1.0, 0.5, -1.8},
                            {1.0, 0.0, -0.6, -0.4}}; /* theta_o, phi_o, theta_j, phi_j */
    const int mats[2] = {0, 4};
    for (int mi = 0; mi < 2; mi++)
        for (int k = 0; k < 4; k++) {
            sl_material m;
            deon_material(mats[mi], &m);
            double lam = 0.02, f[SL_MATERIAL_MAX_ORDERS + 3];
            float got[SL_SRBF_DEON_NOUT];
            slref_deon_scatter(&m, 0, q[k][2], q[k][3], q[k][0], q[k][1], f);
            fast_one(&t, &m, q[k][0], q[k][1], q[k][2], q[k][3], lam, got);
            double ig = slref_srbf_lobe_integral(lam);
            int no = m.orders;
            for (int p = 0; p <= no + 2; p++)
                CHECK_MSG(fabs(got[p] / ig - f[p]) <= 0.06 * f[no + 2],
                          "mat %d query %d output %d: I/intG %g, f %g (f total %g)", mats[mi], k, p,
                          got[p] / ig, f[p], f[no + 2]);
        }
    sl_srbf_tables_free(&t);
}

/* Extreme inputs: beta 0.5 deg (v = 7.6e-5: M_p peaks ~1e4, log space), lambda 3 (wider than the
 * tables), lobes and views at the poles, grazing views: every output finite and >= 0, the
 * total the sum; at a pole the response cannot depend on phi_j (G is symmetric about the fiber
 * axis there): equal to float rounding (1e-5 relative: the same code with phi_j entering only
 * through phi = phi_o - phi_j and a zero kappa). */
TEST(srbf_deon_extreme_inputs) {
    sl_srbf_tables t;
    CHECK(get_tables(&t) == 0);
    if (sl_test_failed_now()) return;
    const double lams[4] = {0.02, 0.3, 3.0, 10.0};
    const double ths[6] = {-PI / 2, -1.5, -0.3, 0.0, 1.2, PI / 2};
    for (int mi = 0; mi < 5; mi++) {
        sl_material m;
        deon_material(mi, &m);
        if (mi == 3) m.orders = 32; /* the float backends' most */
        int no = m.orders;
        for (int a = 0; a < 6; a++)
            for (int b = 0; b < 6; b++)
                for (int l = 0; l < 4; l++) {
                    float got[SL_SRBF_DEON_NOUT];
                    fast_one(&t, &m, ths[a], 0.7, ths[b], -2.0, lams[l], got);
                    double s = 0.0;
                    int ok = 1;
                    for (int p = 0; p <= no + 1; p++) {
                        ok &= isfinite(got[p]) && got[p] >= 0.0f;
                        s += got[p];
                    }
                    CHECK_MSG(ok && fabs(got[no + 2] - s) <= 1e-5 * s + 1e-30,
                              "mat %d to %g tj %g lam %g: not finite/negative or bad total", mi,
                              ths[a], ths[b], lams[l]);
                }
        /* pole invariance */
        for (int l = 0; l < 4; l++) {
            float a0[SL_SRBF_DEON_NOUT], a1[SL_SRBF_DEON_NOUT];
            fast_one(&t, &m, 0.4, 0.3, PI / 2, 0.0, lams[l], a0);
            fast_one(&t, &m, 0.4, 0.3, PI / 2, 2.5, lams[l], a1);
            CHECK_REL(a0[no + 2], a1[no + 2], 1e-5);
        }
    }
    /* lambda 3 against the exact reference (the wide-lobe limit of the tables): 0.05 */
    sl_material m;
    deon_material(0, &m);
    double ex[SL_MATERIAL_MAX_ORDERS + 3];
    float got[SL_SRBF_DEON_NOUT];
    slref_srbf(&m, 0, 0.5, 1.0, -0.3, 0.0, 3.0, ex);
    fast_one(&t, &m, 0.5, 1.0, -0.3, 0.0, 3.0, got);
    CHECK_MSG(slref_srbf_error(got[5], ex[5], 3.0) <= 0.05, "lambda 3: %g vs %g", (double)got[5],
              ex[5]);
    sl_srbf_tables_free(&t);
}

/* C twin against the OpenCL kernel (PoCL here) on 200 rows of the sample per material: the
 * same float header, so only device exp/log/asin ulps differ: 1e-3 relative of the row's total,
 * as the Marschner kernel check (host/passes/shade/srbf_cl.c) allows. */
TEST(srbf_deon_c_vs_opencl) {
    sl_device dev = {0};
    sl_err e;
    SL_TEST_OPEN_CL(&dev, &e);
    unsigned long k0 = sl_cl_kernels_enqueued();
    sl_srbf_tables t;
    CHECK(get_tables(&t) == 0);
    enum { N = 200 };
    sl_srbf_config cfg[N];
    sl_srbf_sample(SL_SRBF_SAMPLE_SEED, N, cfg);
    float *in = malloc(N * 5 * sizeof *in);
    float *a = malloc(N * SL_SRBF_DEON_NOUT * sizeof *a),
          *b = malloc(N * SL_SRBF_DEON_NOUT * sizeof *b);
    for (int r = 0; r < N; r++)
        sl_srbf_config_row(cfg + r, in + 5 * r);
    for (int mi = 0; mi < 5 && !sl_test_failed_now(); mi++) {
        sl_material m;
        deon_material(mi, &m);
        sl_fiber_params fp;
        sl_material_to_fiber(&m, 0, &fp);
        int no = m.orders;
        CHECK(slcl_srbf_deon_batch(dev.cl, &fp, &t, N, in, a, &e) == 0);
        slc_srbf_deon_batch(&fp, t.C, t.H, t.D, N, in, b);
        for (int r = 0; r < N; r++) {
            float tot = b[r * (no + 3) + no + 2];
            for (int p = 0; p <= no + 2; p++) {
                float x = a[r * (no + 3) + p], y = b[r * (no + 3) + p];
                CHECK_MSG(fabsf(x - y) <= 1e-3f * tot + 1e-12f, "mat %d row %d out %d: cl %g c %g",
                          mi, r, p, (double)x, (double)y);
            }
        }
    }
    free(in);
    free(a);
    free(b);
    CHECK_CL_RAN(k0);
    sl_srbf_tables_free(&t);
    sl_device_close(&dev);
}

/* The renderer's RGB rows (sl_srbf_deon_rgb_row) against three single-channel evaluations
 * (the same float code with sigma_a set per channel: equal to the last bit, tolerance 1e-6
 * relative for the order of the sums) and, with a device, the OpenCL rgb kernel against the C
 * batch (1e-3 of the row's total, as above). */
TEST(srbf_deon_rgb_rows) {
    sl_srbf_tables t;
    CHECK(get_tables(&t) == 0);
    if (sl_test_failed_now()) return;
    enum { N = 60 };
    sl_srbf_config cfg[N];
    sl_srbf_sample(SL_SRBF_SAMPLE_SEED, N, cfg);
    float in[N * 5], sig[N * 3], rgb[N * 9], cl_rgb[N * 9];
    for (int r = 0; r < N; r++) {
        sl_srbf_config_row(cfg + r, in + 5 * r);
        sig[3 * r] = 0.1f + 0.05f * (float)(r % 7);
        sig[3 * r + 1] = r % 3 ? sig[3 * r] : 1.5f; /* some rows with equal channels */
        sig[3 * r + 2] = 2.0f;
    }
    sl_material m;
    deon_material(2, &m); /* 8 orders */
    sl_fiber_params fp;
    sl_material_to_fiber(&m, 0, &fp);
    slc_srbf_deon_rgb_batch(&fp, t.C, t.H, t.D, N, in, sig, rgb);
    for (int r = 0; r < N; r++)
        for (int ch = 0; ch < 3; ch++) {
            sl_fiber_params q = fp;
            q.sigma_a = sig[3 * r + ch];
            float o[SL_SRBF_DEON_NOUT], rest = 0.0f;
            slc_srbf_deon_batch(&q, t.C, t.H, t.D, 1, in + 5 * r, o);
            for (int p = 2; p <= m.orders + 1; p++)
                rest += o[p];
            CHECK_REL(rgb[9 * r + ch], o[0], 1e-6);
            CHECK_REL(rgb[9 * r + 3 + ch], o[1], 1e-6);
            CHECK_REL(rgb[9 * r + 6 + ch], rest, 1e-6);
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

/* ---- measurement (not a check): SL_SRBF_DEON_MEASURE=<rows> ---- */

static double rate(const sl_srbf_tables *t, sl_device *dev, int deon, const float *in, int n,
                   int reps) {
    sl_material m;
    deon_material(0, &m);
    if (!deon) sl_material_default(&m);
    m.orders = 8;
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
            if (deon)
                slcl_srbf_deon_batch(dev->cl, &fp, t, big, rows, out, &e);
            else
                slcl_srbf_batch(dev->cl, &fp, t, SL_SRBF_METHOD_FAST, 4, big, rows, out, &e);
        } else if (deon)
            slc_srbf_deon_batch(&fp, t->C, t->H, t->D, big, rows, out);
        else
            slc_srbf_batch(&fp, t->C, t->H, SL_SRBF_METHOD_FAST, 4, big, rows, out);
        best = fmin(best, sl_now() - t0);
    }
    free(rows);
    free(out);
    return (double)big / best;
}

TEST(srbf_deon_measure) {
    const char *v = getenv("SL_SRBF_DEON_MEASURE");
    if (!v || atoi(v) <= 0) {
        SKIP("set SL_SRBF_DEON_MEASURE=<rows> to measure the d'Eon stiff sample");
        return;
    }
    int n = atoi(v);
    sl_srbf_tables t;
    CHECK(get_tables(&t) == 0);
    sl_srbf_config *cfg = malloc((size_t)n * sizeof *cfg);
    sl_srbf_sample(SL_SRBF_SAMPLE_SEED, n, cfg);
    /* per output kind: 0 R, 1 TT, 2 TRT, 3 orders >= 3, 4 rest, 5 total */
    double *err[6];
    int cnt[6] = {0};
    for (int k = 0; k < 6; k++)
        err[k] = malloc((size_t)n * 40 * sizeof(double));
    double t_ref = 0.0;
    int speed_only = getenv("SL_SRBF_DEON_SPEED_ONLY") != NULL; /* skip the exact values */
    for (int r = 0; r < n && !speed_only; r++) {
        const sl_srbf_config *c = cfg + r;
        sl_material m;
        deon_material(c->material, &m);
        double ex[SL_MATERIAL_MAX_ORDERS + 3];
        float got[SL_SRBF_DEON_NOUT];
        double t0 = sl_now();
        slref_srbf(&m, 0, c->theta_o, c->phi_o, c->theta_j, c->phi_j, c->lambda, ex);
        t_ref += sl_now() - t0;
        fast_one(&t, &m, c->theta_o, c->phi_o, c->theta_j, c->phi_j, c->lambda, got);
        int no = m.orders;
        for (int p = 0; p <= no + 2; p++) {
            int kind = p <= 2 ? p : (p <= no ? 3 : (p == no + 1 ? 4 : 5));
            double er = slref_srbf_error(got[p], ex[p], c->lambda);
            err[kind][cnt[kind]++] = er;
            if (kind == 5 && er > 0.03)
                printf("  row %d mat %d to %.3f po %.3f tj %.3f pj %.3f lam %.3f: I %.6g exact "
                       "%.6g err %.3f\n",
                       r, c->material, c->theta_o, c->phi_o, c->theta_j, c->phi_j, c->lambda,
                       (double)got[p], ex[p], er);
        }
    }
    const char *names[6] = {"I_0 (R)", "I_1 (TT)", "I_2 (TRT)", "I_3..", "I_rest", "I"};
    printf("d'Eon fast vs exact, %d rows of the stiff sample (reference %.1f s):\n", n, t_ref);
    for (int k = 0; k < 6 && !speed_only; k++) {
        double med = quantile(err[k], cnt[k], 0.5), p95 = quantile(err[k], cnt[k], 0.95),
               mx = quantile(err[k], cnt[k], 1.0);
        printf("  %-10s n %4d  median %.4f  p95 %.4f  max %.4f\n", names[k], cnt[k], med, p95, mx);
    }
    /* speed: the same rows, d'Eon (8 orders) and the Marschner fast path, best of 3 */
    float *in = malloc((size_t)n * 5 * sizeof *in);
    for (int r = 0; r < n; r++)
        sl_srbf_config_row(cfg + r, in + 5 * r);
    int reps = 20000 / n + 1;
    printf("lobe evaluations per second, C twin, 1 thread: deon (8 orders) %.3g, marschner fast "
           "%.3g\n",
           rate(&t, NULL, 1, in, n, reps), rate(&t, NULL, 0, in, n, reps));
    sl_device dev = {0};
    sl_err e;
    if (sl_test_open_cl(&dev, &e) == 0) {
        reps = 200000 / n + 1;
        rate(&t, &dev, 1, in, n, 1); /* program builds */
        rate(&t, &dev, 0, in, n, 1);
        printf("lobe evaluations per second, OpenCL (%s, uploads included): deon %.3g, "
               "marschner fast %.3g\n",
               sl_cl_device_name(dev.cl), rate(&t, &dev, 1, in, n, reps),
               rate(&t, &dev, 0, in, n, reps));
        sl_device_close(&dev);
    }
    for (int k = 0; k < 6; k++)
        free(err[k]);
    free(in);
    free(cfg);
    sl_srbf_tables_free(&t);
}
