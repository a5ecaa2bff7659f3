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
        /* Means over incident directions: weight cos theta_d on [0, pi/2] (trapezoid rule on
         * the table's nodes). */
        double sf = 0.0, sb = 0.0, sw = 0.0;
        const float *af = t->tab[c] + SL_DUAL_AF * SL_DUAL_N,
                    *ab = t->tab[c] + SL_DUAL_AB * SL_DUAL_N;
        for (int i = 1; i < SL_DUAL_N; i++) {
            double x0 = sl_dual_node(i - 1), x1 = sl_dual_node(i), h = 0.5 * (x1 - x0);
            double w0 = h * cos(x0), w1 = h * cos(x1);
            sf += w0 * af[i - 1] + w1 * af[i];
            sb += w0 * ab[i - 1] + w1 * ab[i];
            sw += w0 + w1;
        }
        double r = sb / sw, tr = sf / sw;
        double R = sl_dual_stack_reflectance(r, tr);
        num += lum[c] * (R - r);
        den += lum[c] * R;
    }
    free(t);
    return den > 0.0 ? fmax(num / den, 0.0) : 0.0;
}
