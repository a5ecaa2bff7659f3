/* fuzz_csv.c: libFuzzer target for the `eval` CSV reader (csv.h): sl_csv_parse, then every
 * cell through sl_csv_number / sl_csv_is_number and every header name through sl_csv_find, as
 * cmd_eval does. Any input must parse into a consistent table or fail with a one-line message
 * starting with the source name; numbers that are accepted must be finite. The input is an
 * exact-size copy without a terminating NUL so ASan sees reads past the end. The chunked reader
 * (sl_csv_reader, eval's streaming path) reads the same bytes in chunks of 3 rows: it must accept
 * exactly the inputs sl_csv_parse accepts, with the same header and rows, and fail with a
 * one-line message otherwise (not always the same one: on an input with several errors it names
 * the first in reading order).
 * Seeds: test/fuzz/corpus/fuzz_csv/.
 * FUZZ_SOURCES: host/base/csv.c host/base/common.c */
#include "base/csv.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check_message(const sl_err *e) {
    if (e->msg[0] == 0 || strchr(e->msg, '\n') || strncmp(e->msg, "<fuzz>", 6) != 0)
        __builtin_trap();
}

/* The reader over text: 0 when it accepts, after checking its rows against ref (NULL: parse
 * rejected it, so the reader must too). */
static int check_reader(const char *text, size_t size, const sl_csv *ref) {
    if (size == 0) return -1; /* fmemopen of 0 bytes is not portable; parse rejects it anyway */
    FILE *fp = fmemopen((void *)text, size, "r");
    if (!fp) __builtin_trap();
    sl_csv_reader r;
    sl_err e = {{0}};
    int rc = sl_csv_reader_open(&r, fp, "<fuzz>", &e);
    size_t row = 0;
    if (!rc) {
        if (ref && (strcmp(r.csv.header, ref->header) != 0 || r.csv.ncols != ref->ncols))
            __builtin_trap();
        while (!(rc = sl_csv_reader_next(&r, 3, &e)) && r.csv.nrows)
            for (size_t k = 0; k < r.csv.nrows && ref; k++, row++)
                if (row >= ref->nrows || strcmp(r.csv.rows[k], ref->rows[row]) != 0 ||
                    r.csv.line_no[k] != ref->line_no[row])
                    __builtin_trap();
        sl_csv_reader_close(&r);
    }
    fclose(fp);
    if (rc) check_message(&e);
    if (!rc && ref && row != ref->nrows) __builtin_trap();
    return rc;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *text = malloc(size ? size : 1);
    if (size) memcpy(text, data, size);
    sl_csv csv;
    sl_err e = {{0}};
    int parsed = sl_csv_parse(text, size, "<fuzz>", &csv, &e) == 0;
    if ((check_reader(text, size, parsed ? &csv : NULL) == 0) != parsed) __builtin_trap();
    if (parsed) {
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
