/* output_set.c: see output_set.h. */
#include "base/output_set.h"

#include <errno.h>
#include <fcntl.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

/* The flags of renameat2(2) (linux/fs.h), spelled here so that no _GNU_SOURCE is needed. */
#define SL_RENAME_NOREPLACE (1u << 0)
#define SL_RENAME_EXCHANGE (1u << 1)

static int renameat2_raw(const char *from, const char *to, unsigned flags) {
#ifdef SYS_renameat2
    return (int)syscall(SYS_renameat2, AT_FDCWD, from, AT_FDCWD, to, flags);
#else
    (void)from, (void)to, (void)flags;
    errno = ENOSYS;
    return -1;
#endif
}

int sl_exchange_unsupported(int err) {
    return err == EINVAL || err == ENOSYS || err == ENOTSUP || err == EOPNOTSUPP;
}

int sl_dir_exchange(const char *a, const char *b) {
    const char *off = getenv("SL_NO_RENAME_EXCHANGE");
    if (off && *off && strcmp(off, "0") != 0) {
        errno = EINVAL;
        return -1;
    }
    return renameat2_raw(a, b, SL_RENAME_EXCHANGE);
}

int sl_rename_noreplace(const char *from, const char *to) {
    if (renameat2_raw(from, to, SL_RENAME_NOREPLACE) == 0) return 0;
    if (!sl_exchange_unsupported(errno)) return -1;
    /* no renameat2 here: check, then rename (a name created in between is replaced; rename
     * never replaces a non-empty directory) */
    struct stat st;
    if (lstat(to, &st) == 0) {
        errno = EEXIST;
        return -1;
    }
    return rename(from, to);
}

void sl_fsync_dir(const char *dir) {
    int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    (void)fsync(fd);
    close(fd);
}

void sl_signals_hold(sl_signal_hold *h) {
    sigset_t s;
    sigemptyset(&s);
    sigaddset(&s, SIGINT);
    sigaddset(&s, SIGTERM);
    sigaddset(&s, SIGHUP);
    /* the process's mask: the renderer's worker threads are joined before any output is written */
    sigprocmask(SIG_BLOCK, &s, &h->old);
}

void sl_signals_release(sl_signal_hold *h) {
    sigprocmask(SIG_SETMASK, &h->old, NULL);
}

int sl_output_set_commit(sl_atomic_file *const *set, int n, sl_err *e) {
    sl_signal_hold hold;
    sl_signals_hold(&hold);
    int failed = -1, err = 0;
    for (int i = 0; i < n; i++) {
        if (!set[i]->tmp_path[0]) continue;
        if (i > 0) sl_kill_point("between the renames of an output set");
        if (rename(set[i]->tmp_path, set[i]->path) != 0) {
            failed = i;
            err = errno;
            break;
        }
        set[i]->tmp_path[0] = 0;
    }
    if (failed >= 0)
        for (int i = failed; i < n; i++)
            if (set[i]->tmp_path[0]) {
                remove(set[i]->tmp_path);
                set[i]->tmp_path[0] = 0;
            }
    sl_signals_release(&hold);
    char dir[4096], prev[4096] = "";
    for (int i = 0; i < (failed >= 0 ? failed : n); i++) {
        sl_dirname(set[i]->path, dir, sizeof dir);
        if (strcmp(dir, prev) != 0) sl_fsync_dir(dir);
        snprintf(prev, sizeof prev, "%s", dir);
    }
    if (failed < 0) return 0;
    if (failed == 0)
        return sl_fail(e, "%s: cannot rename temporary file into place: %s", set[0]->path,
                       strerror(err));
    return sl_fail(e, "%s: cannot rename temporary file into place: %s (%s was already replaced)",
                   set[failed]->path, strerror(err), set[0]->path);
}

/* Process-wide, like the allocation counter (common.c): tests only. */
static atomic_long kill_count;
static atomic_int kill_mode = -1; /* -1: read the environment; 0: off; 1: on */
static long kill_at;
static int kill_print, kill_sig = SIGKILL;

void sl_kill_at(long k, int print) {
    kill_at = k;
    kill_print = print;
    atomic_store(&kill_count, 0);
    atomic_store(&kill_mode, k > 0 || print);
}

void sl_kill_point(const char *what) {
    int mode = atomic_load(&kill_mode);
    if (mode < 0) {
        const char *a = getenv("SL_KILL_AT"), *p = getenv("SL_KILL_POINTS");
        kill_at = a ? strtol(a, NULL, 10) : 0;
        kill_print = p && *p && strcmp(p, "0") != 0;
        const char *g = getenv("SL_KILL_SIGNAL");
        if (g && atoi(g) > 0) kill_sig = atoi(g);
        mode = kill_at > 0 || kill_print;
        atomic_store(&kill_mode, mode);
    }
    if (!mode) return;
    long k = atomic_fetch_add(&kill_count, 1) + 1;
    if (kill_print) fprintf(stderr, "strandlight: kill point %ld: %s\n", k, what);
    if (k == kill_at) {
        fflush(stderr);
        kill(getpid(), kill_sig);
    }
}
