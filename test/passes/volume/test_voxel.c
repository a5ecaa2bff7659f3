/* test_voxel.c: hair voxelization (kernels/voxel.h, cpu/voxel_c.c, host/passes/volume/voxel_cl.c,
 * host/passes/volume/volume.c): C twin against analytic grids and independent double computations, and the
 * OpenCL kernel against the C twin (the test device, cl_fixture.h). */
#include "test.h"

#include "cl_fixture.h"

#include "passes/volume/volume.h"
#include "voxel.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static double vrand(uint64_t *s) {
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) * (1.0 / 9007199254740992.0);
}

static void set_grid(sl_voxel_grid *g, int n, float h) {
    memset(g, 0, sizeof *g);
    g->n[0] = g->n[1] = g->n[2] = n;
    g->h = h;
}

/* Slab of fibers along x on a lattice (spacing 0.05 in y and z: n = 400 per unit area), radius
 * 0.002, crossing an 8^3 grid of 0.25 voxels. Analytic per voxel: density = n = 400, sigma_perp =
 * 2 r n = 1.6, dir = (1, 0, 0), dev = 0. */
static float *slab_x(size_t *nseg) {
    size_t n = 0;
    float *s = sl_malloc(40 * 40 * SL_VOX_SEG * sizeof *s);
    for (int i = 0; i < 40; i++)
        for (int k = 0; k < 40; k++) {
            float *o = s + n++ * SL_VOX_SEG;
            float y = (i + 0.5f) * 0.05f, z = (k + 0.5f) * 0.05f;
            float rec[SL_VOX_SEG] = {-0.5f, y, z, 0.002f, 2.5f, y, z, 0.002f};
            memcpy(o, rec, sizeof rec);
        }
    *nseg = n;
    return s;
}

TEST(voxel_slab_analytic) {
    sl_err e = {{0}};
    size_t ns;
    float *segs = slab_x(&ns);
    sl_voxel_grid g;
    set_grid(&g, 8, 0.25f);
    CHECK(sl_voxelize_segments(NULL, segs, ns, &g, &e) == 0);
    double worst = 0;
    for (size_t v = 0; v < 512; v++) {
        const float *x = g.vox + v * SL_VOX_FIELDS;
        /* Pieces are 1/16 long and aligned with the voxel faces: each voxel gets exactly 25
         * fibers x 0.25; float rounding of the pieces and of / h^3: 1e-5 relative. */
        double r1 = fabs(x[SL_VOX_DENSITY] - 400.0) / 400.0, r2 = fabs(x[SL_VOX_SIGMA] - 1.6) / 1.6;
        if (r1 > worst) worst = r1;
        if (r2 > worst) worst = r2;
        CHECK_NEAR(x[SL_VOX_DIRX], 1.0, 1e-6);
        CHECK_NEAR(x[SL_VOX_DIRY], 0.0, 1e-6);
        CHECK_NEAR(x[SL_VOX_DEV], 0.0, 1e-3); /* sqrt of a 1e-7 rounding residue at most */
    }
    CHECK_MSG(worst < 1e-5, "density/sigma worst relative error %g", worst);
    /* alpha (Ren's attenuation ratio) of parallel fibers is |sin| exactly. */
    const float *x = g.vox;
    CHECK_NEAR(sl_vox_alpha(x, 0.0f, 0.0f, 1.0f), 1.0, 1e-3);
    CHECK_NEAR(sl_vox_alpha(x, 0.6f, 0.0f, 0.8f), 0.8, 1e-3);
    sl_voxel_grid_free(&g);
    free(segs);
}

/* A grid over SL_VOXEL_MAX voxels is refused with a message, not allocated. */
TEST(voxel_too_large) {
    sl_err e = {{0}};
    sl_voxel_grid g;
    set_grid(&g, 512, 1.0f);
    CHECK(sl_voxelize_segments(NULL, NULL, 0, &g, &e) == -1);
    CHECK(strstr(e.msg, "lower quality.voxels") != NULL);
    CHECK(g.vox == NULL);
}

TEST(voxel_empty_and_outside) {
    sl_err e = {{0}};
    sl_voxel_grid g;
    set_grid(&g, 4, 1.0f);
    CHECK(sl_voxelize_segments(NULL, NULL, 0, &g, &e) == 0);
    for (size_t i = 0; i < 64 * SL_VOX_FIELDS; i++)
        CHECK(g.vox[i] == 0.0f);
    sl_voxel_grid_free(&g);
    /* A segment entirely outside the grid and a zero-length one add nothing. */
    float segs[2 * SL_VOX_SEG] = {5, 5, 5, 0.1f, 6, 6, 6, 0.1f, 1, 1, 1, 0.1f, 1, 1, 1, 0.1f};
    set_grid(&g, 4, 1.0f);
    CHECK(sl_voxelize_segments(NULL, segs, 2, &g, &e) == 0);
    for (size_t i = 0; i < 64 * SL_VOX_FIELDS; i++)
        CHECK(g.vox[i] == 0.0f);
    sl_voxel_grid_free(&g);
}

/* Power iteration in double (independent of the float header): principal eigenvector. */
static void principal(const double m[3][3], double v[3], double *lam) {
    double x[3] = {0.577, 0.571, 0.583};
    for (int it = 0; it < 2000; it++) {
        double y[3] = {0, 0, 0};
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++)
                y[a] += m[a][b] * x[b];
        double n = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
        for (int a = 0; a < 3; a++)
            x[a] = y[a] / n;
    }
    double y = 0;
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            y += x[a] * m[a][b] * x[b];
    memcpy(v, x, sizeof x);
    *lam = y;
}

/* All hair in one voxel: 300 random short segments around a preferred axis inside voxel (1,1,1)
 * of a 3^3 grid; density, sigma, direction and deviation against double sums. */
TEST(voxel_one_voxel) {
    sl_err e = {{0}};
    uint64_t s = 7;
    const int NS = 300;
    float *segs = sl_malloc(NS * SL_VOX_SEG * sizeof *segs);
    double sum_l = 0, sum_2rl = 0, m[3][3] = {{0}};
    for (int i = 0; i < NS; i++) {
        double t[3] = {0.3 + 0.4 * (vrand(&s) - 0.5), 1.0, 0.2 * (vrand(&s) - 0.5)};
        double tn = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
        double L = 0.1 + 0.3 * vrand(&s), r = 0.001 + 0.01 * vrand(&s);
        double c[3] = {1.3 + 0.4 * vrand(&s), 1.3 + 0.4 * vrand(&s), 1.3 + 0.4 * vrand(&s)};
        float *o = segs + i * SL_VOX_SEG;
        for (int a = 0; a < 3; a++) {
            o[a] = (float)(c[a] - 0.5 * L * t[a] / tn);
            o[4 + a] = (float)(c[a] + 0.5 * L * t[a] / tn);
        }
        o[3] = o[7] = (float)r;
        /* The float endpoints define the segment: take L and t from them. */
        double d[3] = {o[4] - o[0], o[5] - o[1], o[6] - o[2]};
        double Lf = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        sum_l += Lf;
        sum_2rl += 2 * (double)o[3] * Lf;
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++)
                m[a][b] += d[a] * d[b] / Lf;
    }
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            m[a][b] /= sum_l;
    double v[3], lam;
    principal(m, v, &lam);
    sl_voxel_grid g;
    set_grid(&g, 3, 1.0f);
    CHECK(sl_voxelize_segments(NULL, segs, NS, &g, &e) == 0);
    for (int vi = 0; vi < 27; vi++) {
        const float *x = g.vox + vi * SL_VOX_FIELDS;
        if (vi != 13) {
            CHECK(x[SL_VOX_DENSITY] == 0.0f);
            continue;
        }
        /* Float pieces summed exactly in fixed point: 1e-5 relative. */
        CHECK_REL(x[SL_VOX_DENSITY], sum_l, 1e-5);
        CHECK_REL(x[SL_VOX_SIGMA], sum_2rl, 1e-5);
        double dot = fabs(x[SL_VOX_DIRX] * v[0] + x[SL_VOX_DIRY] * v[1] + x[SL_VOX_DIRZ] * v[2]);
        /* 24 float power iterations on a well-separated spectrum: 1e-5 in the cosine. */
        CHECK_NEAR(dot, 1.0, 1e-5);
        CHECK_NEAR(x[SL_VOX_DEV], sqrt(1 - lam), 1e-3);
        CHECK(x[SL_VOX_DIRY] > 0); /* canonical sign: the largest component positive */
    }
    sl_voxel_grid_free(&g);
    free(segs);
}

/* Strands along an axis (y) through a 16^3 layout from sl_voxel_grid_layout. */
TEST(voxel_axis_strands_layout) {
    sl_err e = {{0}};
    sl_hair h;
    memset(&h, 0, sizeof h);
    sl_hair_alloc(&h, 10, 40);
    for (int s = 0; s < 10; s++) {
        h.strand_first[s] = 4 * s;
        for (int p = 0; p < 4; p++) {
            float *q = h.pos + 3 * (4 * s + p);
            q[0] = (float)s * 0.2f;
            q[1] = (float)p;
            q[2] = (float)(s % 3) * 0.5f;
        }
    }
    h.strand_first[10] = 40;
    h.default_radius = 0.01f;
    sl_voxel_grid g;
    CHECK(sl_voxelize(NULL, &h, 16, &g, &e) == 0);
    /* Longest extent y (3 + margins): 16 voxels along y; others from their extents. */
    CHECK(g.n[1] == 16);
    CHECK(g.n[0] >= 1 && g.n[0] <= 16 && g.n[2] >= 1 && g.n[2] <= 16);
    CHECK(g.lo[1] < 0.0f && g.lo[1] + 16 * g.h > 3.0f);
    double total = 0;
    size_t nv = (size_t)g.n[0] * g.n[1] * g.n[2];
    for (size_t v = 0; v < nv; v++) {
        const float *x = g.vox + v * SL_VOX_FIELDS;
        total += x[SL_VOX_DENSITY];
        if (x[SL_VOX_DENSITY] > 0) {
            CHECK_NEAR(x[SL_VOX_DIRY], 1.0, 1e-6);
            CHECK_NEAR(x[SL_VOX_DEV], 0.0, 1e-3);
        }
    }
    /* Total length 10 x 3, every piece inside the grid. */
    CHECK_REL(total * g.h * g.h * g.h, 30.0, 1e-5);
    sl_voxel_grid_free(&g);
    sl_hair_free(&h);
}

/* An isotropic cloud: M = I/3 in expectation, so the deviation is near sqrt(2/3). */
TEST(voxel_isotropic_cloud) {
    sl_err e = {{0}};
    uint64_t s = 11;
    const int NS = 4000;
    float *segs = sl_malloc(NS * SL_VOX_SEG * sizeof *segs);
    for (int i = 0; i < NS; i++) {
        double z = 2 * vrand(&s) - 1, ph = 2 * M_PI * vrand(&s), q = sqrt(1 - z * z);
        double t[3] = {q * cos(ph), q * sin(ph), z}, c[3];
        for (int a = 0; a < 3; a++)
            c[a] = 0.1 + 0.8 * vrand(&s);
        float *o = segs + i * SL_VOX_SEG;
        for (int a = 0; a < 3; a++) {
            o[a] = (float)(c[a] - 0.02 * t[a]);
            o[4 + a] = (float)(c[a] + 0.02 * t[a]);
        }
        o[3] = o[7] = 0.001f;
    }
    sl_voxel_grid g;
    set_grid(&g, 1, 1.0f);
    CHECK(sl_voxelize_segments(NULL, segs, NS, &g, &e) == 0);
    /* 4000 directions: M's eigenvalues are 1/3 +- ~0.01, so dev = sqrt(1 - lam_max) is within
     * 0.02 of sqrt(2/3) = 0.8165 (the largest of three noisy eigenvalues is biased up). */
    CHECK_NEAR(g.vox[SL_VOX_DEV], sqrt(2.0 / 3.0), 0.02);
    /* alpha: the rms sine sqrt(2/3) in every direction (E|sin| = pi/4 is 3.9 % lower). */
    CHECK_NEAR(sl_vox_alpha(g.vox, 0, 0, 1), sqrt(2.0 / 3.0), 0.02);
    sl_voxel_grid_free(&g);
    free(segs);
}

static void compare_grids(const sl_voxel_grid *a, const sl_voxel_grid *b, double *worst_rel,
                          double *worst_dir) {
    size_t nv = (size_t)a->n[0] * a->n[1] * a->n[2];
    *worst_rel = *worst_dir = 0;
    for (size_t v = 0; v < nv; v++) {
        const float *x = a->vox + v * SL_VOX_FIELDS, *y = b->vox + v * SL_VOX_FIELDS;
        for (int k = 0; k < 2; k++) {
            double d = fabs(x[k] - y[k]), r = y[k] != 0 ? d / fabs(y[k]) : (d > 0 ? INFINITY : 0);
            if (r > *worst_rel) *worst_rel = r;
        }
        if (y[SL_VOX_DENSITY] == 0.0f) {
            for (int k = 0; k < SL_VOX_FIELDS; k++)
                if (x[k] != 0.0f) *worst_dir = INFINITY;
            continue;
        }
        double dd = fabs(x[SL_VOX_DEV] - y[SL_VOX_DEV]);
        if (dd > *worst_dir) *worst_dir = dd;
        /* The axis is only defined where the spectrum is separated (dev well below isotropic). */
        if (y[SL_VOX_DEV] < 0.6f) {
            double dot = fabs(x[2] * y[2] + x[3] * y[3] + x[4] * y[4]);
            if (1 - dot > *worst_dir) *worst_dir = 1 - dot;
        }
    }
}

TEST(voxel_opencl_vs_c) {
    sl_err e = {{0}};
    sl_device dev, c;
    SL_TEST_OPEN_CL(&dev, &e);
    sl_device_open("c", &c, &e);
    sl_hair h;
    sl_hair_procedural p = {SL_PROC_WAVY, 300, 12, 3};
    CHECK(sl_hair_generate(&p, &h, &e) == 0);
    sl_voxel_grid a, b;
    /* Typical: procedural hair at 32 voxels. */
    unsigned long k0 = sl_cl_kernels_enqueued();
    CHECK(sl_voxelize(&dev, &h, 32, &a, &e) == 0);
    CHECK_CL_RAN(k0);
    CHECK(sl_voxelize(&c, &h, 32, &b, &e) == 0);
    double wr, wd;
    compare_grids(&a, &b, &wr, &wd);
    /* Sums are exact fixed point in both; the pieces may differ by the device's float sqrt and
     * division (a few ulp): 1e-5 relative on density/sigma, 1e-4 on dev and on the axis cosine. */
    if (getenv("SL_TEST_VERBOSE"))
        fprintf(stderr, "  voxel kernel vs C (procedural): rel %g dir/dev %g\n", wr, wd);
    CHECK_MSG(wr <= 1e-5 && wd <= 1e-4, "procedural: rel %g dir/dev %g", wr, wd);
    sl_voxel_grid_free(&a);
    sl_voxel_grid_free(&b);
    /* Extremes: the slab along an axis, all hair in one voxel, an empty grid. */
    size_t ns;
    float *segs = slab_x(&ns);
    for (int t = 0; t < 3; t++) {
        int n = t == 1 ? 1 : 8;
        set_grid(&a, n, t == 1 ? 4.0f : 0.25f);
        set_grid(&b, n, t == 1 ? 4.0f : 0.25f);
        size_t nn = t == 2 ? 0 : ns;
        CHECK(sl_voxelize_segments(&dev, segs, nn, &a, &e) == 0);
        CHECK(sl_voxelize_segments(&c, segs, nn, &b, &e) == 0);
        compare_grids(&a, &b, &wr, &wd);
        CHECK_MSG(wr <= 1e-5 && wd <= 1e-4, "case %d: rel %g dir/dev %g", t, wr, wd);
        sl_voxel_grid_free(&a);
        sl_voxel_grid_free(&b);
    }
    free(segs);
    sl_hair_free(&h);
    sl_device_close(&dev);
    sl_device_close(&c);
}
