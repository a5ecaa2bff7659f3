/* viewer_paint.c: the absorption brush and its undo stack. A strand is under the brush when any
 * of its vertices projects (with the viewer's camera at full image size) in front of the camera
 * and within the brush radius of the brush centre; with the depth test on, that vertex must also
 * not lie behind the nearest fragment of the last refined frame at its pixel (so the brush
 * paints the hair you see, not the strands behind it). Each stroke is one undo step holding the
 * strands it changed and their previous values. */
#include "viewer/viewer.h"

#include "scene/scene_strands.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void step_free(sl_paint_step *s) {
    free(s->strand);
    free(s->old_sa);
    free(s->old_set);
    memset(s, 0, sizeof *s);
}

void sl_paint_free(sl_paint *p) {
    for (int i = 0; i < p->nundo; i++)
        step_free(&p->undo[i]);
    free(p->sa);
    free(p->set);
    memset(p, 0, sizeof *p);
}

void sl_paint_reset(sl_paint *p, uint32_t nstrands) {
    sl_paint_free(p);
    p->n = nstrands;
    p->sa = sl_calloc(3 * (size_t)(nstrands ? nstrands : 1), sizeof *p->sa);
    p->set = sl_calloc(nstrands ? nstrands : 1, 1);
}

int sl_viewer_paint_from_scene(sl_viewer *v, sl_err *e) {
    float *sa = NULL;
    if (sl_scene_strand_sigma_a(&v->scene, &v->hair, &sa, e)) return -1;
    if (!sa) return 0;
    sl_paint *p = &v->paint;
    const double *base = v->scene.material.sigma_a;
    p->nset = 0;
    for (uint32_t i = 0; i < p->n; i++) {
        int differs = 0;
        for (int c = 0; c < 3; c++) {
            p->sa[3 * i + c] = sa[3 * i + c];
            differs |= sa[3 * i + c] != (float)base[c];
        }
        /* "colors" gives every strand its own value; a CSV only the rows it lists */
        p->set[i] = (uint8_t)(v->scene.strand_sigma_a_colors || differs);
        p->nset += p->set[i];
    }
    free(sa);
    v->dirty = 1;
    v->refined = 0;
    return 0;
}

float *sl_viewer_paint_array(const sl_viewer *v) {
    const sl_paint *p = &v->paint;
    if (p->nset == 0 || p->n != v->hair.num_strands) return NULL;
    float *a = sl_malloc(3 * (size_t)p->n * sizeof *a);
    for (uint32_t i = 0; i < p->n; i++)
        for (int c = 0; c < 3; c++)
            a[3 * i + c] = p->set[i] ? p->sa[3 * i + c] : (float)v->scene.material.sigma_a[c];
    return a;
}

/* Appends strand i's previous state to step s unless the stroke already recorded it. */
static void record(sl_paint_step *s, const sl_paint *p, uint32_t i, uint8_t *seen) {
    if (seen[i]) return;
    seen[i] = 1;
    s->strand = sl_realloc(s->strand, (s->n + 1) * sizeof *s->strand);
    s->old_sa = sl_realloc(s->old_sa, 3 * (s->n + 1) * sizeof *s->old_sa);
    s->old_set = sl_realloc(s->old_set, s->n + 1);
    s->strand[s->n] = i;
    memcpy(s->old_sa + 3 * s->n, p->sa + 3 * (size_t)i, 3 * sizeof *s->old_sa);
    s->old_set[s->n] = p->set[i];
    s->n++;
}

/* Is a vertex at view depth z visible at pixel (px, py) of the last refined frame? Tolerance:
 * a few fiber radii plus 1 % of the depth, because the fragment depth is that of the nearest
 * strand surface at the pixel centre while the vertex lies on the fiber axis. */
static int depth_ok(const sl_viewer *v, const sl_camera *cam, double px, double py, double z,
                    double r) {
    const sl_fbuf *f = &v->last_full;
    /* no refined frame of this very view (e.g. the camera moved since): no depth test */
    if (!f->depth || memcmp(cam, &v->last_full_cam, sizeof *cam) != 0) return 1;
    int x = (int)floor(px), y = (int)floor(py);
    if (x < 0 || y < 0 || x >= f->width || y >= f->height) return 1;
    float d = f->depth[(size_t)y * f->width + x];
    if (!isfinite(d)) return 1;
    return z <= d + 4.0 * r + 0.01 * z;
}

long sl_viewer_paint_at(sl_viewer *v, double x, double y, double radius, const float sa[3],
                        int continue_stroke, sl_err *e) {
    sl_paint *p = &v->paint;
    if (!(radius > 0) || !isfinite(x) || !isfinite(y))
        return sl_fail(e, "paint: the brush needs a finite centre and a radius > 0");
    for (int c = 0; c < 3; c++)
        if (!(sa[c] >= 0) || !isfinite(sa[c]))
            return sl_fail(e, "paint: sigma_a must be finite and >= 0");
    if (p->n != v->hair.num_strands) sl_paint_reset(p, v->hair.num_strands);
    if (!continue_stroke || p->nundo == 0) {
        if (p->nundo == SL_VIEWER_UNDO_MAX) { /* drop the oldest */
            step_free(&p->undo[0]);
            memmove(p->undo, p->undo + 1, (SL_VIEWER_UNDO_MAX - 1) * sizeof *p->undo);
            memset(&p->undo[SL_VIEWER_UNDO_MAX - 1], 0, sizeof p->undo[0]);
            p->nundo--;
        }
        p->nundo++;
    }
    sl_paint_step *s = &p->undo[p->nundo - 1];
    uint8_t *seen = sl_calloc(p->n ? p->n : 1, 1);
    for (uint32_t k = 0; k < s->n; k++)
        seen[s->strand[k]] = 1;
    sl_camera cam;
    sl_viewer_camera(v, v->scene.width, v->scene.height, &cam);
    const sl_hair *h = &v->hair;
    double r2 = radius * radius;
    long hits = 0;
    for (uint32_t i = 0; i < h->num_strands; i++) {
        int hit = 0;
        for (uint32_t j = h->strand_first[i]; j < h->strand_first[i + 1] && !hit; j++) {
            double q[3] = {h->pos[3 * j], h->pos[3 * j + 1], h->pos[3 * j + 2]}, px, py, z;
            if (!sl_camera_project(&cam, q, &px, &py, &z)) continue;
            double dx = px - x, dy = py - y;
            if (dx * dx + dy * dy > r2) continue;
            double rad = h->radius ? h->radius[j] : h->default_radius;
            if (v->brush_depth_test && !depth_ok(v, &cam, px, py, z, rad)) continue;
            hit = 1;
        }
        if (!hit) continue;
        record(s, p, i, seen);
        if (!p->set[i]) p->nset++;
        p->set[i] = 1;
        memcpy(p->sa + 3 * (size_t)i, sa, 3 * sizeof *sa);
        hits++;
    }
    free(seen);
    if (s->n == 0) { /* nothing hit: no empty undo step */
        step_free(s);
        p->nundo--;
    }
    if (hits) {
        v->dirty = 1;
        v->refined = 0;
    }
    return hits;
}

int sl_viewer_undo(sl_viewer *v) {
    sl_paint *p = &v->paint;
    if (p->nundo == 0) return 0;
    sl_paint_step *s = &p->undo[--p->nundo];
    for (uint32_t k = s->n; k-- > 0;) {
        uint32_t i = s->strand[k];
        if (i >= p->n) continue;
        if (p->set[i] && !s->old_set[k]) p->nset--;
        if (!p->set[i] && s->old_set[k]) p->nset++;
        p->set[i] = s->old_set[k];
        memcpy(p->sa + 3 * (size_t)i, s->old_sa + 3 * (size_t)k, 3 * sizeof *p->sa);
    }
    step_free(s);
    v->dirty = 1;
    v->refined = 0;
    return 1;
}
