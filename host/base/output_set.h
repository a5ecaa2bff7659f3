/* output_set.h: outputs that must change together (issue 21, docs/robustness.md section 5).
 *
 * A render's EXR and PNG, or a report directory, are written completely under temporary names
 * first, flushed to disk, and only then put in place, with the renames back to back and SIGINT,
 * SIGTERM and SIGHUP held off between them, so that a reader (and a user who presses ^C) sees the
 * old set or the new one. A SIGKILL (or a power cut) between two renames of two files cannot be
 * excluded in an arbitrary directory: POSIX has no rename of two names at once. A directory can
 * do better: sl_dir_exchange swaps two directories in one step. */
#ifndef SL_OUTPUT_SET_H
#define SL_OUTPUT_SET_H

#include "base/common.h"

#include <signal.h>

/* Renames n finished temporaries (sl_atomic_finish, or a writer's own fsynced temporary) over
 * their targets, back to back, with SIGINT/SIGTERM/SIGHUP blocked until the last one, then
 * fsyncs their directories. On a failure the temporaries not yet renamed are removed and e names
 * the target that failed and those already replaced. Entries with an empty tmp_path are skipped. */
int sl_output_set_commit(sl_atomic_file *const *set, int n, sl_err *e);

/* Blocks (and then restores) SIGINT, SIGTERM and SIGHUP around a few steps that must not be
 * split by a ^C: a signal that arrives meanwhile is delivered at the restore. */
typedef struct {
    sigset_t old;
} sl_signal_hold;
void sl_signals_hold(sl_signal_hold *h);
void sl_signals_release(sl_signal_hold *h);

/* Swaps the directory entries a and b in one step (Linux renameat2 RENAME_EXCHANGE): both must
 * exist. Returns 0, or -1 with errno: EINVAL / ENOSYS / ENOTSUP / EOPNOTSUPP where the filesystem
 * or kernel cannot (then the caller's fallback applies). Tests only: SL_NO_RENAME_EXCHANGE=1 makes
 * it fail with EINVAL, to run the fallback on a filesystem that could. */
int sl_dir_exchange(const char *a, const char *b);
/* 1 when errno from sl_dir_exchange means "not supported here" rather than a real failure. */
int sl_exchange_unsupported(int err);

/* Renames from to to unless to exists (renameat2 RENAME_NOREPLACE where the kernel has it, else
 * link-free rename after a check). Returns 0, or -1 with errno (EEXIST when to exists). */
int sl_rename_noreplace(const char *from, const char *to);

/* fsync of a directory (after renames in it); errors are ignored (some filesystems refuse). */
void sl_fsync_dir(const char *dir);

/* Kill points, for tests only (test/cli/test_outputs.sh): a step of a multi-step output calls
 * sl_kill_point("what"). SL_KILL_AT=k makes the k-th call of the process raise SIGKILL (no
 * handler, no cleanup: a crash or the OOM killer at that moment); SL_KILL_POINTS=1 prints
 * "strandlight: kill point K: what" for each, so a test can count them; SL_KILL_SIGNAL=N sends
 * signal N instead (15: a SIGTERM at that moment, which a held-off step must delay; the signal
 * may then be delivered later, so the call returns). Without the variables a
 * call costs one getenv the first time. */
void sl_kill_point(const char *what);
/* The same from a unit test's forked child (the environment is read once per process): from
 * now, the k-th kill point raises SIGKILL (k = 0: never); print: the lines above. */
void sl_kill_at(long k, int print);

#endif
