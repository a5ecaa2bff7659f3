/* envmap_hdr.c: Radiance RGBE (.hdr) decoding through stb_image (stbi_loadf_from_memory).
 *
 * stb_image reads past a truncated RLE scanline by returning 0 bytes forever, which makes it
 * loop without end, and it silently fills a truncated flat file with zeros. So the header and
 * the scanline structure are walked here first, exactly the way stb will read them (including
 * its quirks: widths < 8 or >= 32768 are always flat; if the first scanline is not RLE the whole
 * image is read flat), and only a complete, well-formed stream is handed to stb. Layout:
 * ../shared/data/README.md "Radiance RGBE". */
#include "io/envmap/envmap.h"

#include <stb/stb_image.h>

#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* Returns the length of the line starting at *pos as stb_image sees it and advances *pos past
 * its '\n'; -1 when no '\n' is left. stb keeps at most 1023 bytes of a line in a C string, so
 * the line ends at its first NUL byte too (a line starting with NUL ends the header for stb). */
static long next_line(const unsigned char *d, size_t n, size_t *pos, const char **line) {
    const unsigned char *nl = memchr(d + *pos, '\n', n - *pos);
    if (!nl) return -1;
    *line = (const char *)d + *pos;
    long len = (long)(nl - (d + *pos));
    *pos = (size_t)(nl - d) + 1;
    const char *nul = memchr(*line, 0, (size_t)len);
    if (nul) len = (long)(nul - *line);
    return len < 1023 ? len : 1023;
}

static int line_is(const char *line, long len, const char *s) {
    return (size_t)len == strlen(s) && memcmp(line, s, (size_t)len) == 0;
}

/* Parses "-Y <H> +X <W>" (the only orientation stb reads). */
static int parse_resolution(const char *line, long len, long long *w, long long *h) {
    char buf[128];
    if (len <= 0 || len >= (long)sizeof buf) return -1;
    memcpy(buf, line, (size_t)len);
    buf[len] = 0;
    char *p = buf, *end;
    if (strncmp(p, "-Y ", 3) != 0) return -1;
    p += 3;
    if (*p < '0' || *p > '9') return -1;
    *h = strtoll(p, &end, 10);
    p = end;
    while (*p == ' ')
        p++;
    if (strncmp(p, "+X ", 3) != 0) return -1;
    p += 3;
    if (*p < '0' || *p > '9') return -1;
    *w = strtoll(p, &end, 10);
    return *end == 0 ? 0 : -1;
}

/* Walks the pixel stream from pos; 0 when it holds exactly what stb will read. */
static int walk_scanlines(const unsigned char *d, size_t n, size_t pos, long w, long h,
                          const char *name, sl_err *e) {
    size_t flat = (size_t)w * (size_t)h * 4;
    if (w < 8 || w >= 32768) {
        if (n - pos < flat)
            return sl_fail(e, "%s: Radiance .hdr: truncated (%zu bytes of pixels, %zu needed)",
                           name, n - pos, flat);
        return 0;
    }
    for (long y = 0; y < h; y++) {
        if (n - pos < 4)
            return sl_fail(e, "%s: Radiance .hdr: truncated at scanline %ld of %ld", name, y, h);
        const unsigned char *s = d + pos;
        if (s[0] != 2 || s[1] != 2 || (s[2] & 0x80)) {
            if (y > 0)
                return sl_fail(e,
                               "%s: Radiance .hdr: scanline %ld is not run-length encoded but "
                               "earlier ones are (unsupported mix)",
                               name, y);
            if (n - pos < flat)
                return sl_fail(
                    e, "%s: Radiance .hdr: truncated (%zu bytes of flat pixels, %zu needed)", name,
                    n - pos, flat);
            return 0;
        }
        long len = (long)s[2] << 8 | s[3];
        if (len != w)
            return sl_fail(e, "%s: Radiance .hdr: scanline %ld has length %ld, expected %ld", name,
                           y, len, w);
        pos += 4;
        for (int k = 0; k < 4; k++) {
            long i = 0;
            while (i < w) {
                if (pos >= n)
                    return sl_fail(e, "%s: Radiance .hdr: truncated at scanline %ld of %ld", name,
                                   y, h);
                unsigned c = d[pos++];
                if (c > 128) {
                    c -= 128;
                    if (pos >= n)
                        return sl_fail(e, "%s: Radiance .hdr: truncated at scanline %ld of %ld",
                                       name, y, h);
                    pos++;
                } else if (n - pos < c) {
                    return sl_fail(e, "%s: Radiance .hdr: truncated at scanline %ld of %ld", name,
                                   y, h);
                } else {
                    pos += c;
                }
                if ((long)c > w - i)
                    return sl_fail(e, "%s: Radiance .hdr: corrupt run-length data in scanline %ld",
                                   name, y);
                i += c;
            }
        }
    }
    return 0;
}

int sl_envmap_decode_hdr(const unsigned char *d, size_t n, const char *name, sl_envmap *out,
                         sl_err *e) {
    memset(out, 0, sizeof *out);
    if (n > INT_MAX) return sl_fail(e, "%s: Radiance .hdr: file too large", name);
    size_t pos = 0;
    const char *line;
    long len = next_line(d, n, &pos, &line);
    /* Exactly what stbi__hdr_test accepts (otherwise stb would try its 8-bit formats). */
    int magic = (n >= 11 && memcmp(d, "#?RADIANCE\n", 11) == 0) ||
                (n >= 7 && memcmp(d, "#?RGBE\n", 7) == 0);
    if (len < 0 || !magic)
        return sl_fail(e, "%s: not a Radiance .hdr file (first line must be #?RADIANCE)", name);
    int format_ok = 0;
    for (;;) {
        len = next_line(d, n, &pos, &line);
        if (len < 0) return sl_fail(e, "%s: Radiance .hdr: truncated header", name);
        if (len == 0) break;
        if (len > 10 && memcmp(line, "FORMAT=", 7) == 0) {
            if (!line_is(line, len, "FORMAT=32-bit_rle_rgbe"))
                return sl_fail(e, "%s: Radiance .hdr: unsupported %.*s (only 32-bit_rle_rgbe)",
                               name, (int)(len > 60 ? 60 : len), line);
            format_ok = 1;
        }
    }
    if (!format_ok)
        return sl_fail(e, "%s: Radiance .hdr: missing FORMAT=32-bit_rle_rgbe header line", name);
    len = next_line(d, n, &pos, &line);
    if (len < 0) return sl_fail(e, "%s: Radiance .hdr: missing resolution line", name);
    long long w, h;
    if (parse_resolution(line, len, &w, &h))
        return sl_fail(
            e,
            "%s: Radiance .hdr: unsupported resolution line '%.*s' (expected -Y <height> "
            "+X <width>)",
            name, (int)(len > 40 ? 40 : len), line);
    /* RLE stores at most 127 bytes of one component in 2 bytes: at most ~16 pixels per byte. */
    if (!sl_envmap_size_ok(w, h, n, 32.0))
        return sl_fail(e, "%s: Radiance .hdr: implausible size %lld x %lld for a %zu-byte file",
                       name, w, h, n);
    /* stb's floats and our copy (envmap.h): limits before the scanline walk and the decode */
    if (!sl_decode_budget_ok(name, "Radiance .hdr", w, h, 4.0, 24.0, n, e)) return -1;
    if (walk_scanlines(d, n, pos, (long)w, (long)h, name, e)) return -1;

    int sw, sh, comp;
    float *px = stbi_loadf_from_memory(d, (int)n, &sw, &sh, &comp, 3);
    if (!px) return sl_fail(e, "%s: Radiance .hdr: %s", name, stbi_failure_reason());
    if (sw != w || sh != h) {
        stbi_image_free(px);
        return sl_fail(e, "%s: Radiance .hdr: decoder disagrees on the size", name);
    }
    size_t nv = (size_t)w * (size_t)h * 3;
    out->rgb = sl_malloc(nv * sizeof(float));
    memcpy(out->rgb, px, nv * sizeof(float));
    stbi_image_free(px);
    out->width = (int)w;
    out->height = (int)h;
    out->channels = 3;
    snprintf(out->format, sizeof out->format, "Radiance RGBE");
    snprintf(out->channel_names, sizeof out->channel_names, "RGBE");
    return 0;
}
