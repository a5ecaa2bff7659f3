/* parallel.h: the one thread fan-out of the tree. Every pass, C twin and reference that splits
 * work over threads goes through one of these three calls, so that the rules that keep outputs
 * independent of the thread count live in one place:
 *  - an item is computed by the same code whichever thread takes it;
 *  - where per-part results are reduced (partial sums, fragment lists, raster planes), the parts
 *    are fixed by the call (sl_parallel_parts) and reduced by the caller in part order;
 *  - a thread that cannot start is no error: its work runs on the calling thread, so a fan-out
 *    never fails and its output does not depend on how many threads did start.
 * No call allocates heap memory (the allocation counts of test/cli/test_faults.sh stay put). */
#ifndef SL_PARALLEL_H
#define SL_PARALLEL_H

#include <stddef.h>

/* The most threads one fan-out starts. Parts beyond it are shared out round-robin (the parts
 * themselves, and so the output, stay the same). */
#define SL_PARALLEL_MAX_THREADS 256

/* Work on items begin .. end - 1. worker: the part (sl_parallel_parts) or the worker
 * (sl_parallel_for*, 0 .. nthreads - 1), for per-part outputs or per-worker scratch. */
typedef void (*sl_parallel_fn)(void *ctx, size_t begin, size_t end, int worker);

/* Static partition: items 0 .. n - 1 in nparts contiguous parts, part p being
 * n p / nparts .. n (p + 1) / nparts - 1; fn runs exactly once for every part, empty ones too,
 * with worker = p. Part 0 runs on the calling thread, the others on threads of their own (a
 * part whose thread does not start runs on the calling thread after part 0). nparts < 1 counts
 * as 1. Returns, when every part is done, the number of threads that ran parts (1 when none
 * started). */
int sl_parallel_parts(int nparts, size_t n, sl_parallel_fn fn, void *ctx);

/* Dynamic: nthreads workers (worker 0 is the calling thread) take chunks of `chunk` items (the
 * last one shorter; chunk 0 counts as 1) in item order from a shared counter until none is
 * left. Which worker runs a chunk changes from run to run, so fn must not let it change a
 * result. Returns the number of threads that worked (at most one per chunk); n = 0: no call. */
int sl_parallel_for(int nthreads, size_t n, size_t chunk, sl_parallel_fn fn, void *ctx);

/* sl_parallel_for with a progress report: the nthreads workers run on threads of their own
 * while the calling thread calls progress(user, done / n) every 0.1 s, done counting the items
 * of finished chunks, and progress(user, 1.0) once all are done. The calling thread does the
 * work itself when no thread starts. progress NULL: exactly sl_parallel_for. */
int sl_parallel_for_progress(int nthreads, size_t n, size_t chunk, sl_parallel_fn fn, void *ctx,
                             void (*progress)(void *user, double fraction), void *user);

/* Tests only: from now on at most max threads start per fan-out, as if pthread_create failed
 * for the others; max < 0 lifts the limit (the default). Not for use while a fan-out runs. */
void sl_parallel_limit_spawns(int max);

/* The online CPUs (at least 1). */
int sl_parallel_cpus(void);
/* The thread count for a request: requested when > 0, else the online CPUs, at most 16. */
int sl_parallel_threads(int requested);

#endif
