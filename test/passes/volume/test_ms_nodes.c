/* test_ms_nodes.c: the multiple-scattering response of per-strand sigma_a
 * (host/passes/volume/volume_ms_nodes.h) against the response tables built for a material whose
 * sigma_a is the strand's own value (sl_volume_ms_init at that value: the same tables the
 * frame uses when the material itself has it, themselves checked against the direct evaluation
 * in test_ms_table.c). Exact nodes must give that value to float rounding; grid nodes blend two
 * neighbours, and their error is the blend's. */
#include "test.h"

#include "passes/volume/volume_ms_nodes.h"
#include "scene/material.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

static double unif(uint64_t *s) {
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) * (1.0 / 9007199254740992.0);
}

static int chiang(const char *json, sl_material *m) {
    sl_err e = {{0}};
    int rc = sl_material_parse(json, strlen(json), "test_ms_nodes", m, &e);
    CHECK_MSG(rc == 0, "%s", e.msg);
    return rc;
}

/* Rows of angles, lobe width and spread (the ranges of test_ms_table.c's typical run). */
enum { NROW = 400 };
static void rows(uint64_t seed, float *r) {
    for (int i = 0; i < NROW; i++, r += 6) {
        r[0] = (float)((2 * unif(&seed) - 1) * 1.2);
        r[1] = (float)((2 * unif(&seed) - 1) * PI);
        r[2] = (float)((2 * unif(&seed) - 1) * 1.2);
        r[3] = (float)((2 * unif(&seed) - 1) * PI);
        r[4] = (float)(0.05 * pow(40.0, unif(&seed)));
        r[5] = (float)(0.4 * unif(&seed));
    }
}

/* Errors of the nodes' MG and ML at channel values sa against the tables of m with sigma_a =
 * sa, relative to the largest exact value of the same term over the rows (a term's share of a
 * pixel is what matters; a tail value near 0 counts by its absolute error): 2 x 3 x NROW into
 * err. Returns the largest. */
static double errors(const sl_volume_ms_nodes *nd, const sl_material *m, const float sa[3],
                     const float *r, double *err) {
    sl_err e = {{0}};
    sl_material mx = *m;
    mx.sigma_a_rgb = 1;
    for (int c = 0; c < 3; c++)
        mx.sigma_a[c] = sa[c];
    sl_volume_ms ms;
    CHECK_MSG(sl_volume_ms_init(&mx, &ms, &e) == 0, "%s", e.msg);
    if (sl_test_failed_now()) return 1;
    static double g[NROW][3], l[NROW][3], gx[NROW][3], lx[NROW][3];
    double gs = 0, ls = 0, worst = 0;
    for (int i = 0; i < NROW; i++) {
        const float *x = r + 6 * i;
        float sf[3] = {x[5], x[5], x[5]}, MG[3], ML[3], MGx[3], MLx[3];
        sl_volume_ms_nodes_terms(nd, sa, x[0], x[1], x[2], x[3], x[4], sf, MG, ML);
        sl_volume_ms_terms(&ms, x[0], x[1], x[2], x[3], x[4], sf, MGx, MLx);
        for (int c = 0; c < 3; c++) {
            g[i][c] = MG[c], l[i][c] = ML[c], gx[i][c] = MGx[c], lx[i][c] = MLx[c];
            gs = fmax(gs, fabs(MGx[c]));
            ls = fmax(ls, fabs(MLx[c]));
        }
    }
    for (int i = 0; i < NROW; i++)
        for (int c = 0; c < 3; c++) {
            err[6 * i + c] = fabs(g[i][c] - gx[i][c]) / gs;
            err[6 * i + 3 + c] = fabs(l[i][c] - lx[i][c]) / ls;
            worst = fmax(worst, fmax(err[6 * i + c], err[6 * i + 3 + c]));
        }
    sl_volume_ms_free(&ms);
    return worst;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* A file colour (every strand alike) and a few paint colours: the nodes are the strands' own
 * values and the response is that of the tables built at the value: identical bits expected
 * (the same build on the same channel value); 1e-6 allows a compiler's contraction. */
TEST(ms_nodes_exact_values) {
    sl_material m;
    if (chiang("{\"model\": \"chiang\", \"melanin\": 0.3}", &m)) return;
    enum { NS = 50 };
    float sa[3 * NS];
    const float colours[3][3] = {{0.0f, 1.7e-4f, 9.2e-3f}, {2.5f, 3.1f, 4.0f}, {0.3f, 0.3f, 0.3f}};
    for (int i = 0; i < NS; i++)
        memcpy(sa + 3 * i, colours[i % 3], sizeof colours[0]);
    sl_err e = {{0}};
    sl_volume_ms_nodes nd;
    CHECK_MSG(sl_volume_ms_nodes_init(&m, sa, NS, 2, &nd, &e) == 0, "%s", e.msg);
    if (sl_test_failed_now()) return;
    CHECK(nd.exact == 1);
    CHECK_MSG(nd.n == 7, "distinct channel values: %d, want 7", nd.n);
    float *r = malloc(NROW * 6 * sizeof *r);
    rows(11, r);
    double *err = malloc(6 * NROW * sizeof *err);
    for (int k = 0; k < 3; k++) {
        double worst = errors(&nd, &m, colours[k], r, err);
        CHECK_MSG(worst <= 1e-6, "colour %d: max error %g", k, worst);
    }
    free(err);
    free(r);
    sl_volume_ms_nodes_free(&nd);
}

/* Strands spread over sigma_a 0 .. 8 (more distinct values than nodes): the nodes are spaced
 * evenly in ln(sigma_a + 0.02) and a value between two blends them geometrically (linearly in
 * sigma_a). Against the tables built at the value, over 8 values x 400 rows x 3 channels x
 * {MG, ML}, measured with 12 values (chiang melanin 0.3; a blond d'Eon): median 5e-6 / 3e-6,
 * p95 8e-4 / 1.1e-3, max 2.6e-2 / 0.20. The max is one ML row of the d'Eon material (sigma_a
 * 0.77) where ML is not monotone in sigma_a; it stays inside the response table's own error against
 * the direct evaluation (ML max 0.3, test ms_table_vs_exact_typical). Checked: median 1e-3,
 * p95 1e-2, max 0.3. */
TEST(ms_nodes_grid_vs_exact) {
    const char *mats[2] = {"{\"model\": \"chiang\", \"melanin\": 0.3}",
                           "{\"model\": \"deon\", \"sigma_a\": [0.2, 0.3, 0.5]}"};
    enum { NV = 8 };
    float *r = malloc(NROW * 6 * sizeof *r);
    double *err = malloc((size_t)NV * 6 * NROW * sizeof *err);
    rows(5, r);
    for (int v = 0; v < 2; v++) {
        sl_material m;
        if (chiang(mats[v], &m)) break;
        enum { NS = 300 };
        float sa[3 * NS];
        uint64_t s = 99 + (uint64_t)v;
        for (int i = 0; i < 3 * NS; i++) /* log-uniform in sigma_a + 0.02 over 0 .. 8 */
            sa[i] = (float)(0.02 * pow(8.02 / 0.02, unif(&s)) - 0.02);
        sa[0] = 0.0f;
        sa[1] = 8.0f;
        sl_err e = {{0}};
        sl_volume_ms_nodes nd;
        CHECK_MSG(sl_volume_ms_nodes_init(&m, sa, NS, 2, &nd, &e) == 0, "%s", e.msg);
        if (sl_test_failed_now()) break;
        CHECK(nd.exact == 0 && nd.n == SL_MSN_MAX);
        CHECK(nd.sa[0] == 0.0f && nd.sa[nd.n - 1] == 8.0f);
        for (int k = 0; k < NV; k++) /* strands' own values, off the nodes */
            errors(&nd, &m, sa + 3 * (7 * k + 2), r, err + (size_t)k * 6 * NROW);
        int n = NV * 6 * NROW;
        qsort(err, (size_t)n, sizeof *err, cmp_double);
        double med = err[n / 2], p95 = err[(int)(0.95 * (n - 1))], mx = err[n - 1];
        if (getenv("SL_TEST_VERBOSE"))
            fprintf(stderr, "  material %d: grid nodes: median %.2g p95 %.2g max %.2g\n", v, med,
                    p95, mx);
        CHECK_MSG(med <= 1e-3 && p95 <= 1e-2 && mx <= 0.3, "material %d: median %g p95 %g max %g",
                  v, med, p95, mx);
        sl_volume_ms_nodes_free(&nd);
    }
    free(err);
    free(r);
}

/* Placement: one strand, values sorted and unique, -0 and 0 one node; the key changes with a
 * node value and not with the order of strands. */
TEST(ms_nodes_place) {
    float a[6] = {0.5f, -0.0f, 0.5f, 0.0f, 2.0f, 0.5f}, b[6] = {0.0f, 2.0f, 0.5f, 0.5f, 0.0f, 0.5f};
    sl_volume_ms_nodes x, y;
    sl_volume_ms_nodes_place(a, 2, &x);
    sl_volume_ms_nodes_place(b, 2, &y);
    CHECK(x.exact && x.n == 3 && x.nsets == 1);
    CHECK(x.sa[0] == 0.0f && x.sa[1] == 0.5f && x.sa[2] == 2.0f);
    CHECK(x.key == y.key);
    b[1] = 2.5f;
    sl_volume_ms_nodes_place(b, 2, &y);
    CHECK(x.key != y.key);
}
