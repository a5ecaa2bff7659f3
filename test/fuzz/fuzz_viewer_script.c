/* fuzz_viewer_script.c: libFuzzer target for `strandlight view --script` files: the line reader
 * (sl_viewer_run_script_text: line length, NUL bytes, `#` comments) and the command parser
 * (sl_viewer_command: words, numbers, argument counts). The viewer operations a command calls
 * are stubs here that check what they are given and succeed or fail by the input, so no window,
 * device or scene is needed and the target links viewer_script.c alone.
 * Checks: every number a command passes on is finite (zoom's factor also > 0), words and paths
 * are non-empty, hold no `#` (stripped as a comment), no newline and no leading or trailing
 * white space (a word none at all); brush_depth sets 0 or 1; on failure the message is one
 * non-empty line that starts with "fuzz.txt:LINE: " (the file and line of the failing
 * command). The script is an exact-size copy (no NUL) so ASan catches a read past its end.
 * Seeds: test/fuzz/corpus/fuzz_viewer_script/.
 */
// clang-format off
/* FUZZ_SOURCES: host/viewer/viewer_script.c host/base/common.c */
// clang-format on
#include "viewer/viewer.h"

#include <ctype.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerInitialize(int *argc, char ***argv);

/* A stub fails when its argument's first byte is odd: both outcomes are reached. */
static int stub_fails(const char *s) {
    return ((unsigned char)s[0] & 1) != 0;
}

static void check_word(const char *w, int spaces_ok) {
    size_t n = strlen(w);
    if (n == 0 || strchr(w, '#') || strchr(w, '\n') || isspace((unsigned char)w[0]) ||
        isspace((unsigned char)w[n - 1]))
        __builtin_trap();
    if (!spaces_ok)
        for (size_t i = 0; i < n; i++)
            if (isspace((unsigned char)w[i])) __builtin_trap();
}

static void check_num(double x) {
    if (!isfinite(x)) __builtin_trap();
}

int sl_viewer_set(sl_viewer *v, const char *key, const char *value, sl_err *e) {
    (void)v;
    check_word(key, 0);
    check_word(value, 1);
    return stub_fails(value) ? sl_fail(e, "set %s: refused by the stub", key) : 0;
}
void sl_viewer_orbit(sl_viewer *v, double yaw_deg, double pitch_deg) {
    (void)v;
    check_num(yaw_deg);
    check_num(pitch_deg);
}
void sl_viewer_pan(sl_viewer *v, double dx, double dy) {
    (void)v;
    check_num(dx);
    check_num(dy);
}
void sl_viewer_zoom(sl_viewer *v, double f) {
    (void)v;
    check_num(f);
    if (!(f > 0)) __builtin_trap();
}
void sl_viewer_reset(sl_viewer *v) {
    (void)v;
}
int sl_viewer_env_rotate(sl_viewer *v, double deg, sl_err *e) {
    (void)v;
    check_num(deg);
    return fabs(deg) > 1e6 ? sl_fail(e, "env_rotate: refused by the stub") : 0;
}
long sl_viewer_paint_at(sl_viewer *v, double x, double y, double radius, const float sa[3],
                        int continue_stroke, sl_err *e) {
    (void)v, (void)continue_stroke;
    check_num(x);
    check_num(y);
    check_num(radius);
    (void)sa; /* floats of finite doubles: may be inf, the painter's to refuse */
    return radius < 0 ? sl_fail(e, "paint: refused by the stub") : 1;
}
int sl_viewer_undo(sl_viewer *v) {
    (void)v;
    return 1;
}
int sl_viewer_drop(sl_viewer *v, const char *path, sl_err *e) {
    (void)v;
    check_word(path, 1);
    return stub_fails(path) ? sl_fail(e, "%s: refused by the stub", path) : 0;
}
int sl_viewer_set_device(sl_viewer *v, const char *spec, sl_err *e) {
    (void)v;
    check_word(spec, 0);
    return stub_fails(spec) ? sl_fail(e, "device %s: refused by the stub", spec) : 0;
}
int sl_viewer_save(sl_viewer *v, const char *path, sl_err *e) {
    (void)v;
    check_word(path, 1);
    return stub_fails(path) ? sl_fail(e, "%s: refused by the stub", path) : 0;
}
const sl_renderer *sl_viewer_shown_renderer(const sl_viewer *v) {
    (void)v;
    return NULL;
}
void sl_renderer_explain(const sl_renderer *r, FILE *f) {
    (void)r, (void)f;
}

static int steps;
static int host_step(sl_viewer *v, int until_refined, sl_err *e) {
    (void)v;
    if (until_refined != 0 && until_refined != 1) __builtin_trap();
    return ++steps % 61 == 0 ? sl_fail(e, "render: refused by the stub") : 0;
}
static int host_screenshot(sl_viewer *v, const char *path, int whole_window, sl_err *e) {
    (void)v;
    check_word(path, 1);
    if (whole_window != 0 && whole_window != 1) __builtin_trap();
    return stub_fails(path) ? sl_fail(e, "%s: refused by the stub", path) : 0;
}

int LLVMFuzzerInitialize(int *argc, char ***argv) {
    (void)argc, (void)argv;
    /* paint, explain and stats print to stdout; libFuzzer reports on stderr */
    if (!freopen("/dev/null", "w", stdout)) abort();
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *text = malloc(size ? size : 1);
    if (size) memcpy(text, data, size);
    static sl_viewer v;
    memset(&v, 0, sizeof v);
    v.brush_depth_test = 1;
    steps = 0;
    const sl_viewer_host host = {host_step, host_screenshot};
    sl_err e = {{0}};
    if (sl_viewer_run_script_text(&v, text, size, "fuzz.txt", &host, &e) != 0) {
        /* "fuzz.txt:LINE: ..." */
        char *end;
        if (strncmp(e.msg, "fuzz.txt:", 9) != 0 || strchr(e.msg, '\n')) __builtin_trap();
        long line = strtol(e.msg + 9, &end, 10);
        if (line < 1 || end[0] != ':' || end[1] != ' ' || end[2] == 0) __builtin_trap();
    }
    if (v.brush_depth_test != 0 && v.brush_depth_test != 1) __builtin_trap();
    free(text);
    return 0;
}
