/* fuzz_strands.c: libFuzzer target for the painted-strand CSV (`material.strand_sigma_a`,
 * scene/scene_strands.h: strand,sigma_a_r,sigma_a_g,sigma_a_b), sl_strand_sigma_a_parse_csv
 * (sl_strand_sigma_a_read_csv is it plus the file read). Input: two bytes that give the hair's
 * strand count n (0..4095), then the CSV.
 * Checks: on success *out holds 3 n floats, every one finite and >= 0, and no more strands
 * differ from base than the input has lines after the header (a strand without a row keeps
 * base exactly); on failure *out is NULL and the message is one non-empty line that
 * starts with the file name. The CSV is an exact-size copy (no NUL) so ASan catches a read past
 * its end. Seeds: test/fuzz/corpus/fuzz_strands/.
 */
// clang-format off
/* FUZZ_SOURCES: host/scene/scene_strands.c host/base/csv.c host/base/common.c */
// clang-format on
#include "scene/scene_strands.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size < 2) return 0;
    uint32_t n = ((uint32_t)data[0] | (uint32_t)data[1] << 8) & 4095u;
    data += 2;
    size -= 2;
    char *text = malloc(size ? size : 1);
    if (size) memcpy(text, data, size);
    const float base[3] = {0.123456789f, 1.5f, 3.25f};
    float *sa = (float *)1;
    sl_err e = {{0}};
    if (sl_strand_sigma_a_parse_csv(text, size, "fuzz.csv", n, base, &sa, &e) == 0) {
        if (!sa) __builtin_trap();
        size_t lines = 1, changed = 0;
        for (size_t i = 0; i < size; i++)
            lines += text[i] == '\n' || text[i] == '\r';
        for (uint32_t s = 0; s < n; s++) {
            int differs = 0;
            for (int q = 0; q < 3; q++) {
                float v = sa[3 * (size_t)s + q];
                if (!(v >= 0) || !isfinite(v)) __builtin_trap();
                differs |= v != base[q];
            }
            changed += differs;
        }
        if (changed > lines - 1) __builtin_trap(); /* the header is one of the lines */
        free(sa);
    } else {
        if (sa != NULL) __builtin_trap();
        if (e.msg[0] == 0 || strchr(e.msg, '\n') || strncmp(e.msg, "fuzz.csv", 8) != 0)
            __builtin_trap();
    }
    free(text);
    return 0;
}
