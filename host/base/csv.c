/* csv.c: see csv.h for the dialect. The input is copied once; lines are cut in place and each
 * row's fields are cut in a second copy so the row text stays intact for copying through. */
#include "base/csv.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

static int is_blank(char c) {
    return c == ' ' || c == '\t';
}

/* Trims spaces/tabs in place (s is a writable field). */
static char *trim(char *s) {
    while (is_blank(*s))
        s++;
    size_t n = strlen(s);
    while (n > 0 && is_blank(s[n - 1]))
        s[--n] = 0;
    return s;
}

static int blank_line(const char *s) {
    for (; *s; s++)
        if (!is_blank(*s)) return 0;
    return 1;
}

static size_t count_fields(const char *s) {
    size_t n = 1;
    for (; *s; s++)
        if (*s == ',') n++;
    return n;
}

int sl_csv_is_number(const char *s) {
    while (is_blank(*s))
        s++;
    if (!*s) return 0;
    char *end;
    (void)strtod(s, &end);
    if (end == s) return 0;
    while (is_blank(*end))
        end++;
    return *end == 0;
}

/* Splits `line` (a writable copy) at commas into out[0..n), trimming each field. */
static void split(char *line, size_t n, const char **out) {
    size_t k = 0;
    char *f = line;
    for (char *c = line;; c++) {
        if (*c == ',' || *c == 0) {
            int last = *c == 0;
            *c = 0;
            if (k < n) out[k++] = trim(f);
            if (last) break;
            f = c + 1;
        }
    }
}

void sl_csv_free(sl_csv *csv) {
    free(csv->text);
    free(csv->names);
    free(csv->names_buf);
    free(csv->rows);
    free(csv->line_no);
    free(csv->fields);
    free(csv->fields_buf);
    memset(csv, 0, sizeof *csv);
}

/* qsort has no context argument in C11: the names being sorted, per thread. */
static _Thread_local const char *const *sort_names;

static int cmp_name_index(const void *a, const void *b) {
    size_t i = *(const size_t *)a, j = *(const size_t *)b;
    int c = strcmp(sort_names[i], sort_names[j]);
    return c ? c : (i < j ? -1 : i > j);
}

/* Parses the header line (csv->header = line, which must outlive csv): column names, then the
 * checks of a number (no header), an empty name and a duplicate. */
static int parse_header(sl_csv *csv, const char *line, const char *src, sl_err *e) {
    csv->header = line;
    csv->ncols = count_fields(line);
    csv->names_buf = sl_strdup(line);
    csv->names = sl_malloc(csv->ncols * sizeof *csv->names);
    split(csv->names_buf, csv->ncols, (const char **)csv->names);
    for (size_t c = 0; c < csv->ncols; c++) {
        if (sl_csv_is_number(csv->names[c]))
            return sl_fail(e,
                           "%s:1: expected a header line naming the columns, got the number '%s' "
                           "(input needs a header)",
                           src, csv->names[c]);
        if (!csv->names[c][0]) return sl_fail(e, "%s:1: column %zu has an empty name", src, c + 1);
    }
    /* Duplicates by sorting (n log n: a header of 200 000 columns took 52 s pairwise, issue
     * 21); the one named is the first column, in header order, that repeats an earlier one. */
    size_t *ord = sl_malloc((csv->ncols ? csv->ncols : 1) * sizeof *ord);
    for (size_t c = 0; c < csv->ncols; c++)
        ord[c] = c;
    sort_names = (const char *const *)csv->names;
    qsort(ord, csv->ncols, sizeof *ord, cmp_name_index);
    size_t dup = csv->ncols;
    for (size_t k = 1; k < csv->ncols; k++)
        if (strcmp(csv->names[ord[k]], csv->names[ord[k - 1]]) == 0 && ord[k] < dup) dup = ord[k];
    free(ord);
    if (dup < csv->ncols) return sl_fail(e, "%s:1: duplicate column '%s'", src, csv->names[dup]);
    return 0;
}

int sl_csv_parse(const char *text, size_t len, const char *src, sl_csv *csv, sl_err *e) {
    memset(csv, 0, sizeof *csv);
    csv->src = src;
    if (len >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0) text += 3, len -= 3; /* UTF-8 BOM */
    csv->text = sl_malloc(len + 1);
    memcpy(csv->text, text, len);
    csv->text[len] = 0;

    /* Cut lines; remember where each starts. */
    size_t nlines = 0, cap = 64;
    char **lines = sl_malloc(cap * sizeof *lines);
    char *p = csv->text, *end = csv->text + len;
    while (p < end) {
        char *nl = memchr(p, '\n', (size_t)(end - p));
        char *stop = nl ? nl : end;
        if (memchr(p, 0, (size_t)(stop - p))) {
            free(lines);
            sl_csv_free(csv);
            return sl_fail(e, "%s:%zu: contains a NUL byte (expected text)", src, nlines + 1);
        }
        *stop = 0;
        if (stop > p && stop[-1] == '\r') stop[-1] = 0; /* CRLF */
        if (nlines == cap) lines = sl_realloc(lines, (cap *= 2) * sizeof *lines);
        lines[nlines++] = p;
        p = stop + 1;
    }
    /* Blank trailing lines (and a missing final newline) are tolerated. */
    while (nlines > 0 && blank_line(lines[nlines - 1]))
        nlines--;
    if (nlines == 0) {
        free(lines);
        sl_csv_free(csv);
        return sl_fail(e, "%s: empty input: expected a CSV header line naming the columns", src);
    }
    int rc = -1;
    for (size_t l = 0; l < nlines; l++) {
        if (strchr(lines[l], '"')) {
            sl_fail(e, "%s:%zu: quoted fields are not supported (no '\"' anywhere)", src, l + 1);
            goto done;
        }
        if (l > 0 && blank_line(lines[l])) {
            sl_fail(e, "%s:%zu: blank line between records", src, l + 1);
            goto done;
        }
    }

    /* Header. */
    if (blank_line(lines[0])) {
        sl_fail(e, "%s:1: blank line: expected a header line naming the columns", src);
        goto done;
    }
    if (parse_header(csv, lines[0], src, e)) goto done;

    /* Rows. */
    csv->nrows = nlines - 1;
    csv->rows = sl_malloc(csv->nrows * sizeof *csv->rows);
    csv->line_no = sl_malloc(csv->nrows * sizeof *csv->line_no);
    size_t total = 0;
    for (size_t r = 0; r < csv->nrows; r++) {
        const char *row = lines[r + 1];
        size_t nf = count_fields(row);
        if (nf != csv->ncols) {
            sl_fail(e, "%s:%zu: expected %zu fields like the header, got %zu", src, r + 2,
                    csv->ncols, nf);
            goto done;
        }
        csv->rows[r] = row;
        csv->line_no[r] = (long)(r + 2);
        total += strlen(row) + 1;
    }
    csv->fields_buf = sl_malloc(total ? total : 1);
    size_t ncells = csv->nrows * csv->ncols;
    csv->fields = sl_malloc((ncells > 0 ? ncells : 1) * sizeof *csv->fields);
    char *q = csv->fields_buf;
    for (size_t r = 0; r < csv->nrows; r++) {
        size_t n = strlen(csv->rows[r]) + 1;
        memcpy(q, csv->rows[r], n);
        split(q, csv->ncols, csv->fields + r * csv->ncols);
        q += n;
    }
    rc = 0;
done:
    free(lines);
    if (rc) sl_csv_free(csv);
    return rc;
}

int sl_csv_find(const sl_csv *csv, const char *name) {
    for (size_t c = 0; c < csv->ncols; c++)
        if (strcmp(csv->names[c], name) == 0) return (int)c;
    return -1;
}

int sl_csv_number(const sl_csv *csv, size_t row, int col, double *out, sl_err *e) {
    const char *s = csv->fields[row * csv->ncols + (size_t)col];
    long line = csv->line_no[row];
    const char *name = csv->names[col];
    if (!sl_csv_is_number(s))
        return sl_fail(e, "%s:%ld: %s: '%.64s' is not a number", csv->src, line, name, s);
    errno = 0;
    double v = strtod(s, NULL);
    /* strtod: "nan", "inf", and overflow (1e999, ERANGE with HUGE_VAL) are all non-finite;
     * underflow to a subnormal or zero is accepted as the nearest double. */
    if (!isfinite(v))
        return sl_fail(e, "%s:%ld: %s: '%.64s' is not finite (inputs must be finite numbers)",
                       csv->src, line, name, s);
    *out = v;
    return 0;
}

void sl_buf_add(sl_buf *b, const char *s, size_t n) {
    if (b->len + n + 1 > b->cap) {
        size_t cap = b->cap ? b->cap : 4096;
        while (b->len + n + 1 > cap)
            cap *= 2;
        b->p = sl_realloc(b->p, cap);
        b->cap = cap;
    }
    memcpy(b->p + b->len, s, n);
    b->len += n;
    b->p[b->len] = 0;
}

void sl_buf_puts(sl_buf *b, const char *s) {
    sl_buf_add(b, s, strlen(s));
}

void sl_buf_printf(sl_buf *b, const char *fmt, ...) {
    char tmp[256];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(tmp, sizeof tmp, fmt, ap);
    va_end(ap);
    if (n < 0) return;
    if ((size_t)n < sizeof tmp) {
        sl_buf_add(b, tmp, (size_t)n);
        return;
    }
    char *big = sl_malloc((size_t)n + 1);
    va_start(ap, fmt);
    vsnprintf(big, (size_t)n + 1, fmt, ap);
    va_end(ap);
    sl_buf_add(b, big, (size_t)n);
    free(big);
}

void sl_buf_free(sl_buf *b) {
    free(b->p);
    memset(b, 0, sizeof *b);
}

int sl_read_stream(FILE *fp, const char *name, char **data, size_t *size, sl_err *e) {
    size_t cap = 65536, n = 0;
    char *buf = sl_malloc(cap);
    for (;;) {
        if (n + 1 >= cap) buf = sl_realloc(buf, cap *= 2);
        size_t got = fread(buf + n, 1, cap - n - 1, fp);
        n += got;
        if (got == 0) break;
    }
    if (ferror(fp)) {
        free(buf);
        return sl_fail(e, "%s: read error", name);
    }
    buf[n] = 0;
    *data = buf;
    *size = n;
    return 0;
}

/* ---- the chunked reader (csv.h) ---- */

/* The next physical line into r->line_buf, its line ending cut (LF, then one CR; the UTF-8 BOM
 * off line 1): 1, 0 at the end of the input, or -1 with e set (a NUL byte, a read error). */
static int reader_line(sl_csv_reader *r, char **line, sl_err *e) {
    ssize_t n = getline(&r->line_buf, &r->line_cap, r->fp);
    if (n < 0) {
        if (ferror(r->fp)) return sl_fail(e, "%s: read error", r->csv.src);
        return 0;
    }
    r->line++;
    char *p = r->line_buf;
    size_t len = (size_t)n;
    if (len > 0 && p[len - 1] == '\n') p[--len] = 0;
    if (memchr(p, 0, len))
        return sl_fail(e, "%s:%ld: contains a NUL byte (expected text)", r->csv.src, r->line);
    if (len > 0 && p[len - 1] == '\r') p[--len] = 0;                           /* CRLF */
    if (r->line == 1 && len >= 3 && memcmp(p, "\xEF\xBB\xBF", 3) == 0) p += 3; /* UTF-8 BOM */
    *line = p;
    return 1;
}

/* The next non-blank line: 1, 0 at the end (blank lines before it are trailing, so tolerated),
 * -1 with e set: a quote, or blank lines that turn out to lie between records (or before the
 * header), with sl_csv_parse's messages. */
static int reader_record(sl_csv_reader *r, char **line, sl_err *e) {
    const char *src = r->csv.src;
    for (;;) {
        int rc = reader_line(r, line, e);
        if (rc <= 0) return rc;
        if (blank_line(*line)) {
            if (!r->blank_count++) r->blank_first = r->line;
            continue;
        }
        int quote = strchr(*line, '"') != NULL;
        if (r->blank_count && r->blank_first == 1 && r->blank_count == 1 && !quote)
            return sl_fail(e, "%s:1: blank line: expected a header line naming the columns", src);
        if (r->blank_count && !(r->blank_first == 1 && r->blank_count == 1))
            return sl_fail(e, "%s:%ld: blank line between records", src,
                           r->blank_first == 1 ? 2 : r->blank_first);
        if (quote)
            return sl_fail(e, "%s:%ld: quoted fields are not supported (no '\"' anywhere)", src,
                           r->line);
        return 1;
    }
}

int sl_csv_reader_open(sl_csv_reader *r, FILE *fp, const char *src, sl_err *e) {
    memset(r, 0, sizeof *r);
    r->fp = fp;
    r->csv.src = src;
    char *line;
    int rc = reader_record(r, &line, e);
    if (rc == 0) sl_fail(e, "%s: empty input: expected a CSV header line naming the columns", src);
    if (rc == 1) {
        r->csv.text = sl_strdup(line); /* the header, kept for the whole run */
        rc = parse_header(&r->csv, r->csv.text, src, e) ? -1 : 1;
    }
    if (rc != 1) {
        sl_csv_reader_close(r);
        return -1;
    }
    return 0;
}

int sl_csv_reader_next(sl_csv_reader *r, size_t max_rows, sl_err *e) {
    sl_csv *c = &r->csv;
    c->nrows = 0;
    r->text.len = 0;
    while (c->nrows < max_rows && !r->at_eof) {
        char *line;
        int rc = reader_record(r, &line, e);
        if (rc < 0) return -1;
        if (rc == 0) {
            r->at_eof = 1;
            break;
        }
        size_t nf = count_fields(line);
        if (nf != c->ncols)
            return sl_fail(e, "%s:%ld: expected %zu fields like the header, got %zu", c->src,
                           r->line, c->ncols, nf);
        if (c->nrows == r->rows_cap) {
            r->rows_cap = r->rows_cap ? 2 * r->rows_cap : 1024;
            r->offs = sl_realloc(r->offs, r->rows_cap * sizeof *r->offs);
            c->rows = sl_realloc(c->rows, r->rows_cap * sizeof *c->rows);
            c->line_no = sl_realloc(c->line_no, r->rows_cap * sizeof *c->line_no);
        }
        r->offs[c->nrows] = r->text.len;
        c->line_no[c->nrows] = r->line;
        sl_buf_add(&r->text, line, strlen(line) + 1);
        c->nrows++;
    }
    /* Row pointers only now: the text buffer may have moved while it grew. */
    size_t ncells = c->nrows * c->ncols;
    if (ncells > r->fields_cap || !c->fields) {
        r->fields_cap = ncells > r->fields_cap ? ncells : r->fields_cap;
        c->fields = sl_realloc(c->fields, (r->fields_cap ? r->fields_cap : 1) * sizeof *c->fields);
    }
    if (c->nrows) c->fields_buf = sl_realloc(c->fields_buf, r->text.len);
    for (size_t k = 0; k < c->nrows; k++) {
        c->rows[k] = r->text.p + r->offs[k];
        size_t n = strlen(c->rows[k]) + 1;
        memcpy(c->fields_buf + r->offs[k], c->rows[k], n);
        split(c->fields_buf + r->offs[k], c->ncols, c->fields + k * c->ncols);
    }
    return 0;
}

void sl_csv_reader_close(sl_csv_reader *r) {
    sl_csv_free(&r->csv); /* the header copy, names, rows, line numbers, fields */
    free(r->line_buf);
    sl_buf_free(&r->text);
    free(r->offs);
    memset(r, 0, sizeof *r);
}
