/* test_frame.c: the frame (host/plan/frame.h): K-buffer merge (kernels/kbuffer.h), view-pass
 * coverage (cpu/view.c), the planner's reuse and skipping, AOV consistency, determinism, and the C
 * path against OpenCL on a tiny scene. Expected values come from independent double computations
 * (alpha products, ribbon areas) or from invariants (a camera move must not re-run a light pass;
 * modes sum to the beauty), never from the code under test. */
#include "test.h"

#include "cl_fixture.h"

#include "frame_fixture.h"
#include "lighting/lobe_subdivide.h"
#include "kbuffer.h"
#include "view.h"
#include "passes/view/view_cl.h"
#include "plan/renderer.h" /* white box: the buffers the estimate counts */

#include <math.h>
#include <stdlib.h>
#include <string.h>

static uint32_t lcg(uint32_t *s) {
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

static double frame_alpha(const sl_kfrag *b, int n) {
    double t = 1;
    for (int i = 0; i < n; i++)
        t *= 1 - b[i].a;
    return 1 - t;
}

TEST(frame_kbuffer_merge_conserves_alpha) {
    /* 12 fragments into K = 3: the pixel's alpha must equal 1 - prod(1 - a_i) over ALL of
     * them (merged, not dropped), and the 2 nearest must be kept exactly. Tolerance 1e-6:
     * float rounding of ~12 "over" operations on values <= 1. */
    uint32_t s = 7;
    sl_kfrag all[12], buf[3];
    int n = 0;
    double prod = 1;
    for (int i = 0; i < 12; i++) {
        all[i] = (sl_kfrag){(float)(lcg(&s) % 1000) / 10.0f + 1.0f,
                            0.05f + (float)(lcg(&s) % 900) / 1000.0f, (uint32_t)i, 0.5f};
        prod *= 1 - all[i].a;
        n = sl_kbuffer_insert(buf, n, 3, all[i]);
    }
    CHECK(n == 3);
    CHECK_NEAR(frame_alpha(buf, n), 1 - prod, 1e-6);
    /* the two nearest, found independently */
    int i0 = 0, i1 = -1;
    for (int i = 1; i < 12; i++)
        if (all[i].z < all[i0].z) i0 = i;
    for (int i = 0; i < 12; i++)
        if (i != i0 && (i1 < 0 || all[i].z < all[i1].z)) i1 = i;
    CHECK(buf[0].seg == (uint32_t)i0 && buf[0].a == all[i0].a);
    CHECK(buf[1].seg == (uint32_t)i1 && buf[1].a == all[i1].a);
    CHECK(buf[0].z <= buf[1].z && buf[1].z <= buf[2].z);
    /* weights sum to the alpha */
    float w[3];
    float a = sl_kbuffer_weights(buf, n, w);
    CHECK_NEAR(a, w[0] + w[1] + w[2], 1e-6);
}

TEST(frame_kbuffer_order_independent_alpha) {
    /* the same 20 fragments in two orders: same alpha (1e-6, float rounding) and same K-1
     * nearest entries */
    uint32_t s = 3;
    sl_kfrag f[20], b1[4], b2[4];
    for (int i = 0; i < 20; i++)
        f[i] = (sl_kfrag){(float)(lcg(&s) % 5000) / 100.0f, 0.3f, (uint32_t)i, 0.25f};
    int n1 = 0, n2 = 0;
    for (int i = 0; i < 20; i++)
        n1 = sl_kbuffer_insert(b1, n1, 4, f[i]);
    for (int i = 19; i >= 0; i--)
        n2 = sl_kbuffer_insert(b2, n2, 4, f[i]);
    CHECK_NEAR(frame_alpha(b1, n1), frame_alpha(b2, n2), 1e-6);
    CHECK_NEAR(frame_alpha(b1, n1), 1 - pow(0.7, 20), 1e-6);
    for (int i = 0; i < 3; i++)
        CHECK(b1[i].seg == b2[i].seg);
}

static double frags_sum(const slc_frag_list *l) {
    double s = 0;
    for (size_t i = 0; i < l->n; i++)
        s += l->f[i].a;
    return s;
}

TEST(frame_view_coverage_area) {
    /* A thin ribbon (0.3 px wide, ~30 px long) inside the image: the tent splat conserves area,
     * so the summed coverage equals 2 hw |p1 - p0| (double). 1e-3 relative: float rounding of
     * the per-sample shares (the 1e-4 drop threshold removes nothing here: every touched pixel
     * gets > 1e-3). A half-transparent ribbon gives half. */
    double p0[3] = {10.3, 20.5, 5.0}, p1[3] = {40.7, 22.1, 6.0}, hw = 0.15;
    double area = 2 * hw * hypot(p1[0] - p0[0], p1[1] - p0[1]);
    slc_frag_list l = {0};
    slc_view_segment(p0, p1, hw, 1.0f, 1.0f, 0, 64, 48, &l);
    CHECK_REL(frags_sum(&l), area, 1e-3);
    for (size_t i = 0; i < l.n; i++)
        CHECK(l.f[i].a <= 1.0f && l.f[i].t >= 0 && l.f[i].t <= 1);
    slc_frag_list_free(&l);
    slc_view_segment(p0, p1, hw, 0.5f, 0.5f, 0, 64, 48, &l);
    CHECK_REL(frags_sum(&l), 0.5 * area, 1e-3);
    slc_frag_list_free(&l);
    /* a wide ribbon saturates: coverage capped at 1 per pixel */
    slc_view_segment(p0, p1, 3.0, 1.0f, 1.0f, 0, 64, 48, &l);
    int full = 0;
    for (size_t i = 0; i < l.n; i++) {
        CHECK(l.f[i].a <= 1.0f);
        full += l.f[i].a == 1.0f;
    }
    CHECK(full > 30);
    slc_frag_list_free(&l);
}

/* ---- whole frames on a tiny scene ---- */

/* The shared tiny scene (frame_fixture.h) with a coloured absorption. */
static int tiny_setup(frame_tiny *t, int strands) {
    if (frame_tiny_setup(t, strands)) return -1;
    t->s.material.sigma_a[0] = 0.2, t->s.material.sigma_a[1] = 0.4, t->s.material.sigma_a[2] = 0.8;
    t->s.material.sigma_a_rgb = 1;
    return 0;
}

/* tiny_setup and the C device, checked. */
static void tiny_open(frame_tiny *t, int strands, sl_device *dev) {
    sl_err e;
    CHECK(tiny_setup(t, strands) == 0);
    CHECK(sl_device_open("c", dev, &e) == 0);
}

TEST(frame_planner_camera_move_reuses_light) {
    frame_tiny t;
    sl_device dev = {0};
    tiny_open(&t, 200, &dev);
    sl_renderer *r = NULL;
    sl_render_opts o;
    sl_render_opts_default(&o);
    o.quiet = 1;
    r = sl_renderer_create(&dev, &o);
    sl_fbuf a, b, c;
    t.s.multiple_scattering = SL_MS_ON;
    CHECK(frame_tiny_render(r, &t, &a) == 0);
    CHECK(frame_pass_state(r, "light") == SL_PASS_RUN);
    CHECK(frame_pass_state(r, "volume") == SL_PASS_RUN);
    CHECK(frame_pass_state(r, "ms table") == SL_PASS_RUN);
    CHECK(frame_pass_state(r, "view") == SL_PASS_RUN);
    /* camera move: no light pass, no volume pass, the view pass re-runs */
    t.cam.eye[0] += 3.0;
    CHECK(frame_tiny_render(r, &t, &b) == 0);
    CHECK(frame_pass_state(r, "light") == SL_PASS_CACHED);
    CHECK(frame_pass_state(r, "volume") == SL_PASS_CACHED);
    CHECK(frame_pass_state(r, "ms table") == SL_PASS_CACHED);
    CHECK(frame_pass_state(r, "view") == SL_PASS_RUN);
    /* material edit: neither light nor view re-runs, the image changes */
    t.s.material.sigma_a[0] = 2.0;
    CHECK(frame_tiny_render(r, &t, &c) == 0);
    CHECK(frame_pass_state(r, "light") == SL_PASS_CACHED);
    CHECK(frame_pass_state(r, "view") == SL_PASS_CACHED);
    double d = 0;
    for (int i = 0; i < 64 * 48 * 4; i++)
        d += fabs(c.rgba[i] - b.rgba[i]);
    CHECK(d > 0);
    sl_fbuf_free(&a);
    sl_fbuf_free(&b);
    sl_fbuf_free(&c);
    sl_renderer_free(r);
    frame_tiny_close(&t, &dev);
}

TEST(frame_planner_dark_hair_skips_ms) {
    /* docs/dual.md: black hair (sigma_a ~ 8) has an MS share ~0.004 < 0.02 -> skipped under
     * auto; white hair (sigma_a = 0) 0.65 -> run. */
    frame_tiny t;
    sl_device dev = {0};
    tiny_open(&t, 100, &dev);
    sl_renderer *r = sl_renderer_create(&dev, NULL);
    sl_fbuf a;
    t.s.multiple_scattering = SL_MS_AUTO;
    for (int c = 0; c < 3; c++)
        t.s.material.sigma_a[c] = 8.0;
    CHECK(frame_tiny_render(r, &t, &a) == 0);
    CHECK(frame_pass_state(r, "ms") == SL_PASS_SKIPPED);
    CHECK(frame_pass_state(r, "volume") == SL_PASS_SKIPPED);
    CHECK(frame_pass_state(r, "ms table") == SL_PASS_SKIPPED);
    double ms = 0;
    for (int i = 0; i < 64 * 48 * 3; i++)
        ms += a.mode[3][i];
    CHECK(ms == 0);
    sl_fbuf_free(&a);
    for (int c = 0; c < 3; c++)
        t.s.material.sigma_a[c] = 0.0;
    CHECK(frame_tiny_render(r, &t, &a) == 0);
    CHECK(frame_pass_state(r, "ms") == SL_PASS_RUN);
    CHECK(frame_pass_state(r, "volume") == SL_PASS_RUN);
    ms = 0;
    for (int i = 0; i < 64 * 48 * 3; i++)
        ms += a.mode[3][i];
    CHECK(ms > 0);
    sl_fbuf_free(&a);
    sl_renderer_free(r);
    frame_tiny_close(&t, &dev);
}

TEST(frame_negligible_lobe_skipped) {
    /* a fifth lobe with 1e-9 of the power is left out (planner "lobes" skipped) and the frame
     * matches the 4-lobe frame to 1e-6 relative (only the power normalisation differs by 1e-9) */
    frame_tiny t;
    sl_device dev = {0};
    tiny_open(&t, 100, &dev);
    sl_renderer *r = sl_renderer_create(&dev, NULL);
    sl_fbuf a, b;
    CHECK(frame_tiny_render(r, &t, &a) == 0);
    CHECK(frame_pass_state(r, "lobes") == SL_PASS_RUN);
    t.l.lobe = realloc(t.l.lobe, 5 * sizeof *t.l.lobe);
    t.l.lobe[4] = (sl_lobe){{1, 0, 0}, 0.5, {1e-9, 1e-9, 1e-9}};
    t.l.count = 5;
    CHECK(frame_tiny_render(r, &t, &b) == 0);
    CHECK(frame_pass_state(r, "lobes") == SL_PASS_SKIPPED);
    CHECK(sl_renderer_lobes_used(r) == 4);
    double mx, md = frame_max_diff(&a, &b, &mx);
    CHECK(md <= 1e-6 * mx);
    sl_fbuf_free(&a);
    sl_fbuf_free(&b);
    sl_renderer_free(r);
    frame_tiny_close(&t, &dev);
}

TEST(frame_aovs_consistent_and_deterministic) {
    /* modes R + TT + TRT + MS = beauty (each is the same front-to-back composite; 1e-5 relative
     * to the pixel for float rounding of 4 casts); 0 <= alpha, shadow <= 1; lobe count <= the
     * lobes the frame shades: 4, of which 3 broad, subdivided within 4 + SL_SUBDIV_SET_MAX
     * (host/lighting/lobe_subdivide.h; was 4 before broad lobes were subdivided, 12 before the
     * sub-lobes' count was set by their width);
     * one thread and two threads give bit-identical frames (fixed insertion order). */
    frame_tiny t;
    sl_device dev = {0};
    tiny_open(&t, 200, &dev);
    t.s.multiple_scattering = SL_MS_ON;
    sl_render_opts o;
    sl_render_opts_default(&o);
    o.threads = 1;
    sl_renderer *r1 = NULL, *r2 = NULL;
    r1 = sl_renderer_create(&dev, &o);
    o.threads = 2;
    r2 = sl_renderer_create(&dev, &o);
    sl_fbuf a, b;
    CHECK(frame_tiny_render(r1, &t, &a) == 0);
    CHECK(frame_tiny_render(r2, &t, &b) == 0);
    size_t n = 64 * 48;
    int covered = 0;
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 3; c++) {
            double s = 0;
            for (int m = 0; m < 4; m++)
                s += a.mode[m][3 * i + c];
            CHECK_NEAR(s, a.rgba[4 * i + c], 1e-5 * fabs(a.rgba[4 * i + c]) + 1e-7);
        }
        float al = a.rgba[4 * i + 3];
        CHECK(al >= 0 && al <= 1.0f + 1e-6f);
        CHECK(a.shadow[i] >= 0 && a.shadow[i] <= 1.0f + 1e-6f);
        CHECK(a.lobes[i] >= 0 && a.lobes[i] <= (float)(4 + SL_SUBDIV_SET_MAX) + 1e-5f);
        covered += al > 0.05f;
        CHECK((al > 0) == isfinite(a.depth[i]));
    }
    CHECK_MSG(covered > 100, "covered %d", covered);
    CHECK(memcmp(a.rgba, b.rgba, 4 * n * sizeof(float)) == 0);
    sl_fbuf_free(&a);
    sl_fbuf_free(&b);
    sl_renderer_free(r1);
    sl_renderer_free(r2);
    frame_tiny_close(&t, &dev);
}

/* Sum of the rgb of a 64 x 48 frame. */
static double frame_rgb_sum(const sl_fbuf *x) {
    double m = 0;
    for (int i = 0; i < x->width * x->height; i++)
        for (int c = 0; c < 3; c++)
            m += x->rgba[4 * i + c];
    return m;
}

/* Mean |x - ref| / mean ref over the rgb of two frames of one size. */
static double frame_rel_l1(const sl_fbuf *x, const sl_fbuf *ref) {
    double d = 0;
    for (int i = 0; i < x->width * x->height; i++)
        for (int c = 0; c < 3; c++)
            d += fabs(x->rgba[4 * i + c] - ref->rgba[4 * i + c]);
    const double m = frame_rgb_sum(ref);
    return m > 0 ? d / m : INFINITY;
}

TEST(frame_shading_rates_agree) {
    /* fragment vs vertex shading estimate the same radiance; with segments of a few pixels the
     * interpolation error is small. Measured mean |difference| / mean: 2-3 % while broad lobes'
     * maps were blurred over the whole map, 0.115-0.147 with the capped support and split broad
     * lobes (0.09 of it a mean bias: T looked up at the vertices only), 0.034 at the start of
     * session 16, 0.013 since bent vertices are shaded once per segment with its own tangent
     * (docs/frame.md, "Bent vertices"; the refinement of T does not act on this wavy hair).
     * Bound 0.025: the mean tangent at every vertex (0.034) or a missing mode (TT or TRT, each
     * > 20 % of this image) exceeds it. */
    frame_tiny t;
    sl_device dev = {0};
    tiny_open(&t, 200, &dev);
    sl_renderer *r = sl_renderer_create(&dev, NULL);
    sl_fbuf a, b;
    snprintf(t.s.shading_rate, sizeof t.s.shading_rate, "fragment");
    CHECK(frame_tiny_render(r, &t, &a) == 0);
    CHECK(sl_renderer_shading_rate(r) == 0);
    snprintf(t.s.shading_rate, sizeof t.s.shading_rate, "vertex");
    CHECK(frame_tiny_render(r, &t, &b) == 0);
    CHECK(sl_renderer_shading_rate(r) == 1);
    const double m = frame_rgb_sum(&a), d = frame_rel_l1(&b, &a);
    CHECK(m > 0);
    printf("frame_shading_rates: fragment %.5f vertex %.5f mean |diff| %.4f of the mean\n", m,
           frame_rgb_sum(&b), d);
    CHECK_MSG(d < 0.025, "mean rel diff %.4f", d);
    sl_fbuf_free(&a);
    sl_fbuf_free(&b);
    sl_renderer_free(r);
    frame_tiny_close(&t, &dev);
}

/* A block of n vertical straight fibers (y in [0, L], 4 points each) at random (x, z) in a
 * W x W square, radius r. */
static void vertical_block(sl_hair *h, int n, double L, double W, double r) {
    memset(h, 0, sizeof *h);
    sl_hair_alloc(h, (uint32_t)n, (uint32_t)(4 * n));
    h->default_radius = (float)r;
    uint32_t seed = 7;
    for (int f = 0; f < n; f++) {
        h->strand_first[f] = (uint32_t)(4 * f);
        const double x = (lcg(&seed) / 16777216.0 - 0.5) * W;
        const double z = (lcg(&seed) / 16777216.0 - 0.5) * W;
        for (int p = 0; p < 4; p++) {
            float *q = h->pos + 3 * (size_t)(4 * f + p);
            q[0] = (float)x, q[1] = (float)(L * p / 3), q[2] = (float)z;
        }
    }
    h->strand_first[n] = (uint32_t)(4 * n);
}

/* The tiny scene with its hair replaced by make_hair's and one lobe (dir, lambda), multiple
 * scattering off: the setting of the vertex-rate tests below. */
static int one_lobe_scene(frame_tiny *t, void (*make_hair)(sl_hair *), double dx, double dy,
                          double dz, double lambda) {
    if (frame_tiny_setup(t, 1)) return -1;
    sl_hair_free(&t->h);
    make_hair(&t->h);
    t->l.count = 1;
    t->l.lobe[0].dir[0] = dx, t->l.lobe[0].dir[1] = dy, t->l.lobe[0].dir[2] = dz;
    t->l.lobe[0].lambda = lambda;
    t->s.multiple_scattering = SL_MS_OFF;
    return 0;
}

/* The frame at fragment rate (f[0]), then at vertex rate with a feature off (f[1]) and on
 * (f[2]): set(&t->s, 0 or 1) switches it. Returns the number of frames rendered. */
static int three_rates(frame_tiny *t, void (*set)(sl_scene *, int), sl_fbuf f[3]) {
    sl_device dev = {0};
    sl_err e;
    if (sl_device_open("c", &dev, &e)) return 0;
    sl_renderer *r = sl_renderer_create(&dev, NULL);
    int n = 0;
    snprintf(t->s.shading_rate, sizeof t->s.shading_rate, "fragment");
    n += frame_tiny_render(r, t, &f[0]) == 0 && sl_renderer_shading_rate(r) == 0;
    snprintf(t->s.shading_rate, sizeof t->s.shading_rate, "vertex");
    for (int on = 0; on < 2; on++) {
        set(&t->s, on);
        n += frame_tiny_render(r, t, &f[1 + on]) == 0 && sl_renderer_shading_rate(r) == 1;
    }
    sl_renderer_free(r);
    sl_device_close(&dev);
    return n;
}

static void vertical_block_600(sl_hair *h) {
    vertical_block(h, 600, 12, 6, 0.05);
}

static void set_refine(sl_scene *s, int on) {
    s->shading_refine = on ? SL_FRAME_SHADING_REFINE : 0;
}

TEST(frame_refined_vertex_rate_follows_the_shadow) {
    /* A block of straight vertical fibers of 3 long segments, lit by one lobe from below at 45
     * deg: T falls by orders of magnitude along a segment into the block. Interpolating the
     * vertices' shading linearly along the strand overestimates it there (an exponential lies
     * below its chord; on straight.hair lit from below, against the path tracer's direct light,
     * the bottom rows were 3.6x too bright at vertex rate and 1.2x at fragment rate,
     * docs/results.md session 16). The refinement (quality.shading_refine) adds shading points
     * where T changes by more than 3x along a span. The fibers are straight, so a vertex's
     * tangent is its segments' and the fiber response barely changes along a strand; the
     * fragment rate (each K-buffer entry shaded where it lies: the same lookups and SRBF, only
     * the sampling rate differs) is what the refinement converges to. Measured against it (mean
     * |difference| / mean; image sum over the fragment rate's): 1.21 / 2.21x unrefined (1.18
     * / 2.18x with the tent pixel filter), 0.35 / 1.35x refined. What is left is the end vertices:
     * the deep opacity maps shadow a fiber by its own ribbon, less so at its two ends, and the
     * vertex rate samples the ends. Bounds: both figures refined within half of the unrefined ones
     * (the refinement disabled fails them both). */
    frame_tiny t;
    CHECK(one_lobe_scene(&t, vertical_block_600, 0.70710678, -0.70710678, 0, 0.2) == 0);
    frame_tiny_frame_camera(&t);
    sl_fbuf f[3];
    CHECK(three_rates(&t, set_refine, f) == 3);
    if (sl_test_failed_now()) return;
    const sl_fbuf a = f[0], b = f[1], c = f[2];
    const double db = frame_rel_l1(&b, &a), dc = frame_rel_l1(&c, &a);
    const double sa = frame_rgb_sum(&a), sb = frame_rgb_sum(&b), sc = frame_rgb_sum(&c);
    CHECK(sa > 0);
    printf("frame_refined_vertex_rate: against the fragment rate %.4f / %.3fx unrefined, "
           "%.4f / %.3fx refined\n",
           db, sb / sa, dc, sc / sa);
    CHECK_MSG(dc < 0.5 * db, "refined %.4f, unrefined %.4f", dc, db);
    CHECK_MSG(fabs(sc / sa - 1) < 0.5 * fabs(sb / sa - 1), "sums refined %.3f, unrefined %.3f",
              sc / sa, sb / sa);
    for (int k = 0; k < 3; k++)
        sl_fbuf_free(&f[k]);
    frame_tiny_free(&t);
}

/* A row of nv vertical fibers (x in [-1, 1], z = 0, y in [0, 3], two segments of 1.5, radius
 * 0.02) beside a comb of horizontal occluders along z (x = 2.2, z in [0, 2.5], y = 0.25, 0.5,
 * ..., 2.75; radius 0.04): light from (0.866, 0, 0.5) casts a shadow stripe ~0.1 high every
 * 0.25 along each fiber, six per segment, and the fibers do not shadow each other. */
static void comb_beside_fibers(sl_hair *h, int nv) {
    const int nh = 11, n = nv + nh, np = 3 * nv + 2 * nh;
    memset(h, 0, sizeof *h);
    sl_hair_alloc(h, (uint32_t)n, (uint32_t)np);
    h->radius = calloc((size_t)np, sizeof *h->radius);
    h->radius_source = SL_RADIUS_PER_POINT;
    uint32_t o = 0;
    for (int f = 0; f < n; f++) {
        h->strand_first[f] = o;
        const int vertical = f < nv, pts = vertical ? 3 : 2;
        for (int p = 0; p < pts; p++, o++) {
            float *q = h->pos + 3 * (size_t)o;
            if (vertical)
                q[0] = (float)(-1.0 + 2.0 * (f + 0.5) / nv), q[1] = 1.5f * p, q[2] = 0;
            else
                q[0] = 2.2f, q[1] = 0.25f * (float)(f - nv + 1), q[2] = p ? 2.5f : 0.0f;
            h->radius[o] = vertical ? 0.02f : 0.04f;
        }
    }
    h->strand_first[n] = o;
}

static void comb_beside_12(sl_hair *h) {
    comb_beside_fibers(h, 12);
}

static void set_sharp(sl_scene *s, int on) {
    s->sharp_shadows = on ? SL_FRAME_SHARP_SHADOWS : 0;
}

TEST(frame_sharp_lobe_shadow_per_entry) {
    /* A sun (one lobe of width lambda 0.02 < SL_FRAME_SHARP_LAMBDA) shining through a comb of
     * occluders casts a dozen shadow stripes on every segment of the fibers behind it. At vertex
     * rate the frame interpolates T between the segment's ends, so the stripes vanish; with
     * quality.sharp_shadows each K-buffer entry looks the sun's T up where it lies
     * (docs/frame.md, "Sharp shadows per entry"). The fragment rate shades every entry where it
     * lies: its T is the same lookup at the same position, so the shadow AOVs must agree to
     * float rounding (bound 1e-4 per pixel; measured 0; interpolated, 0.53). The fibers are
     * straight, so what is left of the beauty's difference is the response (the view direction
     * along a segment): mean |difference| / mean 0.040 per entry against 0.270 interpolated.
     * Bounds: 0.08 and a quarter of the interpolated figure. */
    frame_tiny t;
    CHECK(one_lobe_scene(&t, comb_beside_12, 0.8660254, 0, 0.5, 0.02) == 0);
    for (int k = 0; k < 3; k++) /* a sun's power: G's integral is pi lambda^2 */
        t.l.lobe[0].rgb[k] = 1.0 / (M_PI * 0.02 * 0.02);
    t.s.shading_refine = 0; /* the stripes, not the refinement, are under test */
    t.s.width = 128, t.s.height = 128;
    float lo[3], hi[3];
    sl_hair_bounds(&t.h, lo, hi);
    const double target[3] = {0, 1.5, 0};
    sl_camera_setup(&t.cam, NULL, target, t.s.up, 40, 128, 128, lo, hi);
    sl_fbuf f[3];
    CHECK(three_rates(&t, set_sharp, f) == 3);
    if (sl_test_failed_now()) return;
    const sl_fbuf a = f[0], b = f[1], c = f[2];
    double dmax_b = 0, dmax_c = 0, lit = 0, dark = 0;
    const size_t npx = (size_t)a.width * a.height;
    for (size_t i = 0; i < npx; i++) {
        if (a.rgba[4 * i + 3] <= 0) continue;
        dmax_b = fmax(dmax_b, fabs((double)b.shadow[i] - a.shadow[i]));
        dmax_c = fmax(dmax_c, fabs((double)c.shadow[i] - a.shadow[i]));
        lit += a.shadow[i] > 0.8f, dark += a.shadow[i] < 0.5f;
    }
    const double db = frame_rel_l1(&b, &a), dc = frame_rel_l1(&c, &a);
    printf("frame_sharp_lobe_shadow: %.0f lit and %.0f dark pixels; shadow AOV max |diff| "
           "%.2e (per entry) %.3f (interpolated); beauty %.4f / %.4f of the fragment rate's\n",
           lit, dark, dmax_c, dmax_b, dc, db);
    CHECK_MSG(lit > 20 && dark > 20, "the comb casts no stripes: %.0f lit, %.0f dark", lit, dark);
    CHECK_MSG(dmax_c < 1e-4, "shadow AOV per entry differs by %.2e", dmax_c);
    CHECK_MSG(dmax_b > 0.3, "interpolated shadows differ by only %.3f: the test sees no stripes",
              dmax_b);
    CHECK_MSG(dc < 0.08 && dc < 0.25 * db, "beauty %.4f per entry, %.4f interpolated", dc, db);
    /* the entries' lookups run in blocks of pixels on the threads (run_shade.c): the frame must
     * not depend on the thread count (tolerance 0) */
    sl_device dev = {0};
    sl_err e;
    CHECK(sl_device_open("c", &dev, &e) == 0);
    sl_fbuf g[2];
    for (int k = 0; k < 2; k++) {
        sl_render_opts o;
        sl_render_opts_default(&o);
        o.threads = k ? 3 : 1;
        o.quiet = 1;
        sl_renderer *r = sl_renderer_create(&dev, &o);
        CHECK(frame_tiny_render(r, &t, &g[k]) == 0);
        sl_renderer_free(r);
    }
    CHECK(memcmp(g[0].rgba, g[1].rgba, (size_t)g[0].width * g[0].height * 4 * sizeof(float)) == 0);
    CHECK(memcmp(g[0].rgba, f[2].rgba, (size_t)g[0].width * g[0].height * 4 * sizeof(float)) == 0);
    for (int k = 0; k < 2; k++)
        sl_fbuf_free(&g[k]);
    sl_device_close(&dev);
    for (int k = 0; k < 3; k++)
        sl_fbuf_free(&f[k]);
    frame_tiny_free(&t);
}

TEST(frame_c_vs_opencl) {
    /* The same frame on the C path and on OpenCL (PoCL here): the view pass, K-buffer and
     * resolve are shared C code, the DODM maps are bit-identical (docs/shadow.md) and the
     * lookup agrees to 1.2e-7; the SRBF kernel is the same float header as the C twin, so the
     * only differences are float rounding of device math (exp, cos, ...: a few ulps). Checked:
     * max |difference| <= 1e-3 x the brightest pixel (about 100x the float effects; a wrong
     * kernel argument or a missing lobe is > 1e-2). */
    sl_device cl = {0};
    sl_err e;
    SL_TEST_OPEN_CL(&cl, &e);
    frame_tiny t;
    CHECK(tiny_setup(&t, 150) == 0);
    sl_device c = {0};
    CHECK(sl_device_open("c", &c, &e) == 0);
    sl_renderer *rc = NULL, *ro = NULL;
    rc = sl_renderer_create(&c, NULL);
    ro = sl_renderer_create(&cl, NULL);
    sl_fbuf a, b;
    CHECK(frame_tiny_render(rc, &t, &a) == 0);
    unsigned long k0 = sl_cl_kernels_enqueued();
    CHECK(frame_tiny_render(ro, &t, &b) == 0);
    CHECK_CL_RAN(k0);
    double mx, md = frame_max_diff(&a, &b, &mx);
    CHECK(mx > 0);
    CHECK_MSG(md <= 1e-3 * mx, "max diff %g of max %g", md, mx);
    sl_fbuf_free(&a);
    sl_fbuf_free(&b);
    sl_renderer_free(rc);
    sl_renderer_free(ro);
    sl_device_close(&c);
    sl_device_close(&cl);
    frame_tiny_free(&t);
}

TEST(frame_kbuffer_opencl_equals_c) {
    /* kernels/view.cl vs the C twin on 300 random ribbons in a 40x30 image, K = 3 (many
     * merges): counts and every kept entry bit-identical (the same float "over" operations in
     * the same order per pixel). */
    sl_device cl = {0};
    sl_err e;
    SL_TEST_OPEN_CL(&cl, &e);
    uint32_t s = 11;
    slc_frag_list l = {0};
    for (uint32_t i = 0; i < 300; i++) {
        double p0[3] = {(lcg(&s) % 4000) / 100.0, (lcg(&s) % 3000) / 100.0, 1 + (lcg(&s) % 100)};
        double p1[3] = {p0[0] + (double)(lcg(&s) % 800) / 100.0 - 4,
                        p0[1] + (double)(lcg(&s) % 800) / 100.0 - 4, 1 + (lcg(&s) % 100)};
        slc_view_segment(p0, p1, 0.1 + (lcg(&s) % 100) / 100.0, 0.9f, 0.5f, i, 40, 30, &l);
    }
    enum { W = 40, H = 30, K = 3 };
    sl_kfrag *a = calloc(W * H * K, sizeof *a), *b = calloc(W * H * K, sizeof *b);
    uint8_t ca[W * H], cb[W * H];
    size_t ma = slc_kbuffer_build(&l, W, H, K, a, ca, 2), mb = 0;
    unsigned long k0 = sl_cl_kernels_enqueued();
    CHECK(slcl_kbuffer_build(cl.cl, &l, W, H, K, b, cb, &mb, &e) == 0);
    CHECK_CL_RAN(k0);
    CHECK(ma == mb && ma > 100);
    CHECK(memcmp(ca, cb, sizeof ca) == 0);
    int same = 1;
    for (int p = 0; p < W * H; p++)
        for (int i = 0; i < ca[p]; i++)
            same &= memcmp(&a[p * K + i], &b[p * K + i], sizeof *a) == 0;
    CHECK(same);
    free(a);
    free(b);
    slc_frag_list_free(&l);
    sl_device_close(&cl);
}

/* ---- planner audit (issue 9): per-strand sigma_a, material edits, thresholds, occlusion ---- */

static sl_renderer *new_renderer(sl_device *dev, int threads) {
    sl_render_opts o;
    sl_render_opts_default(&o);
    o.threads = threads;
    o.quiet = 1;
    return sl_renderer_create(dev, &o);
}

static void delete_renderer(sl_renderer *r) {
    sl_renderer_free(r);
}

/* The paint tests' state: the tiny scene with 150 strands, MS on and fragment-rate shading on a
 * 2-thread C renderer, its first (unpainted) frame a, and n per-strand sigma_a at the
 * material's values (sa). */
typedef struct paint_fx {
    frame_tiny t;
    sl_device dev;
    sl_renderer *r;
    sl_fbuf a;
    float *sa;
    uint32_t n;
} paint_fx;

static void paint_begin(paint_fx *p) {
    memset(p, 0, sizeof *p);
    tiny_open(&p->t, 150, &p->dev);
    p->t.s.multiple_scattering = SL_MS_ON;
    snprintf(p->t.s.shading_rate, sizeof p->t.s.shading_rate, "fragment");
    p->r = new_renderer(&p->dev, 2);
    CHECK(frame_tiny_render(p->r, &p->t, &p->a) == 0);
    p->n = p->t.h.num_strands;
    p->sa = frame_strand_sigma_a(&p->t);
}

static void paint_end(paint_fx *p) {
    free(p->sa);
    sl_fbuf_free(&p->a);
    delete_renderer(p->r);
    frame_tiny_close(&p->t, &p->dev);
}

TEST(frame_paint_reruns_only_shading) {
    /* per-strand sigma_a (paint): view, light, dual and volume stay cached; lookup and shade
     * run. Overrides equal to the material's sigma_a give the same frame (1e-5 relative to the
     * brightest pixel: the per-row absorption path may round differently from the per-material
     * one); a wrong strand count is a one-line error. */
    paint_fx p;
    sl_err e;
    sl_fbuf b;
    paint_begin(&p);
    CHECK(sl_renderer_set_strand_sigma_a(p.r, p.sa, p.n, &e) == 0);
    CHECK(frame_tiny_render(p.r, &p.t, &b) == 0);
    CHECK(frame_pass_state(p.r, "view") == SL_PASS_CACHED);
    CHECK(frame_pass_state(p.r, "light") == SL_PASS_CACHED);
    CHECK(frame_pass_state(p.r, "dual") == SL_PASS_CACHED);
    CHECK(frame_pass_state(p.r, "volume") == SL_PASS_CACHED);
    CHECK(frame_pass_state(p.r, "lookup") == SL_PASS_RUN);
    CHECK(frame_pass_state(p.r, "shade") == SL_PASS_RUN);
    double mx, md = frame_max_diff(&p.a, &b, &mx);
    CHECK(mx > 0);
    CHECK_MSG(md <= 1e-5 * mx, "max diff %g of %g", md, mx);
    sl_fbuf_free(&b);
    /* overrides for another hair */
    CHECK(sl_renderer_set_strand_sigma_a(p.r, p.sa, p.n - 1, &e) == 0);
    CHECK(sl_renderer_frame(p.r, &p.t.s, &p.t.h, &p.t.l, &p.t.cam, &b, &e) == -1);
    CHECK(strstr(e.msg, "per-strand sigma_a has 149 strands but the hair has 150") != NULL);
    CHECK(b.rgba == NULL);
    paint_end(&p);
}

/* Strands with an odd index painted black (sigma_a 20), multiple scattering on or off. */
static frame_paint_tally paint_half(int ms) {
    paint_fx p;
    sl_err e;
    sl_fbuf b;
    paint_begin(&p);
    if (!ms) { /* the plain frame again, without MS */
        p.t.s.multiple_scattering = SL_MS_OFF;
        sl_fbuf_free(&p.a);
        CHECK(frame_tiny_render(p.r, &p.t, &p.a) == 0);
    }
    for (uint32_t s = 1; s < p.n; s += 2)
        for (int q = 0; q < 3; q++)
            p.sa[3 * s + q] = 20.0f;
    CHECK(sl_renderer_set_strand_sigma_a(p.r, p.sa, p.n, &e) == 0);
    CHECK(frame_tiny_render(p.r, &p.t, &b) == 0);
    frame_paint_tally y = frame_paint_compare(p.r, &p.t, &p.a, &b);
    if (ms) { /* the march follows the strands' mean absorption */
        CHECK(frame_pass_state(p.r, "dual") == SL_PASS_RUN);
        CHECK(frame_pass_state(p.r, "volume") == SL_PASS_RUN);
        CHECK(frame_pass_state(p.r, "ms table") == SL_PASS_RUN);
    }
    sl_fbuf_free(&b);
    paint_end(&p);
    CHECK_MSG(y.changed, "the painted frame equals the plain one: the shading ignores per-strand "
                         "sigma_a");
    CHECK_MSG(y.clean > 100 && y.painted_px > 100, "clean %d, painted %d", y.clean, y.painted_px);
    CHECK_MSG(y.brighter == 0, "%d painted pixels brighter", y.brighter);
    CHECK_MSG(y.darker > y.painted_px / 2, "%d of %d painted pixels darker", y.darker,
              y.painted_px);
    return y;
}

TEST(frame_paint_half_differs_only_where_painted) {
    /* Single scattering only: every pixel whose K-buffer entries all belong to unpainted strands
     * is bit-identical (nothing but their own shading reaches them); no pixel with a painted
     * entry gets brighter and most get darker. */
    frame_paint_tally y = paint_half(0);
    CHECK(y.clean_same);
}

TEST(frame_paint_half_darkens_multiple_scattering) {
    /* With multiple scattering the black strands absorb light that the march would carry to
     * their unpainted neighbours (the march and the dual tables follow the strands' mean
     * sigma_a, docs/frame.md "Per-strand sigma_a"): unpainted pixels change too, and none gets
     * brighter. Before, MS kept the material's sigma_a and unpainted pixels stayed the same. */
    frame_paint_tally y = paint_half(1);
    CHECK_MSG(!y.clean_same, "unpainted pixels unchanged: MS ignores the painted absorption");
    CHECK_MSG(y.clean_brighter == 0, "%d unpainted pixels brighter", y.clean_brighter);
}

TEST(frame_material_edits_rerun_only_what_reads_them) {
    /* issue 9: editing beta_R re-runs only shading and the dual-scattering tables (and the
     * march that reads them; the voxel grid is reused); editing sigma_a never re-rasterizes
     * (view and light cached). */
    frame_tiny t;
    sl_device dev = {0};
    tiny_open(&t, 150, &dev);
    t.s.multiple_scattering = SL_MS_ON;
    sl_renderer *r = new_renderer(&dev, 2);
    CHECK(frame_tiny_render_drop(r, &t) == 0);
    CHECK(frame_pass_state(r, "dual") == SL_PASS_RUN);
    t.s.material.beta[0] *= 1.5;
    CHECK(frame_tiny_render_drop(r, &t) == 0);
    CHECK(frame_pass_state(r, "light") == SL_PASS_CACHED);
    CHECK(frame_pass_state(r, "view") == SL_PASS_CACHED);
    CHECK(frame_pass_state(r, "dual") == SL_PASS_RUN);
    CHECK(frame_pass_state(r, "volume") == SL_PASS_RUN);
    const sl_pass_rec *v = sl_renderer_pass(r, "volume");
    CHECK(v && strstr(v->why, "grid reused") != NULL);
    CHECK(frame_pass_state(r, "shade") == SL_PASS_RUN);
    t.s.material.sigma_a[1] = 1.3;
    CHECK(frame_tiny_render_drop(r, &t) == 0);
    CHECK(frame_pass_state(r, "light") == SL_PASS_CACHED);
    CHECK(frame_pass_state(r, "view") == SL_PASS_CACHED);
    /* nothing changed: only shading runs again */
    CHECK(frame_tiny_render_drop(r, &t) == 0);
    CHECK(frame_pass_state(r, "dual") == SL_PASS_CACHED);
    CHECK(frame_pass_state(r, "volume") == SL_PASS_CACHED);
    /* MS skipped: no dual tables either */
    t.s.multiple_scattering = SL_MS_OFF;
    CHECK(frame_tiny_render_drop(r, &t) == 0);
    CHECK(frame_pass_state(r, "dual") == SL_PASS_SKIPPED);
    delete_renderer(r);
    frame_tiny_close(&t, &dev);
}

TEST(frame_threshold_keys_drive_the_planner) {
    /* quality.lobe_threshold: 0.2 leaves out the lobes below 20 % of the power (the 4 tiny
     * lobes' shares, luminance x pi lambda^2 (1 - exp(-4 / lambda^2)) in double: 0.063, 0.033,
     * 0.311, 0.592, so two go); quality.ms_auto_threshold 0 runs
     * MS for black hair, 1 skips it for white hair; quality.point_threshold 0.9 cuts the lobes
     * evaluated per point (lobes AOV). */
    frame_tiny t;
    sl_device dev = {0};
    tiny_open(&t, 100, &dev);
    sl_renderer *r = new_renderer(&dev, 2);
    sl_fbuf a;
    t.s.lobe_threshold = 0.2;
    CHECK(frame_tiny_render_drop(r, &t) == 0);
    CHECK(frame_pass_state(r, "lobes") == SL_PASS_SKIPPED);
    CHECK(sl_renderer_lobes_used(r) == 2);
    const sl_pass_rec *p = sl_renderer_pass(r, "lobes");
    CHECK(p && strstr(p->why, "quality.lobe_threshold") != NULL);
    t.s.lobe_threshold = 1e-3;
    for (int c = 0; c < 3; c++)
        t.s.material.sigma_a[c] = 8.0;
    t.s.ms_auto_threshold = 0;
    CHECK(frame_tiny_render_drop(r, &t) == 0);
    CHECK(frame_pass_state(r, "ms") == SL_PASS_RUN);
    for (int c = 0; c < 3; c++)
        t.s.material.sigma_a[c] = 0.0;
    t.s.ms_auto_threshold = 1;
    CHECK(frame_tiny_render(r, &t, &a) == 0);
    CHECK(frame_pass_state(r, "ms") == SL_PASS_SKIPPED);
    p = sl_renderer_pass(r, "ms");
    CHECK(p && strstr(p->why, "quality.ms_auto_threshold") != NULL);
    double l0 = 0, l1 = 0;
    for (int i = 0; i < 64 * 48; i++)
        l0 += a.lobes[i];
    sl_fbuf_free(&a);
    t.s.point_threshold = 0.9;
    CHECK(frame_tiny_render(r, &t, &a) == 0);
    for (int i = 0; i < 64 * 48; i++)
        l1 += a.lobes[i];
    sl_fbuf_free(&a);
    delete_renderer(r);
    frame_tiny_close(&t, &dev);
    CHECK(l0 > 0);
    CHECK_MSG(l1 < l0,
              "lobes AOV %g at point_threshold 0.9, %g at the default: the shading "
              "ignores quality.point_threshold",
              l1, l0);
}

TEST(frame_kbuffer_occlusion_exact) {
    /* Fragments with a = 1 (full coverage of an opaque strand) hide what lies behind: the
     * K-buffer keeps nothing behind them, and the composite of every pixel (alpha and a colour
     * that is a function of the segment) equals the exact front-to-back composite of ALL its
     * fragments computed in double (K = 64 > fragments per pixel: no merge). 1e-5 absolute:
     * float weights of <= 30 layers. */
    uint32_t s = 5;
    slc_frag_list l = {0};
    for (uint32_t i = 0; i < 200; i++) {
        double p0[3] = {(lcg(&s) % 2000) / 100.0, (lcg(&s) % 1500) / 100.0, 1 + (lcg(&s) % 100)};
        double p1[3] = {p0[0] + (double)(lcg(&s) % 800) / 100.0 - 4,
                        p0[1] + (double)(lcg(&s) % 800) / 100.0 - 4, 1 + (lcg(&s) % 100)};
        float op = i % 3 ? 1.0f : 0.6f; /* two thirds opaque */
        slc_view_segment(p0, p1, 0.2 + (lcg(&s) % 200) / 100.0, op, op, i, 20, 15, &l);
    }
    enum { W = 20, H = 15, K = 64 };
    sl_kfrag *kb = calloc(W * H * K, sizeof *kb);
    uint8_t cnt[W * H];
    slc_kbuffer_build(&l, W, H, K, kb, cnt, 2);
    int hidden_pixels = 0, maxn = 0;
    double maxerr = 0;
    for (int p = 0; p < W * H; p++) {
        /* reference: every fragment of the pixel, sorted by (z, seg, t), composited in double */
        sl_kfrag all[256];
        int m = 0;
        for (size_t i = 0; i < l.n && m < 256; i++)
            if (l.pix[i] == (uint32_t)p) all[m++] = l.f[i];
        for (int i = 1; i < m; i++)
            for (int j = i; j > 0 && sl_kfrag_before(&all[j], &all[j - 1]); j--) {
                sl_kfrag x = all[j];
                all[j] = all[j - 1], all[j - 1] = x;
            }
        double T = 1, ref_a = 0, ref_c = 0;
        for (int i = 0; i < m; i++) {
            ref_a += T * all[i].a;
            ref_c += T * all[i].a * (double)(all[i].seg % 7);
            T *= 1 - (double)all[i].a;
        }
        float w[K];
        int n = cnt[p];
        float al = sl_kbuffer_weights(kb + p * K, n, w);
        double c = 0;
        for (int i = 0; i < n; i++)
            c += w[i] * (double)(kb[p * K + i].seg % 7);
        maxerr = fmax(maxerr, fmax(fabs(al - ref_a), fabs(c - ref_c)));
        hidden_pixels += n < m;
        if (m > maxn) maxn = m;
        for (int i = 0; i + 1 < n; i++) /* only the last entry may be fully opaque */
            CHECK(kb[p * K + i].a < 1.0f);
    }
    CHECK(maxn < K);
    CHECK_MSG(hidden_pixels > 20, "%d pixels lost hidden fragments", hidden_pixels);
    CHECK_MSG(maxerr <= 1e-5, "max error %g", maxerr);
    free(kb);
    slc_frag_list_free(&l);
}

TEST(frame_estimate_covers_allocations) {
    /* sl_frame_estimate_bytes >= what the frame really holds after a frame with MS (K-buffer,
     * counts, frame buffer, deep opacity maps, voxel grid), and not absurdly more (< 4x: the
     * shading points are counted at their fragment-rate maximum) */
    frame_tiny t;
    sl_device dev = {0};
    tiny_open(&t, 150, &dev);
    t.s.multiple_scattering = SL_MS_ON;
    t.s.voxels = 16;
    t.s.lobes = t.l.count;
    sl_renderer *r = new_renderer(&dev, 2);
    sl_fbuf a;
    CHECK(frame_tiny_render(r, &t, &a) == 0);
    double held = (double)r->view.w * r->view.h * (r->view.K * sizeof(sl_kfrag) + 1) +
                  (double)a.width * a.height * SL_FBUF_FLOATS * sizeof(float);
    for (int j = 0; j < r->nlights; j++)
        held += (double)r->light[j].view.w * r->light[j].view.h * (4.0 + 8.0 * r->light[j].K);
    held += (double)r->vgrid.n[0] * r->vgrid.n[1] * r->vgrid.n[2] * 4.0 * 6;
    double est = (double)sl_frame_estimate_bytes(&t.s, 0);
    CHECK_MSG(est >= held && est < 4 * held, "estimate %.0f, held %.0f", est, held);
    sl_fbuf_free(&a);
    delete_renderer(r);
    frame_tiny_close(&t, &dev);
}

TEST(frame_estimate_matches_sizes) {
    /* the estimate's parts follow the scene's settings: K-buffer bytes scale with oit_layers,
     * maps with shadow_size^2 x layers, per the size rules the passes allocate with */
    sl_scene s;
    sl_scene_default(&s);
    s.width = 100, s.height = 50, s.voxels = 4, s.lobes = 1, s.layers = 4, s.shadow_size = 16;
    s.oit_layers = 4;
    s.broad_lobes = SL_BROAD_SPLIT; /* subdivision's budget: checked at the end */
    double a = (double)sl_frame_estimate_bytes(&s, 0);
    s.oit_layers = 8;
    double b = (double)sl_frame_estimate_bytes(&s, 0);
    /* per pixel and layer: one sl_kfrag, one uint32 shade-map slot and one shading point
     * (pos 24 + tan 12 + strand 4 + T and B 4 each per lobe + 14 floats out = 104 B) */
    CHECK_NEAR(b - a, 5000.0 * 4 * (sizeof(sl_kfrag) + 4 + 104), 0.5);
    s.shadow_size = 32;
    double c = (double)sl_frame_estimate_bytes(&s, 0);
    /* x SL_SHADOW_SPLIT_MAPS_PER_LOBE maps per lobe (broad lobes are split, shadow_split.h) */
    CHECK_NEAR(c - b, 2.0 * (32.0 * 32 - 16 * 16) * (4 + 8 * 4), 0.5);
    CHECK_NEAR((double)sl_frame_estimate_bytes(&s, 16), b, 0.5); /* the option overrides */
    /* broad lobes subdivided (host/lighting/lobe_subdivide.h): at most the lobe plus the
     * ceil(4 pi (0.5 / w)^2) sub-lobes of quality.sublobe_width w (35 at the default 0.3, 51 at
     * 0.25) maps and as many lobes shaded (a T float per lobe per point) instead of 2 maps and
     * 1 lobe: the scene's width, not the finest one. Per lobe shaded: T and B per point, and the
     * march's four textures of 3 floats and the maps' depth tau (1 float) on (4 / 4 + 2)^3
     * coarse vertices. */
    s.broad_lobes = SL_BROAD_SUBDIVIDE;
    s.sublobe_width = 0.3;
    double d = (double)sl_frame_estimate_bytes(&s, 0);
    const double per_lobe = 5000.0 * 8 * 8 + 27.0 * 4 * (3 * 4 + 1);
    CHECK_NEAR(d - c, (36.0 - 2.0) * 32 * 32 * (4 + 8 * 4) + per_lobe * (36 - 1), 0.5);
    s.sublobe_width = 0.25;
    d = (double)sl_frame_estimate_bytes(&s, 0);
    CHECK_NEAR(d - c, (52.0 - 2.0) * 32 * 32 * (4 + 8 * 4) + per_lobe * (52 - 1), 0.5);
    s.broad_lobes = SL_BROAD_SPLIT;
    CHECK(sl_frame_oit_k(&s) == 8);
    s.oit_layers = 1000;
    CHECK(sl_frame_oit_k(&s) == SL_KBUFFER_MAX);
    s.shadow_size = 0;
    CHECK(sl_frame_shadow_size(&s, 0) == 256);
    s.width = 2000, s.height = 1000;
    CHECK(sl_frame_shadow_size(&s, 0) == 512);
}
