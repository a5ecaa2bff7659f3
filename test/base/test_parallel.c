/* test_parallel.c: the thread fan-out of host/base/parallel.c. Every item runs exactly once,
 * the static parts are the documented ones whatever the thread count, results reduced in part or
 * item order are bit-identical for 1 .. N threads, empty ranges call nothing (dynamic) or every
 * part with an empty range (static), and threads that fail to start leave their work to the
 * calling thread (sl_parallel_limit_spawns stands in for pthread_create failing). */
#include "base/parallel.h"
#include "test.h"

#include <math.h>
#include <stdatomic.h>
#include <string.h>

enum { N_ITEMS = 5000, MAX_PARTS = 300 };

typedef struct rec_ctx {
    atomic_int hits[N_ITEMS]; /* how often each item ran */
    double value[N_ITEMS];    /* the item's result */
    size_t begin[MAX_PARTS], end[MAX_PARTS];
    atomic_int calls[MAX_PARTS]; /* static: calls per part; dynamic: chunks per worker */
    double part_sum[MAX_PARTS];  /* static: per-part partial sum, in item order */
    atomic_int max_worker;
} rec_ctx;

/* An item's value: enough float work that a different order of operations would show. */
static double item_value(size_t i) {
    double x = 0.1 + (double)i * 1e-3;
    return sin(x) * exp(-x * 1e-2) + 1.0 / (1.0 + x);
}

static void rec_reset(rec_ctx *c) {
    memset(c, 0, sizeof *c);
    atomic_init(&c->max_worker, -1);
}

static void note_worker(rec_ctx *c, int w) {
    int m = atomic_load(&c->max_worker);
    while (w > m && !atomic_compare_exchange_weak(&c->max_worker, &m, w)) {
    }
}

static void rec_part(void *arg, size_t b, size_t e, int part) {
    rec_ctx *c = arg;
    c->begin[part] = b, c->end[part] = e;
    atomic_fetch_add(&c->calls[part], 1);
    note_worker(c, part);
    double s = 0;
    for (size_t i = b; i < e; i++) {
        atomic_fetch_add(&c->hits[i], 1);
        c->value[i] = item_value(i);
        s += c->value[i];
    }
    c->part_sum[part] = s;
}

static void rec_chunk(void *arg, size_t b, size_t e, int worker) {
    rec_ctx *c = arg;
    atomic_fetch_add(&c->calls[worker], 1);
    note_worker(c, worker);
    for (size_t i = b; i < e; i++) {
        atomic_fetch_add(&c->hits[i], 1);
        c->value[i] = item_value(i);
    }
}

static int each_once(rec_ctx *c, size_t n) {
    for (size_t i = 0; i < n; i++)
        if (atomic_load(&c->hits[i]) != 1) return 0;
    return 1;
}

static rec_ctx ctx; /* big: not on the stack */

/* Parts are n p / nparts .. n (p + 1) / nparts - 1, each called once with worker = p, and the
 * per-part sums reduced in part order equal a one-thread loop over the same parts bit for bit. */
TEST(parallel_parts_partition_and_sums) {
    const size_t ns[] = {0, 1, 7, N_ITEMS};
    const int nps[] = {1, 2, 3, 7, 16, 257, MAX_PARTS};
    for (size_t a = 0; a < sizeof ns / sizeof *ns; a++)
        for (size_t b = 0; b < sizeof nps / sizeof *nps; b++) {
            size_t n = ns[a];
            int np = nps[b];
            rec_reset(&ctx);
            int used = sl_parallel_parts(np, n, rec_part, &ctx);
            CHECK(used >= 1 &&
                  used <= (np < SL_PARALLEL_MAX_THREADS ? np : SL_PARALLEL_MAX_THREADS));
            CHECK(each_once(&ctx, n));
            double sum = 0, want = 0;
            for (int p = 0; p < np; p++) {
                CHECK(atomic_load(&ctx.calls[p]) == 1);
                CHECK(ctx.begin[p] == n * (size_t)p / (size_t)np);
                CHECK(ctx.end[p] == n * (size_t)(p + 1) / (size_t)np);
                sum += ctx.part_sum[p];
                double s = 0;
                for (size_t i = n * (size_t)p / (size_t)np; i < n * (size_t)(p + 1) / (size_t)np;
                     i++)
                    s += item_value(i);
                want += s;
            }
            CHECK(memcmp(&sum, &want, sizeof sum) == 0);
        }
    /* nparts < 1 is one part */
    rec_reset(&ctx);
    CHECK(sl_parallel_parts(0, 10, rec_part, &ctx) == 1);
    CHECK(atomic_load(&ctx.calls[0]) == 1 && ctx.begin[0] == 0 && ctx.end[0] == 10);
}

/* Dynamic: every item once for 1 .. 9 threads and several chunk sizes, workers numbered below
 * the returned count, the values (and their sum in item order) the same as one thread's. */
TEST(parallel_for_deterministic) {
    static double want[N_ITEMS];
    double want_sum = 0;
    for (size_t i = 0; i < N_ITEMS; i++)
        want[i] = item_value(i), want_sum += want[i];
    const size_t chunks[] = {0, 1, 13, 1000, N_ITEMS + 5};
    for (int nt = 1; nt <= 9; nt++)
        for (size_t k = 0; k < sizeof chunks / sizeof *chunks; k++) {
            rec_reset(&ctx);
            int used = sl_parallel_for(nt, N_ITEMS, chunks[k], rec_chunk, &ctx);
            CHECK(used >= 1 && used <= nt);
            CHECK(each_once(&ctx, N_ITEMS));
            CHECK(atomic_load(&ctx.max_worker) < used);
            CHECK(memcmp(ctx.value, want, sizeof want) == 0);
            double sum = 0;
            for (size_t i = 0; i < N_ITEMS; i++)
                sum += ctx.value[i];
            CHECK(memcmp(&sum, &want_sum, sizeof sum) == 0);
        }
    /* at most one thread per chunk */
    rec_reset(&ctx);
    CHECK(sl_parallel_for(8, 3, 1, rec_chunk, &ctx) <= 3);
    CHECK(each_once(&ctx, 3));
}

static void count_call(void *arg, size_t b, size_t e, int worker) {
    (void)b, (void)e, (void)worker;
    atomic_fetch_add((atomic_int *)arg, 1);
}

TEST(parallel_empty_range) {
    atomic_int calls;
    atomic_init(&calls, 0);
    CHECK(sl_parallel_for(4, 0, 1, count_call, &calls) == 1);
    CHECK(atomic_load(&calls) == 0);
    CHECK(sl_parallel_for_progress(4, 0, 1, count_call, &calls, NULL, NULL) == 1);
    CHECK(atomic_load(&calls) == 0);
    /* static: every part runs (callers initialise per-part outputs there), all empty */
    rec_reset(&ctx);
    sl_parallel_parts(5, 0, rec_part, &ctx);
    for (int p = 0; p < 5; p++)
        CHECK(atomic_load(&ctx.calls[p]) == 1 && ctx.begin[p] == 0 && ctx.end[p] == 0);
}

typedef struct prog_log {
    int n, monotone, in_range;
    double last;
} prog_log;

/* Called on the calling thread only, so no atomics. */
static void prog_cb(void *user, double f) {
    prog_log *l = user;
    if (l->n && f < l->last) l->monotone = 0;
    if (!(f >= 0.0 && f <= 1.0)) l->in_range = 0;
    l->last = f;
    l->n++;
}

/* Progress: fractions in [0, 1], non-decreasing, the last 1.0; the work done once. */
TEST(parallel_for_progress_reports) {
    for (int nt = 1; nt <= 4; nt++) {
        prog_log l = {0, 1, 1, -1};
        rec_reset(&ctx);
        int used = sl_parallel_for_progress(nt, N_ITEMS, 1, rec_chunk, &ctx, prog_cb, &l);
        CHECK(used >= 1 && used <= nt);
        CHECK(each_once(&ctx, N_ITEMS));
        CHECK(atomic_load(&ctx.max_worker) < used);
        CHECK(l.n >= 1 && l.monotone && l.in_range && l.last == 1.0);
    }
    prog_log l = {0, 1, 1, -1};
    sl_parallel_for_progress(3, 0, 1, rec_chunk, &ctx, prog_cb, &l);
    CHECK(l.n == 1 && l.last == 1.0);
}

/* Threads that do not start: their parts / chunks run on the calling thread, with the same
 * partition, the same values and the same per-part sums as when every thread starts. */
TEST(parallel_spawn_failure_runs_here) {
    static double full_sum[MAX_PARTS], full_val[N_ITEMS];
    rec_reset(&ctx);
    sl_parallel_parts(7, N_ITEMS, rec_part, &ctx);
    memcpy(full_sum, ctx.part_sum, sizeof full_sum);
    memcpy(full_val, ctx.value, sizeof full_val);
    for (int lim = 0; lim <= 3; lim++) {
        sl_parallel_limit_spawns(lim);
        rec_reset(&ctx);
        CHECK(sl_parallel_parts(7, N_ITEMS, rec_part, &ctx) == lim + 1);
        CHECK(each_once(&ctx, N_ITEMS));
        for (int p = 0; p < 7; p++)
            CHECK(atomic_load(&ctx.calls[p]) == 1 &&
                  ctx.begin[p] == (size_t)N_ITEMS * (size_t)p / 7);
        CHECK(memcmp(ctx.part_sum, full_sum, sizeof full_sum) == 0);
        CHECK(memcmp(ctx.value, full_val, sizeof full_val) == 0);

        rec_reset(&ctx);
        CHECK(sl_parallel_for(6, N_ITEMS, 17, rec_chunk, &ctx) == lim + 1);
        CHECK(each_once(&ctx, N_ITEMS));
        CHECK(atomic_load(&ctx.max_worker) <= lim);
        CHECK(memcmp(ctx.value, full_val, sizeof full_val) == 0);

        prog_log l = {0, 1, 1, -1};
        rec_reset(&ctx);
        CHECK(sl_parallel_for_progress(4, N_ITEMS, 1, rec_chunk, &ctx, prog_cb, &l) ==
              (lim ? lim : 1));
        CHECK(each_once(&ctx, N_ITEMS));
        CHECK(l.last == 1.0 && l.monotone);
    }
    sl_parallel_limit_spawns(-1);
    rec_reset(&ctx);
    CHECK(sl_parallel_parts(4, 100, rec_part, &ctx) >= 1);
    CHECK(each_once(&ctx, 100));
}
