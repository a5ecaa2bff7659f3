/* common.h: error reporting, allocation, file and atomic-output helpers used by every host file.
 *
 * Errors travel as return codes (0 ok, -1 failure) with a message in an sl_err, up to one place
 * (main) that prints them. A message is one line that names the file and the problem, e.g.
 * "scene.json: camera.fov_deg: expected a number". */
#ifndef SL_COMMON_H
#define SL_COMMON_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#define SL_VERSION "0.1.0"

typedef struct sl_err {
    char msg[1024];
} sl_err;

/* Formats the message into e (if non-NULL) and returns -1, so callers can `return sl_fail(...)`. */
int sl_fail(sl_err *e, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Prints a one-line warning to stderr ("strandlight: warning: ..."). */
void sl_warn(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Prints a one-line note to stderr ("strandlight: ..."), e.g. which device was picked. */
void sl_note(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* --quiet: notes, status lines and progress bars off (warnings and errors stay). */
void sl_set_quiet(int quiet);
int sl_is_quiet(void);
/* A one-line status on a terminal ("\r... " overwritten by the next; nothing when stderr is not a
 * terminal or quiet), e.g. the pass a long frame is in; sl_status_clear() erases it. */
void sl_status(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
void sl_status_clear(void);

/* Allocation that aborts with a message on out-of-memory (used for sizes already validated). */
void *sl_malloc(size_t n);
void *sl_calloc(size_t count, size_t size);
void *sl_realloc(void *p, size_t n);
char *sl_strdup(const char *s);
/* Allocation failure injection, for tests only (test/cli/test_faults.sh, docs/robustness.md).
 * The k-th sl_malloc/sl_calloc/sl_realloc/sl_strdup call from now fails as if out of memory
 * (one line "strandlight: out of memory allocating N bytes", temporary outputs removed, exit
 * status 1); k = 0 turns injection off. The environment does the same for a whole process:
 * SL_ALLOC_FAIL_AT=k counts from the start; SL_ALLOC_COUNT=1 prints
 * "strandlight: allocations: N" at exit. sl_alloc_count: allocations counted so far. */
void sl_alloc_fail_after(long k);
long sl_alloc_count(void);

/* Reads a whole regular file. Errors name the path: missing, unreadable, a directory, too big. */
int sl_read_file(const char *path, unsigned char **data, size_t *size, size_t max_size, sl_err *e);

/* Atomic output: write into a temporary file beside `path`, then rename over it on success, or
 * remove it on failure, so no half-written output is ever left behind. */
typedef struct sl_atomic_file {
    char path[4096];
    char tmp_path[4096];
    FILE *fp; /* open on the temporary file */
} sl_atomic_file;
int sl_atomic_open(sl_atomic_file *af, const char *path, sl_err *e);
/* Flushes and fsyncs the temporary of af and closes it, leaving it under its temporary name
 * (af->tmp_path) for sl_output_set_commit; on a write error the temporary is removed and e set. */
int sl_atomic_finish(sl_atomic_file *af, sl_err *e);
int sl_atomic_commit(sl_atomic_file *af, sl_err *e); /* sl_atomic_finish, then renames */
void sl_atomic_abort(sl_atomic_file *af);            /* closes and removes */
/* For writers that open files themselves (OpenEXRCore): a unique temporary name beside path. */
void sl_temp_name(const char *path, char *tmp, size_t tmp_size);
/* Creates that temporary (O_CREAT | O_EXCL | O_NOFOLLOW, mode 0666 less the umask) and returns
 * its descriptor, or -1 with e set; the name is in tmp. */
int sl_temp_create(const char *path, char *tmp, size_t tmp_size, sl_err *e);
/* SIGINT, SIGTERM and SIGHUP remove this process's recent temporaries before it dies (main). */
void sl_install_temp_cleanup(void);
/* An existing output that is one of inputs[0..n-1] (the same file, by device and inode, under
 * any name): a one-line error naming both. */
int sl_output_not_input(const char *path, const char *what, const char *const *inputs, int n,
                        sl_err *e);
/* Creates the parent directories of a file path (like mkdir -p on dirname). */
/* Checks before any work that `path` can be written as a new or replaced regular file: not
 * empty, not a directory (nor ending in '/'), an existing target a regular file (not a symbolic
 * link, a device, a FIFO or a socket: refused, nothing touched), and its directory
 * either existing and writable or one missing level below an existing writable directory (which
 * sl_make_parent_dirs then creates; deeper missing trees are refused: a typo should not build
 * directories anywhere). `what` names the option or key in the message. Returns 0 or -1. */
int sl_output_precheck(const char *path, const char *what, sl_err *e);
int sl_make_parent_dirs(const char *path, sl_err *e);

/* Path helpers. Returns the directory part of path ("." if none) into out. */
void sl_dirname(const char *path, char *out, size_t out_size);
/* Joins base_dir and rel unless rel is absolute. */
void sl_path_join(const char *base_dir, const char *rel, char *out, size_t out_size);
/* Lower-case file extension without the dot ("" if none), pointer into path. */
const char *sl_path_ext(const char *path);
int sl_ext_is(const char *path, const char *ext); /* case-insensitive */

/* Monotonic wall clock in seconds. */
double sl_now(void);

/* 64-bit FNV-1a, for cache keys. */
uint64_t sl_hash64(const void *data, size_t n, uint64_t seed);
/* FNV-1a 64 continued from state h over n more bytes, so that pieces hash as their
 * concatenation: sl_hash64(d, n, seed) == sl_hash64_more(SL_HASH64_BASIS ^ seed, d, n). */
#define SL_HASH64_BASIS 1469598103934665603ull
uint64_t sl_hash64_more(uint64_t h, const void *data, size_t n);

/* Progress bar on stderr when it is a terminal; silent otherwise. */
typedef struct sl_progress {
    const char *label;
    double start, last;
    int active;
} sl_progress;
void sl_progress_begin(sl_progress *p, const char *label);
void sl_progress_update(sl_progress *p, double fraction);
void sl_progress_end(sl_progress *p);

#endif
