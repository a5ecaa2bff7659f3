/* test_shade_points.c: the refined vertex rate (sl_shade_points_refine, sl_shade_entry): how many
 * parts each anchor pair is cut into, where the inner points lie, and the piecewise
 * interpolation a K-buffer entry reads back. */
#include "test.h"

#include "passes/shade/shade_points.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* One strand of 4 points along +x at x = 0, 1, 2, 3; a 3 x 1 K-buffer with one entry per pixel,
 * on segment px at t = 0.5. */
typedef struct refine_fx {
    sl_hair h;
    sl_kfrag kbuf[3];
    uint8_t kcount[3];
    sl_kbuf_view kb;
    sl_shade_map m;
    sl_shade_points p;
} refine_fx;

static void refine_fx_init(refine_fx *f) {
    memset(f, 0, sizeof *f);
    sl_hair_alloc(&f->h, 1, 4);
    f->h.default_radius = 0.05f;
    f->h.strand_first[1] = 4;
    for (int i = 0; i < 4; i++) {
        f->h.pos[3 * i] = (float)i;
        f->h.pos[3 * i + 1] = 0.0f;
        f->h.pos[3 * i + 2] = 0.0f;
    }
    for (int px = 0; px < 3; px++) {
        f->kbuf[px] = (sl_kfrag){1.0f, 1.0f, (uint32_t)px, 0.5f};
        f->kcount[px] = 1;
    }
    f->kb = (sl_kbuf_view){3, 1, 1, f->kbuf, f->kcount};
    f->m.strand_of = calloc(4, sizeof *f->m.strand_of);
    sl_shade_points_build(&f->h, &f->kb, 1, &f->m, &f->p);
}

static void refine_fx_free(refine_fx *f) {
    sl_shade_points_free(&f->p);
    sl_shade_map_free(&f->m);
    sl_hair_free(&f->h);
}

TEST(shade_refine_parts_points_and_interpolation) {
    refine_fx f;
    refine_fx_init(&f);
    CHECK(f.p.n == 4);
    /* T of 2 lobes (equal shares) at the 4 vertices, index j n + anchor:
     * vertex 0 (1, 1), 1 (0.1, 0.1), 2 (0.1, 0.1), 3 (0.1, 1) */
    const double share[2] = {0.5, 0.5};
    float T[8];
    const float t0[4] = {1, 0.1f, 0.1f, 0.1f}, t1[4] = {1, 0.1f, 0.1f, 1};
    for (int v = 0; v < 4; v++) {
        T[f.m.anchor[v]] = t0[v];
        T[4 + f.m.anchor[v]] = t1[v];
    }
    const size_t added = sl_shade_points_refine(&f.h, &f.kb, 1, &f.m, &f.p, T, 2, share, 3.0);
    /* pair 0-1: both lobes fall 10x: D = ln 10, parts ceil(ln 10 / ln 3) = 3 (2 inner points);
     * pair 1-2: D = 0, 1 part; pair 2-3: lobe 1 rises 10x, weights 0.5 x 0.1 and 0.5 x 1:
     * D = ln 10 / 1.1, parts ceil(1.905) = 2 (1 inner point) */
    CHECK(added == 3);
    CHECK(f.p.n == 7);
    CHECK(f.m.sub_m && f.m.sub_m[0] == 3 && f.m.sub_m[1] == 1 && f.m.sub_m[2] == 2);
    const double want_x[3] = {1.0 / 3, 2.0 / 3, 2.5};
    const uint32_t first[3] = {f.m.sub_first[0], f.m.sub_first[0] + 1, f.m.sub_first[2]};
    for (int q = 0; q < 3; q++) {
        const uint32_t i = first[q];
        CHECK(i >= 4 && i < 7);
        CHECK_MSG(fabs(f.p.pos[3 * i] - want_x[q]) < 1e-12 && f.p.pos[3 * i + 1] == 0,
                  "inner point %d at %g, want %g", q, f.p.pos[3 * i], want_x[q]);
        CHECK(f.p.tan[3 * i] == 1.0f && f.p.strand[i] == 0);
    }
    /* the shading read back: out[0] = x^2 at every shading point; an entry interpolates
     * linearly between the two points around it: x = 0.5 lies in [1/3, 2/3] (the chord there
     * gives 0.2778, the unrefined chord over [0, 1] 0.5), x = 1.5 in [1, 2] (2.5), x = 2.5 on
     * the inner point (6.25) */
    f.p.out = calloc(sl_shade_stride(&f.p) * f.p.n, sizeof *f.p.out);
    for (size_t i = 0; i < f.p.n; i++)
        f.p.out[sl_shade_stride(&f.p) * i] = (float)(f.p.pos[3 * i] * f.p.pos[3 * i]);
    const double want[3] = {(1.0 / 9 + 4.0 / 9) / 2, 2.5, 6.25};
    for (int px = 0; px < 3; px++) {
        float v[SL_SHADE_FLOATS];
        sl_shade_entry(&f.h, &f.kb, 1, &f.m, &f.p, (size_t)px, 0, v);
        CHECK_MSG(fabs(v[0] - want[px]) < 1e-5, "entry %d: %g, want %g", px, v[0], want[px]);
    }
    refine_fx_free(&f);
}

TEST(shade_refine_off_flat_and_dark_add_nothing) {
    refine_fx f;
    refine_fx_init(&f);
    const double share[1] = {1};
    float T[4] = {0.5f, 0.5f, 0.5f, 0.5f};
    /* flat T: nothing to cut, and the map keeps no refinement */
    CHECK(sl_shade_points_refine(&f.h, &f.kb, 1, &f.m, &f.p, T, 1, share, 1.5) == 0);
    CHECK(f.p.n == 4 && f.m.sub_m == NULL);
    /* a 1e4 drop: more parts than allowed are capped; ratio <= 1 (off) adds nothing */
    T[f.m.anchor[1]] = 1e-4f;
    CHECK(sl_shade_points_refine(&f.h, &f.kb, 1, &f.m, &f.p, T, 1, share, 0.0) == 0);
    CHECK(sl_shade_points_refine(&f.h, &f.kb, 1, &f.m, &f.p, T, 1, share, 1.05) ==
          2 * (SL_SHADE_REFINE_MAX - 1));
    CHECK(f.m.sub_m[0] == SL_SHADE_REFINE_MAX && f.m.sub_m[1] == SL_SHADE_REFINE_MAX &&
          f.m.sub_m[2] == 1);
    refine_fx_free(&f);
    /* deep shadow: a 10x drop whose larger end is under the gate is left alone, one just above
     * it is cut */
    refine_fx_init(&f);
    for (int v = 0; v < 4; v++)
        T[f.m.anchor[v]] = v == 1 ? 0.9f * SL_SHADE_REFINE_GATE : 0.09f * SL_SHADE_REFINE_GATE;
    CHECK(sl_shade_points_refine(&f.h, &f.kb, 1, &f.m, &f.p, T, 1, share, 3.0) == 0);
    for (int v = 0; v < 4; v++)
        T[f.m.anchor[v]] = v == 1 ? 1.1f * SL_SHADE_REFINE_GATE : 0.11f * SL_SHADE_REFINE_GATE;
    CHECK(sl_shade_points_refine(&f.h, &f.kb, 1, &f.m, &f.p, T, 1, share, 3.0) == 4);
    refine_fx_free(&f);
}

TEST(shade_points_bent_vertex_has_a_point_per_segment) {
    /* vertex 1 bends by 30 deg (more than SL_SHADE_SPLIT_DEG): each of its segments' ends is
     * shaded with that segment's tangent; vertex 2 bends by 2 deg: one point, the mean tangent */
    refine_fx f;
    refine_fx_init(&f);
    sl_shade_points_free(&f.p);
    sl_shade_map_free(&f.m);
    const double a1 = 30 * 3.14159265358979 / 180, a2 = 32 * 3.14159265358979 / 180;
    f.h.pos[3 * 2] = (float)(1 + cos(a1)), f.h.pos[3 * 2 + 1] = (float)sin(a1);
    f.h.pos[3 * 3] = (float)(f.h.pos[3 * 2] + cos(a2));
    f.h.pos[3 * 3 + 1] = (float)(f.h.pos[3 * 2 + 1] + sin(a2));
    f.m.strand_of = calloc(4, sizeof *f.m.strand_of);
    sl_shade_points_build(&f.h, &f.kb, 1, &f.m, &f.p);
    CHECK(f.p.n == 5);
    CHECK(f.m.anchor_end != NULL);
    CHECK(f.m.anchor_end[0] == f.m.anchor[0] && f.m.anchor[3] == f.m.anchor_end[3]);
    CHECK(f.m.anchor_end[1] != f.m.anchor[1] && f.m.anchor_end[2] == f.m.anchor[2]);
    const float *tin = f.p.tan + 3 * f.m.anchor_end[1], *tout = f.p.tan + 3 * f.m.anchor[1];
    CHECK_MSG(fabsf(tin[0] - 1) < 1e-6f && fabsf(tin[1]) < 1e-6f, "in %g %g", tin[0], tin[1]);
    CHECK_MSG(fabsf(tout[0] - (float)cos(a1)) < 1e-6f && fabsf(tout[1] - (float)sin(a1)) < 1e-6f,
              "out %g %g", tout[0], tout[1]);
    const float *tm = f.p.tan + 3 * f.m.anchor[2];
    CHECK(fabsf(tm[0] - (float)cos(0.5 * (a1 + a2))) < 1e-5f);
    /* an entry at the end of segment 0 reads the segment-0 point of vertex 1, one at the start
     * of segment 1 the segment-1 point: out[0] = the point's tangent x */
    f.p.out = calloc(sl_shade_stride(&f.p) * f.p.n, sizeof *f.p.out);
    for (size_t i = 0; i < f.p.n; i++)
        f.p.out[sl_shade_stride(&f.p) * i] = f.p.tan[3 * i];
    float v[SL_SHADE_FLOATS];
    f.kbuf[0].t = 1.0f;
    f.kbuf[1].t = 0.0f;
    sl_shade_entry(&f.h, &f.kb, 1, &f.m, &f.p, 0, 0, v);
    CHECK(fabsf(v[0] - 1) < 1e-6f);
    sl_shade_entry(&f.h, &f.kb, 1, &f.m, &f.p, 1, 0, v);
    CHECK(fabsf(v[0] - (float)cos(a1)) < 1e-6f);
    refine_fx_free(&f);
}
