/* test_hair_formats.c: the hair parsers on small files built byte by byte here (from the layouts
 * in ../shared/data/README.md, not from the loader), every cyHair flag combination, TressFX 3/4
 * optional arrays, USC single-point strands, and the error for each kind of bad input. */
#include "io/hair/hair.h"
#include "test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A growable little-endian byte buffer. */
typedef struct buf {
    unsigned char d[8192];
    size_t n;
} buf;
static void put_u32(buf *b, uint32_t v) {
    for (int i = 0; i < 4; i++)
        b->d[b->n++] = (unsigned char)(v >> (8 * i));
}
static void put_u16(buf *b, uint32_t v) {
    b->d[b->n++] = (unsigned char)v;
    b->d[b->n++] = (unsigned char)(v >> 8);
}
static void put_f32(buf *b, float f) {
    uint32_t u;
    memcpy(&u, &f, 4);
    put_u32(b, u);
}
static void put_zeros(buf *b, size_t k) {
    memset(b->d + b->n, 0, k);
    b->n += k;
}
static void set_u32(buf *b, size_t at, uint32_t v) {
    for (int i = 0; i < 4; i++)
        b->d[at + i] = (unsigned char)(v >> (8 * i));
}

/* Loads b as `name`; returns the loader's status and leaves the message in e. */
static int load(const buf *b, const char *name, sl_hair *h, sl_err *e) {
    e->msg[0] = 0;
    return sl_hair_load_memory(b->d, b->n, name, h, e);
}
/* The load must fail with a message containing `want` (and starting with the name). */
static void expect_fail(const buf *b, const char *name, const char *want) {
    sl_hair h;
    sl_err e;
    int rc = load(b, name, &h, &e);
    CHECK_MSG(rc == -1, "%s: loaded, expected an error containing '%s'", name, want);
    CHECK_MSG(strstr(e.msg, want) != NULL, "message '%s' lacks '%s'", e.msg, want);
    CHECK_MSG(strncmp(e.msg, name, strlen(name)) == 0, "message '%s' does not start with %s", e.msg,
              name);
    CHECK(h.pos == NULL && h.num_strands == 0); /* nothing left to free */
}

/* Point value used in the synthetic files: distinct per point and coordinate. */
static float coord(uint32_t i, int c) {
    return 0.5f * (float)i + 0.25f * (float)c * (float)(i % 3 + 1);
}

/* cyHair with strands of 3, 4 and 2 points (segments 2, 3, 1), or 3 x default 2 segments. */
static void make_cyhair(buf *b, uint32_t flags) {
    const uint16_t segs[3] = {2, 3, 1};
    uint32_t S = 3, P = (flags & 1) ? 3 + 4 + 2 : 9;
    b->n = 0;
    memcpy(b->d, "HAIR", 4);
    b->n = 4;
    put_u32(b, S);
    put_u32(b, P);
    put_u32(b, flags);
    put_u32(b, 2);     /* default segments */
    put_f32(b, 0.3f);  /* default thickness (diameter) */
    put_f32(b, 0.25f); /* default transparency */
    put_f32(b, 0.1f), put_f32(b, 0.2f), put_f32(b, 0.4f);
    memcpy(b->d + b->n, "test", 5);
    put_zeros(b, 88); /* info: "test" then NULs */
    if (flags & 1)
        for (int s = 0; s < 3; s++)
            put_u16(b, segs[s]);
    for (uint32_t i = 0; i < P; i++)
        for (int c = 0; c < 3; c++)
            put_f32(b, coord(i, c));
    if (flags & 4)
        for (uint32_t i = 0; i < P; i++)
            put_f32(b, 0.01f * (float)(i + 1)); /* thickness */
    if (flags & 8)
        for (uint32_t i = 0; i < P; i++)
            put_f32(b, 0.05f * (float)i); /* transparency */
    if (flags & 16)
        for (uint32_t i = 0; i < P; i++)
            for (int c = 0; c < 3; c++)
                put_f32(b, 0.1f * (float)c + 0.01f * (float)i);
}

TEST(hair_cyhair_every_flag_combination) {
    for (uint32_t combo = 0; combo < 16; combo++) {
        /* bit 1 (points) is always set; the other four bits take every combination */
        uint32_t flags = 2 | (combo & 1) | (combo & 2) << 1 | (combo & 4) << 1 | (combo & 8) << 1;
        buf b;
        make_cyhair(&b, flags);
        sl_hair h;
        sl_err e;
        int rc = load(&b, "t.hair", &h, &e);
        CHECK_MSG(rc == 0, "flags 0x%x: %s", flags, e.msg);
        if (rc) continue;
        uint32_t P = (flags & 1) ? 9 : 9, first3[4] = {0, 3, 7, 9}, firstd[4] = {0, 3, 6, 9};
        CHECK(h.num_strands == 3 && h.num_points == P);
        for (int s = 0; s <= 3; s++)
            CHECK(h.strand_first[s] == ((flags & 1) ? first3[s] : firstd[s]));
        for (uint32_t i = 0; i < P; i++)
            for (int c = 0; c < 3; c++)
                CHECK(h.pos[3 * i + c] == coord(i, c));
        if (flags & 4) {
            CHECK(h.radius != NULL);
            /* radius is half the stored diameter; halving a float is exact */
            for (uint32_t i = 0; h.radius && i < P; i++)
                CHECK(h.radius[i] == 0.5f * (0.01f * (float)(i + 1)));
        } else {
            CHECK(h.radius == NULL);
            CHECK(h.default_radius == 0.15f); /* 0.3 / 2 */
            CHECK(h.radius_source == SL_RADIUS_HEADER);
        }
        if (flags & 8) {
            CHECK(h.transparency != NULL);
            for (uint32_t i = 0; h.transparency && i < P; i++)
                CHECK(h.transparency[i] == 0.05f * (float)i);
        } else {
            CHECK(h.transparency == NULL && h.default_transparency == 0.25f);
        }
        if (flags & 16) {
            CHECK(h.color != NULL);
            for (uint32_t i = 0; h.color && i < P; i++)
                for (int c = 0; c < 3; c++)
                    CHECK(h.color[3 * i + c] == 0.1f * (float)c + 0.01f * (float)i);
        } else {
            CHECK(h.color == NULL);
            CHECK(h.default_color[0] == 0.1f && h.default_color[1] == 0.2f &&
                  h.default_color[2] == 0.4f);
        }
        CHECK(strcmp(h.format, "cyHair .hair") == 0);
        sl_hair_free(&h);
    }
}

TEST(hair_cyhair_bad_inputs) {
    buf b;
    make_cyhair(&b, 0x1f);
    size_t full = b.n;
    b.n = 100;
    expect_fail(&b, "t.hair", "truncated header (100 bytes");
    b.n = full - 1;
    expect_fail(&b, "t.hair", "truncated: the header declares 3 strands and 9 points");
    b.n = full + 3;
    expect_fail(&b, "t.hair", "3 trailing bytes");
    b.n = full;
    b.d[0] = 'X';
    expect_fail(&b, "t.hair", "wrong magic number");
    b.d[0] = 'H';
    set_u32(&b, 8, 0xffffffffu); /* absurd point count: refused before allocating 50 GB */
    expect_fail(&b, "t.hair", "truncated: the header declares 3 strands and 4294967295 points");
    set_u32(&b, 4, 0xffffffffu);
    expect_fail(&b, "t.hair", "truncated");
    make_cyhair(&b, 0x1f);
    set_u32(&b, 8, 10); /* P disagrees with the segment counts, file size adjusted */
    put_zeros(&b, 12 + 4 + 4 + 12);
    expect_fail(&b, "t.hair", "add up to 9 points, the header says 10");
    make_cyhair(&b, 0x1f);
    b.d[128] = 0, b.d[129] = 0; /* strand 0 with 0 segments */
    expect_fail(&b, "t.hair", "strand 0 has 0 segments (1 point)");
    make_cyhair(&b, 0x02);
    set_u32(&b, 16, 0); /* default segments 0 */
    expect_fail(&b, "t.hair", "default segment count is 0");
    make_cyhair(&b, 0x02 | 0x20);
    expect_fail(&b, "t.hair", "unknown header flag bits 0x22");
    make_cyhair(&b, 0x10);
    expect_fail(&b, "t.hair", "no points array");
    make_cyhair(&b, 0x02);
    set_u32(&b, 4, 0);
    expect_fail(&b, "t.hair", "no strands");
    make_cyhair(&b, 0x02);
    put_f32(&b, 0); /* keep the size right after overwriting below */
    b.n -= 4;
    float nan = NAN, inf = INFINITY;
    memcpy(b.d + 128 + 12 * 4 + 4, &nan, 4); /* point 4, y */
    expect_fail(&b, "t.hair", "strand 1 point 1: coordinate y is not finite (nan)");
    memcpy(b.d + 128 + 12 * 4 + 4, &inf, 4);
    expect_fail(&b, "t.hair", "coordinate y is not finite (inf)");
    make_cyhair(&b, 0x02);
    for (int k = 1; k < 3; k++)
        memcpy(b.d + 128 + 12 * k, b.d + 128, 12); /* strand 0 coincident */
    expect_fail(&b, "t.hair", "strand 0 has zero length (all 3 points coincide)");
    make_cyhair(&b, 0x06);
    float neg = -1;
    memcpy(b.d + 128 + 12 * 9 + 8, &neg, 4);
    expect_fail(&b, "t.hair", "point 2: thickness -1 is not a finite number >= 0");
    make_cyhair(&b, 0x02);
    memcpy(b.d + 20, &neg, 4);
    expect_fail(&b, "t.hair", "default thickness -1 is not a positive number");
    make_cyhair(&b, 0x0a);
    float two = 2;
    memcpy(b.d + 128 + 12 * 9, &two, 4);
    expect_fail(&b, "t.hair", "point 0: transparency 2 is not in [0, 1]");
    b.n = 0;
    expect_fail(&b, "t.hair", "empty file");
}

/* TressFX 3: S strands x V vertices, positions right after the header (+ optional arrays). */
static void make_tfx3(buf *b, uint32_t S, uint32_t V, int with_thickness) {
    b->n = 0;
    put_f32(b, 3.0f);
    put_u32(b, S);
    put_u32(b, V);
    put_u32(b, 0);
    put_u32(b, 1); /* bothEndsImmovable */
    put_zeros(b, 124);
    put_u32(b, 296);                                   /* verticesOffset */
    put_u32(b, with_thickness ? 296 + 12 * S * V : 0); /* perStrandThicknessOffset */
    put_zeros(b, 4 * 4 + 128);
    for (uint32_t i = 0; i < S * V; i++)
        for (int c = 0; c < 3; c++)
            put_f32(b, coord(i, c));
    if (with_thickness)
        for (uint32_t s = 0; s < S; s++)
            put_f32(b, 0.5f + (float)s);
}

/* TressFX 4: positions (x,y,z,w) at 160, strand UVs after them. */
static void make_tfx4(buf *b, uint32_t S, uint32_t V, int with_color) {
    b->n = 0;
    put_f32(b, 4.0f);
    put_u32(b, S);
    put_u32(b, V);
    put_u32(b, 160);
    put_u32(b, 160 + 16 * S * V); /* strand UVs */
    put_u32(b, 0);
    put_u32(b, 0);
    put_u32(b, with_color ? 160 + 16 * S * V + 8 * S : 0);
    put_zeros(b, 128);
    for (uint32_t i = 0; i < S * V; i++) {
        for (int c = 0; c < 3; c++)
            put_f32(b, coord(i, c));
        put_f32(b, i % V ? 1.0f : 0.0f);
    }
    for (uint32_t s = 0; s < S; s++)
        put_f32(b, 0.1f * (float)s), put_f32(b, 0.2f);
    if (with_color)
        for (uint32_t i = 0; i < S * V; i++)
            put_f32(b, 0.3f), put_f32(b, 0.4f), put_f32(b, 0.5f), put_f32(b, 1.0f);
}

TEST(hair_tfx3_and_tfx4_synthetic) {
    buf b;
    sl_hair h;
    sl_err e;
    make_tfx3(&b, 5, 4, 0);
    CHECK(b.n == 296 + 12 * 20);
    CHECK_MSG(load(&b, "a.tfx", &h, &e) == 0, "%s", e.msg);
    CHECK(strcmp(h.format, "TressFX 3 .tfx") == 0);
    CHECK(h.num_strands == 5 && h.num_points == 20 && h.strand_first[5] == 20);
    for (uint32_t i = 0; i < 20; i++)
        for (int c = 0; c < 3; c++)
            CHECK(h.pos[3 * i + c] == coord(i, c));
    CHECK(h.radius == NULL && h.radius_source == SL_RADIUS_ESTIMATED && h.default_radius > 0);
    sl_hair_free(&h);

    make_tfx3(&b, 2, 8, 1); /* per-strand thickness coefficients scale the estimated radius */
    CHECK_MSG(load(&b, "b.tfx", &h, &e) == 0, "%s", e.msg);
    CHECK(h.radius != NULL);
    for (uint32_t i = 0; h.radius && i < 16; i++)
        CHECK(h.radius[i] == (0.5f + (float)(i / 8)) * h.default_radius);
    sl_hair_free(&h);

    make_tfx4(&b, 3, 4, 1);
    CHECK_MSG(load(&b, "c.tfx", &h, &e) == 0, "%s", e.msg);
    CHECK(strcmp(h.format, "TressFX 4 .tfx") == 0);
    CHECK(h.num_strands == 3 && h.num_points == 12);
    for (uint32_t i = 0; i < 12; i++)
        for (int c = 0; c < 3; c++)
            CHECK(h.pos[3 * i + c] == coord(i, c)); /* w skipped */
    CHECK(h.color != NULL && h.color[0] == 0.3f && h.color[35] == 0.5f);
    sl_hair_free(&h);

    /* No extension: recognised by the version float. */
    make_tfx4(&b, 3, 4, 0);
    CHECK_MSG(load(&b, "noext", &h, &e) == 0, "%s", e.msg);
    sl_hair_free(&h);
}

TEST(hair_tfx_bad_inputs) {
    buf b;
    make_tfx3(&b, 5, 4, 0);
    size_t full = b.n;
    b.n = 200;
    expect_fail(&b, "t.tfx", "truncated header (200 bytes, a TressFX 3 header has 296)");
    b.n = full - 12;
    expect_fail(&b, "t.tfx",
                "truncated: vertex positions for 5 strands x 4 vertices end at byte 536");
    b.n = full + 8;
    expect_fail(&b, "t.tfx", "8 trailing bytes");
    b.n = full;
    set_u32(&b, 4, 0x7fffffffu); /* absurd strand count */
    expect_fail(&b, "t.tfx",
                "truncated: the header declares 2147483647 strands x 4 vertices, "
                "more than the 536-byte file can hold");
    set_u32(&b, 4, 30); /* 30 x 4 points: fewer than the bytes, more than the file holds */
    expect_fail(&b, "t.tfx",
                "truncated: vertex positions for 30 strands x 4 vertices end at byte "
                "1736, the file has 536 bytes");
    make_tfx3(&b, 5, 4, 0);
    set_u32(&b, 8, 1);
    expect_fail(&b, "t.tfx", "1 vertices per strand, need at least 2");
    make_tfx3(&b, 5, 4, 0);
    set_u32(&b, 4, 0);
    expect_fail(&b, "t.tfx", "no strands");
    make_tfx3(&b, 5, 4, 0);
    set_u32(&b, 144, 100);
    expect_fail(&b, "t.tfx", "vertex positions offset 100 lies inside the 296-byte header");
    make_tfx3(&b, 5, 4, 0);
    set_u32(&b, 144, 0);
    expect_fail(&b, "t.tfx", "no vertex positions");
    make_tfx3(&b, 5, 4, 0);
    float v = 7.0f;
    memcpy(b.d, &v, 4);
    expect_fail(&b, "t.tfx", "not a TressFX file (version float 7 at offset 0");
    make_tfx3(&b, 5, 4, 0);
    float nan = NAN;
    memcpy(b.d + 296 + 12 * 6, &nan, 4); /* strand 1 point 2 x */
    expect_fail(&b, "t.tfx", "strand 1 point 2: coordinate x is not finite");
    make_tfx4(&b, 3, 4, 0);
    set_u32(&b, 4, 0x40000000u); /* S = V = 2^30: 16 S V wraps to 0 in 64 bits */
    set_u32(&b, 8, 0x40000000u);
    expect_fail(&b, "t.tfx", "truncated: the header declares 1073741824 strands x 1073741824");
    set_u32(&b, 16, 0); /* no strand UVs and just the header: every array check would pass */
    b.n = 160;
    expect_fail(&b, "t.tfx", "truncated: the header declares 1073741824 strands x 1073741824");
    make_tfx4(&b, 3, 4, 0);
    b.n = 150;
    expect_fail(&b, "t.tfx", "truncated header (150 bytes, a TressFX 4 header has 160)");
    make_tfx4(&b, 3, 4, 0);
    b.n -= 4;
    expect_fail(&b, "t.tfx", "truncated: strand UVs for 3 strands x 4 vertices");
    make_tfx4(&b, 3, 4, 0);
    for (int k = 1; k < 4; k++)
        memcpy(b.d + 160 + 16 * (4 + k), b.d + 160 + 16 * 4, 12);
    expect_fail(&b, "t.tfx", "strand 1 has zero length (all 4 points coincide)");
    memcpy(b.d, "abcd", 4);
    expect_fail(&b, "t.bin", "unknown hair format");
}

/* USC .data: records of (i32 n, f32[n][3]). */
static void make_usc(buf *b, int S, const int *np) {
    b->n = 0;
    put_u32(b, (uint32_t)S);
    uint32_t i = 0;
    for (int s = 0; s < S; s++) {
        put_u32(b, (uint32_t)np[s]);
        for (int k = 0; k < np[s]; k++, i++)
            for (int c = 0; c < 3; c++)
                put_f32(b, coord(i, c));
    }
}

TEST(hair_usc_synthetic_and_bad) {
    buf b;
    sl_hair h;
    sl_err e;
    const int np[4] = {3, 1, 5, 2};
    make_usc(&b, 4, np);
    CHECK_MSG(load(&b, "u.data", &h, &e) == 0, "%s", e.msg);
    CHECK(strcmp(h.format, "USC-HairSalon .data") == 0);
    /* the single-point strand is dropped (as Digital Salon's reader) and counted */
    CHECK(h.num_strands == 3 && h.num_points == 10 && h.dropped_strands == 1);
    CHECK(h.strand_first[1] == 3 && h.strand_first[2] == 8 && h.strand_first[3] == 10);
    CHECK(h.pos[3 * 3] == coord(4, 0)); /* strand 2's first point is file point 4 */
    CHECK(h.pos[3 * 9 + 2] == coord(10, 2));
    sl_hair_free(&h);

    size_t full = b.n;
    b.n = full - 1;
    expect_fail(&b, "u.data", "truncated: strand 3 declares 2 points");
    b.n = full + 2;
    expect_fail(&b, "u.data", "2 trailing bytes");
    b.n = 2;
    expect_fail(&b, "u.data", "truncated: 2 bytes");
    b.n = full;
    set_u32(&b, 0, 0x7fffffff); /* absurd strand count: walks out of data, no allocation */
    expect_fail(&b, "u.data", "truncated: the file declares 2147483647 strands but ends after 4");
    set_u32(&b, 0, 0);
    expect_fail(&b, "u.data", "strand count 0 (must be positive)");
    set_u32(&b, 0, 0xffffffffu);
    expect_fail(&b, "u.data", "strand count -1");
    set_u32(&b, 0, 4);
    set_u32(&b, 4, 0x40000000u); /* absurd point count */
    expect_fail(&b, "u.data", "truncated: strand 0 declares 1073741824 points");
    set_u32(&b, 4, 0);
    expect_fail(&b, "u.data", "strand 0: point count 0");
    const int ones[2] = {1, 1};
    make_usc(&b, 2, ones);
    expect_fail(&b, "u.data", "no strand has at least 2 points");
}

TEST(hair_helpers_bounds_up_axis_append) {
    buf b;
    sl_hair h, g;
    sl_err e;
    make_cyhair(&b, 0x1f);
    CHECK(load(&b, "t.hair", &h, &e) == 0);
    float lo[3], hi[3];
    sl_hair_bounds(&h, lo, hi);
    for (int c = 0; c < 3; c++) { /* independent min/max over the generating function */
        float l = coord(0, c), u = coord(0, c);
        for (uint32_t i = 1; i < 9; i++)
            l = fminf(l, coord(i, c)), u = fmaxf(u, coord(i, c));
        CHECK(lo[c] == l && hi[c] == u);
    }
    sl_hair_z_up_to_y_up(&h); /* a point on +Z goes to +Y; +Y goes to -Z */
    for (uint32_t i = 0; i < 9; i++) {
        CHECK(h.pos[3 * i] == coord(i, 0));
        CHECK(h.pos[3 * i + 1] == coord(i, 2));
        CHECK(h.pos[3 * i + 2] == -coord(i, 1));
    }
    make_usc(&b, 1, (const int[]){4});
    CHECK(load(&b, "u.data", &g, &e) == 0);
    CHECK(sl_hair_append(&h, &g, &e) == 0);
    CHECK(h.num_strands == 4 && h.num_points == 13 && h.strand_first[4] == 13);
    CHECK(h.strand_first[3] == 9 && h.pos[3 * 9] == coord(0, 0));
    /* g had no per-point arrays: its points take its defaults */
    CHECK(h.radius[9] == g.default_radius && h.transparency[12] == 0 && h.color[3 * 12] == 1);
    CHECK(sl_hair_validate(&h, "x", &e) == 0);
    sl_hair_free(&h);
    sl_hair_free(&g);
    sl_hair_free(&g); /* free is idempotent after the first (zeroes the struct) */
}

TEST(hair_tangent_degenerate_segments) {
    /* One strand: a segment along +X, then one of length 0 (coincident points inside a strand
     * that is not all coincident), then one 1e-8 long at coordinate 1 (below 4 float ulps =
     * 4.8e-7 there: its direction is rounding noise), then one along +Z. */
    sl_hair h;
    memset(&h, 0, sizeof h);
    sl_hair_alloc(&h, 1, 5);
    const float p[15] = {0, 0, 0, 1, 0, 0, 1, 0, 0, 1, 1e-8f, 0, 1, 0, 2};
    memcpy(h.pos, p, sizeof p);
    h.strand_first[1] = 5;
    float t[3];
    sl_hair_tangent(&h, 0, 0, t);
    CHECK(t[0] == 1 && t[1] == 0 && t[2] == 0);
    sl_hair_tangent(&h, 0, 1, t); /* zero length: nearest usable is seg 0 (towards the root) */
    CHECK(t[0] == 1 && t[1] == 0 && t[2] == 0);
    sl_hair_tangent(&h, 0, 2, t); /* seg 1 and 3 are at distance 1; seg 1 is unusable -> seg 3 */
    CHECK(t[0] == 0 && fabsf(t[1]) < 1e-8f && t[2] == 1);
    CHECK(!sl_hair_segment_usable(&h, 0, 1) && !sl_hair_segment_usable(&h, 0, 2));
    CHECK(sl_hair_segment_usable(&h, 0, 0) && sl_hair_segment_usable(&h, 0, 3));
    sl_hair_point_tangent(&h, 0, 4, t); /* the tip: its one segment */
    CHECK(t[2] == 1);
    sl_hair_point_tangent(&h, 0, 0, t);
    CHECK(t[0] == 1);
    /* A strand whose every segment is unusable falls back to +Y. */
    const float q[15] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
    memcpy(h.pos, q, sizeof q);
    sl_hair_tangent(&h, 0, 2, t);
    CHECK(t[0] == 0 && t[1] == 1 && t[2] == 0);
    sl_hair_point_tangent(&h, 0, 2, t);
    CHECK(t[0] == 0 && t[1] == 1 && t[2] == 0);
    sl_hair_free(&h);
}
