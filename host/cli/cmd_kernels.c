/* cmd_kernels.c: `strandlight kernels`: runs every registered OpenCL kernel against its C twin
 * (host/verify/checks/kernel_checks.c) on the chosen device and prints differences, tolerances and
 * times.
 * --check: the table kernel | backend | cases | max abs | max rel | tolerance | result over the
 * generated typical inputs and (checks with has_extreme) their extreme inputs, then the extreme
 * sweep (sl_kernel_extreme); --bench: the same rows with the best C and OpenCL times. Without
 * either: the compact table with times that scripts and tests read. */
#include "cli/cli.h"
#include "base/text_wrap.h"
#include "cl/clrt.h"
#include "verify/checks/kernel_checks.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static void usage(FILE *fp) {
    size_t n;
    const sl_kernel_check *c = sl_kernel_checks(&n);
    fprintf(fp, "usage: strandlight kernels [--device D] [--only NAME] [--size N] [--reps R] "
                "[--list] [--check | --bench] [--extreme]\n\n"
                "Runs each OpenCL kernel and its C twin on the same input and compares them:\n"
                "max abs/rel difference, tolerance, PASS/FAIL, best C and OpenCL times (ms).\n"
                "Exit status 1 if any check fails.\n\n"
                "  --device D   auto (default), gpu, pocl, opencl, P:D or N (see 'strandlight "
                "devices');\n"
                "               with c there is nothing to compare and every check is skipped\n"
                "  --only NAME  run one check\n"
                "  --size N     problem size (per check; prefix_sum: an N x N image)\n"
                "  --reps R     timed repetitions, best reported (default 3)\n"
                "  --list       list the checks and exit\n"
                "  --check      the accuracy table: kernel, backend, cases (typical and extreme\n"
                "               inputs), max abs/rel error, tolerance, PASS/FAIL; then the\n"
                "               extreme sweep\n"
                "  --bench      the same rows with times: C twin and OpenCL kernel, best of R\n"
                "  --extreme    then sweep degenerate geometry and extreme materials through the\n"
                "               C path and the kernels: FAIL on any NaN/Inf output (also with c)\n"
                "\nchecks:\n");
    for (size_t i = 0; i < n; i++)
        fprintf(fp, "  %-14s %s\n", c[i].name, c[i].what);
}

static void fmt_num(char *out, size_t n, double v) {
    if (v == 0)
        snprintf(out, n, "0");
    else
        snprintf(out, n, "%.3g", v);
}

static void tol_str(const sl_kernel_check_result *r, char *tol, size_t n) {
    if (r->tol_abs == 0 && r->tol_rel == 0)
        snprintf(tol, n, "exact");
    else
        snprintf(tol, n, "abs %.2g|rel %.2g", r->tol_abs, r->tol_rel);
}

/* --check / --bench: one row per (check, input set); typical always, extreme where the check
 * generates its own (the others: the extreme sweep after the table). Rows are gathered and printed
 * at the end with columns as wide as their widest cell (nothing is cut); a terminal shows which
 * check is running meanwhile. */
#define KROWS 256
#define KCOLS 7
typedef struct krow {
    char cell[KCOLS][260];
    char extra[1100]; /* a FAIL's message or the "outside the tolerance" line, or "" */
    char bench[80];
    int fail_msg; /* the row is "FAIL: msg" after kernel and backend */
} krow;

static void table(const sl_device *dev, const sl_kernel_check *checks, size_t n, const char *only,
                  const sl_kernel_check_opts *o0, int bench, int *passed, int *failed) {
    static krow rows[KROWS];
    int nr = 0;
    static const char *head[KCOLS] = {"kernel",  "backend",   "cases", "max_abs",
                                      "max_rel", "tolerance", "result"};
    for (size_t i = 0; i < n; i++) {
        if (only && strcmp(only, checks[i].name) != 0) continue;
        for (int x = 0; x <= (checks[i].has_extreme ? 1 : 0) && nr < KROWS; x++) {
            sl_kernel_check_opts o = *o0;
            o.extreme = x;
            sl_kernel_check_result r;
            memset(&r, 0, sizeof r);
            sl_err e = {{0}};
            krow *w = &rows[nr++];
            memset(w, 0, sizeof *w);
            snprintf(w->cell[0], sizeof w->cell[0], "%s", checks[i].name);
            snprintf(w->cell[1], sizeof w->cell[1], "%s", dev->name);
            sl_status("kernels: %s (%s)", checks[i].name, x ? "extreme" : "typical");
            if (checks[i].run(dev->cl, &o, &r, &e)) {
                w->fail_msg = 1;
                snprintf(w->extra, sizeof w->extra, "FAIL: %s", e.msg);
                (*failed)++;
                continue;
            }
            fmt_num(w->cell[3], sizeof w->cell[3], r.max_abs);
            fmt_num(w->cell[4], sizeof w->cell[4], r.max_rel);
            tol_str(&r, w->cell[5], sizeof w->cell[5]);
            if (checks[i].has_extreme)
                snprintf(w->cell[2], sizeof w->cell[2], "%s", r.problem);
            else
                snprintf(w->cell[2], sizeof w->cell[2], "typical %s", r.problem);
            snprintf(w->cell[6], sizeof w->cell[6], "%s", r.pass ? "PASS" : "FAIL");
            if (bench)
                snprintf(w->bench, sizeof w->bench, "   %9.3f %9.3f%s %8.3f", 1e3 * r.c_s,
                         1e3 * r.cl_s, r.cl_s_is_device ? "" : "w", 1e3 * r.cl_wall_s);
            if (!r.pass)
                snprintf(w->extra, sizeof w->extra,
                         "  %zu of %zu outputs outside the tolerance (%s)", r.bad, r.compared,
                         r.note);
            r.pass ? (*passed)++ : (*failed)++;
        }
    }
    sl_status_clear();
    int wd[KCOLS];
    for (int c = 0; c < KCOLS; c++) {
        wd[c] = (int)strlen(head[c]);
        for (int k = 0; k < nr; k++)
            if (!rows[k].fail_msg || c < 2)
                if ((int)strlen(rows[k].cell[c]) > wd[c]) wd[c] = (int)strlen(rows[k].cell[c]);
    }
    for (int c = 0; c < KCOLS; c++)
        printf("%-*s%s", c + 1 < KCOLS ? wd[c] : 0, head[c], c + 1 < KCOLS ? " " : "");
    if (bench) printf(" %9s %9s %9s", "C_ms", "CL_ms", "CL_wall");
    printf("\n");
    /* cells are never cut; a failure's message wraps at a terminal's width (whole in a pipe) */
    int width = sl_term_width(stdout);
    for (int k = 0; k < nr; k++) {
        const krow *w = &rows[k];
        if (w->fail_msg) {
            printf("%-*s %-*s ", wd[0], w->cell[0], wd[1], w->cell[1]);
            sl_put_wrapped(stdout, w->extra, wd[0] + wd[1] + 2, 4, width);
            printf("\n");
            continue;
        }
        for (int c = 0; c < KCOLS; c++) /* the last column unpadded: no trailing blanks */
            printf("%-*s%s", c + 1 < KCOLS ? wd[c] : 0, w->cell[c], c + 1 < KCOLS ? " " : "");
        printf("%s\n", w->bench);
        if (w->extra[0]) {
            sl_put_wrapped(stdout, w->extra, 0, 4, width);
            printf("\n");
        }
    }
}

int cmd_kernels(int argc, char **argv) {
    const char *device = "auto", *only = NULL, *v;
    long size = 0, reps = 3;
    int list = 0, extreme = 0, mode = 0; /* mode 0 compact, 1 --check, 2 --bench */
    for (int i = 1; i < argc; i++) {
        int missing = 0;
        if (cli_is_help(argv[i])) {
            usage(stdout);
            return 0;
        } else if (cli_opt(argc, argv, &i, "--device", &v, &missing)) {
            if (missing) return 2;
            device = v;
        } else if (cli_opt(argc, argv, &i, "--only", &v, &missing)) {
            if (missing) return 2;
            only = v;
        } else if (cli_opt(argc, argv, &i, "--size", &v, &missing)) {
            if (missing || cli_int("kernels", "--size", v, 1, 16384, &size)) return 2;
        } else if (cli_opt(argc, argv, &i, "--reps", &v, &missing)) {
            if (missing || cli_int("kernels", "--reps", v, 1, 1000, &reps)) return 2;
        } else if (strcmp(argv[i], "--list") == 0) {
            list = 1;
        } else if (strcmp(argv[i], "--check") == 0) {
            mode = 1;
        } else if (strcmp(argv[i], "--bench") == 0) {
            mode = 2;
        } else if (strcmp(argv[i], "--extreme") == 0) {
            extreme = 1;
        } else {
            return cli_usage_error("kernels", "unexpected argument '%s'", argv[i]);
        }
    }
    size_t n;
    const sl_kernel_check *checks = sl_kernel_checks(&n);
    if (list) {
        for (size_t i = 0; i < n; i++)
            printf("%-14s %s\n", checks[i].name, checks[i].what);
        return 0;
    }
    if (only && !sl_kernel_check_find(only))
        return cli_usage_error("kernels", "--only: no check named '%s' (try --list)", only);

    sl_err e = {{0}};
    sl_device dev;
    if (sl_device_open(device, &dev, &e)) {
        fprintf(stderr, "strandlight: %s\n", e.msg);
        return 1;
    }
    printf("device: %s\n", dev.name);
    if (!dev.is_opencl) {
        for (size_t i = 0; i < n; i++)
            if (!only || strcmp(only, checks[i].name) == 0)
                printf("%-18s SKIP (no OpenCL device: the C path has nothing to compare "
                       "against)\n",
                       checks[i].name);
        int bad = extreme ? sl_kernel_extreme(NULL, stdout) : 0;
        sl_device_close(&dev);
        return bad ? 1 : 0;
    }
    int passed = 0, failed = 0;
    sl_kernel_check_opts o = {size, (int)reps, 0};
    if (mode) {
        table(&dev, checks, n, only, &o, mode == 2, &passed, &failed);
        if (mode == 1) extreme = 1;
    } else {
        printf("%-18s %-16s %-9s %-9s %-16s %-6s %9s %9s %9s\n", "kernel", "problem", "max_abs",
               "max_rel", "tolerance", "result", "C_ms", "CL_ms", "CL_wall");
    }
    for (size_t i = 0; i < n && !mode; i++) {
        if (only && strcmp(only, checks[i].name) != 0) continue;
        sl_kernel_check_result r;
        memset(&r, 0, sizeof r);
        if (checks[i].run(dev.cl, &o, &r, &e)) {
            printf("%-18s FAIL: %s\n", checks[i].name, e.msg);
            failed++;
            continue;
        }
        char ma[32], mr[32], tol[64];
        fmt_num(ma, sizeof ma, r.max_abs);
        fmt_num(mr, sizeof mr, r.max_rel);
        tol_str(&r, tol, sizeof tol);
        printf("%-18s %-16s %-9s %-9s %-16s %-6s %9.3f %9.3f%s %8.3f\n", checks[i].name, r.problem,
               ma, mr, tol, r.pass ? "PASS" : "FAIL", 1e3 * r.c_s, 1e3 * r.cl_s,
               r.cl_s_is_device ? "" : "w", 1e3 * r.cl_wall_s);
        if (!r.pass)
            printf("  %zu of %zu outputs outside the tolerance (%s)\n", r.bad, r.compared, r.note);
        r.pass ? passed++ : failed++;
    }
    int from_source, from_cache;
    double build_s;
    sl_cl_build_stats(dev.cl, &from_source, &from_cache, &build_s);
    printf("%d passed, %d failed; programs: %d built from source, %d from the disk cache "
           "(%.3f s)\n",
           passed, failed, from_source, from_cache, build_s);
    if (extreme) failed += sl_kernel_extreme(dev.cl, stdout);
    sl_device_close(&dev);
    return failed ? 1 : 0;
}
