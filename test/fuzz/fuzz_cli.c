/* fuzz_cli.c: libFuzzer target for command-line option parsing. Each subcommand parses its
 * argv inline (host/cli/cmd_*.c) and then runs, so a whole command cannot be fuzzed without
 * running it; what is fuzzed is the option layer they all share (host/cli/cli.c: cli_opt,
 * cli_is_help, cli_int, cli_double, cli_usage_error), driven by the option table of `render`
 * (its names, integer ranges and number options, copied from cmd_render.c) in the same loop
 * shape as cmd_render. Input: argv, split on NUL bytes.
 * Checks: cli_opt matches only NAME or NAME=VALUE, returns the value after '=' or the next
 * argument (advancing i by one), or sets missing at the end of argv; cli_int accepts only a
 * whole decimal integer in range, cli_double only a whole finite number (both compared against
 * strtol / strtod here); every usage error is exactly one line on stderr that starts with
 * "strandlight" (stderr is captured with open_memstream). Each argument is an
 * exact-size copy, so ASan catches a read past its NUL. Seeds: test/fuzz/corpus/fuzz_cli/.
 */
// clang-format off
/* FUZZ_SOURCES: host/cli/cli.c */
// clang-format on
#include "cli/cli.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

typedef struct opt {
    const char *name;
    char kind; /* s string, i integer, d number */
    long lo, hi;
} opt;

static const opt opts[] = {
    {"--exr", 's', 0, 0},        {"-o", 's', 0, 0},          {"--output", 's', 0, 0},
    {"--png", 's', 0, 0},        {"--device", 's', 0, 0},    {"--shading-rate", 's', 0, 0},
    {"--frames", 's', 0, 0},     {"--aov", 's', 0, 0},       {"--method", 's', 0, 0},
    {"--exposure", 'd', 0, 0},   {"--width", 'i', 1, 16384}, {"--height", 'i', 1, 16384},
    {"--orbit", 'i', 1, 100000}, {"--threads", 'i', 1, 16},
};

/* The captured stderr of one call: empty, or exactly one line starting with "strandlight". */
static void check_stderr(const char *buf, size_t n, int want_message) {
    if (!want_message) {
        if (n != 0) __builtin_trap();
        return;
    }
    if (n < 2 || strncmp(buf, "strandlight", 11) != 0 || buf[n - 1] != '\n' ||
        memchr(buf, '\n', n - 1) || memchr(buf, 0, n))
        __builtin_trap();
}

static int whole_long(const char *v, long lo, long hi, long *out) {
    char *end;
    errno = 0;
    long x = strtol(v, &end, 10);
    if (errno || end == v || *end || x < lo || x > hi) return 0;
    *out = x;
    return 1;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    /* argv: argv[0] = "render", then the input split on NUL bytes, each an exact-size copy */
    enum { MAXARG = 64 };
    char *argv[MAXARG + 2];
    int argc = 0;
    argv[argc++] = strdup("render");
    size_t a = 0;
    while (a <= size && argc < MAXARG) {
        const uint8_t *z = memchr(data + a, 0, size - a);
        size_t len = z ? (size_t)(z - (data + a)) : size - a;
        argv[argc] = malloc(len + 1);
        memcpy(argv[argc], data + a, len);
        argv[argc][len] = 0;
        argc++;
        a += len + 1;
    }
    argv[argc] = NULL;

    /* one stream per input (cheaper than one per argument); each argument's part of it is
     * what was written since the last flush */
    char *buf = NULL;
    size_t blen = 0, seen = 0;
    FILE *saved = stderr, *mem = open_memstream(&buf, &blen);
    if (!mem) abort();
    stderr = mem;
    for (int i = 1; i < argc; i++) {
        int i0 = i, matched = -1, missing = 0, rc = 0, message = 0;
        const char *v = NULL;
        if (cli_is_help(argv[i])) {
            if (strcmp(argv[i], "-h") != 0 && strcmp(argv[i], "--help") != 0) __builtin_trap();
        } else {
            for (size_t k = 0; k < sizeof opts / sizeof opts[0]; k++) {
                missing = 0;
                if (cli_opt(argc, argv, &i, opts[k].name, &v, &missing)) {
                    matched = (int)k;
                    break;
                }
                if (i != i0) __builtin_trap(); /* no match, no advance */
            }
            if (matched < 0) {
                const char *arg = argv[i];
                if (arg[0] == '-') rc = cli_usage_error("render", "unknown option '%s'", arg);
                message = rc != 0;
            } else {
                const opt *o = &opts[matched];
                size_t nl = strlen(o->name);
                const char *arg = argv[i0];
                if (strncmp(arg, o->name, nl) != 0) __builtin_trap();
                if (arg[nl] == '=') {
                    if (i != i0 || v != arg + nl + 1 || missing) __builtin_trap();
                } else if (arg[nl] == 0) {
                    if (missing) {
                        if (i != i0 || i0 + 1 < argc || v) __builtin_trap();
                        message = 1;
                    } else if (i != i0 + 1 || v != argv[i0 + 1]) {
                        __builtin_trap();
                    }
                } else {
                    __builtin_trap();
                }
                if (!missing && o->kind == 'i') {
                    long got = -1, want = 0;
                    int ok = cli_int("render", o->name, v, o->lo, o->hi, &got) == 0;
                    if (ok != whole_long(v, o->lo, o->hi, &want) || (ok && got != want))
                        __builtin_trap();
                    message = !ok;
                } else if (!missing && o->kind == 'd') {
                    double got = NAN;
                    int ok = cli_double("render", o->name, v, &got) == 0;
                    char *end;
                    errno = 0;
                    double want = strtod(v, &end);
                    int want_ok = !errno && end != v && !*end && isfinite(want);
                    if (ok != want_ok || (ok && !(got == want || (isnan(got) && isnan(want)))))
                        __builtin_trap();
                    message = !ok;
                }
            }
        }
        fflush(mem);
        check_stderr(buf + seen, blen - seen, message);
        seen = blen;
    }
    stderr = saved;
    fclose(mem);
    free(buf);
    for (int k = 0; k < argc; k++)
        free(argv[k]);
    return 0;
}
