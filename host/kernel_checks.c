/* kernel_checks.c: the table of kernel-vs-C-twin checks (kernel_checks.h) and the prefix-sum
 * check. */
#include "kernel_checks.h"

#include "../cpu/prefix_sum.h"
#include "prefix_sum_cl.h"
#include "dodm_cl.h"   /* slchk_dodm (shadow) */
#include "raster_cl.h" /* slchk_raster (shadow) */

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const sl_kernel_check checks[] = {
    {"prefix_sum", "inclusive 2-D prefix sum (summed-area table), prefix_sum.cl, work-group scan",
     slchk_prefix_sum},
    {"prefix_sum_serial", "the same, one work-item per tile (the variant CPU devices use)",
     slchk_prefix_sum_serial},
    {"raster", "segment rasterizer + DODM tables, raster.cl + dodm.cl (bit-identical)", slchk_raster},
    {"dodm_lookup", "convolution optical depth lookup T = exp(-tau), dodm.cl", slchk_dodm},
};

const sl_kernel_check *sl_kernel_checks(size_t *count) {
    *count = sizeof checks / sizeof checks[0];
    return checks;
}

const sl_kernel_check *sl_kernel_check_find(const char *name) {
    for (size_t i = 0; i < sizeof checks / sizeof checks[0]; i++)
        if (strcmp(checks[i].name, name) == 0) return &checks[i];
    return NULL;
}

void sl_kernel_compare(const float *kernel_out, const float *c_out, size_t n,
                       sl_kernel_check_result *r) {
    r->max_abs = r->max_rel = 0;
    r->compared = n;
    r->bad = 0;
    for (size_t i = 0; i < n; i++) {
        double a = kernel_out[i], b = c_out[i];
        if (isnan(a) && isnan(b)) continue;
        if (isinf(a) || isinf(b)) {
            if (a != b) {
                r->bad++;
                r->max_abs = r->max_rel = INFINITY;
            }
            continue;
        }
        double d = fabs(a - b);
        if (isnan(d)) d = INFINITY; /* one NaN */
        double rel = d == 0 ? 0 : (b != 0 ? d / fabs(b) : INFINITY);
        if (d > r->max_abs) r->max_abs = d;
        if (rel > r->max_rel) r->max_rel = rel;
        if (!(d <= r->tol_abs || d <= r->tol_rel * fabs(b))) r->bad++;
    }
    r->pass = r->bad == 0;
}

void sl_kernel_check_fill(float *x, size_t n, unsigned long long seed, float lo, float hi) {
    unsigned long long s = seed * 2654435761ull + 0x9e3779b97f4a7c15ull;
    for (size_t i = 0; i < n; i++) {
        s ^= s >> 12;
        s ^= s << 25;
        s ^= s >> 27;
        double u = (double)((s * 2685821657736338717ull) >> 11) * 0x1.0p-53; /* [0,1) */
        x[i] = (float)(lo + (hi - lo) * u);
        if (x[i] >= hi) x[i] = lo; /* rounding up to hi */
    }
}

/* ---------------------------------------------------------------- prefix sum */

static int check_prefix_sum(sl_cl *cl, const sl_kernel_check_opts *o, sl_ps_variant variant,
                            sl_kernel_check_result *r, sl_err *e) {
    /* Default: sizes that are not multiples of the 256 tile and need two scan levels. */
    size_t w = o->size > 0 ? (size_t)o->size : 1031, h = o->size > 0 ? (size_t)o->size : 517;
    int reps = o->reps > 0 ? o->reps : 3;
    snprintf(r->problem, sizeof r->problem, "%zux%zu image", w, h);
    /* Same additions in the same order (kernels/prefix_sum.h), IEEE single additions only:
     * the results must be bit-identical. */
    r->tol_abs = 0;
    r->tol_rel = 0;
    snprintf(r->note, sizeof r->note, "same summation order as the C twin: bit-identical");
    float *in = sl_malloc(w * h * sizeof *in), *a = sl_malloc(w * h * sizeof *a),
          *b = sl_malloc(w * h * sizeof *b);
    sl_kernel_check_fill(in, w * h, 1, 0.0f, 1.0f);
    int rc = 0;
    r->c_s = r->cl_s = r->cl_wall_s = INFINITY;
    /* One untimed OpenCL run first: the program build and PoCL's code generation at the first
     * enqueue are not kernel time. */
    double ks;
    if ((rc = slcl_prefix_sum_2d_variant(cl, in, a, w, h, variant, &ks, e))) goto done;
    for (int i = 0; i < reps; i++) {
        double t0 = sl_now();
        if ((rc = slcl_prefix_sum_2d_variant(cl, in, a, w, h, variant, &ks, e))) goto done;
        double wall = sl_now() - t0;
        if (ks < r->cl_s) r->cl_s = ks;
        if (wall < r->cl_wall_s) r->cl_wall_s = wall;
        t0 = sl_now();
        slc_prefix_sum_2d(in, b, w, h);
        double c = sl_now() - t0;
        if (c < r->c_s) r->c_s = c;
    }
    r->cl_s_is_device = sl_cl_profiling(cl);
    sl_kernel_compare(a, b, w * h, r);
done:
    free(in);
    free(a);
    free(b);
    return rc;
}

int slchk_prefix_sum(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                     sl_err *e) {
    return check_prefix_sum(cl, o, SL_PS_WORKGROUP, r, e);
}

int slchk_prefix_sum_serial(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                            sl_err *e) {
    return check_prefix_sum(cl, o, SL_PS_SERIAL, r, e);
}
