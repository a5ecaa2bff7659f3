/* test_path.c: the path tracer on whole scenes (host/verify/reference/reference_path.h over
 * cpu/reference/path_ref.h), each written here as a scene JSON with procedural hair and a tiny
 * map: the white furnace (constant radiance 1, sigma_a 0: every hair pixel is 1), its first
 * bounce against the pixel-mode reference lit by the same few bright pixels, the same image for
 * any thread count, the time budget, cancellation, and the record (EXR + JSON, cache, readable
 * by sl_reference_load). Tolerances and their reasons: docs/validation.md "White furnace" and
 * docs/reference.md "Path tracer". */
#include "test.h"

#include "verify/reference/reference.h"
#include "verify/reference/reference_path.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int write_text(const char *path, const char *text) {
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    int ok = fputs(text, f) >= 0;
    return fclose(f) == 0 && ok ? 0 : -1;
}

/* A flat (not run-length encoded) Radiance map: RGBE per pixel, row 0 at the top. */
static int write_hdr(const char *path, int w, int h, const float *rgb) {
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    fprintf(f, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n", h, w);
    for (int i = 0; i < w * h; i++) {
        const float *p = rgb + 3 * i;
        float m = fmaxf(p[0], fmaxf(p[1], p[2]));
        unsigned char q[4] = {0, 0, 0, 0};
        if (m > 1e-32f) {
            int e;
            frexpf(m, &e);
            float s = ldexpf(256.0f, -e);
            q[0] = (unsigned char)(p[0] * s), q[1] = (unsigned char)(p[1] * s);
            q[2] = (unsigned char)(p[2] * s), q[3] = (unsigned char)(e + 128);
        }
        fwrite(q, 1, 4, f);
    }
    return fclose(f);
}

/* dir/name.json with the given hair, material and camera over dir/map.hdr; loads it into s. */
static int scene_in(const char *dir, const char *name, const char *hair, const char *mat,
                    const char *camera_image, sl_scene *s) {
    char path[1200], text[2048];
    snprintf(path, sizeof path, "%s/%s.json", dir, name);
    snprintf(text, sizeof text,
             "{\"hair\": %s, \"material\": %s, \"environment\": {\"file\": \"map.hdr\"}, %s}\n",
             hair, mat, camera_image);
    sl_err e;
    if (write_text(path, text) || sl_scene_load(path, s, &e)) {
        CHECK_MSG(0, "scene %s: %s", name, e.msg);
        return -1;
    }
    return 0;
}

static const char *WHITE_CHIANG = "{\"model\": \"chiang\", \"melanin\": 0, \"tint\": [1, 1, 1]}";
/* d'Eon is white when sigma_a = 0 and every order shares one lobe (docs/numerics-deon.md) */
static const char *WHITE_DEON = "{\"model\": \"deon\", \"sigma_a\": 0, \"alpha_R_deg\": 0, "
                                "\"beta_R_deg\": 10, \"beta_TT_deg\": 10, \"beta_TRT_deg\": 10}";
/* dense: 600 wavy strands of radius 0.2 seen from behind the head, every pixel covered, ~8
 * scattering events per path (~12 while a ray leaving an overlapping fiber was a hit); sparse:
 * 30 straight strands, ~2 events per path */
static const char *DENSE =
    "{\"procedural\": {\"style\": \"wavy\", \"strands\": 600, \"points\": 8, \"seed\": 3}, "
    "\"radius\": 0.2}";
static const char *DENSE_VIEW = "\"camera\": {\"eye\": [0, 0, -60], \"target\": [0, -2, 0], "
                                "\"fov_deg\": 10}, \"image\": {\"width\": 12, \"height\": 12}";
static const char *SPARSE =
    "{\"procedural\": {\"style\": \"straight\", \"strands\": 30, \"points\": 6, \"seed\": 3}, "
    "\"radius\": 0.5}";
static const char *SPARSE_VIEW = "\"camera\": {\"eye\": [0, 0, -60], \"target\": [0, -2, 0], "
                                 "\"fov_deg\": 20}, \"image\": {\"width\": 16, \"height\": 16}";

static void white_map(const char *dir) {
    char path[1200];
    float rgb[8 * 4 * 3];
    for (int i = 0; i < 8 * 4 * 3; i++)
        rgb[i] = 1.0f; /* RGBE (128, 128, 128, 129): exactly 1 */
    snprintf(path, sizeof path, "%s/map.hdr", dir);
    CHECK(write_hdr(path, 8, 4, rgb) == 0);
}

/* sum(rgb) / sum(alpha) of a furnace render, per channel, and the render's figures. */
static void furnace(const char *dir, const char *name, const char *mat, const char *hair,
                    const char *view, int spp, double ratio[3], sl_path_result *r) {
    sl_scene *s = malloc(sizeof *s);
    ratio[0] = ratio[1] = ratio[2] = NAN;
    if (scene_in(dir, name, hair, mat, view, s)) {
        free(s);
        return;
    }
    sl_path_settings set;
    sl_path_settings_default(&set);
    set.spp = spp, set.threads = 2, set.progress = 0;
    sl_path_frame f;
    sl_err e;
    if (sl_path_render(s, &set, &f, r, &e)) {
        CHECK_MSG(0, "%s: %s", name, e.msg);
        free(s);
        return;
    }
    double sum[4] = {0, 0, 0, 0};
    for (int i = 0; i < f.width * f.height; i++)
        for (int c = 0; c < 4; c++)
            sum[c] += f.rgba[4 * i + c];
    for (int c = 0; c < 3; c++)
        ratio[c] = sum[c] / sum[3];
    sl_path_frame_free(&f);
    free(s);
}

/* The tolerance, 1 %, is the issue's; the samples are chosen so that the ratio's noise (about
 * 0.3 % dense, 0.25 % sparse: docs/validation.md) is a third of it or less. Grey fibers: the three
 * channels are one. */
static void check_furnace(const char *mat, const char *tag, int spp_dense, int spp_sparse) {
    char dir[1024];
    sl_test_fresh_dir(tag, dir, sizeof dir);
    if (!dir[0]) SKIP("no temporary directory");
    white_map(dir);
    double rd[3], rs[3];
    sl_path_result r;
    furnace(dir, "dense", mat, DENSE, DENSE_VIEW, spp_dense, rd, &r);
    CHECK_MSG(fabs(rd[0] - 1) < 0.01, "%s dense: sum(rgb)/sum(alpha) = %.5f", tag, rd[0]);
    CHECK_MSG(r.events_per_path > 6 && r.capped == 0, "%s dense: %.1f events per path, %lld cut",
              tag, r.events_per_path, r.capped);
    if (getenv("SL_TEST_VERBOSE"))
        fprintf(stderr, "%s dense: %.5f (%d spp, %.1f events/path, %.2f s)\n", tag, rd[0], r.spp,
                r.events_per_path, r.wall_s);
    furnace(dir, "sparse", mat, SPARSE, SPARSE_VIEW, spp_sparse, rs, &r);
    CHECK_MSG(fabs(rs[0] - 1) < 0.01, "%s sparse: sum(rgb)/sum(alpha) = %.5f", tag, rs[0]);
    if (getenv("SL_TEST_VERBOSE"))
        fprintf(stderr, "%s sparse: %.5f (%d spp, %.1f events/path, %.2f s)\n", tag, rs[0], r.spp,
                r.events_per_path, r.wall_s);
    CHECK(rd[0] == rd[1] && rd[1] == rd[2]);
}

TEST(path_white_furnace_chiang) {
    check_furnace(WHITE_CHIANG, "path_furnace_chiang", 64, 256);
}

TEST(path_white_furnace_deon) {
    check_furnace(WHITE_DEON, "path_furnace_deon", 64, 256);
}

/* The first bounce against the pixel-mode reference (reference.h: N directional lights cut from
 * the map by median cut, single scattering, shadow rays through the fibers). Both must see the
 * same light: a black 256 x 128 map with one bright pixel, which the cut turns into one light
 * at that pixel's centre carrying its power; the path tracer sees the pixel's 1.4 degree cell,
 * which differs from the point by ~(0.7 / 20)^2 / 6 = 2e-4 against the narrowest lobe here.
 * The hair is straight, sparse and thin (fibers 0.1 px wide), because the path tracer shades
 * each hit at its own offset h while the reference uses f averaged over the width: the two
 * agree where every fiber's whole width is seen (not where a neighbour or the frame's edge
 * hides part of it; fibers 0.8 px wide put a strand's two sides in two pixels and move light
 * between them by up to 5x, docs/reference.md). Tolerances (docs/reference.md "Path tracer"):
 * the image sums within 2.5 % and the 4 x 4-block rel. RMSE within 3 x the path image's own
 * 4 x 4 noise + 0.02: over seeds the sums differ by 0.6-1.0 % and the block error is ~1.5x the
 * noise (the reference has noise of its own). */
static void direct_matches_reference(const char *tag, const char *mat) {
    char dir[1024], path[1200];
    sl_test_fresh_dir(tag, dir, sizeof dir);
    if (!dir[0]) SKIP("no temporary directory");
    enum { MW = 256, MH = 128 };
    float *map = calloc(MW * MH * 3, sizeof(float));
    for (int c = 0; c < 3; c++)
        map[3 * (40 * MW + 100) + c] = 800;
    snprintf(path, sizeof path, "%s/map.hdr", dir);
    CHECK(write_hdr(path, MW, MH, map) == 0);
    free(map);
    sl_scene *s = malloc(sizeof *s);
    const char *hair = "{\"procedural\": {\"style\": \"straight\", \"strands\": 30, \"points\": "
                       "8, \"seed\": 5}, \"radius\": 0.1}";
    const char *view = "\"camera\": {\"eye\": [0, 0, -60], \"target\": [0, -2, 0], \"fov_deg\": "
                       "24}, \"image\": {\"width\": 24, \"height\": 24}";
    if (scene_in(dir, "direct", hair, mat, view, s)) {
        free(s);
        return;
    }
    sl_path_settings ps;
    sl_path_settings_default(&ps);
    ps.spp = 512, ps.threads = 2, ps.progress = 0;
    sl_path_frame pf;
    sl_path_result pr;
    sl_err e;
    CHECK(sl_path_render(s, &ps, &pf, &pr, &e) == 0);
    sl_reference_settings rs;
    sl_reference_settings_default(&rs);
    rs.lights = 8, rs.aa = 6, rs.light_split = 0, rs.ms = 0, rs.threads = 2, rs.progress = 0;
    sl_reference_frame rf;
    CHECK(sl_reference_render(s, &rs, &rf, &e) == 0);
    if (pf.rgba && rf.rgba) {
        int n = pf.width * pf.height;
        float *d = malloc(4 * n * sizeof(float));
        double sp = 0, sr = 0;
        for (int i = 0; i < n; i++) {
            for (int c = 0; c < 3; c++) {
                d[4 * i + c] = pf.direct[3 * i + c];
                sp += pf.direct[3 * i + c], sr += rf.rgba[4 * i + c];
            }
            d[4 * i + 3] = pf.rgba[4 * i + 3];
        }
        double b4, p99;
        sl_image_error_blocks(d, rf.rgba, pf.width, pf.height, 4, &b4, &p99);
        if (getenv("SL_TEST_VERBOSE"))
            fprintf(stderr, "%s: sums %.6g vs %.6g (ratio %.4f), 4x4 rel RMSE %.4f (noise %.4f)\n",
                    tag, sp, sr, sp / sr, b4, pr.noise_4x4);
        CHECK_MSG(sr > 0 && fabs(sp / sr - 1) < 0.025, "%s: direct sum %.6g vs reference %.6g", tag,
                  sp, sr);
        CHECK_MSG(b4 < 3 * pr.noise_4x4 + 0.02, "%s: 4x4 blocks rel. RMSE %.4f, noise %.4f", tag,
                  b4, pr.noise_4x4);
        free(d);
    }
    sl_path_frame_free(&pf);
    sl_reference_frame_free(&rf);
    free(s);
}

TEST(path_direct_matches_reference) {
    direct_matches_reference("path_direct",
                             "{\"model\": \"deon\", \"sigma_a\": 0.3, \"alpha_R_deg\": -3, "
                             "\"beta_R_deg\": 25, \"beta_TT_deg\": 20, \"beta_TRT_deg\": 30, "
                             "\"orders\": 2}");
}

/* The same for chiang (the reference renderer shaded chiang with Marschner's f until session 12:
 * its sum was 1.8-1.9x the path tracer's direct light, which this check fails at 2.5 %). */
TEST(reference_chiang_matches_path) {
    direct_matches_reference("path_direct_chiang",
                             "{\"model\": \"chiang\", \"melanin\": 0.3, \"roughness\": 0.4}");
}

static const char *SMALL_VIEW =
    "\"camera\": {\"eye\": [0, 0, -60], \"target\": [0, -2, 0], \"fov_deg\": 20}, \"image\": "
    "{\"width\": 12, \"height\": 10}";
static const char *CHIANG = "{\"model\": \"chiang\", \"melanin\": 0.4}";

/* One small scene for the tests below: chiang hair over the white map. */
static sl_scene *small_scene(const char *tag, char *dir, size_t n) {
    sl_test_fresh_dir(tag, dir, n);
    if (!dir[0]) return NULL;
    white_map(dir);
    sl_scene *s = malloc(sizeof *s);
    if (scene_in(dir, "small", DENSE, CHIANG, SMALL_VIEW, s)) {
        free(s);
        return NULL;
    }
    return s;
}

static int frames_equal(const sl_path_frame *a, const sl_path_frame *b) {
    size_t n = (size_t)a->width * a->height;
    return a->width == b->width && a->height == b->height &&
           memcmp(a->rgba, b->rgba, 4 * n * sizeof(float)) == 0 &&
           memcmp(a->depth, b->depth, n * sizeof(float)) == 0 &&
           memcmp(a->direct, b->direct, 3 * n * sizeof(float)) == 0 &&
           memcmp(a->indirect, b->indirect, 3 * n * sizeof(float)) == 0 &&
           memcmp(a->lobes, b->lobes, 12 * n * sizeof(float)) == 0;
}

/* Per-(pixel, sample) random streams and per-pixel sums in sample order: the same bytes for 1
 * and 3 threads; another seed is another image; the AOVs add up to rgb. */
TEST(path_threads_identical) {
    char dir[1024];
    sl_scene *s = small_scene("path_threads", dir, sizeof dir);
    if (!s) SKIP("no temporary directory");
    sl_path_settings set;
    sl_path_settings_default(&set);
    set.spp = 4, set.progress = 0;
    sl_path_frame f1, f3, f2;
    sl_path_result r;
    sl_err e;
    set.threads = 1;
    CHECK(sl_path_render(s, &set, &f1, &r, &e) == 0);
    set.threads = 3;
    CHECK(sl_path_render(s, &set, &f3, &r, &e) == 0);
    set.seed = 2;
    CHECK(sl_path_render(s, &set, &f2, &r, &e) == 0);
    CHECK(frames_equal(&f1, &f3));
    CHECK(!frames_equal(&f1, &f2));
    /* direct + indirect = rgb and the four lobes sum to rgb (float rounding of each plane) */
    double worst = 0, total = 0;
    for (int i = 0; i < f1.width * f1.height; i++)
        for (int c = 0; c < 3; c++) {
            double v = f1.rgba[4 * i + c], l = 0;
            for (int k = 0; k < 4; k++)
                l += f1.lobes[12 * i + 3 * k + c];
            worst = fmax(worst, fabs(f1.direct[3 * i + c] + f1.indirect[3 * i + c] - v));
            worst = fmax(worst, fabs(l - v));
            total = fmax(total, v);
        }
    CHECK_MSG(worst <= 1e-5 * total, "AOVs miss rgb by %g (max rgb %g)", worst, total);
    sl_path_frame_free(&f1);
    sl_path_frame_free(&f3);
    sl_path_frame_free(&f2);
    free(s);
}

/* --time: whole passes until the next would pass the budget; the spp reached is recorded and
 * the image is the fixed-spp image of that count (same key). A cancel flag set: no image. */
TEST(path_time_budget_and_cancel) {
    char dir[1024];
    sl_scene *s = small_scene("path_budget", dir, sizeof dir);
    if (!s) SKIP("no temporary directory");
    sl_path_settings set;
    sl_path_settings_default(&set);
    set.spp = 0, set.time_s = 0.4, set.threads = 2, set.progress = 0;
    sl_path_frame f, g;
    sl_path_result r, q;
    sl_err e;
    CHECK(sl_path_render(s, &set, &f, &r, &e) == 0);
    CHECK_MSG(r.spp >= 1 && r.wall_s < 0.4 + r.wall_s / r.spp + 0.2,
              "%d spp in %.3f s for a 0.4 s budget", r.spp, r.wall_s);
    set.time_s = 0, set.spp = r.spp;
    CHECK(sl_path_render(s, &set, &g, &q, &e) == 0);
    CHECK(q.key == r.key && frames_equal(&f, &g));
    sl_path_frame_free(&f);
    sl_path_frame_free(&g);
    volatile sig_atomic_t stop = 1;
    set.cancel = &stop;
    CHECK(sl_path_render(s, &set, &f, &r, &e) == -1 && r.interrupted == 1);
    CHECK(strstr(e.msg, "interrupted") != NULL);
    sl_path_frame_free(&f);
    free(s);
}

/* The record: EXR + JSON; the same settings again are a cache hit; sl_reference_load (what
 * `report` reads) reads the path EXR; an interrupted run writes nothing. */
TEST(path_run_record_cache_load) {
    char dir[1024], exr[1200], json[1300];
    sl_scene *s = small_scene("path_record", dir, sizeof dir);
    if (!s) SKIP("no temporary directory");
    snprintf(exr, sizeof exr, "%s/out/p.exr", dir);
    snprintf(json, sizeof json, "%s.json", exr);
    sl_path_settings set;
    sl_path_settings_default(&set);
    set.spp = 4, set.threads = 2, set.progress = 0;
    sl_path_result r1, r2;
    sl_err e;
    CHECK(sl_path_run(s, &set, exr, 0, &r1, &e) == 0 && r1.cached == 0 && r1.spp == 4);
    CHECK(sl_path_run(s, &set, exr, 0, &r2, &e) == 0 && r2.cached == 1 && r2.key == r1.key);
    CHECK(isfinite(r1.noise) && r1.noise > 0 && r1.noise_8x8 <= r1.noise_4x4 + 1e-12);
    sl_reference_frame lf;
    sl_path_frame pf;
    sl_path_result r3;
    CHECK(sl_reference_load(exr, &lf, &e) == 0);
    CHECK(sl_path_render(s, &set, &pf, &r3, &e) == 0);
    if (lf.rgba && pf.rgba) {
        size_t n = (size_t)pf.width * pf.height;
        CHECK(lf.key == r1.key && lf.ms == 1 && lf.fragments == 0);
        CHECK(memcmp(lf.rgba, pf.rgba, 4 * n * sizeof(float)) == 0);
        CHECK(memcmp(lf.ms_rgb, pf.indirect, 3 * n * sizeof(float)) == 0);
    }
    sl_reference_frame_free(&lf);
    sl_path_frame_free(&pf);
    char exr2[1200];
    snprintf(exr2, sizeof exr2, "%s/cancelled.exr", dir);
    volatile sig_atomic_t stop = 1;
    set.cancel = &stop;
    CHECK(sl_path_run(s, &set, exr2, 0, &r3, &e) == -1 && r3.interrupted);
    CHECK(sl_test_count_files(dir, "cancelled") == 0);
    free(s);
}
