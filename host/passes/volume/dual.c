/* dual.c: dual-scattering tables of a material and the multiple-scattering share estimate
 * (host/passes/volume/dual.h, docs/dual.md). The math is kernels/dual_material.h through the C twin
 * cpu/dual_c.c.
 */
#include "passes/volume/dual.h"

#include "dual_c.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int sl_dual_tables_build(const sl_material *m, sl_dual_tables *t, sl_err *e) {
    (void)e; /* every model has its terms (kernels/dual_material.h, dual_ec.h) */
    t->nch = m->sigma_a_rgb ? 3 : 1;
    for (int c = 0; c < t->nch; c++) {
        sl_fiber_params fp;
        sl_material_to_fiber(m, c, &fp);
        slc_dual_table(&fp, t->tab[c]);
    }
    for (int c = t->nch; c < 3; c++)
        memcpy(t->tab[c], t->tab[0], sizeof t->tab[0]);
    return 0;
}

double sl_dual_stack_reflectance(double r, double t) {
    if (!(r > 0.0)) return 0.0;
    /* Adding equations: R = r + t^2 R / (1 - r R), the root in [0, 1]. */
    double b = 1.0 + r * r - t * t, disc = b * b - 4.0 * r * r;
    if (disc < 0.0) disc = 0.0; /* r + t = 1 exactly: R = 1 */
    /* 2r / (b + sqrt(disc)) is the same root without cancellation when r is small. */
    return 2.0 * r / (b + sqrt(disc));
}

void sl_dual_means(const sl_dual_tables *t, int c, double *r, double *tr, double *Ab) {
    /* Means over incident directions: weight cos theta_d on [0, pi/2] (trapezoid rule on the
     * table's nodes). */
    double sf = 0.0, sb = 0.0, sa = 0.0, sw = 0.0;
    const float *af = t->tab[c] + SL_DUAL_AF * SL_DUAL_N, *ab = t->tab[c] + SL_DUAL_AB * SL_DUAL_N,
                *Al = t->tab[c] + SL_DUAL_A_B * SL_DUAL_N;
    for (int i = 1; i < SL_DUAL_N; i++) {
        double x0 = sl_dual_node(i - 1), x1 = sl_dual_node(i), h = 0.5 * (x1 - x0);
        double w0 = h * cos(x0), w1 = h * cos(x1);
        sf += w0 * af[i - 1] + w1 * af[i];
        sb += w0 * ab[i - 1] + w1 * ab[i];
        sa += w0 * Al[i - 1] + w1 * Al[i];
        sw += w0 + w1;
    }
    *r = sb / sw, *tr = sf / sw;
    if (Ab) *Ab = sa / sw;
}

void sl_dual_stack_init(double r, double t, double Ab, sl_dual_stack *s) {
    memset(s, 0, sizeof *s);
    s->r = r > 0.0 ? r : 0.0;
    s->t = t > 0.0 ? t : 0.0;
    s->Ab = Ab;
    s->R_inf = sl_dual_stack_reflectance(s->r, s->t);
    s->lossless = 1;
    if (!(s->r > 0.0)) return;
    /* Kubelka-Munk form of the adding equations (x = N kappa, E = exp(-2 x)):
     *   R_N = sinh x / (a sinh x + b cosh x) = (1 - E) / ((a + b) - (a - b) E),
     *   T_N = b / (a sinh x + b cosh x) = 2 b e^-x / ((a + b) - (a - b) E),
     * a = (1 + r^2 - t^2) / (2 r), b = sqrt(a^2 - 1), tanh kappa = b / (1 / r - a), so that
     * R_1 = r, T_1 = t and R_inf = a - b. Without absorption (r + t = 1, b -> 0) the limit is
     * R_N = N r / (1 + (N - 1) r), T_N = 1 - R_N. t = 0: kappa = inf, R_N = r, T_N = 0. */
    double a = (1.0 + s->r * s->r - s->t * s->t) / (2.0 * s->r), b2 = a * a - 1.0;
    s->a = a;
    if (!(b2 > 1e-12)) return;
    s->lossless = 0;
    s->b = sqrt(b2);
    double x = s->b / (1.0 / s->r - a);
    s->kappa = x < 1.0 ? atanh(x) : INFINITY;
}

/* R_N and T_N from e = exp(-N kappa) (absorbing stacks). */
static double stack_R(const sl_dual_stack *s, double e) {
    double E = e * e;
    return (1.0 - E) / ((s->a + s->b) - (s->a - s->b) * E);
}
static double stack_T(const sl_dual_stack *s, double e) {
    return 2.0 * s->b * e / ((s->a + s->b) - (s->a - s->b) * e * e);
}

double sl_dual_stack_reflectance_n(const sl_dual_stack *s, double N) {
    if (!(s->r > 0.0) || !(N > 0.0)) return 0.0;
    if (s->lossless) return isfinite(N) ? N * s->r / (1.0 + (N - 1.0) * s->r) : 1.0;
    return stack_R(s, exp(-N * s->kappa));
}

double sl_dual_stack_transmittance_n(const sl_dual_stack *s, double N) {
    if (!(N > 0.0)) return 1.0;
    if (!(s->r > 0.0)) return pow(s->t, N); /* no reflection: plain attenuation */
    if (s->lossless) return isfinite(N) ? (1.0 - s->r) / (1.0 + (N - 1.0) * s->r) : 0.0;
    return stack_T(s, exp(-N * s->kappa));
}

double sl_dual_stack_incident_factor(const sl_dual_stack *s, double m, double n) {
    if (!(m > 0.0)) return 1.0;
    double tm = pow(s->t, m);
    if (!(tm > 0.0)) return 1.0; /* no light reaches the point by the march either */
    double Tm, Rm;
    if (!s->lossless) { /* r > 0 and absorbing: one exp for both (the per-row hot path) */
        double em = exp(-m * s->kappa);
        Tm = stack_T(s, em), Rm = stack_R(s, em);
    } else {
        Tm = sl_dual_stack_transmittance_n(s, m), Rm = sl_dual_stack_reflectance_n(s, m);
    }
    double den = 1.0 - Rm * sl_dual_stack_reflectance_n(s, n);
    if (!(den > 1e-12)) den = 1e-12;
    double f = Tm / den / tm;
    return f < SL_DUAL_STACK_MAX_FACTOR ? f : SL_DUAL_STACK_MAX_FACTOR;
}

double sl_dual_stack_local_factor(const sl_dual_stack *s, double n) {
    if (!(s->Ab > 0.0)) return 1.0;
    if (!(n > 0.0)) return 0.0;
    double f = (sl_dual_stack_reflectance_n(s, n + 1.0) - s->r) / s->Ab;
    return f > 0.0 ? f : 0.0;
}

double sl_dual_ms_share(const sl_material *m) {
    static const double lum[3] = {0.2126, 0.7152, 0.0722};
    sl_dual_tables *t = sl_malloc(sizeof *t);
    sl_err e;
    if (sl_dual_tables_build(m, t, &e)) {
        free(t);
        return -1.0;
    }
    double num = 0.0, den = 0.0;
    for (int c = 0; c < 3; c++) {
        double r, tr;
        sl_dual_means(t, c, &r, &tr, NULL);
        double R = sl_dual_stack_reflectance(r, tr);
        num += lum[c] * (R - r);
        den += lum[c] * R;
    }
    free(t);
    return den > 0.0 ? fmax(num / den, 0.0) : 0.0;
}
