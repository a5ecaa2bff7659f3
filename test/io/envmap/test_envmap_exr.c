/* test_envmap_exr.c: OpenEXR environment maps: scanline (written by sl_exr_write) and tiled
 * (written here with OpenEXRCore directly) files, half and float, any channel order, Y as grey,
 * unsupported channel sets, non-finite values, truncation; the OpenEXRCore path is compared with
 * the OpenEXR C++ path (two independent decoders) and with the values written. */
#include "io/envmap/envmap.h"
#include "io/image/image_write.h"
#include "test.h"

#include <openexr.h>

#include <stdlib.h>
#include <string.h>

/* Test values exactly representable in half (k/8 up to 1024 and some tiny values), so half and
 * float files must round-trip bit-exactly. */
static float val(int x, int y, int c) {
    int k = (x * 7 + y * 13 + c * 29) % 97;
    return c == 1 && x == 1 ? 0.0009765625f * (float)(y + 1) : (float)k / 8.0f;
}

static void fill_planes(int w, int h, float *r, float *g, float *b, float *a) {
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            r[i] = val(x, y, 0);
            g[i] = val(x, y, 1);
            b[i] = val(x, y, 2);
            if (a) a[i] = 1.0f;
        }
}

static int check_map(const sl_envmap *m, int w, int h, int grey) {
    int bad = 0;
    if (m->width != w || m->height != h) return -1;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 3; c++)
                bad += m->rgb[3 * ((size_t)y * w + x) + c] != val(x, y, grey ? 0 : c);
    return bad;
}

static void tmp_path(char *out, size_t n, const char *name) {
    snprintf(out, n, "%s/%s", sl_test_tmpdir(), name);
}

static unsigned char *slurp(const char *path, size_t *n) {
    unsigned char *d;
    sl_err e;
    if (sl_read_file(path, &d, n, 1 << 26, &e)) return NULL;
    return d;
}

TEST(envexr_scanline_half_float_rgba_any_order) {
    int w = 23, h = 11; /* not a multiple of the 16-line ZIP chunk */
    size_t np = (size_t)w * h;
    float *pl = malloc(4 * np * sizeof(float));
    fill_planes(w, h, pl, pl + np, pl + 2 * np, pl + 3 * np);
    /* Given in a scrambled order, plus an unrelated channel that must be ignored. */
    sl_exr_channel ch[5] = {
        {"G", pl + np}, {"A", pl + 3 * np}, {"R", pl}, {"depth.Z", pl}, {"B", pl + 2 * np}};
    for (int use_float = 0; use_float < 2; use_float++) {
        char path[600];
        tmp_path(path, sizeof path, use_float ? "envexr_f.exr" : "envexr_h.exr");
        sl_err e;
        CHECK(sl_exr_write(path, w, h, ch, 5, use_float, &e) == 0);
        sl_envmap m;
        CHECK(sl_envmap_load(path, 0, &m, &e) == 0);
        CHECK_MSG(check_map(&m, w, h, 0) == 0, "%s: pixels differ", path);
        CHECK(m.channels == 5);
        CHECK(strstr(m.format, use_float ? "float RGBA (ZIP)" : "half RGBA (ZIP)") != NULL);
        CHECK(strcmp(m.channel_names, "A,B,G,R,depth.Z") == 0); /* EXR sorts channels */
        sl_envmap_free(&m);
        /* The C++ decoder reads the same values. */
        size_t n;
        unsigned char *d = slurp(path, &n);
        CHECK(d && sl_envmap_decode_exr(d, n, path, 1, &m, &e) == 0);
        CHECK(check_map(&m, w, h, 0) == 0);
        sl_envmap_free(&m);
        free(d);
    }
    free(pl);
}

TEST(envexr_grey_and_channel_sets) {
    int w = 8, h = 4;
    size_t np = (size_t)w * h;
    float *pl = malloc(3 * np * sizeof(float));
    fill_planes(w, h, pl, pl + np, pl + 2 * np, NULL);
    char path[600];
    sl_err e;
    sl_envmap m;
    tmp_path(path, sizeof path, "envexr_y.exr");
    sl_exr_channel y[1] = {{"Y", pl}};
    CHECK(sl_exr_write(path, w, h, y, 1, 0, &e) == 0);
    CHECK(sl_envmap_load(path, 0, &m, &e) == 0);
    CHECK(check_map(&m, w, h, 1) == 0);
    CHECK(strstr(m.format, "half Y") != NULL);
    sl_envmap_free(&m);
    /* R and G only: not a colour map. */
    tmp_path(path, sizeof path, "envexr_rg.exr");
    sl_exr_channel rg[2] = {{"R", pl}, {"G", pl + np}};
    CHECK(sl_exr_write(path, w, h, rg, 2, 0, &e) == 0);
    CHECK(sl_envmap_load(path, 0, &m, &e) == -1);
    CHECK(strstr(e.msg, path) && strstr(e.msg, "unsupported channel set (G,R)"));
    /* Layered names only ("diffuse.R" ...) are not picked up either. */
    tmp_path(path, sizeof path, "envexr_layer.exr");
    sl_exr_channel lay[3] = {{"diffuse.R", pl}, {"diffuse.G", pl}, {"diffuse.B", pl}};
    CHECK(sl_exr_write(path, w, h, lay, 3, 0, &e) == 0);
    CHECK(sl_envmap_load(path, 0, &m, &e) == -1);
    CHECK(strstr(e.msg, "unsupported channel set") != NULL);
    free(pl);
}

TEST(envexr_nonfinite_and_negative) {
    int w = 4, h = 2;
    float r[8] = {1, NAN, 2, 3, -4, 5, INFINITY, 7}, g[8] = {0}, b[8] = {0};
    sl_exr_channel ch[3] = {{"R", r}, {"G", g}, {"B", b}};
    char path[600];
    tmp_path(path, sizeof path, "envexr_nan.exr");
    sl_err e;
    CHECK(sl_exr_write(path, w, h, ch, 3, 1, &e) == 0);
    sl_envmap m;
    CHECK(sl_envmap_load(path, 0, &m, &e) == -1);
    CHECK(strstr(e.msg, path) && strstr(e.msg, "2 non-finite"));
    CHECK(sl_envmap_load(path, 1, &m, &e) == 0);
    CHECK(m.nonfinite == 2 && m.negatives == 1);
    CHECK(m.rgb[3] == 0 && m.rgb[12] == 0 && m.rgb[18] == 0 && m.rgb[21] == 7);
    sl_envmap_free(&m);
}

/* Writes a tiled RGBA half file (tiles tw x th, ZIP) with OpenEXRCore directly. */
static int write_tiled(const char *path, int w, int h, int tw, int th, const float *const pl[4]) {
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exr_context_t c;
    int p;
    static const char *names[4] = {"R", "G", "B", "A"};
    if (exr_start_write(&c, path, EXR_WRITE_FILE_DIRECTLY, &init)) return -1;
    exr_result_t rv = exr_add_part(c, "main", EXR_STORAGE_TILED, &p);
    if (!rv) rv = exr_initialize_required_attr_simple(c, p, w, h, EXR_COMPRESSION_ZIP);
    if (!rv)
        rv = exr_set_tile_descriptor(c, p, (uint32_t)tw, (uint32_t)th, EXR_TILE_ONE_LEVEL,
                                     EXR_TILE_ROUND_DOWN);
    for (int i = 0; i < 4 && !rv; i++)
        rv = exr_add_channel(c, p, names[i], EXR_PIXEL_HALF, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    if (!rv) rv = exr_write_header(c);
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    int first = 1;
    for (int ty = 0; ty * th < h && !rv; ty++)
        for (int tx = 0; tx * tw < w && !rv; tx++) {
            exr_chunk_info_t ci;
            rv = exr_write_tile_chunk_info(c, p, tx, ty, 0, 0, &ci);
            if (!rv)
                rv = first ? exr_encoding_initialize(c, p, &ci, &enc)
                           : exr_encoding_update(c, p, &ci, &enc);
            first = 0;
            for (int k = 0; k < enc.channel_count && !rv; k++) {
                int j = 0;
                while (strcmp(names[j], enc.channels[k].channel_name) != 0)
                    j++;
                enc.channels[k].encode_from_ptr =
                    (const uint8_t *)(pl[j] + (size_t)ty * th * w + (size_t)tx * tw);
                enc.channels[k].user_pixel_stride = 4;
                enc.channels[k].user_line_stride = 4 * w;
                enc.channels[k].user_bytes_per_element = 4;
                enc.channels[k].user_data_type = EXR_PIXEL_FLOAT;
            }
            if (!rv) rv = exr_encoding_choose_default_routines(c, p, &enc);
            if (!rv) rv = exr_encoding_run(c, p, &enc);
        }
    exr_encoding_destroy(c, &enc);
    exr_result_t frv = exr_finish(&c);
    return rv || frv ? -1 : 0;
}

TEST(envexr_tiled_core_and_cxx_agree) {
    int w = 37, h = 19; /* edge tiles are partial in both directions */
    size_t np = (size_t)w * h;
    float *pl = malloc(4 * np * sizeof(float));
    fill_planes(w, h, pl, pl + np, pl + 2 * np, pl + 3 * np);
    const float *const planes[4] = {pl, pl + np, pl + 2 * np, pl + 3 * np};
    char path[600];
    tmp_path(path, sizeof path, "envexr_tiled.exr");
    CHECK(write_tiled(path, w, h, 16, 8, planes) == 0);
    size_t n;
    unsigned char *d = slurp(path, &n);
    CHECK(d != NULL);
    for (int cxx = 0; cxx < 2 && d; cxx++) {
        sl_envmap m;
        sl_err e;
        CHECK_MSG(sl_envmap_decode_exr(d, n, path, cxx, &m, &e) == 0, "%s", e.msg);
        CHECK_MSG(check_map(&m, w, h, 0) == 0, "%s decoder: pixels differ", cxx ? "C++" : "Core");
        CHECK(strstr(m.format, "tiled") != NULL);
        sl_envmap_free(&m);
    }
    free(d);
    free(pl);
}

TEST(envexr_every_truncation_fails) {
    int w = 9, h = 20; /* two ZIP chunks */
    size_t np = (size_t)w * h;
    float *pl = malloc(3 * np * sizeof(float));
    fill_planes(w, h, pl, pl + np, pl + 2 * np, NULL);
    sl_exr_channel ch[3] = {{"R", pl}, {"G", pl + np}, {"B", pl + 2 * np}};
    char path[600];
    tmp_path(path, sizeof path, "envexr_trunc.exr");
    sl_err e;
    CHECK(sl_exr_write(path, w, h, ch, 3, 0, &e) == 0);
    size_t n;
    unsigned char *d = slurp(path, &n);
    CHECK(d != NULL);
    int loaded = 0, unnamed = 0;
    for (size_t k = 0; d && k < n; k++) {
        for (int cxx = 0; cxx < 2; cxx++) {
            sl_envmap m;
            /* Copy so that ASan sees reads past the truncated end. */
            unsigned char *t = malloc(k ? k : 1);
            memcpy(t, d, k);
            if (k >= 4 && cxx) {
                if (sl_envmap_decode_exr(t, k, "t.exr", 1, &m, &e) == 0) {
                    loaded++;
                    sl_envmap_free(&m);
                } else {
                    unnamed += strstr(e.msg, "t.exr") == NULL;
                }
            } else if (!cxx) {
                if (sl_envmap_load_memory(t, k, "t.exr", 0, &m, &e) == 0) {
                    loaded++;
                    sl_envmap_free(&m);
                } else {
                    unnamed += strstr(e.msg, "t.exr") == NULL;
                }
            }
            free(t);
        }
    }
    CHECK_MSG(loaded == 0, "%d truncated files loaded", loaded);
    CHECK(unnamed == 0);
    /* Corrupt bytes in the pixel data: an error or a map, never a crash (ASan checks). */
    for (size_t k = n > 200 ? n - 200 : 0; d && k < n; k += 3) {
        unsigned char *t = malloc(n);
        memcpy(t, d, n);
        t[k] ^= 0x5a;
        sl_envmap m;
        if (sl_envmap_load_memory(t, n, "c.exr", 1, &m, &e) == 0) sl_envmap_free(&m);
        free(t);
    }
    free(d);
    free(pl);
}
