/* test_shadow_threads.c: the threaded C paths of the light and volume passes (issue 9 speed):
 * the deep opacity maps and the march textures must not depend on the thread count (the farm
 * test compares frames byte for byte), and the rasterizer's unrolled in-map fast path must give
 * the same maps as a plain per-sample loop written here from the shared primitives of
 * kernels/raster.h with the libm rounding (llrintf) the kernel's convert_ulong_rte matches. */
#include "test.h"

#include "march_fixture.h"

#include "../cpu/dodm.h"
#include "../cpu/raster.h"
#include "../kernels/raster.h"
#include "passes/volume/dual.h"
#include "march.h"
#include "io/hair/hair.h"
#include "passes/light/shadow.h"
#include "passes/volume/volume.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double brand(uint64_t *s) {
    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

/* Every lobe's z0 and tables of a C batch built with 2, 3 and 7 threads equal the one-thread
 * maps bit for bit (exact integer sums and unsigned minima: no tolerance). 2 000 segments, so
 * 7 threads get ranges of ~300 segments with boundaries inside strands. */
TEST(shadow_threads_maps_identical) {
    sl_device dev;
    sl_err e = {{0}};
    CHECK(sl_device_open("c", &dev, &e) == 0);
    sl_hair h;
    sl_hair_procedural p = {SL_PROC_WAVY, 200, 11, 9};
    CHECK(sl_hair_generate(&p, &h, &e) == 0);
    enum { NL = 3, S = 64 };
    double dirs[3 * NL] = {0, 1, 0, 0.6, -0.48, 0.64, -0.8, 0, 0.6}, lam[NL] = {0.1, 0.3, 0.9};
    sl_shadow_opts o;
    sl_shadow_opts_default(&o);
    o.size = S;
    const size_t plane = S * S;
    uint32_t *z0[2];
    uint64_t *sat[2];
    for (int i = 0; i < 2; i++) {
        z0[i] = malloc(plane * sizeof *z0[i]);
        sat[i] = malloc(plane * o.layers * sizeof *sat[i]);
    }
    sl_shadow_batch ref;
    o.threads = 1;
    CHECK(sl_shadow_build_batch(&dev, &h, NL, dirs, lam, &o, &ref, &e) == 0);
    const int counts[3] = {2, 3, 7};
    for (int c = 0; c < 3; c++) {
        o.threads = counts[c];
        sl_shadow_batch b;
        CHECK(sl_shadow_build_batch(&dev, &h, NL, dirs, lam, &o, &b, &e) == 0);
        for (int j = 0; j < NL; j++) {
            CHECK(sl_shadow_batch_read(&ref, j, z0[0], sat[0], &e) == 0);
            CHECK(sl_shadow_batch_read(&b, j, z0[1], sat[1], &e) == 0);
            CHECK_MSG(!memcmp(z0[0], z0[1], plane * sizeof *z0[0]), "z0 of lobe %d, %d threads", j,
                      counts[c]);
            CHECK_MSG(!memcmp(sat[0], sat[1], plane * o.layers * sizeof *sat[0]),
                      "tables of lobe %d, %d threads", j, counts[c]);
            CHECK(b.map[j].samples == ref.map[j].samples);
        }
        /* the maps are not empty: the comparison above compares something */
        uint64_t total = sat[1][(size_t)(o.layers - 1) * plane + plane - 1];
        CHECK(total > 0);
        sl_shadow_batch_free(&b);
    }
    /* the single-lobe build (the renderer's call) too */
    sl_dodm m1, m3;
    o.threads = 1;
    CHECK(sl_shadow_build(&dev, &h, dirs + 3, lam[1], &o, &m1, &e) == 0);
    o.threads = 3;
    CHECK(sl_shadow_build(&dev, &h, dirs + 3, lam[1], &o, &m3, &e) == 0);
    CHECK(!memcmp(m1.z0bits, m3.z0bits, plane * sizeof *m1.z0bits));
    CHECK(!memcmp(m1.sat, m3.sat, plane * o.layers * sizeof *m1.sat));
    sl_dodm_free(&m1);
    sl_dodm_free(&m3);
    sl_shadow_batch_free(&ref);
    for (int i = 0; i < 2; i++) {
        free(z0[i]);
        free(sat[i]);
    }
    sl_hair_free(&h);
    sl_device_close(&dev);
}

/* The plain loop both plain passes share: every sample, every tent corner, bounds checked per
 * corner; visit(ctx, texel, rounded share, sample z) for each corner whose share rounds to > 0. */
typedef void (*naive_visit)(void *ctx, int texel, long long q, float z);
static void naive_corners(const float *recs, size_t n, int w, int h, naive_visit visit, void *ctx) {
    for (size_t s = 0; s < n; s++) {
        const float *r = recs + s * SL_RASTER_REC;
        for (sl_uint i = 0; i < (sl_uint)r[9]; i++)
            for (sl_uint j = 0; j < (sl_uint)r[10]; j++) {
                float x, y, z, fx, fy;
                sl_int ix, iy;
                sl_raster_sample(r, i, j, &x, &y, &z);
                sl_raster_tent(x, y, &ix, &iy, &fx, &fy);
                for (int c = 0; c < 4; c++) {
                    int tx = ix + (c & 1), ty = iy + (c >> 1);
                    if (tx < 0 || ty < 0 || tx >= w || ty >= h) continue;
                    float sh =
                        sl_raster_share(r[8], (c & 1) ? fx : 1.0f - fx, (c >> 1) ? fy : 1.0f - fy);
                    long long q = llrintf(sh);
                    if (q == 0) continue;
                    visit(ctx, ty * w + tx, q, z);
                }
            }
    }
}

/* z0: the minimum of the float bits of z per texel. */
static void visit_z0(void *ctx, int t, long long q, float z) {
    uint32_t *z0 = ctx, b;
    (void)q;
    memcpy(&b, &z, sizeof b);
    if (b < z0[t]) z0[t] = b;
}

static void naive_z0(const float *recs, size_t n, int w, int h, uint32_t *z0) {
    for (int t = 0; t < w * h; t++)
        z0[t] = SL_RASTER_Z_EMPTY;
    naive_corners(recs, n, w, h, visit_z0, z0);
}

typedef struct naive_layer_ctx {
    unsigned K;
    float d;
    const uint32_t *z0;
    uint64_t *bins;
    size_t plane;
} naive_layer_ctx;

/* layers: the rounded share into the bin of the layer of z below the texel's z0. */
static void visit_layer(void *ctx, int t, long long q, float z) {
    const naive_layer_ctx *c = ctx;
    float zz;
    memcpy(&zz, &c->z0[t], sizeof zz);
    c->bins[(size_t)sl_raster_layer(z - zz, c->d, c->K) * c->plane + t] += (uint64_t)q;
}

static void naive_layers(const float *recs, size_t n, int w, int h, unsigned K, float d,
                         const uint32_t *z0, uint64_t *bins) {
    memset(bins, 0, (size_t)K * w * h * sizeof *bins);
    naive_layer_ctx c = {K, d, z0, bins, (size_t)w * h};
    naive_corners(recs, n, w, h, visit_layer, &c);
}

/* Random ribbons in a 40 x 40 map, a third of them crossing or beyond its edges (the checked
 * path), the rest inside (the unrolled path); masses from 0.3 (shares rounding to 0 or 1, ties
 * included) to 2^40 (above 2^23: already integers), so both branches of the rounding are taken.
 * z0 and layers must equal the plain loops bit for bit. */
TEST(raster_fast_path_matches_plain_loops) {
    enum { N = 400, W = 40, H = 40, K = 5 };
    float *recs = malloc(N * SL_RASTER_REC * sizeof *recs);
    uint64_t st = 77;
    for (int s = 0; s < N; s++) {
        double x0, y0, x1, y1;
        if (s % 3 == 0) { /* anywhere, edges included */
            x0 = -6 + 52 * brand(&st), y0 = -6 + 52 * brand(&st);
        } else {
            x0 = 6 + 28 * brand(&st), y0 = 6 + 28 * brand(&st);
        }
        x1 = x0 + 6 * (brand(&st) - 0.5), y1 = y0 + 6 * (brand(&st) - 0.5);
        double p0[3] = {x0, y0, 3 * brand(&st)}, p1[3] = {x1, y1, 3 * brand(&st)};
        double mass = s % 4 == 0 ? 0.3 + brand(&st) : ldexp(1.0, (int)(40 * brand(&st)));
        slc_raster_record(p0, p1, 0.05 + 1.5 * brand(&st), mass, recs + s * SL_RASTER_REC);
    }
    uint32_t *za = malloc(W * H * 4), *zb = malloc(W * H * 4);
    uint64_t *ba = malloc((size_t)K * W * H * 8), *bb = malloc((size_t)K * W * H * 8);
    slc_raster_z0(recs, N, W, H, za);
    naive_z0(recs, N, W, H, zb);
    CHECK(!memcmp(za, zb, W * H * 4));
    size_t hit = 0;
    for (int t = 0; t < W * H; t++)
        hit += za[t] != SL_RASTER_Z_EMPTY;
    CHECK(hit > W * H / 2); /* most texels are covered: the comparison is not vacuous */
    slc_raster_layers(recs, N, W, H, K, 0.2f, za, ba);
    naive_layers(recs, N, W, H, K, 0.2f, za, bb);
    CHECK(!memcmp(ba, bb, (size_t)K * W * H * 8));
    size_t deep = 0;
    for (int t = 0; t < W * H; t++)
        deep += ba[(size_t)(K - 1) * W * H + t] > 0;
    CHECK(deep > 0); /* the last layer is reached too */
    /* texel-major layers (the lobe-parallel light pass), K = 5 (the generic loop) and K = 4 (its
     * own unrolled copy), cumulated into planes: the plain loop's cumulated planes bit for bit */
    uint64_t *bt = malloc((size_t)K * W * H * 8), *bc = malloc((size_t)K * W * H * 8);
    for (unsigned k = 4; k <= 5; k++) {
        naive_layers(recs, N, W, H, k, 0.2f, za, bb);
        slc_dodm_cumulate(bb, W * H, k);
        slc_raster_layers_texel(recs, N, W, H, k, 0.2f, za, bt);
        slc_dodm_cumulate_texel(bt, W * H, k, bc);
        CHECK_MSG(!memcmp(bb, bc, (size_t)k * W * H * 8), "texel-major layers, K = %u", k);
    }
    free(bt);
    free(bc);
    free(recs);
    free(za);
    free(zb);
    free(ba);
    free(bb);
}

/* In-map samples exactly on texel boundaries (x - 0.5 and y - 0.5 integers) and between them,
 * where the fast path takes floor as a truncation (cpu/raster.c: tent_inside, and quad_load for
 * the one-sample-wide records, half of these), and shares from
 * below 1 to above 2^32 (the rounding is one conversion on x86-64): z0 and the texel-major layers
 * (K = 4, the renderer's) equal the plain loops, which use sl_raster_tent and llrintf, bit for bit.
 * (A texel index one too low exactly on a boundary would give the same maps: the tent weight
 * there is 0. A truncation that rounds instead fails this test and the one above.) */
TEST(raster_fast_path_texel_edges) {
    enum { N = 64, W = 32, H = 32, K = 4 };
    float recs[N * SL_RASTER_REC];
    uint64_t st = 5;
    for (int s = 0; s < N; s++) {
        float *r = recs + s * SL_RASTER_REC;
        memset(r, 0, SL_RASTER_REC * sizeof *r);
        r[0] = 4.5f + (float)(s % 16);     /* x - 0.5 an integer */
        r[1] = 4.5f + (float)(s / 4 % 16); /* y - 0.5 an integer */
        r[2] = (float)(3 * brand(&st));
        r[3] = (s & 1) ? 0.5f : 0.25f; /* every other / every fourth sample on an edge again */
        r[4] = (s & 2) ? 0.5f : 0.0f;
        r[5] = (float)(0.1 * (brand(&st) - 0.5));
        r[6] = (s & 4) ? 0.0f : 0.5f;
        r[7] = (s & 4) ? 0.5f : 0.0f;
        r[8] = s % 3 == 0 ? (float)(0.3 + brand(&st)) : (float)ldexp(1.0, 10 + s % 36);
        r[9] = (float)(1 + s % 12);
        r[10] = (float)(1 + s % 2);
    }
    uint32_t za[W * H], zb[W * H];
    slc_raster_z0(recs, N, W, H, za);
    naive_z0(recs, N, W, H, zb);
    CHECK(!memcmp(za, zb, sizeof za));
    static uint64_t bt[K * W * H], bc[K * W * H], bb[K * W * H];
    naive_layers(recs, N, W, H, K, 0.02f, za, bb);
    slc_dodm_cumulate(bb, W * H, K);
    slc_raster_layers_texel(recs, N, W, H, K, 0.02f, za, bt);
    slc_dodm_cumulate_texel(bt, W * H, K, bc);
    CHECK(!memcmp(bb, bc, sizeof bb));
    size_t deep = 0;
    for (int t = 0; t < W * H; t++)
        deep += bb[(size_t)(K - 1) * W * H + t] != bb[(size_t)(K - 2) * W * H + t];
    CHECK(deep > 0); /* the last layer is reached: the layer choice is compared too */
}

/* sl_shadow_build_maps (the renderer's call: one batch, whole lobes per thread) gives every lobe
 * the map sl_shadow_build gives it alone, bit for bit, with 1 and 2 threads. */
TEST(shadow_build_maps_equal_single_builds) {
    sl_device dev;
    sl_err e = {{0}};
    CHECK(sl_device_open("c", &dev, &e) == 0);
    sl_hair h;
    sl_hair_procedural p = {SL_PROC_WAVY, 150, 9, 4};
    CHECK(sl_hair_generate(&p, &h, &e) == 0);
    enum { NL = 5, S = 48 };
    double dirs[3 * NL] = {0, 1, 0, 0.6, -0.48, 0.64, -0.8, 0, 0.6, 0, 0, -1, 0.36, 0.48, 0.8};
    double lam[NL] = {0.1, 0.3, 0.9, 0.2, 0.05};
    sl_shadow_opts o;
    sl_shadow_opts_default(&o);
    o.size = S;
    const size_t plane = S * S;
    sl_dodm one[NL], many[NL];
    o.threads = 1;
    for (int j = 0; j < NL; j++)
        CHECK(sl_shadow_build(&dev, &h, dirs + 3 * j, lam[j], &o, &one[j], &e) == 0);
    for (int nt = 1; nt <= 2; nt++) {
        o.threads = nt;
        CHECK(sl_shadow_build_maps(&dev, &h, NL, dirs, lam, &o, many, &e) == 0);
        for (int j = 0; j < NL; j++) {
            CHECK(!memcmp(one[j].z0bits, many[j].z0bits, plane * sizeof *one[j].z0bits));
            CHECK(!memcmp(one[j].sat, many[j].sat, plane * o.layers * sizeof *one[j].sat));
            CHECK(one[j].d == many[j].d && one[j].rfac == many[j].rfac);
            CHECK(one[j].samples == many[j].samples);
            CHECK(many[j].sat[(size_t)o.layers * plane - 1] > 0); /* not empty */
            sl_dodm_free(&many[j]);
        }
    }
    double zero[3 * NL] = {0};
    CHECK(sl_shadow_build_maps(&dev, &h, NL, zero, lam, &o, many, &e) != 0); /* a bad lobe */
    CHECK(strstr(e.msg, "direction") != NULL);
    for (int j = 0; j < NL; j++)
        sl_dodm_free(&one[j]);
    sl_hair_free(&h);
    sl_device_close(&dev);
}

/* The fixture's march on the C path: both lobes, 4 paths a vertex, `threads` C threads (0: the
 * default options' choice). */
static void march_c(const march_wavy *w, int threads, sl_ftex *f) {
    sl_err e = {{0}};
    sl_march_opts o;
    sl_march_opts_default(&o);
    o.paths = 4;
    o.threads = threads;
    CHECK(sl_march_build(NULL, &w->g, &w->dt, 2, w->dirs, &o, f, &e) == 0);
}

/* March textures (T_f, sigma_f) with 1, 2 and 5 C threads: bit-identical (every (vertex, lobe)
 * has its own random stream and the threads only split the list). */
TEST(march_threads_identical) {
    march_wavy w;
    march_wavy_setup(&w, NULL);
    sl_ftex a;
    march_c(&w, 1, &a);
    CHECK(a.active > 10);
    size_t nv = (size_t)a.m[0] * a.m[1] * a.m[2] * SL_MARCH_CH * 2;
    int below1 = 0;
    for (size_t i = 0; i < nv; i++)
        below1 += a.T[i] < 1.0f;
    CHECK(below1 > 0); /* some paths are shadowed: the textures carry something */
    const int counts[2] = {2, 5};
    for (int c = 0; c < 2; c++) {
        sl_ftex b;
        march_c(&w, counts[c], &b);
        CHECK(b.active == a.active);
        CHECK(!memcmp(a.T, b.T, nv * sizeof *a.T));
        CHECK(!memcmp(a.sigma, b.sigma, nv * sizeof *a.sigma));
        sl_ftex_free(&b);
    }
    sl_ftex_free(&a);
    march_wavy_free(&w);
}

/* sl_ftex_lookup from the precomputed log texture (f.logT) against the same lookup taking the
 * logs of the corners itself (f.logT hidden): bit-identical T_f and sigma_f at random points
 * inside and outside the grid (the same logf of the same texels, summed in the same order). */
TEST(march_ftex_log_texture_identical) {
    march_wavy w;
    march_wavy_setup(&w, NULL);
    sl_ftex f;
    march_c(&w, 0, &f);
    CHECK(f.logT != NULL);
    uint64_t st = 3;
    int shadowed = 0;
    for (int i = 0; i < 500; i++) {
        double q[3];
        for (int a = 0; a < 3; a++) /* the grid's box grown by 10 % on each side */
            q[a] = f.lo[a] + (1.2 * brand(&st) - 0.1) * (f.m[a] - 1) * f.H;
        float Ta[3], Sa[3], Tb[3], Sb[3];
        int lobe = i & 1;
        sl_ftex_lookup(&f, lobe, q, Ta, Sa);
        float *keep = f.logT;
        f.logT = NULL;
        sl_ftex_lookup(&f, lobe, q, Tb, Sb);
        f.logT = keep;
        CHECK(!memcmp(Ta, Tb, sizeof Ta) && !memcmp(Sa, Sb, sizeof Sa));
        shadowed += Ta[0] < 0.999f;
    }
    CHECK(shadowed > 0); /* the points see some T_f < 1 */
    sl_ftex_free(&f);
    march_wavy_free(&w);
}
