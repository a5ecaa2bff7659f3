/* test_robust.c: unit tests of the robustness hooks (docs/robustness.md): allocation failure
 * injection (sl_alloc_fail_after, common.h) in a forked child, so that the out-of-memory exit
 * does not end the test binary; regressions for inputs the fuzz targets are built around; and the
 * OpenCL fault layer (SL_CL_FAULT): a pipeline step under auto finishes on the C path, an
 * explicit device fails with a clean message. */
#include "../cpu/prefix_sum.h"
#include "cl/clrt.h"
#include "base/common.h"
#include "scene/material.h"
#include "passes/light/prefix_sum_cl.h"
#include "test.h"

#include "cl_fixture.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

/* Runs fn in a child with stderr captured; returns its wait status, stderr text in err. */
static int run_child(void (*fn)(const char *), const char *arg, char *err, size_t err_size) {
    int fd[2];
    err[0] = 0;
    if (pipe(fd) != 0) return -1;
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        close(fd[0]);
        dup2(fd[1], 2);
        fn(arg);
        _exit(0);
    }
    close(fd[1]);
    size_t n = 0;
    ssize_t got;
    while (n + 1 < err_size && (got = read(fd[0], err + n, err_size - 1 - n)) > 0)
        n += (size_t)got;
    err[n] = 0;
    close(fd[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    return status;
}

/* Two allocations succeed, the third (a strdup) is the injected failure. */
static void child_third_fails(const char *unused) {
    (void)unused;
    sl_alloc_fail_after(3);
    void *a = sl_malloc(10), *b = sl_calloc(2, 8);
    char *c = sl_strdup("never");
    /* Not reached when the hook works: exit 0 tells the parent it did not fail. */
    free(a), free(b), free(c);
}

TEST(robust_alloc_fail_after_kth) {
    char err[512];
    int st = run_child(child_third_fails, NULL, err, sizeof err);
    CHECK_MSG(WIFEXITED(st) && WEXITSTATUS(st) == 1, "child status %d (want exit 1)", st);
    /* sl_strdup("never") asks for strlen + 1 = 6 bytes. */
    CHECK_MSG(strcmp(err, "strandlight: out of memory allocating 6 bytes\n") == 0, "stderr '%s'",
              err);
}

/* k = 0 turns injection off; the count still runs. */
static void child_off(const char *unused) {
    (void)unused;
    sl_alloc_fail_after(0);
    for (int i = 0; i < 100; i++)
        free(sl_realloc(NULL, 16));
    if (sl_alloc_count() != 100) _exit(3);
}

TEST(robust_alloc_fail_off_counts) {
    char err[512];
    int st = run_child(child_off, NULL, err, sizeof err);
    CHECK_MSG(WIFEXITED(st) && WEXITSTATUS(st) == 0, "child status %d, stderr '%s'", st, err);
}

/* An atomic output open when memory runs out is removed, and the target never appears. */
static void child_atomic(const char *path) {
    sl_atomic_file af;
    sl_err e;
    if (sl_atomic_open(&af, path, &e)) _exit(4);
    fputs("half of an output\n", af.fp);
    fflush(af.fp);
    sl_alloc_fail_after(1);
    free(sl_malloc(1));
    sl_atomic_commit(&af, &e); /* not reached */
}

TEST(robust_alloc_fail_removes_temp) {
    char dir[4096], path[4200], err[512];
    snprintf(dir, sizeof dir, "%s/robust_atomic", sl_test_tmpdir());
    snprintf(path, sizeof path, "%s/out.txt", dir);
    int st = run_child(child_atomic, path, err, sizeof err);
    CHECK_MSG(WIFEXITED(st) && WEXITSTATUS(st) == 1, "child status %d, stderr '%s'", st, err);
    DIR *d = opendir(dir);
    CHECK(d != NULL);
    if (!d) return;
    int files = 0;
    for (struct dirent *de; (de = readdir(d)) != NULL;)
        if (strcmp(de->d_name, ".") != 0 && strcmp(de->d_name, "..") != 0) {
            files++;
            CHECK_MSG(0, "left behind: %s", de->d_name);
        }
    closedir(d);
    CHECK(files == 0);
}

/* Found by reading for the fuzz target's invariant (sigma_a finite): melanin concentrations
 * that are each finite but whose weighted sum overflows (1e308 * 1.37 + 1e308 * 1.05 > DBL_MAX,
 * d'Eon 2011 Sec. 6.1 coefficients) must be an error, not sigma_a = inf. */
TEST(robust_material_melanin_overflow) {
    static const char txt[] = "{\"melanin\": {\"eumelanin\": 1e308, \"pheomelanin\": 1e308}}";
    sl_material m;
    sl_err e = {{0}};
    CHECK(sl_material_parse(txt, sizeof txt - 1, "m.json", &m, &e) == -1);
    CHECK_MSG(strstr(e.msg, "m.json: melanin") != NULL, "message '%s'", e.msg);
    /* Large concentrations whose sum stays below DBL_MAX still give a finite sigma_a. */
    static const char ok[] = "{\"melanin\": {\"eumelanin\": 1e300, \"pheomelanin\": 1e300}}";
    CHECK(sl_material_parse(ok, sizeof ok - 1, "m.json", &m, &e) == 0);
    CHECK(isfinite(m.sigma_a[2]) && m.sigma_a[2] > 0);
}

/* ---- OpenCL faults (SL_CL_FAULT, clrt.h): pipeline steps fall back under auto ---- */

/* Opens `spec` with SL_CL_FAULT=fault set; returns 0 when an OpenCL device is open. */
static int open_faulty(const char *spec, const char *fault, sl_device *dev, sl_err *e) {
    setenv("SL_CL_FAULT", fault, 1);
    if (sl_device_open(spec, dev, e)) return -1;
    if (!dev->is_opencl) {
        sl_fail(e, "no OpenCL device under %s", spec);
        sl_device_close(dev);
        return -1;
    }
    return 0;
}

/* Input with a spike and mixed signs, so that a wrong (or partial) result cannot match. */
static void ps_input(float *in, size_t n) {
    for (size_t i = 0; i < n; i++)
        in[i] = (float)((int)(i % 7) - 3) * 0.25f + (i == n / 3 ? 100.0f : 0.0f);
}

static void fallback_case(const char *fault) {
    enum { W = 300, H = 40 }; /* more than one 256-tile per row: several kernel enqueues */
    float *in = sl_malloc(W * H * sizeof *in), *out = sl_malloc(W * H * sizeof *out),
          *ref = sl_malloc(W * H * sizeof *ref);
    ps_input(in, W * H);
    slc_prefix_sum_2d(in, ref, W, H);
    sl_device dev;
    sl_err e = {{0}};
    if (open_faulty("auto", fault, &dev, &e)) {
        unsetenv("SL_CL_FAULT");
        free(in), free(out), free(ref);
        /* a FAIL outranks the SKIP */
        CHECK_MSG(!sl_test_cl_listed(), "an OpenCL device is listed but not usable: %s", e.msg);
        SKIP(e.msg);
    }
    int rc = sl_prefix_sum_2d(&dev, in, out, W, H, &e);
    unsetenv("SL_CL_FAULT");
    CHECK_MSG(rc == 0, "%s: rc %d: %s", fault, rc, e.msg);
    CHECK_MSG(!dev.is_opencl, "%s: still on OpenCL after the fault", fault);
    /* The C path is the C twin itself: bit-identical (tolerance 0). */
    CHECK(rc != 0 || memcmp(out, ref, W * H * sizeof *out) == 0);
    sl_device_close(&dev);
    free(in), free(out), free(ref);
}

TEST(robust_cl_fault_build_falls_back) {
    fallback_case("build");
}
TEST(robust_cl_fault_enqueue_falls_back) {
    fallback_case("enqueue");
}
TEST(robust_cl_fault_lost_falls_back) {
    fallback_case("lost");
}

/* An explicitly chosen device fails cleanly instead, and a device made by hand around another
 * owner's sl_cl never releases it (it used to: kernels + SL_CL_FAULT=build crashed). */
TEST(robust_cl_fault_explicit_fails_cleanly) {
    enum { W = 64, H = 8 };
    float in[W * H], out[W * H];
    ps_input(in, W * H);
    const char *spec = sl_test_cl_spec();
    sl_device dev;
    sl_err e = {{0}};
    if (open_faulty(spec, "enqueue", &dev, &e)) {
        unsetenv("SL_CL_FAULT");
        CHECK_MSG(!sl_test_cl_listed(), "an OpenCL device is listed but not usable: %s", e.msg);
        SKIP(e.msg);
    }
    int rc = sl_prefix_sum_2d(&dev, in, out, W, H, &e);
    CHECK(rc == -1);
    CHECK_MSG(strstr(e.msg, "CL_OUT_OF_RESOURCES (-5)") != NULL, "message '%s'", e.msg);
    CHECK(dev.is_opencl);
    sl_device_close(&dev);
    /* auto, but through a hand-made wrapper: no fallback, the owner's sl_cl survives. */
    if (open_faulty("auto", "build", &dev, &e) == 0) {
        sl_device wrap = {0};
        wrap.is_opencl = 1;
        wrap.cl = dev.cl;
        rc = sl_prefix_sum_2d(&wrap, in, out, W, H, &e);
        CHECK(rc == -1);
        CHECK_MSG(strstr(e.msg, "SL_CL_FAULT=build") != NULL, "message '%s'", e.msg);
        CHECK(wrap.is_opencl && dev.is_opencl && sl_cl_queue(dev.cl) != NULL);
        sl_device_close(&dev);
    }
    unsetenv("SL_CL_FAULT");
}
