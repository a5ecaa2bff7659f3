/* view_check.c: the `strandlight kernels` checks of the view pass: kernels/view.cl, its
 * -DSL_KB_K build and its generic one (host/passes/view/view_cl.c), against the C twin
 * slc_kbuffer_build (cpu/view.h). */
#include "verify/checks/kernel_checks.h"

#include "passes/view/view_cl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static uint32_t chk_lcg(uint32_t *s) {
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

/* Typical: ~6 fragments per pixel from random ribbons of a few pixels, opacity 0.3..1, K = 8.
 * Extreme: K = 1 and K = 64 alternatives are too slow to sweep here, so one input mixes what
 * breaks K-buffers: fully opaque wide ribbons (occlusion), 40x overdraw in one corner (merges
 * on every insert), equal depths (the seg / t tie-break), zero-length and off-image segments,
 * faint 1e-4 coverage; K = 3. */
static void chk_fragments(int extreme, int w, int h, slc_frag_list *l, int *K) {
    uint32_t s = extreme ? 77u : 13u;
    size_t target = (size_t)w * h * 6;
    uint32_t seg = 0;
    *K = extreme ? 3 : 8;
    while (l->n < target && seg < 10000000u) {
        double x0 = (chk_lcg(&s) % (100 * w)) / 100.0, y0 = (chk_lcg(&s) % (100 * h)) / 100.0;
        double z0 = 1 + chk_lcg(&s) % 1000 / 10.0;
        double dx = (double)(chk_lcg(&s) % 1200) / 100.0 - 6,
               dy = (double)(chk_lcg(&s) % 1200) / 100.0 - 6;
        double hw = 0.05 + (chk_lcg(&s) % 100) / 100.0;
        float a0 = 0.3f + 0.7f * (float)(chk_lcg(&s) % 1000) / 1000.0f, a1 = a0;
        if (extreme) {
            switch (seg % 6) {
            case 0:
                hw = 2.5, a0 = a1 = 1.0f;
                break; /* opaque, full coverage */
            case 1:
                x0 = x0 * 0.1, y0 = y0 * 0.1;
                break; /* overdraw in a corner */
            case 2:
                z0 = 50.0;
                break; /* depth ties */
            case 3:
                dx = dy = 0;
                break; /* zero length */
            case 4:
                x0 += 2 * w;
                break; /* off the image */
            default:
                hw = 0.002;
                break; /* faint coverage */
            }
        }
        double p0[3] = {x0, y0, z0},
               p1[3] = {x0 + dx, y0 + dy, extreme && seg % 6 == 2 ? z0 : z0 + fabs(dx)};
        slc_view_segment(p0, p1, hw, a0, a1, seg++, w, h, l);
    }
}

static int chk_kbuffer(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                       int specialised, sl_err *e) {
    int w = o->size > 0 ? (int)o->size : 256, h = w * 3 / 4 > 0 ? w * 3 / 4 : 1;
    slc_frag_list l = {0};
    int K;
    chk_fragments(o->extreme, w, h, &l, &K);
    size_t npx = (size_t)w * h;
    sl_kfrag *a = sl_calloc(npx * K, sizeof *a), *b = sl_calloc(npx * K, sizeof *b);
    uint8_t *ca = sl_malloc(npx), *cb = sl_malloc(npx);
    r->c_s = r->cl_s = r->cl_wall_s = INFINITY;
    int rc = 0;
    for (int rep = 0; rep < (o->reps > 0 ? o->reps : 1) && !rc; rep++) {
        double t0 = sl_now();
        slc_kbuffer_build(&l, w, h, K, a, ca, 1);
        double t1 = sl_now();
        size_t m;
        double ks = 0;
        rc = slcl_kbuffer_build_ex(cl, &l, w, h, K, specialised, b, cb, &m, &ks, e);
        double t2 = sl_now();
        if (t1 - t0 < r->c_s) r->c_s = t1 - t0;
        if (ks < r->cl_s) r->cl_s = ks;
        if (t2 - t1 < r->cl_wall_s) r->cl_wall_s = t2 - t1;
    }
    if (!rc) {
        /* every count and every kept entry's fields (z, a, seg, t) as floats: seg < 2^24 */
        size_t n = npx * (1 + 4 * (size_t)K);
        float *fa = sl_calloc(n, sizeof *fa), *fb = sl_calloc(n, sizeof *fb);
        for (size_t p = 0; p < npx; p++) {
            fa[p] = ca[p], fb[p] = cb[p];
            for (int i = 0; i < ca[p] && i < cb[p]; i++) {
                const sl_kfrag *x = &a[p * K + i], *y = &b[p * K + i];
                float *u = fa + npx + 4 * (p * K + i), *v = fb + npx + 4 * (p * K + i);
                u[0] = x->z, u[1] = x->a, u[2] = (float)x->seg, u[3] = x->t;
                v[0] = y->z, v[1] = y->a, v[2] = (float)y->seg, v[3] = y->t;
            }
        }
        r->tol_abs = r->tol_rel = 0;
        sl_kernel_compare(fb, fa, n, r);
        free(fa);
        free(fb);
        snprintf(r->problem, sizeof r->problem, "%s %dx%d K%d %zuf",
                 o->extreme ? "extreme" : "typical", w, h, K, l.n);
        snprintf(
            r->note, sizeof r->note,
            "exact: the same kbuffer.h inserts in the same order per pixel, FP contraction off "
            "(%s build)",
            specialised ? "-DSL_KB_K" : "generic");
        r->cl_s_is_device = 0;
    }
    free(a);
    free(b);
    free(ca);
    free(cb);
    slc_frag_list_free(&l);
    return rc;
}

int slchk_kbuffer(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r, sl_err *e) {
    return chk_kbuffer(cl, o, r, 1, e);
}

int slchk_kbuffer_generic(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                          sl_err *e) {
    return chk_kbuffer(cl, o, r, 0, e);
}
