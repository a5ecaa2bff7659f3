/* shadow_check.c: the `strandlight kernels` checks of the light pass: raster.cl and dodm.cl
 * against their C twins (cpu/raster.c, cpu/dodm.c) on procedural hair. */
#include "verify/checks/kernel_checks.h"

#include "../cpu/dodm.h"
#include "../cpu/raster.h"
#include "passes/light/dodm_cl.h"
#include "passes/light/raster_cl.h"
#include "passes/light/shadow.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Builds the light pass of procedural hair on C and on cl; returns both maps. */
static int both(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r, sl_dodm *a,
                sl_dodm *b, sl_hair *h, sl_err *e) {
    int size = o->size > 0 ? (int)o->size : 256, reps = o->reps > 0 ? o->reps : 3;
    sl_hair_procedural p = {SL_PROC_WAVY, 2000, 16, 1};
    if (sl_hair_generate(&p, h, e)) return -1;
    snprintf(r->problem, sizeof r->problem, "%d^2, %u strands", size, h->num_strands);
    sl_shadow_opts so;
    sl_shadow_opts_default(&so);
    so.size = size;
    double dir[3] = {0.36, 0.8, 0.48};
    sl_device dc = {0}, dk = {0};
    dk.is_opencl = 1;
    dk.cl = cl;
    snprintf(dc.name, sizeof dc.name, "C path");
    r->c_s = r->cl_s = r->cl_wall_s = INFINITY;
    memset(a, 0, sizeof *a);
    memset(b, 0, sizeof *b);
    for (int i = 0; i <= reps; i++) { /* the first OpenCL run builds and warms up: untimed */
        sl_dodm_free(a);
        sl_dodm_free(b);
        double t0 = sl_now();
        if (sl_shadow_build(&dk, h, dir, 0.3, &so, a, e)) return -1;
        double wall = sl_now() - t0;
        if (sl_shadow_build(&dc, h, dir, 0.3, &so, b, e)) return -1;
        if (i == 0) continue;
        r->cl_s = fmin(r->cl_s, a->raster_s + a->tables_s);
        r->cl_wall_s = fmin(r->cl_wall_s, wall);
        r->c_s = fmin(r->c_s, b->raster_s + b->tables_s);
    }
    r->cl_s_is_device = sl_cl_profiling(cl);
    return 0;
}

int slchk_raster(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r, sl_err *e) {
    sl_dodm a, b;
    sl_hair h;
    memset(&h, 0, sizeof h);
    int rc = both(cl, o, r, &a, &b, &h, e);
    if (!rc) {
        /* Fixed-point integer atomics: order-independent, so bit-identical. Compared: the
         * first-depth map and the summed-area tables (as floats of their low bits would lose
         * information, so mismatches are counted on the integers). */
        r->tol_abs = r->tol_rel = 0;
        snprintf(r->note, sizeof r->note,
                 "64-bit fixed-point atomics and integer scans: bit-identical maps and tables");
        size_t plane = (size_t)a.view.w * a.view.h, n = plane * (1 + a.K);
        float *ka = sl_malloc(n * sizeof *ka), *kb = sl_malloc(n * sizeof *kb);
        for (size_t i = 0; i < plane; i++) {
            memcpy(&ka[i], &a.z0bits[i], 4);
            memcpy(&kb[i], &b.z0bits[i], 4);
        }
        for (size_t i = 0; i < plane * a.K; i++) {
            ka[plane + i] = (float)(a.sat[i] != b.sat[i]);
            kb[plane + i] = 0;
        }
        sl_kernel_compare(ka, kb, n, r);
        free(ka);
        free(kb);
    }
    sl_dodm_free(&a);
    sl_dodm_free(&b);
    sl_hair_free(&h);
    return rc;
}

/* The lookup (behind = 0: T; 1: the optical depth behind) of both maps at 20 000 points in the
 * hair's box, OpenCL against C. */
static int dodm_lookups(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                        int behind, sl_err *e) {
    sl_dodm a, b;
    sl_hair h;
    memset(&h, 0, sizeof h);
    int rc = both(cl, o, r, &a, &b, &h, e);
    if (!rc) {
        /* T = exp(-tau): the same float operations but OpenCL's exp and division may differ by
         * a few ulp: 4e-6 relative. Behind: the column's optical depth less the point's; the
         * difference keeps a few ulp of the column's (an optical depth of at most ~100 here):
         * 1e-4 absolute (a ten-thousandth of a fiber), 4e-6 relative. */
        r->tol_abs = behind ? 1e-4 : 1e-30;
        r->tol_rel = 4e-6;
        snprintf(r->note, sizeof r->note, "%s",
                 behind ? "column less the point's tau: 1e-4 abs, 4e-6 rel"
                        : "lookup: exp/division within a few ulp (4e-6 rel)");
        enum { NP = 20000 };
        double *xyz = sl_malloc(3 * NP * sizeof *xyz), *ta = sl_malloc(NP * sizeof *ta),
               *tb = sl_malloc(NP * sizeof *tb);
        float lo[3], hi[3], *fa = sl_malloc(NP * sizeof *fa), *fb = sl_malloc(NP * sizeof *fb);
        sl_hair_bounds(&h, lo, hi);
        float u[3 * NP];
        sl_kernel_check_fill(u, 3 * NP, 7, 0.0f, 1.0f);
        for (int i = 0; i < 3 * NP; i++)
            xyz[i] = lo[i % 3] + (hi[i % 3] - lo[i % 3]) * u[i];
        sl_device dc = {0}, dk = {0};
        dk.is_opencl = 1;
        dk.cl = cl;
        /* behind: the kernel that returns both (sl_dodm_lookup_both), its B compared; its T goes
         * to scratch (the same T as sl_dodm_lookup's, checked above) */
        double *scratch = sl_malloc(NP * sizeof *scratch);
        if ((rc = sl_shadow_lookup_both(&dk, &a, NP, xyz, behind ? scratch : ta, behind ? ta : NULL,
                                        e)) == 0 &&
            (rc = sl_shadow_lookup_both(&dc, &b, NP, xyz, behind ? scratch : tb, behind ? tb : NULL,
                                        e)) == 0) {
            for (int i = 0; i < NP; i++) {
                fa[i] = (float)ta[i];
                fb[i] = (float)tb[i];
            }
            sl_kernel_compare(fa, fb, NP, r);
        }
        free(scratch);
        free(xyz);
        free(ta);
        free(tb);
        free(fa);
        free(fb);
    }
    sl_dodm_free(&a);
    sl_dodm_free(&b);
    sl_hair_free(&h);
    return rc;
}

int slchk_dodm(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r, sl_err *e) {
    return dodm_lookups(cl, o, r, 0, e);
}

int slchk_dodm_behind(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                      sl_err *e) {
    return dodm_lookups(cl, o, r, 1, e);
}
