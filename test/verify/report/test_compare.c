/* test_compare.c: host/verify/report/compare.c on synthetic images whose answer is known: a
 * constant reference and ours = 1.1 x it (ratio 1.1, rel. RMSE 0.1 on pixels and blocks); two
 * reference seeds with Gaussian noise of known variance and a biased, itself noisy image of ours
 * (the corrected block RMSE recovers the bias, the raw one does not); the "first half" form of
 * our second image; masks, sizes and errors; and the EXR reader of io/image (channels R G B A
 * read back from sl_exr_write, an image without A refused). */
#include "io/image/image_read.h"
#include "io/image/image_write.h"
#include "verify/report/compare.h"
#include "test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static sl_image make_image(int w, int h) {
    sl_image im = {w, h, calloc(4 * (size_t)w * h, sizeof(float))};
    return im;
}

/* Deterministic standard normal deviates (splitmix64 + Box-Muller): reproducible tolerances. */
typedef struct rng {
    uint64_t s;
} rng;
static double uniform(rng *r) {
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return ((double)(z >> 11) + 0.5) / 9007199254740992.0;
}
static double normal(rng *r) {
    double u = uniform(r), v = uniform(r);
    return sqrt(-2 * log(u)) * cos(2 * M_PI * v);
}

/* The noise-free truth: a smooth colour ramp (never 0), alpha 1. */
static void truth(int x, int y, double t[3]) {
    t[0] = 0.2 + 0.3 * x / 512.0;
    t[1] = 0.1 + 0.2 * y / 512.0;
    t[2] = 0.05 + 0.1 * (x + y) / 1024.0;
}

/* im = scale x truth x (1 + rel_sigma N(0,1)) per pixel and channel, alpha 1. */
static void fill(sl_image *im, double scale, double rel_sigma, uint64_t seed) {
    rng r = {seed};
    for (int y = 0; y < im->height; y++)
        for (int x = 0; x < im->width; x++) {
            double t[3];
            truth(x, y, t);
            float *p = im->rgba + 4 * ((size_t)y * im->width + x);
            for (int c = 0; c < 3; c++)
                p[c] = (float)(scale * t[c] * (1 + rel_sigma * normal(&r)));
            p[3] = 1;
        }
}

static sl_compare_in input(const sl_image *x, const sl_image *a, const sl_image *b, int k) {
    sl_compare_in in = {.ours = x,
                        .ref_a = a,
                        .ref_b = b,
                        .block = k,
                        .names = {"ours.exr", "ours2.exr", "a.exr", "b.exr"}};
    return in;
}

TEST(compare_constant_ratio) {
    sl_image a = make_image(40, 24), x = make_image(40, 24);
    for (size_t i = 0; i < 40 * 24; i++) {
        for (int c = 0; c < 3; c++) {
            a.rgba[4 * i + c] = 0.5f * (float)(c + 1);
            x.rgba[4 * i + c] = 1.1f * a.rgba[4 * i + c];
        }
        a.rgba[4 * i + 3] = x.rgba[4 * i + 3] = 1;
    }
    sl_compare_in in = input(&x, &a, NULL, 8);
    sl_compare_result r;
    sl_err e;
    CHECK(sl_compare(&in, &r, &e) == 0);
    for (int c = 0; c < 3; c++) {
        CHECK_REL(r.ratio[c], 1.1, 1e-6);
        CHECK_REL(r.mean_a[c], 0.5 * (c + 1), 1e-6);
    }
    for (int c = 0; c < 4; c++) {
        CHECK_REL(r.px.raw[c], 0.1, 1e-5);
        CHECK_REL(r.blk.raw[c], 0.1, 1e-5);
        CHECK_NEAR(r.blk.ref_noise[c], 0, 0); /* one reference: no noise estimate */
    }
    CHECK(r.px.count == 40 * 24);
    CHECK(r.blk.count == 5 * 3);
    CHECK(isnan(r.ab_blocks[0]));
    free(a.rgba);
    free(x.rgba);
}

/* Two seeds of a reference with 30 % per-pixel noise each; ours 5 % brighter with 20 % noise and
 * an independent second image. Per 8 x 8 block the reference mean has 0.3 / sqrt(2) / 8 = 2.7 %
 * noise, ours 1.8 %: the raw block RMSE is sqrt(5^2 + 2.7^2 + 1.8^2) % = 5.9 %, the corrected one
 * must come back to 5 %. Over 4096 blocks the corrected figure has a standard deviation of
 * about 0.0006 (the spread of the squared differences and of the variance estimates), so the
 * tolerances below are about 4 sigma (the seeds are fixed anyway). */
TEST(compare_noise_corrected_blocks) {
    int w = 512, h = 512;
    sl_image a = make_image(w, h), b = make_image(w, h), x = make_image(w, h),
             x2 = make_image(w, h);
    fill(&a, 1.0, 0.3, 1);
    fill(&b, 1.0, 0.3, 2);
    fill(&x, 1.05, 0.2, 3);
    fill(&x2, 1.05, 0.2, 4);
    sl_compare_in in = input(&x, &a, &b, 8);
    in.ours2 = &x2;
    in.ours2_mode = SL_OURS_INDEPENDENT;
    sl_compare_result r;
    sl_err e;
    CHECK(sl_compare(&in, &r, &e) == 0);
    for (int c = 0; c < 4; c++) {
        CHECK_NEAR(r.blk.corrected[c], 0.05, 0.0025);
        CHECK(r.blk.raw[c] > 0.056);
        CHECK_NEAR(r.blk.ref_noise[c], 0.3 / sqrt(2) / 8, 0.0015);
        CHECK_NEAR(r.blk.ours_noise[c], 0.2 / sqrt(2) / 8 * 1.05, 0.0015);
        CHECK_NEAR(r.ab_blocks[c], 0.3 * sqrt(2) / 8, 0.002);
        /* per pixel the noise dominates (0.25 of 0.26): corrected to about +-0.0025 (1 sigma) */
        CHECK_NEAR(r.px.corrected[c], 0.05, 0.012);
        CHECK(r.px.raw[c] > 0.2);
    }
    for (int c = 0; c < 3; c++)
        CHECK_NEAR(r.ratio[c], 1.05, 0.003);
    /* without the noise estimates the same images give the raw figure only */
    sl_compare_in raw = input(&x, &a, NULL, 8);
    sl_compare_result r1;
    CHECK(sl_compare(&raw, &r1, &e) == 0);
    CHECK(r1.blk.corrected[3] == r1.blk.raw[3]);
    free(a.rgba);
    free(b.rgba);
    free(x.rgba);
    free(x2.rgba);
}

/* SL_OURS_HALF: X2 is the first half of X's samples, X = (H1 + H2) / 2. */
TEST(compare_ours_half) {
    int w = 512, h = 512;
    sl_image a = make_image(w, h), b = make_image(w, h), h1 = make_image(w, h),
             h2 = make_image(w, h), x = make_image(w, h);
    fill(&a, 1.0, 0.1, 11);
    fill(&b, 1.0, 0.1, 12);
    fill(&h1, 0.95, 0.4, 13);
    fill(&h2, 0.95, 0.4, 14);
    for (size_t i = 0; i < 4 * (size_t)w * h; i++)
        x.rgba[i] = 0.5f * (h1.rgba[i] + h2.rgba[i]);
    sl_compare_in in = input(&x, &a, &b, 8);
    in.ours2 = &h1;
    in.ours2_mode = SL_OURS_HALF;
    sl_compare_result r;
    sl_err e;
    CHECK(sl_compare(&in, &r, &e) == 0);
    for (int c = 0; c < 4; c++) {
        CHECK_NEAR(r.blk.corrected[c], 0.05, 0.003);
        CHECK_NEAR(r.blk.ours_noise[c], 0.4 / sqrt(2) / 8 * 0.95, 0.003);
    }
    for (int c = 0; c < 3; c++)
        CHECK_REL(r.mean_x[c], r.mean_ours[c], 1e-12); /* ours stays X */
    free(a.rgba);
    free(b.rgba);
    free(h1.rgba);
    free(h2.rgba);
    free(x.rgba);
}

/* Only hair counts: pixels with alpha > 0 in any image, blocks holding one. */
TEST(compare_mask_and_errors) {
    sl_image a = make_image(16, 16), x = make_image(16, 16), small = make_image(8, 16);
    /* hair: pixel (1, 1) in ours only, pixel (12, 12) in the reference only */
    float *p = x.rgba + 4 * (1 * 16 + 1);
    p[0] = p[1] = p[2] = 0.5f, p[3] = 1;
    p = a.rgba + 4 * (12 * 16 + 12);
    p[0] = p[1] = p[2] = 0.25f, p[3] = 0.5f;
    sl_compare_in in = input(&x, &a, NULL, 8);
    sl_compare_result r;
    sl_err e;
    CHECK(sl_compare(&in, &r, &e) == 0);
    CHECK(r.px.count == 2);
    CHECK(r.blk.count == 2);
    CHECK_REL(r.mean_ours[0], 0.25, 1e-9);
    CHECK_REL(r.mean_a[0], 0.125, 1e-9);
    /* sizes differ: names both files */
    sl_compare_in bad = input(&x, &small, NULL, 8);
    CHECK(sl_compare(&bad, &r, &e) == -1);
    CHECK(strstr(e.msg, "a.exr is 8 x 16") && strstr(e.msg, "ours.exr is 16 x 16"));
    /* no hair anywhere */
    memset(x.rgba, 0, 4 * 16 * 16 * sizeof(float));
    memset(a.rgba, 0, 4 * 16 * 16 * sizeof(float));
    CHECK(sl_compare(&in, &r, &e) == -1);
    CHECK(strstr(e.msg, "no hair pixel") != NULL);
    free(a.rgba);
    free(x.rgba);
    free(small.rgba);
}

TEST(image_read_exr_rgba) {
    int w = 5, h = 3;
    float pl[4][15];
    for (int c = 0; c < 4; c++)
        for (int i = 0; i < w * h; i++)
            pl[c][i] = (float)(c + 1) * 0.125f + (float)i;
    sl_exr_channel ch[4] = {{"R", pl[0]}, {"G", pl[1]}, {"B", pl[2]}, {"A", pl[3]}};
    char path[4096], noa[4096];
    snprintf(path, sizeof path, "%s/compare_rgba.exr", sl_test_tmpdir());
    snprintf(noa, sizeof noa, "%s/compare_rgb.exr", sl_test_tmpdir());
    sl_err e;
    CHECK(sl_exr_write(path, w, h, ch, 4, 1, &e) == 0);
    CHECK(sl_exr_write(noa, w, h, ch, 3, 0, &e) == 0);
    sl_image im;
    CHECK(sl_image_read_exr(path, &im, &e) == 0);
    CHECK(im.width == w && im.height == h);
    int same = 1;
    for (int i = 0; im.rgba && i < w * h; i++)
        for (int c = 0; c < 4; c++)
            if (im.rgba[4 * i + c] != pl[c][i]) same = 0;
    CHECK(same);
    sl_image_free(&im);
    CHECK(sl_image_read_exr(noa, &im, &e) == -1);
    CHECK_MSG(strstr(e.msg, "compare_rgb.exr") && strstr(e.msg, "R, G, B and A"), "%s", e.msg);
    CHECK(im.rgba == NULL);
    CHECK(sl_image_read_exr("/nonexistent/x.exr", &im, &e) == -1);
    CHECK(strstr(e.msg, "/nonexistent/x.exr") != NULL);
}
