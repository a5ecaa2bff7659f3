/* dual_deflect.c: the azimuthal deflection moments of a material (dual_deflect.h). */
#include "passes/volume/dual_deflect.h"

#include "base/common.h"
#include "base/parallel.h"
#include "fiber_c.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>

/* Midpoint nodes. The moments are ratios of smooth sums over the lobes: 8 x 24 x 48 gives the
 * same kf, kb as 16 x 48 x 96 within 2 % on the default, a dark and a d'Eon material
 * (test dual_deflect_resolution), at 1/8 of the cost (d'Eon's f: ~30 us a row). */
#define DEFLECT_NI 8  /* theta_i */
#define DEFLECT_NO 24 /* theta_o */
#define DEFLECT_NP 48 /* phi */

typedef struct deflect_job {
    const sl_fiber_params *fp;
    int ni, no, np;
    double *sums; /* 4 per theta_i node: forward, forward x (1 + cos), backward, backward x ... */
} deflect_job;

static void deflect_rows(void *arg, size_t begin, size_t end, int worker) {
    (void)worker;
    const deflect_job *j = arg;
    const size_t nrow = (size_t)j->no * j->np, w = slc_scatter_width(j->fp);
    float *in = sl_malloc(4 * nrow * sizeof *in), *out = sl_malloc(w * nrow * sizeof *out);
    for (size_t a = begin; a < end; a++) {
        double ti = -0.5 * M_PI + M_PI * ((double)a + 0.5) / j->ni;
        size_t k = 0;
        for (int o = 0; o < j->no; o++)
            for (int q = 0; q < j->np; q++, k++) {
                in[4 * k] = (float)ti, in[4 * k + 1] = 0.0f;
                in[4 * k + 2] = (float)(-0.5 * M_PI + M_PI * (o + 0.5) / j->no);
                in[4 * k + 3] = (float)(-M_PI + 2.0 * M_PI * (q + 0.5) / j->np);
            }
        slc_scatter_batch(j->fp, nrow, in, out);
        double *s = j->sums + 4 * a;
        s[0] = s[1] = s[2] = s[3] = 0.0;
        k = 0;
        for (int o = 0; o < j->no; o++) {
            double wo = cos(ti) * cos(-0.5 * M_PI + M_PI * (o + 0.5) / j->no);
            for (int q = 0; q < j->np; q++, k++) {
                double phi = -M_PI + 2.0 * M_PI * (q + 0.5) / j->np;
                double f = out[w * k + w - 1]; /* the last column: the whole f */
                if (!(f > 0.0) || !isfinite(f)) continue;
                double e = wo * f, tri = fabs(phi) / M_PI, c1 = 1.0 + cos(phi);
                s[0] += e * tri, s[1] += e * tri * c1;
                s[2] += e * (1.0 - tri), s[3] += e * (1.0 - tri) * c1;
            }
        }
    }
    free(in);
    free(out);
}

void sl_dual_deflect_moments(const sl_fiber_params *fp, int ni, int no, int np, float *kf,
                             float *kb) {
    double *sums = sl_calloc((size_t)4 * ni, sizeof *sums);
    deflect_job j = {fp, ni, no, np, sums};
    sl_parallel_for(sl_parallel_cpus(), (size_t)ni, 1, deflect_rows, &j);
    double t[4] = {0, 0, 0, 0};
    for (int a = 0; a < ni; a++)
        for (int q = 0; q < 4; q++)
            t[q] += sums[4 * a + q];
    free(sums);
    *kf = t[0] > 0.0 ? (float)(2.0 * t[1] / t[0]) : 0.0f;
    *kb = t[2] > 0.0 ? (float)(2.0 * t[3] / t[2]) : 0.0f;
}

#define NORM_S0 1.0
#define NORM_SMAX 6.0

/* N(mu, s): 8 panels of 8-point Gauss-Legendre over the part of [-pi/2, pi/2] within 7 s of mu
 * (beyond, the Gaussian is below 1e-21), in x = mu + s z, so a narrow spread is resolved too. */
static double norm_exact(double mu, double s) {
    static const double x8[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                 0.9602898564975363};
    static const double w8[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                 0.1012285362903763};
    if (!(s > 1e-6)) return cos(mu);
    double a = fmax(-0.5 * M_PI, mu - 7.0 * s), b = fmin(0.5 * M_PI, mu + 7.0 * s);
    if (!(b > a)) return 0.0;
    double sum = 0.0, hw = (b - a) / 16.0;
    for (int p = 0; p < 8; p++) {
        double c = a + (2 * p + 1) * hw;
        for (int q = 0; q < 4; q++)
            for (int sg = -1; sg <= 1; sg += 2) {
                double x = c + sg * hw * x8[q], z = (x - mu) / s;
                sum += hw * w8[q] * exp(-z * z) * cos(x);
            }
    }
    return sum / (sqrt(M_PI) * s);
}

/* N on SL_DEFLECT_NMU x SL_DEFLECT_NS nodes: material-independent, built once per process. */
static float norm_tab[SL_DEFLECT_NMU * SL_DEFLECT_NS];
static pthread_once_t norm_once = PTHREAD_ONCE_INIT;

static void norm_table(void) {
    float *t = norm_tab;
    double xmax = NORM_SMAX / (NORM_SMAX + NORM_S0);
    for (int a = 0; a < SL_DEFLECT_NMU; a++) {
        double mu = -0.5 * M_PI + M_PI * a / (SL_DEFLECT_NMU - 1);
        for (int b = 0; b < SL_DEFLECT_NS; b++) {
            double x = xmax * b / (SL_DEFLECT_NS - 1), s = NORM_S0 * x / (1.0 - x);
            t[a * SL_DEFLECT_NS + b] = (float)norm_exact(mu, s);
        }
    }
}

float sl_dual_deflect_norm(float theta_j, float s) {
    pthread_once(&norm_once, norm_table);
    float u = (theta_j + 0.5f * (float)M_PI) * ((float)(SL_DEFLECT_NMU - 1) / (float)M_PI);
    u = u > 0.0f ? (u < (float)(SL_DEFLECT_NMU - 1) ? u : (float)(SL_DEFLECT_NMU - 1)) : 0.0f;
    float xmax = (float)(NORM_SMAX / (NORM_SMAX + NORM_S0));
    float v = s > 0.0f ? s / (s + (float)NORM_S0) / xmax * (float)(SL_DEFLECT_NS - 1) : 0.0f;
    v = v < (float)(SL_DEFLECT_NS - 1) ? v : (float)(SL_DEFLECT_NS - 1);
    int a = (int)u, b = (int)v;
    a = a > SL_DEFLECT_NMU - 2 ? SL_DEFLECT_NMU - 2 : a;
    b = b > SL_DEFLECT_NS - 2 ? SL_DEFLECT_NS - 2 : b;
    float fu = u - (float)a, fv = v - (float)b;
    const float *r0 = norm_tab + a * SL_DEFLECT_NS + b, *r1 = r0 + SL_DEFLECT_NS;
    return (1.0f - fu) * ((1.0f - fv) * r0[0] + fv * r0[1]) +
           fu * ((1.0f - fv) * r1[0] + fv * r1[1]);
}

void sl_dual_deflect_build(const sl_material *m, const sl_dual_tables *t, sl_dual_deflect *d) {
    int nch = m->sigma_a_rgb ? 3 : 1;
    for (int c = 0; c < nch; c++) {
        sl_fiber_params fp;
        sl_material_to_fiber(m, c, &fp);
        sl_dual_deflect_moments(&fp, DEFLECT_NI, DEFLECT_NO, DEFLECT_NP, &d->kf[c], &d->kb[c]);
    }
    for (int c = nch; c < 3; c++)
        d->kf[c] = d->kf[0], d->kb[c] = d->kb[0];
    for (int c = 0; c < 3; c++) {
        /* sigma_b^2 weighted by a_b cos theta_d (trapezoid on the table's nodes, as sl_dual_means)
         */
        const float *ab = t->tab[c] + SL_DUAL_AB * SL_DUAL_N,
                    *sb = t->tab[c] + SL_DUAL_SIGMA_B * SL_DUAL_N;
        double num = 0.0, den = 0.0;
        for (int i = 1; i < SL_DUAL_N; i++) {
            double x0 = sl_dual_node(i - 1), x1 = sl_dual_node(i), h = 0.5 * (x1 - x0);
            double w0 = h * cos(x0) * ab[i - 1], w1 = h * cos(x1) * ab[i];
            num += w0 * sb[i - 1] * sb[i - 1] + w1 * sb[i] * sb[i];
            den += w0 + w1;
        }
        d->sb2[c] = den > 0.0 ? (float)(num / den) : 0.0f;
    }
}
