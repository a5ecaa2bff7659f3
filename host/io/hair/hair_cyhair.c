/* hair_cyhair.c: Cem Yuksel's cyHair .hair format (layout: ../shared/data/README.md).
 *
 * 128-byte header ("HAIR", strands S, points P, flags, defaults), then the arrays whose flag
 * bits are set: u16 segments[S], f32 points[P][3], thickness[P], transparency[P], color[P][3].
 * The file size must be exactly what the header declares (checked before allocating, so absurd
 * counts cannot allocate gigabytes). Thickness is a DIAMETER: radius = thickness / 2. */
#include "io/hair/hair.h"
#include "io/hair/hair_cyhair.h"

#include <math.h>
#include <string.h>

/* Copies count little-endian floats from an unaligned buffer. */
static void read_floats(const unsigned char *src, size_t count, float *dst) {
    for (size_t i = 0; i < count; i++)
        dst[i] = sl_rd_f32(src + 4 * i);
}

int sl_hair_parse_cyhair(const unsigned char *d, size_t n, const char *name, sl_hair *out,
                         sl_err *e) {
    memset(out, 0, sizeof *out);
    if (n < 4 || memcmp(d, "HAIR", 4) != 0)
        return sl_fail(e, "%s: wrong magic number (expected \"HAIR\" for a .hair file)", name);
    if (n < CY_HEADER)
        return sl_fail(e, "%s: truncated header (%zu bytes, a .hair header has %d)", name, n,
                       CY_HEADER);
    uint32_t S = sl_rd_u32(d + 4), P = sl_rd_u32(d + 8), flags = sl_rd_u32(d + 12);
    uint32_t def_segments = sl_rd_u32(d + 16);
    float def_thickness = sl_rd_f32(d + 20), def_transparency = sl_rd_f32(d + 24);
    if (flags & ~0x1fu)
        return sl_fail(e, "%s: unknown header flag bits 0x%x (only bits 0-4 are defined)", name,
                       flags);
    if (!(flags & CY_POINTS))
        return sl_fail(e, "%s: no points array (header flag bit 1 is clear)", name);
    if (S == 0) return sl_fail(e, "%s: no strands (header says 0)", name);
    uint64_t expect = CY_HEADER;
    if (flags & CY_SEGMENTS) expect += 2ull * S;
    expect += 12ull * P; /* points */
    if (flags & CY_THICKNESS) expect += 4ull * P;
    if (flags & CY_TRANSPARENCY) expect += 4ull * P;
    if (flags & CY_COLOR) expect += 12ull * P;
    if (expect > n)
        return sl_fail(e,
                       "%s: truncated: the header declares %u strands and %u points (%llu bytes), "
                       "the file has %zu bytes",
                       name, S, P, (unsigned long long)expect, n);
    if (expect < n)
        return sl_fail(e, "%s: %llu trailing bytes after the %llu bytes the header declares", name,
                       (unsigned long long)(n - expect), (unsigned long long)expect);

    /* Strand sizes: each strand has segments + 1 points; they must add up to P. */
    const unsigned char *a = d + CY_HEADER;
    uint64_t sum;
    if (flags & CY_SEGMENTS) {
        sum = 0;
        for (uint32_t s = 0; s < S; s++) {
            uint32_t seg = (uint32_t)a[2 * (size_t)s] | (uint32_t)a[2 * (size_t)s + 1] << 8;
            if (seg == 0)
                return sl_fail(e, "%s: strand %u has 0 segments (1 point), need at least 1", name,
                               s);
            sum += seg + 1;
        }
    } else {
        if (def_segments == 0)
            return sl_fail(e, "%s: default segment count is 0 (strands need at least 1)", name);
        sum = (uint64_t)S * ((uint64_t)def_segments + 1);
    }
    if (sum != P)
        return sl_fail(e,
                       "%s: the strands' segment counts add up to %llu points, the header says %u",
                       name, (unsigned long long)sum, P);

    sl_hair_alloc(out, S, P);
    snprintf(out->format, sizeof out->format, "cyHair .hair");
    uint32_t first = 0;
    for (uint32_t s = 0; s < S; s++) {
        out->strand_first[s] = first;
        first += (flags & CY_SEGMENTS)
                     ? ((uint32_t)a[2 * (size_t)s] | (uint32_t)a[2 * (size_t)s + 1] << 8) + 1
                     : def_segments + 1;
    }
    out->strand_first[S] = first;
    if (flags & CY_SEGMENTS) a += 2 * (size_t)S;
    read_floats(a, 3 * (size_t)P, out->pos);
    a += 12 * (size_t)P;
    if (flags & CY_THICKNESS) {
        out->radius = sl_malloc((size_t)P * sizeof *out->radius);
        read_floats(a, P, out->radius);
        for (uint32_t i = 0; i < P; i++) {
            if (!(out->radius[i] >= 0 && isfinite(out->radius[i]))) {
                sl_fail(e, "%s: point %u: thickness %g is not a finite number >= 0", name, i,
                        (double)out->radius[i]);
                sl_hair_free(out);
                return -1;
            }
            out->radius[i] *= 0.5f; /* diameter -> radius */
        }
        a += 4 * (size_t)P;
        out->radius_source = SL_RADIUS_PER_POINT;
    } else {
        if (!(def_thickness > 0 && isfinite(def_thickness))) {
            sl_hair_free(out);
            return sl_fail(e, "%s: default thickness %g is not a positive number", name,
                           (double)def_thickness);
        }
        out->radius_source = SL_RADIUS_HEADER;
    }
    out->default_radius = 0.5f * def_thickness;
    if (flags & CY_TRANSPARENCY) {
        out->transparency = sl_malloc((size_t)P * sizeof *out->transparency);
        read_floats(a, P, out->transparency);
        a += 4 * (size_t)P;
    }
    out->default_transparency = def_transparency;
    if (flags & CY_COLOR) {
        out->color = sl_malloc((size_t)P * 3 * sizeof *out->color);
        read_floats(a, 3 * (size_t)P, out->color);
    }
    for (int c = 0; c < 3; c++)
        out->default_color[c] = sl_rd_f32(d + 28 + 4 * c);
    /* Defaults that no point uses are not validated: give them neutral values. */
    if (out->radius && !(out->default_radius > 0 && isfinite(out->default_radius)))
        out->default_radius = 0;
    if (out->transparency && !(def_transparency >= 0 && def_transparency <= 1))
        out->default_transparency = 0;
    for (int c = 0; out->color && c < 3; c++)
        if (!(out->default_color[c] >= 0 && isfinite(out->default_color[c])))
            out->default_color[c] = 1;

    char info[89];
    memcpy(info, d + 40, 88);
    info[88] = 0;
    for (char *c = info; *c; c++)
        if ((unsigned char)*c < 32 || (unsigned char)*c > 126) *c = '?';
    snprintf(out->notes, sizeof out->notes, "flags 0x%02x, default segments %u%s%s%s", flags,
             def_segments, info[0] ? ", info \"" : "", info, info[0] ? "\"" : "");
    return 0;
}
