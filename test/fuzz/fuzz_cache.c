/* fuzz_cache.c: libFuzzer target for disk cache entries read back from disk (base/disk_cache.h:
 * header magic, format, key, length, FNV-1a 64 of the payload; sl_cache_parse, the checks of
 * sl_cache_read without the file I/O) and the payload decoders that consume a hit:
 *   format 1 fitted lobes (env_lighting.c: the payload is a lobes file, sl_lobes_parse),
 *   format 2 OpenCL program binary (clrt_cache.c: nothing parses it before OpenCL, which is not
 *            called here; the cache refuses an empty payload, checked below),
 *   format 5 SRBF tables (sl_srbf_tables_from_payload), REN format 2 Ren's table
 *            (sl_srbf_ren_from_payload), with their real format numbers.
 * Input: a selector byte, then the entry (the whole file). Selector bits 0-1 pick the consumer
 * (lobes, program binary, SRBF tables, Ren's table); bit 2 takes the expected key from the
 * entry's own key field (else a fixed key, so that "another key" is reached too); bit 3 has the
 * harness write the true payload length and hash into the header first, so that mutations reach
 * the payload decoders (a fuzzer cannot find FNV-1a 64 values).
 * Checks: on a hit, the payload is the entry's bytes after the 48-byte header, its hash is the
 * stored one, and the format, key and length match; on a rejection, *payload is NULL and the
 * message is one non-empty line that starts with the file name. The payload decoders keep their
 * promises (lobes: 1..SL_LOBES_MAX unit-direction lobes with lambda > 0 and finite rgb >= 0, or a
 * one-line message; tables: only the exact size is accepted; Ren: only the expected n_floats and
 * dims and the exact size, built_on NUL-terminated). The entry is an exact-size copy, so ASan
 * catches a read past its end. Seeds: test/fuzz/corpus/fuzz_cache/.
 */
// clang-format off
/* FUZZ_SOURCES: host/base/disk_cache.c host/base/common.c host/lighting/lobes_json.c host/base/json_util.c host/passes/shade/srbf_cache_payload.c */
// clang-format on
#include "base/disk_cache.h"
#include "lighting/lobes_json.h"
#include "passes/shade/srbf_cache_payload.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define HEAD 48
#define NAME "fuzz.bin"

static void check_msg(const sl_err *e) {
    if (e->msg[0] == 0 || strchr(e->msg, '\n') || strncmp(e->msg, NAME, strlen(NAME)) != 0)
        __builtin_trap();
}

static void check_lobes(const void *payload, size_t n) {
    sl_lobes l;
    sl_err e = {{0}};
    if (sl_lobes_parse(payload, n, NAME, &l, &e) == 0) {
        if (l.count < 1 || l.count > SL_LOBES_MAX || !l.lobe) __builtin_trap();
        for (int i = 0; i < l.count; i++) {
            const sl_lobe *b = &l.lobe[i];
            double len =
                sqrt(b->dir[0] * b->dir[0] + b->dir[1] * b->dir[1] + b->dir[2] * b->dir[2]);
            /* normalised by the loader: 1 up to a few ulps (as fuzz_lobes.c) */
            if (!(fabs(len - 1) < 1e-12) || !(b->lambda > 0) || !isfinite(b->lambda))
                __builtin_trap();
            for (int k = 0; k < 3; k++)
                if (!(b->rgb[k] >= 0) || !isfinite(b->rgb[k])) __builtin_trap();
        }
        sl_lobes_free(&l);
    } else {
        check_msg(&e);
        if (l.count || l.lobe || l.fit_json) __builtin_trap();
    }
}

static void check_tables(const void *payload, size_t n) {
    sl_srbf_tables t;
    memset(&t, 0, sizeof t);
    int rc = sl_srbf_tables_from_payload(&t, payload, n);
    if ((rc == 0) != (n == sl_srbf_tables_payload_bytes())) __builtin_trap();
    if (rc == 0) {
        if (!t.C || !t.H || !t.D || !t.from_cache) __builtin_trap();
        free(t.C);
        free(t.H);
        free(t.D);
    } else if (t.C || t.H || t.D || t.from_cache) {
        __builtin_trap();
    }
}

static void check_ren(const void *payload, size_t n) {
    sl_srbf_ren t;
    memset(&t, 0, sizeof t);
    /* what the caller expects: a small table of a fixed shape (the fuzzer matches the 88 dims
     * bytes through libFuzzer's memcmp hooks) */
    t.n_floats = 6;
    t.dims.n_h = t.dims.n_t = t.dims.n_p = t.dims.n_l = 2;
    t.dims.nc[0] = 1, t.dims.nc[1] = t.dims.nc[2] = 4;
    t.dims.lmin = 0.01f, t.dims.lmax = 10.0f;
    sl_srbf_ren_dims want = t.dims;
    int rc = sl_srbf_ren_from_payload(&t, payload, n);
    if (rc == 0) {
        sl_srbf_ren_meta h;
        if (n != sizeof h + 6 * sizeof(float)) __builtin_trap();
        memcpy(&h, payload, sizeof h);
        if (h.n_floats != 6 || memcmp(&h.dims, &want, sizeof h.dims) != 0) __builtin_trap();
        if (!t.T || !t.from_cache || !memchr(t.built_on, 0, sizeof t.built_on)) __builtin_trap();
        if (memcmp(t.T, (const unsigned char *)payload + sizeof h, 6 * sizeof(float)) != 0)
            __builtin_trap();
        free(t.T);
    } else if (t.T || t.from_cache || t.build_s != 0 || t.built_on[0]) {
        __builtin_trap(); /* untouched on a refusal */
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size < 1) return 0;
    unsigned sel = data[0];
    data++;
    size--;
    static const uint32_t formats[4] = {1u, 2u, 5u, 2u};
    uint32_t format = formats[sel & 3];
    /* Exact-size copy (no spare byte) so that ASan sees any read past the end. */
    unsigned char *entry = malloc(size ? size : 1);
    if (size) memcpy(entry, data, size);
    if ((sel & 8) && size >= HEAD) {
        uint64_t n = size - HEAD, h = sl_cache_hash(entry + HEAD, size - HEAD);
        memcpy(entry + 32, &n, 8);
        memcpy(entry + 40, &h, 8);
    }
    sl_cache_key key = {0x0123456789abcdefull, 0};
    if ((sel & 4) && size >= 32) {
        memcpy(&key.a, entry + 16, 8);
        memcpy(&key.b, entry + 24, 8);
    }
    size_t max = (sel & 3) == 2   ? sl_srbf_tables_payload_bytes()
                 : (sel & 3) == 3 ? sizeof(sl_srbf_ren_meta) + 6 * sizeof(float)
                                  : (size_t)256 << 20;
    const void *payload = (const void *)1;
    size_t n = 1;
    sl_err e = {{0}};
    if (sl_cache_parse(entry, size, NAME, format, key, max, &payload, &n, &e) == 0) {
        uint32_t f;
        uint64_t len, hash, ka, kb;
        if (size < HEAD || payload != entry + HEAD || n != size - HEAD || n > max) __builtin_trap();
        memcpy(&f, entry + 8, 4);
        memcpy(&ka, entry + 16, 8);
        memcpy(&kb, entry + 24, 8);
        memcpy(&len, entry + 32, 8);
        memcpy(&hash, entry + 40, 8);
        if (memcmp(entry, "SLCACHE1", 8) != 0 || f != format || ka != key.a || kb != key.b ||
            len != n || hash != sl_cache_hash(payload, n))
            __builtin_trap();
        switch (sel & 3) {
        case 0:
            check_lobes(payload, n);
            break;
        case 1:
            break; /* clrt_cache.c hands any non-empty payload to OpenCL, refuses an empty one */
        case 2:
            check_tables(payload, n);
            break;
        default:
            check_ren(payload, n);
            break;
        }
    } else {
        if (payload != NULL || n != 0) __builtin_trap();
        check_msg(&e);
    }
    free(entry);
    return 0;
}
