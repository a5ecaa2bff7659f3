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
 * sl_csv_reader reads the same dialect from a stream in chunks of rows (eval's bounded-memory
 * path, issue 21): the header once, then up to max_rows rows at a time into the same sl_csv
 * layout, so a 10M-row input never has to be in memory at once:
 *
 *   sl_csv_reader r;
 *   if (sl_csv_reader_open(&r, stdin, "<stdin>", &e)) ...     (r.csv: header, names; no rows)
 *   while (!(rc = sl_csv_reader_next(&r, 65536, &e)) && r.csv.nrows) ... r.csv.rows, fields
 *   sl_csv_reader_close(&r);
 *
 * Each error is the one sl_csv_parse gives for the same line; where an input has several errors,
 * the reader names the first it meets in input order (sl_csv_parse looks for some kinds in the
 * whole input first).
 *
 * sl_buf is the growable output buffer that eval formats each chunk into. */
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

/* The chunked reader (see the top of this file). */
typedef struct sl_csv_reader {
    sl_csv csv; /* header and names; after sl_csv_reader_next, that chunk's rows */
    FILE *fp;
    long line;        /* physical lines read so far */
    long blank_first; /* first of the blank lines read but not yet known to be trailing (0: none) */
    long blank_count; /* how many */
    int at_eof;
    char *line_buf; /* getline's buffer */
    size_t line_cap;
    sl_buf text;     /* the chunk's row texts, each NUL-terminated */
    size_t *offs;    /* where each row starts in text */
    size_t rows_cap; /* capacity of offs, csv.rows, csv.line_no */
    size_t fields_cap;
} sl_csv_reader;
/* Reads lines up to the header and parses it (the same checks and messages as sl_csv_parse:
 * empty input, a number or an empty name in the header, duplicates, a quote, a NUL byte, a
 * blank line before the header). On failure everything is freed. */
int sl_csv_reader_open(sl_csv_reader *r, FILE *fp, const char *src, sl_err *e);
/* Replaces r->csv's rows with the next at most max_rows rows (csv.nrows == 0: end of input). */
int sl_csv_reader_next(sl_csv_reader *r, size_t max_rows, sl_err *e);
void sl_csv_reader_close(sl_csv_reader *r);

/* Reads all of fp (e.g. stdin) into memory (NUL-terminated). */
int sl_read_stream(FILE *fp, const char *name, char **data, size_t *size, sl_err *e);

#endif
