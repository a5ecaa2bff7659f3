/* parallel.c: see parallel.h. Thread handles and per-thread arguments live on the calling
 * thread's stack (SL_PARALLEL_MAX_THREADS of each), never on the heap. */
#include "base/parallel.h"

#include <pthread.h>
#include <unistd.h>
#include <stdatomic.h>
#include <time.h>

static atomic_int spawn_limit = -1;

void sl_parallel_limit_spawns(int max) {
    atomic_store(&spawn_limit, max < 0 ? -1 : max);
}

/* Starts run(arg) on a new thread unless the test limit says no (spawned: threads this fan-out
 * has started so far). 1 when it started. */
static int spawn(pthread_t *tid, void *(*run)(void *), void *arg, int spawned) {
    int lim = atomic_load(&spawn_limit);
    if (lim >= 0 && spawned >= lim) return 0;
    return pthread_create(tid, NULL, run, arg) == 0;
}

static int clamp_threads(int n) {
    return n < 1 ? 1 : (n > SL_PARALLEL_MAX_THREADS ? SL_PARALLEL_MAX_THREADS : n);
}

/* ---- static partition ---- */

typedef struct parts_run {
    size_t n;
    int nparts, nthreads;
    sl_parallel_fn fn;
    void *ctx;
} parts_run;

typedef struct parts_thread {
    const parts_run *r;
    int t;
} parts_thread;

/* Thread t runs parts t, t + nthreads, ...: with nparts <= SL_PARALLEL_MAX_THREADS, part t. */
static void *parts_worker(void *arg) {
    const parts_thread *w = arg;
    const parts_run *r = w->r;
    for (int p = w->t; p < r->nparts; p += r->nthreads) {
        size_t b = r->n * (size_t)p / (size_t)r->nparts;
        size_t e = r->n * (size_t)(p + 1) / (size_t)r->nparts;
        r->fn(r->ctx, b, e, p);
    }
    return NULL;
}

int sl_parallel_parts(int nparts, size_t n, sl_parallel_fn fn, void *ctx) {
    if (nparts < 1) nparts = 1;
    parts_run r = {n, nparts, clamp_threads(nparts), fn, ctx};
    pthread_t tid[SL_PARALLEL_MAX_THREADS];
    parts_thread w[SL_PARALLEL_MAX_THREADS];
    int started[SL_PARALLEL_MAX_THREADS] = {0}, count = 0;
    for (int t = 0; t < r.nthreads; t++) {
        w[t] = (parts_thread){&r, t};
        if (t > 0 && spawn(&tid[t], parts_worker, &w[t], count)) started[t] = 1, count++;
    }
    for (int t = 0; t < r.nthreads; t++)
        if (!started[t]) parts_worker(&w[t]);
    for (int t = 1; t < r.nthreads; t++)
        if (started[t]) pthread_join(tid[t], NULL);
    return count + 1;
}

/* ---- dynamic: chunks from a shared counter ---- */

typedef struct for_run {
    size_t n, chunk;
    sl_parallel_fn fn;
    void *ctx;
    atomic_size_t next, done;
} for_run;

typedef struct for_thread {
    for_run *r;
    int worker;
} for_thread;

static void *for_worker(void *arg) {
    const for_thread *w = arg;
    for_run *r = w->r;
    for (;;) {
        size_t b = atomic_fetch_add(&r->next, r->chunk);
        if (b >= r->n) return NULL;
        size_t e = r->n - b < r->chunk ? r->n : b + r->chunk;
        r->fn(r->ctx, b, e, w->worker);
        atomic_fetch_add(&r->done, e - b);
    }
}

/* Shared set-up: chunk within 1 .. n (so the counter cannot wrap), threads at most one per
 * chunk. Returns the thread count. */
static int for_setup(for_run *r, int nthreads, size_t n, size_t chunk, sl_parallel_fn fn,
                     void *ctx) {
    if (chunk < 1) chunk = 1;
    if (chunk > n) chunk = n ? n : 1;
    r->n = n, r->chunk = chunk, r->fn = fn, r->ctx = ctx;
    atomic_init(&r->next, 0);
    atomic_init(&r->done, 0);
    size_t nchunks = n / chunk + (n % chunk != 0);
    int nt = clamp_threads(nthreads);
    return (size_t)nt > nchunks ? (nchunks ? (int)nchunks : 1) : nt;
}

int sl_parallel_for(int nthreads, size_t n, size_t chunk, sl_parallel_fn fn, void *ctx) {
    for_run r;
    int nt = for_setup(&r, nthreads, n, chunk, fn, ctx);
    if (n == 0) return 1;
    pthread_t tid[SL_PARALLEL_MAX_THREADS];
    for_thread w[SL_PARALLEL_MAX_THREADS];
    int count = 0;
    /* Workers are numbered in the order they start (0 the calling thread), so that the worker
     * index stays below the number that work. */
    for (int t = 1; t < nt; t++) {
        w[count + 1] = (for_thread){&r, count + 1};
        if (spawn(&tid[count + 1], for_worker, &w[count + 1], count)) count++;
    }
    w[0] = (for_thread){&r, 0};
    for_worker(&w[0]);
    for (int t = 1; t <= count; t++)
        pthread_join(tid[t], NULL);
    return count + 1;
}

int sl_parallel_for_progress(int nthreads, size_t n, size_t chunk, sl_parallel_fn fn, void *ctx,
                             void (*progress)(void *user, double fraction), void *user) {
    if (!progress) return sl_parallel_for(nthreads, n, chunk, fn, ctx);
    for_run r;
    int nt = for_setup(&r, nthreads, n, chunk, fn, ctx);
    pthread_t tid[SL_PARALLEL_MAX_THREADS];
    for_thread w[SL_PARALLEL_MAX_THREADS];
    int count = 0;
    for (int t = 0; t < nt && n > 0; t++) {
        w[count] = (for_thread){&r, count};
        if (spawn(&tid[count], for_worker, &w[count], count)) count++;
    }
    if (n > 0 && count == 0) {
        w[0] = (for_thread){&r, 0};
        for_worker(&w[0]); /* no thread started: the work runs here, unreported */
    } else if (n > 0) {
        struct timespec ts = {0, 100 * 1000 * 1000};
        while (atomic_load(&r.done) < n) {
            progress(user, (double)atomic_load(&r.done) / (double)n);
            nanosleep(&ts, NULL);
        }
        for (int t = 0; t < count; t++)
            pthread_join(tid[t], NULL);
    }
    progress(user, 1.0);
    return count ? count : 1;
}

int sl_parallel_cpus(void) {
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : (n > 4096 ? 4096 : (int)n);
}

int sl_parallel_threads(int requested) {
    if (requested > 0) return requested;
    int n = sl_parallel_cpus();
    return n > 16 ? 16 : n;
}
