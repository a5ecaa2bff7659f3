/* test_image_write.c: EXR and PNG output of host/io/image/image_write.c: channels read back through the
 * OpenEXR C++ API (an independent decoder) and the envmap loader, half clamping, PNG pixels
 * re-read with stb_image and compared with the documented transform computed here in double,
 * and failing writes that leave nothing behind. */
#include "io/envmap/envmap.h"
#include "io/envmap/exr_cxx_shim.h"
#include "io/image/image_write.h"
#include "test.h"

#include <stb/stb_image.h>

#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static void tmp_path(char *out, size_t n, const char *name) {
    snprintf(out, n, "%s/%s", sl_test_tmpdir(), name);
}

static int read_planes(const char *path, int w, int h, int np, const char *const *names,
                       float *const *planes) {
    unsigned char *d;
    size_t n;
    sl_err e;
    char msg[256];
    if (sl_read_file(path, &d, &n, 1 << 26, &e)) return -1;
    int rc = sl_exrcxx_read_planes(d, n, w, h, np, names, planes, msg, sizeof msg);
    free(d);
    return rc;
}

/* Counts entries of dir whose name contains part. */
static int count_entries(const char *dir, const char *part) {
    DIR *dd = opendir(dir);
    int k = 0;
    if (!dd) return -1;
    struct dirent *de;
    while ((de = readdir(dd)))
        if (strstr(de->d_name, part)) k++;
    closedir(dd);
    return k;
}

TEST(imgw_exr_aov_channels_half_and_float) {
    int w = 7, h = 18;
    size_t np = (size_t)w * h;
    float *src = malloc(5 * np * sizeof(float));
    for (size_t i = 0; i < 5 * np; i++)
        src[i] = (float)(i % 251) * 0.25f - 20.0f; /* exact in half */
    src[3] = 1e6f; /* beyond half range: clamped to 65504 in half, kept in float */
    src[4] = -1e6f;
    src[5] = 1.0f / 3.0f; /* not representable in half */
    const char *names[5] = {"R", "G", "B", "R_mode.R", "depth.Z"};
    sl_exr_channel ch[5];
    for (int c = 0; c < 5; c++)
        ch[c] = (sl_exr_channel){names[c], src + c * np};
    float *got = malloc(5 * np * sizeof(float));
    float *planes[5];
    for (int c = 0; c < 5; c++)
        planes[c] = got + c * np;
    for (int use_float = 0; use_float < 2; use_float++) {
        char path[600];
        tmp_path(path, sizeof path, use_float ? "imgw_f.exr" : "imgw_h.exr");
        sl_err e;
        CHECK(sl_exr_write(path, w, h, ch, 5, use_float, &e) == 0);
        CHECK(read_planes(path, w, h, 5, names, planes) == 0);
        int bad = 0;
        for (size_t i = 0; i < 5 * np; i++) {
            double want = src[i];
            if (!use_float) {
                if (i == 3) want = 65504.0;
                if (i == 4) want = -65504.0;
                if (i == 5) want = 0.333251953125; /* 1/3 rounded to 11 significant bits */
            }
            bad += got[i] != (float)want;
        }
        CHECK_MSG(bad == 0, "%s: %d values differ", path, bad);
    }
    free(src);
    free(got);
}

TEST(imgw_exr_bad_args_and_failed_write_leave_nothing) {
    char dir[600], path[700];
    tmp_path(dir, sizeof dir, "imgw_fail");
    mkdir(dir, 0777);
    float v[4] = {1, 2, 3, 4};
    sl_exr_channel ch[2] = {{"R", v}, {"R", v}};
    sl_err e;
    snprintf(path, sizeof path, "%s/dup.exr", dir);
    CHECK(sl_exr_write(path, 2, 2, ch, 2, 0, &e) == -1);
    CHECK(strstr(e.msg, "given twice") != NULL);
    CHECK(sl_exr_write(path, 0, 2, ch, 1, 0, &e) == -1);
    /* The target is an existing directory: the rename fails after the whole file is written. */
    snprintf(path, sizeof path, "%s/isdir.exr", dir);
    mkdir(path, 0777);
    CHECK(sl_exr_write(path, 2, 2, ch, 1, 0, &e) == -1);
    CHECK(strstr(e.msg, path) != NULL);
    snprintf(path, sizeof path, "%s/isdir.png", dir);
    mkdir(path, 0777);
    float rgba[16] = {0};
    CHECK(sl_png_write(path, 2, 2, rgba, 0, &e) == -1);
    CHECK(strstr(e.msg, path) != NULL);
    /* A parent that is a file: nothing can be created. */
    snprintf(path, sizeof path, "%s/afile", dir);
    FILE *f = fopen(path, "w");
    if (f) fclose(f);
    snprintf(path, sizeof path, "%s/afile/x.exr", dir);
    CHECK(sl_exr_write(path, 2, 2, ch, 1, 0, &e) == -1);
    CHECK(sl_png_write(path, 2, 2, rgba, 0, &e) == -1);
    CHECK(count_entries(dir, ".tmp") == 0);
    CHECK(count_entries(dir, "dup") == 0);
}

/* The documented PNG transform, written out again here in double. */
static int expect_byte(double c, double a, double exposure) {
    if (a > 0) c /= a;
    c *= pow(2.0, exposure);
    double t = 0;
    if (c > 0) t = c * (2.51 * c + 0.03) / (c * (2.43 * c + 0.59) + 0.14);
    if (t > 1) t = 1;
    double s = t <= 0.0031308 ? 12.92 * t : 1.055 * pow(t, 1 / 2.4) - 0.055;
    return (int)floor(s * 255 + 0.5);
}

TEST(imgw_png_roundtrip) {
    int w = 6, h = 3;
    float rgba[72];
    for (int i = 0; i < w * h; i++) {
        rgba[4 * i + 0] = 0.05f * (float)i;
        rgba[4 * i + 1] = (float)i * (float)i * 0.3f;
        rgba[4 * i + 2] = i == 4 ? -1.0f : 0.001f * (float)i;
        rgba[4 * i + 3] = i == 7 ? 0.5f : 1.0f;
    }
    rgba[4 * 7 + 0] = 0.2f; /* premultiplied: straight colour 0.4 */
    char path[600];
    tmp_path(path, sizeof path, "imgw.png");
    sl_err e;
    for (int k = 0; k < 2; k++) {
        double exposure = k ? 1.5 : 0.0;
        CHECK(sl_png_write(path, w, h, rgba, (float)exposure, &e) == 0);
        int pw, ph, pc;
        unsigned char *px = stbi_load(path, &pw, &ph, &pc, 4);
        CHECK(px != NULL && pw == w && ph == h && pc == 4);
        if (!px) return;
        int worst = 0;
        for (int i = 0; i < w * h; i++) {
            for (int c = 0; c < 3; c++) {
                int d =
                    abs(px[4 * i + c] - expect_byte(rgba[4 * i + c], rgba[4 * i + 3], exposure));
                if (d > worst) worst = d;
            }
            CHECK(px[4 * i + 3] == (i == 7 ? 128 : 255)); /* 0.5 * 255 = 127.5 rounds up */
        }
        /* The only difference allowed is float vs double rounding at a .5 boundary. */
        CHECK_MSG(worst <= 1, "largest difference %d", worst);
        stbi_image_free(px);
    }
    /* Known anchors of the transform: 0 -> 0, huge -> 255, mid grey 0.18 -> sRGB(0.2670). */
    CHECK(expect_byte(0, 1, 0) == 0 && expect_byte(1e9, 1, 0) == 255);
    CHECK_NEAR(
        sl_tonemap_srgb(0.18f),
        1.055 * pow(0.18 * (2.51 * 0.18 + 0.03) / (0.18 * (2.43 * 0.18 + 0.59) + 0.14), 1 / 2.4) -
            0.055,
        1e-6); /* float vs double evaluation */
    CHECK(sl_tonemap_srgb(NAN) == 0 && sl_tonemap_srgb(INFINITY) == 1);
}

/* "Z" is stored as FLOAT even in a half file: a depth of 120.03 survives (half: 120.0). */
TEST(imgw_exr_depth_is_float) {
    int w = 3, h = 2;
    float z[6] = {120.03f, 1.0f / 3.0f, 1e6f, 0.5f, 7.0f, 65519.0f};
    float r[6] = {0.25f, 0.5f, 1, 2, 4, 8};
    const char *names[2] = {"R", "Z"};
    sl_exr_channel ch[2] = {{names[0], r}, {names[1], z}};
    char path[600];
    tmp_path(path, sizeof path, "imgw_z.exr");
    sl_err e;
    CHECK(sl_exr_write(path, w, h, ch, 2, 0, &e) == 0);
    float gr[6], gz[6];
    float *planes[2] = {gr, gz};
    CHECK(read_planes(path, w, h, 2, names, planes) == 0);
    for (int i = 0; i < 6; i++)
        CHECK_MSG(gz[i] == z[i] && gr[i] == r[i], "pixel %d: Z %.9g (want %.9g)", i, gz[i], z[i]);
}
