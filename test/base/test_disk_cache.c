/* test_disk_cache.c: host/base/disk_cache.c, the one disk cache every cache uses: entry names,
 * round trip, rejection of anything that does not verify (a flipped byte, a truncated file, a
 * foreign key or format) and concurrent writers of one key (processes and threads) ending with
 * one whole entry and no temporary files. */
#include "base/disk_cache.h"
#include "test.h"

#include <dirent.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#define FORMAT 7u

/* Overwrites one byte of a file at offset (from the end when negative). */
static void poke(const char *path, long offset, unsigned char v) {
    FILE *f = fopen(path, "r+b");
    if (!f) return;
    fseek(f, offset, offset < 0 ? SEEK_END : SEEK_SET);
    fputc(v, f);
    fclose(f);
}

static int write_entry(const char *path, sl_cache_key key, const char *a, const char *b) {
    sl_cache_part parts[2] = {{a, strlen(a)}, {b, strlen(b)}};
    sl_err e = {{0}};
    return sl_cache_write(path, FORMAT, key, parts, 2, 0, &e);
}

TEST(disk_cache_path_from_key) {
    char p[64];
    CHECK(sl_cache_path(p, sizeof p, "/c", "tab", (sl_cache_key){0x1234, 0}, 3));
    CHECK(strcmp(p, "/c/tab-0000000000001234-v1.3.bin") == 0); /* 64-bit keys: 16 digits */
    CHECK(sl_cache_path(p, sizeof p, "/c", "t", (sl_cache_key){1, 2}, 12));
    CHECK(strcmp(p, "/c/t-00000000000000010000000000000002-v1.12.bin") == 0);
    CHECK(!sl_cache_path(p, 20, "/c", "tab", (sl_cache_key){1, 0}, 1) && p[0] == 0);
}

TEST(disk_cache_round_trip) {
    char dir[4096], path[4600];
    sl_test_fresh_dir("dcache_rt", dir, sizeof dir);
    sl_cache_key key = {0xabcdef, 0x42};
    CHECK(sl_cache_path(path, sizeof path, dir, "rt", key, FORMAT));
    void *data = (void *)1;
    size_t n = 99;
    sl_err e = {{0}};
    CHECK(sl_cache_read(path, FORMAT, key, 1 << 20, &data, &n, &e) == 1); /* no entry yet */
    CHECK(data == NULL && n == 0);
    CHECK(write_entry(path, key, "hello, ", "cache") == 0);
    CHECK(sl_cache_read(path, FORMAT, key, 1 << 20, &data, &n, &e) == 0);
    CHECK(n == 12 && data && memcmp(data, "hello, cache", 12) == 0);
    CHECK(data && ((char *)data)[12] == 0); /* the spare 0 after the payload */
    free(data);
    CHECK(sl_cache_probe(path, FORMAT, key, 12));
    CHECK(!sl_cache_probe(path, FORMAT, key, 11));
    CHECK(sl_test_count_files(dir, ".tmp") == 0);
    /* an empty payload is an entry too */
    CHECK(write_entry(path, key, "", "") == 0);
    CHECK(sl_cache_read(path, FORMAT, key, 1 << 20, &data, &n, &e) == 0 && n == 0);
    free(data);
    /* the integrity hash is FNV-1a 64, the same as sl_hash64 with seed 0 and a whole file's */
    CHECK(sl_cache_hash("abc", 3) == sl_hash64("abc", 3, 0));
    uint64_t h = 0, bytes = 0;
    CHECK(sl_cache_file_hash(path, &h, &bytes, &e) == 0 && bytes == 48);
    unsigned char *raw = NULL;
    size_t rn = 0;
    CHECK(sl_read_file(path, &raw, &rn, 1 << 20, &e) == 0 && rn == 48);
    CHECK(raw && h == sl_cache_hash(raw, rn));
    free(raw);
}

/* Every kind of damage is a miss (-1, with a reason), never a trusted payload; a rewrite makes
 * the entry good again. */
TEST(disk_cache_rejects_damage) {
    char dir[4096], path[4600];
    sl_test_fresh_dir("dcache_bad", dir, sizeof dir);
    sl_cache_key key = {7, 8};
    CHECK(sl_cache_path(path, sizeof path, dir, "bad", key, FORMAT));
    const char *payload = "0123456789abcdefghijklmnopqrstuvwxyz";
    void *data = NULL;
    size_t n = 0;
    sl_err e = {{0}};

    /* a flipped byte in the payload, then in each header field */
    long offsets[] = {-1, 48, 0, 8, 16, 24, 32, 40};
    for (size_t i = 0; i < sizeof offsets / sizeof offsets[0]; i++) {
        CHECK(write_entry(path, key, payload, "") == 0);
        CHECK(sl_cache_read(path, FORMAT, key, 1 << 20, &data, &n, &e) == 0);
        free(data);
        FILE *f = fopen(path, "rb");
        int c = 0;
        if (f) {
            fseek(f, offsets[i], offsets[i] < 0 ? SEEK_END : SEEK_SET);
            c = fgetc(f);
            fclose(f);
        }
        poke(path, offsets[i], (unsigned char)(c ^ 0x10));
        e.msg[0] = 0;
        CHECK_MSG(sl_cache_read(path, FORMAT, key, 1 << 20, &data, &n, &e) == -1,
                  "byte at %ld flipped: accepted", offsets[i]);
        CHECK(data == NULL && e.msg[0] != 0);
    }
    /* a flipped payload byte is caught by the hash */
    CHECK(write_entry(path, key, payload, "") == 0);
    poke(path, 60, 'Z');
    CHECK(sl_cache_read(path, FORMAT, key, 1 << 20, &data, &n, &e) == -1);
    CHECK(strstr(e.msg, "hash") != NULL);

    /* truncated: inside the payload, inside the header, empty; and a byte appended */
    size_t cuts[] = {60, 47, 20, 0};
    for (size_t i = 0; i < sizeof cuts / sizeof cuts[0]; i++) {
        CHECK(write_entry(path, key, payload, "") == 0);
        CHECK(truncate(path, (off_t)cuts[i]) == 0);
        CHECK_MSG(sl_cache_read(path, FORMAT, key, 1 << 20, &data, &n, &e) == -1,
                  "truncated to %zu: accepted", cuts[i]);
        CHECK(!sl_cache_probe(path, FORMAT, key, strlen(payload)));
    }
    CHECK(write_entry(path, key, payload, "") == 0);
    FILE *f = fopen(path, "ab");
    if (f) {
        fputc('x', f);
        fclose(f);
    }
    CHECK(sl_cache_read(path, FORMAT, key, 1 << 20, &data, &n, &e) == -1);

    /* wrong key, wrong format, larger than the caller allows */
    CHECK(write_entry(path, key, payload, "") == 0);
    CHECK(sl_cache_read(path, FORMAT, (sl_cache_key){7, 9}, 1 << 20, &data, &n, &e) == -1);
    CHECK(sl_cache_read(path, FORMAT, (sl_cache_key){6, 8}, 1 << 20, &data, &n, &e) == -1);
    CHECK(strstr(e.msg, "key") != NULL);
    CHECK(sl_cache_read(path, FORMAT + 1, key, 1 << 20, &data, &n, &e) == -1);
    CHECK(sl_cache_read(path, FORMAT, key, 10, &data, &n, &e) == -1);
    CHECK(!sl_cache_probe(path, FORMAT, (sl_cache_key){7, 9}, strlen(payload)));
    /* a file in an older layout (here: plain text) */
    f = fopen(path, "wb");
    if (f) {
        fputs("{\"lobes\": []}\n and more text to be longer than a header ..........", f);
        fclose(f);
    }
    CHECK(sl_cache_read(path, FORMAT, key, 1 << 20, &data, &n, &e) == -1);

    /* rewritten: good again */
    CHECK(write_entry(path, key, payload, "") == 0);
    CHECK(sl_cache_read(path, FORMAT, key, 1 << 20, &data, &n, &e) == 0);
    CHECK(n == strlen(payload) && data && memcmp(data, payload, n) == 0);
    free(data);
    CHECK(sl_test_count_files(dir, ".tmp") == 0);
}

/* A write that cannot happen fails with a message and leaves nothing behind. */
TEST(disk_cache_write_failure) {
    char dir[4096], path[4600], blocker[4200];
    sl_test_fresh_dir("dcache_fail", dir, sizeof dir);
    snprintf(blocker, sizeof blocker, "%s/file", dir);
    FILE *f = fopen(blocker, "wb");
    if (f) fclose(f);
    snprintf(path, sizeof path, "%s/sub/x.bin", blocker); /* parent is a regular file */
    sl_cache_part part = {"x", 1};
    sl_err e = {{0}};
    CHECK(sl_cache_write(path, FORMAT, (sl_cache_key){1, 0}, &part, 1, SL_CACHE_SYNC, &e) == -1);
    CHECK(e.msg[0] != 0);
    CHECK(sl_test_count_files(dir, ".tmp") == 0);
    /* SL_CACHE_SYNC on a good path */
    snprintf(path, sizeof path, "%s/new/dirs/y.bin", dir);
    CHECK(sl_cache_write(path, FORMAT, (sl_cache_key){1, 0}, &part, 1, SL_CACHE_SYNC, &e) == 0);
    CHECK(sl_cache_probe(path, FORMAT, (sl_cache_key){1, 0}, 1));
}

/* ---- concurrent writers ---- */

#define PAYLOAD (96 * 1024)
#define ROUNDS 25

/* Payload of writer w: every byte derived from w, so a reader can tell whose entry it got and
 * whether it is whole. */
static void fill(unsigned char *p, int w) {
    for (size_t i = 0; i < PAYLOAD; i++)
        p[i] = (unsigned char)(w * 31 + i * 7 + (i >> 9));
}

static int is_whole(const void *data, size_t n, int writers) {
    if (n != PAYLOAD) return 0;
    unsigned char *want = malloc(PAYLOAD);
    int ok = 0;
    for (int w = 0; w < writers && !ok; w++) {
        fill(want, w);
        ok = memcmp(data, want, PAYLOAD) == 0;
    }
    free(want);
    return ok;
}

typedef struct writer_arg {
    const char *path;
    int w, failures;
} writer_arg;

static void *writer_thread(void *p) {
    writer_arg *a = p;
    unsigned char *buf = malloc(PAYLOAD);
    fill(buf, a->w);
    sl_cache_part part = {buf, PAYLOAD};
    for (int r = 0; r < ROUNDS; r++) {
        sl_err e;
        if (sl_cache_write(a->path, FORMAT, (sl_cache_key){5, 5}, &part, 1, 0, &e)) a->failures++;
    }
    free(buf);
    return NULL;
}

/* Processes and threads write the same key at once while the parent reads: every read is a
 * whole entry of one writer or no entry (never a rejected or mixed one), and at the end there is
 * one valid entry and no temporary file. */
TEST(disk_cache_concurrent_writers) {
    char dir[4096], path[4600];
    sl_test_fresh_dir("dcache_conc", dir, sizeof dir);
    sl_cache_key key = {5, 5};
    CHECK(sl_cache_path(path, sizeof path, dir, "conc", key, FORMAT));
    enum { PROCS = 3, THREADS = 3 };
    pid_t pids[PROCS];
    int status[PROCS] = {0}, reaped[PROCS] = {0};
    fflush(stdout);
    for (int i = 0; i < PROCS; i++) {
        pids[i] = fork();
        if (pids[i] == 0) {
            writer_arg a = {path, i, 0};
            writer_thread(&a);
            _exit(a.failures ? 1 : 0);
        }
    }
    pthread_t th[THREADS];
    writer_arg args[THREADS];
    for (int i = 0; i < THREADS; i++) {
        args[i] = (writer_arg){path, PROCS + i, 0};
        pthread_create(&th[i], NULL, writer_thread, &args[i]);
    }
    int reads = 0, bad = 0;
    for (int live = 1; live;) {
        void *data = NULL;
        size_t n = 0;
        sl_err e = {{0}};
        int rc = sl_cache_read(path, FORMAT, key, PAYLOAD, &data, &n, &e);
        reads++;
        if (rc == 0) {
            if (!is_whole(data, n, PROCS + THREADS)) bad++;
        } else if (rc < 0) {
            if (bad++ < 3) CHECK_MSG(0, "a concurrent read was rejected: %s", e.msg);
        }
        free(data);
        live = 0; /* read until the writer processes are done (the threads are as busy) */
        for (int i = 0; i < PROCS; i++)
            if (!reaped[i]) {
                if (pids[i] > 0 && waitpid(pids[i], &status[i], WNOHANG) == 0)
                    live = 1;
                else
                    reaped[i] = 1;
            }
        if (reads > 100000) break;
    }
    for (int i = 0; i < THREADS; i++) {
        pthread_join(th[i], NULL);
        CHECK(args[i].failures == 0);
    }
    for (int i = 0; i < PROCS; i++) {
        if (!reaped[i] && pids[i] > 0) waitpid(pids[i], &status[i], 0);
        CHECK_MSG(pids[i] > 0 && WIFEXITED(status[i]) && WEXITSTATUS(status[i]) == 0,
                  "writer process %d failed", i);
    }
    CHECK(bad == 0);
    void *data = NULL;
    size_t n = 0;
    sl_err e = {{0}};
    CHECK(sl_cache_read(path, FORMAT, key, PAYLOAD, &data, &n, &e) == 0);
    CHECK(is_whole(data, n, PROCS + THREADS));
    free(data);
    CHECK(sl_test_count_files(dir, ".tmp") == 0);
    CHECK(sl_test_count_files(dir, ".bin") == 1);
}
