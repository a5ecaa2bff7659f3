/* test_envmap.c: the lat-long frame, solid angles, statistics, clamping and the Radiance .hdr
 * decoder of host/io/envmap/envmap*.c, on small maps built here byte by byte (expected values come from
 * the RGBE definition in ../shared/data/README.md, value = m * 2^(E-136), computed in double). */
#include "io/envmap/envmap.h"
#include "test.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const double PI_ = 3.14159265358979323846;

/* ---- frame ---- */

TEST(envmap_dir_frame) {
    double d[3];
    /* The exact image centre (between the 4 middle pixels) looks down -Z (numerics.md sec. 4). */
    sl_envmap_dir(64, 32, 31.5, 15.5, d);
    CHECK_NEAR(d[0], 0, 1e-12);
    CHECK_NEAR(d[1], 0, 1e-12);
    CHECK_NEAR(d[2], -1, 1e-12);
    /* A quarter of the width: ph = -pi/2, direction -X on the equator. */
    sl_envmap_dir(64, 32, 15.5, 15.5, d);
    CHECK_NEAR(d[0], -1, 1e-12);
    CHECK_NEAR(d[2], 0, 1e-12);
    /* Row 0 is near the zenith: th = pi/64 for a 32-row map. */
    sl_envmap_dir(64, 32, 0, 0, d);
    CHECK_NEAR(d[1], cos(PI_ / 64), 1e-12);
    /* Round trip for a spread of continuous pixel positions. */
    unsigned s = 12345;
    for (int i = 0; i < 200; i++) {
        s = s * 1103515245u + 12345u;
        double x = (s >> 8) % 1000 / 1000.0 * 100 - 0.49;
        s = s * 1103515245u + 12345u;
        double y = (s >> 8) % 1000 / 1000.0 * 49 - 0.49;
        double x2, y2;
        sl_envmap_dir(100, 50, x, y, d);
        CHECK_NEAR(d[0] * d[0] + d[1] * d[1] + d[2] * d[2], 1, 1e-12);
        sl_envmap_dir_to_pixel(100, 50, d, &x2, &y2);
        CHECK_NEAR(x2, x, 1e-9); /* double round trip through trig: ~1e-13 in practice */
        CHECK_NEAR(y2, y, 1e-9);
    }
}

TEST(envmap_solid_angle) {
    /* The pixels cover the sphere exactly once. */
    int w = 40, h = 20;
    double sum = 0;
    for (int y = 0; y < h; y++)
        sum += w * sl_envmap_pixel_solid_angle(w, h, y);
    CHECK_NEAR(sum, 4 * PI_, 1e-12);
    /* Independent: integrate sin(th) dth over row 7 with a fine midpoint rule. */
    double a = PI_ * 7 / h, b = PI_ * 8 / h, integ = 0;
    int n = 10000;
    for (int i = 0; i < n; i++)
        integ += sin(a + (b - a) * (i + 0.5) / n) * (b - a) / n;
    CHECK_REL(sl_envmap_pixel_solid_angle(w, h, 7), 2 * PI_ / w * integ, 1e-8);
}

/* ---- statistics ---- */

TEST(envmap_stats_small_map) {
    sl_envmap m;
    memset(&m, 0, sizeof m);
    m.width = 4;
    m.height = 2;
    float px[24];
    for (int i = 0; i < 8; i++) {
        px[3 * i] = (float)i;
        px[3 * i + 1] = (float)(2 * i);
        px[3 * i + 2] = 1.0f;
    }
    m.rgb = px;
    sl_envmap_stats s;
    sl_envmap_stats_compute(&m, &s);
    /* Independent expectations: rows of a 2-row map each cover half the sphere (2pi), so the
     * solid-angle mean is the plain mean here; Y of pixel i = 0.2126 i + 0.7152 2i + 0.0722. */
    double ysum = 0;
    for (int i = 0; i < 8; i++)
        ysum += 0.2126 * i + 0.7152 * 2 * i + 0.0722;
    CHECK_NEAR(s.lum_mean_pixel, ysum / 8, 1e-12);
    CHECK_NEAR(s.lum_mean_solid_angle, ysum / 8, 1e-12);
    CHECK_NEAR(s.lum_min, 0.0722, 1e-12);
    CHECK_NEAR(s.lum_max, 0.2126 * 7 + 0.7152 * 14 + 0.0722, 1e-12);
    CHECK(s.max_x == 3 && s.max_y == 1);
    CHECK_NEAR(s.rgb_mean_pixel[0], 3.5, 1e-12);
    CHECK_NEAR(s.rgb_mean_solid_angle[1], 7.0, 1e-12);
    CHECK_NEAR(s.max_elev_deg, -45.0, 1e-12);
}

/* ---- clamping ---- */

TEST(envmap_sanitize_counts_and_modes) {
    float src[12] = {1, -2, 3, NAN, 0.5f, INFINITY, -0.0f, -1e-9f, 4, 5, 6, 7};
    sl_envmap m;
    memset(&m, 0, sizeof m);
    m.width = 2;
    m.height = 2;
    m.rgb = malloc(sizeof src);
    memcpy(m.rgb, src, sizeof src);
    sl_err e;
    CHECK(sl_envmap_sanitize(&m, "x.exr", SL_NONFINITE_ERROR, &e) == -1);
    CHECK(strstr(e.msg, "x.exr") && strstr(e.msg, "2 non-finite"));
    CHECK(sl_envmap_sanitize(&m, "x.exr", SL_NONFINITE_CLAMP_QUIET, &e) == 0);
    CHECK(m.nonfinite == 2);
    CHECK(m.negatives == 2); /* -2 and -1e-9; -0 is not below 0 */
    for (int i = 0; i < 12; i++)
        CHECK(isfinite(m.rgb[i]) && m.rgb[i] >= 0);
    CHECK(m.rgb[0] == 1 && m.rgb[1] == 0 && m.rgb[3] == 0 && m.rgb[5] == 0 && m.rgb[11] == 7);
    uint64_t h1 = m.hash;
    m.rgb[11] = 8;
    sl_envmap_sanitize(&m, "x.exr", SL_NONFINITE_CLAMP_QUIET, &e);
    CHECK(m.hash != h1);
    m.rgb[11] = 7;
    sl_envmap_sanitize(&m, "x.exr", SL_NONFINITE_CLAMP_QUIET, &e);
    CHECK(m.hash == h1);
    sl_envmap_free(&m);
}

/* ---- Radiance .hdr ---- */

typedef struct bytes {
    unsigned char d[8192];
    size_t n;
} bytes;

static void put(bytes *b, const void *p, size_t n) {
    memcpy(b->d + b->n, p, n);
    b->n += n;
}
static void puts_(bytes *b, const char *s) {
    put(b, s, strlen(s));
}

/* RGBE pixel used in the test images: deterministic, varied exponents. */
static void test_rgbe(int x, int y, unsigned char q[4]) {
    q[0] = (unsigned char)(17 * x + 3 * y);
    q[1] = (unsigned char)(128 + x);
    q[2] = (unsigned char)(5 * y);
    q[3] = (unsigned char)((x + y) % 5 == 0 ? 0 : 120 + (x + 2 * y) % 20);
}

static double rgbe_value(const unsigned char q[4], int c) {
    return q[3] == 0 ? 0.0 : q[c] * ldexp(1.0, q[3] - 136); /* README: m * 2^(E-136) */
}

static void header(bytes *b, int w, int h) {
    char res[64];
    snprintf(res, sizeof res, "-Y %d +X %d\n", h, w);
    puts_(b, "#?RADIANCE\n# a comment\nFORMAT=32-bit_rle_rgbe\nGAMMA=1\n\n");
    puts_(b, res);
}

/* Flat file (w < 8 is always flat for stb). */
static void make_flat(bytes *b, int w, int h) {
    b->n = 0;
    header(b, w, h);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            unsigned char q[4];
            test_rgbe(x, y, q);
            put(b, q, 4);
        }
}

/* New-style RLE file: each component as one run of the first 5 values' pattern, then dumps. */
static void make_rle(bytes *b, int w, int h) {
    b->n = 0;
    header(b, w, h);
    for (int y = 0; y < h; y++) {
        unsigned char lead[4] = {2, 2, (unsigned char)(w >> 8), (unsigned char)(w & 255)};
        put(b, lead, 4);
        for (int k = 0; k < 4; k++) {
            unsigned char comp[256];
            for (int x = 0; x < w; x++) {
                unsigned char q[4];
                test_rgbe(x < 5 ? 0 : x, y, q); /* x 0..4 equal: a run */
                comp[x] = q[k];
            }
            unsigned char run[2] = {128 + 5, comp[0]};
            put(b, run, 2);
            int i = 5;
            while (i < w) {
                int c = w - i > 128 ? 128 : w - i;
                unsigned char cnt = (unsigned char)c;
                put(b, &cnt, 1);
                put(b, comp + i, (size_t)c);
                i += c;
            }
        }
    }
}

static void check_pixels(const sl_envmap *m, int w, int h, int rle) {
    CHECK(m->width == w && m->height == h);
    int bad = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            unsigned char q[4];
            test_rgbe(rle && x < 5 ? 0 : x, y, q);
            for (int c = 0; c < 3; c++)
                bad += m->rgb[3 * (y * w + x) + c] != (float)rgbe_value(q, c); /* exact: m*2^k */
        }
    CHECK_MSG(bad == 0, "%d values differ", bad);
}

TEST(envmap_hdr_flat_and_rle) {
    bytes *b = malloc(sizeof *b);
    sl_envmap m;
    sl_err e;
    make_flat(b, 5, 3);
    CHECK(sl_envmap_load_memory(b->d, b->n, "flat.hdr", 0, &m, &e) == 0);
    check_pixels(&m, 5, 3, 0);
    CHECK(strcmp(m.format, "Radiance RGBE") == 0 && m.negatives == 0);
    sl_envmap_free(&m);
    make_rle(b, 200, 4); /* > 128 wide: the dumps need two count bytes */
    CHECK(sl_envmap_load_memory(b->d, b->n, "rle.hdr", 0, &m, &e) == 0);
    check_pixels(&m, 200, 4, 1);
    sl_envmap_free(&m);
    free(b);
}

static void expect_fail(const unsigned char *d, size_t n, const char *want) {
    sl_envmap m;
    sl_err e;
    e.msg[0] = 0;
    int rc = sl_envmap_load_memory(d, n, "bad.hdr", 0, &m, &e);
    CHECK_MSG(rc == -1 && strstr(e.msg, "bad.hdr") && strstr(e.msg, want),
              "rc %d, message '%s' lacks '%s'", rc, e.msg, want);
    if (rc == 0) sl_envmap_free(&m);
}

TEST(envmap_hdr_every_truncation_fails) {
    bytes *b = malloc(sizeof *b);
    make_rle(b, 40, 3);
    int ok = 0;
    for (size_t n = 0; n < b->n; n++) {
        sl_envmap m;
        sl_err e;
        if (sl_envmap_load_memory(b->d, n, "t.hdr", 0, &m, &e) == 0) {
            ok++;
            sl_envmap_free(&m);
        } else {
            CHECK_MSG(strstr(e.msg, "t.hdr") != NULL, "%s", e.msg);
        }
    }
    CHECK_MSG(ok == 0, "%d truncated files loaded", ok);
    make_flat(b, 6, 4);
    for (size_t n = 0; n < b->n; n++) {
        sl_envmap m;
        sl_err e;
        if (sl_envmap_load_memory(b->d, n, "t.hdr", 0, &m, &e) == 0) {
            ok++;
            sl_envmap_free(&m);
        }
    }
    CHECK_MSG(ok == 0, "%d truncated flat files loaded", ok);
    free(b);
}

TEST(envmap_hdr_bad_headers) {
    bytes *b = malloc(sizeof *b);
    expect_fail((const unsigned char *)"", 0, "empty");
    expect_fail((const unsigned char *)"GIF89a....", 10, "unrecognised magic");
    /* each header and the word its error must name */
    static const struct {
        const char *header, *want;
    } bad[] = {
        {"#?RADIANCE\n\n-Y 2 +X 2\n", "FORMAT"},
        {"#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 2 +X 2\n", "xyze"},
        {"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n+Y 2 +X 2\n0000000000000000", "resolution"},
        {"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 0 +X 2\n", "size"},
        {"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 100000\n", "implausible"},
        /* 32 Mpixel from a 45-byte file */
        {"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4096 +X 8192\n", "implausible"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        b->n = 0;
        puts_(b, bad[i].header);
        expect_fail(b->d, b->n, bad[i].want);
    }
    /* RLE scanline with the wrong length. */
    make_rle(b, 20, 2);
    bytes *c = malloc(sizeof *c);
    memcpy(c, b, sizeof *b);
    size_t lead = 0;
    for (size_t i = 0; i + 3 < c->n; i++)
        if (c->d[i] == 2 && c->d[i + 1] == 2 && c->d[i + 2] == 0 && c->d[i + 3] == 20) {
            lead = i;
            break;
        }
    CHECK(lead > 0);
    c->d[lead + 3] = 21;
    expect_fail(c->d, c->n, "length 21");
    /* A run longer than what is left of the scanline. */
    memcpy(c, b, sizeof *b);
    c->d[lead + 4] = 128 + 30;
    expect_fail(c->d, c->n, "corrupt");
    free(c);
    free(b);
}

TEST(envmap_load_file_errors) {
    char path[600];
    sl_envmap m;
    sl_err e;
    CHECK(sl_envmap_load(sl_test_tmpdir(), 0, &m, &e) == -1);
    CHECK(strstr(e.msg, "directory") != NULL);
    snprintf(path, sizeof path, "%s/envmap_missing.hdr", sl_test_tmpdir());
    CHECK(sl_envmap_load(path, 0, &m, &e) == -1);
    CHECK(strstr(e.msg, path) != NULL);
    snprintf(path, sizeof path, "%s/envmap_empty.exr", sl_test_tmpdir());
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL);
    if (f) fclose(f);
    CHECK(sl_envmap_load(path, 0, &m, &e) == -1);
    CHECK(strstr(e.msg, path) && strstr(e.msg, "empty"));
    CHECK(sl_envmap_info(path, stdout, &e) == -1);
}

TEST(envmap_info_small_file) {
    bytes *b = malloc(sizeof *b);
    make_flat(b, 6, 3);
    char path[600], outp[600];
    snprintf(path, sizeof path, "%s/envmap_info.hdr", sl_test_tmpdir());
    snprintf(outp, sizeof outp, "%s/envmap_info.txt", sl_test_tmpdir());
    FILE *f = fopen(path, "wb");
    fwrite(b->d, 1, b->n, f);
    fclose(f);
    f = fopen(outp, "w+");
    sl_err e;
    CHECK(sl_envmap_info(path, f, &e) == 0);
    rewind(f);
    char text[4096];
    size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = 0;
    fclose(f);
    CHECK(strstr(text, "size: 6 x 3") != NULL);
    CHECK(strstr(text, "Radiance RGBE") != NULL);
    CHECK(strstr(text, "non-finite values: 0") != NULL);
    free(b);
}

/* Regression (found by fuzz_envmap: stb_image looped forever): stb keeps header lines as C
 * strings, so a line starting with a NUL byte ends the header. The structure check must read the
 * header the same way, here accepting this complete 2 x 1 flat file exactly as stb does. */
TEST(envmap_hdr_nul_line_ends_header) {
    static const unsigned char d[] = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\0junk\n-Y 1 +X 2\n"
                                     "\x80\x40\x20\x81"
                                     "\x10\x20\x30\x80";
    sl_envmap m;
    sl_err e;
    CHECK_MSG(sl_envmap_load_memory(d, sizeof d - 1, "nul.hdr", 0, &m, &e) == 0, "%s", e.msg);
    if (!m.rgb) return;
    CHECK(m.width == 2 && m.height == 1);
    CHECK(m.rgb[0] == 128 * ldexp(1.0, 0x81 - 136) && m.rgb[5] == 48 * ldexp(1.0, 0x80 - 136));
    sl_envmap_free(&m);
}
