/* test_prefix_sum.c: the inclusive 2-D prefix sum (summed-area table): the C twin
 * (cpu/prefix_sum.c) against an independent double-precision computation, and the OpenCL kernels
 * (kernels/prefix_sum.cl via host/passes/light/prefix_sum_cl.c) against the C twin, bit for bit.
 *
 * Tolerance against double. Every output is a float sum of the input terms of its rectangle
 * computed by a tree in which each term passes through at most D additions, so
 * |S_float - S| <= gamma_D * sum|a| (Higham, Accuracy and Stability, Sec. 4.2), gamma_D =
 * D u / (1 - D u), u = 2^-24. Per dimension of length n the scan has L(n) levels (256-element
 * tiles, tile totals scanned recursively); a term passes <= 2 log2(256) = 16 additions in its
 * tile's up/down-sweep plus <= 1 offset addition per level, and <= 8 + 1 more per extra level,
 * so D1(n) <= 17 L(n) and D = D1(w) + D1(h). The double reference (row sums then column sums,
 * sequential) adds its own error <= (w + h) 2^-53 sum|a|, added to the tolerance. */
#include "test.h"

#include "cl_fixture.h"

#include "../cpu/prefix_sum.h"
#include "../kernels/prefix_sum.h"
#include "cl/clrt.h"
#include "base/common.h"
#include "passes/light/prefix_sum_cl.h"

#include <float.h>
#include <stdlib.h>
#include <string.h>

enum { RAND01, MIXED, ZEROS, HUGE_VALS, TINY_VALS, CANCEL, SPIKE, INTS, OVERFLOW };

typedef struct ps_case {
    size_t w, h;
    int kind;
} ps_case;

/* Typical sizes: square, odd, 1-wide, 1-high, not multiples of the 256 tile, three levels. */
static const ps_case typical[] = {
    {257, 129, RAND01}, {512, 512, RAND01}, {1, 1, RAND01},    {1, 1000, RAND01},
    {1000, 1, RAND01},  {255, 257, MIXED},  {70000, 1, MIXED}, {1, 70000, RAND01},
    {513, 3, MIXED},    {257, 129, MIXED},  {256, 256, MIXED},
};
/* Extreme inputs. */
static const ps_case extreme[] = {
    {257, 129, ZEROS},    {300, 200, INTS},   {257, 129, SPIKE},     {257, 129, HUGE_VALS},
    {64, 300, TINY_VALS}, {257, 129, CANCEL}, {1, 70000, INTS},      {8, 8, OVERFLOW},
    {1, 1, SPIKE},        {3000, 2, CANCEL},  {129, 257, TINY_VALS},
};

static double urand(unsigned long long *s) {
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return (double)((*s * 2685821657736338717ull) >> 11) * 0x1.0p-53;
}

static float *make_input(const ps_case *c, unsigned long long seed) {
    size_t n = c->w * c->h;
    float *a = sl_malloc(n * sizeof *a);
    unsigned long long s = seed * 0x9e3779b97f4a7c15ull + 12345;
    for (size_t i = 0; i < n; i++) {
        double u = urand(&s);
        switch (c->kind) {
        case RAND01:
            a[i] = (float)u;
            break;
        case MIXED:
            a[i] = (float)(2 * u - 1);
            break;
        case ZEROS:
            a[i] = 0.0f;
            break;
        case HUGE_VALS:
            a[i] = (float)(1e30 * (0.5 + 0.5 * u));
            break; /* sums stay < FLT_MAX */
        case TINY_VALS:
            a[i] = (float)(1e-30 * (0.5 + 0.5 * u));
            break;
        /* Large terms of both signs that mostly cancel, plus small ones lost beside them. */
        case CANCEL:
            a[i] = (i % 7 == 3) ? (float)u : (float)((i & 1 ? 1e20 : -1e20) * (1 + u));
            break;
        case SPIKE:
            a[i] = 0.0f;
            break;
        case INTS:
            a[i] = (float)(int)(10 * u);
            break; /* 0..9 */
        case OVERFLOW:
            a[i] = 3e38f;
            break;
        }
    }
    if (c->kind == SPIKE) a[(c->h / 3) * c->w + c->w / 2] = 1.0f;
    return a;
}

/* Independent reference: sequential row sums then column sums in double, of a and of |a|. */
static void reference(const float *a, size_t w, size_t h, double *s, double *abs_s) {
    for (size_t y = 0; y < h; y++) {
        double r = 0, ra = 0;
        for (size_t x = 0; x < w; x++) {
            r += a[y * w + x];
            ra += fabs((double)a[y * w + x]);
            s[y * w + x] = r + (y ? s[(y - 1) * w + x] : 0);
            abs_s[y * w + x] = ra + (y ? abs_s[(y - 1) * w + x] : 0);
        }
    }
}

static int levels(size_t n) {
    int l = 1;
    while (n > SL_SCAN_TILE)
        n = (n + SL_SCAN_TILE - 1) / SL_SCAN_TILE, l++;
    return l;
}

/* gamma_D for the 2-D scan of a w x h image (see the top of this file). */
static double gamma_wh(size_t w, size_t h) {
    double d = 17.0 * (levels(w) + levels(h)), u = 0x1p-24;
    return d * u / (1 - d * u);
}

/* Checks out against the double reference within the derived bound; returns max |err|/bound. */
static double check_vs_double(const char *what, const ps_case *c, const float *a,
                              const float *out) {
    size_t n = c->w * c->h;
    double *s = sl_malloc(n * sizeof *s), *abs_s = sl_malloc(n * sizeof *abs_s);
    reference(a, c->w, c->h, s, abs_s);
    double g = gamma_wh(c->w, c->h), ref_err = (double)(c->w + c->h) * 0x1p-53, worst = 0;
    int reported = 0;
    for (size_t i = 0; i < n; i++) {
        double tol = (g + ref_err) * abs_s[i];
        double err = fabs((double)out[i] - s[i]);
        if (tol > 0 && err / tol > worst) worst = err / tol;
        if (!(err <= tol) && reported++ < 3)
            sl_test_fail(__FILE__, __LINE__,
                         "%s %zux%zu kind %d: at %zu got %.9g want %.17g, "
                         "|err| %.3g > bound %.3g",
                         what, c->w, c->h, c->kind, i, out[i], s[i], err, tol);
    }
    free(s);
    free(abs_s);
    return worst;
}

/* ---------------------------------------------------------------- C twin */

TEST(ps_c_typical_vs_double) {
    for (size_t k = 0; k < sizeof typical / sizeof typical[0]; k++) {
        const ps_case *c = &typical[k];
        float *a = make_input(c, k + 1), *out = sl_malloc(c->w * c->h * sizeof *out);
        slc_prefix_sum_2d(a, out, c->w, c->h);
        check_vs_double("C twin", c, a, out);
        free(a);
        free(out);
    }
}

TEST(ps_c_extreme_vs_double) {
    for (size_t k = 0; k < sizeof extreme / sizeof extreme[0]; k++) {
        const ps_case *c = &extreme[k];
        if (c->kind == OVERFLOW) continue; /* separate test */
        float *a = make_input(c, k + 100), *out = sl_malloc(c->w * c->h * sizeof *out);
        slc_prefix_sum_2d(a, out, c->w, c->h);
        check_vs_double("C twin", c, a, out);
        free(a);
        free(out);
    }
}

/* Small integers: every partial sum is an integer below 2^24, so float sums are exact in any
 * order and must equal the double reference exactly (catches indexing errors that a tolerance
 * could hide). */
TEST(ps_c_exact_cases) {
    const ps_case cases[] = {{300, 200, INTS},  {1, 70000, INTS},  {70000, 1, INTS},
                             {257, 129, SPIKE}, {257, 129, ZEROS}, {1, 1, SPIKE}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const ps_case *c = &cases[k];
        size_t n = c->w * c->h;
        float *a = make_input(c, k + 7), *out = sl_malloc(n * sizeof *out);
        double *s = sl_malloc(n * sizeof *s), *abs_s = sl_malloc(n * sizeof *abs_s);
        slc_prefix_sum_2d(a, out, c->w, c->h);
        reference(a, c->w, c->h, s, abs_s);
        size_t bad = 0;
        for (size_t i = 0; i < n; i++)
            bad += (double)out[i] != s[i];
        CHECK_MSG(bad == 0, "%zux%zu kind %d: %zu of %zu outputs not exact", c->w, c->h, c->kind,
                  bad, n);
        free(a);
        free(out);
        free(s);
        free(abs_s);
    }
    /* The spike's SAT is the indicator of x >= x0 && y >= y0 (written out, not from the code). */
    float a[5 * 4] = {0}, out[5 * 4];
    a[1 * 5 + 2] = 1.0f;
    slc_prefix_sum_2d(a, out, 5, 4);
    for (int y = 0; y < 4; y++)
        for (int x = 0; x < 5; x++)
            CHECK_NEAR(out[y * 5 + x], (x >= 2 && y >= 1) ? 1.0 : 0.0, 0);
}

TEST(ps_c_overflow_and_in_place) {
    /* 8x8 of 3e38: the first output is finite, sums of two or more overflow to +inf (as IEEE
     * float addition does; the kernel must agree, see ps_cl_matches_c_twin). */
    const ps_case c = {8, 8, OVERFLOW};
    float *a = make_input(&c, 1), out[64];
    slc_prefix_sum_2d(a, out, 8, 8);
    CHECK(out[0] == 3e38f);
    CHECK(isinf(out[1]) && out[1] > 0);
    CHECK(isinf(out[63]) && out[63] > 0);
    free(a);
    /* in == out gives the same as separate buffers. */
    const ps_case r = {300, 70, MIXED};
    float *x = make_input(&r, 3), *y = sl_malloc(300 * 70 * sizeof *y);
    slc_prefix_sum_2d(x, y, 300, 70);
    slc_prefix_sum_2d(x, x, 300, 70);
    CHECK(memcmp(x, y, 300 * 70 * sizeof *y) == 0);
    free(x);
    free(y);
}

TEST(ps_c_bound_is_sharp_enough) {
    /* The tolerance must be able to fail: for the largest typical case (512x512, two levels per
     * dimension, D = 68) it is 68 u ~ 4.1e-6 of sum|a|, i.e. ~68 float rounding errors, far below
     * any summation mistake such as a term dropped or counted twice in a 257x129 image (the bound
     * there is 51 u * sum|a| ~ 0.05 while the terms average 0.5). Indexing mistakes are
     * also caught exactly by ps_c_exact_cases. */
    double g = gamma_wh(512, 512) + (512 + 512) * 0x1p-53;
    CHECK(g < 4.2e-6);
    CHECK(gamma_wh(257, 129) * 0.5 * 257 * 129 < 0.06);
}

TEST(ps_sat_box_sum) {
    const ps_case c = {37, 23, INTS};
    float *a = make_input(&c, 5), *sat = sl_malloc(37 * 23 * sizeof *sat);
    slc_prefix_sum_2d(a, sat, 37, 23);
    const sl_uint boxes[][4] = {{0, 0, 36, 22},   {0, 0, 0, 0},  {5, 3, 17, 9},
                                {36, 22, 36, 22}, {0, 7, 12, 7}, {9, 0, 9, 22}};
    for (size_t k = 0; k < sizeof boxes / sizeof boxes[0]; k++) {
        double want = 0;
        for (sl_uint y = boxes[k][1]; y <= boxes[k][3]; y++)
            for (sl_uint x = boxes[k][0]; x <= boxes[k][2]; x++)
                want += a[y * 37 + x];
        /* Integers below 2^24: exact. */
        CHECK_NEAR(sl_sat_box_sum(sat, 37, boxes[k][0], boxes[k][1], boxes[k][2], boxes[k][3]),
                   want, 0);
    }
    free(a);
    free(sat);
}

/* ---------------------------------------------------------------- OpenCL */

/* Kernel vs C twin: same additions in the same order, IEEE single precision without
 * contraction (additions only), so tolerance 0: the bits must match. Covers every case above. */
TEST(ps_cl_matches_c_twin) {
    sl_device dev;
    sl_err e = {{0}};
    SL_TEST_OPEN_CL(&dev, &e);
    unsigned long k0 = sl_cl_kernels_enqueued();
    const ps_case *sets[2] = {typical, extreme};
    size_t counts[2] = {sizeof typical / sizeof typical[0], sizeof extreme / sizeof extreme[0]};
    for (int set = 0; set < 2; set++)
        for (size_t k = 0; k < counts[set]; k++) {
            const ps_case *c = &sets[set][k];
            size_t n = c->w * c->h;
            float *a = make_input(c, k + 1 + 100 * (size_t)set);
            float *want = sl_malloc(n * sizeof *want), *got = sl_malloc(n * sizeof *got);
            slc_prefix_sum_2d(a, want, c->w, c->h);
            /* Alternate the two kernel variants (both must match): even cases run the
             * work-group scan, odd ones the serial one; the big 1-D cases run serially, the
             * work-group variant launching 70000 work-groups is slow on PoCL. */
            sl_ps_variant v = (k % 2 == 0 && n < 65536) ? SL_PS_WORKGROUP : SL_PS_SERIAL;
            int rc = slcl_prefix_sum_2d_variant(dev.cl, a, got, c->w, c->h, v, NULL, &e);
            CHECK_MSG(rc == 0, "%s", e.msg);
            size_t bad = 0, first = 0;
            for (size_t i = 0; i < n && rc == 0; i++)
                if (memcmp(&got[i], &want[i], sizeof(float)) != 0 && bad++ == 0) first = i;
            CHECK_MSG(bad == 0,
                      "variant %d %zux%zu kind %d: %zu of %zu differ, first at %zu: %.9g vs %.9g",
                      (int)v, c->w, c->h, c->kind, bad, n, first, got[first], want[first]);
            /* And the kernel against double directly (implied, but independent of the twin). */
            if (rc == 0 && c->kind != OVERFLOW) check_vs_double("OpenCL", c, a, got);
            free(a);
            free(want);
            free(got);
        }
    CHECK_CL_RAN(k0);
    sl_device_close(&dev);
}

/* The device-buffer entry point with separate buffers, and size errors. */
TEST(ps_cl_buffers_and_errors) {
    sl_device dev;
    sl_err e = {{0}};
    SL_TEST_OPEN_CL(&dev, &e);
    const ps_case c = {333, 77, INTS};
    size_t n = c.w * c.h;
    float *a = make_input(&c, 9), *want = sl_malloc(n * sizeof *want),
          *got = sl_malloc(n * sizeof *got);
    slc_prefix_sum_2d(a, want, c.w, c.h);
    cl_int err;
    cl_mem in = clCreateBuffer(sl_cl_context(dev.cl), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                               n * sizeof(float), a, &err);
    CHECK(err == CL_SUCCESS);
    cl_mem out =
        clCreateBuffer(sl_cl_context(dev.cl), CL_MEM_WRITE_ONLY, n * sizeof(float), NULL, &err);
    CHECK(err == CL_SUCCESS);
    CHECK(slcl_prefix_sum_2d_buf(dev.cl, in, out, c.w, c.h, NULL, &e) == 0);
    /* Both variants on one more odd size, explicitly (the case table alternates them). */
    for (int v = SL_PS_WORKGROUP; v <= SL_PS_SERIAL; v++) {
        memset(got, 0, n * sizeof(float));
        CHECK(slcl_prefix_sum_2d_variant(dev.cl, a, got, c.w, c.h, (sl_ps_variant)v, NULL, &e) ==
              0);
        CHECK_MSG(memcmp(got, want, n * sizeof(float)) == 0, "variant %d", v);
    }
    CHECK(clEnqueueReadBuffer(sl_cl_queue(dev.cl), out, CL_TRUE, 0, n * sizeof(float), got, 0, NULL,
                              NULL) == CL_SUCCESS);
    CHECK(memcmp(got, want, n * sizeof(float)) == 0);
    clReleaseMemObject(in);
    clReleaseMemObject(out);
    CHECK(slcl_prefix_sum_2d(dev.cl, a, got, 0, 5, NULL, &e) == -1);
    CHECK(strstr(e.msg, "size") != NULL);
    CHECK(sl_prefix_sum_2d(&dev, a, got, 5, 0, &e) == -1);
    free(a);
    free(want);
    free(got);
    sl_device_close(&dev);
}
