/* test_reference_host.c: host/verify/reference/reference.c: the image error of numerics.md sec. 6 on a hand-worked
 * case, and sl_reference_run's cache (a second run renders nothing, the loaded pixels equal a
 * fresh render) on a tiny scene written here (procedural hair, a uniform 8x4 .hdr map). */
#include "test.h"

#include "verify/reference/reference.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

TEST(reference_image_error_hand_case) {
    /* 3 pixels: (1,1,1) a 1; empty in both (ignored); (2,2,2) a 1. x adds 0.1 to R of pixel 0.
     * R: sqrt(0.01 / (1 + 4)) = 0.0447214; G, B: 0; mean 0.0149071. p99 over 2 hair pixels:
     * the larger per-pixel error, 0.1 / sqrt(3) = 0.0577350. */
    float ref[12] = {1, 1, 1, 1, 0, 0, 0, 0, 2, 2, 2, 1};
    float x[12] = {1.1f, 1, 1, 1, 0, 0, 0, 0, 2, 2, 2, 1};
    double r, rgb[3], p99;
    sl_image_error(x, ref, 3, 1, &r, rgb, &p99);
    /* tolerance 1e-6: 1.1f carries a 2e-8 float rounding */
    CHECK_NEAR(rgb[0], sqrt(0.01 / 5), 1e-6);
    CHECK(rgb[1] == 0 && rgb[2] == 0);
    CHECK_NEAR(r, sqrt(0.01 / 5) / 3, 1e-6);
    CHECK_NEAR(p99, 0.1 / sqrt(3.0), 1e-6);
    /* a pixel covered only in x counts (alpha > 0 in either image) */
    float x2[12] = {1, 1, 1, 1, 0.5f, 0, 0, 1, 2, 2, 2, 1};
    sl_image_error(x2, ref, 3, 1, &r, rgb, &p99);
    CHECK_NEAR(rgb[0], sqrt(0.25 / 5), 1e-6);
}

static int write_file(const char *path, const void *d, size_t n) {
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    int ok = fwrite(d, 1, n, f) == n;
    return fclose(f) == 0 && ok ? 0 : -1;
}

TEST(reference_run_cache_and_load) {
    const char *tmp = sl_test_tmpdir();
    if (!tmp) SKIP("no temporary directory");
    char dir[1024], map[1200], scene_path[1200], exr[1200], json[1300];
    /* per process: two builds may run the suite at once in the same tmpdir */
    snprintf(dir, sizeof dir, "%s/refhost_%ld", tmp, (long)getpid());
    mkdir(dir, 0777);
    snprintf(map, sizeof map, "%s/refhost_map.hdr", dir);
    snprintf(scene_path, sizeof scene_path, "%s/refhost_scene.json", dir);
    snprintf(exr, sizeof exr, "%s/out/ref.exr", dir);
    snprintf(json, sizeof json, "%s.json", exr);
    remove(exr);
    remove(json);
    /* uniform radiance 1: RGBE (128, 128, 128, 129) = 0.5 x 2^1 */
    char hdr[256];
    int hn = snprintf(hdr, sizeof hdr, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8\n");
    unsigned char buf[256 + 128];
    memcpy(buf, hdr, (size_t)hn);
    for (int i = 0; i < 32; i++)
        buf[hn + 4 * i] = buf[hn + 4 * i + 1] = buf[hn + 4 * i + 2] = 128,
                     buf[hn + 4 * i + 3] = 129;
    CHECK(write_file(map, buf, (size_t)hn + 128) == 0);
    const char *sc =
        "{\"hair\": {\"procedural\": {\"style\": \"straight\", \"strands\": 12, \"points\": "
        "6, \"seed\": 4}, \"radius\": 0.4}, \"environment\": {\"file\": "
        "\"refhost_map.hdr\"}, \"image\": {\"width\": 16, \"height\": 12}, "
        "\"quality\": {\"multiple_scattering\": \"off\"}}\n";
    CHECK(write_file(scene_path, sc, strlen(sc)) == 0);
    sl_scene *s = malloc(sizeof *s);
    sl_err e;
    if (sl_scene_load(scene_path, s, &e)) {
        CHECK_MSG(0, "%s", e.msg);
        free(s);
        return;
    }
    sl_reference_settings set;
    sl_reference_settings_default(&set);
    set.lights = 3;
    set.threads = 2;
    set.progress = 0;
    sl_reference_result r1, r2;
    CHECK(sl_reference_run(s, &set, exr, 1, &r1, &e) == 0);
    CHECK(r1.cached == 0 && r1.has_convergence && r1.lights == 3);
    CHECK(isfinite(r1.conv_rel_rmse) && r1.conv_rel_rmse >= 0);
    CHECK(sl_reference_run(s, &set, exr, 1, &r2, &e) == 0);
    CHECK(r2.cached == 1 && r2.key == r1.key);
    CHECK_NEAR(r2.conv_rel_rmse, r1.conv_rel_rmse, 1e-12 * (1 + r1.conv_rel_rmse));
    sl_reference_frame lf, rf;
    CHECK(sl_reference_load(exr, &lf, &e) == 0);
    set.threads = 1; /* the image must not depend on it */
    CHECK(sl_reference_render(s, &set, &rf, &e) == 0);
    CHECK(lf.width == 16 && lf.height == 12 && lf.key == r1.key && rf.key == r1.key);
    if (lf.rgba && rf.rgba) {
        /* float EXR: exact */
        CHECK(memcmp(lf.rgba, rf.rgba, 16 * 12 * 4 * sizeof(float)) == 0);
        CHECK(memcmp(lf.mode_rgb, rf.mode_rgb, 16 * 12 * 9 * sizeof(float)) == 0);
        CHECK(memcmp(lf.depth, rf.depth, 16 * 12 * sizeof(float)) == 0);
        int hair = 0;
        for (int i = 0; i < 16 * 12; i++)
            hair += rf.rgba[4 * i + 3] > 0;
        CHECK(hair > 5);
    }
    /* a damaged EXR fails the digest in its JSON: the loader refuses it, a run renders it again
     * (and the rewritten pair is a cache hit again) */
    FILE *fx = fopen(exr, "r+b");
    CHECK(fx != NULL);
    if (fx) {
        fseek(fx, -5, SEEK_END);
        int c = fgetc(fx);
        fseek(fx, -5, SEEK_END);
        fputc(c ^ 1, fx);
        fclose(fx);
    }
    sl_reference_frame bad;
    CHECK(sl_reference_load(exr, &bad, &e) == -1 && strstr(e.msg, "digest") != NULL);
    sl_reference_frame_free(&bad);
    sl_reference_result r4;
    CHECK(sl_reference_run(s, &set, exr, 1, &r4, &e) == 0 && r4.cached == 0 && r4.key == r1.key);
    CHECK(sl_reference_run(s, &set, exr, 1, &r4, &e) == 0 && r4.cached == 1);
    CHECK(sl_reference_load(exr, &bad, &e) == 0);
    sl_reference_frame_free(&bad);
    /* another environment intensity is another key */
    s->env_intensity = 2;
    sl_reference_result r3;
    set.threads = 2;
    CHECK(sl_reference_run(s, &set, exr, 0, &r3, &e) == 0);
    CHECK(r3.cached == 0 && r3.key != r1.key);
    sl_reference_frame_free(&lf);
    sl_reference_frame_free(&rf);
    free(s);
    remove(exr);
    remove(json);
    remove(map);
    remove(scene_path);
    char outdir[1300];
    snprintf(outdir, sizeof outdir, "%s/out", dir);
    rmdir(outdir);
    rmdir(dir);
}
