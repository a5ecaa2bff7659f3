/* csv.h: the small CSV dialect of `strandlight eval` (numerics.md sec. 5, docs/eval.md).
 *
 *   sl_csv csv;
 *   if (sl_csv_parse(text, len, "<stdin>", &csv, &e)) ... "<stdin>:3: theta_i: 'x' is not a number"
 *   int c = sl_csv_find(&csv, "theta_i");            (-1 when the column is absent)
 *   double v; sl_csv_number(&csv, row, c, &v, &e);   (finite, else an error naming the line)
 *   ... sl_csv_free(&csv);
 *
 * Dialect: comma-separated, a header line of column names is required (line 1), one record per
 * line, no quoting (a '"' anywhere is an error), LF or CRLF line endings, an optional UTF-8 BOM,
 * a missing final newline and blank trailing lines are tolerated; a blank line between records
 * is an error. Spaces and tabs around a name or a number are ignored; the row text itself is
 * kept exactly as given so it can be copied through. Line numbers count from 1 at the header.
 *
 * sl_buf is the growable output buffer that eval writes into before anything goes to stdout. */
#ifndef SL_CSV_H
#define SL_CSV_H

#include "base/common.h"

typedef struct sl_csv {
    char *text;         /* owned copy of the input; lines are NUL-terminated in place */
    const char *header; /* the header line as given (without its line ending) */
    size_t ncols;
    char **names; /* ncols trimmed column names (point into names_buf) */
    char *names_buf;
    size_t nrows;
    const char **rows;   /* nrows row texts as given (without line endings) */
    long *line_no;       /* 1-based input line of each row */
    const char **fields; /* nrows * ncols trimmed fields (point into fields_buf) */
    char *fields_buf;
    const char *src; /* name used in messages, e.g. "<stdin>" */
} sl_csv;

/* Parses a whole input. Errors (one line, "SRC:LINE: problem"): empty input, a first line that
 * holds a number (no header), an empty or duplicate column name, a quote, a NUL byte, a row with
 * the wrong number of fields, a blank line between records. */
int sl_csv_parse(const char *text, size_t len, const char *src, sl_csv *csv, sl_err *e);
void sl_csv_free(sl_csv *csv);

/* Index of the column called name, or -1. */
int sl_csv_find(const sl_csv *csv, const char *name);
/* The number in (row, col): "SRC:LINE: NAME: 'txt' is not a number" / "...: is not finite". */
int sl_csv_number(const sl_csv *csv, size_t row, int col, double *out, sl_err *e);
/* True when s (spaces/tabs around it ignored) is entirely a number that strtod accepts. */
int sl_csv_is_number(const char *s);

/* Growable text buffer (aborts on out-of-memory like sl_malloc). */
typedef struct sl_buf {
    char *p;
    size_t len, cap;
} sl_buf;
void sl_buf_add(sl_buf *b, const char *s, size_t n);
void sl_buf_puts(sl_buf *b, const char *s);
void sl_buf_printf(sl_buf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void sl_buf_free(sl_buf *b);

/* Reads all of fp (e.g. stdin) into memory (NUL-terminated). */
int sl_read_stream(FILE *fp, const char *name, char **data, size_t *size, sl_err *e);

#endif
