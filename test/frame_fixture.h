/* frame_fixture.h: the tiny scene the whole-frame tests share (test_frame.c, test_frame_table.c)
 * and the helpers they all repeat: render a frame, a pass's state, the max pixel difference of
 * two frames, per-strand sigma_a arrays, and the painted/clean pixel tally of a paint test.
 * Static inline: every test file includes it into the one unit_tests binary. */
#ifndef SL_TEST_FRAME_FIXTURE_H
#define SL_TEST_FRAME_FIXTURE_H

#include "test.h"

#include "plan/frame.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct frame_tiny {
    sl_scene s;
    sl_hair h;
    sl_lobes l;
    sl_camera cam;
} frame_tiny;

/* The camera of t framing t's hair (its bounds' centre) at 64 x 48. */
static inline void frame_tiny_frame_camera(frame_tiny *t) {
    float lo[3], hi[3];
    sl_hair_bounds(&t->h, lo, hi);
    double target[3];
    for (int k = 0; k < 3; k++)
        target[k] = 0.5 * (lo[k] + hi[k]);
    sl_camera_setup(&t->cam, NULL, target, t->s.up, t->s.fov_deg, 64, 48, lo, hi);
}

/* Default scene at 64 x 48, `strands` wavy strands (10 points, seed 3), 4 lobes of different
 * widths and colours, the camera framing the hair. The caller sets the material it needs. */
static inline int frame_tiny_setup(frame_tiny *t, int strands) {
    memset(t, 0, sizeof *t);
    sl_scene_default(&t->s);
    t->s.width = 64;
    t->s.height = 48;
    sl_hair_procedural p = {SL_PROC_WAVY, (uint32_t)strands, 10, 3};
    sl_err e;
    if (sl_hair_generate(&p, &t->h, &e)) return -1;
    static const double dirs[4][3] = {{0, 1, 0}, {0.6, 0.0, 0.8}, {-0.8, 0.0, 0.6}, {0, -1, 0}};
    static const double lam[4] = {0.5, 0.3, 0.8, 1.0};
    t->l.count = 4;
    t->l.lobe = calloc(4, sizeof *t->l.lobe);
    for (int j = 0; j < 4; j++) {
        memcpy(t->l.lobe[j].dir, dirs[j], sizeof dirs[j]);
        t->l.lobe[j].lambda = lam[j];
        for (int c = 0; c < 3; c++)
            t->l.lobe[j].rgb[c] = 1.0 + 0.5 * j + 0.1 * c;
    }
    frame_tiny_frame_camera(t);
    return 0;
}

static inline void frame_tiny_free(frame_tiny *t) {
    sl_hair_free(&t->h);
    sl_lobes_free(&t->l);
}

/* The end of a test: the device it rendered on, then the scene. */
static inline void frame_tiny_close(frame_tiny *t, sl_device *dev) {
    sl_device_close(dev);
    frame_tiny_free(t);
}

/* One frame of the tiny scene; prints the error when it fails. */
static inline int frame_tiny_render(sl_renderer *r, frame_tiny *t, sl_fbuf *fb) {
    sl_err e;
    int rc = sl_renderer_frame(r, &t->s, &t->h, &t->l, &t->cam, fb, &e);
    if (rc) fprintf(stderr, "render: %s\n", e.msg);
    return rc;
}

/* One frame whose image is not looked at (only the planner's record): rendered and freed. */
static inline int frame_tiny_render_drop(sl_renderer *r, frame_tiny *t) {
    sl_fbuf fb;
    int rc = frame_tiny_render(r, t, &fb);
    sl_fbuf_free(&fb);
    return rc;
}

/* The planner's state of pass `name` in the last frame, -1 when it has no such pass. */
static inline int frame_pass_state(const sl_renderer *r, const char *name) {
    const sl_pass_rec *p = sl_renderer_pass(r, name);
    return p ? p->state : -1;
}

/* max |b - a| over every rgba float of two frames of the same size; *peak = max |a|. */
static inline double frame_max_diff(const sl_fbuf *a, const sl_fbuf *b, double *peak) {
    double md = 0, mx = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height * 4; i++) {
        md = fmax(md, fabs(a->rgba[i] - b->rgba[i]));
        mx = fmax(mx, fabs(a->rgba[i]));
    }
    *peak = mx;
    return md;
}

/* malloc'd 3 x num_strands per-strand sigma_a, every strand at the material's own values. */
static inline float *frame_strand_sigma_a(const frame_tiny *t) {
    uint32_t n = t->h.num_strands;
    float *sa = malloc(3 * n * sizeof *sa);
    for (uint32_t s = 0; s < n; s++)
        for (int q = 0; q < 3; q++)
            sa[3 * s + q] = (float)t->s.material.sigma_a[q];
    return sa;
}

/* A paint test's tally of frame b (odd strands painted) against frame a (unpainted). */
typedef struct frame_paint_tally {
    int clean;          /* pixels whose K-buffer entries all belong to even (unpainted) strands */
    int clean_same;     /* 1 when every clean pixel is bit-identical in a and b */
    int clean_brighter; /* clean pixels brighter in b beyond float rounding */
    int painted_px;     /* pixels with a painted entry and alpha > 0.05 */
    int darker;         /* of those, darker in b */
    int brighter;       /* of those, brighter in b beyond float rounding */
    int changed;        /* rgb floats that differ at all */
} frame_paint_tally;

/* r's K-buffer (of frame b) says which strands reach each pixel. */
static inline frame_paint_tally frame_paint_compare(const sl_renderer *r, const frame_tiny *t,
                                                    const sl_fbuf *a, const sl_fbuf *b) {
    frame_paint_tally y = {0, 1, 0, 0, 0, 0, 0};
    uint32_t n = t->h.num_strands;
    uint32_t *strand_of = malloc(t->h.num_points * sizeof *strand_of);
    for (uint32_t s = 0; s < n; s++)
        for (uint32_t i = t->h.strand_first[s]; i < t->h.strand_first[s + 1]; i++)
            strand_of[i] = s;
    int kw, kh, K;
    const sl_kfrag *kbuf;
    const uint8_t *kcount;
    CHECK(sl_renderer_kbuffer(r, &kw, &kh, &K, &kbuf, &kcount) == 0);
    CHECK(kw == a->width && kh == a->height);
    for (int px = 0; px < a->width * a->height; px++) {
        int k = kcount[px], painted = 0;
        for (int i = 0; i < k; i++)
            painted |= strand_of[kbuf[px * K + i].seg] % 2;
        for (int c = 0; c < 3; c++)
            y.changed += a->rgba[4 * px + c] != b->rgba[4 * px + c];
        double sa_ = a->rgba[4 * px] + a->rgba[4 * px + 1] + a->rgba[4 * px + 2];
        double sb_ = b->rgba[4 * px] + b->rgba[4 * px + 1] + b->rgba[4 * px + 2];
        if (!painted) {
            y.clean++;
            y.clean_same &= memcmp(a->rgba + 4 * px, b->rgba + 4 * px, 4 * sizeof(float)) == 0;
            y.clean_brighter += sb_ > sa_ * (1 + 1e-6) + 1e-9;
        } else if (a->rgba[4 * px + 3] > 0.05f) {
            /* more absorption never brightens (R does not depend on sigma_a, TT and TRT fall);
             * 1e-6 relative: float rounding of the composite */
            y.painted_px++;
            y.darker += sb_ < sa_;
            y.brighter += sb_ > sa_ * (1 + 1e-6) + 1e-9;
        }
    }
    free(strand_of);
    return y;
}

#endif
