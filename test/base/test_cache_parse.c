/* test_cache_parse.c: sl_cache_parse (base/disk_cache.h), the in-memory twin of sl_cache_read
 * that test/fuzz/fuzz_cache.c drives: on an entry written by sl_cache_write and on each kind of
 * damage, the two must agree (a hit with the same payload, or a rejection with the same
 * reason), since the fuzzer's findings only transfer to the reader if they do. */
#include "base/disk_cache.h"
#include "test.h"

#include <stdlib.h>
#include <string.h>

#define FORMAT 9u

/* sl_cache_read on the file and sl_cache_parse on its bytes give the same verdict, payload and
 * reason (after the "NAME: " prefix, which names the file for one and NAME for the other). */
static void agree(const char *path, sl_cache_key key, size_t max, int want_hit) {
    void *rd = NULL;
    size_t rn = 0;
    sl_err re = {{0}}, pe = {{0}};
    int rrc = sl_cache_read(path, FORMAT, key, max, &rd, &rn, &re);
    unsigned char *raw = NULL;
    size_t size = 0;
    CHECK(sl_read_file(path, &raw, &size, 1 << 20, NULL) == 0);
    const void *pd = NULL;
    size_t pn = 0;
    int prc = sl_cache_parse(raw, size, "mem", FORMAT, key, max, &pd, &pn, &pe);
    CHECK_MSG(rrc == (want_hit ? 0 : -1) && prc == rrc, "read %d parse %d (want hit %d)", rrc, prc,
              want_hit);
    if (rrc == 0 && prc == 0) {
        CHECK(pn == rn && memcmp(pd, rd, rn) == 0 && pd == raw + 48);
    } else {
        const char *r = strstr(re.msg, ": "), *p = strstr(pe.msg, ": ");
        CHECK_MSG(r && p && strcmp(r, p) == 0 && strncmp(pe.msg, "mem: ", 5) == 0,
                  "read '%s' parse '%s'", re.msg, pe.msg);
        CHECK(pd == NULL && pn == 0);
    }
    free(rd);
    free(raw);
}

static void poke(const char *path, long offset, unsigned char v) {
    FILE *f = fopen(path, "r+b");
    if (!f) return;
    fseek(f, offset, SEEK_SET);
    fputc(v, f);
    fclose(f);
}

TEST(cache_parse_agrees_with_read) {
    char dir[4096], path[4600];
    sl_test_fresh_dir("cache_parse", dir, sizeof dir);
    sl_cache_key key = {0x1122334455667788ull, 7};
    CHECK(sl_cache_path(path, sizeof path, dir, "p", key, FORMAT));
    const char *text = "a payload of some bytes";
    sl_cache_part part = {text, strlen(text)};
    sl_err e = {{0}};
    CHECK(sl_cache_write(path, FORMAT, key, &part, 1, 0, &e) == 0);
    agree(path, key, 1 << 20, 1);
    agree(path, (sl_cache_key){key.a, 8}, 1 << 20, 0); /* another key */
    agree(path, key, 5, 0);                            /* larger than expected */
    poke(path, 8, 0x55);                               /* another format */
    agree(path, key, 1 << 20, 0);
    CHECK(sl_cache_write(path, FORMAT, key, &part, 1, 0, &e) == 0);
    poke(path, 50, 'X'); /* a flipped payload byte: hash mismatch */
    agree(path, key, 1 << 20, 0);
    CHECK(sl_cache_write(path, FORMAT, key, &part, 1, 0, &e) == 0);
    poke(path, 7, '0'); /* another layout's magic */
    agree(path, key, 1 << 20, 0);
    /* shorter than a header: the same reason from both */
    FILE *f = fopen(path, "wb");
    if (f) {
        fwrite("SLCACHE1", 1, 8, f);
        fclose(f);
    }
    agree(path, key, 1 << 20, 0);
}
