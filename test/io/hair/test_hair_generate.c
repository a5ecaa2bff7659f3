/* test_hair_generate.c: the procedural generator (determinism, counts, a head-of-hair shape,
 * styles that differ as named) and TressFX follow strands (offsets in the root's normal plane
 * within root_radius, growing to 1 + tip_spread at the tip, copies of per-point arrays). */
#include "io/hair/hair.h"
#include "test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double dist3(const float *a, const float *b) {
    double d2 = 0;
    for (int c = 0; c < 3; c++)
        d2 += ((double)a[c] - b[c]) * ((double)a[c] - b[c]);
    return sqrt(d2);
}
static double norm3(const float *a) {
    const float z[3] = {0, 0, 0};
    return dist3(a, z);
}

/* Mean over strands of (root-to-tip distance / arc length): 1 for a straight line. */
static double straightness(const sl_hair *h) {
    double sum = 0;
    for (uint32_t s = 0; s < h->num_strands; s++) {
        uint32_t a = h->strand_first[s], b = h->strand_first[s + 1];
        double arc = 0;
        for (uint32_t i = a; i + 1 < b; i++)
            arc += dist3(h->pos + 3 * i, h->pos + 3 * (i + 1));
        sum += dist3(h->pos + 3 * a, h->pos + 3 * (b - 1)) / arc;
    }
    return sum / h->num_strands;
}

TEST(hair_procedural_deterministic_and_counted) {
    sl_hair_procedural p = {SL_PROC_WAVY, 500, 16, 7};
    sl_hair a, b, c;
    sl_err e;
    CHECK_MSG(sl_hair_generate(&p, &a, &e) == 0, "%s", e.msg);
    CHECK_MSG(sl_hair_generate(&p, &b, &e) == 0, "%s", e.msg);
    p.seed = 8;
    CHECK_MSG(sl_hair_generate(&p, &c, &e) == 0, "%s", e.msg);
    if (!a.pos || !b.pos || !c.pos) return;
    CHECK(a.num_strands == 500 && a.num_points == 500 * 16);
    for (uint32_t s = 0; s <= 500; s++)
        CHECK(a.strand_first[s] == 16 * s);
    CHECK(memcmp(a.pos, b.pos, sizeof(float) * 3 * a.num_points) == 0); /* same seed: bit equal */
    CHECK(memcmp(a.pos, c.pos, sizeof(float) * 3 * a.num_points) != 0); /* another seed differs */
    CHECK(strcmp(a.format, "procedural (wavy)") == 0);
    CHECK(a.radius == NULL && a.default_radius == 0.04f);
    CHECK(sl_hair_validate(&a, "p", &e) == 0);
    sl_hair_free(&a), sl_hair_free(&b), sl_hair_free(&c);
}

TEST(hair_procedural_looks_like_a_head_of_hair) {
    const float R = 10; /* the brief: scalp sphere of radius ~10 at the origin, length ~25 */
    for (int style = 0; style < 3; style++) {
        sl_hair_procedural p = {style, 2000, 32, 1};
        sl_hair h;
        sl_err e;
        CHECK_MSG(sl_hair_generate(&p, &h, &e) == 0, "%s", e.msg);
        if (!h.pos) continue;
        int on_scalp = 1, outside = 1, on_face = 0;
        double root_y = 0, tip_y = 0, arc_sum = 0, arc_min = 1e9, arc_max = 0;
        for (uint32_t s = 0; s < h.num_strands; s++) {
            uint32_t a = h.strand_first[s], b = h.strand_first[s + 1];
            const float *r = h.pos + 3 * a;
            /* roots on the sphere (float rounding of R * unit vector: 1e-4) */
            if (fabs(norm3(r) - R) > 1e-4) on_scalp = 0;
            if (r[2] > 0.4f * R && r[1] < 0.5f * R) on_face = 1; /* forehead/face stays bare */
            for (uint32_t i = a; i < b; i++)
                if (norm3(h.pos + 3 * i) < R - 1e-3) outside = 0; /* never inside the head */
            double arc = 0;
            for (uint32_t i = a; i + 1 < b; i++)
                arc += dist3(h.pos + 3 * i, h.pos + 3 * (i + 1));
            arc_sum += arc, arc_min = fmin(arc_min, arc), arc_max = fmax(arc_max, arc);
            root_y += r[1], tip_y += h.pos[3 * (b - 1) + 1];
        }
        double n = h.num_strands;
        CHECK(on_scalp);
        CHECK(outside);
        CHECK(!on_face);
        /* gravity: tips hang well below the roots */
        CHECK_MSG(tip_y / n < root_y / n - 10, "style %d: root y %g tip y %g", style, root_y / n,
                  tip_y / n);
        /* fiber lengths ~25 (+-15 % by design); sampling a wave with 31 chords loses a little */
        CHECK_MSG(arc_sum / n > 22 && arc_sum / n < 28, "style %d: mean length %g", style,
                  arc_sum / n);
        CHECK_MSG(arc_min > 25 * 0.75 && arc_max < 25 * 1.25, "style %d: lengths %g..%g", style,
                  arc_min, arc_max);
        sl_hair_free(&h);
    }
}

TEST(hair_procedural_styles_differ) {
    double st[3];
    for (int style = 0; style < 3; style++) {
        sl_hair_procedural p = {style, 300, 64, 3};
        sl_hair h;
        sl_err e;
        CHECK_MSG(sl_hair_generate(&p, &h, &e) == 0, "%s", e.msg);
        st[style] = h.pos ? straightness(&h) : 0;
        sl_hair_free(&h);
    }
    /* straight > wavy > curly, each by a visible margin */
    CHECK_MSG(st[1] < st[0] - 0.01 && st[2] < st[1] - 0.05, "straightness %g %g %g", st[0], st[1],
              st[2]);
}

TEST(hair_procedural_rejects_bad_parameters) {
    sl_hair h;
    sl_err e;
    sl_hair_procedural p = {3, 10, 10, 1};
    CHECK(sl_hair_generate(&p, &h, &e) == -1 && strstr(e.msg, "procedural: style 3"));
    p = (sl_hair_procedural){0, 0, 10, 1};
    CHECK(sl_hair_generate(&p, &h, &e) == -1 && strstr(e.msg, "procedural: strands 0 is not in"));
    p = (sl_hair_procedural){0, 10, 1, 1};
    CHECK(sl_hair_generate(&p, &h, &e) == -1 && strstr(e.msg, "procedural: points 1 is not in"));
    p = (sl_hair_procedural){0, 10, 100000, 1};
    CHECK(sl_hair_generate(&p, &h, &e) == -1 && strstr(e.msg, "procedural: points 100000"));
    CHECK(sl_hair_style_from_name("curly") == SL_PROC_CURLY && sl_hair_style_from_name("x") == -1);
    p = (sl_hair_procedural){2, 1, 2, 0}; /* the smallest hair */
    CHECK(sl_hair_generate(&p, &h, &e) == 0 && h.num_points == 2);
    sl_hair_free(&h);
}

/* Two guides of 5 points, with per-point radius/transparency/color; coordinates are small
 * integers and halves so that follow offsets can be checked to float rounding. */
static void make_guides(sl_hair *h) {
    memset(h, 0, sizeof *h);
    sl_hair_alloc(h, 2, 10);
    for (uint32_t i = 0; i < 5; i++) {
        float g0[3] = {0, -(float)i, 0}, g1[3] = {5 + 0.5f * (float)i, 2 - (float)i, 1};
        memcpy(h->pos + 3 * i, g0, sizeof g0);
        memcpy(h->pos + 3 * (5 + i), g1, sizeof g1);
    }
    h->strand_first[1] = 5, h->strand_first[2] = 10;
    h->radius = malloc(10 * sizeof(float));
    h->transparency = malloc(10 * sizeof(float));
    h->color = malloc(30 * sizeof(float));
    for (int i = 0; i < 10; i++) {
        h->radius[i] = 0.01f * (float)(i + 1);
        h->transparency[i] = 0.05f * (float)i;
        for (int c = 0; c < 3; c++)
            h->color[3 * i + c] = 0.1f * (float)c;
    }
}

TEST(hair_follow_offsets_as_tressfx) {
    sl_hair h, ref;
    sl_err e;
    make_guides(&h);
    make_guides(&ref);
    sl_hair_follow f = {3, 0.5f, 2.0f, 42};
    CHECK_MSG(sl_hair_add_follow(&h, &f, &e) == 0, "%s", e.msg);
    CHECK(h.num_strands == 8 && h.num_points == 40 && h.guide_strands == 2 && h.follow_added);
    for (int g = 0; g < 2; g++) {
        const float *gp = ref.pos + 15 * g;
        /* root segment direction of the guide, in double */
        double t[3], tl = 0;
        for (int c = 0; c < 3; c++)
            t[c] = (double)gp[3 + c] - gp[c], tl += t[c] * t[c];
        for (int c = 0; c < 3; c++)
            t[c] /= sqrt(tl);
        for (int j = 0; j < 4; j++) {
            uint32_t s = 4 * g + j;
            CHECK(h.strand_first[s] == 5 * s);
            const float *fp = h.pos + 3 * h.strand_first[s];
            double off[3], dot = 0, r = 0;
            for (int c = 0; c < 3; c++)
                off[c] = (double)fp[c] - gp[c];
            for (int c = 0; c < 3; c++)
                dot += off[c] * t[c], r += off[c] * off[c];
            r = sqrt(r);
            if (j == 0) {
                CHECK(r == 0); /* the guide itself comes first, unchanged */
            } else {
                CHECK(r > 0 && r <= 0.5 + 1e-6); /* inside the root disc (float rounding) */
                CHECK_NEAR(dot, 0, 1e-6);        /* in the normal plane of the root segment */
            }
            for (int k = 0; k < 5; k++) {
                double scale = 1.0 + 2.0 * k / 4.0; /* 1 at the root, 1 + tip_spread at the tip */
                for (int c = 0; c < 3; c++)
                    /* float positions of magnitude <= 8 and offsets <= 1.5: a few ulps */
                    CHECK_NEAR(fp[3 * k + c], gp[3 * k + c] + off[c] * scale, 4e-6);
                uint32_t i = 5 * s + k;
                CHECK(h.radius[i] == ref.radius[5 * g + k]);
                CHECK(h.transparency[i] == ref.transparency[5 * g + k]);
                CHECK(h.color[3 * i + 2] == ref.color[3 * (5 * g + k) + 2]);
            }
        }
    }
    CHECK(sl_hair_validate(&h, "follow", &e) == 0);
    /* The same seed gives the same strands; another seed other offsets. */
    sl_hair h2, h3;
    make_guides(&h2), make_guides(&h3);
    sl_hair_add_follow(&h2, &f, &e);
    f.seed = 43;
    sl_hair_add_follow(&h3, &f, &e);
    CHECK(memcmp(h.pos, h2.pos, 120 * sizeof(float)) == 0);
    CHECK(memcmp(h.pos, h3.pos, 120 * sizeof(float)) != 0);
    sl_hair_free(&h), sl_hair_free(&h2), sl_hair_free(&h3), sl_hair_free(&ref);
}

TEST(hair_follow_parameters) {
    sl_hair h;
    sl_err e;
    make_guides(&h);
    sl_hair_follow f = {0, 0.5f, 2.0f, 1};
    CHECK(sl_hair_add_follow(&h, &f, &e) == 0 && h.num_strands == 2 && !h.follow_added);
    f.per_guide = 65;
    CHECK(sl_hair_add_follow(&h, &f, &e) == -1 && strstr(e.msg, "per_guide 65 is not in [0, 64]"));
    f.per_guide = 2, f.root_radius = -1;
    CHECK(sl_hair_add_follow(&h, &f, &e) == -1 && strstr(e.msg, "root_radius -1"));
    f.root_radius = 1, f.tip_spread = NAN;
    CHECK(sl_hair_add_follow(&h, &f, &e) == -1 && strstr(e.msg, "tip_spread nan"));
    f.tip_spread = 3e38f, f.root_radius = 3e38f;
    CHECK(sl_hair_add_follow(&h, &f, &e) == -1 && strstr(e.msg, "overflows"));
    uint32_t real = h.num_points;
    h.num_points = 10000000; /* the size check comes before any access */
    f = (sl_hair_follow){64, 1, 1, 1};
    CHECK(sl_hair_add_follow(&h, &f, &e) == -1 && strstr(e.msg, "would make 650000000 points"));
    h.num_points = real;
    CHECK(h.num_strands == 2 && sl_hair_validate(&h, "x", &e) == 0); /* untouched by failures */
    sl_hair_free(&h);
}

TEST(hair_follow_on_real_guides) {
    const char *dir = sl_test_shared_data();
    if (!dir) SKIP("../shared/data not present");
    char path[4096];
    snprintf(path, sizeof path, "%s/hair/tressfx3/ponytail/front_top.tfx", dir);
    sl_hair h, g;
    sl_err e;
    if (sl_hair_load(path, &h, &e) || sl_hair_load(path, &g, &e)) {
        CHECK_MSG(0, "%s", e.msg);
        return;
    }
    sl_hair_follow f = {4, 0.4f, 5.0f, 1}; /* ponytail.tfxproj's settings */
    CHECK(sl_hair_add_follow(&h, &f, &e) == 0);
    int bad = 0;
    for (uint32_t s = 0; s < h.num_strands; s++) {
        uint32_t gs = s / 5, n = 16;
        const float *fp = h.pos + 3 * h.strand_first[s], *gp = g.pos + 3 * g.strand_first[gs];
        double off[3], r = 0;
        for (int c = 0; c < 3; c++)
            off[c] = (double)fp[c] - gp[c], r += off[c] * off[c];
        /* coordinates up to ~124: float spacing 7.6e-6, so 1e-4 covers the rounding */
        if (sqrt(r) > 0.4 + 1e-4) bad++;
        for (uint32_t k = 0; k < n; k++)
            for (int c = 0; c < 3; c++)
                if (fabs(fp[3 * k + c] - (gp[3 * k + c] + off[c] * (1 + 5.0 * k / (n - 1)))) > 1e-3)
                    bad++;
    }
    CHECK_MSG(bad == 0, "%d bad follow points", bad);
    sl_hair_free(&h), sl_hair_free(&g);
}
