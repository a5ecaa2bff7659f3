/* test_text_wrap.c: host/base/text_wrap.h, the wrapping of `--explain` rows and `kernels
 * --check` failures on a terminal. */
#include "test.h"

#include "base/text_wrap.h"

#include <stdlib.h>
#include <string.h>

/* What sl_put_wrapped writes, in a buffer. */
static char *wrapped(const char *text, int col, int indent, int width) {
    char *buf = NULL;
    size_t n = 0;
    FILE *f = open_memstream(&buf, &n);
    sl_put_wrapped(f, text, col, indent, width);
    fclose(f);
    return buf;
}

TEST(text_wrap_lines_fit_and_keep_every_word) {
    const char *text = "voxels 44x64x43 (voxelized), march 16 paths toward 48 lobes (1549 active "
                       "vertices)  [geometry, lobe dirs, dual + quality.voxels]";
    char *out = wrapped(text, 31, 31, 80);
    /* every line within 80 columns (the first starts at column 31), later lines indented 31 */
    int line = 0, col = 31;
    for (const char *p = out; *p; p++) {
        if (*p == '\n') {
            line++, col = 0;
            CHECK(strncmp(p + 1, "                               ", 31) == 0 && p[32] != ' ');
            continue;
        }
        col++;
        CHECK_MSG(col <= 80, "line %d longer than 80 columns", line);
    }
    CHECK(line >= 1);
    /* the words, in order, with the breaks and indents taken out */
    char *joined = malloc(strlen(out) + 1), *q = joined;
    for (const char *p = out; *p; p++) {
        if (*p == '\n') {
            *q++ = ' ';
            p += 31;
            continue;
        }
        *q++ = *p;
    }
    *q = 0;
    char *t = strdup(text);
    for (char *a = t, *b = t;; a++) { /* the text with runs of blanks as one, as the wrap joins */
        if (*a == ' ' && b > t && b[-1] == ' ') continue;
        if (!(*b++ = *a)) break;
    }
    char *j2 = strdup(joined);
    for (char *a = j2, *b = j2;; a++) {
        if (*a == ' ' && b > j2 && b[-1] == ' ') continue;
        if (!(*b++ = *a)) break;
    }
    CHECK_MSG(strcmp(j2, t) == 0, "words changed: '%s'", j2);
    free(j2), free(t), free(joined), free(out);
}

TEST(text_wrap_off_and_short) {
    const char *text = "a row far longer than any terminal would show on one line, to a file";
    char *out = wrapped(text, 0, 4, 0); /* width 0: a file or a pipe gets it whole */
    CHECK(strcmp(out, text) == 0);
    free(out);
    out = wrapped("short", 10, 10, 80);
    CHECK(strcmp(out, "short") == 0);
    free(out);
    /* a word longer than a line is cut rather than overrunning */
    char longw[200];
    memset(longw, 'x', 150);
    longw[150] = 0;
    out = wrapped(longw, 0, 2, 60);
    CHECK(strchr(out, '\n') != NULL && strlen(strtok(out, "\n")) <= 60);
    free(out);
}
