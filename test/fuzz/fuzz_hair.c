/* fuzz_hair.c: libFuzzer target for the hair loaders (cyHair, TressFX 3/4, USC .data) and the
 * .tfxproj parser, through the in-memory entry points (no file I/O).
 *
 * The first input byte selects what the rest is: (b & 3) = 0 .hair, 1 .tfx, 2 .data, 3 no
 * extension (content sniffing); bit 2 set = .tfxproj text. On success the loaded hair goes
 * through validation, bounds, tangents, up-axis conversion and follow strands; on failure the
 * message must be a single non-empty line. Seeds: test/fuzz/corpus/fuzz_hair/.
 * FUZZ_SOURCES: host/io/hair/*.c host/base/common.c */
#include "io/hair/hair.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void check_message(const sl_err *e) {
    if (e->msg[0] == 0 || strchr(e->msg, '\n')) __builtin_trap();
}

static void exercise(sl_hair *h) {
    sl_err e;
    if (sl_hair_validate(h, "fuzz", &e)) __builtin_trap(); /* the loader promised this */
    float lo[3], hi[3], t[3];
    sl_hair_bounds(h, lo, hi);
    uint32_t budget = 20000; /* keep each input fast */
    for (uint32_t s = 0; s < h->num_strands && budget; s++) {
        uint32_t n = h->strand_first[s + 1] - h->strand_first[s];
        for (uint32_t k = 0; k < n && budget; k++, budget--) {
            sl_hair_point_tangent(h, s, k, t);
            if (!isfinite(t[0]) || !isfinite(t[1]) || !isfinite(t[2])) __builtin_trap();
            if (fabsf(t[0] * t[0] + t[1] * t[1] + t[2] * t[2] - 1) > 1e-4f) __builtin_trap();
        }
    }
    sl_hair_z_up_to_y_up(h);
    if (h->num_points <= 20000) {
        sl_hair_follow f = {2, 0.5f, 3.0f, 1};
        if (sl_hair_add_follow(h, &f, &e) == 0) {
            if (h->num_strands % 3) __builtin_trap();
        } else {
            check_message(&e);
        }
    }
}

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size) {
    if (size < 1) return 0;
    static const char *names[4] = {"fuzz.hair", "fuzz.tfx", "fuzz.data", "fuzz"};
    unsigned sel = data[0];
    data++, size--;
    sl_err e;
    if (sel & 4) {
        sl_tfxproj *p = malloc(sizeof *p);
        if (sl_tfxproj_parse((const char *)data, size, "fuzz.tfxproj", p, &e) == 0) {
            if (p->num_groups < 1 || p->num_groups > SL_TFXPROJ_MAX_GROUPS) __builtin_trap();
        } else {
            check_message(&e);
        }
        free(p);
        return 0;
    }
    sl_hair h;
    if (sl_hair_load_memory(data, size, names[sel & 3], &h, &e) == 0) {
        exercise(&h);
        sl_hair_free(&h);
    } else {
        check_message(&e);
        if (h.pos || h.strand_first || h.num_points) __builtin_trap(); /* zeroed on failure */
    }
    return 0;
}
