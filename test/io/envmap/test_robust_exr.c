/* test_robust_exr.c: regressions for hostile OpenEXR headers (docs/robustness.md sec. 1). The
 * C++ reader (Imf::InputFile, used for DWA files) allocates from header sizes before checking
 * them; host/io/envmap/envmap_exr.c now walks the header as the C++ reader will and refuses sizes
 * that cannot fit in the file. The inputs are the fuzz_envmap seeds (first byte: the harness's
 * selector, stripped here). */
#include "base/common.h"
#include "io/envmap/envmap.h"
#include "test.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* The seed file without its selector byte, in an exact-size buffer (ASan sees overreads). */
static unsigned char *seed(const char *file, size_t *n) {
    char path[256];
    snprintf(path, sizeof path, "test/fuzz/corpus/fuzz_envmap/%s", file);
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    unsigned char buf[65536];
    size_t got = fread(buf, 1, sizeof buf, f);
    fclose(f);
    if (got < 2) return NULL;
    *n = got - 1;
    unsigned char *d = malloc(*n);
    memcpy(d, buf + 1, *n);
    return d;
}

/* A ~1.3 KB file whose header (as the C++ reader parses it) declares a 1,678,311,424-byte opaque
 * attribute: before the fix the load allocated 1.6 GB (libFuzzer OOM); now it is refused with a
 * one-line message naming the file, the size and what remains. Both the DWA dispatch (the file
 * says DWAB) and a forced C++ decode go through the check. */
TEST(robust_exr_hostile_attribute_refused) {
    size_t n = 0;
    unsigned char *d = seed("exr_oom_opaque_attribute", &n);
    CHECK(d != NULL);
    if (!d) return;
    for (int cxx = 0; cxx < 2; cxx++) {
        sl_envmap m;
        sl_err e;
        CHECK(sl_envmap_decode_exr(d, n, "hostile.exr", cxx, &m, &e) == -1);
        CHECK_MSG(strncmp(e.msg, "hostile.exr: ", 13) == 0, "%s", e.msg);
        CHECK_MSG(strstr(e.msg, "declares 1678311424 bytes") != NULL, "%s", e.msg);
        CHECK_MSG(strstr(e.msg, "remain in the file") != NULL, "%s", e.msg);
        CHECK(strchr(e.msg, '\n') == NULL);
    }
    free(d);
}

/* The valid seed the hostile file was mutated from still loads, through Core and forced
 * through the C++ reader (whose header walk must accept it), with the same pixels. */
TEST(robust_exr_valid_seed_loads_both_ways) {
    size_t n = 0;
    unsigned char *d = seed("exr_16x12_half", &n);
    CHECK(d != NULL);
    if (!d) return;
    sl_envmap a, b;
    sl_err e;
    CHECK_MSG(sl_envmap_decode_exr(d, n, "seed.exr", 0, &a, &e) == 0, "%s", e.msg);
    CHECK_MSG(sl_envmap_decode_exr(d, n, "seed.exr", 1, &b, &e) == 0, "%s", e.msg);
    CHECK(a.width == 16 && a.height == 12 && b.width == 16 && b.height == 12);
    /* Both decoders convert the same half values to float: bit-identical, tolerance 0. */
    if (a.rgb && b.rgb) CHECK(memcmp(a.rgb, b.rgb, 16 * 12 * 3 * sizeof(float)) == 0);
    sl_envmap_free(&a);
    sl_envmap_free(&b);
    free(d);
}

/* ---- decode limits from the header (issue 21, envmap.h sl_decode_budget_ok) ---- */

static size_t put_attr(unsigned char *b, size_t o, const char *name, const char *type,
                       const void *data, int len) {
    size_t nl = strlen(name) + 1, tl = strlen(type) + 1;
    memcpy(b + o, name, nl);
    memcpy(b + o + nl, type, tl);
    memcpy(b + o + nl + tl, &len, 4);
    memcpy(b + o + nl + tl + 4, data, (size_t)len);
    return o + nl + tl + 4 + (size_t)len;
}

/* A valid header (B, G, R half) declaring w x h with compression comp (9: DWAB, 3: ZIP), its
 * line-offset table, and zero-filled chunks up to size bytes (as test/cli/exr_header_bomb.py;
 * little-endian host). A loader that bounds its work from the header never reads the chunks. */
static unsigned char *header_bomb(int w, int h, int comp, size_t size, size_t *n) {
    unsigned char *b = calloc(1, size);
    static const unsigned char magic[8] = {0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0};
    memcpy(b, magic, 8);
    unsigned char chl[64];
    size_t c = 0;
    for (int k = 0; k < 3; k++) {
        int32_t f[4] = {1, 0, 1, 1}; /* half; pLinear + reserved; x, y sampling */
        chl[c++] = (unsigned char)"BGR"[k];
        chl[c++] = 0;
        memcpy(chl + c, f, 16);
        c += 16;
    }
    chl[c++] = 0;
    int32_t box[4] = {0, 0, w - 1, h - 1};
    float one = 1.0f, v2[2] = {0, 0};
    unsigned char cm = (unsigned char)comp, lo = 0;
    size_t o = 8;
    o = put_attr(b, o, "channels", "chlist", chl, (int)c);
    o = put_attr(b, o, "compression", "compression", &cm, 1);
    o = put_attr(b, o, "dataWindow", "box2i", box, 16);
    o = put_attr(b, o, "displayWindow", "box2i", box, 16);
    o = put_attr(b, o, "lineOrder", "lineOrder", &lo, 1);
    o = put_attr(b, o, "pixelAspectRatio", "float", &one, 4);
    o = put_attr(b, o, "screenWindowCenter", "v2f", v2, 8);
    o = put_attr(b, o, "screenWindowWidth", "float", &one, 4);
    b[o++] = 0;
    int lpc = comp == 9 ? 256 : comp == 3 ? 16 : 1;
    size_t nchunks = (size_t)((h + lpc - 1) / lpc), table = o + 8 * nchunks;
    size_t per = (size - table) / nchunks;
    for (size_t i = 0; i < nchunks; i++) {
        uint64_t off = table + i * per;
        memcpy(b + o + 8 * i, &off, 8);
        int32_t ch[2] = {(int32_t)i * lpc, (int32_t)(per - 8)};
        memcpy(b + off, ch, 8);
    }
    *n = size;
    return b;
}

/* The 49 KB DWAB file of the issue declares 16384 x 8192: before, `info` decoded it for 13.6 s
 * into 3.16 GB; now the header alone refuses it, naming the file, the limit and the variable. */
TEST(robust_exr_decode_memory_limit) {
    size_t n;
    unsigned char *d = header_bomb(16384, 8192, 9, 49152, &n);
    unsetenv("SL_IMAGE_MAX_MB");
    unsetenv("SL_IMAGE_MAX_RATIO");
    long before = sl_alloc_count();
    sl_envmap m;
    sl_err e = {{0}};
    CHECK(sl_envmap_decode_exr(d, n, "bomb.exr", 0, &m, &e) == -1);
    CHECK_MSG(strstr(e.msg, "bomb.exr: OpenEXR: decoding 16384 x 8192 needs 3072 MiB, over the "
                            "limit of 2048 MiB (SL_IMAGE_MAX_MB raises it)"),
              "%s", e.msg);
    CHECK_MSG(sl_alloc_count() - before < 8, "%ld allocations", sl_alloc_count() - before);
    /* with more memory allowed, the decompression ratio still refuses it (768 MiB of half RGB
     * from 48 KB: 16384 bytes per byte, where deflate cannot pass 1032) */
    setenv("SL_IMAGE_MAX_MB", "100000", 1);
    CHECK(sl_envmap_decode_exr(d, n, "bomb.exr", 0, &m, &e) == -1);
    CHECK_MSG(strstr(e.msg, "bomb.exr: OpenEXR: 16384 x 8192 decompresses to 768 MiB from a "
                            "49152-byte file, over 1100 bytes per file byte (SL_IMAGE_MAX_RATIO "
                            "raises it)"),
              "%s", e.msg);
    /* both raised: the header passes, and the (zero) chunks fail to decode instead */
    setenv("SL_IMAGE_MAX_RATIO", "1000000", 1);
    CHECK(sl_envmap_decode_exr(d, n, "bomb.exr", 0, &m, &e) == -1);
    CHECK_MSG(!strstr(e.msg, "SL_IMAGE_MAX"), "%s", e.msg);
    unsetenv("SL_IMAGE_MAX_MB");
    unsetenv("SL_IMAGE_MAX_RATIO");
    free(d);
}

/* Small images pass whatever their ratio (a flat test map of a few KB), and the limits follow
 * the variables: SL_IMAGE_MAX_MB=1 refuses a 512 x 512 RGB map (6 MiB decoded). */
TEST(robust_exr_decode_limit_setting) {
    size_t n = 0;
    unsigned char *d = seed("exr_16x12_half", &n);
    CHECK(d != NULL);
    if (!d) return;
    sl_envmap m;
    sl_err e = {{0}};
    setenv("SL_IMAGE_MAX_RATIO", "1", 1); /* the seed is 16 x 12: under the floor */
    CHECK_MSG(sl_envmap_decode_exr(d, n, "seed.exr", 0, &m, &e) == 0, "%s", e.msg);
    sl_envmap_free(&m);
    unsetenv("SL_IMAGE_MAX_RATIO");
    free(d);
    d = header_bomb(512, 512, 3, 4096, &n);
    setenv("SL_IMAGE_MAX_MB", "1", 1);
    CHECK(sl_envmap_decode_exr(d, n, "small.exr", 0, &m, &e) == -1);
    CHECK_MSG(strstr(e.msg, "small.exr: OpenEXR: decoding 512 x 512 needs 6 MiB, over the limit "
                            "of 1 MiB (SL_IMAGE_MAX_MB raises it)"),
              "%s", e.msg);
    unsetenv("SL_IMAGE_MAX_MB");
    free(d);
}
