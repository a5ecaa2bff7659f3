/* test_scene_strands.c: per-strand sigma_a overrides (host/scene/scene_strands.h): the CSV round
 * trip and its errors, "colors" from a .hair file with a colour array (Chiang 2016 Eq. 9 checked by
 * its forward form in double; with multiple scattering off, the single-scattering inverse
 * checked by its own quadrature), the scene keys material.strand_sigma_a and the planner
 * thresholds quality.*_threshold (parse, defaults, range errors). The frame's use of them is in
 * test/plan/test_frame.c. */
#include "test.h"

#include "scene/scene.h"
#include "scene/scene_strands.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

TEST(scene_strands_csv_round_trip) {
    /* 1000 strands, every 7th overridden with values that need all 9 significant digits; the
     * file must hold exactly those rows and read back bit-exact (tolerance 0: %.9g round-trips
     * every binary32 value) */
    enum { N = 1000 };
    const float base[3] = {0.36f, 0.36f, 0.36f};
    float *sa = malloc(3 * N * sizeof *sa);
    int over = 0;
    for (int s = 0; s < N; s++)
        for (int q = 0; q < 3; q++)
            sa[3 * s + q] = s % 7 == 0 ? (float)(0.1 + s * 1.2345678e-3 + q / 3.0) : base[q];
    for (int s = 0; s < N; s += 7)
        over++;
    char path[4200];
    snprintf(path, sizeof path, "%s/strands_rt.csv", sl_test_tmpdir());
    sl_err e;
    CHECK(sl_strand_sigma_a_write_csv(path, sa, N, base, &e) == 0);
    FILE *f = fopen(path, "rb");
    CHECK(f != NULL);
    int lines = 0, c;
    char first[64] = "";
    if (f) {
        if (!fgets(first, sizeof first, f)) first[0] = 0;
        lines = 1;
        while ((c = fgetc(f)) != EOF)
            lines += c == '\n';
        fclose(f);
    }
    CHECK(strcmp(first, "strand,sigma_a_r,sigma_a_g,sigma_a_b\n") == 0);
    CHECK(lines == 1 + over);
    float *back = NULL;
    CHECK(sl_strand_sigma_a_read_csv(path, N, base, &back, &e) == 0);
    int same = back != NULL;
    for (int i = 0; back && i < 3 * N; i++)
        same &= back[i] == sa[i];
    CHECK(same);
    free(back);
    free(sa);
}

static void expect_csv_error(const char *text, uint32_t n, const char *want) {
    const float base[3] = {0.5f, 0.5f, 0.5f};
    float *out = (float *)1;
    sl_err e = {{0}};
    int rc = sl_strand_sigma_a_parse_csv(text, strlen(text), "paint.csv", n, base, &out, &e);
    CHECK(rc == -1);
    CHECK(out == NULL);
    if (!strstr(e.msg, want)) fprintf(stderr, "  got \"%s\", want \"%s\"\n", e.msg, want);
    CHECK(strstr(e.msg, want) != NULL);
    CHECK(strchr(e.msg, '\n') == NULL);
}

TEST(scene_strands_csv_errors) {
    const char *h = "strand,sigma_a_r,sigma_a_g,sigma_a_b\n";
    char buf[512];
    expect_csv_error("", 10, "paint.csv");
    expect_csv_error("strand,r,g,b\n1,1,1,1\n", 10, "paint.csv:1: missing column 'sigma_a_r'");
    expect_csv_error("strand,sigma_a_r,sigma_a_g,sigma_a_b,x\n1,1,1,1,1\n", 10,
                     "paint.csv:1: expected exactly the columns");
    snprintf(buf, sizeof buf, "%s0,1,1,1\n10,1,1,1\n", h);
    expect_csv_error(buf, 10, "paint.csv:3: strand 10: out of range (the hair has 10 strands)");
    snprintf(buf, sizeof buf, "%s-1,1,1,1\n", h);
    expect_csv_error(buf, 10, "paint.csv:2: strand: '-1' is not a strand index");
    snprintf(buf, sizeof buf, "%s1.5,1,1,1\n", h);
    expect_csv_error(buf, 10, "paint.csv:2: strand: '1.5' is not a strand index");
    snprintf(buf, sizeof buf, "%s3,1,1,1\n4,1,1,1\n3,2,2,2\n", h);
    expect_csv_error(buf, 10, "paint.csv:4: strand 3: given twice");
    snprintf(buf, sizeof buf, "%s3,1,-0.5,1\n", h);
    expect_csv_error(buf, 10, "paint.csv:2: sigma_a_g: -0.5: must be a finite value >= 0");
    snprintf(buf, sizeof buf, "%s3,1,x,1\n", h);
    expect_csv_error(buf, 10, "paint.csv:2: sigma_a_g: 'x' is not a number");
    snprintf(buf, sizeof buf, "%s3,1,1\n", h);
    expect_csv_error(buf, 10, "paint.csv:2");
    /* a header alone: no override, every strand keeps the base */
    const float base[3] = {0.5f, 0.25f, 0.125f};
    float *out = NULL;
    sl_err e;
    CHECK(sl_strand_sigma_a_parse_csv(h, strlen(h), "p.csv", 3, base, &out, &e) == 0);
    CHECK(out && out[0] == 0.5f && out[4] == 0.25f && out[8] == 0.125f);
    free(out);
    /* a missing file names the path */
    CHECK(sl_strand_sigma_a_read_csv("/nonexistent/p.csv", 3, base, &out, &e) == -1);
    CHECK(strstr(e.msg, "/nonexistent/p.csv") != NULL);
}

/* A cyHair file (../shared/data/README.md layout) of 2 strands x 3 points with a colour array
 * (flags: points + colours = 0x12, default segments 2). */
static int write_tiny_hair(const char *path, const float col[6][3]) {
    unsigned char hdr[128] = {0};
    memcpy(hdr, "HAIR", 4);
    uint32_t S = 2, P = 6, flags = 0x12, seg = 2;
    float thick = 0.1f, transp = 0, dcol[3] = {1, 1, 1};
    memcpy(hdr + 4, &S, 4);
    memcpy(hdr + 8, &P, 4);
    memcpy(hdr + 12, &flags, 4);
    memcpy(hdr + 16, &seg, 4);
    memcpy(hdr + 20, &thick, 4);
    memcpy(hdr + 24, &transp, 4);
    memcpy(hdr + 28, dcol, 12);
    float pts[6][3];
    for (int i = 0; i < 6; i++)
        pts[i][0] = (float)(i / 3), pts[i][1] = (float)(i % 3), pts[i][2] = 0;
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    fwrite(hdr, 1, 128, f);
    fwrite(pts, sizeof(float), 18, f);
    fwrite(col, sizeof(float), 18, f);
    return fclose(f);
}

TEST(scene_strands_from_colors) {
    /* strand 0: mean colour (0.5, 0.3, 0.1) from varying points; strand 1: white and black.
     * Chiang 2016 Eq. 9 is checked through its forward form c = exp(-sqrt(sigma_a) d(beta_n))
     * in double (relative 1e-5: the result is stored in float, ~6e-8, and c is averaged from
     * floats); beta_n through Eq. 7's forward polynomial (1e-9: bisection to double). */
    const float col[6][3] = {{0.4f, 0.2f, 0.1f}, {0.5f, 0.3f, 0.1f}, {0.6f, 0.4f, 0.1f},
                             {1.0f, 0.0f, 1.0f}, {1.0f, 0.0f, 1.0f}, {1.0f, 0.0f, 1.0f}};
    char path[4200];
    snprintf(path, sizeof path, "%s/colors.hair", sl_test_tmpdir());
    CHECK(write_tiny_hair(path, col) == 0);
    sl_hair h;
    sl_err e;
    CHECK(sl_hair_load(path, &h, &e) == 0);
    CHECK(h.color != NULL);
    sl_material m;
    sl_material_default(&m);
    double sd = m.beta[0] / sqrt(2.0);
    double bn = sl_chiang_beta_m(sd);
    CHECK_NEAR(0.726 * bn + 0.812 * bn * bn + 3.7 * pow(bn, 20), sd, 1e-9);
    float *sa = NULL;
    CHECK(sl_strand_sigma_a_from_colors(&h, &m, &sa, &e) == 0);
    CHECK(sa != NULL);
    double d = 5.969 - 0.215 * bn + 2.532 * bn * bn - 10.73 * pow(bn, 3) + 5.574 * pow(bn, 4) +
               0.245 * pow(bn, 5);
    const double mean0[3] = {0.5, 0.3, 0.1};
    for (int q = 0; sa && q < 3; q++)
        CHECK_REL(exp(-sqrt((double)sa[q]) * d), mean0[q], 1e-5);
    /* white -> no absorption; black -> clamped at c = 1e-4, finite */
    CHECK(sa && sa[3] == 0.0f && sa[5] == 0.0f);
    CHECK(sa && isfinite(sa[4]));
    if (sa) CHECK_REL(exp(-sqrt((double)sa[4]) * d), 1e-4, 1e-5);
    /* darker colour, more absorption */
    CHECK(sa && sa[0] < sa[1] && sa[1] < sa[2]);
    free(sa);
    /* model chiang: Chiang's beta_n is its own radial roughness (0.45 here), not a width */
    sl_material mc;
    sl_material_default(&mc);
    mc.model = SL_MODEL_CHIANG;
    mc.chiang.radial_roughness = 0.45;
    sl_chiang_derive(&mc);
    CHECK(sl_strand_sigma_a_from_colors(&h, &mc, &sa, &e) == 0);
    double b = 0.45, dc = 5.969 - 0.215 * b + 2.532 * b * b - 10.73 * pow(b, 3) +
                          5.574 * pow(b, 4) + 0.245 * pow(b, 5);
    for (int q = 0; sa && q < 3; q++)
        CHECK_REL(exp(-sqrt((double)sa[q]) * dc), mean0[q], 1e-5);
    free(sa);
    /* through the scene key */
    sl_scene s;
    char text[256];
    snprintf(text, sizeof text,
             "{\"hair\":{\"file\":\"colors.hair\"},\"material\":{\"strand_sigma_a\":\"colors\"},"
             "\"environment\":{\"lobes\":\"l.json\"}}");
    char sp[4200];
    snprintf(sp, sizeof sp, "%s/colors_scene.json", sl_test_tmpdir());
    CHECK(sl_scene_parse(text, strlen(text), sp, &s, &e) == 0);
    CHECK(s.strand_sigma_a_colors == 1);
    CHECK(sl_scene_strand_sigma_a(&s, &h, &sa, &e) == 0);
    CHECK(sa != NULL);
    if (sa) CHECK_REL(exp(-sqrt((double)sa[0]) * d), 0.5, 1e-5);
    free(sa);
    sl_hair_free(&h);
    /* a hair without colours: a clear error */
    sl_hair_procedural p = {SL_PROC_STRAIGHT, 4, 4, 1};
    CHECK(sl_hair_generate(&p, &h, &e) == 0);
    CHECK(sl_scene_strand_sigma_a(&s, &h, &sa, &e) == -1);
    CHECK(sa == NULL);
    CHECK(strstr(e.msg, "no per-point colours") != NULL);
    sl_hair_free(&h);
}

TEST(scene_strands_shared_straight_hair) {
    /* ../shared/data/hair/straight.hair has a constant colour array (1, 0.925490, 0.568627,
     * data/README.md): every strand gets the same sigma_a, blue absorbing most */
    const char *d = sl_test_shared_data();
    if (!d) SKIP("no ../shared/data");
    char path[4200];
    snprintf(path, sizeof path, "%s/hair/straight.hair", d);
    sl_hair h;
    sl_err e;
    if (sl_hair_load(path, &h, &e)) SKIP("straight.hair not loadable");
    sl_material m;
    sl_material_default(&m);
    float *sa = NULL;
    CHECK(sl_strand_sigma_a_from_colors(&h, &m, &sa, &e) == 0);
    int same = sa != NULL;
    for (uint32_t s = 1; sa && s < h.num_strands; s++)
        for (int q = 0; q < 3; q++)
            same &= sa[3 * s + q] == sa[q];
    CHECK(same);
    CHECK(sa && sa[0] == 0.0f && sa[1] > 0 && sa[2] > sa[1]);
    free(sa);
    sl_hair_free(&h);
}

static void expect_scene_error(const char *quality, const char *want) {
    char text[512];
    snprintf(text, sizeof text,
             "{\"hair\":{\"procedural\":{}},\"environment\":{\"lobes\":\"l.json\"},"
             "\"quality\":{%s}}",
             quality);
    sl_scene s;
    sl_err e = {{0}};
    CHECK(sl_scene_parse(text, strlen(text), "dir/scene.json", &s, &e) == -1);
    if (!strstr(e.msg, want)) fprintf(stderr, "  got \"%s\", want \"%s\"\n", e.msg, want);
    CHECK(strstr(e.msg, want) != NULL);
}

TEST(scene_strands_scene_keys) {
    sl_scene s;
    sl_err e;
    const char *t0 = "{\"hair\":{\"procedural\":{}},\"environment\":{\"lobes\":\"l.json\"}}";
    CHECK(sl_scene_parse(t0, strlen(t0), "dir/scene.json", &s, &e) == 0);
    /* defaults unchanged (docs/frame.md) */
    CHECK(s.lobe_threshold == 1e-3 && s.point_threshold == 1e-4);
    CHECK(s.ms_auto_threshold == 0.02 && s.auto_fragment_px == 24.0);
    CHECK(s.strand_sigma_a[0] == 0 && s.strand_sigma_a_colors == 0);
    const char *t1 = "{\"hair\":{\"procedural\":{}},\"environment\":{\"lobes\":\"l.json\"},"
                     "\"material\":{\"sigma_a\":0.5,\"strand_sigma_a\":\"paint/p.csv\"},"
                     "\"quality\":{\"lobe_threshold\":0.01,\"point_threshold\":0,"
                     "\"ms_auto_threshold\":0.5,\"auto_fragment_px\":8}}";
    CHECK(sl_scene_parse(t1, strlen(t1), "dir/scene.json", &s, &e) == 0);
    CHECK(strcmp(s.strand_sigma_a, "dir/paint/p.csv") == 0);
    CHECK(s.material.sigma_a[0] == 0.5); /* the rest of the material still read */
    CHECK(s.lobe_threshold == 0.01 && s.point_threshold == 0);
    CHECK(s.ms_auto_threshold == 0.5 && s.auto_fragment_px == 8);
    const char *t2 = "{\"hair\":{\"procedural\":{}},\"environment\":{\"lobes\":\"l.json\"},"
                     "\"material\":{\"strand_sigma_a\":3}}";
    CHECK(sl_scene_parse(t2, strlen(t2), "dir/scene.json", &s, &e) == -1);
    CHECK(strstr(e.msg, "dir/scene.json: material.strand_sigma_a: expected \"colors\" or a CSV "
                        "path") != NULL);
    const char *t3 = "{\"hair\":{\"procedural\":{}},\"environment\":{\"lobes\":\"l.json\"},"
                     "\"material\":{\"strand_sigma_a\":\"colors\",\"bogus\":1}}";
    CHECK(sl_scene_parse(t3, strlen(t3), "dir/scene.json", &s, &e) == -1);
    CHECK(strstr(e.msg, "bogus") != NULL); /* unknown keys are still errors */
    expect_scene_error("\"lobe_threshold\":1", "dir/scene.json: quality.lobe_threshold: must be in "
                                               "[0, 1)");
    expect_scene_error("\"lobe_threshold\":-0.1", "quality.lobe_threshold: must be in [0, 1)");
    expect_scene_error("\"point_threshold\":\"x\"", "quality.point_threshold");
    expect_scene_error("\"ms_auto_threshold\":1.5", "quality.ms_auto_threshold: must be in [0, 1]");
    expect_scene_error("\"auto_fragment_px\":0", "quality.auto_fragment_px: must be in (0, 1e6]");
}

/* "colors" maps by Chiang's Eq. 9 whatever quality.multiple_scattering says: sigma_a is the
 * fiber's (the path tracer, which scatters every order, reads the same value). A session-8
 * branch mapped by a single-scattering inverse when MS was off; the ground truth of one
 * physical scene then depended on a render setting. */
TEST(scene_strands_colors_independent_of_ms) {
    const float col[6][3] = {{0.5f, 0.3f, 0.1f}, {0.5f, 0.3f, 0.1f}, {0.5f, 0.3f, 0.1f},
                             {0.5f, 0.3f, 0.1f}, {0.5f, 0.3f, 0.1f}, {0.5f, 0.3f, 0.1f}};
    char path[4200], sp[4200];
    snprintf(path, sizeof path, "%s/colors_ms.hair", sl_test_tmpdir());
    snprintf(sp, sizeof sp, "%s/colors_ms.json", sl_test_tmpdir());
    CHECK(write_tiny_hair(path, col) == 0);
    sl_hair h;
    sl_err e;
    CHECK(sl_hair_load(path, &h, &e) == 0);
    const char *ms[3] = {"off", "on", "auto"};
    for (int k = 0; k < 3; k++) {
        char text[300];
        snprintf(text, sizeof text,
                 "{\"hair\":{\"file\":\"colors_ms.hair\"},\"material\":{\"strand_sigma_a\":"
                 "\"colors\"},\"environment\":{\"lobes\":\"l.json\"},\"quality\":{"
                 "\"multiple_scattering\":\"%s\"}}",
                 ms[k]);
        sl_scene s;
        CHECK(sl_scene_parse(text, strlen(text), sp, &s, &e) == 0);
        float *sa = NULL;
        CHECK(sl_scene_strand_sigma_a(&s, &h, &sa, &e) == 0);
        double bn = sl_chiang_beta_m(s.material.beta[0] / sqrt(2.0));
        for (int q = 0; sa && q < 3; q++) /* Eq. 9 by hand: (ln c / d(bn))^2 */
            CHECK_REL(sa[q],
                      pow(log(col[0][q]) / (5.969 - 0.215 * bn + 2.532 * bn * bn -
                                            10.73 * pow(bn, 3) + 5.574 * pow(bn, 4) +
                                            0.245 * pow(bn, 5)),
                          2),
                      1e-6); /* stored as float */
        free(sa);
    }
    sl_hair_free(&h);
}
