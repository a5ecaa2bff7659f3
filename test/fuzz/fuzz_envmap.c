/* fuzz_envmap.c: libFuzzer target for the environment-map decoders (Radiance .hdr through the
 * scanline walker + stb_image, OpenEXR through OpenEXRCore and the C++ DWA shim), fed from
 * memory. The first input byte selects the path, so that both are reached without the fuzzer
 * having to find the magic bytes: byte % 4 == 1 prepends the EXR magic (76 2f 31 01), == 3 the
 * Radiance line "#?RADIANCE\n", 0 or 2 passes the rest as is (dispatch by magic); bit 2 sets
 * clamp_nonfinite. Seeds: any small .hdr/.exr with one byte (0) in front.
 * FUZZ_SOURCES: host/io/envmap/*.c host/io/envmap/*.cpp host/base/common.c */
#include "io/envmap/envmap.h"

#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size);

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size) {
    if (size < 1) return 0;
    unsigned sel = data[0];
    data++;
    size--;
    unsigned char *buf = malloc(size + 16);
    size_t n = 0;
    if (sel % 4 == 1) {
        static const unsigned char magic[4] = {0x76, 0x2f, 0x31, 0x01};
        memcpy(buf, magic, 4);
        n = 4;
    } else if (sel % 4 == 3) {
        memcpy(buf, "#?RADIANCE\n", 11);
        n = 11;
    }
    memcpy(buf + n, data, size);
    n += size;
    /* Exact-size copy so that ASan sees any read past the end. */
    unsigned char *exact = malloc(n ? n : 1);
    memcpy(exact, buf, n);
    free(buf);
    sl_envmap m;
    sl_err e;
    if (sl_envmap_load_memory(exact, n, "fuzz", sel & 4 ? 1 : 0, &m, &e) == 0) {
        sl_envmap_stats s;
        sl_envmap_stats_compute(&m, &s);
        sl_envmap_free(&m);
    }
    free(exact);
    return 0;
}
