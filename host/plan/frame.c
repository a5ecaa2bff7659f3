/* frame.c: the frame's pass planner and the passes' glue (see frame.h, docs/frame.md). Each pass
 * declares what it reads by the hash it is keyed on:
 *   light   hair geometry (points, radii, strands) + used lobes (dir, lambda) + shadow quality
 *   dual    material
 *   view    hair geometry + transparency + camera + image size + K
 *   srbf    material (Ren's table, kept while sl_srbf_ren_matches; the auto choice: plan_srbf)
 *   shade   everything, including the per-strand sigma_a (strand_key; always runs),
 *   resolve view + shade
 * and the planner re-runs a pass only when its key changed: a per-strand sigma_a edit (paint)
 * re-runs only lookup + shade + resolve (the multiple-scattering tables and volume use the
 * material's sigma_a, docs/frame.md). It also leaves out what the scene does not need: lobes
 * below quality.lobe_threshold of the total power (no map, no shading), multiple scattering for
 * dark hair (quality.multiple_scattering auto, quality.ms_auto_threshold), (point, lobe) pairs
 * below quality.point_threshold, the K-buffer layers no pixel reached and, for opaque hair, the
 * transparency channel. */
#include "plan/frame_internal.h"
#include "lighting/lobe_subdivide.h"
#include "passes/light/shadow_split.h"
#include "srbf_c.h"
#include "voxel.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

void sl_render_opts_default(sl_render_opts *o) {
    memset(o, 0, sizeof *o);
    o->srbf_method = SL_RENDER_SRBF_AUTO;
    o->segments = 4;
    o->lobe_threshold = -1; /* the scene's quality.lobe_threshold */
}

void sl_fbuf_free(sl_fbuf *f) {
    free(f->rgba);
    free(f->depth);
    for (int k = 0; k < 4; k++)
        free(f->mode[k]);
    free(f->shadow);
    free(f->lobes);
    memset(f, 0, sizeof *f);
}

int sl_render_method_parse(const char *s, int *method, sl_err *e) {
    if (strcmp(s, "auto") == 0)
        *method = SL_RENDER_SRBF_AUTO;
    else if (strcmp(s, "fast") == 0)
        *method = SL_SRBF_METHOD_FAST;
    else if (strcmp(s, "xu") == 0)
        *method = SL_SRBF_METHOD_XU;
    else if (strcmp(s, "table") == 0)
        *method = SL_RENDER_SRBF_TABLE;
    else
        return sl_fail(e, "SRBF method \"%s\": expected auto, fast, xu or table", s);
    return 0;
}

const char *sl_render_method_name(int method) {
    switch (method) {
    case SL_SRBF_METHOD_XU:
        return "xu";
    case SL_SRBF_METHOD_FAST:
        return "fast";
    case SL_RENDER_SRBF_TABLE:
        return "table";
    default:
        return "auto";
    }
}

void sl_renderer_set_editing(sl_renderer *r, int editing) {
    r->editing = editing != 0;
}

static void free_ren(sl_renderer *r) {
    slcl_srbf_ren_table_release(&r->ren_mem);
    if (r->have_ren) sl_srbf_ren_free(&r->ren);
    r->have_ren = 0;
}

void sl_renderer_init(sl_renderer *r, sl_device *dev, const sl_render_opts *o) {
    memset(r, 0, sizeof *r);
    r->dev = dev;
    if (o)
        r->o = *o;
    else
        sl_render_opts_default(&r->o);
}

static void free_lights(sl_renderer *r) {
    for (int i = 0; i < r->nlights; i++)
        sl_dodm_free(&r->light[i]);
    free(r->light);
    free(r->light_lobe);
    free(r->light_w);
    r->light_w = NULL;
    r->light = NULL;
    r->light_lobe = NULL;
    r->nlights = 0;
    r->light_key = 0;
}

static void free_march(sl_renderer *r) {
    if (r->have_vol) sl_ftex_free(&r->ftex);
    r->have_vol = 0;
    r->vol_key = 0;
}

static void free_volume(sl_renderer *r) {
    free_march(r);
    if (r->have_vgrid) sl_voxel_grid_free(&r->vgrid);
    r->have_vgrid = 0;
    r->vox_key = 0;
}

void sl_renderer_free(sl_renderer *r) {
    free_lights(r);
    free_volume(r);
    if (r->have_vms) sl_volume_ms_free(&r->vms);
    if (r->have_tables) sl_srbf_tables_free(&r->tables);
    free_ren(r);
    free(r->kbuf);
    free(r->kcount);
    free(r->strand_sigma_a);
    memset(r, 0, sizeof *r);
}

int sl_renderer_set_strand_sigma_a(sl_renderer *r, const float *sigma_a, uint32_t n, sl_err *e) {
    free(r->strand_sigma_a);
    r->strand_sigma_a = NULL;
    r->strand_sigma_a_n = 0;
    r->strand_key = 0;
    if (!sigma_a) return 0;
    for (size_t i = 0; i < 3 * (size_t)n; i++)
        if (!(sigma_a[i] >= 0.0f) || !isfinite(sigma_a[i]))
            return sl_fail(e, "per-strand sigma_a: strand %zu: expected a finite value >= 0",
                           i / 3);
    r->strand_sigma_a = sl_malloc(3 * (size_t)(n ? n : 1) * sizeof *r->strand_sigma_a);
    memcpy(r->strand_sigma_a, sigma_a, 3 * (size_t)n * sizeof *sigma_a);
    r->strand_sigma_a_n = n;
    r->strand_key = sl_hash64(sigma_a, 3 * (size_t)n * sizeof *sigma_a, 0x5354524e) | 1;
    return 0;
}

int sl_frame_threads(const sl_renderer *r) {
    if (r->o.threads > 0) return r->o.threads;
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : (n > 16 ? 16 : (int)n);
}

void sl_frame_pass(sl_renderer *r, const char *name, int state, double seconds, const char *fmt,
                   ...) {
    if (r->npass >= SL_FRAME_MAX_PASSES) return;
    sl_pass_rec *p = &r->pass[r->npass++];
    snprintf(p->name, sizeof p->name, "%s", name);
    p->state = state;
    p->seconds = seconds;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(p->why, sizeof p->why, fmt, ap);
    va_end(ap);
}

const sl_pass_rec *sl_renderer_pass(const sl_renderer *r, const char *name) {
    for (int i = 0; i < r->npass; i++)
        if (strcmp(r->pass[i].name, name) == 0) return &r->pass[i];
    return NULL;
}

void sl_renderer_explain(const sl_renderer *r, FILE *f) {
    static const char *st[] = {"run", "cached", "skipped"};
    fprintf(f, "%-10s %-8s %9s  %s\n", "pass", "state", "time", "why");
    for (int i = 0; i < r->npass; i++)
        fprintf(f, "%-10s %-8s %8.3fs  %s\n", r->pass[i].name, st[r->pass[i].state],
                r->pass[i].seconds, r->pass[i].why);
    fprintf(f, "%-10s %-8s %8.3fs\n", "total", "", r->total_s);
}

int sl_shading_rate_parse(const char *s, int *k, sl_err *e) {
    if (strcmp(s, "auto") == 0) {
        *k = -1;
    } else if (strcmp(s, "fragment") == 0) {
        *k = 0;
    } else if (strcmp(s, "vertex") == 0) {
        *k = 1;
    } else if (strncmp(s, "vertex:", 7) == 0) {
        char *end;
        long v = strtol(s + 7, &end, 10);
        if (*end || end == s + 7 || v < 1 || v > 64)
            return sl_fail(e, "shading rate \"%s\": vertex:K needs an integer K in 1..64", s);
        *k = (int)v;
    } else {
        return sl_fail(e, "shading rate \"%s\": expected auto, fragment, vertex or vertex:K", s);
    }
    return 0;
}

static uint64_t hash_geometry(const sl_hair *h, uint64_t k) {
    k = sl_hash64(&h->num_strands, sizeof h->num_strands, k);
    k = sl_hash64(h->strand_first, ((size_t)h->num_strands + 1) * sizeof *h->strand_first, k);
    k = sl_hash64(h->pos, (size_t)h->num_points * 3 * sizeof *h->pos, k);
    if (h->radius)
        k = sl_hash64(h->radius, (size_t)h->num_points * sizeof *h->radius, k);
    else
        k = sl_hash64(&h->default_radius, sizeof h->default_radius, k);
    return k;
}

static int hair_transparent(const sl_hair *h) {
    if (!h->transparency) return h->default_transparency > 0;
    for (uint32_t i = 0; i < h->num_points; i++)
        if (h->transparency[i] > 0) return 1;
    return 0;
}

/* Light pass: one deep opacity map per used lobe, cached by key. */
/* A broad lobe of the light pass: its position in the used list, its split directions and its
 * power (the budget's extra maps go to the most powerful first). */
typedef struct split_order {
    int lobe, dirs;
    double power;
} split_order;

static int split_order_cmp(const void *a, const void *b) {
    const split_order *x = a, *y = b;
    if (x->power != y->power) return x->power > y->power ? -1 : 1;
    return x->lobe - y->lobe; /* ties: the used order, so the plan is deterministic */
}

static int light_pass(sl_renderer *r, const sl_scene *s, const sl_hair *h, const sl_lobes *lobes,
                      const int *used, int nused, int extra_maps, sl_err *e) {
    sl_shadow_opts so;
    memset(&so, 0, sizeof so); /* padding too: the struct is hashed */
    sl_shadow_opts_default(&so);
    so.layers = sl_frame_shadow_layers(s);
    so.kappa = s->kappa > 0 ? s->kappa : 1.0;
    so.size = sl_frame_shadow_size(s, r->o.shadow_size);
    uint64_t k = hash_geometry(h, 0x11);
    k = sl_hash64(&so, sizeof so, k);
    so.threads = sl_frame_threads(r); /* after the key: the maps do not depend on it */
    for (int j = 0; j < nused; j++) {
        k = sl_hash64(lobes->lobe[used[j]].dir, sizeof lobes->lobe[0].dir, k);
        k = sl_hash64(&lobes->lobe[used[j]].lambda, sizeof(double), k);
    }
    k = sl_hash64(&extra_maps, sizeof extra_maps, k);
    if (k == r->light_key && r->light) {
        sl_frame_pass(r, "light", SL_PASS_CACHED, 0,
                      "%d deep opacity maps reused (geometry, lobes and shadow quality unchanged)",
                      r->nlights);
        return 0;
    }
    free_lights(r);
    double t0 = sl_now();
    /* broad lobes get several maps (shadow_split.h), within a budget of extra_maps beyond one
     * per lobe (SL_SHADOW_SPLIT_MAPS_PER_LOBE per lobe; with sub-lobes, what they left): the
     * extra maps go to the broad lobes of largest power first (a lobe left without extras keeps
     * its single capped map) */
    int nmaps = 0, nsplit = 0;
    double sd[3 * SL_SHADOW_SPLIT_N], sw[SL_SHADOW_SPLIT_N];
    int *want = sl_malloc((nused ? nused : 1) * sizeof *want);
    split_order *order = sl_malloc((nused ? nused : 1) * sizeof *order);
    int nbroad = 0;
    for (int j = 0; j < nused; j++) {
        const sl_lobe *lb = &lobes->lobe[used[j]];
        int c = sl_shadow_split(lb->dir, lb->lambda, sd, sw);
        want[j] = 1;
        if (c > 1)
            order[nbroad++] = (split_order){
                j, c, (lb->rgb[0] + lb->rgb[1] + lb->rgb[2]) * sl_lobe_integral(lb->lambda)};
    }
    qsort(order, (size_t)nbroad, sizeof *order, split_order_cmp);
    for (int b = 0, extra = extra_maps; b < nbroad; b++) {
        int give = order[b].dirs - 1 < extra ? order[b].dirs - 1 : extra;
        want[order[b].lobe] = 1 + give;
        extra -= give;
    }
    free(order);
    for (int j = 0; j < nused; j++)
        nsplit += want[j] > 1;
    sl_shadow_maps sm;
    sl_shadow_maps_plan(lobes, used, nused, want, &sm);
    nmaps = sm.n;
    r->light = sl_calloc(nmaps ? nmaps : 1, sizeof *r->light);
    r->light_lobe = sl_malloc((nmaps ? nmaps : 1) * sizeof *r->light_lobe);
    r->light_w = sl_malloc((nmaps ? nmaps : 1) * sizeof *r->light_w);
    sl_progress pr;
    sl_progress_begin(&pr, "light pass");
    for (int m = 0; m < nmaps; m++) {
        if (sl_shadow_build(r->dev, h, sm.dir + 3 * m, sm.lambda[m], &so, &r->light[m], e)) {
            sl_progress_end(&pr);
            r->nlights = m;
            free_lights(r);
            free(want);
            sl_shadow_maps_free(&sm);
            return -1;
        }
        r->light_lobe[m] = sm.lobe[m];
        r->light_w[m] = sm.w[m];
        r->nlights = m + 1;
        sl_progress_update(&pr, (m + 1.0) / nmaps);
    }
    sl_shadow_maps_free(&sm);
    sl_progress_end(&pr);
    free(want);
    r->light_key = k;
    sl_frame_pass(
        r, "light", SL_PASS_RUN, sl_now() - t0,
        "%d deep opacity maps %dx%d for %d lobes (%d broad, split), K=%d, kappa %.3g (%s)", nmaps,
        so.size, so.size, nused, nsplit, so.layers, so.kappa, r->dev->is_opencl ? "OpenCL" : "C");
    return 0;
}

/* The shading points of the last view pass (rate k: 0 fragment, >= 1 every k-th vertex) and the
 * map from each K-buffer entry to its shading (point index, or anchor pair + weight). */
typedef struct shade_map {
    uint32_t *strand_of; /* per point */
    uint32_t *anchor;    /* per hair point: shading point index, UINT32_MAX if not shaded */
    uint32_t *entry;     /* fragment rate: per K-buffer slot */
} shade_map;

static void anchors_of(const sl_hair *h, const uint32_t *strand_of, uint32_t pt, int k,
                       uint32_t *lo, uint32_t *hi) {
    uint32_t s = strand_of[pt], a = h->strand_first[s], b = h->strand_first[s + 1];
    *lo = a + (pt - a) / (uint32_t)k * (uint32_t)k;
    *hi = *lo + (uint32_t)k < b - 1 ? *lo + (uint32_t)k : b - 1;
    if (*lo == b - 1 && *lo > a) { /* the last point: its own anchor */
        *hi = *lo;
    }
}

static void build_points(sl_renderer *r, const sl_hair *h, shade_map *m, sl_shade_points *p) {
    size_t npx = (size_t)r->vw * r->vh;
    int K = r->vK, k = r->rate_k;
    size_t cap = 1024, n = 0;
    p->pos = sl_malloc(cap * 3 * sizeof *p->pos);
    p->tan = sl_malloc(cap * 3 * sizeof *p->tan);
    p->strand = sl_malloc(cap * sizeof *p->strand);
#define ADD_POINT(X, T, S)                                                                         \
    do {                                                                                           \
        if (n == cap) {                                                                            \
            cap *= 2;                                                                              \
            p->pos = sl_realloc(p->pos, cap * 3 * sizeof *p->pos);                                 \
            p->tan = sl_realloc(p->tan, cap * 3 * sizeof *p->tan);                                 \
            p->strand = sl_realloc(p->strand, cap * sizeof *p->strand);                            \
        }                                                                                          \
        for (int q = 0; q < 3; q++)                                                                \
            p->pos[3 * n + q] = (X)[q], p->tan[3 * n + q] = (T)[q];                                \
        p->strand[n] = (S);                                                                        \
        n++;                                                                                       \
    } while (0)
    if (k == 0) {
        m->entry = sl_malloc(npx * K * sizeof *m->entry);
        for (size_t px = 0; px < npx; px++)
            for (int i = 0; i < r->kcount[px]; i++) {
                const sl_kfrag *f = &r->kbuf[px * K + i];
                uint32_t s = m->strand_of[f->seg];
                double x[3];
                for (int q = 0; q < 3; q++)
                    x[q] = h->pos[3 * f->seg + q] +
                           (double)f->t * (h->pos[3 * f->seg + 3 + q] - h->pos[3 * f->seg + q]);
                float t[3];
                sl_hair_tangent(h, s, f->seg - h->strand_first[s], t);
                m->entry[px * K + i] = (uint32_t)n;
                ADD_POINT(x, t, s);
            }
    } else {
        m->anchor = sl_malloc((size_t)h->num_points * sizeof *m->anchor);
        for (uint32_t i = 0; i < h->num_points; i++)
            m->anchor[i] = 0;
        for (size_t px = 0; px < npx; px++)
            for (int i = 0; i < r->kcount[px]; i++) {
                uint32_t seg = r->kbuf[px * K + i].seg, lo, hi;
                anchors_of(h, m->strand_of, seg, k, &lo, &hi);
                m->anchor[lo] = m->anchor[hi] = 1;
            }
        for (uint32_t i = 0; i < h->num_points; i++) {
            if (!m->anchor[i]) {
                m->anchor[i] = UINT32_MAX;
                continue;
            }
            uint32_t s = m->strand_of[i];
            double x[3];
            for (int q = 0; q < 3; q++)
                x[q] = h->pos[3 * i + q];
            float t[3];
            sl_hair_point_tangent(h, s, i - h->strand_first[s], t);
            m->anchor[i] = (uint32_t)n;
            ADD_POINT(x, t, s);
        }
    }
#undef ADD_POINT
    p->n = n;
}

/* The shade vector (SL_SHADE_FLOATS) of K-buffer entry i of pixel px. */
static void entry_shade(const sl_renderer *r, const sl_hair *h, const shade_map *m,
                        const sl_shade_points *p, size_t px, int i, float *v) {
    const sl_kfrag *f = &r->kbuf[px * r->vK + i];
    if (r->rate_k == 0) {
        memcpy(v, p->out + (size_t)SL_SHADE_FLOATS * m->entry[px * r->vK + i],
               SL_SHADE_FLOATS * sizeof *v);
        return;
    }
    uint32_t lo, hi;
    anchors_of(h, m->strand_of, f->seg, r->rate_k, &lo, &hi);
    float w = hi > lo ? ((float)(f->seg - lo) + f->t) / (float)(hi - lo) : 0.0f;
    w = w < 0 ? 0 : (w > 1 ? 1 : w);
    const float *a = p->out + (size_t)SL_SHADE_FLOATS * m->anchor[lo];
    const float *b = p->out + (size_t)SL_SHADE_FLOATS * m->anchor[hi];
    for (int q = 0; q < SL_SHADE_FLOATS; q++)
        v[q] = a[q] + w * (b[q] - a[q]);
}

/* A lobe's power for the planner: luminance of rgb x the lobe's integral of G. */
static double lobe_power(const sl_lobe *lb) {
    static const double lum[3] = {0.2126, 0.7152, 0.0722};
    return (lum[0] * lb->rgb[0] + lum[1] * lb->rgb[1] + lum[2] * lb->rgb[2]) *
           sl_lobe_integral(lb->lambda);
}

int sl_frame_oit_k(const sl_scene *s) {
    int K = s->oit_layers > 0 ? s->oit_layers : 8;
    return K > SL_KBUFFER_MAX ? SL_KBUFFER_MAX : K;
}

int sl_frame_shadow_size(const sl_scene *s, int opt) {
    if (opt > 0) return opt;
    if (s->shadow_size > 0) return s->shadow_size;
    return (size_t)s->width * s->height > 1000000 ? 512 : 256;
}

int sl_frame_shadow_layers(const sl_scene *s) {
    int L = s->layers > 0 ? s->layers : SL_SHADOW_DEFAULT_LAYERS;
    return L > SL_SHADOW_MAX_LAYERS ? SL_SHADOW_MAX_LAYERS : L;
}

/* Per pixel: the frame buffer (SL_FBUF_FLOATS, alloc_fbuf), the K-buffer (K sl_kfrag + a uint8
 * count, frame_view.c), the fragment-rate shade map (K uint32, build_points) and ~16 B for the
 * outputs (cmd_render's EXR planes). Per lobe map: z0 (uint32) + K layers of 64-bit summed-area
 * tables (host/passes/light/shadow.h). The voxel grid: SL_VOX_FIELDS floats per voxel. The shading points
 * (at most one per K-buffer entry: pos 24 B, tan 12 B, strand 4 B, T 4 B per lobe, out 56 B)
 * are counted at fragment rate, their largest case. */
void sl_frame_estimate(const sl_scene *s, int shadow_size_opt, sl_frame_need *n) {
    double npx = (double)s->width * (double)s->height;
    int K = sl_frame_oit_k(s);
    double fbuf = SL_FBUF_FLOATS * sizeof(float) * npx, kbuf = npx * K * (double)sizeof(sl_kfrag);
    double view = kbuf + npx * (1.0 + 4.0 * K), outs = 16.0 * npx;
    int size = sl_frame_shadow_size(s, shadow_size_opt), layers = sl_frame_shadow_layers(s);
    int nl = s->lobes > 0 ? s->lobes : 1;
    /* maps: SL_SHADOW_SPLIT_MAPS_PER_LOBE per lobe (broad lobes split), at least
     * SL_SUBDIV_MIN_BUDGET when broad lobes are subdivided; the frame shades as many lobes at most
     * (sub-lobes: lobe_subdivide.h), each a T per point */
    int nmaps = SL_SHADOW_SPLIT_MAPS_PER_LOBE * nl;
    if (s->broad_lobes == SL_BROAD_SUBDIVIDE && nmaps < SL_SUBDIV_MIN_BUDGET)
        nmaps = SL_SUBDIV_MIN_BUDGET;
    int nshade = s->broad_lobes == SL_BROAD_SUBDIVIDE ? nmaps : nl;
    double points = npx * K * (24.0 + 12.0 + 4.0 + 4.0 * nshade + 4.0 * SL_SHADE_FLOATS);
    double shadow_one = (double)size * size * (4.0 + 8.0 * layers),
           shadow = (double)nmaps * shadow_one;
    double vox =
        s->voxels > 0 ? (double)s->voxels * s->voxels * s->voxels * 4.0 * SL_VOX_FIELDS : 0.0;
    n->host = fbuf + view + outs + points + shadow + vox;
    n->largest = kbuf, n->largest_what = "K-buffer",
    n->setting = "image.width/height or quality.oit_layers";
    if (npx * 16.0 > n->largest)
        n->largest = npx * 16.0, n->largest_what = "frame buffer",
        n->setting = "image.width/height";
    if (shadow_one > n->largest)
        n->largest = shadow_one, n->largest_what = "deep opacity map",
        n->setting = "quality.shadow_size or quality.layers";
    if (vox > n->largest)
        n->largest = vox, n->largest_what = "voxel grid", n->setting = "quality.voxels";
    /* the setting to name for the total: the biggest contributor */
    double parts[4] = {fbuf + outs, view + points, shadow, vox};
    const char *names[4] = {"image.width/height", "image.width/height or quality.oit_layers",
                            "quality.shadow_size, quality.layers or quality.lobes",
                            "quality.voxels"};
    int big = 0;
    for (int i = 1; i < 4; i++)
        if (parts[i] > parts[big]) big = i;
    n->host_setting = names[big];
}

size_t sl_frame_estimate_bytes(const sl_scene *s, int shadow_size_opt) {
    sl_frame_need n;
    sl_frame_estimate(s, shadow_size_opt, &n);
    return n.host >= (double)SIZE_MAX ? SIZE_MAX : (size_t)n.host;
}

static int alloc_fbuf(sl_fbuf *f, int w, int h) {
    memset(f, 0, sizeof *f);
    size_t n = (size_t)w * h;
    f->width = w, f->height = h;
    /* SL_FBUF_FLOATS per pixel (the estimate counts them): 4 + 1 + 4 x 3 + 1 + 1 */
    _Static_assert(SL_FBUF_FLOATS == 4 + 1 + 4 * 3 + 1 + 1, "sl_fbuf layout");
    f->rgba = sl_calloc(4 * n, sizeof(float));
    f->depth = sl_malloc(n * sizeof(float));
    for (int k = 0; k < 4; k++)
        f->mode[k] = sl_calloc(3 * n, sizeof(float));
    f->shadow = sl_calloc(n, sizeof(float));
    f->lobes = sl_calloc(n, sizeof(float));
    for (size_t i = 0; i < n; i++)
        f->depth[i] = INFINITY;
    return 0;
}

/* 1 when shading point i's strand has a per-strand sigma_a other than the material's: its rows
 * use `fast` even when the table is on (the table is baked for one sigma_a). */
static int painted(const sl_renderer *r, const sl_material *m, const sl_shade_points *p, size_t i) {
    if (!r->strand_sigma_a || !p->strand) return 0;
    const float *q = r->strand_sigma_a + 3 * (size_t)p->strand[i];
    return q[0] != (float)m->sigma_a[0] || q[1] != (float)m->sigma_a[1] ||
           q[2] != (float)m->sigma_a[2];
}

static void table_params(const sl_renderer *r, sl_srbf_ren_params *p) {
    if (r->o.table_params) {
        *p = *r->o.table_params;
    } else {
        sl_srbf_ren_params_default(p);
        p->threads = r->o.threads;
    }
}

/* Loads or builds the table for mat (kept while the material matches). */
static int ensure_table(sl_renderer *r, const sl_material *mat, int *state, sl_err *e) {
    if (r->have_ren && sl_srbf_ren_matches(&r->ren, mat)) {
        *state = SL_PASS_CACHED;
        return 0;
    }
    free_ren(r);
    sl_srbf_ren_params p;
    table_params(r, &p);
    if (sl_srbf_ren_get(r->dev, mat, &p, &r->ren, e)) return -1;
    r->have_ren = 1;
    *state = SL_PASS_RUN;
    return 0;
}

/* The SRBF method of this frame (docs/frame.md, "SRBF method"): records pass "srbf" and sets
 * r->srbf_used. rows: (point, lobe) rows of unpainted strands this frame shades. */
static int plan_srbf(sl_renderer *r, const sl_material *mat, double rows, double rows_painted,
                     sl_err *e) {
    int m = r->o.srbf_method, state = SL_PASS_SKIPPED;
    double t0 = sl_now();
    const char *paint_note = rows_painted > 0 ? "; rows of painted strands (per-strand sigma_a "
                                                "other than the material's) use fast"
                                              : "";
    if (mat->model != SL_MODEL_MARSCHNER && m == SL_RENDER_SRBF_AUTO) {
        r->srbf_used = SL_SRBF_METHOD_FAST;
        snprintf(r->srbf_why, sizeof r->srbf_why,
                 "auto: fast (model deon: the d'Eon fast path; no table for it)");
        sl_frame_pass(r, "srbf", SL_PASS_SKIPPED, 0, "no table: %s", r->srbf_why);
        return 0;
    }
    if (m == SL_SRBF_METHOD_XU || m == SL_SRBF_METHOD_FAST) {
        r->srbf_used = m;
        snprintf(r->srbf_why, sizeof r->srbf_why, "%s chosen (render --method %s)",
                 sl_render_method_name(m), sl_render_method_name(m));
        sl_frame_pass(r, "srbf", SL_PASS_SKIPPED, 0, "no table: %s", r->srbf_why);
        return 0;
    }
    const char *why = NULL;
    char buf[200];
    int use = 0;
    if (m == SL_RENDER_SRBF_TABLE) {
        use = 1;
        why = "table chosen (render --method table)";
    } else if (r->editing) {
        why = "auto: the material is being edited (sl_renderer_set_editing): fast, no table built";
    } else if (mat->eccentricity != 1.0) {
        /* the table averages an eccentric fiber over its rotation: p95 0.18 against the exact
         * value at one orientation where fast has 0.04 (docs/srbf_ren.md) */
        why = "auto: eccentric fiber (the table averages over the fiber's rotation, p95 error "
              "0.18 vs fast's 0.04): fast";
    } else if (r->have_ren && sl_srbf_ren_matches(&r->ren, mat)) {
        use = 1;
        why = "auto: the table for this material is in memory";
    } else if (rows <= 0) {
        why = "auto: no rows to shade from a table: fast";
    } else {
        sl_srbf_ren_params p;
        table_params(r, &p);
        long left = (r->o.frames > 0 ? r->o.frames : 1) - r->frames_done;
        if (left < 1) left = 1;
        double build = sl_srbf_ren_build_rows(mat, &p), saved = SL_FRAME_TABLE_SAVING * rows * left;
        if (sl_srbf_ren_cached(mat, &p, r->have_tables ? &r->tables : NULL)) {
            use = 1;
            why = "auto: the table for this material is in the disk cache";
        } else if (saved > build) {
            use = 1;
            snprintf(buf, sizeof buf,
                     "auto: building pays off: %ld frame%s x %.0f rows x %.1f saved > %.0f fast "
                     "evaluations to build",
                     left, left == 1 ? "" : "s", rows, SL_FRAME_TABLE_SAVING, build);
            why = buf;
        } else {
            snprintf(buf, sizeof buf,
                     "auto: fast: a build (%.0f fast evaluations) would not pay off over %ld "
                     "frame%s x %.0f rows x %.1f saved",
                     build, left, left == 1 ? "" : "s", rows, SL_FRAME_TABLE_SAVING);
            why = buf;
        }
    }
    if (use) {
        if (mat->model != SL_MODEL_MARSCHNER)
            return sl_fail(e, "render: the SRBF table exists for the Marschner model only");
        if (ensure_table(r, mat, &state, e)) return -1;
        r->srbf_used = SL_RENDER_SRBF_TABLE;
    } else {
        r->srbf_used = SL_SRBF_METHOD_FAST;
    }
    snprintf(r->srbf_why, sizeof r->srbf_why, "%s%s", why, use ? paint_note : "");
    if (use && state == SL_PASS_RUN)
        sl_frame_pass(r, "srbf", SL_PASS_RUN, sl_now() - t0,
                      "Ren table %s in %.2f s (built on %s; self-check vs fast: median %.2g, p95 "
                      "%.2g); %s",
                      r->ren.from_cache ? "loaded from the disk cache" : "built",
                      r->ren.from_cache ? sl_now() - t0 : r->ren.build_s, r->ren.built_on,
                      r->ren.err_median, r->ren.err_p95, r->srbf_why);
    else if (use)
        sl_frame_pass(r, "srbf", SL_PASS_CACHED, 0, "Ren table kept in memory; %s", r->srbf_why);
    else
        sl_frame_pass(r, "srbf", SL_PASS_SKIPPED, sl_now() - t0, "no table: %s", r->srbf_why);
    return 0;
}

int sl_renderer_frame(sl_renderer *r, const sl_scene *s, const sl_hair *h, const sl_lobes *lobes,
                      const sl_camera *cam, sl_fbuf *out, sl_err *e) {
    double t_start = sl_now(), t0;
    r->npass = 0;
    memset(out, 0, sizeof *out);
    const sl_material *mat = &s->material;
    /* model deon: the d'Eon fast path (kernels/srbf_deon.h) shades; Xu's form and Ren's table
     * exist for the Marschner model only, and so do the dual-scattering terms (docs/dual.md) */
    if (mat->model != SL_MODEL_MARSCHNER && r->o.srbf_method == SL_SRBF_METHOD_XU)
        return sl_fail(e, "render: material model deon: --method xu exists for the Marschner "
                          "model only (deon shades with --method fast; docs/srbf.md)");
    if (mat->model != SL_MODEL_MARSCHNER && r->o.srbf_method == SL_RENDER_SRBF_TABLE)
        return sl_fail(e, "render: material model deon: the SRBF table exists for the Marschner "
                          "model only (deon shades with --method fast; docs/srbf_ren.md)");
    if (lobes->count < 1) return sl_fail(e, "render: the environment has no lobes");
    if (r->strand_sigma_a && r->strand_sigma_a_n != h->num_strands)
        return sl_fail(e,
                       "render: per-strand sigma_a has %u strands but the hair has %u (the "
                       "overrides belong to another hair)",
                       r->strand_sigma_a_n, h->num_strands);
    const double lobe_thr = r->o.lobe_threshold >= 0 ? r->o.lobe_threshold : s->lobe_threshold;
    int rate;
    if (sl_shading_rate_parse(s->shading_rate, &rate, e)) return -1;
    if (!r->have_tables) {
        t0 = sl_now();
        if (sl_srbf_tables_get(&r->tables, 0, e)) return -1;
        r->have_tables = 1;
        sl_frame_pass(r, "tables", SL_PASS_RUN, sl_now() - t0, "SRBF C_k/H_k tables %s",
                      r->tables.from_cache ? "loaded from the disk cache" : "built");
    } else {
        sl_frame_pass(r, "tables", SL_PASS_CACHED, 0, "SRBF tables kept in memory");
    }

    /* lobes: skip those whose share of the total power is negligible */
    double *power = sl_malloc(lobes->count * sizeof *power), total = 0;
    for (int j = 0; j < lobes->count; j++) {
        power[j] = lobe_power(&lobes->lobe[j]);
        total += power[j];
    }
    int *used = sl_malloc(lobes->count * sizeof *used), nused = 0;
    double *share = sl_malloc(lobes->count * sizeof *share), skipped_share = 0;
    for (int j = 0; j < lobes->count; j++) {
        double sh = total > 0 ? power[j] / total : 0;
        if (sh >= lobe_thr) {
            share[nused] = sh;
            used[nused++] = j;
        } else {
            skipped_share += sh;
        }
    }
    free(power);
    r->lobes_used = nused;
    if (nused < lobes->count)
        sl_frame_pass(r, "lobes", SL_PASS_SKIPPED, 0,
                      "%d of %d lobes below %.3g of the total power (quality.lobe_threshold; "
                      "together %.2g %%) left out",
                      lobes->count - nused, lobes->count, lobe_thr, 100 * skipped_share);
    else
        sl_frame_pass(r, "lobes", SL_PASS_RUN, 0,
                      "all %d lobes above %.3g of the total power (quality.lobe_threshold)", nused,
                      lobe_thr);

    /* broad lobes (docs/shadow.md, "Broad lobes"): with quality.broad_lobes subdivide, every used
     * lobe with lambda > SL_SUBDIV_LAMBDA_MIN becomes narrower sub-lobes that sum to it
     * (host/lighting/lobe_subdivide.h), so every pass below (light, march, lookup, shade) sees narrow
     * lobes, each with its own transmittance and response. The budget is the split's: lobes
     * (one map each) plus split maps <= SL_SHADOW_SPLIT_MAPS_PER_LOBE x the used lobes (at least
     * SL_SUBDIV_MIN_BUDGET). The fit takes ~1 ms per broad lobe and is redone each frame; the
     * sub-lobes are deterministic, so an orbit's light pass still finds its maps by key. */
    const sl_lobes *fl = lobes;
    sl_lobes sub;
    memset(&sub, 0, sizeof sub);
    int extra_maps = (SL_SHADOW_SPLIT_MAPS_PER_LOBE - 1) * nused;
    if (s->broad_lobes == SL_BROAD_SUBDIVIDE) {
        t0 = sl_now();
        int budget = SL_SHADOW_SPLIT_MAPS_PER_LOBE * nused, nbroad = 0, nsub = 0;
        if (budget < SL_SUBDIV_MIN_BUDGET) budget = SL_SUBDIV_MIN_BUDGET;
        sl_lobes_subdivide(lobes, used, nused, budget, NULL, &sub, NULL, &nbroad, &nsub);
        if (nbroad > 0) {
            fl = &sub;
            free(used);
            free(share);
            nused = sub.count;
            used = sl_malloc(nused * sizeof *used);
            share = sl_malloc(nused * sizeof *share);
            for (int j = 0; j < nused; j++) {
                used[j] = j;
                share[j] = total > 0 ? lobe_power(&sub.lobe[j]) / total : 0;
            }
            extra_maps = budget - nused > 0 ? budget - nused : 0;
            sl_frame_pass(r, "subdivide", SL_PASS_RUN, sl_now() - t0,
                          "%d broad lobes (lambda > %.2g) subdivided into %d sub-lobes: %d lobes "
                          "shaded, at most %d deep opacity maps (quality.broad_lobes subdivide)",
                          nbroad, SL_SUBDIV_LAMBDA_MIN, nsub, nused, nused + extra_maps);
        } else {
            sl_frame_pass(r, "subdivide", SL_PASS_SKIPPED, sl_now() - t0,
                          "no used lobe broader than lambda %.2g (quality.broad_lobes subdivide)",
                          SL_SUBDIV_LAMBDA_MIN);
        }
    } else {
        sl_frame_pass(r, "subdivide", SL_PASS_SKIPPED, 0,
                      "quality.broad_lobes split: a broad lobe keeps one lobe, its transmittance "
                      "split over several maps");
    }

    int rc = -1;
    sl_shade_points pts = {0};
    shade_map sm = {0};
    if (light_pass(r, s, h, fl, used, nused, extra_maps, e)) goto done;

    /* the multiple-scattering decision (the material key dk: dual tables, march, MS response) */
    uint64_t dk = 0x22; /* field by field: the struct has padding */
    int mi[4] = {mat->model, mat->fresnel, mat->orders, mat->sigma_a_rgb};
    dk = sl_hash64(mi, sizeof mi, dk);
    dk = sl_hash64(&mat->eta, sizeof mat->eta, dk);
    dk = sl_hash64(mat->alpha, sizeof mat->alpha, dk);
    dk = sl_hash64(mat->beta, sizeof mat->beta, dk);
    dk = sl_hash64(mat->sigma_a, sizeof mat->sigma_a, dk);
    dk = sl_hash64(&mat->eccentricity, sizeof mat->eccentricity, dk);
    dk = sl_hash64(&mat->caustic_width, sizeof mat->caustic_width, dk);
    t0 = sl_now();
    double ms_share = -1;
    if (s->multiple_scattering == SL_MS_OFF) {
        r->ms_on = 0;
        sl_frame_pass(r, "ms", SL_PASS_SKIPPED, 0, "quality.multiple_scattering is off");
    } else if (mat->model != SL_MODEL_MARSCHNER) {
        r->ms_on = 0;
        sl_frame_pass(r, "ms", SL_PASS_SKIPPED, 0,
                      "model deon: the dual-scattering terms exist for the Marschner model only "
                      "(docs/dual.md); single scattering only");
    } else {
        ms_share = sl_dual_ms_share(mat);
        r->ms_on = s->multiple_scattering == SL_MS_ON || ms_share >= s->ms_auto_threshold;
        if (r->ms_on)
            sl_frame_pass(r, "ms", SL_PASS_RUN, sl_now() - t0,
                          "%s: estimated multiple-scattering share %.3f (quality.ms_auto_threshold "
                          "%.3g)%s",
                          s->multiple_scattering == SL_MS_ON ? "on" : "auto", ms_share,
                          s->ms_auto_threshold,
                          r->strand_sigma_a ? "; uses the material's sigma_a, not per strand" : "");
        else
            sl_frame_pass(r, "ms", SL_PASS_SKIPPED, sl_now() - t0,
                          "auto: dark hair, estimated multiple-scattering share %.4f < %.3g "
                          "(quality.ms_auto_threshold)",
                          ms_share, s->ms_auto_threshold);
    }
    if (r->ms_on) {
        /* the dual-scattering tables feed only the march: built when MS runs */
        t0 = sl_now();
        if (!r->dual_ok || dk != r->dual_key) {
            r->dual_ok = 0;
            if (sl_dual_tables_build(mat, &r->dual, e)) goto done;
            r->dual_ok = 1;
            r->dual_key = dk;
            sl_frame_pass(r, "dual", SL_PASS_RUN, sl_now() - t0,
                          "dual-scattering material tables (material changed)");
        } else {
            sl_frame_pass(r, "dual", SL_PASS_CACHED, 0,
                          "dual-scattering tables reused (material unchanged)");
        }
        /* volume: voxel grid (geometry) + shadow-path march toward every used lobe through the
         * dual tables (material), keyed apart so a material edit re-runs only the march */
        uint64_t gk = hash_geometry(h, 0x44);
        gk = sl_hash64(&s->voxels, sizeof s->voxels, gk);
        double *dirs = sl_malloc(3 * (nused ? nused : 1) * sizeof *dirs);
        for (int j = 0; j < nused; j++)
            for (int k = 0; k < 3; k++)
                dirs[3 * j + k] = fl->lobe[used[j]].dir[k];
        uint64_t vk0 = sl_hash64(&dk, sizeof dk, gk);
        vk0 = sl_hash64(dirs, 3 * nused * sizeof *dirs, vk0);
        if (r->have_vol && r->have_vgrid && gk == r->vox_key && vk0 == r->vol_key) {
            sl_frame_pass(r, "volume", SL_PASS_CACHED, 0,
                          "voxel grid and march textures reused (geometry, lobes, material "
                          "unchanged)");
        } else {
            t0 = sl_now();
            int grid_cached = r->have_vgrid && gk == r->vox_key;
            free_march(r);
            sl_march_opts mo;
            sl_march_opts_default(&mo);
            mo.threads = sl_frame_threads(r);
            if (!grid_cached) {
                free_volume(r);
                if (sl_voxelize(r->dev, h, s->voxels, &r->vgrid, e)) {
                    free(dirs);
                    goto done;
                }
                r->have_vgrid = 1;
                r->vox_key = gk;
            }
            if (sl_march_build(r->dev, &r->vgrid, &r->dual, nused, dirs, &mo, &r->ftex, e)) {
                free(dirs);
                goto done;
            }
            r->have_vol = 1;
            r->vol_key = vk0;
            sl_frame_pass(r, "volume", SL_PASS_RUN, sl_now() - t0,
                          "voxels %dx%dx%d (%s), march %d paths toward %d lobes (%zu active "
                          "vertices)",
                          r->vgrid.n[0], r->vgrid.n[1], r->vgrid.n[2],
                          grid_cached ? "grid reused: geometry unchanged" : "voxelized", mo.paths,
                          nused, r->ftex.active);
        }
        free(dirs);
        if (!r->have_vms || r->vms_key != dk) {
            if (r->have_vms) sl_volume_ms_free(&r->vms);
            r->have_vms = 0;
            t0 = sl_now();
            if (sl_volume_ms_init(mat, &r->vms, e)) goto done;
            r->have_vms = 1;
            r->vms_key = dk;
            sl_frame_pass(r, "ms table", SL_PASS_RUN, sl_now() - t0,
                          "multiple-scattering response tables of the material (%.2f s of it "
                          "the response table, docs/volume.md)",
                          r->vms.table_s);
        } else {
            sl_frame_pass(r, "ms table", SL_PASS_CACHED, 0, "material unchanged");
        }
    } else {
        sl_frame_pass(r, "dual", SL_PASS_SKIPPED, 0, "no multiple scattering");
        sl_frame_pass(r, "volume", SL_PASS_SKIPPED, 0, "no multiple scattering");
        sl_frame_pass(r, "ms table", SL_PASS_SKIPPED, 0, "no multiple scattering");
    }

    /* view pass */
    int K = sl_frame_oit_k(s);
    int transparent = hair_transparent(h);
    uint64_t vk = hash_geometry(h, 0x33);
    if (h->transparency) vk = sl_hash64(h->transparency, (size_t)h->num_points * sizeof(float), vk);
    vk = sl_hash64(&h->default_transparency, sizeof(float), vk);
    vk = sl_hash64(cam, sizeof *cam, vk);
    vk = sl_hash64(&K, sizeof K, vk);
    if (r->kbuf && vk == r->view_key) {
        sl_frame_pass(r, "view", SL_PASS_CACHED, 0,
                      "K-buffer reused (geometry, camera and K unchanged)");
    } else {
        t0 = sl_now();
        r->view_key = 0; /* a failed view pass leaves nothing valid behind */
        if (sl_frame_view(r, h, cam, K, e)) goto done;
        r->view_key = vk;
        size_t npx = (size_t)r->vw * r->vh;
        int maxc = 0;
        for (size_t i = 0; i < npx; i++)
            if (r->kcount[i] > maxc) maxc = r->kcount[i];
        sl_frame_pass(r, "view", SL_PASS_RUN, sl_now() - t0,
                      "%zu fragments, K=%d (deepest pixel %d), %zu merged on overflow or hidden "
                      "behind full coverage, "
                      "K-buffer on %s; %s",
                      r->frags, K, maxc, r->merges, r->kbuf_on_device ? "OpenCL" : "C",
                      transparent ? "per-point transparency applied"
                                  : "opaque hair: coverage only (transparency channel skipped)");
    }

    /* shading rate */
    if (rate < 0) {
        /* auto: shading dominates the CPU cost, so shade at strand vertices (interpolated along
         * the strand) unless segments project longer than quality.auto_fragment_px, where the
         * linear interpolation would visibly flatten highlights; segments shorter than a pixel
         * are shaded every k-th vertex, k = floor(2 px / length), so shaded points stay about
         * 2 px apart on screen (k <= 8) */
        float L = r->seg_px_median;
        if (L >= s->auto_fragment_px)
            rate = 0;
        else {
            int k = L > 0 ? (int)floorf(2.0f / L) : 8;
            rate = k < 1 ? 1 : (k > 8 ? 8 : k);
        }
    }
    r->rate_k = rate;

    /* shading points, transmittance lookups, shading */
    t0 = sl_now();
    sm.strand_of = sl_malloc((h->num_points ? h->num_points : 1) * sizeof *sm.strand_of);
    for (uint32_t st = 0; st < h->num_strands; st++)
        for (uint32_t i = h->strand_first[st]; i < h->strand_first[st + 1]; i++)
            sm.strand_of[i] = st;
    build_points(r, h, &sm, &pts);
    pts.T = sl_malloc(((size_t)nused * pts.n + 1) * sizeof *pts.T);
    pts.out = sl_malloc((pts.n * SL_SHADE_FLOATS + 1) * sizeof *pts.out);
    {
        /* T_j = sum over lobe j's maps of w T (one map, w = 1, unless the lobe is broad) */
        double *Td = sl_malloc((pts.n + 1) * sizeof *Td);
        double *Tj = sl_calloc((size_t)nused * pts.n + 1, sizeof *Tj);
        for (int m = 0; m < r->nlights; m++) {
            if (sl_shadow_lookup(r->dev, &r->light[m], pts.n, pts.pos, Td, e)) {
                free(Td);
                free(Tj);
                goto done;
            }
            double *t = Tj + (size_t)r->light_lobe[m] * pts.n;
            for (size_t i = 0; i < pts.n; i++)
                t[i] += r->light_w[m] * Td[i];
        }
        for (size_t i = 0; i < (size_t)nused * pts.n; i++)
            pts.T[i] = (float)Tj[i];
        free(Td);
        free(Tj);
    }
    sl_frame_pass(r, "lookup", SL_PASS_RUN, sl_now() - t0,
                  "transmittance of %zu shading points toward %d lobes", pts.n, nused);
    {
        /* rows this frame shades (the same cut as sl_frame_shade's), split by whether the
         * strand's sigma_a is the material's: only those can come from a table */
        double share_sum = 0, rows = 0, rows_p = 0;
        for (int j = 0; j < nused; j++)
            share_sum += share[j];
        for (size_t i = 0; i < pts.n; i++) {
            int c = 0;
            for (int j = 0; j < nused; j++)
                c += pts.T[(size_t)j * pts.n + i] * share[j] >= s->point_threshold * share_sum;
            if (painted(r, mat, &pts, i))
                rows_p += c;
            else
                rows += c;
        }
        if (plan_srbf(r, mat, rows, rows_p, e)) goto done;
    }
    t0 = sl_now();
    sl_shade_ctx sc = {mat,
                       fl,
                       used,
                       nused,
                       share,
                       cam,
                       r->ms_on,
                       &r->ftex,
                       &r->vms,
                       s->point_threshold,
                       r->strand_sigma_a};
    if (sl_frame_shade(r, &sc, &pts, e)) goto done;
    double lobes_eval = 0;
    for (size_t i = 0; i < pts.n; i++)
        lobes_eval += pts.out[SL_SHADE_FLOATS * i + 13];
    char ratebuf[48];
    if (rate == 0)
        snprintf(ratebuf, sizeof ratebuf, "fragment");
    else
        snprintf(ratebuf, sizeof ratebuf, "vertex:%d", rate);
    sl_frame_pass(
        r, "shade", SL_PASS_RUN, sl_now() - t0,
        "rate %s (%s; median segment %.2f px): %zu points, %.0f lobe evaluations "
        "(%.1f per point, quality.point_threshold %.3g)%s, SRBF %s on %s",
        ratebuf,
        strcmp(s->shading_rate, "auto") ? "quality.shading_rate" : "auto, quality.auto_fragment_px",
        r->seg_px_median, pts.n, lobes_eval, pts.n ? lobes_eval / pts.n : 0.0, s->point_threshold,
        r->strand_sigma_a ? ", per-strand sigma_a" : "", sl_render_method_name(r->srbf_used),
        sl_frame_srbf_on_device(r) ? "OpenCL"
        : r->dev->is_opencl ? "C (auto picked a CPU OpenCL device; the C twin is faster there)"
                            : "C");

    /* resolve */
    t0 = sl_now();
    alloc_fbuf(out, r->vw, r->vh);
    size_t npx = (size_t)r->vw * r->vh;
    for (size_t px = 0; px < npx; px++) {
        int n = r->kcount[px];
        if (!n) continue;
        float wt[SL_KBUFFER_MAX], v[SL_SHADE_FLOATS];
        float alpha = sl_kbuffer_weights(r->kbuf + px * K, n, wt);
        double acc[SL_SHADE_FLOATS] = {0};
        for (int i = 0; i < n; i++) {
            entry_shade(r, h, &sm, &pts, px, i, v);
            for (int q = 0; q < SL_SHADE_FLOATS; q++)
                acc[q] += (double)wt[i] * v[q];
        }
        for (int c = 0; c < 3; c++) {
            double sum = 0;
            for (int m = 0; m < 4; m++) {
                out->mode[m][3 * px + c] = (float)acc[3 * m + c];
                sum += acc[3 * m + c];
            }
            out->rgba[4 * px + c] = (float)sum;
        }
        out->rgba[4 * px + 3] = alpha;
        out->depth[px] = r->kbuf[px * K].z;
        out->shadow[px] = alpha > 0 ? (float)(acc[12] / alpha) : 0.0f;
        out->lobes[px] = alpha > 0 ? (float)(acc[13] / alpha) : 0.0f;
    }
    sl_frame_pass(r, "resolve", SL_PASS_RUN, sl_now() - t0,
                  "front-to-back compositing of %dx%d pixels%s", r->vw, r->vh,
                  transparent ? "" : " (opaque hair: coverage alpha only)");
    rc = 0;
    r->frames_done++;
done:
    sl_lobes_free(&sub);
    free(used);
    free(share);
    free(pts.pos);
    free(pts.tan);
    free(pts.strand);
    free(pts.T);
    free(pts.out);
    free(sm.strand_of);
    free(sm.anchor);
    free(sm.entry);
    if (rc) sl_fbuf_free(out);
    r->total_s = sl_now() - t_start;
    return rc;
}
