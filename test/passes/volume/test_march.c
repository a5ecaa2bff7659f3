/* test_march.c: the shadow-path march (kernels/march.h, cpu/march_c.c,
 * host/passes/volume/march_cl.c, host/passes/volume/volume.c) and its fiber-exact reference
 * (cpu/reference/march_ref.c), on slabs of parallel fibers where T_f and sigma_f have closed forms
 * (docs/volume.md), and kernel vs C twin. */
#include "test.h"

#include "cl_fixture.h"
#include "march_fixture.h"

#include "base/parallel.h"
#include "passes/volume/dual.h"
#include "dual_ref.h"
#include "march.h"
#include "march_ref.h"
#include "passes/volume/volume.h"
#include "voxel.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Lattice slab: fibers along x over [-0.5, 4.5], at y = (i + 1/2) 0.05 (i < 80, y in [0, 4)) and
 * z = (k + 1/2) 0.05 (k < 20, z in [0, 1)): n = 400 per unit area, radius 0.002, so sigma_perp =
 * 2 r n = 1.6 (numerics.md sec. 7). */
static float *lattice_slab(size_t *nseg) {
    float *s = sl_malloc(80 * 20 * SL_VOX_SEG * sizeof *s);
    size_t n = 0;
    for (int i = 0; i < 80; i++)
        for (int k = 0; k < 20; k++) {
            float y = (i + 0.5f) * 0.05f, z = (k + 0.5f) * 0.05f;
            float rec[SL_VOX_SEG] = {-0.5f, y, z, 0.002f, 4.5f, y, z, 0.002f};
            memcpy(s + n++ * SL_VOX_SEG, rec, sizeof rec);
        }
    *nseg = n;
    return s;
}

/* The lattice slab voxelized on a grid of 16 x 16 x 8 voxels of h = 0.25 from the origin, with
 * the default material and its dual tables. */
typedef struct slab_grid {
    float *segs;
    sl_voxel_grid g;
    sl_material m;
    sl_dual_tables dt;
} slab_grid;

static void slab_grid_setup(slab_grid *s) {
    sl_err e = {{0}};
    size_t ns;
    s->segs = lattice_slab(&ns);
    memset(&s->g, 0, sizeof s->g);
    s->g.n[0] = s->g.n[1] = 16;
    s->g.n[2] = 8;
    s->g.h = 0.25f;
    CHECK(sl_voxelize_segments(NULL, s->segs, ns, &s->g, &e) == 0);
    sl_material_default(&s->m);
    CHECK(sl_dual_tables_build(&s->m, &s->dt, &e) == 0);
}

static void slab_grid_free(slab_grid *s) {
    sl_voxel_grid_free(&s->g);
    free(s->segs);
}

/* The march on the slab from +z: coarse cells of 2 voxels, 512 paths, seed 5 (the tests below). */
static void slab_march_z(const slab_grid *s, sl_ftex *f) {
    sl_err e = {{0}};
    sl_march_opts o = {2, 512, 5, 1};
    double dir[3] = {0, 0, 1};
    CHECK(sl_march_build(NULL, &s->g, &s->dt, 1, dir, &o, f, &e) == 0);
}

/* The march on the lattice slab lit from +z (perpendicular to the fibers, theta = 0 at every
 * event). Grid 16 x 16 x 8 voxels of h = 0.25 from the origin (slab: voxel rows z < 1), coarse
 * cells of 2 voxels: vertices at z = 0 (depth d = 1) and z = 0.5 (d = 0.5). Steps of delta = h/2
 * with jittered starts: exactly M = d / delta of them fall in the slab, each an event with
 * probability P = 1 - exp(-1.6 delta); so K ~ Binomial(M, P) and, with a = a_f(0), b = beta_f(0):
 *     E[T_f] = (1 - P + P a)^M,   sigma_f^2 = E[a^K K] b^2 / E[a^K] = M P a b^2 / (1 - P + P a).
 * Interior vertices (9 per depth) x 512 paths are averaged; the tolerance is 4 standard errors of
 * the mean of a^K plus the float table's 1e-4. */
TEST(march_slab_binomial) {
    slab_grid s;
    slab_grid_setup(&s);
    sl_ftex f;
    slab_march_z(&s, &f);
    double ref[9];
    slref_dual_terms(&s.m, 0, 0.0, ref);
    double a = ref[SLREF_DUAL_AF], b = ref[SLREF_DUAL_BETA_F];
    double P = 1 - exp(-1.6 * 0.125);
    for (int depth = 0; depth < 2; depth++) {
        int M = depth == 0 ? 8 : 4, kz = depth; /* vertex z = 0.5 kz */
        double ET = pow(1 - P + P * a, M), ET2 = pow(1 - P + P * a * a, M);
        double s2 = M * P * a * b * b / (1 - P + P * a);
        double se = sqrt((ET2 - ET * ET) / (9 * 512));
        double sumT = 0, sumS = 0;
        int cnt = 0;
        for (int j = 1; j < f.m[1] - 1; j++)
            for (int i = 1; i < f.m[0] - 1; i++) {
                if (i > 3 || j > 3) continue; /* 3 x 3 interior vertices */
                size_t v = ((size_t)kz * f.m[1] + j) * f.m[0] + i;
                sumT += f.T[v * SL_MARCH_CH];
                sumS += f.sigma[v * SL_MARCH_CH] * f.sigma[v * SL_MARCH_CH];
                CHECK(f.T[v * SL_MARCH_CH + 1] == f.T[v * SL_MARCH_CH]); /* grey material */
                cnt++;
            }
        CHECK(cnt == 9);
        if (getenv("SL_TEST_VERBOSE"))
            fprintf(stderr, "  d=%g: T_f %.5f exact %.5f (se %.5f), sigma_f^2 %.6f exact %.6f\n",
                    depth == 0 ? 1.0 : 0.5, sumT / cnt, ET, se, sumS / cnt, s2);
        CHECK_MSG(fabs(sumT / cnt - ET) <= 4 * se + 1e-4, "d=%g: T_f %g vs %g (se %g)",
                  depth == 0 ? 1.0 : 0.5, sumT / cnt, ET, se);
        /* sigma_f^2: a ratio estimate; 5 % (its spread over 4608 paths is ~1 %). */
        CHECK_MSG(fabs(sumS / cnt - s2) <= 0.05 * s2, "d=%g: sigma_f^2 %g vs %g",
                  depth == 0 ? 1.0 : 0.5, sumS / cnt, s2);
    }
    /* Above the slab (z = 1, 1.5): no fibers on the path, T_f = 1 exactly, sigma_f = 0. */
    size_t v = ((size_t)3 * f.m[1] + 2) * f.m[0] + 2;
    CHECK(f.T[v * SL_MARCH_CH] == 1.0f && f.sigma[v * SL_MARCH_CH] == 0.0f);
    /* Lookup halfway between depths 1 and 0.5: T_f interpolates in log space (the geometric mean
     * of the two vertices), sigma_f linearly. */
    double p[3] = {1.0, 1.0, 0.25};
    float T[3], S[3];
    sl_ftex_lookup(&f, 0, p, T, S);
    size_t v0 = ((size_t)0 * f.m[1] + 2) * f.m[0] + 2, v1 = ((size_t)1 * f.m[1] + 2) * f.m[0] + 2;
    CHECK_NEAR(T[0], sqrt((double)f.T[v0 * SL_MARCH_CH] * f.T[v1 * SL_MARCH_CH]), 1e-6);
    CHECK_NEAR(S[0], 0.5 * (f.sigma[v0 * SL_MARCH_CH] + f.sigma[v1 * SL_MARCH_CH]), 1e-6);
    sl_ftex_free(&f);
    slab_grid_free(&s);
}

/* The tilt the light crosses (kernels/march.h, docs/volume.md "Where the scattered light goes").
 * On the lattice slab every fiber is parallel to the vertex's (dev 0): tilt2 = 0 at every vertex.
 * With every filled voxel's spread set to D = 0.1, an event's fiber is d + g (g Gaussian in the
 * normal plane, E|g|^2 = D^2, so |g|^2 is exponential of mean D^2) and its unit tilt from d is
 * 2 (1 - (1 + |g|^2)^-1/2), of mean E1 (by quadrature below); each event adds E1 + D^2 (the
 * shading fiber's own spread), and the energy-weighted count of events is the binomial
 * E[K a^K] / E[a^K] = M P a / (1 - P + P a) of march_slab_binomial, with P from the attenuation
 * sl_vox_alpha gives the spread fibers (sqrt(1 - D^2 / 2) of sigma_perp across them). The
 * per-event a_f(theta) now varies with the tilt (theta ~ 0.07 rad): 5 % covers it and the
 * ratio estimate's spread over 4608 paths. */
TEST(march_slab_tilt) {
    slab_grid s;
    slab_grid_setup(&s);
    sl_ftex f;
    slab_march_z(&s, &f);
    size_t nvert = (size_t)f.m[0] * f.m[1] * f.m[2];
    float worst = 0.0f;
    for (size_t i = 0; i < nvert * SL_MARCH_CH; i++)
        worst = fmaxf(worst, fabsf(f.tilt2[i]));
    CHECK_MSG(worst < 1e-6f, "parallel fibers: tilt2 up to %g", worst);
    sl_ftex_free(&f);

    const double D = 0.1;
    size_t nvox = (size_t)s.g.n[0] * s.g.n[1] * s.g.n[2];
    for (size_t v = 0; v < nvox; v++)
        if (s.g.vox[v * SL_VOX_FIELDS + SL_VOX_SIGMA] > 0.0f)
            s.g.vox[v * SL_VOX_FIELDS + SL_VOX_DEV] = (float)D;
    slab_march_z(&s, &f);
    double E1 = 0.0, du = D * D / 200.0; /* midpoint rule over u = |g|^2 to 40 D^2 */
    for (int k = 0; k < 8000; k++) {
        double u = (k + 0.5) * du;
        E1 += 2.0 * (1.0 - 1.0 / sqrt(1.0 + u)) * exp(-u / (D * D)) / (D * D) * du;
    }
    double ref[9];
    slref_dual_terms(&s.m, 0, 0.0, ref);
    double a = ref[SLREF_DUAL_AF];
    double P = 1 - exp(-1.6 * sqrt(1.0 - 0.5 * D * D) * 0.125);
    for (int depth = 0; depth < 2; depth++) {
        int M = depth == 0 ? 8 : 4, kz = depth;
        double want = M * P * a / (1 - P + P * a) * (E1 + D * D), sum = 0.0;
        for (int j = 1; j <= 3; j++)
            for (int i = 1; i <= 3; i++)
                sum += f.tilt2[(((size_t)kz * f.m[1] + j) * f.m[0] + i) * SL_MARCH_CH];
        if (getenv("SL_TEST_VERBOSE"))
            fprintf(stderr, "  d=%g: tilt2 %.6f closed form %.6f\n", depth == 0 ? 1.0 : 0.5,
                    sum / 9, want);
        CHECK_MSG(fabs(sum / 9 - want) <= 0.05 * want, "d=%g: tilt2 %g vs %g",
                  depth == 0 ? 1.0 : 0.5, sum / 9, want);
    }
    /* Above the slab no fiber is crossed: no tilt. */
    CHECK(f.tilt2[(((size_t)3 * f.m[1] + 2) * f.m[0] + 2) * SL_MARCH_CH] == 0.0f);
    sl_ftex_free(&f);
    slab_grid_free(&s);
}

/* Deterministic: the same seed gives the same textures; another seed different ones. */
TEST(march_seeded) {
    sl_err e = {{0}};
    slab_grid s;
    slab_grid_setup(&s);
    double dir[3] = {0.3, 0.2, 0.9327379};
    sl_march_opts o = {4, 4, 1, 1};
    sl_ftex f1, f2, f3;
    CHECK(sl_march_build(NULL, &s.g, &s.dt, 1, dir, &o, &f1, &e) == 0);
    CHECK(sl_march_build(NULL, &s.g, &s.dt, 1, dir, &o, &f2, &e) == 0);
    o.seed = 2;
    CHECK(sl_march_build(NULL, &s.g, &s.dt, 1, dir, &o, &f3, &e) == 0);
    size_t nv = (size_t)f1.m[0] * f1.m[1] * f1.m[2] * SL_MARCH_CH;
    CHECK(memcmp(f1.T, f2.T, nv * sizeof(float)) == 0);
    CHECK(memcmp(f1.T, f3.T, nv * sizeof(float)) != 0);
    sl_ftex_free(&f1);
    sl_ftex_free(&f2);
    sl_ftex_free(&f3);
    slab_grid_free(&s);
}

/* The reference on a lattice of 6 layers of fibers along x (z = 0.1 k, y = 0.05 i): a ray from
 * below through a fiber column crosses exactly N = 6 fibers, all at the inclination theta0 of the
 * ray to the fibers' normal plane: T_f = a_f(theta0)^6, sigma_f = sqrt(6) beta_f(theta0). */
TEST(march_reference_lattice) {
    sl_hair h;
    memset(&h, 0, sizeof h);
    sl_hair_alloc(&h, 60, 180);
    for (int s = 0; s < 60; s++) {
        h.strand_first[s] = 3 * s;
        for (int p = 0; p < 3; p++) {
            float *q = h.pos + 3 * (3 * s + p);
            q[0] = -3.0f + 3.0f * p;
            q[1] = (s % 10) * 0.05f;
            q[2] = (s / 10) * 0.1f;
        }
    }
    h.strand_first[60] = 180;
    h.default_radius = 0.01f;
    sl_material m;
    sl_material_default(&m);
    double th0s[2] = {0.0, 0.6};
    for (int t = 0; t < 2; t++) {
        double th0 = th0s[t];
        /* x between the strand's two segments' joint and not at it: x = 0.7. */
        double x[3] = {0.7, 0.2 + 0.004, -0.5}, w[3] = {sin(th0), 0, cos(th0)}, theta[16];
        size_t n = slref_march_events(&h, x, w, theta, 16);
        CHECK(n == 6);
        for (size_t k = 0; k < n && k < 16; k++)
            CHECK_NEAR(theta[k], th0, 1e-12);
        double Tf, sf, ref[9];
        slref_forward_from_events(&m, 0, theta, n, NULL, &Tf, &sf);
        slref_dual_terms(&m, 0, th0, ref);
        CHECK_REL(Tf, pow(ref[SLREF_DUAL_AF], 6), 1e-12);
        CHECK_REL(sf, sqrt(6.0) * ref[SLREF_DUAL_BETA_F], 1e-12);
    }
    /* A ray through the joint of two segments of one strand is one event per strand, not two. */
    double x[3] = {0.0, 0.2, -0.5}, w[3] = {0, 0, 1}, theta[16];
    CHECK(slref_march_events(&h, x, w, theta, 16) == 6);
    /* A ray between the columns (y = 0.225, 0.025 from each) meets nothing; one starting inside
     * a fiber ignores that fiber. */
    double x2[3] = {0.7, 0.225, -0.5}, x3[3] = {0.7, 0.2, 0.1};
    CHECK(slref_march_events(&h, x2, w, theta, 16) == 0);
    CHECK(slref_march_events(&h, x3, w, theta, 16) == 4);
    sl_hair_free(&h);
}

TEST(march_opencl_vs_c) {
    sl_err e = {{0}};
    sl_device dev;
    SL_TEST_OPEN_CL(&dev, &e);
    march_wavy w;
    const double sa[3] = {0.2, 0.5, 1.1};
    march_wavy_setup(&w, sa);
    sl_march_opts o = {4, 8, 3, 1};
    sl_ftex a, b;
    unsigned long k0 = sl_cl_kernels_enqueued();
    CHECK(sl_march_build(&dev, &w.g, &w.dt, 2, w.dirs, &o, &a, &e) == 0);
    CHECK_CL_RAN(k0);
    CHECK(sl_march_build(NULL, &w.g, &w.dt, 2, w.dirs, &o, &b, &e) == 0);
    CHECK(a.active == b.active && a.active > 0);
    size_t nv = (size_t)a.m[0] * a.m[1] * a.m[2] * SL_MARCH_CH * 2, bad = 0;
    double worst = 0;
    for (size_t i = 0; i < nv; i++) {
        double d = fmax(fabs(a.T[i] - b.T[i]), fabs(a.sigma[i] - b.sigma[i]));
        d = fmax(d, fabs(a.tilt2[i] - b.tilt2[i]));
        if (d > worst) worst = d;
        if (d > 1e-4) bad++;
    }
    /* T_f, sigma_f and tilt2. Same random numbers, same float steps; the device's exp/asin/log may
     * differ by a few ulp,
     * which can flip an event decision when a uniform lies within ~1e-7 of P: at most 1 in 1000
     * values may differ by more than 1e-4 (one path of 8 changed). */
    if (getenv("SL_TEST_VERBOSE"))
        fprintf(stderr, "  march kernel vs C: %zu of %zu differ by > 1e-4, worst %g\n", bad, nv,
                worst);
    CHECK_MSG(bad * 1000 <= nv, "%zu of %zu values differ by > 1e-4 (worst %g)", bad, nv, worst);
    sl_ftex_free(&a);
    sl_ftex_free(&b);
    march_wavy_free(&w);
    sl_device_close(&dev);
}

/* The per-path and per-event constants of sl_march_path (session 7) give the numbers of the
 * direct forms: the random key (four of the five hashes, once per path) then the last hash
 * equals the five-hash chain written out here (the counter of docs/volume.md), and one
 * sl_dual_locate per event with sl_march_dual_at equals sl_dual_lookup of each row and channel,
 * bit for bit, over a sweep of theta that includes the table's ends and nodes. The chain is
 * checked, not the hash itself, so the test calls the kernel's sl_march_hash. */
TEST(march_event_constants_bit_identical) {
    for (sl_uint i = 0; i < 2000; i++) {
        sl_uint seed = i * 7u + 1u, a = i * 2654435761u, b = i % 70u, c = i % 16u;
        sl_uint d = i == 0 ? 0xffffffffu : 4u * i + (i % 3u);
        sl_uint x = sl_march_hash(seed ^ 0x9e3779b9u);
        x = sl_march_hash(x ^ a);
        x = sl_march_hash(x ^ (b * 0x85ebca6bu));
        x = sl_march_hash(x ^ (c * 0xc2b2ae35u));
        x = sl_march_hash(x ^ d);
        float direct = (float)(x >> 8) * (1.0f / 16777216.0f);
        float viakey = sl_march_rand_at(sl_march_rand_key(seed, a, b, c), d);
        CHECK_MSG(direct == viakey, "counter %u: %.9g vs %.9g", i, direct, viakey);
    }
    sl_material m;
    sl_material_default(&m);
    m.sigma_a_rgb = 1;
    m.sigma_a[0] = 0.2, m.sigma_a[1] = 0.5, m.sigma_a[2] = 1.1;
    sl_err e = {{0}};
    sl_dual_tables dt;
    CHECK(sl_dual_tables_build(&m, &dt, &e) == 0);
    const int rows[2] = {SL_DUAL_AF, SL_DUAL_BETA_F};
    for (int q = 0; q <= 4000; q++) {
        float theta = q < 4000 ? 1.6f * (float)q / 4000.0f : SL_DUAL_HALF_PI;
        if (q % 500 == 7) theta = sl_dual_node(q / 40); /* exactly on a node */
        float t;
        int it = sl_dual_locate(theta, &t);
        for (int ch = 0; ch < SL_MARCH_CH; ch++)
            for (int r = 0; r < 2; r++) {
                float once = sl_march_dual_at(dt.tab[ch], rows[r], it, t);
                float each = sl_dual_lookup(dt.tab[ch], rows[r], theta);
                CHECK_MSG(once == each, "theta %.9g ch %d row %d: %.9g vs %.9g", theta, ch, rows[r],
                          once, each);
            }
    }
}

/* The dynamic sharing of the C march (threads take chunks of voxels and vertices from a shared
 * counter): 3 and 16 threads, and 4 threads of which only one can start (the rest of the work
 * falls to the calling thread, sl_parallel_limit_spawns), give the one-thread textures bit for
 * bit, on an [r,g,b] material so that every channel is checked. */
TEST(march_dynamic_threads_identical) {
    march_wavy w;
    const double sa[3] = {0.2, 0.5, 1.1};
    march_wavy_setup(&w, sa);
    sl_err e = {{0}};
    sl_march_opts o;
    sl_march_opts_default(&o);
    o.paths = 4;
    o.threads = 1;
    sl_ftex a;
    CHECK(sl_march_build(NULL, &w.g, &w.dt, 2, w.dirs, &o, &a, &e) == 0);
    size_t nv = (size_t)a.m[0] * a.m[1] * a.m[2] * SL_MARCH_CH * 2;
    CHECK(a.active > 8 * 2); /* more than one chunk of vertices per lobe */
    const int counts[3] = {3, 16, 4}, spawn_limit[3] = {-1, -1, 1};
    for (int c = 0; c < 3; c++) {
        sl_parallel_limit_spawns(spawn_limit[c]);
        o.threads = counts[c];
        sl_ftex b;
        CHECK(sl_march_build(NULL, &w.g, &w.dt, 2, w.dirs, &o, &b, &e) == 0);
        sl_parallel_limit_spawns(-1);
        CHECK_MSG(!memcmp(a.T, b.T, nv * sizeof *a.T), "%d threads: T_f differs", counts[c]);
        CHECK_MSG(!memcmp(a.sigma, b.sigma, nv * sizeof *a.sigma), "%d threads: sigma_f differs",
                  counts[c]);
        sl_ftex_free(&b);
    }
    sl_ftex_free(&a);
    march_wavy_free(&w);
}

/* The depth-guided T_f lookup (sl_ftex_lookup_guided, docs/volume.md "Depth-guided T_f") on two
 * vertices of a medium where T_f = exp(-(1 - a) tau) exactly (Poisson crossings of fibers of
 * forward albedo a, per channel): a vertex outside the hair (tau 0, T_f 1) and one inside (tau
 * 2). A point halfway between them whose own depth is tau_p = 0.3 (a fiber near the lit surface)
 * gets exp(-(1 - a) 0.3) exactly; the log-space interpolation of sl_ftex_lookup_at gives the
 * midpoint's exp(-(1 - a) 1.0), and it is what is left where the corners hold no depth or no
 * depths were set. k is clamped to [-1, 0] (a texel darker than its depth allows). */
TEST(ftex_lookup_depth_guided) {
    const float a[3] = {0.9f, 0.6f, 0.2f};
    sl_ftex f;
    memset(&f, 0, sizeof f);
    f.m[0] = 2, f.m[1] = 1, f.m[2] = 1, f.H = 1.0f, f.nlobes = 1;
    f.T = calloc(2 * SL_MARCH_CH, sizeof(float));
    f.sigma = calloc(2 * SL_MARCH_CH, sizeof(float));
    f.logT = calloc(2 * SL_MARCH_CH, sizeof(float));
    for (int c = 0; c < 3; c++) {
        f.T[c] = 1.0f, f.T[SL_MARCH_CH + c] = expf(-(1.0f - a[c]) * 2.0f);
        for (int v = 0; v < 2; v++)
            f.logT[v * SL_MARCH_CH + c] = logf(f.T[v * SL_MARCH_CH + c]);
    }
    sl_ftex_corners cn;
    double p[3] = {0.5, 0, 0};
    sl_ftex_at(&f, p, &cn);
    float T[3], S[3];
    sl_ftex_lookup_guided(&f, 0, &cn, 0.3f, T, S); /* no depths yet: the log-space lookup */
    for (int c = 0; c < 3; c++)
        CHECK_NEAR(T[c], exp(-(1.0 - a[c]) * 1.0), 1e-6);
    const float Tj[2] = {1.0f, expf(-2.0f)};
    sl_ftex_set_tau(&f, Tj);
    sl_ftex_lookup_guided(&f, 0, &cn, 0.3f, T, S);
    for (int c = 0; c < 3; c++)
        CHECK_NEAR(T[c], exp(-(1.0 - a[c]) * 0.3), 1e-6);
    /* a point deeper than its corners on average: the same law */
    sl_ftex_lookup_guided(&f, 0, &cn, 3.0f, T, S);
    for (int c = 0; c < 3; c++)
        CHECK_NEAR(T[c], exp(-(1.0 - a[c]) * 3.0), 1e-5);
    /* corners with almost no depth (sum w tau 0.025 < SL_FTEX_TAU_MIN): the texels' log-space
     * lookup, whatever tau_p */
    const float out[2] = {1.0f, expf(-0.05f)};
    sl_ftex_set_tau(&f, out);
    sl_ftex_lookup_guided(&f, 0, &cn, 1.0f, T, S);
    for (int c = 0; c < 3; c++)
        CHECK_NEAR(T[c], exp(-(1.0 - a[c]) * 1.0), 1e-6);
    /* a texel darker than e^-tau (k < -1) is clamped to k = -1 */
    const float shallow[2] = {1.0f, expf(-0.5f)};
    sl_ftex_set_tau(&f, shallow);
    sl_ftex_lookup_guided(&f, 0, &cn, 1.0f, T, S);
    CHECK_NEAR(T[2], exp(-1.0), 1e-6); /* k = -(1 - a) / 0.25 = -3.2 -> -1 */
    CHECK_NEAR(T[0], exp(-(0.1 * 2.0 * 0.5) / (0.5 * 0.5)), 1e-6);
    sl_ftex_free(&f);
}
