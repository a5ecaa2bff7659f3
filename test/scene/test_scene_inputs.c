/* test_scene_inputs.c: the one scene loader (host/scene/scene_inputs.h): render's path (from the
 * file) and the reference's (from a loaded scene) frame the same camera, the "eye omitted" rule
 * looks along -Z at the bounds' centre, command-line sizes override the scene's, lobes come
 * rotated and scaled, a missing file fails with the message and in the order of before, and the
 * file's transparency is dropped unless hair.transparency says "file". */
#include "scene/scene_hair.h"
#include "scene/scene_inputs.h"
#include "test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Writes text to name in a scratch directory; returns the path (static buffer per slot). */
static const char *scratch(const char *name, const char *text) {
    static char paths[4][1024];
    static int slot;
    char *p = paths[slot++ % 4];
    snprintf(p, 1024, "%s/scene_inputs_%s", sl_test_tmpdir(), name);
    FILE *f = fopen(p, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
    return p;
}

static const char *HAIR_ONLY = "{\"hair\":{\"procedural\":{\"style\":\"wavy\",\"strands\":40,"
                               "\"points\":6,\"seed\":3}},\"image\":{\"width\":64,\"height\":32},"
                               "\"environment\":{\"lobes\":\"l.json\"}}";

TEST(scene_inputs_render_and_reference_frame_alike) {
    const char *path = scratch("frame.json", HAIR_ONLY);
    sl_scene_inputs_opts o = {.width = 80, .height = 40};
    sl_scene_inputs a, b;
    sl_err e = {{0}};
    int rc = sl_scene_inputs_load(path, &o, &a, &e);
    CHECK_MSG(rc == 0, "%s", e.msg);
    /* the reference's path: the scene as loaded without overrides, the sizes as settings */
    sl_scene *s = calloc(1, sizeof *s);
    CHECK(sl_scene_load(path, s, &e) == 0 && s->width == 64);
    rc = sl_scene_inputs_from_scene(s, &o, &b, &e);
    CHECK_MSG(rc == 0, "%s", e.msg);
    CHECK(s->width == 64 && s->height == 32); /* the caller's scene is not changed */
    if (!rc) {
        CHECK(memcmp(&a.cam, &b.cam, sizeof a.cam) == 0);
        CHECK(memcmp(a.target, b.target, sizeof a.target) == 0);
        CHECK(a.hair.num_strands == 40 && b.hair.num_strands == 40);
        /* eye omitted: at the bounds' centre, looking along -Z, everything in view */
        for (int k = 0; k < 3; k++)
            CHECK_NEAR(a.target[k], 0.5 * (a.lo[k] + a.hi[k]), 1e-12);
        CHECK(a.cam.eye[0] == a.target[0] && a.cam.eye[1] == a.target[1]);
        CHECK(a.cam.eye[2] > a.hi[2]);
        CHECK_NEAR(a.cam.fwd[2], -1.0, 1e-12);
        for (int c = 0; c < 8; c++) {
            double p[3] = {c & 1 ? a.hi[0] : a.lo[0], c & 2 ? a.hi[1] : a.lo[1],
                           c & 4 ? a.hi[2] : a.lo[2]};
            double px, py, z;
            CHECK(sl_camera_project(&a.cam, p, &px, &py, &z));
            CHECK(px >= 0 && px <= 80 && py >= 0 && py <= 40);
        }
        /* the framing function itself gives the same camera */
        sl_camera c;
        double t[3];
        sl_scene_camera(s, a.lo, a.hi, 80, 40, t, &c);
        CHECK(memcmp(&c, &a.cam, sizeof c) == 0);
    }
    sl_scene_inputs_free(&a);
    sl_scene_inputs_free(&b);
    free(s);
}

TEST(scene_inputs_size_override) {
    const char *path = scratch("size.json", HAIR_ONLY);
    sl_err e = {{0}};
    sl_scene_inputs in;
    sl_scene_inputs_opts o = {.width = 100};
    int rc = sl_scene_inputs_load(path, &o, &in, &e);
    CHECK_MSG(rc == 0, "%s", e.msg);
    if (!rc) {
        CHECK(in.scene->width == 100 && in.scene->height == 32); /* height: the scene's */
        CHECK(in.cam.width == 100 && in.cam.height == 32);
        CHECK(in.lobes.count == 0 && in.strand_sigma_a == NULL); /* not asked for */
    }
    sl_scene_inputs_free(&in);
    sl_scene_inputs_opts none = {0};
    CHECK(sl_scene_inputs_load(path, &none, &in, &e) == 0);
    CHECK(in.scene && in.scene->width == 64 && in.cam.width == 64 && in.cam.height == 32);
    sl_scene_inputs_free(&in);
    /* a given eye is kept */
    path = scratch("eye.json", "{\"hair\":{\"procedural\":{\"strands\":10}},"
                               "\"camera\":{\"eye\":[1,2,30],\"target\":[0,1,0]},"
                               "\"environment\":{\"lobes\":\"l.json\"}}");
    CHECK(sl_scene_inputs_load(path, &none, &in, &e) == 0);
    CHECK(in.cam.eye[0] == 1 && in.cam.eye[1] == 2 && in.cam.eye[2] == 30);
    CHECK(in.target[0] == 0 && in.target[1] == 1 && in.target[2] == 0);
    sl_scene_inputs_free(&in);
}

TEST(scene_inputs_lobes_turned_and_scaled) {
    scratch("one.lobes.json", "{\"lobes\":[{\"dir\":[1,0,0],\"lambda\":0.5,\"rgb\":[1,2,3]}]}");
    const char *path =
        scratch("lobes.json", "{\"hair\":{\"procedural\":{\"strands\":10}},"
                              "\"environment\":{\"lobes\":\"scene_inputs_one.lobes.json\","
                              "\"rotation_deg\":90,\"intensity\":2}}");
    sl_err e = {{0}};
    sl_scene_inputs in;
    sl_scene_inputs_opts o = {.lobes = 1};
    int rc = sl_scene_inputs_load(path, &o, &in, &e);
    CHECK_MSG(rc == 0, "%s", e.msg);
    if (!rc && in.lobes.count == 1) {
        /* +X turned 90 degrees about +Y is -Z (sl_lobes_transform) */
        CHECK_NEAR(in.lobes.lobe[0].dir[0], 0, 1e-12);
        CHECK_NEAR(in.lobes.lobe[0].dir[2], -1, 1e-12);
        CHECK_NEAR(in.lobes.lobe[0].rgb[2], 6, 1e-12);
    } else {
        CHECK(0);
    }
    sl_scene_inputs_free(&in);
}

/* The files a scene names fail in render's order (hair, lobes, per-strand absorption), each with
 * the message of the loader it comes from (the file's name), leaving in safe to free. */
TEST(scene_inputs_missing_files_in_order) {
    char dir[1024];
    snprintf(dir, sizeof dir, "%s", sl_test_tmpdir());
    sl_scene_inputs_opts o = {.lobes = 1, .strand_sigma_a = 1};
    sl_scene_inputs in;
    sl_err e = {{0}};
    char want[2048];

    const char *p = scratch("nohair.json", "{\"hair\":{\"file\":\"missing.hair\"},"
                                           "\"environment\":{\"lobes\":\"missing.lobes.json\"}}");
    CHECK(sl_scene_inputs_load(p, &o, &in, &e) == -1);
    /* the scene and the key that named the file come first (issue 22: the old message named
     * only the missing file) */
    snprintf(want, sizeof want, "%s: hair.file: %s/missing.hair: No such file or directory", p,
             dir);
    CHECK_MSG(strcmp(e.msg, want) == 0, "got \"%s\"", e.msg);
    CHECK(in.scene && in.hair.num_strands == 0);
    sl_scene_inputs_free(&in);
    CHECK(in.scene == NULL);

    p = scratch("nolobes.json", "{\"hair\":{\"procedural\":{\"strands\":10}},"
                                "\"material\":{\"strand_sigma_a\":\"missing.csv\"},"
                                "\"environment\":{\"lobes\":\"missing.lobes.json\"}}");
    CHECK(sl_scene_inputs_load(p, &o, &in, &e) == -1);
    snprintf(want, sizeof want,
             "%s: environment.lobes: %s/missing.lobes.json: No such file or directory", p, dir);
    CHECK_MSG(strcmp(e.msg, want) == 0, "got \"%s\"", e.msg);
    sl_scene_inputs_free(&in);

    /* without lobes asked for, the CSV is next */
    sl_scene_inputs_opts no_lobes = {.strand_sigma_a = 1};
    CHECK(sl_scene_inputs_load(p, &no_lobes, &in, &e) == -1);
    CHECK_MSG(strstr(e.msg, "missing.csv") != NULL, "got \"%s\"", e.msg);
    sl_scene_inputs_free(&in);

    /* a bad scene fails with the scene's own message */
    p = scratch("bad.json", "{\"hair\":{\"procedural\":{\"strands\":10}},\"camera\":{\"fov_deg\":"
                            "\"wide\"},\"environment\":{\"lobes\":\"l.json\"}}");
    CHECK(sl_scene_inputs_load(p, &o, &in, &e) == -1);
    CHECK_MSG(strstr(e.msg, "camera.fov_deg") != NULL, "got \"%s\"", e.msg);
    sl_scene_inputs_free(&in);
}

/* hair.transparency (docs/formats.md "Transparency"): by default the file's per-point
 * transparency is dropped at load (fibers are opaque, as in the shadows, the references and
 * Cycles); "file" keeps it for the view pass; anything else is an error naming the key. */
TEST(scene_inputs_hair_transparency) {
    sl_hair h = {0};
    sl_err e = {{0}};
    sl_hair_procedural p = {0, 20, 5, 7};
    CHECK(sl_hair_generate(&p, &h, &e) == 0);
    free(h.transparency);
    h.transparency = malloc(h.num_points * sizeof *h.transparency);
    for (uint32_t i = 0; i < h.num_points; i++)
        h.transparency[i] = 0.25f;
    char hair[1024];
    snprintf(hair, sizeof hair, "%s/scene_inputs_tr.hair", sl_test_tmpdir());
    CHECK_MSG(sl_hair_write_cyhair(hair, &h, NULL, &e) == 0, "%s", e.msg);
    sl_hair_free(&h);
    const char *modes[] = {"", ",\"transparency\":\"opaque\"", ",\"transparency\":\"file\""};
    for (int m = 0; m < 3; m++) {
        char text[2048];
        snprintf(text, sizeof text,
                 "{\"hair\":{\"file\":\"scene_inputs_tr.hair\"%s},\"image\":{\"width\":16,"
                 "\"height\":8},"
                 "\"environment\":{\"lobes\":\"l.json\"}}",
                 modes[m]); /* relative: beside the scene */
        const char *path = scratch("tr.json", text);
        sl_scene *s = calloc(1, sizeof *s);
        CHECK_MSG(sl_scene_load(path, s, &e) == 0, "%s", e.msg);
        sl_hair got = {0};
        CHECK_MSG(sl_scene_load_hair(s, &got, &e) == 0, "%s", e.msg);
        if (m < 2) {
            CHECK(got.transparency == NULL && got.default_transparency == 0.0f);
        } else {
            CHECK(got.transparency != NULL);
            for (uint32_t i = 0; got.transparency && i < got.num_points; i++)
                CHECK(got.transparency[i] == 0.25f);
        }
        sl_hair_free(&got);
        free(s);
    }
    const char *bad =
        scratch("trbad.json", "{\"hair\":{\"procedural\":{},\"transparency\":\"half\"}}");
    sl_scene *s = calloc(1, sizeof *s);
    CHECK(sl_scene_load(bad, s, &e) != 0);
    CHECK_MSG(strstr(e.msg, "hair.transparency: expected \"opaque\" or \"file\"") != NULL, "%s",
              e.msg);
    free(s);
}
