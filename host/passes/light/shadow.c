/* shadow.c: the light pass and lookup of shadow.h: view setup, segment records (host projection,
 * stochastic simplification), and the raster + tables + lookup steps on OpenCL or the C twins. */
#include "passes/light/shadow.h"

#include "base/parallel.h"

#include "../cpu/dodm.h"
#include "../cpu/raster.h"
#include "../kernels/dodm.h"
#include "../kernels/raster.h"
#include "passes/light/dodm_cl.h"
#include "passes/light/shadow_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

void sl_shadow_opts_default(sl_shadow_opts *o) {
    o->size = SL_SHADOW_DEFAULT_SIZE;
    o->layers = SL_SHADOW_DEFAULT_LAYERS;
    o->kappa = 1.0;
    o->seed = 1;
    o->z0_radius = 0;
    o->z0_fibers = 0; /* SL_SHADOW_Z0_FIBERS */
    o->threads = 0;
}

/* The automatic z0 window: its width (2 (m + frac) + 2 texels with the tent footprint) spans
 * `fibers` widened fibers of the hair's mean radius. The fractional part blends the windows m
 * and m + 1 (kernels/raster.h: sl_raster_z0_blend), so the window follows the fibers' width in
 * texels continuously; before session 14 it was rounded up to whole texels, which could widen
 * it by up to two texels (the wavy report hair at 1024^2: half-size 2 for 1.007 wanted). Where
 * the tent footprint alone is wider than `fibers` (most hair at 256^2), nothing changes
 * (docs/shadow.md, "A window of constant width in fibers"). */
static int auto_z0_radius(const sl_hair *h, double kappa, double texel, double fibers,
                          float *frac) {
    double r = h->default_radius;
    if (h->radius && h->num_points) {
        double s = 0;
        for (uint32_t i = 0; i < h->num_points; i++)
            s += h->radius[i];
        r = s / h->num_points;
    }
    const double x = (fibers * 2.0 * r / kappa / texel - 2.0) / 2.0; /* half-size, texels */
    *frac = 0.0f;
    if (!(x > 0)) return 0; /* the tent footprint alone is wider */
    if (x >= SL_SHADOW_Z0_MAX_RADIUS) return SL_SHADOW_Z0_MAX_RADIUS;
    const double m = floor(x);
    *frac = (float)(x - m);
    return (int)m;
}

double sl_shadow_lobe_support(double lambda) {
    /* exp(2 (cos a - 1) / lambda^2) = G  =>  cos a = 1 + lambda^2 ln(G) / 2 */
    double c = 1.0 + lambda * lambda * log(SL_SHADOW_SUPPORT_G) / 2.0;
    return c <= -1.0 ? M_PI : acos(c);
}

double sl_shadow_support_angle(double lambda) {
    double a = sl_shadow_lobe_support(lambda), amax = SL_SHADOW_SUPPORT_MAX_DEG * M_PI / 180.0;
    /* Capped: from lambda ~0.29 on, the 1e-3 support passes 30 degrees and by 0.54 reaches 90,
     * where the filter box covered the whole map and T -> 1 for every point (measured: T 0.91-0.97
     * against the ray-traced 0.15-0.18 for lambda >= 0.52 at the default scene's vertices; with
     * the cap 0.175 against 0.163; docs/shadow.md, docs/results.md). */
    return a < amax ? a : amax;
}

static double dot3(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

void sl_light_view_setup(sl_light_view *v, const double dir[3], const float lo[3],
                         const float hi[3], double margin, int size) {
    double c[3], rad = 0;
    for (int i = 0; i < 3; i++) {
        c[i] = 0.5 * ((double)lo[i] + hi[i]);
        rad += 0.25 * ((double)hi[i] - lo[i]) * ((double)hi[i] - lo[i]);
    }
    rad = sqrt(rad) + margin;
    if (!(rad > 0)) rad = 1;
    rad *= 1.0 + 4.0 / size; /* two spare texels on each side for the tent filter */
    double n = sqrt(dot3(dir, dir));
    for (int i = 0; i < 3; i++)
        v->ez[i] = -dir[i] / n;
    /* ex: the world axis least aligned with ez, made orthogonal to it */
    double a[3] = {0, 0, 0};
    int ai = fabs(v->ez[0]) < fabs(v->ez[1]) ? (fabs(v->ez[0]) < fabs(v->ez[2]) ? 0 : 2)
                                             : (fabs(v->ez[1]) < fabs(v->ez[2]) ? 1 : 2);
    a[ai] = 1;
    double p = dot3(a, v->ez);
    for (int i = 0; i < 3; i++)
        v->ex[i] = a[i] - p * v->ez[i];
    double l = sqrt(dot3(v->ex, v->ex));
    for (int i = 0; i < 3; i++)
        v->ex[i] /= l;
    v->ey[0] = v->ez[1] * v->ex[2] - v->ez[2] * v->ex[1];
    v->ey[1] = v->ez[2] * v->ex[0] - v->ez[0] * v->ex[2];
    v->ey[2] = v->ez[0] * v->ex[1] - v->ez[1] * v->ex[0];
    for (int i = 0; i < 3; i++)
        v->origin[i] = c[i] - rad * (v->ex[i] + v->ey[i] + v->ez[i]);
    v->texel = 2 * rad / size;
    v->w = v->h = size;
}

void sl_light_view_project(const sl_light_view *v, const double p[3], double uvz[3]) {
    double q[3] = {p[0] - v->origin[0], p[1] - v->origin[1], p[2] - v->origin[2]};
    uvz[0] = dot3(q, v->ex) / v->texel;
    uvz[1] = dot3(q, v->ey) / v->texel;
    uvz[2] = dot3(q, v->ez);
}

int sl_shadow_strand_kept(uint32_t strand, uint32_t seed, double kappa) {
    if (kappa >= 1) return 1;
    sl_hair_rng r = {((uint64_t)seed << 32) ^ strand};
    sl_hair_rng_next(&r);
    return (double)sl_hair_rng_float(&r) < kappa;
}

static double seg_radius(const sl_hair *h, uint32_t i) {
    return h->radius ? 0.5 * ((double)h->radius[i] + h->radius[i + 1]) : h->default_radius;
}

static void prep_free(prep *p) {
    free(p->seg);
    free(p->hw);
}

static int prep_make(const sl_hair *h, const sl_shadow_opts *o, prep *p, sl_err *e) {
    memset(p, 0, sizeof *p);
    if (o->size < 2 || o->size > SL_SHADOW_MAX_SIZE)
        return sl_fail(e, "shadow: map size %d is out of range [2, %d]", o->size,
                       SL_SHADOW_MAX_SIZE);
    if (o->layers < 1 || o->layers > SL_SHADOW_MAX_LAYERS)
        return sl_fail(e, "shadow: layers %d is out of range [1, %d]", o->layers,
                       SL_SHADOW_MAX_LAYERS);
    if (!(o->kappa > 0 && o->kappa <= 1))
        return sl_fail(e, "shadow: kappa %g is out of range (0, 1]", o->kappa);
    sl_hair_bounds(h, p->lo, p->hi);
    double rmax = h->default_radius;
    if (h->radius)
        for (uint32_t i = 0; i < h->num_points; i++)
            rmax = fmax(rmax, h->radius[i]);
    p->margin = rmax / o->kappa;
    sl_light_view v;
    double dir[3] = {0, 0, 1};
    sl_light_view_setup(&v, dir, p->lo, p->hi, p->margin, o->size);
    p->texel = v.texel;
    for (uint32_t s = 0; s < h->num_strands; s++)
        if (sl_shadow_strand_kept(s, o->seed, o->kappa))
            p->nseg += h->strand_first[s + 1] - h->strand_first[s] - 1;
    p->seg = sl_malloc((p->nseg ? p->nseg : 1) * sizeof *p->seg);
    p->hw = sl_malloc((p->nseg ? p->nseg : 1) * sizeof *p->hw);
    /* Fixed point: the largest power of two keeping the map's total below 2^60 (every box sum
     * and table entry then fits in 64 bits with room for rounding). The total is bounded by the
     * segments' 3-D lengths (a projection is never longer), so one scale serves every lobe. */
    double total = 0, wscale = 1.0 / o->kappa;
    size_t k = 0;
    for (uint32_t s = 0; s < h->num_strands; s++) {
        if (!sl_shadow_strand_kept(s, o->seed, o->kappa)) continue;
        for (uint32_t i = h->strand_first[s]; i + 1 < h->strand_first[s + 1]; i++, k++) {
            const float *a = h->pos + 3 * (size_t)i;
            double l = sqrt(((double)a[3] - a[0]) * ((double)a[3] - a[0]) +
                            ((double)a[4] - a[1]) * ((double)a[4] - a[1]) +
                            ((double)a[5] - a[2]) * ((double)a[5] - a[2]));
            p->seg[k] = i;
            p->hw[k] = (float)(seg_radius(h, i) * wscale / v.texel);
            total += 2.0 * (double)p->hw[k] * (l / v.texel + 1.0);
        }
    }
    int ex = total > 0 ? (int)floor(log2(ldexp(1.0, 60) / total)) : 0;
    if (ex > 100) ex = 100;
    p->scale = ldexp(1.0, ex);
    p->z0_frac = 0.0f;
    p->z0_radius =
        o->z0_radius < 0 ? 0
        : o->z0_radius > 0
            ? (o->z0_radius > SL_SHADOW_Z0_MAX_RADIUS ? SL_SHADOW_Z0_MAX_RADIUS : o->z0_radius)
            : auto_z0_radius(h, o->kappa, v.texel,
                             o->z0_fibers > 0 ? o->z0_fibers : SL_SHADOW_Z0_FIBERS, &p->z0_frac);
    p->threads = o->threads;
    if (p->threads <= 0) {
        p->threads = sl_parallel_cpus();
        /* automatic: below a few thousand segments a thread costs more than it saves */
        if ((size_t)p->threads > p->nseg / 2048 + 1) p->threads = (int)(p->nseg / 2048 + 1);
    }
    if (p->threads > SL_SHADOW_MAX_THREADS) p->threads = SL_SHADOW_MAX_THREADS;
    if ((size_t)p->threads > p->nseg) p->threads = p->nseg ? (int)p->nseg : 1;
    return 0;
}

/* One lobe's description: view, layer depth d from the kept hair's depth extent, box growth,
 * and the float view / lookup parameters the kernels take. */
static int lobe_setup(const sl_hair *h, const prep *p, const sl_shadow_opts *o, const double dir[3],
                      double lambda, sl_dodm *m, float *view, float *param, sl_err *e) {
    memset(m, 0, sizeof *m);
    if (!(dot3(dir, dir) > 0) || !isfinite(dot3(dir, dir)))
        return sl_fail(e, "shadow: lobe direction is zero");
    sl_light_view_setup(&m->view, dir, p->lo, p->hi, p->margin, o->size);
    m->K = (unsigned)o->layers;
    m->z0_radius = p->z0_radius;
    m->z0_frac = p->z0_frac;
    m->scale = p->scale;
    m->inv_scale = (float)(1.0 / p->scale);
    m->segments = p->nseg;
    double z[2] = {INFINITY, -INFINITY};
    for (size_t k = 0; k < p->nseg; k++)
        for (int c = 0; c < 2; c++) {
            const float *a = h->pos + 3 * ((size_t)p->seg[k] + c);
            double q = ((double)a[0] - m->view.origin[0]) * m->view.ez[0] +
                       ((double)a[1] - m->view.origin[1]) * m->view.ez[1] +
                       ((double)a[2] - m->view.origin[2]) * m->view.ez[2];
            z[0] = fmin(z[0], q);
            z[1] = fmax(z[1], q);
        }
    /* d from the depth extent: the last boundary K (K + 1) d / 2 reaches the far end. */
    double ext = p->nseg ? z[1] - z[0] : 0;
    double d = 2.0 * ext / (m->K * (m->K + 1.0));
    m->d = (float)fmax(d * (1 + 1e-6), 1e-6 * m->view.texel);
    double alpha = sl_shadow_support_angle(lambda);
    m->rfac = alpha >= M_PI / 2 ? INFINITY : (float)(tan(alpha) / (2 * m->view.texel));
    for (int c = 0; c < 3; c++) {
        view[c] = (float)m->view.origin[c];
        view[3 + c] = (float)(m->view.ex[c] / m->view.texel);
        view[6 + c] = (float)(m->view.ey[c] / m->view.texel);
        view[9 + c] = (float)m->view.ez[c];
    }
    param[0] = m->d;
    param[1] = m->rfac;
    param[2] = m->inv_scale;
    param[3] = 0;
    return 0;
}

typedef struct setup_ctx {
    const sl_hair *h;
    const prep *p;
    const sl_shadow_opts *o;
    const double *dirs, *lambdas;
    sl_shadow_batch *b;
} setup_ctx;

/* lobe_setup of lobes begin .. end - 1 (their directions are checked: it cannot fail). */
static void setup_run(void *arg, size_t begin, size_t end, int worker) {
    (void)worker;
    const setup_ctx *c = arg;
    for (size_t j = begin; j < end; j++) {
        struct sl_shadow_group *g = &c->b->group[j / SL_SHADOW_BATCH];
        const unsigned l = (unsigned)j - g->l0;
        sl_err e;
        (void)lobe_setup(c->h, c->p, c->o, c->dirs + 3 * j, c->lambdas[j], &c->b->map[j],
                         g->views + l * SL_RASTER_VIEW, g->params + l * SL_DODM_PARAMS, &e);
    }
}

static void group_release(struct sl_shadow_group *g) {
    free(g->views);
    free(g->params);
    free(g->z0);
    free(g->sat);
    slcl_shadow_group_release(g);
    memset(g, 0, sizeof *g);
}

void sl_shadow_batch_free(sl_shadow_batch *b) {
    for (int i = 0; i < b->ngroups; i++)
        group_release(&b->group[i]);
    free(b->group);
    free(b->map);
    memset(b, 0, sizeof *b);
}

/* One thread's share of a C-path step for one lobe: segments s0 .. s1 - 1 (z0 and layers into
 * this thread's own planes). */
typedef struct rjob {
    int step; /* 0 project, 1 first depth, 2 layers */
    const sl_hair *h;
    const prep *p;
    const struct sl_shadow_group *g;
    const float *view; /* step 0: the lobe's view (SL_RASTER_VIEW floats) */
    float *recs;       /* step 0 output: the lobe's records */
    const float *rec;  /* steps 1, 2: the lobe's records */
    size_t s0, s1;
    int w, hh;
    unsigned K;
    float d;
    const uint32_t *z0; /* step 2: the lobe's final (dilated) first depth */
    uint32_t *z0out;    /* step 1 output: one plane */
    uint64_t *bins;     /* step 2 output: K planes */
} rjob;

static void rjob_run(const rjob *j) {
    const float *r = j->rec + j->s0 * SL_RASTER_REC;
    if (j->step == 0) {
        for (size_t s = j->s0; s < j->s1; s++)
            sl_raster_project_seg(j->h->pos, j->p->seg, j->p->hw, j->view, (sl_uint)j->p->nseg, 0,
                                  (sl_uint)s, (float)j->p->scale, j->recs);
    } else if (j->step == 1) {
        slc_raster_z0(r, j->s1 - j->s0, j->w, j->hh, j->z0out);
    } else {
        slc_raster_layers(r, j->s1 - j->s0, j->w, j->hh, j->K, j->d, j->z0, j->bins);
    }
}

static void rjob_part(void *arg, size_t begin, size_t end, int part) {
    (void)part;
    const rjob *job = arg;
    for (size_t t = begin; t < end; t++)
        rjob_run(&job[t]);
}

/* Runs job[0 .. nt - 1], one a part (sl_parallel_parts), job 0 on the calling thread: the
 * result does not depend on where a job runs. */
static void rjobs_run(rjob *job, int nt) {
    sl_parallel_parts(nt, (size_t)nt, rjob_part, job);
}

/* One worker's scratch for the lobe-parallel C path: a lobe's records, its layers (texel-major)
 * and the window filter's two planes. */
typedef struct lscratch {
    float *recs;
    uint64_t *bins;
    uint32_t *tmp, *tmp2;
} lscratch;

typedef struct lctx {
    const sl_hair *h;
    const prep *p;
    sl_shadow_batch *b;
    lscratch *sc;       /* one per worker */
    double (*times)[3]; /* per lobe: project, raster, tables (s) */
} lctx;

/* Lobe l of the batch, whole, on one thread: projection, first depth, window, layers (texel-major:
 * a sample's four corners touch one or two cache lines, not 4 K), cumulate into the planes, tables.
 * The same functions as the segment-split path, so the same maps bit for bit. */
static void lobe_run(void *arg, size_t begin, size_t end, int worker) {
    const lctx *c = arg;
    const prep *p = c->p;
    sl_shadow_batch *b = c->b;
    const lscratch *sc = &c->sc[worker];
    const int w = b->map[0].view.w, hh = b->map[0].view.h;
    const size_t plane = (size_t)w * hh;
    const unsigned K = b->map[0].K;
    for (size_t j = begin; j < end; j++) {
        const struct sl_shadow_group *g = &b->group[j / SL_SHADOW_BATCH];
        const unsigned l = (unsigned)j - g->l0;
        uint32_t *z0 = g->z0 + l * plane;
        uint64_t *sat = g->sat + (size_t)l * K * plane;
        const double t0 = sl_now();
        for (size_t s = 0; s < p->nseg; s++)
            sl_raster_project_seg(c->h->pos, p->seg, p->hw, g->views + l * SL_RASTER_VIEW,
                                  (sl_uint)p->nseg, 0, (sl_uint)s, (float)p->scale, sc->recs);
        const double t1 = sl_now();
        slc_raster_z0(sc->recs, p->nseg, w, hh, z0);
        slc_raster_z0_dilate(z0, w, hh, p->z0_radius, p->z0_frac, sc->tmp, sc->tmp2);
        slc_raster_layers_texel(sc->recs, p->nseg, w, hh, K, g->params[l * SL_DODM_PARAMS], z0,
                                sc->bins);
        const double t2 = sl_now();
        slc_dodm_cumulate_texel(sc->bins, plane, K, sat);
        slc_dodm_sat(sat, w, hh, K);
        c->times[j][0] = t1 - t0;
        c->times[j][1] = t2 - t1;
        c->times[j][2] = sl_now() - t2;
        size_t n = 0;
        for (size_t s = 0; s < p->nseg; s++)
            n += (size_t)sc->recs[s * SL_RASTER_REC + 9] * (size_t)sc->recs[s * SL_RASTER_REC + 10];
        b->map[j].samples = n;
    }
}

/* The C path with at least as many lobes as threads: every thread takes whole lobes (dynamic,
 * one at a time), so both cores stay busy without a barrier, a merge or a thread start per map.
 * Which thread builds a lobe changes nothing in it. Times are summed over the lobes (thread
 * seconds, not wall). */
static void build_c_lobes(const sl_hair *h, const prep *p, sl_shadow_batch *b, int nt) {
    const size_t plane = (size_t)b->map[0].view.w * b->map[0].view.h;
    const unsigned K = b->map[0].K;
    lscratch sc[SL_SHADOW_MAX_THREADS];
    for (int t = 0; t < nt; t++) {
        sc[t].recs = sl_malloc((p->nseg ? p->nseg : 1) * SL_RASTER_REC * sizeof *sc[t].recs);
        sc[t].bins = sl_malloc(K * plane * sizeof *sc[t].bins);
        sc[t].tmp = sl_malloc(plane * sizeof *sc[t].tmp);
        sc[t].tmp2 = sl_malloc(plane * sizeof *sc[t].tmp2);
    }
    for (int gi = 0; gi < b->ngroups; gi++) {
        struct sl_shadow_group *g = &b->group[gi];
        g->z0 = sl_malloc(g->nl * plane * sizeof *g->z0);
        g->sat = sl_malloc((size_t)g->nl * K * plane * sizeof *g->sat);
    }
    double(*times)[3] = sl_malloc((size_t)b->n * sizeof *times);
    lctx c = {h, p, b, sc, times};
    sl_parallel_for(nt, (size_t)b->n, 1, lobe_run, &c);
    for (int j = 0; j < b->n; j++) {
        b->project_s += times[j][0];
        b->raster_s += times[j][1];
        b->tables_s += times[j][2];
    }
    free(times);
    for (int t = 0; t < nt; t++) {
        free(sc[t].recs);
        free(sc[t].bins);
        free(sc[t].tmp);
        free(sc[t].tmp2);
    }
}

/* The C twin of build_cl: the same records (sl_raster_project_seg), then the passes, one lobe
 * at a time (its records, 48 bytes a segment, stay in cache; a whole group's would not).
 * Threads split the segments into contiguous ranges; each rasterizes its range into its own
 * planes (thread 0 into the lobe's), which are then merged: first depth by minimum, layers by
 * 64-bit integer sums; both exact and order-independent, so the maps equal the one-thread maps
 * (and the kernel's) bit for bit whatever the thread count. With at least as many lobes as
 * threads the threads take whole lobes instead (build_c_lobes): the same maps. */
static void build_c(const sl_hair *h, const prep *p, sl_shadow_batch *b) {
    const int w = b->map[0].view.w, hh = b->map[0].view.h;
    const size_t plane = (size_t)w * hh;
    const unsigned K = b->map[0].K;
    const int nt = p->threads < 1 ? 1 : p->threads;
    if (b->n >= nt) {
        build_c_lobes(h, p, b, nt);
        return;
    }
    float *recs = sl_malloc((p->nseg ? p->nseg : 1) * SL_RASTER_REC * sizeof *recs);
    uint32_t *tmp = sl_malloc(plane * sizeof *tmp), *tmp2 = sl_malloc(plane * sizeof *tmp2);
    /* planes of threads 1 .. nt - 1 */
    uint32_t *xz0 = nt > 1 ? sl_malloc((size_t)(nt - 1) * plane * sizeof *xz0) : NULL;
    uint64_t *xbins = nt > 1 ? sl_malloc((size_t)(nt - 1) * K * plane * sizeof *xbins) : NULL;
    rjob job[SL_SHADOW_MAX_THREADS];
    for (int gi = 0; gi < b->ngroups; gi++) {
        struct sl_shadow_group *g = &b->group[gi];
        g->z0 = sl_malloc(g->nl * plane * sizeof *g->z0);
        g->sat = sl_malloc((size_t)g->nl * K * plane * sizeof *g->sat);
        for (unsigned l = 0; l < g->nl; l++) {
            uint32_t *z0 = g->z0 + l * plane;
            uint64_t *sat = g->sat + (size_t)l * K * plane;
            double t0 = sl_now();
            for (int t = 0; t < nt; t++) {
                job[t] = (rjob){0};
                job[t].h = h;
                job[t].p = p;
                job[t].view = g->views + l * SL_RASTER_VIEW;
                job[t].recs = recs;
                job[t].rec = recs;
                job[t].s0 = p->nseg * t / nt;
                job[t].s1 = p->nseg * (t + 1) / nt;
                job[t].w = w;
                job[t].hh = hh;
                job[t].K = K;
                job[t].d = g->params[l * SL_DODM_PARAMS];
                job[t].z0 = z0;
                job[t].z0out = t ? xz0 + (size_t)(t - 1) * plane : z0;
                job[t].bins = t ? xbins + (size_t)(t - 1) * K * plane : sat;
            }
            rjobs_run(job, nt);
            double t2 = sl_now();
            b->project_s += t2 - t0;
            for (int t = 0; t < nt; t++)
                job[t].step = 1;
            rjobs_run(job, nt);
            for (int t = 1; t < nt; t++) {
                const uint32_t *q = xz0 + (size_t)(t - 1) * plane;
                for (size_t i = 0; i < plane; i++)
                    z0[i] = q[i] < z0[i] ? q[i] : z0[i];
            }
            slc_raster_z0_dilate(z0, w, hh, p->z0_radius, p->z0_frac, tmp, tmp2);
            for (int t = 0; t < nt; t++)
                job[t].step = 2;
            rjobs_run(job, nt);
            for (int t = 1; t < nt; t++) {
                const uint64_t *q = xbins + (size_t)(t - 1) * K * plane;
                for (size_t i = 0; i < K * plane; i++)
                    sat[i] += q[i];
            }
            double t3 = sl_now();
            slc_dodm_cumulate(sat, plane, K);
            slc_dodm_sat(sat, w, hh, K);
            b->raster_s += t3 - t2;
            b->tables_s += sl_now() - t3;
            sl_dodm *m = &b->map[g->l0 + l];
            for (size_t s = 0; s < p->nseg; s++)
                m->samples +=
                    (size_t)recs[s * SL_RASTER_REC + 9] * (size_t)recs[s * SL_RASTER_REC + 10];
        }
    }
    free(recs);
    free(tmp);
    free(tmp2);
    free(xz0);
    free(xbins);
}

int sl_shadow_build_batch(sl_device *dev, const sl_hair *h, int n, const double *dirs,
                          const double *lambdas, const sl_shadow_opts *o, sl_shadow_batch *b,
                          sl_err *e) {
    memset(b, 0, sizeof *b);
    if (n < 1) return sl_fail(e, "shadow: a batch needs at least one lobe (got %d)", n);
    prep p;
    if (prep_make(h, o, &p, e)) return -1;
    b->n = n;
    b->map = sl_malloc((size_t)n * sizeof *b->map);
    b->ngroups = (n + SL_SHADOW_BATCH - 1) / SL_SHADOW_BATCH;
    b->group = sl_malloc((size_t)b->ngroups * sizeof *b->group);
    memset(b->group, 0, (size_t)b->ngroups * sizeof *b->group);
    for (int gi = 0; gi < b->ngroups; gi++) {
        struct sl_shadow_group *g = &b->group[gi];
        g->l0 = (unsigned)gi * SL_SHADOW_BATCH;
        g->nl = (unsigned)(n - (int)g->l0 < SL_SHADOW_BATCH ? n - (int)g->l0 : SL_SHADOW_BATCH);
        g->views = sl_malloc(g->nl * SL_RASTER_VIEW * sizeof *g->views);
        g->params = sl_malloc(g->nl * SL_DODM_PARAMS * sizeof *g->params);
    }
    for (int j = 0; j < n; j++) { /* the one way lobe_setup fails, found before the fan-out */
        const double *d = dirs + 3 * j;
        if (!(dot3(d, d) > 0) || !isfinite(dot3(d, d))) {
            prep_free(&p);
            sl_shadow_batch_free(b);
            return sl_fail(e, "shadow: lobe direction is zero");
        }
    }
    /* every lobe's setup reads every segment (its depth extent): in threads, one lobe a part */
    setup_ctx sc = {h, &p, o, dirs, lambdas, b};
    sl_parallel_for(n >= p.threads ? p.threads : 1, (size_t)n, 1, setup_run, &sc);
    if (dev->is_opencl) {
        int rc = slcl_shadow_build(dev->cl, h, &p, b, e);
        if (rc == 0) {
            b->cl = dev->cl;
            b->on_device = 1;
            prep_free(&p);
            return 0;
        }
        for (int gi = 0; gi < b->ngroups; gi++) /* drop the partial device maps */
            slcl_shadow_group_release(&b->group[gi]);
        b->project_s = b->raster_s = b->tables_s = b->upload_s = 0;
        if (!sl_device_try_fallback(dev, rc, e)) {
            prep_free(&p);
            sl_shadow_batch_free(b);
            return -1;
        }
    }
    build_c(h, &p, b);
    prep_free(&p);
    return 0;
}

int sl_shadow_batch_lookup(const sl_shadow_batch *b, size_t n, const double *xyz, const int *lobe,
                           double *T, sl_err *e) {
    if (lobe)
        for (size_t i = 0; i < n; i++)
            if (lobe[i] < 0 || lobe[i] >= b->n)
                return sl_fail(e, "shadow: point %zu: lobe %d is out of range [0, %d)", i, lobe[i],
                               b->n);
    if (n == 0) return 0;
    const int w = b->map[0].view.w, hh = b->map[0].view.h;
    const unsigned K = b->map[0].K;
    const size_t nout = lobe ? n : n * (size_t)b->n;
    float *pts = sl_malloc(3 * n * sizeof *pts), *t = sl_malloc(nout * sizeof *t);
    uint32_t *lb = lobe ? sl_malloc(n * sizeof *lb) : NULL;
    for (size_t i = 0; i < 3 * n; i++)
        pts[i] = (float)xyz[i];
    for (size_t i = 0; lobe && i < n; i++)
        lb[i] = (uint32_t)lobe[i];
    int rc = 0;
    if (!b->on_device) {
        for (int gi = 0; gi < b->ngroups; gi++) {
            const struct sl_shadow_group *g = &b->group[gi];
            slc_dodm_lookup_lobes(g->z0, g->sat, w, hh, K, g->params, g->views, pts, lb, n, g->nl,
                                  g->l0, (size_t)b->n, t);
        }
    } else {
        rc = slcl_shadow_lookup(b, n, pts, lb, nout, t, e);
    }
    if (!rc)
        for (size_t i = 0; i < nout; i++)
            T[i] = t[i];
    free(pts);
    free(t);
    free(lb);
    return rc;
}

int sl_shadow_batch_read(const sl_shadow_batch *b, int j, uint32_t *z0bits, uint64_t *sat,
                         sl_err *e) {
    if (j < 0 || j >= b->n) return sl_fail(e, "shadow: lobe %d is out of range [0, %d)", j, b->n);
    const struct sl_shadow_group *g = &b->group[j / SL_SHADOW_BATCH];
    const unsigned l = (unsigned)j - g->l0, K = b->map[j].K;
    const size_t plane = (size_t)b->map[j].view.w * b->map[j].view.h;
    if (!b->on_device) {
        memcpy(z0bits, g->z0 + l * plane, plane * sizeof *z0bits);
        memcpy(sat, g->sat + (size_t)l * K * plane, K * plane * sizeof *sat);
        return 0;
    }
    return slcl_shadow_read(b, g, l, z0bits, sat, e);
}

int sl_shadow_build(sl_device *dev, const sl_hair *h, const double dir[3], double lambda,
                    const sl_shadow_opts *o, sl_dodm *m, sl_err *e) {
    sl_shadow_batch b;
    memset(m, 0, sizeof *m);
    if (sl_shadow_build_batch(dev, h, 1, dir, &lambda, o, &b, e)) return -1;
    *m = b.map[0];
    m->raster_s = b.project_s + b.raster_s;
    m->tables_s = b.tables_s;
    const size_t plane = (size_t)m->view.w * m->view.h;
    struct sl_shadow_group *g = &b.group[0];
    int rc = 0;
    if (!b.on_device) { /* the C path's maps change hands */
        m->z0bits = g->z0;
        m->sat = g->sat;
        g->z0 = NULL;
        g->sat = NULL;
    } else {
        m->z0bits = sl_malloc(plane * sizeof *m->z0bits);
        m->sat = sl_malloc(m->K * plane * sizeof *m->sat);
        if (sl_shadow_batch_read(&b, 0, m->z0bits, m->sat, e)) {
            sl_dodm_free(m);
            rc = -1;
        }
    }
    sl_shadow_batch_free(&b);
    return rc;
}

int sl_shadow_build_maps(sl_device *dev, const sl_hair *h, int n, const double *dirs,
                         const double *lambdas, const sl_shadow_opts *o, sl_dodm *maps, sl_err *e) {
    sl_shadow_batch b;
    memset(maps, 0, (size_t)(n > 0 ? n : 0) * sizeof *maps);
    if (sl_shadow_build_batch(dev, h, n, dirs, lambdas, o, &b, e)) return -1;
    int rc = 0;
    for (int j = 0; j < n && !rc; j++) {
        sl_dodm *m = &maps[j];
        *m = b.map[j];
        /* the batch's step times shared out evenly (they are totals over its maps) */
        m->raster_s = (b.project_s + b.raster_s) / n;
        m->tables_s = b.tables_s / n;
        const size_t plane = (size_t)m->view.w * m->view.h;
        m->z0bits = sl_malloc(plane * sizeof *m->z0bits);
        m->sat = sl_malloc(m->K * plane * sizeof *m->sat);
        if (sl_shadow_batch_read(&b, j, m->z0bits, m->sat, e)) rc = -1;
    }
    if (rc)
        for (int j = 0; j < n; j++)
            sl_dodm_free(&maps[j]);
    sl_shadow_batch_free(&b);
    return rc;
}

/* A C-path lookup: points begin .. end - 1 are one part. */
typedef struct ljob {
    const sl_dodm *m;
    const float *pts;
    float *t;
    float *b; /* the optical depth behind too, or NULL */
} ljob;

static void ljob_run(void *arg, size_t begin, size_t end, int part) {
    (void)part;
    const ljob *j = arg;
    const sl_dodm *m = j->m;
    if (j->b)
        slc_dodm_lookup_both(m->z0bits, m->sat, m->view.w, m->view.h, m->K, m->d, m->rfac,
                             m->inv_scale, j->pts + 3 * begin, end - begin, j->t + begin,
                             j->b + begin);
    else
        slc_dodm_lookup(m->z0bits, m->sat, m->view.w, m->view.h, m->K, m->d, m->rfac, m->inv_scale,
                        j->pts + 3 * begin, end - begin, j->t + begin);
}

/* The C lookup, in threads over contiguous point ranges when there are enough points (every
 * point's T depends only on the map and the point: the same values for any split). */
static void lookup_c(const sl_dodm *m, const float *pts, size_t n, float *t, float *b) {
    enum { PER_THREAD = 4096 };
    int nt = sl_parallel_cpus();
    if (nt > SL_SHADOW_MAX_THREADS) nt = SL_SHADOW_MAX_THREADS;
    if ((size_t)nt > n / PER_THREAD + 1) nt = (int)(n / PER_THREAD + 1);
    ljob job = {m, pts, t, b};
    sl_parallel_parts(nt, n, ljob_run, &job);
}

int sl_shadow_lookup_both(sl_device *dev, const sl_dodm *m, size_t n, const double *xyz, double *T,
                          double *B, sl_err *e) {
    size_t nn = n ? n : 1;
    float *pts = sl_malloc(nn * 3 * sizeof *pts), *t = sl_malloc(nn * sizeof *t);
    float *b = B ? sl_malloc(nn * sizeof *b) : NULL;
    for (size_t i = 0; i < n; i++) {
        double uvz[3];
        sl_light_view_project(&m->view, xyz + 3 * i, uvz);
        for (int c = 0; c < 3; c++)
            pts[3 * i + c] = (float)uvz[c];
    }
    int rc = 0;
    if (dev->is_opencl) {
        rc = b ? slcl_dodm_lookup_both(dev->cl, m->z0bits, m->sat, m->view.w, m->view.h, m->K, m->d,
                                       m->rfac, m->inv_scale, pts, n, t, b, e)
               : slcl_dodm_lookup(dev->cl, m->z0bits, m->sat, m->view.w, m->view.h, m->K, m->d,
                                  m->rfac, m->inv_scale, pts, n, t, e);
        if (rc && !sl_device_try_fallback(dev, rc, e))
            rc = -1;
        else
            rc = 0; /* done, or dev is now the C path */
    }
    if (!rc && !dev->is_opencl) lookup_c(m, pts, n, t, b);
    for (size_t i = 0; !rc && i < n; i++) {
        T[i] = t[i];
        if (b) B[i] = b[i];
    }
    free(pts);
    free(t);
    free(b);
    return rc;
}

void sl_shadow_lookup_both_serial(const sl_dodm *m, size_t n, const double *xyz, double *T,
                                  double *B) {
    enum { BLOCK = 1024 }; /* points projected at a time: the float copies stay in cache */
    float pts[3 * BLOCK], t[BLOCK], b[BLOCK];
    for (size_t i0 = 0; i0 < n; i0 += BLOCK) {
        const size_t k = n - i0 < BLOCK ? n - i0 : BLOCK;
        for (size_t i = 0; i < k; i++) {
            double uvz[3];
            sl_light_view_project(&m->view, xyz + 3 * (i0 + i), uvz);
            for (int c = 0; c < 3; c++)
                pts[3 * i + c] = (float)uvz[c];
        }
        ljob job = {m, pts, t, B ? b : NULL};
        ljob_run(&job, 0, k, 0);
        for (size_t i = 0; i < k; i++) {
            T[i0 + i] = t[i];
            if (B) B[i0 + i] = b[i];
        }
    }
}

int sl_shadow_lookup(sl_device *dev, const sl_dodm *m, size_t n, const double *xyz, double *T,
                     sl_err *e) {
    return sl_shadow_lookup_both(dev, m, n, xyz, T, NULL, e);
}

void sl_dodm_free(sl_dodm *m) {
    free(m->z0bits);
    free(m->sat);
    m->z0bits = NULL;
    m->sat = NULL;
}
