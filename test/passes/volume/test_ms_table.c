/* test_ms_table.c: the per-material response table (kernels/ms_table.h, built by
 * sl_volume_ms_init) against the direct evaluation it replaces (sl_volume_ms_terms_exact:
 * kernels/ms_response.h, itself checked against brute-force quadrature in test_march_ms.c), on
 * random and extreme inputs: grazing theta_o / theta_j, lambda tiny and ~2, sigma_f 0 and large,
 * D at 0 and pi; and the combined response with T_f 0 and 1. Errors are relative to the exact
 * value where it matters (see ms_err) and reported as median / p95 / max with SL_TEST_VERBOSE. */
#include "test.h"

#include "cl_fixture.h"

#include "ms_table.h"
#include "passes/volume/volume_ms.h"
#include "passes/volume/ms_cl.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

static double unif(uint64_t *s) {
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) * (1.0 / 9007199254740992.0);
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Error of the table value a against the exact value b, relative to max(|b|, floor): floor is
 * 1e-3 of the largest exact value of the same term over the run (the row's scale), so a value
 * in a Gaussian tail counts by its absolute error against the term's scale (its share of any
 * pixel is < 1e-3 there) and not by a relative error of a number near 0. */
static double ms_err(double a, double b, double floor) {
    return fabs(a - b) / fmax(fabs(b), floor);
}

typedef struct stats {
    double med, p95, max;
} stats;

static stats summarize(double *e, int n) {
    qsort(e, (size_t)n, sizeof *e, cmp_double);
    stats s = {e[n / 2], e[(int)(0.95 * (n - 1))], e[n - 1]};
    return s;
}

/* n rows (theta_o, phi_o, theta_j, phi_j, lambda, sigma_f) from the given ranges; lambda
 * log-uniform. Errors of MG and ML over the 3 channels into eg, el (3 n each). */
static void run_rows(const sl_volume_ms *ms, int n, uint64_t seed, double tmax, double lmin,
                     double lmax, double smax, double *eg, double *el) {
    float *rows = malloc((size_t)n * 6 * sizeof *rows);
    double *xg = malloc((size_t)n * 3 * sizeof *xg), *xl = malloc((size_t)n * 3 * sizeof *xl);
    double *tg = malloc((size_t)n * 3 * sizeof *tg), *tl = malloc((size_t)n * 3 * sizeof *tl);
    double gmax = 0, lmx = 0;
    for (int i = 0; i < n; i++) {
        float *r = rows + 6 * i;
        r[0] = (float)((2 * unif(&seed) - 1) * tmax);
        r[1] = (float)((2 * unif(&seed) - 1) * PI);
        r[2] = (float)((2 * unif(&seed) - 1) * tmax);
        r[3] = (float)((2 * unif(&seed) - 1) * PI);
        r[4] = (float)(lmin * pow(lmax / lmin, unif(&seed)));
        r[5] = (float)(smax * unif(&seed));
        /* sigma_f per channel differs (the march's spread is per channel) */
        float sf[3] = {r[5], 0.8f * r[5], 0.5f * r[5]}, MG[3], ML[3], MGx[3], MLx[3];
        sl_volume_ms_terms(ms, r[0], r[1], r[2], r[3], r[4], sf, MG, ML);
        sl_volume_ms_terms_exact(ms, r[0], r[1], r[2], r[3], r[4], sf, MGx, MLx);
        for (int c = 0; c < 3; c++) {
            tg[3 * i + c] = MG[c];
            tl[3 * i + c] = ML[c];
            xg[3 * i + c] = MGx[c];
            xl[3 * i + c] = MLx[c];
            /* the scale of a term: its exact value times cos theta_j (the table's part; 1/cos
             * theta_j is exact in both) */
            double ct = cos(r[2]);
            gmax = fmax(gmax, MGx[c] * ct);
            lmx = fmax(lmx, MLx[c] * ct);
        }
    }
    for (int i = 0; i < 3 * n; i++) {
        double ct = cos(rows[6 * (i / 3) + 2]);
        eg[i] = ms_err(tg[i] * ct, xg[i] * ct, 1e-3 * gmax);
        el[i] = ms_err(tl[i] * ct, xl[i] * ct, 1e-3 * lmx);
    }
    free(rows);
    free(xg);
    free(xl);
    free(tg);
    free(tl);
}

static void materials(int v, sl_material *m) {
    sl_material_default(m);
    if (v == 1) { /* rgb, eccentric, the default scene's absorption */
        m->sigma_a_rgb = 1;
        m->sigma_a[0] = 0.18;
        m->sigma_a[1] = 0.32;
        m->sigma_a[2] = 0.62;
        m->eccentricity = 0.9;
    } else if (v == 2) { /* dark, wide lobes */
        m->sigma_a_rgb = 1;
        m->sigma_a[0] = 1.2;
        m->sigma_a[1] = 1.6;
        m->sigma_a[2] = 2.4;
        m->beta[0] *= 1.6;
        m->beta[1] *= 1.6;
        m->beta[2] *= 1.6;
    }
}

/* Typical inputs: views and lobes away from the poles (|theta| < 1.3), lambda 0.05-2 (the
 * fitted lobes of data/default.json span 0.13-1.6), sigma_f 0-0.4 (the march's). */
TEST(ms_table_vs_exact_typical) {
    sl_err e = {{0}};
    enum { N = 4000 };
    double *eg = malloc(3 * N * sizeof *eg), *el = malloc(3 * N * sizeof *el);
    for (int v = 0; v < 3; v++) {
        sl_material m;
        materials(v, &m);
        sl_volume_ms ms;
        CHECK(sl_volume_ms_init(&m, &ms, &e) == 0);
        if (sl_test_failed_now()) break;
        run_rows(&ms, N, 7 + (uint64_t)v, 1.2, 0.05, 2.0, 0.4, eg, el);
        stats g = summarize(eg, 3 * N), l = summarize(el, 3 * N);
        if (getenv("SL_TEST_VERBOSE"))
            fprintf(stderr,
                    "  material %d (table %.3f s): MG median %.2e p95 %.2e max %.2e; ML median "
                    "%.2e p95 %.2e max %.2e\n",
                    v, ms.table_s, g.med, g.p95, g.max, l.med, l.p95, l.max);
        /* Interpolation error of a quadrilinear table of smooth functions (the narrow Gaussians
         * are analytic). Measured (3 materials): MG median 1.1-1.8e-3, p95 8.1-8.5e-3, max
         * 3.0-4.7e-2 (cells where N^G turns sharply in D or theta_d); ML median 0.4-1.2e-3,
         * p95 0.7-2.4e-2, max 3.5e-2-0.19 (|theta_o| > 1.1 with wide lobes, where the direct
         * evaluation's Gauss-Hermite nodes cross the +-pi/2 cut: it is itself discontinuous
         * in theta_o there, the table is not). Checked with ~1.5-2x margin. */
        CHECK_MSG(g.med <= 4e-3 && g.p95 <= 2e-2 && g.max <= 0.1,
                  "material %d: MG median %g p95 %g max %g", v, g.med, g.p95, g.max);
        CHECK_MSG(l.med <= 4e-3 && l.p95 <= 4e-2 && l.max <= 0.3,
                  "material %d: ML median %g p95 %g max %g", v, l.med, l.p95, l.max);
        sl_volume_ms_free(&ms);
    }
    free(eg);
    free(el);
}

/* At the table's own nodes (theta_o, theta_j, s_F, D all on nodes; u = theta_j - theta_o and
 * the (~Delta_b, ~sigma_b) table's s_F then are nodes too) the lookup returns the node values,
 * which are the direct evaluation's sums: equal to float rounding. This pins the layout and the
 * indexing (a shifted axis or stride gives O(1) errors). 2e-4 relative: the analytic G_t vs the
 * direct evaluation's Gaussian product (a few ulp through exp), the D and theta coordinates'
 * rounding (a fraction of 1e-6 of a cell). */
TEST(ms_table_nodes_exact) {
    sl_err e = {{0}};
    sl_material m;
    materials(1, &m);
    sl_volume_ms ms;
    CHECK(sl_volume_ms_init(&m, &ms, &e) == 0);
    if (sl_test_failed_now()) return;
    double worst = 0, big = 0;
    int n = 0;
    for (int o = 1; o < SL_MST_NO - 1; o += 3)
        for (int j = 2; j < SL_MST_NJ - 2; j += 5)
            for (int s = 1; s < SL_MST_NS; s += 3)
                for (int k = 0; k < SL_MST_ND; k += 4) {
                    float to = (float)(-PI / 2 + PI * o / (SL_MST_NO - 1));
                    float tj = (float)(-PI / 2 + PI * j / (SL_MST_NJ - 1));
                    float D = (float)(PI * k / (SL_MST_ND - 1));
                    float sF = sl_mst_node_s(s, SL_MST_NS), sf[3] = {0, 0, 0};
                    float MG[3], ML[3], MGx[3], MLx[3];
                    sl_volume_ms_terms(&ms, to, D, tj, 0.0f, sF, sf, MG, ML);
                    sl_volume_ms_terms_exact(&ms, to, D, tj, 0.0f, sF, sf, MGx, MLx);
                    for (int c = 0; c < 3; c++) {
                        big = fmax(big, fmax(MGx[c], MLx[c]));
                        double d = fmax(fabs(MG[c] - MGx[c]) / fmax(MGx[c], 1e-12),
                                        fabs(ML[c] - MLx[c]) / fmax(MLx[c], 1e-12));
                        if (fmax(MGx[c], MLx[c]) > 1e-9 && d > worst) worst = d;
                    }
                    n++;
                }
    if (getenv("SL_TEST_VERBOSE"))
        fprintf(stderr, "  %d node points: worst relative difference %.2e\n", n, worst);
    CHECK(big > 1e-3); /* not all zero */
    CHECK_MSG(worst <= 2e-4, "worst relative difference at nodes %g", worst);
    sl_volume_ms_free(&ms);
}

/* Extreme inputs through the full response (sl_volume_ms_response: T_f 0 and 1, T_j 0 and
 * 0.5): grazing views and lobes (|theta| up to 1.55), lambda 0.005 (far below the first s_F
 * cell) and 2.5, sigma_f 0 and 1.5, D = 0 and pi, and s_F beyond the table (lambda 6: clamped
 * coordinate, exact analytic factors). The table's response is compared with the same
 * combination of the direct terms (P(lambda) [max(T_f - T_j, 0) M^G + d_b T_f M^L]), relative to
 * max(exact, 1e-3 of the largest exact response of the set), T_f = 1 rows. Two groups:
 * |theta_o| <= 1.2 (grazing lobes, s_F below and beyond the table) measured median 1.8e-4,
 * p95 1.9e-2, max 3.8e-2, checked at median 0.01 and max 0.1; theta_o = +-1.55 lies in the last
 * theta_o cell, where cos^2 theta_i / cos^2 theta_d turns singular toward the corner
 * theta_o = -theta_i = +-pi/2 and the direct evaluation's Gauss-Hermite cut is discontinuous:
 * measured median 0.076, p95 0.43, max 0.72 (the table is 10-50 % high there; views within 4
 * degrees of the fiber axis), checked at median 0.2 and max 1. Everywhere: nothing negative or
 * non-finite, and T_f = 0 gives exactly 0. */
TEST(ms_table_extremes) {
    sl_err e = {{0}};
    sl_material m;
    materials(1, &m);
    sl_volume_ms ms;
    CHECK(sl_volume_ms_init(&m, &ms, &e) == 0);
    if (sl_test_failed_now()) return;
    const float th[] = {-1.55f, -1.2f, 0.0f, 0.7f, 1.55f};
    const float lam[] = {0.005f, 0.3f, 2.5f, 6.0f}, sig[] = {0.0f, 1.5f}, Ds[] = {0.0f, 3.14159f};
    const float Tfs[] = {0.0f, 1.0f}, Tjs[] = {0.0f, 0.5f};
    enum { NMAX = 5 * 5 * 4 * 2 * 2 * 2 * 2 * 3 };
    static double tv[NMAX], xv[NMAX], e0[NMAX], e1[NMAX];
    static int grazing[NMAX];
    int n = 0, bad = 0;
    for (int a = 0; a < 5; a++)
        for (int b = 0; b < 5; b++)
            for (int l = 0; l < 4; l++)
                for (int q = 0; q < 2; q++)
                    for (int d = 0; d < 2; d++)
                        for (int f = 0; f < 2; f++)
                            for (int g = 0; g < 2; g++) {
                                float sf[3] = {sig[q], sig[q], 0.5f * sig[q]}, Tf[3];
                                for (int c = 0; c < 3; c++)
                                    Tf[c] = Tfs[f];
                                float r[3], MGx[3], MLx[3];
                                sl_volume_ms_response(&ms, th[a], Ds[d], th[b], 0.0f, lam[l], Tf,
                                                      sf, Tjs[g], r);
                                sl_volume_ms_terms_exact(&ms, th[a], Ds[d], th[b], 0.0f, lam[l], sf,
                                                         MGx, MLx);
                                double l2 = (double)lam[l] * lam[l];
                                double P = PI * l2 * (1 - exp(-4 / l2));
                                for (int c = 0; c < 3; c++) {
                                    if (!isfinite(r[c]) || r[c] < 0) bad++;
                                    if (Tfs[f] == 0.0f) { /* exactly 0; not in the stats */
                                        bad += r[c] != 0.0f;
                                        continue;
                                    }
                                    tv[n] = r[c];
                                    xv[n] = P * (fmax(Tf[c] - Tjs[g], 0) * MGx[c] +
                                                 0.7 * Tf[c] * MLx[c]);
                                    grazing[n] = fabsf(th[a]) > 1.5f;
                                    n++;
                                }
                            }
    double mx = 0;
    for (int i = 0; i < n; i++)
        mx = fmax(mx, xv[i]);
    int n0 = 0, n1 = 0;
    for (int i = 0; i < n; i++) {
        double v = ms_err(tv[i], xv[i], 1e-3 * mx);
        if (grazing[i])
            e1[n1++] = v;
        else
            e0[n0++] = v;
    }
    stats s0 = summarize(e0, n0), s1 = summarize(e1, n1);
    if (getenv("SL_TEST_VERBOSE"))
        fprintf(stderr,
                "  |theta_o| <= 1.2: %d values, median %.2e p95 %.2e max %.2e; theta_o = +-1.55: "
                "%d values, median %.2e p95 %.2e max %.2e\n",
                n0, s0.med, s0.p95, s0.max, n1, s1.med, s1.p95, s1.max);
    CHECK(bad == 0);
    CHECK(mx > 0);
    CHECK_MSG(s0.med <= 0.01 && s0.max <= 0.1, "median %g max %g", s0.med, s0.max);
    CHECK_MSG(s1.med <= 0.2 && s1.max <= 1.0, "grazing: median %g max %g", s1.med, s1.max);
    sl_volume_ms_free(&ms);
}

/* The direct kernel (sl_ms_response_rows in kernels/ms.cl, kept as the table's reference on the
 * device) against the C direct evaluation: the same float math; the device's exp/cos/asin
 * within a few ulp move the N^G weights (node positions go through asin): 5e-4 relative or
 * 1e-7 absolute, as test_march_ms.c's table-kernel check. */
TEST(ms_table_opencl_exact_vs_c) {
    sl_err e = {{0}};
    sl_device dev;
    SL_TEST_OPEN_CL(&dev, &e);
    sl_material m;
    materials(1, &m);
    sl_volume_ms ms;
    CHECK(sl_volume_ms_init(&m, &ms, &e) == 0);
    enum { NR = 200 };
    float in[6 * NR], a[2 * NR];
    uint64_t s = 5;
    for (int i = 0; i < NR; i++) {
        float *r = in + 6 * i;
        r[0] = (float)((unif(&s) - 0.5) * 2.8);
        r[1] = (float)((unif(&s) - 0.5) * 6.2);
        r[2] = (float)((unif(&s) - 0.5) * 2.8);
        r[3] = (float)((unif(&s) - 0.5) * 6.2);
        r[4] = (float)(0.05 + 0.5 * unif(&s));
        r[5] = (float)(0.4 * unif(&s));
    }
    const int ch = 2;
    unsigned long k0 = sl_cl_kernels_enqueued();
    CHECK(slcl_ms_response_rows_exact(dev.cl, &ms, ch, NR, in, a, &e) == 0);
    CHECK_CL_RAN(k0);
    double worst = 0;
    for (int i = 0; i < NR && !sl_test_failed_now(); i++) {
        const float *r = in + 6 * i;
        float sf[3] = {r[5], r[5], r[5]}, MG[3], ML[3];
        sl_volume_ms_terms_exact(&ms, r[0], r[1], r[2], r[3], r[4], sf, MG, ML);
        double d0 = fabs(a[2 * i] - MG[ch]), d1 = fabs(a[2 * i + 1] - ML[ch]);
        if (d0 > 1e-7 && d0 / fabs(MG[ch]) > worst) worst = d0 / fabs(MG[ch]);
        if (d1 > 1e-7 && d1 / fabs(ML[ch]) > worst) worst = d1 / fabs(ML[ch]);
    }
    CHECK_MSG(worst <= 5e-4, "worst relative difference %g", worst);
    sl_volume_ms_free(&ms);
    sl_device_close(&dev);
}
