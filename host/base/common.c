/* common.c: see common.h. */
#include "base/common.h"

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

int sl_fail(sl_err *e, const char *fmt, ...) {
    if (e) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(e->msg, sizeof e->msg, fmt, ap);
        va_end(ap);
        /* Keep messages to one line whatever got formatted in (file contents, build logs). */
        for (char *c = e->msg; *c; c++)
            if (*c == '\n' || *c == '\r') *c = ' ';
    }
    return -1;
}

void sl_warn(const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    fputs("strandlight: warning: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

static int g_quiet, g_status_shown;

void sl_set_quiet(int quiet) {
    g_quiet = quiet;
}
int sl_is_quiet(void) {
    return g_quiet;
}

void sl_status(const char *fmt, ...) {
    if (g_quiet || !isatty(2)) return;
    va_list ap;
    va_start(ap, fmt);
    fputs("\r", stderr);
    vfprintf(stderr, fmt, ap);
    fputs("\033[K", stderr); /* erase the rest of a longer previous status */
    fflush(stderr);
    va_end(ap);
    g_status_shown = 1;
}

void sl_status_clear(void) {
    if (!g_status_shown) return;
    fputs("\r\033[K", stderr);
    fflush(stderr);
    g_status_shown = 0;
}

void sl_note(const char *fmt, ...) {
    if (g_quiet) return;
    sl_status_clear();
    va_list ap;
    va_start(ap, fmt);
    fputs("strandlight: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

/* ---- out of memory, and allocation failure injection for tests ----
 *
 * Process-wide state, the one deliberate exception to "no global mutable state": the allocation
 * counter and the injected failure point (tests only: SL_ALLOC_FAIL_AT or sl_alloc_fail_after)
 * and the names of the last temporary output files (so that an out-of-memory exit removes a
 * half-written one). Atomics: PoCL runs threads, and a counter must not tear. */

static atomic_long alloc_count;        /* sl_* allocations so far */
static atomic_long alloc_fail_at = -1; /* the count that fails; 0: never; -1: read the env */

#define SL_TEMP_RING 16
static char temp_ring[SL_TEMP_RING][4096]; /* recent sl_temp_name results (may be gone) */
static atomic_uint temp_ring_next;

static void print_alloc_count(void) {
    fprintf(stderr, "strandlight: allocations: %ld\n", atomic_load(&alloc_count));
}

void sl_alloc_fail_after(long k) {
    atomic_store(&alloc_count, 0);
    atomic_store(&alloc_fail_at, k > 0 ? k : 0);
}

long sl_alloc_count(void) {
    return atomic_load(&alloc_count);
}

/* Counts one allocation; returns 1 when it is the one that must fail. */
static int alloc_should_fail(void) {
    long at = atomic_load(&alloc_fail_at);
    if (at < 0) {
        const char *v = getenv("SL_ALLOC_FAIL_AT");
        long k = v ? strtol(v, NULL, 10) : 0;
        long expect = -1;
        if (atomic_compare_exchange_strong(&alloc_fail_at, &expect, k > 0 ? k : 0)) {
            const char *c = getenv("SL_ALLOC_COUNT");
            if (c && *c && strcmp(c, "0") != 0) atexit(print_alloc_count);
        }
        at = atomic_load(&alloc_fail_at);
    }
    long n = atomic_fetch_add(&alloc_count, 1) + 1;
    return at > 0 && n == at;
}

/* Out of memory: one line, remove any temporary output file this process may have left half
 * written, and _exit(1) (not exit: atexit handlers and library destructors may allocate again,
 * and buffered stdout must not be flushed as if the output were complete). */
static void remove_temporaries(void) { /* async-signal-safe: unlink only */
    unsigned used = atomic_load(&temp_ring_next);
    for (unsigned i = 0; i < SL_TEMP_RING && i < used; i++)
        if (temp_ring[i][0]) unlink(temp_ring[i]);
}

static void oom(size_t n) {
    remove_temporaries();
    fprintf(stderr, "strandlight: out of memory allocating %zu bytes\n", n);
    fflush(stderr);
    _exit(1);
}

void *sl_malloc(size_t n) {
    void *p = alloc_should_fail() ? NULL : malloc(n ? n : 1);
    if (!p) oom(n);
    return p;
}

void *sl_calloc(size_t count, size_t size) {
    void *p = alloc_should_fail() ? NULL : calloc(count ? count : 1, size ? size : 1);
    if (!p) oom(count * size);
    return p;
}

void *sl_realloc(void *p, size_t n) {
    void *q = alloc_should_fail() ? NULL : realloc(p, n ? n : 1);
    if (!q) oom(n);
    return q;
}

char *sl_strdup(const char *s) {
    size_t n = strlen(s) + 1;
    char *d = sl_malloc(n);
    memcpy(d, s, n);
    return d;
}

int sl_read_file(const char *path, unsigned char **data, size_t *size, size_t max_size, sl_err *e) {
    struct stat st;
    *data = NULL;
    *size = 0;
    if (stat(path, &st) != 0) return sl_fail(e, "%s: %s", path, strerror(errno));
    if (S_ISDIR(st.st_mode)) return sl_fail(e, "%s: is a directory, expected a file", path);
    if (!S_ISREG(st.st_mode)) return sl_fail(e, "%s: not a regular file", path);
    if ((uint64_t)st.st_size > (uint64_t)max_size)
        return sl_fail(e, "%s: file too large (%lld bytes, limit %zu)", path, (long long)st.st_size,
                       max_size);
    FILE *fp = fopen(path, "rb");
    if (!fp) return sl_fail(e, "%s: %s", path, strerror(errno));
    size_t n = (size_t)st.st_size;
    unsigned char *buf = sl_malloc(n + 1);
    size_t got = fread(buf, 1, n, fp);
    int rerr = ferror(fp);
    fclose(fp);
    if (rerr || got != n) {
        free(buf);
        return sl_fail(e, "%s: read error", path);
    }
    buf[n] = 0; /* convenient for text parsers */
    *data = buf;
    *size = n;
    return 0;
}

void sl_temp_name(const char *path, char *tmp, size_t tmp_size) {
    static atomic_uint counter; /* threads writing cache entries at once get distinct names */
    /* Unpredictable (issue 21): another user who can write the directory cannot plant a file
     * or a symbolic link at the name in advance; sl_temp_create also refuses one (O_EXCL,
     * O_NOFOLLOW). getrandom rarely fails; the fallback mixes the clock, pid and counter. */
    unsigned long long r = 0;
    if (getrandom(&r, sizeof r, GRND_NONBLOCK) != (ssize_t)sizeof r) {
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        r = ((unsigned long long)ts.tv_nsec << 20) ^ (unsigned long long)ts.tv_sec ^
            ((unsigned long long)getpid() << 40);
    }
    snprintf(tmp, tmp_size, "%s.tmp%ld.%u.%016llx", path, (long)getpid(),
             atomic_fetch_add(&counter, 1), r);
    /* Remembered so that an out-of-memory exit can remove it (oom above). */
    unsigned slot = atomic_fetch_add(&temp_ring_next, 1) % SL_TEMP_RING;
    snprintf(temp_ring[slot], sizeof temp_ring[slot], "%s", tmp);
}

int sl_temp_create(const char *path, char *tmp, size_t tmp_size, sl_err *e) {
    for (int attempt = 0; attempt < 16; attempt++) {
        sl_temp_name(path, tmp, tmp_size);
        /* 0666 less the umask, as any file the user creates; never an existing name, never
         * through a symbolic link */
        int fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
        if (fd >= 0) return fd;
        if (errno != EEXIST)
            return sl_fail(e, "%s: cannot create a temporary file: %s", path, strerror(errno));
    }
    return sl_fail(e, "%s: no free temporary name", path);
}

static void on_fatal_signal(int sig) {
    remove_temporaries();
    signal(sig, SIG_DFL);
    raise(sig);
}

void sl_install_temp_cleanup(void) {
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_fatal_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGHUP, &sa, NULL);
}

int sl_output_not_input(const char *path, const char *what, const char *const *inputs, int n,
                        sl_err *e) {
    struct stat so, si;
    if (stat(path, &so) != 0) return 0; /* a new file cannot be an input */
    for (int i = 0; i < n; i++) {
        if (!inputs[i] || !inputs[i][0] || stat(inputs[i], &si) != 0) continue;
        if (so.st_dev == si.st_dev && so.st_ino == si.st_ino)
            return sl_fail(e, "%s: %s: is one of this run's inputs (%s): not overwritten", what,
                           path, inputs[i]);
    }
    return 0;
}

int sl_output_precheck(const char *path, const char *what, sl_err *e) {
    if (!path || !path[0]) return sl_fail(e, "%s: empty output path", what);
    size_t n = strlen(path);
    if (path[n - 1] == '/')
        return sl_fail(e, "%s: %s: is a directory, expected a file", what, path);
    struct stat st;
    if (lstat(path, &st) == 0 && S_ISLNK(st.st_mode))
        return sl_fail(e, "%s: %s: is a symbolic link (neither followed nor replaced)", what, path);
    if (stat(path, &st) == 0) {
        if (S_ISDIR(st.st_mode))
            return sl_fail(e, "%s: %s: is a directory, expected a file", what, path);
        if (!S_ISREG(st.st_mode))
            return sl_fail(e, "%s: %s: exists and is not a regular file", what, path);
    }
    char dir[4096];
    sl_dirname(path, dir, sizeof dir);
    if (stat(dir, &st) == 0) {
        if (!S_ISDIR(st.st_mode))
            return sl_fail(e, "%s: %s: %s is not a directory", what, path, dir);
        if (access(dir, W_OK | X_OK) != 0)
            return sl_fail(e, "%s: %s: directory %s is not writable", what, path, dir);
        return 0;
    }
    char up[4096];
    sl_dirname(dir, up, sizeof up);
    if (stat(up, &st) != 0 || !S_ISDIR(st.st_mode))
        return sl_fail(e, "%s: %s: directory %s does not exist (only one missing level is created)",
                       what, path, up);
    /* a typo at the top of the tree (issue 22: "/ouput/x.exr" made /ouput as root) */
    if (strcmp(up, "/") == 0)
        return sl_fail(e, "%s: %s: directory %s does not exist (none is created at /)", what, path,
                       dir);
    if (access(up, W_OK | X_OK) != 0)
        return sl_fail(e, "%s: %s: cannot create %s: %s is not writable", what, path, dir, up);
    return 0;
}

int sl_make_parent_dirs(const char *path, sl_err *e) {
    char dir[4096];
    sl_dirname(path, dir, sizeof dir);
    if (strcmp(dir, ".") == 0 || strcmp(dir, "/") == 0) return 0;
    for (char *p = dir + 1;; p++) {
        if (*p == '/' || *p == 0) {
            char c = *p;
            *p = 0;
            if (mkdir(dir, 0777) != 0 && errno != EEXIST)
                return sl_fail(e, "%s: cannot create directory %s: %s", path, dir, strerror(errno));
            *p = c;
            if (c == 0) break;
        }
    }
    struct stat st;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
        return sl_fail(e, "%s: %s is not a directory", path, dir);
    return 0;
}

int sl_atomic_open(sl_atomic_file *af, const char *path, sl_err *e) {
    memset(af, 0, sizeof *af);
    if (strlen(path) + 32 >= sizeof af->path) return sl_fail(e, "%s: path too long", path);
    if (sl_make_parent_dirs(path, e)) return -1;
    snprintf(af->path, sizeof af->path, "%s", path);
    int fd = sl_temp_create(path, af->tmp_path, sizeof af->tmp_path, e);
    if (fd < 0) {
        af->tmp_path[0] = 0;
        return -1;
    }
    af->fp = fdopen(fd, "wb");
    if (!af->fp) {
        int err = errno;
        close(fd);
        unlink(af->tmp_path);
        af->tmp_path[0] = 0;
        return sl_fail(e, "%s: cannot write: %s", path, strerror(err));
    }
    return 0;
}

int sl_atomic_finish(sl_atomic_file *af, sl_err *e) {
    int bad = fflush(af->fp) != 0 || ferror(af->fp);
    /* on disk before the rename: else a crash can leave the new name with no data (ext4's
     * delayed allocation) while the old file is gone */
    if (!bad && fsync(fileno(af->fp)) != 0 && errno != EINVAL) bad = 1;
    if (fclose(af->fp) != 0) bad = 1;
    af->fp = NULL;
    if (bad) {
        remove(af->tmp_path);
        af->tmp_path[0] = 0;
        return sl_fail(e, "%s: write error", af->path);
    }
    return 0;
}

int sl_atomic_commit(sl_atomic_file *af, sl_err *e) {
    if (sl_atomic_finish(af, e)) return -1;
    if (rename(af->tmp_path, af->path) != 0) {
        int err = errno;
        remove(af->tmp_path);
        return sl_fail(e, "%s: cannot rename temporary file: %s", af->path, strerror(err));
    }
    return 0;
}

void sl_atomic_abort(sl_atomic_file *af) {
    if (af->fp) fclose(af->fp);
    af->fp = NULL;
    if (af->tmp_path[0]) remove(af->tmp_path);
}

void sl_dirname(const char *path, char *out, size_t out_size) {
    const char *slash = strrchr(path, '/');
    if (!slash) {
        snprintf(out, out_size, ".");
    } else if (slash == path) {
        snprintf(out, out_size, "/");
    } else {
        snprintf(out, out_size, "%.*s", (int)(slash - path), path);
    }
}

void sl_path_join(const char *base_dir, const char *rel, char *out, size_t out_size) {
    if (rel[0] == '/' || !base_dir || !base_dir[0] || strcmp(base_dir, ".") == 0)
        snprintf(out, out_size, "%s", rel);
    else
        snprintf(out, out_size, "%s/%s", base_dir, rel);
}

const char *sl_path_ext(const char *path) {
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(path, '.');
    if (!dot || (slash && dot < slash)) return "";
    return dot + 1;
}

int sl_ext_is(const char *path, const char *ext) {
    const char *x = sl_path_ext(path);
    while (*x && *ext) {
        if (tolower((unsigned char)*x) != tolower((unsigned char)*ext)) return 0;
        x++, ext++;
    }
    return *x == 0 && *ext == 0;
}

double sl_now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

uint64_t sl_hash64_more(uint64_t h, const void *data, size_t n) {
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

uint64_t sl_hash64(const void *data, size_t n, uint64_t seed) {
    return sl_hash64_more(SL_HASH64_BASIS ^ seed, data, n);
}

void sl_progress_begin(sl_progress *p, const char *label) {
    p->label = label;
    p->start = p->last = sl_now();
    p->active = isatty(2) && !g_quiet;
    if (p->active) sl_status_clear();
}

void sl_progress_update(sl_progress *p, double fraction) {
    if (!p->active) return;
    double t = sl_now();
    if (t - p->last < 0.1 && fraction < 1.0) return;
    p->last = t;
    if (fraction < 0) fraction = 0;
    if (fraction > 1) fraction = 1;
    int width = 30, fill = (int)(fraction * width + 0.5);
    char bar[64];
    for (int i = 0; i < width; i++)
        bar[i] = i < fill ? '#' : '.';
    bar[width] = 0;
    double el = t - p->start, eta = fraction > 0.01 ? el * (1 - fraction) / fraction : 0;
    fprintf(stderr, "\r%s [%s] %5.1f%% %.1fs eta %.1fs ", p->label, bar, 100 * fraction, el, eta);
    fflush(stderr);
}

void sl_progress_end(sl_progress *p) {
    if (!p->active) return;
    sl_progress_update(p, 1.0);
    fputc('\n', stderr);
}
