/* disk_cache.h: the one way Strandlight keeps things on disk between runs (OpenCL program
 * binaries, SRBF tables, Ren's table, fitted lobes): where the cache lives, an entry's name from
 * its key, an atomic write and a read-back that trusts nothing it cannot verify.
 *
 * An entry is a 48-byte header and a payload:
 *   "SLCACHE1" | format (u32) | 0 (u32) | key.a, key.b (u64) | payload bytes (u64) |
 *   FNV-1a 64 of the payload (u64) | payload
 * in host byte order (a cache belongs to one machine). A reader accepts an entry only when the
 * magic, the caller's format and key, the length (against the file size) and the hash all match;
 * anything else (absent, truncated, flipped bits, another cache's file, an older layout) is a
 * miss, which the caller answers by rebuilding and writing the entry again.
 *
 *   char dir[4096], path[4600];
 *   sl_cache_key key = {hash_of_inputs, 0};
 *   if (sl_cache_dir_find(dir, sizeof dir) &&
 *       sl_cache_path(path, sizeof path, dir, "thing", key, THING_FORMAT) &&
 *       sl_cache_read(path, THING_FORMAT, key, max, &data, &size, NULL) == 0) ... hit ...
 *   sl_cache_part parts[] = {{&meta, sizeof meta}, {table, bytes}};
 *   sl_cache_write(path, THING_FORMAT, key, parts, 2, 0, &e);   (a failure only costs time) */
#ifndef SL_DISK_CACHE_H
#define SL_DISK_CACHE_H

#include "base/common.h"

/* Disk cache directory: $SL_CACHE_DIR, else $XDG_CACHE_HOME/strandlight (absolute values only),
 * else ~/.cache/strandlight; 0 when there is none (SL_CACHE_DIR=off or none, or no HOME). A
 * missing one is created 0700; one that is not a directory, belongs to another user or others
 * can write is not used (0, one warning per process): entries are trusted on their hash only,
 * and another user could plant one with a matching hash. */
int sl_cache_dir_find(char *out, size_t out_size);

/* An entry's key: a hash of everything its payload depends on (each cache derives its own).
 * A 64-bit key leaves b = 0. */
typedef struct sl_cache_key {
    uint64_t a, b;
} sl_cache_key;

/* "<dir>/<stem>-<16 hex digits of a>[<16 of b> when b != 0]-v<layout>.<format>.bin" into out
 * (layout: this header's version); 0 when it does not fit. The versions are in the name so that
 * builds with different layouts sharing one cache directory (two checkouts, an upgrade) keep an
 * entry each instead of rejecting and rewriting each other's. */
int sl_cache_path(char *out, size_t out_size, const char *dir, const char *stem, sl_cache_key key,
                  uint32_t format);

/* One piece of a payload; a write takes several so that a header and large tables need not be
 * copied into one buffer first. */
typedef struct sl_cache_part {
    const void *data;
    size_t size;
} sl_cache_part;

#define SL_CACHE_SYNC 1 /* flags: fsync the entry before the rename (not needed for integrity:
                         * a torn entry fails its hash and is rebuilt) */

/* Writes the entry for key: creates the parent directories, writes a temporary file beside path
 * (a name unique to this process, opened O_CREAT | O_EXCL, so no other writer shares it) and
 * renames it over path. Concurrent writers of one key each rename a whole entry: a reader sees
 * the old one, none, or a complete new one. Returns 0, or -1 with e set (nothing left behind). */
int sl_cache_write(const char *path, uint32_t format, sl_cache_key key, const sl_cache_part *parts,
                   int nparts, int flags, sl_err *e);

/* Reads the payload of a valid entry into *payload (allocated with one spare 0 byte after it, so
 * text can be parsed in place; free() it) and its length into *size. Returns 0 on a hit, 1 when
 * there is no entry, -1 when the entry is rejected, with e (may be NULL) saying why: short,
 * foreign, stale format, another key, larger than max_payload, hash mismatch. A miss leaves
 * *payload NULL. */
int sl_cache_read(const char *path, uint32_t format, sl_cache_key key, size_t max_payload,
                  void **payload, size_t *size, sl_err *e);

/* The checks of sl_cache_read on an entry already in memory (the whole file, entry_size bytes;
 * no I/O): 0 with *payload pointing into entry and *size its length, or -1 with e (may be NULL)
 * saying why ("NAME: why"; *payload NULL). Fuzzed by test/fuzz/fuzz_cache.c. */
int sl_cache_parse(const void *entry, size_t entry_size, const char *name, uint32_t format,
                   sl_cache_key key, size_t max_payload, const void **payload, size_t *size,
                   sl_err *e);

/* Header check only (no payload read, no hash): 1 when path holds an entry of this format and
 * key whose payload is `payload_size` bytes and whose file has exactly that length. A cheap
 * "would a read probably hit" for planners; sl_cache_read still verifies the hash. */
int sl_cache_probe(const char *path, uint32_t format, sl_cache_key key, size_t payload_size);

/* FNV-1a 64 of a file's bytes (the payload hash above), read in blocks; *bytes its length.
 * For files that keep a format of their own (cached reference EXRs) with the hash in a record
 * beside them. Returns 0 or -1 with e set. */
int sl_cache_file_hash(const char *path, uint64_t *hash, uint64_t *bytes, sl_err *e);
/* FNV-1a 64 of a buffer: sl_hash64(data, n, 0) (base/common.h). */
uint64_t sl_cache_hash(const void *data, size_t n);

#endif
