/* test_shadow_batch.c: the batched light pass (host/passes/light/shadow.h: sl_shadow_build_batch,
 * 16 lobes per launch, maps kept where they were built): every lobe of a batch against its own
 * single-lobe build, the two lookup modes against each other, and the OpenCL batch against the
 * C batch (bit-identical maps across two launch groups, lookups within a few ulp). */
#include "test.h"

#include "cl_fixture.h"

#include "io/hair/hair.h"
#include "passes/light/shadow.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double brand(uint64_t *s) {
    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

/* nl lobes spread over the sphere (fixed seed), lambdas 0.05 .. 0.5. */
static void lobes(int nl, double *dirs, double *lambdas) {
    uint64_t s = 21;
    for (int j = 0; j < nl; j++) {
        double z = 2 * brand(&s) - 1, ph = 2 * M_PI * brand(&s), r = sqrt(1 - z * z);
        dirs[3 * j] = r * cos(ph);
        dirs[3 * j + 1] = r * sin(ph);
        dirs[3 * j + 2] = z;
        lambdas[j] = 0.05 + 0.45 * brand(&s);
    }
}

static void points(const sl_hair *h, int n, double *xyz) {
    float lo[3], hi[3];
    sl_hair_bounds(h, lo, hi);
    uint64_t s = 5;
    for (int i = 0; i < 3 * n; i++)
        xyz[i] = lo[i % 3] + (hi[i % 3] - lo[i % 3]) * brand(&s);
}

/* C path: lobe j of a 20-lobe batch (two launch groups: 16 + 4) against sl_shadow_build of lobe j
 * alone: maps bit-identical (the same records, passes and integer tables); the per-lobe lookup
 * projects points in float on the batch path and in double on the single path: a point moves by
 * <= 1e-5 texel and T is continuous in position (area-weighted box, depth interpolation from
 * tau = 0 at z0), so T agrees within 1e-4. The two batch lookup modes run the same float code:
 * equal exactly. */
TEST(shadow_batch_matches_single) {
    sl_device dev;
    sl_err e = {{0}};
    sl_device_open("c", &dev, &e);
    sl_hair h;
    sl_hair_procedural p = {SL_PROC_WAVY, 200, 10, 4};
    CHECK(sl_hair_generate(&p, &h, &e) == 0);
    enum { NL = 20, NP = 300 };
    double dirs[3 * NL], lam[NL], xyz[3 * NP], *tall = malloc(NP * NL * sizeof *tall), tone[NP],
                                               tsingle[NP];
    lobes(NL, dirs, lam);
    points(&h, NP, xyz);
    sl_shadow_opts o;
    sl_shadow_opts_default(&o);
    o.size = 64;
    sl_shadow_batch b;
    CHECK(sl_shadow_build_batch(&dev, &h, NL, dirs, lam, &o, &b, &e) == 0);
    CHECK(b.ngroups == 2 && !b.on_device);
    CHECK(sl_shadow_batch_lookup(&b, NP, xyz, NULL, tall, &e) == 0);
    int lb[NP];
    size_t plane = 64 * 64;
    uint32_t *z0 = malloc(plane * 4);
    uint64_t *sat = malloc(plane * o.layers * 8);
    for (int j = 0; j < NL; j += 3) {
        for (int i = 0; i < NP; i++)
            lb[i] = j;
        CHECK(sl_shadow_batch_lookup(&b, NP, xyz, lb, tone, &e) == 0);
        sl_dodm m;
        CHECK(sl_shadow_build(&dev, &h, dirs + 3 * j, lam[j], &o, &m, &e) == 0);
        CHECK(sl_shadow_lookup(&dev, &m, NP, xyz, tsingle, &e) == 0);
        CHECK(sl_shadow_batch_read(&b, j, z0, sat, &e) == 0);
        CHECK(memcmp(z0, m.z0bits, plane * 4) == 0);
        CHECK(memcmp(sat, m.sat, plane * m.K * 8) == 0);
        int shadowed = 0;
        for (int i = 0; i < NP; i++) {
            CHECK(tone[i] == tall[i * NL + j]);
            CHECK_NEAR(tone[i], tsingle[i], 1e-4);
            shadowed += tone[i] < 0.99;
        }
        CHECK(shadowed > NP / 10); /* the points lie inside the hair: many are shadowed */
        sl_dodm_free(&m);
    }
    lb[7] = NL;
    CHECK(sl_shadow_batch_lookup(&b, NP, xyz, lb, tone, &e) == -1);
    CHECK(strstr(e.msg, "lobe 20 is out of range") != NULL);
    sl_shadow_batch_free(&b);
    free(tall);
    free(z0);
    free(sat);
    sl_hair_free(&h);
    sl_device_close(&dev);
}

/* OpenCL batch vs C batch, 20 lobes (two launches), with stochastic simplification and a z0
 * window, whole (2 texels) and fractional (the automatic window of 30 fibers: half-size 2.8 texels,
 * kernels/raster.h: sl_raster_z0_blend): maps bit-identical (correctly rounded projection,
 * fixed-point atomics, integer scans, the same float blend); lookups within 4e-6 relative (OpenCL
 * exp and division: a few ulp). */
TEST(shadow_batch_kernel_vs_c) {
    sl_device dk, dc;
    sl_err e = {{0}};
    SL_TEST_OPEN_CL(&dk, &e);
    sl_device_open("c", &dc, &e);
    sl_hair h;
    sl_hair_procedural p = {SL_PROC_WAVY, 300, 12, 9};
    CHECK(sl_hair_generate(&p, &h, &e) == 0);
    enum { NL = 20, NP = 200 };
    double dirs[3 * NL], lam[NL], xyz[3 * NP];
    double *ta = malloc(NP * NL * sizeof *ta), *tb = malloc(NP * NL * sizeof *tb);
    lobes(NL, dirs, lam);
    points(&h, NP, xyz);
    size_t plane = 96 * 96;
    uint32_t *za = malloc(plane * 4), *zb = malloc(plane * 4);
    uint64_t *sa = malloc(plane * SL_SHADOW_MAX_LAYERS * 8),
             *sb = malloc(plane * SL_SHADOW_MAX_LAYERS * 8);
    for (int win = 0; win < 2; win++) {
        sl_shadow_opts o;
        sl_shadow_opts_default(&o);
        o.size = 96;
        o.kappa = 0.5;
        o.z0_radius = win ? 0 : 2;
        sl_shadow_batch a, b;
        unsigned long k0 = sl_cl_kernels_enqueued();
        CHECK(sl_shadow_build_batch(&dk, &h, NL, dirs, lam, &o, &a, &e) == 0);
        CHECK_CL_RAN(k0);
        CHECK(sl_shadow_build_batch(&dc, &h, NL, dirs, lam, &o, &b, &e) == 0);
        CHECK(a.on_device && !b.on_device);
        printf("  window %d + %.3f texels\n", b.map[0].z0_radius, b.map[0].z0_frac);
        if (win) /* the fractional window is what this round checks */
            CHECK(b.map[0].z0_frac > 0.05f && b.map[0].z0_frac < 0.95f && b.map[0].z0_radius >= 1);
        for (int j = 0; j < NL; j++) {
            CHECK(sl_shadow_batch_read(&a, j, za, sa, &e) == 0);
            CHECK(sl_shadow_batch_read(&b, j, zb, sb, &e) == 0);
            CHECK(memcmp(za, zb, plane * 4) == 0);
            CHECK(memcmp(sa, sb, plane * o.layers * 8) == 0);
        }
        CHECK(sl_shadow_batch_lookup(&a, NP, xyz, NULL, ta, &e) == 0);
        CHECK(sl_shadow_batch_lookup(&b, NP, xyz, NULL, tb, &e) == 0);
        for (int i = 0; i < NP * NL; i++)
            CHECK_NEAR(ta[i], tb[i], 4e-6 * tb[i] + 1e-30);
        sl_shadow_batch_free(&a);
        sl_shadow_batch_free(&b);
    }
    free(ta);
    free(tb);
    free(za);
    free(zb);
    free(sa);
    free(sb);
    sl_hair_free(&h);
    sl_device_close(&dk);
    sl_device_close(&dc);
}
