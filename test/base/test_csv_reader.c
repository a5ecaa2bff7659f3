/* test_csv_reader.c: the chunked reader of `eval` (host/base/csv.h, sl_csv_reader; issue 21)
 * against the whole-input parser sl_csv_parse, whose every message and row test_csv.c checks
 * against literal expectations: on each input below (valid ones, and ones with a single error of
 * every kind) the reader, with chunks of 1, 2 and 1000 rows, must give the same header, the same
 * rows (text as given, line numbers, trimmed fields) in order, or the same one-line error. */
#include "base/csv.h"
#include "test.h"

#include <stdio.h>
#include <string.h>

static const char *const inputs[] = {
    "b, a ,note\n1,2.5,x y\n-3e-2 ,4, z\n",
    "a,b\r\n1,2\r\n3,4",   /* CRLF, no final newline */
    "a,b\n1,2\n\n \n\t\n", /* blank trailing lines */
    "\xEF\xBB\xBF"
    "a,b\n1,2\n", /* UTF-8 BOM */
    "a,b\n",      /* header only */
    "a\n1\n2\n3\n4\n5\n",
    "",                  /* errors: empty */
    "\n \n",             /* only blank lines */
    "\na,b\n1,2\n",      /* a blank header line */
    "\n\na,b\n1,2\n",    /* blank lines before the header */
    "a,b\n1,2\n\n3,4\n", /* a blank line between records */
    "a,b\n1,2\n3,4\n\n\n5,6\n",
    "a,b\n1,2\n3\n", /* a field count */
    "a,b\n1,2\n3,4\n5,6,7\n",
    "a,\"b\"\n1,2\n", /* a quote */
    "a,b\n1,2\n3,\"4\"\n",
    "a,a\n1,2\n",    /* a duplicate column */
    "a,,b\n1,2,3\n", /* an empty name */
    "0.5,b\n1,2\n",  /* a number for a header */
};

/* Reads text (len bytes) with chunks of max_rows into one sl_csv-like record of the rows, then
 * compares it with sl_csv_parse's. */
static void compare(const char *text, size_t len, size_t max_rows) {
    sl_csv ref;
    sl_err e_ref = {{0}}, e = {{0}};
    int rc_ref = sl_csv_parse(text, len, "<stdin>", &ref, &e_ref);
    FILE *fp = fmemopen((void *)text, len ? len : 1, "r");
    if (len == 0) fgetc(fp); /* fmemopen of 0 bytes is not portable: read the one byte away */
    CHECK(fp != NULL);
    sl_csv_reader r;
    int rc = sl_csv_reader_open(&r, fp, "<stdin>", &e);
    size_t row = 0;
    if (!rc) {
        if (!rc_ref) {
            CHECK_MSG(strcmp(r.csv.header, ref.header) == 0, "header '%s'", r.csv.header);
            CHECK(r.csv.ncols == ref.ncols);
            for (size_t c = 0; c < ref.ncols && c < r.csv.ncols; c++)
                CHECK(strcmp(r.csv.names[c], ref.names[c]) == 0);
        }
        for (;;) {
            rc = sl_csv_reader_next(&r, max_rows, &e);
            if (rc || r.csv.nrows == 0) break;
            CHECK(r.csv.nrows <= max_rows);
            for (size_t k = 0; k < r.csv.nrows && !rc_ref && row < ref.nrows; k++, row++) {
                CHECK_MSG(strcmp(r.csv.rows[k], ref.rows[row]) == 0, "row %zu '%s'", row,
                          r.csv.rows[k]);
                CHECK(r.csv.line_no[k] == ref.line_no[row]);
                for (size_t c = 0; c < ref.ncols; c++)
                    CHECK(strcmp(r.csv.fields[k * r.csv.ncols + c],
                                 ref.fields[row * ref.ncols + c]) == 0);
            }
        }
        sl_csv_reader_close(&r);
    }
    fclose(fp);
    CHECK_MSG((rc != 0) == (rc_ref != 0), "reader rc %d ('%s'), parse rc %d ('%s') on '%s'", rc,
              e.msg, rc_ref, e_ref.msg, text);
    if (rc && rc_ref)
        CHECK_MSG(strcmp(e.msg, e_ref.msg) == 0, "got '%s', want '%s'", e.msg, e_ref.msg);
    if (!rc_ref) {
        CHECK_MSG(row == ref.nrows, "%zu rows read, %zu parsed", row, ref.nrows);
        sl_csv_free(&ref);
    }
}

TEST(csv_reader_matches_parse) {
    static const size_t chunks[] = {1, 2, 1000};
    for (size_t i = 0; i < sizeof inputs / sizeof *inputs; i++)
        for (size_t c = 0; c < 3; c++)
            compare(inputs[i], strlen(inputs[i]), chunks[c]);
    /* a NUL byte (strlen would stop at it) */
    static const char nul[] = "a,b\n1,2\n3,\0"
                              "4\n";
    for (size_t c = 0; c < 3; c++)
        compare(nul, sizeof nul - 1, chunks[c]);
}
