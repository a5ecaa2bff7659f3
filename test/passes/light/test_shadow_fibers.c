/* test_shadow_fibers.c: the light pass's transmittance at points on the fibers themselves (the
 * renderer's shading points) against the ray-traced reference (cpu/reference/transmittance_ref.c:
 * the fibers as capsules, a point's own fiber ignored), with the first-depth window the renderer
 * uses (SL_SHADOW_Z0_FIBERS_SHADING) and with the one for points between fibers
 * (SL_SHADOW_Z0_FIBERS); issue 19, docs/shadow.md "The window for shading points". */
#include "test.h"

#include "io/hair/hair.h"
#include "passes/light/shadow.h"
#include "transmittance_ref.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define NPTS 120
#define NDIRS 1024

/* Mean T of the light pass and of the reference over NPTS vertices (every k-th, roots skipped)
 * for one lobe, with the given window width in fibers. */
static int fiber_points_T_size(const sl_hair *h, const slref_fibers *rf, const double dir[3],
                               double lambda, double fibers, int size, double *mean_c,
                               double *mean_ref) {
    sl_device dev = {0};
    sl_err e;
    if (sl_device_open("c", &dev, &e)) return -1;
    sl_shadow_opts o;
    sl_shadow_opts_default(&o);
    o.size = size;
    o.z0_fibers = fibers;
    sl_dodm m;
    if (sl_shadow_build(&dev, h, dir, lambda, &o, &m, &e)) {
        sl_device_close(&dev);
        return -1;
    }
    double *xyz = malloc(3 * NPTS * sizeof *xyz), *T = malloc(NPTS * sizeof *T);
    uint32_t step = h->num_points / NPTS, n = 0;
    for (uint32_t i = 1; i < h->num_points && n < NPTS; i += step ? step : 1) {
        for (int k = 0; k < 3; k++)
            xyz[3 * n + k] = h->pos[3 * (size_t)i + k];
        n++;
    }
    int rc = sl_shadow_lookup(&dev, &m, n, xyz, T, &e);
    double sc = 0, sr = 0;
    for (uint32_t i = 0; !rc && i < n; i++) {
        sc += T[i];
        if (rf) sr += slref_transmittance(rf, xyz + 3 * i, dir, lambda, NDIRS, 1000 + i, NULL);
    }
    *mean_c = sc / n;
    if (mean_ref) *mean_ref = sr / n;
    free(xyz);
    free(T);
    sl_dodm_free(&m);
    sl_device_close(&dev);
    return rc;
}

static int fiber_points_T(const sl_hair *h, const slref_fibers *rf, const double dir[3],
                          double lambda, double fibers, double *mean_c, double *mean_ref) {
    return fiber_points_T_size(h, rf, dir, lambda, fibers, 512, mean_c, mean_ref);
}

/* Procedural straight hair (a dense head, as the straight.hair of the Cycles scene), a lobe from
 * above (lambda 0.1) and an oblique one (0.3). Measured (C, 512^2, K 4, 120 points): the
 * 30-fiber window 0.655x / 0.889x of the reference, the 3-fiber window 0.947x / 0.920x
 * (straight.hair at 300 points, eval: 0.89x / 0.345x against 1.05x / 0.85x). Bounds: the shading
 * window within 15 % of the reference for both lobes (the reference's own error at 1024
 * directions and 120 points is ~0.5 %), never further from it than the 30-fiber window, and
 * closer by at least 0.1 from above. */
TEST(shadow_fiber_points_vs_traced) {
    sl_hair h;
    sl_err e;
    sl_hair_procedural p = {SL_PROC_STRAIGHT, 6000, 16, 1};
    CHECK(sl_hair_generate(&p, &h, &e) == 0);
    h.default_radius = 0.04f;
    slref_fibers *rf = NULL;
    CHECK(slref_fibers_build(&h, &rf, &e) == 0);
    const double dirs[2][3] = {{0, 1, 0}, {0.6, 0.3, -0.7416198487}}, lambdas[2] = {0.1, 0.3};
    for (int l = 0; rf && l < 2; l++) {
        double c3, c30, r3, r30;
        CHECK(fiber_points_T(&h, rf, dirs[l], lambdas[l], SL_SHADOW_Z0_FIBERS_SHADING, &c3, &r3) ==
              0);
        CHECK(fiber_points_T(&h, rf, dirs[l], lambdas[l], SL_SHADOW_Z0_FIBERS, &c30, &r30) == 0);
        printf("  lobe %d: reference T %.4f; light pass %.4f (%.3fx) with the shading window, "
               "%.4f (%.3fx) with %g fibers\n",
               l, r3, c3, c3 / r3, c30, c30 / r30, SL_SHADOW_Z0_FIBERS);
        CHECK(r3 > 0.05 && r3 < 0.95); /* shadowed, not black: the comparison means something */
        CHECK(fabs(c3 / r3 - 1.0) <= 0.15);
        CHECK(fabs(c3 / r3 - 1.0) <= fabs(c30 / r30 - 1.0));
        if (l == 0) CHECK(fabs(c3 / r3 - 1.0) + 0.1 <= fabs(c30 / r30 - 1.0));
    }
    slref_fibers_free(rf);
    sl_hair_free(&h);
}

/* Not a check: SL_SHADOW_MAPSIZE_FULL=1 prints the docs/shadow.md table "A window of constant
 * width in fibers": the mean T of fiber points of procedural wavy hair (3000 strands, the
 * default scene's style) at map sizes 256 / 512 / 1024 for first-depth windows of 3, 5 and 8
 * fibers (the fiber is 0.3 / 0.6 / 1.3 texels wide), and the procedural straight hair of
 * shadow_fiber_points_vs_traced against its traced reference at 512^2 for the same windows.
 * Otherwise it skips (about 10 s). */
TEST(shadow_fiber_points_map_size_table) {
    const char *full = getenv("SL_SHADOW_MAPSIZE_FULL");
    if (!full || full[0] != '1') SKIP("set SL_SHADOW_MAPSIZE_FULL=1 for the docs/shadow.md table");
    sl_hair h, hs;
    sl_err e;
    sl_hair_procedural p = {SL_PROC_WAVY, 3000, 16, 1}, ps = {SL_PROC_STRAIGHT, 6000, 16, 1};
    CHECK(sl_hair_generate(&p, &h, &e) == 0);
    CHECK(sl_hair_generate(&ps, &hs, &e) == 0);
    h.default_radius = hs.default_radius = 0.04f;
    slref_fibers *rf = NULL;
    CHECK(slref_fibers_build(&hs, &rf, &e) == 0);
    const double dirs[2][3] = {{0, 1, 0}, {0.6, 0.3, -0.7416198487}}, lambdas[2] = {0.1, 0.3};
    const int sizes[3] = {256, 512, 1024};
    const double fibers[3] = {3, 5, 8};
    for (int f = 0; f < 3; f++)
        for (int l = 0; l < 2; l++) {
            double T[3], c, r;
            for (int k = 0; k < 3; k++)
                CHECK(fiber_points_T_size(&h, NULL, dirs[l], lambdas[l], fibers[f], sizes[k], &T[k],
                                          NULL) == 0);
            CHECK(fiber_points_T_size(&hs, rf, dirs[l], lambdas[l], fibers[f], 512, &c, &r) == 0);
            printf("  %g fibers, lobe %d: wavy mean T %.4f / %.4f / %.4f at 256 / 512 / 1024; "
                   "straight at 512 %.3fx the traced\n",
                   fibers[f], l, T[0], T[1], T[2], c / r);
        }
    slref_fibers_free(rf);
    sl_hair_free(&h);
    sl_hair_free(&hs);
}
