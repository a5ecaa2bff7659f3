/* hair_usc.c: the USC-HairSalon .data format (layout: ../shared/data/README.md): i32 strand count,
 * then per strand i32 n and f32[n][3] points, root first; the file ends with the last record.
 *
 * Policy (as Digital Salon's Loader::load_data): a count of 0, a strand with 0 points and
 * trailing bytes are errors; strands with a single point are dropped (counted in
 * dropped_strands; sl_hair_load warns). The records are walked once to validate sizes before
 * anything is allocated, so an absurd strand count cannot allocate more than the file holds. */
#include "io/hair/hair.h"

#include <string.h>

int sl_hair_parse_usc(const unsigned char *d, size_t n, const char *name, sl_hair *out, sl_err *e) {
    memset(out, 0, sizeof *out);
    if (n < 4)
        return sl_fail(
            e, "%s: truncated: %zu bytes, a .data file starts with a 4-byte strand count", name, n);
    int32_t S = (int32_t)sl_rd_u32(d);
    if (S <= 0) return sl_fail(e, "%s: strand count %d (must be positive)", name, (int)S);
    /* Pass 1: sizes only. */
    size_t off = 4;
    uint64_t kept_points = 0;
    uint32_t kept = 0, dropped = 0;
    for (int32_t s = 0; s < S; s++) {
        if (n - off < 4)
            return sl_fail(
                e, "%s: truncated: the file declares %d strands but ends after %d (%zu bytes)",
                name, (int)S, (int)s, n);
        int32_t np = (int32_t)sl_rd_u32(d + off);
        if (np <= 0)
            return sl_fail(e, "%s: strand %d: point count %d (must be positive)", name, (int)s,
                           (int)np);
        if ((uint64_t)(n - off - 4) < 12ull * (uint32_t)np)
            return sl_fail(e,
                           "%s: truncated: strand %d declares %d points (ends at byte %llu), the "
                           "file has %zu bytes",
                           name, (int)s, (int)np,
                           (unsigned long long)(off + 4 + 12ull * (uint32_t)np), n);
        off += 4 + 12 * (size_t)np;
        if (np == 1) {
            dropped++;
        } else {
            kept++;
            kept_points += (uint32_t)np;
        }
    }
    if (off < n)
        return sl_fail(e, "%s: %zu trailing bytes after the last strand (which ends at byte %zu)",
                       name, n - off, off);
    if (kept == 0)
        return sl_fail(e, "%s: no strand has at least 2 points (%u single-point strands)", name,
                       dropped);
    /* Pass 2: copy (kept_points * 12 <= n, so it fits in uint32_t). */
    sl_hair_alloc(out, kept, (uint32_t)kept_points);
    snprintf(out->format, sizeof out->format, "USC-HairSalon .data");
    off = 4;
    uint32_t s_out = 0, p_out = 0;
    for (int32_t s = 0; s < S; s++) {
        uint32_t np = sl_rd_u32(d + off);
        off += 4;
        if (np >= 2) {
            out->strand_first[s_out++] = p_out;
            for (size_t i = 0; i < 3 * (size_t)np; i++)
                out->pos[3 * (size_t)p_out + i] = sl_rd_f32(d + off + 4 * i);
            p_out += np;
        }
        off += 12 * (size_t)np;
    }
    out->strand_first[kept] = p_out;
    out->dropped_strands = dropped;
    sl_hair_estimate_radius(out);
    out->default_transparency = 0;
    for (int c = 0; c < 3; c++)
        out->default_color[c] = 1;
    snprintf(out->notes, sizeof out->notes, "%d strands in the file, %u single-point dropped",
             (int)S, dropped);
    return 0;
}
