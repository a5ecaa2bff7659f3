/* test_clrt.c: the OpenCL runtime (host/cl/clrt.c, host/cl/clrt_cache.c): --device parsing, kernel and
 * cache directory lookup, the on-disk program cache (hit, miss, corrupt entries, atomic writes),
 * build failures and the C fallback under auto, timing. Tests that need an OpenCL device use
 * the test device (cl_fixture.h: $SL_TEST_DEVICE, else a GPU, else PoCL) and SKIP with the
 * reason when there is none. */
#include "test.h"

#include "cl_fixture.h"

#include "../cpu/prefix_sum.h"
#include "cl/clrt.h"
#include "base/common.h"
#include "passes/light/prefix_sum_cl.h"

#include <dirent.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---------------------------------------------------------------- helpers */

/* Remembers an environment variable and puts it back (tests must not leak settings). */
typedef struct saved_env {
    const char *name;
    char value[4096];
    int was_set;
} saved_env;

static void env_save(saved_env *s, const char *name) {
    const char *v = getenv(name);
    s->name = name;
    s->was_set = v != NULL;
    snprintf(s->value, sizeof s->value, "%s", v ? v : "");
}

static void env_restore(const saved_env *s) {
    if (s->was_set)
        setenv(s->name, s->value, 1);
    else
        unsetenv(s->name);
}

/* Path of the first *.bin in dir whose name starts with prefix. */
static int find_bin(const char *dir, const char *prefix, char *out, size_t n) {
    DIR *d = opendir(dir);
    if (!d) return -1;
    struct dirent *de;
    int found = -1;
    while ((de = readdir(d)) != NULL)
        if (strncmp(de->d_name, prefix, strlen(prefix)) == 0 && strstr(de->d_name, ".bin")) {
            snprintf(out, n, "%s/%s", dir, de->d_name);
            found = 0;
            break;
        }
    closedir(d);
    return found;
}

/* stderr into a file while a test provokes messages, so they can be checked (and do not clutter
 * the test log). */
typedef struct captured {
    int saved_fd;
    char path[4096];
} captured;

static void capture_start(captured *c, const char *name) {
    snprintf(c->path, sizeof c->path, "%s/%s.stderr", sl_test_tmpdir(), name);
    fflush(stderr);
    c->saved_fd = dup(2);
    int fd = open(c->path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
        dup2(fd, 2);
        close(fd);
    }
}

/* Restores stderr and returns what was written (caller frees). */
static char *capture_end(captured *c) {
    fflush(stderr);
    if (c->saved_fd >= 0) {
        dup2(c->saved_fd, 2);
        close(c->saved_fd);
    }
    unsigned char *data = NULL;
    size_t size = 0;
    if (sl_read_file(c->path, &data, &size, 1 << 20, NULL)) return sl_strdup("");
    return (char *)data;
}

/* Copies the repository's kernels/ into dir and makes prefix_sum.cl fail to compile. */
static int make_broken_kernel_dir(const char *dir) {
    char src[4096];
    sl_err e;
    if (sl_kernel_dir_find(src, sizeof src, &e)) return -1;
    char cmd[16384];
    snprintf(cmd, sizeof cmd,
             "cp '%s'/*.h '%s'/*.cl '%s' 2>/dev/null; cp '%s'/*.inc '%s' 2>/dev/null; "
             "printf '\\nthis is not OpenCL C;\\n' >> '%s/prefix_sum.cl'",
             src, src, dir, src, dir, dir);
    return system(cmd) == 0 ? 0 : -1;
}

/* ---------------------------------------------------------------- no device needed */

TEST(clrt_device_c_path) {
    sl_device dev;
    sl_err e = {{0}};
    CHECK(sl_device_open("c", &dev, &e) == 0);
    CHECK(dev.is_opencl == 0);
    CHECK(dev.cl == NULL);
    CHECK(strcmp(dev.name, "C path") == 0);
    CHECK(!sl_device_may_fallback(&dev));
    sl_device_close(&dev);
    sl_device_close(&dev); /* closing twice is harmless */
    CHECK(dev.is_opencl == 0);
}

TEST(clrt_device_bad_specs) {
    const char *bad[] = {"bogus", "GPU", "1:", ":1", "x:y", "-1", "1:2:3", "99999", "999:0"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        sl_device dev;
        sl_err e = {{0}};
        CHECK_MSG(sl_device_open(bad[i], &dev, &e) == -1, "spec '%s' accepted", bad[i]);
        CHECK_MSG(strstr(e.msg, bad[i]) != NULL, "message '%s' does not name '%s'", e.msg, bad[i]);
        CHECK(dev.is_opencl == 0 && dev.cl == NULL);
        CHECK(strchr(e.msg, '\n') == NULL);
    }
}

TEST(clrt_strerror_and_check) {
    CHECK(strcmp(sl_cl_strerror(CL_BUILD_PROGRAM_FAILURE), "CL_BUILD_PROGRAM_FAILURE") == 0);
    CHECK(strcmp(sl_cl_strerror(-1001), "CL_PLATFORM_NOT_FOUND_KHR") == 0);
    CHECK(strcmp(sl_cl_strerror(-12345), "unknown OpenCL error") == 0);
    sl_err e = {{0}};
    CHECK(sl_cl_check(CL_SUCCESS, "x", &e) == 0);
    CHECK(sl_cl_check(CL_OUT_OF_RESOURCES, "clEnqueueNDRangeKernel", &e) == -1);
    CHECK(strcmp(e.msg, "clEnqueueNDRangeKernel: CL_OUT_OF_RESOURCES (-5)") == 0);
}

TEST(clrt_kernel_dir_lookup) {
    saved_env s;
    env_save(&s, "STRANDLIGHT_KERNELS");
    char dir[4096];
    sl_err e = {{0}};
    setenv("STRANDLIGHT_KERNELS", "/nonexistent/strandlight-kernels", 1);
    CHECK(sl_kernel_dir_find(dir, sizeof dir, &e) == -1);
    CHECK(strstr(e.msg, "STRANDLIGHT_KERNELS=/nonexistent/strandlight-kernels") != NULL);
    setenv("STRANDLIGHT_KERNELS", sl_test_tmpdir(), 1);
    CHECK(sl_kernel_dir_find(dir, sizeof dir, &e) == 0);
    CHECK(strcmp(dir, sl_test_tmpdir()) == 0);
    /* Unset: <exe>/../kernels (the test binary sits in the build dir) or SL_KERNEL_DIR, either
     * way the repository's kernels/, which holds this kernel. */
    unsetenv("STRANDLIGHT_KERNELS");
    CHECK(sl_kernel_dir_find(dir, sizeof dir, &e) == 0);
    char path[8192];
    snprintf(path, sizeof path, "%s/prefix_sum.cl", dir);
    struct stat st;
    CHECK_MSG(stat(path, &st) == 0, "%s missing", path);
    env_restore(&s);
}

TEST(clrt_cache_dir_lookup) {
    saved_env a, b, c;
    env_save(&a, "SL_CACHE_DIR");
    env_save(&b, "XDG_CACHE_HOME");
    env_save(&c, "HOME");
    char dir[4096];
    setenv("SL_CACHE_DIR", "/tmp/slc", 1);
    setenv("XDG_CACHE_HOME", "/tmp/xdg", 1);
    setenv("HOME", "/home/someone", 1);
    CHECK(sl_cache_dir_find(dir, sizeof dir) == 1 && strcmp(dir, "/tmp/slc") == 0);
    setenv("SL_CACHE_DIR", "off", 1);
    CHECK(sl_cache_dir_find(dir, sizeof dir) == 0);
    unsetenv("SL_CACHE_DIR");
    CHECK(sl_cache_dir_find(dir, sizeof dir) == 1 && strcmp(dir, "/tmp/xdg/strandlight") == 0);
    setenv("XDG_CACHE_HOME", "relative/ignored", 1); /* XDG: relative paths are invalid */
    CHECK(sl_cache_dir_find(dir, sizeof dir) == 1 &&
          strcmp(dir, "/home/someone/.cache/strandlight") == 0);
    unsetenv("XDG_CACHE_HOME");
    unsetenv("HOME");
    CHECK(sl_cache_dir_find(dir, sizeof dir) == 0);
    env_restore(&a);
    env_restore(&b);
    env_restore(&c);
}

TEST(clrt_timer_without_events) {
    sl_cl_timer t;
    sl_cl_timer_start(&t, NULL);
    int is_dev = 1;
    double s = sl_cl_timer_stop(&t, &is_dev);
    CHECK(s >= 0 && s < 1.0);
    CHECK(is_dev == 0); /* no events: wall clock */
    CHECK(sl_cl_event_seconds(NULL) == -1);
}

/* ---------------------------------------------------------------- OpenCL device needed */

/* Builds through a fresh disk cache, then reloads, then survives corrupt entries. */
TEST(clrt_disk_cache) {
    saved_env s;
    env_save(&s, "SL_CACHE_DIR");
    char dir[4096];
    sl_test_fresh_dir("clrt_cache", dir, sizeof dir);
    CHECK(dir[0] != 0);
    setenv("SL_CACHE_DIR", dir, 1);
    sl_device dev;
    sl_err e = {{0}};
    int cl_rc = sl_test_open_cl(&dev, &e);
    if (cl_rc) {
        env_restore(&s);
        SL_TEST_CL_LEAVE(cl_rc, &e);
    }
    cl_kernel k1 = NULL, k2 = NULL, k3 = NULL;
    int src = -1, hit = -1;
    CHECK(sl_cl_get_kernel(dev.cl, "prefix_sum.cl", "sl_transpose", NULL, &k1, &e) == 0);
    CHECK(k1 != NULL);
    sl_cl_build_stats(dev.cl, &src, &hit, NULL);
    CHECK(src == 1 && hit == 0);
    CHECK(sl_test_count_files(dir, ".bin") == 1);
    CHECK(sl_test_count_files(dir, ".tmp") == 0); /* written atomically */
    /* Same file and options: the in-memory cache, same kernel object, no new build. */
    CHECK(sl_cl_get_kernel(dev.cl, "prefix_sum.cl", "sl_transpose", NULL, &k2, &e) == 0);
    CHECK(k2 == k1);
    /* Other options: another program and another cache entry. */
    CHECK(sl_cl_get_kernel(dev.cl, "prefix_sum.cl", "sl_transpose", "-DSL_TEST_OPTION=1", &k3,
                           &e) == 0);
    CHECK(k3 != NULL && k3 != k1);
    sl_cl_build_stats(dev.cl, &src, &hit, NULL);
    CHECK(src == 2 && hit == 0);
    CHECK(sl_test_count_files(dir, ".bin") == 2);
    sl_device_close(&dev);

    /* Reopen: both come from disk now, and the cached program computes correctly. */
    CHECK(sl_device_open(sl_test_cl_spec(), &dev, &e) == 0);
    if (dev.is_opencl) {
        float in[6] = {1, 2, 3, 4, 5, 6}, out[6] = {0};
        CHECK(slcl_prefix_sum_2d(dev.cl, in, out, 3, 2, NULL, &e) == 0);
        /* 3 x 2 image [1 2 3; 4 5 6]: SAT [1 3 6; 5 12 21] (small integers: exact). */
        const float want[6] = {1, 3, 6, 5, 12, 21};
        for (int i = 0; i < 6; i++)
            CHECK_NEAR(out[i], want[i], 0);
        sl_cl_build_stats(dev.cl, &src, &hit, NULL);
        CHECK(src == 0 && hit == 1);
    }
    sl_device_close(&dev);

    /* Corrupt entries are ignored and rebuilt: flipped bytes, then a truncated file. */
    char bin[8192];
    CHECK(find_bin(dir, "prefix_sum-", bin, sizeof bin) == 0);
    for (int round = 0; round < 2; round++) {
        /* Rewrite both entries the same way so whichever is the default program is hit. */
        DIR *d = opendir(dir);
        struct dirent *de;
        while (d && (de = readdir(d)) != NULL) {
            if (!strstr(de->d_name, ".bin")) continue;
            char p[8192];
            snprintf(p, sizeof p, "%s/%s", dir, de->d_name);
            unsigned char *data = NULL;
            size_t size = 0;
            if (sl_read_file(p, &data, &size, 1u << 28, NULL)) continue;
            FILE *fp = fopen(p, "wb");
            if (fp) {
                if (round == 0) {
                    for (size_t i = size / 2; i < size / 2 + 64 && i < size; i++)
                        data[i] ^= 0x5a;
                    fwrite(data, 1, size, fp);
                } else {
                    fwrite(data, 1, size < 20 ? size : 20, fp);
                }
                fclose(fp);
            }
            free(data);
        }
        if (d) closedir(d);
        CHECK(sl_device_open(sl_test_cl_spec(), &dev, &e) == 0);
        CHECK(sl_cl_get_kernel(dev.cl, "prefix_sum.cl", "sl_transpose", NULL, &k1, &e) == 0);
        sl_cl_build_stats(dev.cl, &src, &hit, NULL);
        CHECK_MSG(src == 1 && hit == 0, "round %d: from source %d, from cache %d", round, src, hit);
        sl_device_close(&dev);
        /* ... and the rewritten entry is good again. */
        CHECK(sl_device_open(sl_test_cl_spec(), &dev, &e) == 0);
        CHECK(sl_cl_get_kernel(dev.cl, "prefix_sum.cl", "sl_transpose", NULL, &k1, &e) == 0);
        sl_cl_build_stats(dev.cl, &src, &hit, NULL);
        CHECK_MSG(src == 0 && hit == 1, "round %d: from source %d, from cache %d", round, src, hit);
        sl_device_close(&dev);
    }
    CHECK(sl_test_count_files(dir, ".tmp") == 0);
    env_restore(&s);
}

TEST(clrt_missing_kernel_and_file) {
    sl_device dev;
    sl_err e = {{0}};
    SL_TEST_OPEN_CL(&dev, &e);
    cl_kernel k = NULL;
    CHECK(sl_cl_get_kernel(dev.cl, "no_such_file.cl", "x", NULL, &k, &e) == SL_CL_EKERNEL);
    CHECK(k == NULL);
    CHECK_MSG(strstr(e.msg, "no_such_file.cl") != NULL, "%s", e.msg);
    CHECK(sl_cl_get_kernel(dev.cl, "prefix_sum.cl", "no_such_kernel", NULL, &k, &e) ==
          SL_CL_EKERNEL);
    CHECK_MSG(strstr(e.msg, "no_such_kernel") != NULL, "%s", e.msg);
    /* Asking again replays the remembered failure. */
    CHECK(sl_cl_get_kernel(dev.cl, "no_such_file.cl", "x", NULL, &k, &e) == SL_CL_EKERNEL);
    sl_device_close(&dev);
}

/* An explicit device: a kernel that does not compile is an error, and the build log reaches
 * stderr prefixed with the file name. */
TEST(clrt_build_failure_explicit) {
    saved_env s;
    env_save(&s, "STRANDLIGHT_KERNELS");
    char dir[4096];
    sl_test_fresh_dir("clrt_broken_explicit", dir, sizeof dir);
    CHECK(make_broken_kernel_dir(dir) == 0);
    setenv("STRANDLIGHT_KERNELS", dir, 1);
    sl_device dev;
    sl_err e = {{0}};
    int cl_rc = sl_test_open_cl(&dev, &e);
    if (cl_rc) {
        env_restore(&s);
        SL_TEST_CL_LEAVE(cl_rc, &e);
    }
    captured c;
    capture_start(&c, "clrt_build_failure_explicit");
    cl_kernel k = NULL;
    int rc = sl_cl_get_kernel(dev.cl, "prefix_sum.cl", "sl_transpose", NULL, &k, &e);
    float in[4] = {1, 2, 3, 4}, out[4];
    sl_err e2 = {{0}};
    int rc2 = sl_prefix_sum_2d(&dev, in, out, 2, 2, &e2);
    char *log = capture_end(&c);
    CHECK(rc == SL_CL_EKERNEL);
    CHECK_MSG(strstr(e.msg, "OpenCL build failed") != NULL, "%s", e.msg);
    CHECK(strstr(e.msg, "prefix_sum.cl") != NULL);
    CHECK(strchr(e.msg, '\n') == NULL);
    CHECK_MSG(strstr(log, "strandlight: prefix_sum.cl: ") != NULL, "log: %s", log);
    CHECK(rc2 == -1);          /* no fallback for an explicitly requested device */
    CHECK(dev.is_opencl == 1); /* still the OpenCL device */
    free(log);
    sl_device_close(&dev);
    env_restore(&s);
}

/* Under auto the same failure switches to the C path with a warning, and the result is the C
 * twin's. */
TEST(clrt_build_failure_auto_falls_back) {
    saved_env s;
    env_save(&s, "STRANDLIGHT_KERNELS");
    char dir[4096];
    sl_test_fresh_dir("clrt_broken_auto", dir, sizeof dir);
    CHECK(make_broken_kernel_dir(dir) == 0);
    setenv("STRANDLIGHT_KERNELS", dir, 1);
    sl_device dev;
    sl_err e = {{0}};
    captured c;
    capture_start(&c, "clrt_build_failure_auto");
    int open_rc = sl_device_open("auto", &dev, &e);
    int was_opencl = dev.is_opencl, may = sl_device_may_fallback(&dev);
    enum { W = 300, H = 7 };
    static float in[W * H], out[W * H], want[W * H];
    for (int i = 0; i < W * H; i++)
        in[i] = (float)(i % 13) - 6.0f;
    int rc = open_rc == 0 ? sl_prefix_sum_2d(&dev, in, out, W, H, &e) : -1;
    char *log = capture_end(&c);
    env_restore(&s);
    if (open_rc == 0 && !was_opencl) {
        free(log);
        sl_device_close(&dev);
        /* a FAIL outranks the SKIP */
        CHECK_MSG(!sl_test_cl_listed(), "auto chose the C path though an OpenCL device is listed");
        SKIP("auto chose the C path: no OpenCL device to fall back from");
    }
    CHECK(open_rc == 0);
    CHECK(may == 1);
    CHECK_MSG(rc == 0, "%s", e.msg);
    CHECK(dev.is_opencl == 0 && dev.cl == NULL);
    CHECK(strcmp(dev.name, "C path") == 0);
    CHECK_MSG(strstr(log, "falling back to the C path") != NULL, "log: %s", log);
    CHECK(strstr(log, "strandlight: prefix_sum.cl: ") != NULL); /* the build log */
    slc_prefix_sum_2d(in, want, W, H);
    CHECK(memcmp(out, want, sizeof out) == 0);
    free(log);
    sl_device_close(&dev);
}

TEST(clrt_device_facts_and_timer) {
    sl_device dev;
    sl_err e = {{0}};
    SL_TEST_OPEN_CL(&dev, &e);
    CHECK(dev.is_opencl && dev.cl);
    CHECK(sl_cl_context(dev.cl) && sl_cl_queue(dev.cl) && sl_cl_device_id(dev.cl));
    CHECK(strlen(sl_cl_device_name(dev.cl)) > 0);
    CHECK(strstr(dev.name, sl_cl_device_name(dev.cl)) != NULL);
    CHECK(sl_cl_max_work_group_size(dev.cl) >= 1);
    CHECK(sl_cl_max_alloc(dev.cl) > 0);
    CHECK(!sl_device_may_fallback(&dev)); /* explicitly requested */
    CHECK(sl_cl_profiling(dev.cl));       /* the queue asks for profiling */
    /* A kernel timed with events: device time no larger than the wall time around it. */
    enum { N = 512 };
    static float in[N * N], out[N * N];
    for (int i = 0; i < N * N; i++)
        in[i] = 1.0f;
    double ks = -1;
    double t0 = sl_now();
    CHECK(slcl_prefix_sum_2d(dev.cl, in, out, N, N, &ks, &e) == 0);
    double wall = sl_now() - t0;
    CHECK(ks > 0 && ks <= wall);
    /* All ones: SAT(x, y) = (x+1)(y+1), exact in float below 2^24. */
    CHECK_NEAR(out[N * N - 1], (double)N * N, 0);
    sl_device_close(&dev);
}
