/* disk_cache.c: see disk_cache.h. */
#include "base/disk_cache.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The header's layout version is the magic's last character (and part of every entry's name). */
#define LAYOUT 1
static const char cache_magic[8] = {'S', 'L', 'C', 'A', 'C', 'H', 'E', '0' + LAYOUT};
#define HEAD_BYTES 48

static int cache_dir_name(char *out, size_t out_size) {
    const char *v = getenv("SL_CACHE_DIR");
    if (v && *v) {
        if (strcmp(v, "off") == 0 || strcmp(v, "none") == 0) return 0;
        snprintf(out, out_size, "%s", v);
        return 1;
    }
    v = getenv("XDG_CACHE_HOME");
    if (v && v[0] == '/') { /* XDG: relative values are invalid and ignored */
        snprintf(out, out_size, "%s/strandlight", v);
        return 1;
    }
    v = getenv("HOME");
    if (v && *v) {
        snprintf(out, out_size, "%s/.cache/strandlight", v);
        return 1;
    }
    return 0;
}

/* A cache directory this process may trust (issue 21): ours, a directory, writable by nobody
 * else; created 0700 (its parents as the umask allows) when it does not exist. Anything else:
 * no cache, with one warning per process. Returns 1 when usable. */
static int cache_dir_trusted(const char *dir) {
    static int warned;
    struct stat st;
    if (stat(dir, &st) != 0) {
        if (errno != ENOENT) return 0;
        sl_err e;
        /* its parents as any directory the user makes, then the directory itself 0700 */
        if (sl_make_parent_dirs(dir, &e)) return 0;
        if (mkdir(dir, 0700) != 0 && errno != EEXIST) return 0;
        if (stat(dir, &st) != 0) return 0;
    }
    const char *why = !S_ISDIR(st.st_mode)                 ? "is not a directory"
                      : st.st_uid != geteuid()             ? "belongs to another user"
                      : (st.st_mode & (S_IWGRP | S_IWOTH)) ? "is writable by other users"
                                                           : NULL;
    if (!why) return 1;
    if (!warned)
        sl_warn("cache directory %s %s: not used (no disk cache this run; SL_CACHE_DIR chooses "
                "another)",
                dir, why);
    warned = 1;
    return 0;
}

int sl_cache_dir_find(char *out, size_t out_size) {
    if (!cache_dir_name(out, out_size)) return 0;
    return cache_dir_trusted(out);
}

int sl_cache_path(char *out, size_t out_size, const char *dir, const char *stem, sl_cache_key key,
                  uint32_t format) {
    char b[20] = "";
    if (key.b) snprintf(b, sizeof b, "%016llx", (unsigned long long)key.b);
    int n = snprintf(out, out_size, "%s/%s-%016llx%s-v%d.%u.bin", dir, stem,
                     (unsigned long long)key.a, b, LAYOUT, (unsigned)format);
    if (n < 0 || (size_t)n >= out_size) {
        if (out_size) out[0] = 0;
        return 0;
    }
    return 1;
}

/* ---------------------------------------------------------------- hash */

uint64_t sl_cache_hash(const void *data, size_t n) {
    return sl_hash64(data, n, 0);
}

int sl_cache_file_hash(const char *path, uint64_t *hash, uint64_t *bytes, sl_err *e) {
    FILE *fp = fopen(path, "rb");
    if (!fp) return sl_fail(e, "%s: %s", path, strerror(errno));
    unsigned char buf[1 << 16];
    uint64_t h = SL_HASH64_BASIS, n = 0;
    size_t got;
    while ((got = fread(buf, 1, sizeof buf, fp)) > 0) {
        h = sl_hash64_more(h, buf, got);
        n += got;
    }
    int bad = ferror(fp);
    fclose(fp);
    if (bad) return sl_fail(e, "%s: read error", path);
    *hash = h;
    *bytes = n;
    return 0;
}

/* ---------------------------------------------------------------- header */

static void put_u32(unsigned char *p, uint32_t v) {
    memcpy(p, &v, 4);
}
static void put_u64(unsigned char *p, uint64_t v) {
    memcpy(p, &v, 8);
}
static uint32_t get_u32(const unsigned char *p) {
    uint32_t v;
    memcpy(&v, p, 4);
    return v;
}
static uint64_t get_u64(const unsigned char *p) {
    uint64_t v;
    memcpy(&v, p, 8);
    return v;
}

static void head_pack(unsigned char *h, uint32_t format, sl_cache_key key, uint64_t n,
                      uint64_t hash) {
    memcpy(h, cache_magic, 8);
    put_u32(h + 8, format);
    put_u32(h + 12, 0);
    put_u64(h + 16, key.a);
    put_u64(h + 24, key.b);
    put_u64(h + 32, n);
    put_u64(h + 40, hash);
}

/* Why header h (of an entry whose file is file_bytes long) is not an entry of this format and
 * key with a payload of at most max_payload bytes; NULL when it is. */
static const char *head_why(const unsigned char *h, uint64_t file_bytes, uint32_t format,
                            sl_cache_key key, size_t max_payload) {
    if (memcmp(h, cache_magic, 8) != 0) return "not a cache entry of this version";
    if (get_u32(h + 8) != format) return "another payload format";
    if (get_u64(h + 16) != key.a || get_u64(h + 24) != key.b) return "another key";
    if (get_u64(h + 32) > max_payload) return "payload larger than expected";
    if (file_bytes != HEAD_BYTES + get_u64(h + 32))
        return "truncated or extended (length does not match its header)";
    return NULL;
}

/* Opens path and checks everything but the payload hash; returns the open file (positioned at
 * the payload) with the payload length and stored hash, or NULL with *rc = 1 (no entry) or -1
 * (rejected, e set). */
static FILE *head_open(const char *path, uint32_t format, sl_cache_key key, size_t max_payload,
                       uint64_t *n, uint64_t *hash, int *rc, sl_err *e) {
    *rc = -1;
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        if (errno == ENOENT || errno == ENOTDIR) {
            *rc = 1;
            return NULL;
        }
        sl_fail(e, "%s: %s", path, strerror(errno));
        return NULL;
    }
    struct stat st;
    unsigned char h[HEAD_BYTES];
    const char *why = NULL;
    if (fstat(fileno(fp), &st) != 0 || !S_ISREG(st.st_mode))
        why = "not a regular file";
    else if (fread(h, 1, sizeof h, fp) != sizeof h)
        why = "shorter than a cache header";
    else
        why = head_why(h, (uint64_t)st.st_size, format, key, max_payload);
    if (why) {
        sl_fail(e, "%s: %s", path, why);
        fclose(fp);
        return NULL;
    }
    *n = get_u64(h + 32);
    *hash = get_u64(h + 40);
    *rc = 0;
    return fp;
}

int sl_cache_parse(const void *entry, size_t entry_size, const char *name, uint32_t format,
                   sl_cache_key key, size_t max_payload, const void **payload, size_t *size,
                   sl_err *e) {
    *payload = NULL;
    *size = 0;
    const unsigned char *h = entry;
    const char *why = entry_size < HEAD_BYTES
                          ? "shorter than a cache header"
                          : head_why(h, (uint64_t)entry_size, format, key, max_payload);
    if (!why && sl_cache_hash(h + HEAD_BYTES, entry_size - HEAD_BYTES) != get_u64(h + 40))
        why = "payload hash mismatch (corrupt)";
    if (why) return sl_fail(e, "%s: %s", name, why);
    *payload = h + HEAD_BYTES;
    *size = entry_size - HEAD_BYTES;
    return 0;
}

/* ---------------------------------------------------------------- read */

int sl_cache_read(const char *path, uint32_t format, sl_cache_key key, size_t max_payload,
                  void **payload, size_t *size, sl_err *e) {
    *payload = NULL;
    *size = 0;
    uint64_t n = 0, want = 0;
    int rc;
    FILE *fp = head_open(path, format, key, max_payload, &n, &want, &rc, e);
    if (!fp) return rc;
    unsigned char *buf = sl_malloc((size_t)n + 1);
    size_t got = fread(buf, 1, (size_t)n, fp);
    fclose(fp);
    const char *why = NULL;
    if (got != n)
        why = "read error or shrank while being read";
    else if (sl_cache_hash(buf, (size_t)n) != want)
        why = "payload hash mismatch (corrupt)";
    if (why) {
        free(buf);
        return sl_fail(e, "%s: %s", path, why);
    }
    buf[n] = 0;
    *payload = buf;
    *size = (size_t)n;
    return 0;
}

int sl_cache_probe(const char *path, uint32_t format, sl_cache_key key, size_t payload_size) {
    uint64_t n = 0, hash = 0;
    int rc;
    FILE *fp = head_open(path, format, key, payload_size, &n, &hash, &rc, NULL);
    if (!fp) return 0;
    fclose(fp);
    return n == payload_size;
}

/* ---------------------------------------------------------------- write */

static int write_all(int fd, const void *data, size_t n) {
    const unsigned char *p = data;
    while (n > 0) {
        ssize_t k = write(fd, p, n);
        if (k < 0) {
            if (errno == EINTR) continue;
            return -1;
        }
        p += k;
        n -= (size_t)k;
    }
    return 0;
}

int sl_cache_write(const char *path, uint32_t format, sl_cache_key key, const sl_cache_part *parts,
                   int nparts, int flags, sl_err *e) {
    uint64_t n = 0, hash = SL_HASH64_BASIS;
    for (int i = 0; i < nparts; i++) {
        n += parts[i].size;
        hash = sl_hash64_more(hash, parts[i].data, parts[i].size);
    }
    unsigned char h[HEAD_BYTES];
    head_pack(h, format, key, n, hash);
    if (sl_make_parent_dirs(path, e)) return -1;
    /* sl_temp_create: an unpredictable name (remembered for the clean-up on out of memory or a
     * signal), O_EXCL | O_NOFOLLOW: no other writer, file or link shares it. */
    char tmp[4200];
    int fd = sl_temp_create(path, tmp, sizeof tmp, e);
    if (fd < 0) return -1;
    int bad = write_all(fd, h, sizeof h);
    for (int i = 0; i < nparts && !bad; i++)
        bad = write_all(fd, parts[i].data, parts[i].size);
    int err = errno;
    if (!bad && (flags & SL_CACHE_SYNC) && fsync(fd) != 0) bad = 1, err = errno;
    if (close(fd) != 0 && !bad) bad = 1, err = errno;
    if (bad) {
        unlink(tmp);
        return sl_fail(e, "%s: write error: %s", path, strerror(err));
    }
    if (rename(tmp, path) != 0) {
        err = errno;
        unlink(tmp);
        return sl_fail(e, "%s: cannot rename the temporary file: %s", path, strerror(err));
    }
    return 0;
}
