/* test_shadow_kappa.c: stochastic simplification (Ren 2010 Sec. 7; host/passes/light/shadow.h: kappa) on real
 * hair: the light pass keeps a fraction kappa of the strands, widened by 1 / kappa. Error is
 * measured against kappa = 1 at the hair's own vertices (where fragments are shaded), time is the
 * C light pass. SL_SHADOW_KAPPA_FULL=1 runs the docs/shadow.md table instead of the quick check:
 * the default procedural hair (10000 wavy strands x 16 points) and ../shared/data/hair models at
 * 512^2. */
#include "test.h"

#include "io/hair/hair.h"
#include "passes/light/shadow.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct kstat {
    double mean_T, mean_abs, bias, p95, build_s;
} kstat;

static int cmp_d(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Light pass of nl lobes for each kappa; T at every `stride`-th vertex; stats against kappas[0]
 * (= 1). */
static void kappa_sweep(const char *name, const sl_hair *h, int size, int nk, const double *kappas,
                        kstat *st) {
    sl_device dev;
    sl_err e = {{0}};
    sl_device_open("c", &dev, &e);
    enum { NL = 4 };
    /* four lobes: above, two oblique, one from below (lambda: a moderately wide SRBF) */
    const double dirs[3 * NL] = {0, 1, 0, 0.6, 0.5, 0.624, -0.7, 0.2, -0.685, 0, -1, 0};
    const double lam[NL] = {0.3, 0.3, 0.5, 0.3};
    size_t stride = h->num_points / 4000 + 1, np = (h->num_points + stride - 1) / stride;
    double *xyz = malloc(3 * np * sizeof *xyz), *t1 = malloc(np * NL * sizeof *t1),
           *t = malloc(np * NL * sizeof *t), *ad = malloc(np * NL * sizeof *ad);
    for (size_t i = 0; i < np; i++)
        for (int c = 0; c < 3; c++)
            xyz[3 * i + c] = h->pos[3 * (i * stride) + c];
    for (int k = 0; k < nk; k++) {
        sl_shadow_opts o;
        sl_shadow_opts_default(&o);
        o.size = size;
        o.kappa = kappas[k];
        sl_shadow_batch b;
        double t0 = sl_now();
        if (sl_shadow_build_batch(&dev, h, NL, dirs, lam, &o, &b, &e)) {
            sl_test_fail(__FILE__, __LINE__, "%s", e.msg);
            break;
        }
        st[k].build_s = sl_now() - t0;
        if (sl_shadow_batch_lookup(&b, np, xyz, NULL, k ? t : t1, &e))
            sl_test_fail(__FILE__, __LINE__, "%s", e.msg);
        sl_shadow_batch_free(&b);
        const double *tk = k ? t : t1;
        memset(&st[k], 0, offsetof(kstat, build_s));
        for (size_t i = 0; i < np * NL; i++) {
            st[k].mean_T += tk[i] / (np * NL);
            st[k].bias += (tk[i] - t1[i]) / (np * NL);
            ad[i] = fabs(tk[i] - t1[i]);
            st[k].mean_abs += ad[i] / (np * NL);
        }
        qsort(ad, np * NL, sizeof *ad, cmp_d);
        st[k].p95 = ad[(size_t)(0.95 * (np * NL - 1))];
        printf("  %s %d^2 kappa %.2f: light pass (4 lobes, C) %.3f s, mean T %.4f, |T - T(1)| "
               "mean %.4f p95 %.4f, bias %+.4f\n",
               name, size, kappas[k], st[k].build_s, st[k].mean_T, st[k].mean_abs, st[k].p95,
               st[k].bias);
    }
    free(xyz);
    free(t1);
    free(t);
    free(ad);
    sl_device_close(&dev);
}

/* Quick check on procedural hair (2000 wavy strands, 128^2, 4 lobes, ~2000 vertices): the kept
 * strands carry the same mean optical depth, so T moves by the sampling noise of the dropped
 * strands (relative sd of tau ~ sqrt((1/kappa - 1) / N) for N fibers per box) plus the
 * partial-coverage bias of widened fibers (a fiber covering a fraction f of the box counts exp(-f)
 * instead of 1 - f; f grows as 1/kappa: T high, docs/shadow.md). Measured: kappa 0.5 mean |dT|
 * 0.034, bias +0.017; kappa 0.25: 0.067, +0.033 (mean T 0.44). Tolerances, about twice those:
 * mean |dT| <= 0.07 (0.5), <= 0.13 (0.25); bias <= 0.04 (0.5), <= 0.07 (0.25). Dropping strands
 * without widening the kept ones would scale tau by kappa (mean T 0.44 -> ~0.66 at 0.5) and fail
 * both. */
TEST(shadow_kappa_procedural) {
    const char *full = getenv("SL_SHADOW_KAPPA_FULL");
    const double kappas[] = {1.0, 0.5, 0.25, 0.1};
    kstat st[4];
    sl_err e = {{0}};
    sl_hair h;
    if (full && full[0] == '1') {
        sl_hair_procedural p = {SL_PROC_WAVY, 10000, 16, 1};
        CHECK(sl_hair_generate(&p, &h, &e) == 0);
        kappa_sweep("procedural", &h, 512, 4, kappas, st);
        sl_hair_free(&h);
        const char *dir = sl_test_shared_data();
        static const char *const files[] = {"hair/straight.hair", "hair/harolongo.data",
                                            "hair/sintel/sintel_hair_full_16pts.tfx"};
        for (int f = 0; dir && f < 3; f++) {
            char path[4096];
            snprintf(path, sizeof path, "%s/%s", dir, files[f]);
            if (sl_hair_load(path, &h, &e)) {
                printf("  %s: %s\n", files[f], e.msg);
                continue;
            }
            kappa_sweep(files[f], &h, 512, 4, kappas, st);
            sl_hair_free(&h);
        }
        return;
    }
    sl_hair_procedural p = {SL_PROC_WAVY, 2000, 16, 1};
    CHECK(sl_hair_generate(&p, &h, &e) == 0);
    kappa_sweep("procedural", &h, 128, 3, kappas, st);
    CHECK(st[1].mean_abs <= 0.07);
    CHECK(st[2].mean_abs <= 0.13);
    CHECK(fabs(st[1].bias) <= 0.04 && fabs(st[2].bias) <= 0.07);
    CHECK(st[0].mean_T < 0.9); /* the points are shadowed: the comparison means something */
    sl_hair_free(&h);
}
