/* hair_tfx.c: AMD TressFX .tfx guide-strand files, 3.x (296-byte TressFXFileObject header) and
 * 4.x (160-byte TressFXTFXFileHeader), told apart by the version float at offset 0 (below 3.5:
 * 3.x). Layouts: ../shared/data/README.md. Every strand has the same V vertices, strand-major,
 * vertex 0 the root. Each array is located by an offset in the header; every present array must
 * lie after the header and inside the file, and the file must end with the last array (no
 * trailing bytes). TressFX stores no fiber radius: it is estimated from the bounding box
 * (SL_HAIR_RADIUS_SCALE), times the per-strand thickness coefficient when the file has one. */
#include "io/hair/hair.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct tfx_array {
    const char *what;
    uint32_t offset; /* 0 = absent */
    uint64_t bytes;  /* element size x count */
} tfx_array;

/* Checks that every present array lies inside [header, n) and that the file ends with the last
 * one. The first array (positions) is required. */
static int check_arrays(const tfx_array *arr, int count, uint32_t header, size_t n, uint32_t S,
                        uint32_t V, const char *name, sl_err *e) {
    if (arr[0].offset == 0) return sl_fail(e, "%s: no vertex positions (offset 0)", name);
    uint64_t end_max = header;
    for (int i = 0; i < count; i++) {
        if (!arr[i].offset) continue;
        if (arr[i].offset < header)
            return sl_fail(e, "%s: %s offset %u lies inside the %u-byte header", name, arr[i].what,
                           arr[i].offset, header);
        uint64_t end = (uint64_t)arr[i].offset + arr[i].bytes;
        if (end > n)
            return sl_fail(e,
                           "%s: truncated: %s for %u strands x %u vertices end at byte %llu, the "
                           "file has %zu bytes",
                           name, arr[i].what, S, V, (unsigned long long)end, n);
        if (end > end_max) end_max = end;
    }
    if (end_max < n)
        return sl_fail(e, "%s: %llu trailing bytes after the last array (which ends at byte %llu)",
                       name, (unsigned long long)(n - end_max), (unsigned long long)end_max);
    return 0;
}

int sl_hair_parse_tfx(const unsigned char *d, size_t n, const char *name, sl_hair *out, sl_err *e) {
    memset(out, 0, sizeof *out);
    float version = n >= 4 ? sl_rd_f32(d) : 0;
    if (n < 4 || !(version >= 2.5f && version < 5.0f))
        return sl_fail(e,
                       "%s: not a TressFX file (version float %g at offset 0, expected 3.x or 4.x)",
                       name, (double)version);
    int v3 = version < 3.5f;
    uint32_t header = v3 ? 296 : 160;
    if (n < header)
        return sl_fail(e, "%s: truncated header (%zu bytes, a TressFX %d header has %u)", name, n,
                       v3 ? 3 : 4, header);
    uint32_t S = sl_rd_u32(d + 4), V = sl_rd_u32(d + 8);
    if (S == 0) return sl_fail(e, "%s: no strands (header says 0)", name);
    if (V < 2) return sl_fail(e, "%s: %u vertices per strand, need at least 2", name, V);
    /* S, V < 2^32, so S*V fits in 64 bits, but 16*S*V may not (S = V = 2^30 wraps to 0): a
     * point takes at least 12 bytes, so more points than bytes is refused before any product. */
    uint64_t SV = (uint64_t)S * V;
    if (SV > n)
        return sl_fail(e,
                       "%s: truncated: the header declares %u strands x %u vertices, more than the "
                       "%zu-byte file can hold",
                       name, S, V, n);
    tfx_array all[6];
    int count;
    uint32_t pos_off, pos_stride, thick_off, color_off;
    if (v3) {
        pos_off = sl_rd_u32(d + 144), pos_stride = 12;
        thick_off = sl_rd_u32(d + 148), color_off = sl_rd_u32(d + 156);
        all[0] = (tfx_array){"vertex positions", pos_off, 12 * SV};
        all[1] = (tfx_array){"strand thickness", thick_off, 4ull * S};
        all[2] = (tfx_array){"strand texcoords", sl_rd_u32(d + 152), 8ull * S};
        all[3] = (tfx_array){"vertex colors", color_off, 16 * SV};
        all[4] = (tfx_array){"guide strand indices", sl_rd_u32(d + 160), 4ull * S};
        all[5] = (tfx_array){"vertex texcoords", sl_rd_u32(d + 164), 8 * SV};
        count = 6;
    } else {
        pos_off = sl_rd_u32(d + 12), pos_stride = 16;
        thick_off = sl_rd_u32(d + 24), color_off = sl_rd_u32(d + 28);
        all[0] = (tfx_array){"vertex positions", pos_off, 16 * SV};
        all[1] = (tfx_array){"strand UVs", sl_rd_u32(d + 16), 8ull * S};
        all[2] = (tfx_array){"vertex UVs", sl_rd_u32(d + 20), 8 * SV};
        all[3] = (tfx_array){"strand thickness", thick_off, 4ull * S};
        all[4] = (tfx_array){"vertex colors", color_off, 16 * SV};
        count = 5;
    }
    if (check_arrays(all, count, header, n, S, V, name, e)) return -1;
    /* The positions fit in a file of n bytes, so S*V < n/12 fits in uint32_t. */

    sl_hair_alloc(out, S, (uint32_t)SV);
    snprintf(out->format, sizeof out->format, "TressFX %d .tfx", v3 ? 3 : 4);
    for (uint32_t s = 0; s <= S; s++)
        out->strand_first[s] = s * V;
    for (uint64_t i = 0; i < SV; i++)
        for (int c = 0; c < 3; c++)
            out->pos[3 * i + c] = sl_rd_f32(d + pos_off + pos_stride * i + 4 * c);
    sl_hair_estimate_radius(out);
    out->default_transparency = 0;
    for (int c = 0; c < 3; c++)
        out->default_color[c] = 1;
    if (thick_off) {
        /* TressFX's per-strand thickness is a coefficient of the fiber radius. */
        out->radius = sl_malloc(SV * sizeof *out->radius);
        for (uint32_t s = 0; s < S; s++) {
            float k = sl_rd_f32(d + thick_off + 4 * (size_t)s);
            if (!(k >= 0 && isfinite(k))) {
                sl_hair_free(out);
                return sl_fail(
                    e, "%s: strand %u: thickness coefficient %g is not a finite number >= 0", name,
                    s, (double)k);
            }
            for (uint32_t v = 0; v < V; v++)
                out->radius[(size_t)s * V + v] = k * out->default_radius;
        }
        out->radius_source = SL_RADIUS_PER_POINT;
    }
    if (color_off) {
        out->color = sl_malloc(SV * 3 * sizeof *out->color);
        for (uint64_t i = 0; i < SV; i++)
            for (int c = 0; c < 3; c++)
                out->color[3 * i + c] = sl_rd_f32(d + color_off + 16 * i + 4 * c);
    }
    char extra[128] = "";
    size_t used = 0;
    for (int i = 1; i < count; i++)
        if (all[i].offset && used < sizeof extra)
            used += (size_t)snprintf(extra + used, sizeof extra - used, ", %s", all[i].what);
    if (v3)
        snprintf(
            out->notes, sizeof out->notes,
            "version %.1f, %u vertices per strand, followHairsPerGuide %u, bothEndsImmovable %u%s",
            (double)version, V, sl_rd_u32(d + 12), sl_rd_u32(d + 16), extra);
    else
        snprintf(out->notes, sizeof out->notes, "version %.1f, %u vertices per strand%s",
                 (double)version, V, extra);
    return 0;
}

/* ---- .tfxproj (AMD viewer project, text) ---- */

/* Parses a float token strictly (the whole token). */
static int tok_float(const char *t, float *v) {
    char *end;
    double d = strtod(t, &end);
    if (end == t || *end || !isfinite(d)) return -1;
    *v = (float)d;
    return 0;
}

int sl_tfxproj_parse(const char *text, size_t len, const char *path, sl_tfxproj *p, sl_err *e) {
    memset(p, 0, sizeof *p);
    char dir[4096];
    sl_dirname(path, dir, sizeof dir);
    if (memchr(text, 0, len)) return sl_fail(e, "%s: not a text file (NUL byte)", path);
    size_t pos = 0;
    for (int line_no = 1; pos < len; line_no++) {
        size_t end = pos;
        while (end < len && text[end] != '\n')
            end++;
        char line[1024];
        size_t ll = end - pos;
        if (ll >= sizeof line)
            return sl_fail(e, "%s:%d: line longer than %zu characters", path, line_no,
                           sizeof line - 1);
        memcpy(line, text + pos, ll);
        line[ll] = 0;
        pos = end + 1;
        for (char *c = line; *c; c++) {
            if (*c == '#') {
                *c = 0;
                break;
            }
            if (*c == '\r' || *c == '\t')
                *c = ' ';
            else if ((unsigned char)*c < 32)
                return sl_fail(e, "%s:%d: not a text file (control character)", path, line_no);
        }
        char *tok[8];
        int nt = 0;
        char *save = NULL;
        for (char *s = strtok_r(line, " ", &save); s && nt < 8; s = strtok_r(NULL, " ", &save))
            tok[nt++] = s;
        if (nt == 0) continue;
        if (sl_ext_is(tok[0], "tfx")) {
            if (p->num_groups == SL_TFXPROJ_MAX_GROUPS)
                return sl_fail(e, "%s:%d: more than %d hair groups", path, line_no,
                               SL_TFXPROJ_MAX_GROUPS);
            sl_tfxproj_group *g = &p->groups[p->num_groups];
            char *endp;
            long per = nt >= 2 ? strtol(tok[1], &endp, 10) : -1;
            if (nt < 4 || *endp || per < 0 || per > SL_FOLLOW_MAX_PER_GUIDE ||
                tok_float(tok[2], &g->follow.root_radius) || g->follow.root_radius < 0 ||
                tok_float(tok[3], &g->follow.tip_spread) || g->follow.tip_spread < 0)
                return sl_fail(e,
                               "%s:%d: expected `<file>.tfx <followPerGuide 0..%d> <followRadius "
                               ">= 0> <tipSeparation >= 0> [<file>.tfxsim] [<group>]`",
                               path, line_no, SL_FOLLOW_MAX_PER_GUIDE);
            g->follow.per_guide = (int)per;
            g->follow.seed = (uint32_t)p->num_groups + 1;
            if (strlen(dir) + strlen(tok[0]) + 2 > sizeof g->tfx_path)
                return sl_fail(e, "%s:%d: path too long", path, line_no);
            sl_path_join(dir, tok[0], g->tfx_path, sizeof g->tfx_path);
            snprintf(g->name, sizeof g->name, "%s", nt >= 6 ? tok[5] : tok[0]);
            p->num_groups++;
        } else if (strcmp(tok[0], "hairColor") == 0) {
            if (nt != 4 || tok_float(tok[1], &p->hair_color[0]) ||
                tok_float(tok[2], &p->hair_color[1]) || tok_float(tok[3], &p->hair_color[2]) ||
                p->hair_color[0] < 0 || p->hair_color[1] < 0 || p->hair_color[2] < 0)
                return sl_fail(e, "%s:%d: expected `hairColor r g b` with numbers >= 0", path,
                               line_no);
            p->has_color = 1;
        }
    }
    if (p->num_groups == 0)
        return sl_fail(e, "%s: no hair group (a `<file>.tfx <followPerGuide> ...` line)", path);
    return 0;
}

int sl_tfxproj_read(const char *path, sl_tfxproj *p, sl_err *e) {
    unsigned char *data;
    size_t size;
    memset(p, 0, sizeof *p);
    if (sl_read_file(path, &data, &size, 1 << 20, e)) return -1;
    if (size == 0) {
        free(data);
        return sl_fail(e, "%s: empty file", path);
    }
    int rc = sl_tfxproj_parse((const char *)data, size, path, p, e);
    free(data);
    return rc;
}

int sl_tfxproj_load(const char *path, sl_hair_follow *f, char *tfx_path, size_t n, sl_err *e) {
    sl_tfxproj *p = sl_malloc(sizeof *p);
    int rc = sl_tfxproj_read(path, p, e);
    if (rc == 0) {
        *f = p->groups[0].follow;
        if (tfx_path) snprintf(tfx_path, n, "%s", p->groups[0].tfx_path);
    }
    free(p);
    return rc;
}

int sl_hair_load_tfxproj(const char *path, int with_follow, sl_hair *out, sl_err *e) {
    memset(out, 0, sizeof *out);
    sl_tfxproj *p = sl_malloc(sizeof *p);
    sl_hair *g = sl_calloc(SL_TFXPROJ_MAX_GROUPS, sizeof *g);
    int rc = sl_tfxproj_read(path, p, e), loaded = 0;
    for (; rc == 0 && loaded < p->num_groups; loaded++)
        if (sl_ext_is(p->groups[loaded].tfx_path, "tfxproj"))
            rc = sl_fail(e, "%s: group %s is itself a project", path, p->groups[loaded].name);
        else
            rc = sl_hair_load(p->groups[loaded].tfx_path, &g[loaded], e);
    if (rc == 0) {
        /* One radius estimate for the whole project, from every group's bounds. */
        float lo[3], hi[3], l[3], h[3];
        for (int i = 0; i < loaded; i++) {
            sl_hair_bounds(&g[i], l, h);
            for (int c = 0; c < 3; c++) {
                lo[c] = i == 0 || l[c] < lo[c] ? l[c] : lo[c];
                hi[c] = i == 0 || h[c] > hi[c] ? h[c] : hi[c];
            }
        }
        double d2 = 0;
        for (int c = 0; c < 3; c++)
            d2 += ((double)hi[c] - lo[c]) * ((double)hi[c] - lo[c]);
        float r = (float)(SL_HAIR_RADIUS_SCALE * sqrt(d2));
        size_t used = 0;
        for (int i = 0; rc == 0 && i < loaded; i++) {
            if (g[i].radius_source == SL_RADIUS_ESTIMATED && r > 0) g[i].default_radius = r;
            if (p->has_color) memcpy(g[i].default_color, p->hair_color, sizeof p->hair_color);
            if (with_follow) rc = sl_hair_add_follow(&g[i], &p->groups[i].follow, e);
            if (rc == 0 && used < sizeof out->notes)
                used += (size_t)snprintf(out->notes + used, sizeof out->notes - used,
                                         "%s%s: %u guides x (1 + %d follow)", i ? "; " : "",
                                         p->groups[i].name, g[i].guide_strands,
                                         with_follow ? p->groups[i].follow.per_guide : 0);
        }
    }
    if (rc == 0) {
        char notes[256];
        memcpy(notes, out->notes, sizeof notes);
        *out = g[0];
        memset(&g[0], 0, sizeof g[0]);
        for (int i = 1; rc == 0 && i < loaded; i++)
            rc = sl_hair_append(out, &g[i], e);
        snprintf(out->format, sizeof out->format, "TressFX project .tfxproj");
        out->color_from_file = p->has_color && !out->color;
        memcpy(out->notes, notes, sizeof notes);
        if (rc) sl_hair_free(out);
    }
    for (int i = 0; i < SL_TFXPROJ_MAX_GROUPS; i++)
        sl_hair_free(&g[i]);
    free(g);
    free(p);
    return rc;
}
