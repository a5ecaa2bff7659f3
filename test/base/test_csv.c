/* test_csv.c: the CSV dialect of `strandlight eval` (host/base/csv.h, numerics.md sec. 5): header,
 * columns in any order, row text kept for copying through, CRLF / missing final newline / blank
 * trailing lines, and every error with its line number (the header is line 1). */
#include "base/csv.h"
#include "test.h"

#include <string.h>

static int parse(const char *text, sl_csv *csv, sl_err *e) {
    return sl_csv_parse(text, strlen(text), "<stdin>", csv, e);
}

static void expect_fail(const char *text, const char *msg) {
    sl_csv csv;
    sl_err e = {{0}};
    int rc = parse(text, &csv, &e);
    CHECK_MSG(rc == -1, "'%s' was accepted", text);
    CHECK_MSG(strcmp(e.msg, msg) == 0, "got '%s', want '%s'", e.msg, msg);
    if (rc == 0) sl_csv_free(&csv);
}

TEST(csv_basic) {
    sl_csv csv;
    sl_err e = {{0}};
    CHECK_MSG(parse("b, a ,note\n1,2.5,x y\n-3e-2 ,4, z\n", &csv, &e) == 0, "%s", e.msg);
    CHECK(csv.ncols == 3 && csv.nrows == 2);
    CHECK(sl_csv_find(&csv, "a") == 1 && sl_csv_find(&csv, "b") == 0);
    CHECK(sl_csv_find(&csv, "note") == 2 && sl_csv_find(&csv, "c") == -1);
    CHECK(strcmp(csv.header, "b, a ,note") == 0);
    CHECK(strcmp(csv.rows[0], "1,2.5,x y") == 0);
    CHECK(strcmp(csv.rows[1], "-3e-2 ,4, z") == 0); /* kept exactly as given */
    CHECK(csv.line_no[0] == 2 && csv.line_no[1] == 3);
    double v = 0;
    CHECK(sl_csv_number(&csv, 1, 0, &v, &e) == 0 && v == -3e-2);
    CHECK(sl_csv_number(&csv, 0, 1, &v, &e) == 0 && v == 2.5);
    CHECK(sl_csv_number(&csv, 0, 2, &v, &e) == -1);
    CHECK_MSG(strcmp(e.msg, "<stdin>:2: note: 'x y' is not a number") == 0, "%s", e.msg);
    sl_csv_free(&csv);
}

TEST(csv_line_endings) {
    sl_csv csv;
    sl_err e = {{0}};
    /* CRLF, no final newline */
    CHECK(parse("x,y\r\n1,2\r\n3,4", &csv, &e) == 0);
    CHECK(csv.nrows == 2 && strcmp(csv.rows[1], "3,4") == 0 && strcmp(csv.header, "x,y") == 0);
    double v;
    CHECK(sl_csv_number(&csv, 0, 1, &v, &e) == 0 && v == 2);
    sl_csv_free(&csv);
    /* blank trailing lines, with and without spaces / CR */
    CHECK(parse("x\n1\n\n  \r\n\n", &csv, &e) == 0);
    CHECK(csv.nrows == 1);
    sl_csv_free(&csv);
    /* header only, UTF-8 BOM */
    CHECK(parse("\xEF\xBB\xBFx,y\n", &csv, &e) == 0);
    CHECK(csv.nrows == 0 && csv.ncols == 2 && strcmp(csv.header, "x,y") == 0);
    sl_csv_free(&csv);
}

TEST(csv_numbers) {
    sl_csv csv;
    sl_err e = {{0}};
    CHECK(parse("a\nnan\ninf\n-Infinity\n1e999\n1e-400\n0x1p-2\n1.5x\n\t7 \n", &csv, &e) == 0);
    double v = 0;
    CHECK(sl_csv_number(&csv, 0, 0, &v, &e) == -1);
    CHECK_MSG(strcmp(e.msg, "<stdin>:2: a: 'nan' is not finite (inputs must be finite numbers)") ==
                  0,
              "%s", e.msg);
    CHECK(sl_csv_number(&csv, 1, 0, &v, &e) == -1 && strstr(e.msg, "<stdin>:3: a:"));
    CHECK(sl_csv_number(&csv, 2, 0, &v, &e) == -1 && strstr(e.msg, "<stdin>:4: a:"));
    CHECK(sl_csv_number(&csv, 3, 0, &v, &e) == -1 && strstr(e.msg, "<stdin>:5: a: '1e999'"));
    CHECK(sl_csv_number(&csv, 4, 0, &v, &e) == 0 && v == 0); /* underflow: nearest double */
    CHECK(sl_csv_number(&csv, 5, 0, &v, &e) == 0 && v == 0.25);
    CHECK(sl_csv_number(&csv, 6, 0, &v, &e) == -1);
    CHECK_MSG(strcmp(e.msg, "<stdin>:8: a: '1.5x' is not a number") == 0, "%s", e.msg);
    CHECK(sl_csv_number(&csv, 7, 0, &v, &e) == 0 && v == 7);
    sl_csv_free(&csv);
    CHECK(parse("a,b\n,1\n", &csv, &e) == 0);
    CHECK(sl_csv_number(&csv, 0, 0, &v, &e) == -1);
    CHECK_MSG(strcmp(e.msg, "<stdin>:2: a: '' is not a number") == 0, "%s", e.msg);
    sl_csv_free(&csv);
}

TEST(csv_errors) {
    expect_fail("", "<stdin>: empty input: expected a CSV header line naming the columns");
    expect_fail("\n\n", "<stdin>: empty input: expected a CSV header line naming the columns");
    expect_fail("0.1,0.2\n0.3,0.4\n",
                "<stdin>:1: expected a header line naming the columns, got the number '0.1' "
                "(input needs a header)");
    expect_fail("a,,b\n1,2,3\n", "<stdin>:1: column 2 has an empty name");
    expect_fail("a,b,a\n1,2,3\n", "<stdin>:1: duplicate column 'a'");
    expect_fail("a,b\n1,2\n3\n", "<stdin>:3: expected 2 fields like the header, got 1");
    expect_fail("a,b\n1,2\n3,4,5\n", "<stdin>:3: expected 2 fields like the header, got 3");
    expect_fail("a,b\n1,2\n\n3,4\n", "<stdin>:3: blank line between records");
    expect_fail("a,\"b\"\n1,2\n", "<stdin>:1: quoted fields are not supported (no '\"' anywhere)");
    expect_fail("\na\n1\n", "<stdin>:1: blank line: expected a header line naming the columns");
    static const char nul[] = "a\n1\n2\0x\n";
    sl_csv csv;
    sl_err e = {{0}};
    CHECK(sl_csv_parse(nul, sizeof nul - 1, "<stdin>", &csv, &e) == -1);
    CHECK_MSG(strcmp(e.msg, "<stdin>:3: contains a NUL byte (expected text)") == 0, "%s", e.msg);
}

TEST(csv_buf) {
    sl_buf b = {0};
    for (int i = 0; i < 2000; i++)
        sl_buf_printf(&b, "%d,", i);
    CHECK(b.len > 5000 && strncmp(b.p, "0,1,2,", 6) == 0 && b.p[b.len] == 0);
    char big[600];
    memset(big, 'q', sizeof big - 1);
    big[sizeof big - 1] = 0;
    size_t before = b.len;
    sl_buf_printf(&b, "<%s>", big); /* longer than the formatter's stack buffer */
    CHECK(b.len == before + 601 && b.p[b.len - 1] == '>');
    sl_buf_free(&b);
}
