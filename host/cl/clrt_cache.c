/* clrt_cache.c: where kernels live, and building OpenCL programs through an on-disk binary
 * cache (see clrt.h and docs/opencl.md).
 *
 * Cache entry: <cache dir>/<stem>-<32 hex>-v1.2.bin, keyed by a hash of the .cl source, every
 * kernels/ *.h and *.inc (name + content), device name, driver version, platform name and version
 * and the full build options. The file is a base/disk_cache.h entry (key and integrity hash in
 * its header) holding the driver's binary. Anything that does not check out (short, wrong key or
 * hash, rejected by the driver) is ignored, rebuilt from source and rewritten atomically. */
#include "cl/clrt.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define SL_MAX_KERNEL_SOURCE (16u << 20)
#define SL_MAX_CACHE_ENTRY (256u << 20)

static int is_dir(const char *p) {
    struct stat st;
    return stat(p, &st) == 0 && S_ISDIR(st.st_mode);
}

int sl_kernel_dir_find(char *out, size_t out_size, sl_err *e) {
    const char *env = getenv("STRANDLIGHT_KERNELS");
    if (env && *env) {
        if (!is_dir(env))
            return sl_fail(e,
                           "STRANDLIGHT_KERNELS=%s: not a directory (it should point at the "
                           "kernels/ folder)",
                           env);
        snprintf(out, out_size, "%s", env);
        return 0;
    }
    char exe[4096], dir[4096], cand[4096 + 16];
    ssize_t k = readlink("/proc/self/exe", exe, sizeof exe - 1);
    cand[0] = 0;
    if (k > 0) {
        exe[k] = 0;
        sl_dirname(exe, dir, sizeof dir);
        snprintf(cand, sizeof cand, "%s/../kernels", dir);
        if (is_dir(cand)) {
            char real[PATH_MAX];
            snprintf(out, out_size, "%s", realpath(cand, real) ? real : cand);
            return 0;
        }
    }
#ifdef SL_KERNEL_DIR
    if (is_dir(SL_KERNEL_DIR)) {
        snprintf(out, out_size, "%s", SL_KERNEL_DIR);
        return 0;
    }
    return sl_fail(e, "kernel directory not found (tried %s and %s; set STRANDLIGHT_KERNELS)",
                   cand[0] ? cand : "<exe dir>/../kernels", SL_KERNEL_DIR);
#else
    return sl_fail(e, "kernel directory not found (tried %s; set STRANDLIGHT_KERNELS)",
                   cand[0] ? cand : "<exe dir>/../kernels");
#endif
}

/* ---------------------------------------------------------------- cache key */

/* The key is 128 bits: two FNV-1a chains with different seeds over the same inputs. */
typedef sl_cache_key key_hash;

static void key_add(key_hash *h, const void *data, size_t n) {
    uint64_t len = n; /* length first, so ("ab","c") and ("a","bc") differ */
    h->a = sl_hash64(data, n, sl_hash64(&len, sizeof len, h->a));
    h->b = sl_hash64(data, n, sl_hash64(&len, sizeof len, h->b));
}

static void key_add_str(key_hash *h, const char *s) {
    key_add(h, s, strlen(s));
}

static int cmp_str(const void *a, const void *b) {
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static int is_header_name(const char *n) {
    size_t l = strlen(n);
    return n[0] != '.' &&
           ((l > 2 && strcmp(n + l - 2, ".h") == 0) || (l > 4 && strcmp(n + l - 4, ".inc") == 0));
}

/* Every *.h and *.inc in the kernel dir, sorted by name, goes into the key: an edit to any
 * header a kernel might include invalidates the entry (over-invalidation is cheap). */
static int key_add_headers(key_hash *h, const char *dir, sl_err *e) {
    DIR *d = opendir(dir);
    if (!d) return sl_fail(e, "%s: cannot list: %s", dir, strerror(errno));
    char **names = NULL;
    size_t n = 0;
    struct dirent *de;
    while ((de = readdir(d)) != NULL) {
        if (!is_header_name(de->d_name)) continue;
        names = sl_realloc(names, (n + 1) * sizeof *names);
        names[n++] = sl_strdup(de->d_name);
    }
    closedir(d);
    if (n) qsort(names, n, sizeof *names, cmp_str);
    int rc = 0;
    for (size_t i = 0; i < n; i++) {
        char path[8192];
        unsigned char *data = NULL;
        size_t size = 0;
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        if (rc == 0 && sl_read_file(path, &data, &size, SL_MAX_KERNEL_SOURCE, e) == 0) {
            key_add_str(h, names[i]);
            key_add(h, data, size);
            free(data);
        } else {
            rc = -1;
        }
        free(names[i]);
    }
    free(names);
    return rc;
}

/* ---------------------------------------------------------------- cache file */

/* The payload is the driver's binary as clGetProgramInfo gives it (base/disk_cache.h wraps it
 * with the key and an integrity hash); bump when that changes. */
#define CLBIN_FORMAT 2u

/* Every kernel the source declares (`__kernel void NAME(`) is in the program's kernel list: a
 * cache entry whose key and hash are right but whose binary is another program's (forged, or
 * copied over) is caught here, not by every later run failing (issue 21). */
static int has_source_kernels(cl_program p, const unsigned char *src, size_t n) {
    size_t len = 0;
    if (clGetProgramInfo(p, CL_PROGRAM_KERNEL_NAMES, 0, NULL, &len) != CL_SUCCESS || len == 0)
        return 0;
    char *names = sl_malloc(len + 2);
    names[0] = ';';
    if (clGetProgramInfo(p, CL_PROGRAM_KERNEL_NAMES, len, names + 1, NULL) != CL_SUCCESS) {
        free(names);
        return 0;
    }
    names[len] = ';'; /* ";k1;k2;...;kn;" */
    names[len + 1] = 0;
    int ok = 1;
    const char *kw = "__kernel void ";
    size_t kl = strlen(kw);
    for (size_t i = 0; ok && i + kl < n; i++) {
        if (memcmp(src + i, kw, kl) != 0) continue;
        size_t a = i + kl, b = a;
        while (b < n && (isalnum((unsigned char)src[b]) || src[b] == '_'))
            b++;
        char want[160];
        if (b == a || b - a + 3 > sizeof want) continue;
        snprintf(want, sizeof want, ";%.*s;", (int)(b - a), (const char *)src + a);
        ok = strstr(names, want) != NULL;
        i = b;
    }
    free(names);
    return ok;
}

/* Loads a valid entry into a built program, or returns -1 (missing, corrupt, rejected, or
 * without the source's kernels). */
static int cache_load(const sl_cl_build_target *t, const char *path, sl_cache_key key,
                      const char *options, const unsigned char *src, size_t src_size,
                      cl_program *prog) {
    void *data = NULL;
    size_t bin_size = 0;
    if (sl_cache_read(path, CLBIN_FORMAT, key, SL_MAX_CACHE_ENTRY, &data, &bin_size, NULL))
        return -1;
    if (bin_size == 0) {
        free(data);
        return -1;
    }
    const unsigned char *bin = data;
    cl_int err, status = CL_SUCCESS;
    cl_program p = clCreateProgramWithBinary(t->ctx, 1, &t->device, &bin_size, &bin, &status, &err);
    free(data);
    if (err != CL_SUCCESS || status != CL_SUCCESS) {
        if (err == CL_SUCCESS) clReleaseProgram(p);
        return -1;
    }
    if (clBuildProgram(p, 1, &t->device, options, NULL, NULL) != CL_SUCCESS ||
        !has_source_kernels(p, src, src_size)) {
        clReleaseProgram(p);
        return -1; /* a miss: rebuilt from source, and the entry rewritten */
    }
    *prog = p;
    return 0;
}

/* Best effort: a cache that cannot be written only costs time later. */
static void cache_store(const char *path, sl_cache_key key, cl_program prog) {
    size_t bin_size = 0;
    if (clGetProgramInfo(prog, CL_PROGRAM_BINARY_SIZES, sizeof bin_size, &bin_size, NULL) !=
            CL_SUCCESS ||
        bin_size == 0 || bin_size > SL_MAX_CACHE_ENTRY)
        return;
    unsigned char *bin = sl_malloc(bin_size);
    if (clGetProgramInfo(prog, CL_PROGRAM_BINARIES, sizeof bin, &bin, NULL) == CL_SUCCESS) {
        sl_cache_part part = {bin, bin_size};
        sl_cache_write(path, CLBIN_FORMAT, key, &part, 1, 0, NULL);
    }
    free(bin);
}

/* ---------------------------------------------------------------- build */

/* Prints the build log to stderr, each line prefixed with "strandlight: <file>: ". */
static void print_build_log(cl_program p, cl_device_id dev, const char *cl_file) {
    size_t n = 0;
    if (clGetProgramBuildInfo(p, dev, CL_PROGRAM_BUILD_LOG, 0, NULL, &n) != CL_SUCCESS || n == 0)
        return;
    char *log = sl_calloc(n + 1, 1);
    if (clGetProgramBuildInfo(p, dev, CL_PROGRAM_BUILD_LOG, n, log, NULL) == CL_SUCCESS) {
        for (char *line = log; *line;) {
            char *nl = strchr(line, '\n');
            if (nl) *nl = 0;
            if (*line) fprintf(stderr, "strandlight: %s: %s\n", cl_file, line);
            if (!nl) break;
            line = nl + 1;
        }
    }
    free(log);
}

int sl_cl_build_program(const sl_cl_build_target *t, const char *cl_file, const char *options,
                        cl_program *prog, int *from_cache, sl_err *e) {
    *prog = NULL;
    *from_cache = 0;
    char path[8192];
    sl_path_join(t->kernel_dir, cl_file, path, sizeof path);
    unsigned char *src = NULL;
    size_t src_size = 0;
    if (sl_read_file(path, &src, &src_size, SL_MAX_KERNEL_SOURCE, e)) return SL_CL_EKERNEL;

    size_t opt_len = strlen(t->kernel_dir) + strlen(options ? options : "") + 64;
    char *opts = sl_malloc(opt_len);
    snprintf(opts, opt_len, "-I%s -cl-std=CL1.2%s%s", t->kernel_dir, options && *options ? " " : "",
             options ? options : "");

    char entry[8192 + 64];
    entry[0] = 0;
    key_hash key = {0x5354524e444c4954ull, 0x9e3779b97f4a7c15ull};
    if (t->cache_dir && *t->cache_dir) {
        key_add(&key, src, src_size);
        int ok = key_add_headers(&key, t->kernel_dir, NULL) == 0;
        key_add_str(&key, t->device_name);
        key_add_str(&key, t->driver_version);
        key_add_str(&key, t->platform_name);
        key_add_str(&key, t->platform_version);
        key_add_str(&key, opts);
        if (ok) {
            char stem[256];
            const char *base = strrchr(cl_file, '/');
            snprintf(stem, sizeof stem, "%s", base ? base + 1 : cl_file);
            char *dot = strrchr(stem, '.');
            if (dot) *dot = 0;
            if (sl_cache_path(entry, sizeof entry, t->cache_dir, stem, key, CLBIN_FORMAT) &&
                cache_load(t, entry, key, opts, src, src_size, prog) == 0) {
                *from_cache = 1;
                free(src);
                free(opts);
                return 0;
            }
        }
    }

    cl_int err;
    const char *srcp = (const char *)src;
    cl_program p = clCreateProgramWithSource(t->ctx, 1, &srcp, &src_size, &err);
    free(src);
    if (err != CL_SUCCESS) {
        free(opts);
        return sl_cl_check(err, path, e);
    }
    err = clBuildProgram(p, 1, &t->device, opts, NULL, NULL);
    free(opts);
    if (err != CL_SUCCESS) {
        print_build_log(p, t->device, cl_file);
        clReleaseProgram(p);
        sl_fail(e, "%s: OpenCL build failed on '%s': %s (%d)%s", path, t->device_name,
                sl_cl_strerror(err), (int)err,
                err == CL_BUILD_PROGRAM_FAILURE ? " (build log above)" : "");
        return SL_CL_EKERNEL;
    }
    if (entry[0]) cache_store(entry, key, p);
    *prog = p;
    return 0;
}
