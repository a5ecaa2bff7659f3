/* fuzz_csv.c: libFuzzer target for the `eval` CSV reader (csv.h): sl_csv_parse, then every
 * cell through sl_csv_number / sl_csv_is_number and every header name through sl_csv_find, as
 * cmd_eval does. Any input must parse into a consistent table or fail with a one-line message
 * starting with the source name; numbers that are accepted must be finite. The input is an
 * exact-size copy without a terminating NUL so ASan sees reads past the end.
 * Seeds: test/fuzz/corpus/fuzz_csv/.
 * FUZZ_SOURCES: host/base/csv.c host/base/common.c */
#include "base/csv.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check_message(const sl_err *e) {
    if (e->msg[0] == 0 || strchr(e->msg, '\n') || strncmp(e->msg, "<fuzz>", 6) != 0)
        __builtin_trap();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *text = malloc(size ? size : 1);
    if (size) memcpy(text, data, size);
    sl_csv csv;
    sl_err e = {{0}};
    if (sl_csv_parse(text, size, "<fuzz>", &csv, &e) == 0) {
        if (csv.ncols < 1) __builtin_trap();
        for (size_t c = 0; c < csv.ncols; c++) {
            int f = sl_csv_find(&csv, csv.names[c]);
            if (f != (int)c) __builtin_trap(); /* names are unique */
        }
        size_t budget = 20000; /* keep each input fast */
        for (size_t r = 0; r < csv.nrows && budget; r++) {
            if (csv.line_no[r] < 2) __builtin_trap();
            for (size_t c = 0; c < csv.ncols && budget; c++, budget--) {
                double v;
                int is_num = sl_csv_is_number(csv.fields[r * csv.ncols + c]);
                if (sl_csv_number(&csv, r, (int)c, &v, &e) == 0) {
                    if (!is_num || !isfinite(v)) __builtin_trap();
                } else {
                    check_message(&e);
                }
            }
        }
        sl_csv_free(&csv);
    } else {
        check_message(&e);
    }
    free(text);
    return 0;
}
