/* test_cli_usage.c: host/cli/cli.c's usage errors stay one line whatever the argument they quote
 * holds (a newline in an argument made two lines; found by test/fuzz/fuzz_cli.c). */
#include "cli/cli.h"
#include "test.h"

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* What cli_usage_error("render", "unknown option %s", arg) writes to stderr, into out. */
static void usage_text(const char *arg, char *out, size_t n) {
    char dir[4096], path[4200];
    sl_test_fresh_dir("cli_usage", dir, sizeof dir);
    snprintf(path, sizeof path, "%s/stderr", dir);
    out[0] = 0;
    fflush(stderr);
    int saved = dup(2), fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (saved < 0 || fd < 0) return;
    dup2(fd, 2);
    int rc = cli_usage_error("render", "unknown option %s", arg);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    close(fd);
    CHECK(rc == 2);
    FILE *f = fopen(path, "rb");
    if (!f) return;
    size_t got = fread(out, 1, n - 1, f);
    out[got] = 0;
    fclose(f);
}

TEST(cli_usage_error_one_line) {
    char t[2048];
    usage_text("--q", t, sizeof t);
    CHECK_MSG(
        strcmp(t, "strandlight render: unknown option --q (see 'strandlight render --help')\n") ==
            0,
        "got '%s'", t);
    usage_text("--x\ny\r\x1b[2J", t, sizeof t);
    CHECK_MSG(strcmp(t, "strandlight render: unknown option --x?y??[2J (see 'strandlight render "
                        "--help')\n") == 0,
              "got '%s'", t);
}
