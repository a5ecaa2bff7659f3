/* fuzz_report_exact.c: libFuzzer target for the exact-values CSV of `strandlight report --kernel
 * srbf --exact FILE` (sl_srbf_exact_parse, verify/report/report_srbf.h; sl_srbf_exact_read is it
 * plus the file read). Input: one byte whose value mod 5 is the number of rows the report asks
 * for (0..4), then the CSV. The sample it must match is a fixed small one built here (short
 * decimal values, so that seeds and mutations can match it), not the seeded report sample,
 * which keeps srbf_sample.c and the materials out of this target.
 * Checks: on success out[i] holds cfg[i] and four finite values; on failure the message is one
 * non-empty line that starts with the file name. The CSV is an exact-size copy (no NUL) so ASan
 * catches a read past its end. Seeds: test/fuzz/corpus/fuzz_report_exact/.
 */
// clang-format off
/* FUZZ_SOURCES: host/verify/report/srbf_exact_csv.c host/base/csv.c host/base/common.c */
// clang-format on
#include "verify/report/report_srbf.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size < 1) return 0;
    int n = data[0] % 5;
    data++;
    size--;
    char *text = malloc(size ? size : 1);
    if (size) memcpy(text, data, size);
    sl_srbf_config cfg[4];
    for (int i = 0; i < 4; i++)
        cfg[i] = (sl_srbf_config){i, 0.25 * i, 0.5, -0.125 * i, 1.5, 0.01 * (i + 1)};
    sl_srbf_exact out[4];
    memset(out, 0xff, sizeof out);
    sl_err e = {{0}};
    if (sl_srbf_exact_parse(text, size, "fuzz.csv", cfg, n, out, &e) == 0) {
        for (int i = 0; i < n; i++) {
            const sl_srbf_config *a = &out[i].c, *b = &cfg[i];
            if (a->material != b->material || a->theta_o != b->theta_o || a->phi_o != b->phi_o ||
                a->theta_j != b->theta_j || a->phi_j != b->phi_j || a->lambda != b->lambda)
                __builtin_trap();
            for (int k = 0; k < 4; k++)
                if (!isfinite(out[i].v[k])) __builtin_trap();
        }
    } else if (e.msg[0] == 0 || strchr(e.msg, '\n') || strncmp(e.msg, "fuzz.csv", 8) != 0) {
        __builtin_trap();
    }
    free(text);
    return 0;
}
