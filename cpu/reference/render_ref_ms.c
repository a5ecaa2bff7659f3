/* render_ref_ms.c: the dual-scattering tables of the reference renderer (render_ref.h):
 * the nine Zinke 2008 material terms of dual_ref.h and Xu 2011 Eq. 28's forward-averaged
 * azimuthal functions N^G_t, tabulated per colour channel over theta_d in double.
 *
 * theta_d nodes: theta_k = pi/2 sin(pi/2 k / (NTD - 1)) (denser toward grazing, where the terms
 * bend: docs/dual.md), linear interpolation. N^G_t: N_t (marschner_ref.c, eta for TRT, i.e. no
 * eccentricity) sampled at NPH_FINE midpoints over the circle, integrated over each window of
 * width pi by the running sum (windows start and end on cell edges), at NPH + 1 nodes over
 * [0, pi] (N^G is even in phi). */
#include "dual_ref.h"
#include "marschner_ref.h"
#include "render_ref.h"
#include "base/parallel.h"

#include <math.h>
#include <stdlib.h>

#define NTD 25
#define NPH 64
#define NPH_FINE 512 /* multiple of 4 * NPH / 2 so window edges fall on cell edges */

struct slref_ms_tables {
    int nch;
    double dual[3][NTD][9];
    double ng[3][3][NTD][NPH + 1];
};

static double td_node(int k) {
    return M_PI / 2 * sin(M_PI / 2 * k / (NTD - 1));
}

/* Fractional node index of |theta_d| (inverse of td_node). */
static double td_index(double td) {
    double a = fabs(td) / (M_PI / 2);
    if (a > 1) a = 1;
    return asin(a) / (M_PI / 2) * (NTD - 1);
}

typedef struct build_job {
    const sl_material *m;
    slref_ms_tables *t;
} build_job;

static void build_row(const sl_material *m, slref_ms_tables *t, int ch, int k) {
    double td = td_node(k);
    if (td > M_PI / 2 - 1e-9) td = M_PI / 2 - 1e-9;
    slref_dual_terms(m, ch, td, t->dual[ch][k]);
    for (int mode = 0; mode < 3; mode++) {
        double run[NPH_FINE + 1], dx = 2 * M_PI / NPH_FINE;
        run[0] = 0;
        for (int i = 0; i < NPH_FINE; i++) {
            double x = -M_PI + (i + 0.5) * dx;
            run[i + 1] = run[i] + dx * slref_marschner_N(m, ch, mode, m->eta, td, x);
        }
        /* Window [phi - pi/2, phi + pi/2], phi = j pi / NPH, in cells of the running sum
         * (cell 0 starts at -pi); periodic. */
        for (int j = 0; j <= NPH; j++) {
            int c0 = NPH_FINE / 2 + j * (NPH_FINE / 2) / NPH - NPH_FINE / 4;
            int c1 = c0 + NPH_FINE / 2;
            double s = 0;
            /* c0 >= 0 always; c1 may pass the end */
            if (c1 <= NPH_FINE)
                s = run[c1] - run[c0];
            else
                s = run[NPH_FINE] - run[c0] + run[c1 - NPH_FINE];
            t->ng[ch][mode][k][j] = s / M_PI;
        }
    }
}

/* Rows r = ch * NTD + k, each written by the one worker that takes it. */
static void build_rows(void *arg, size_t begin, size_t end, int worker) {
    (void)worker;
    const build_job *j = arg;
    for (size_t r = begin; r < end; r++)
        build_row(j->m, j->t, (int)r / NTD, (int)r % NTD);
}

int slref_ms_tables_build(const sl_material *m, int threads, slref_ms_tables **out, sl_err *e) {
    *out = NULL;
    if (m->model != SL_MODEL_MARSCHNER)
        return sl_fail(e, "reference: multiple scattering needs material.model \"marschner\" "
                          "(dual-scattering terms: docs/dual.md)");
    slref_ms_tables *t = sl_calloc(1, sizeof *t);
    t->nch = m->sigma_a_rgb ? 3 : 1;
    build_job j = {.m = m, .t = t};
    if (threads > 64) threads = 64;
    sl_parallel_for(threads, (size_t)t->nch * NTD, 1, build_rows, &j);
    *out = t;
    return 0;
}

void slref_ms_tables_free(slref_ms_tables *t) {
    free(t);
}

double slref_ms_term(const slref_ms_tables *t, int ch, int term, double theta_d) {
    if (ch >= t->nch) ch = 0;
    double x = td_index(theta_d);
    int k = (int)x;
    if (k >= NTD - 1) k = NTD - 2;
    double f = x - k;
    return (1 - f) * t->dual[ch][k][term] + f * t->dual[ch][k + 1][term];
}

double slref_ms_ng(const slref_ms_tables *t, int ch, int mode, double theta_d, double phi) {
    if (ch >= t->nch) ch = 0;
    double x = td_index(theta_d);
    int k = (int)x;
    if (k >= NTD - 1) k = NTD - 2;
    double f = x - k;
    double p = fabs(remainder(phi, 2 * M_PI)) / M_PI * NPH;
    int j = (int)p;
    if (j >= NPH) j = NPH - 1;
    double g = p - j;
    double a = (1 - g) * t->ng[ch][mode][k][j] + g * t->ng[ch][mode][k][j + 1];
    double b = (1 - g) * t->ng[ch][mode][k + 1][j] + g * t->ng[ch][mode][k + 1][j + 1];
    return (1 - f) * a + f * b;
}
