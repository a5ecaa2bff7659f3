/* test_main.c: runner for the unit tests registered with TEST() (see test.h). */
#include "test.h"

#include <dirent.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define MAX_TESTS 2048
static struct {
    const char *name;
    sl_test_fn fn;
} tests[MAX_TESTS];
static int num_tests;
static int cur_failed, cur_skipped;
static char skip_reason[512];
static const char *cur_name;

void sl_test_register(const char *name, sl_test_fn fn) {
    if (num_tests < MAX_TESTS) {
        tests[num_tests].name = name;
        tests[num_tests].fn = fn;
        num_tests++;
    }
}

void sl_test_fail(const char *file, int line, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    /* Print only the first few failures of a test; the count is what matters. */
    if (cur_failed < 5) {
        printf("  %s:%d: ", file, line);
        vprintf(fmt, ap);
        printf("\n");
    }
    va_end(ap);
    cur_failed++;
}

int sl_test_failed_now(void) { return cur_failed; }

void sl_test_skip(const char *why) {
    cur_skipped = 1;
    snprintf(skip_reason, sizeof skip_reason, "%s", why);
}

const char *sl_test_shared_data(void) {
    static char path[4096];
    const char *env = getenv("SL_SHARED_DATA");
    snprintf(path, sizeof path, "%s", env ? env : "../shared/data");
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode)) return NULL;
    return path;
}

const char *sl_test_tmpdir(void) {
    static char path[4096];
    if (!path[0]) {
        const char *env = getenv("SL_TEST_TMP");
        snprintf(path, sizeof path, "%s", env ? env : "build/test-tmp");
        mkdir(path, 0777);
    }
    return path;
}

void sl_test_fresh_dir(const char *name, char *out, size_t n) {
    snprintf(out, n, "%s/%s-%ld", sl_test_tmpdir(), name, (long)getpid());
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s'", out, out);
    if (system(cmd) != 0) out[0] = 0;
}

int sl_test_count_files(const char *dir, const char *part) {
    DIR *d = opendir(dir);
    if (!d) return -1;
    int n = 0;
    struct dirent *de;
    while ((de = readdir(d)) != NULL)
        if (de->d_name[0] != '.' && strstr(de->d_name, part)) n++;
    closedir(d);
    return n;
}

int main(int argc, char **argv) {
    const char *filter = argc > 1 ? argv[1] : NULL;
    int passed = 0, failed = 0, skipped = 0;
    setvbuf(stdout, NULL, _IOLBF, 0);
    for (int i = 0; i < num_tests; i++) {
        if (filter && !strstr(tests[i].name, filter)) continue;
        cur_name = tests[i].name;
        cur_failed = 0;
        cur_skipped = 0;
        struct timespec t0, t1;
        clock_gettime(CLOCK_MONOTONIC, &t0);
        tests[i].fn();
        clock_gettime(CLOCK_MONOTONIC, &t1);
        double dt = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
        if (cur_failed) {
            printf("FAIL %s (%d checks failed, %.2f s)\n", cur_name, cur_failed, dt);
            failed++;
        } else if (cur_skipped) {
            printf("SKIP %s: %s\n", cur_name, skip_reason);
            skipped++;
        } else {
            printf("PASS %s (%.2f s)\n", cur_name, dt);
            passed++;
        }
    }
    printf("unit: %d passed, %d failed, %d skipped\n", passed, failed, skipped);
    return failed ? 1 : 0;
}
