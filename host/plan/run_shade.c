/* run_shade.c: the frame's lookup and shade passes, run every frame: the shading points of
 * the view pass at this frame's rate with their transmittance toward each shaded lobe, then
 * the SRBF response (+ multiple scattering) per point (frame_shade.c). */
#include "plan/frame_internal.h"

#include "base/parallel.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int sl_frame_srbf_on_device(const sl_renderer *r) {
    return sl_shade_on_device(r->dev);
}

int sl_frame_shade(sl_renderer *r, const sl_shade_ctx *c, sl_shade_points *p, sl_err *e) {
    sl_shade_env env = {
        .dev = r->dev,
        .threads = sl_frame_threads(r),
        .on_device = sl_frame_srbf_on_device(r),
        /* the srbf pass's choice: rows whose sigma_a is the material's come from Ren's table,
         * the rest (painted strands) from the closed form */
        .table = r->srbf_used == SL_RENDER_SRBF_TABLE && r->have_ren,
        .method = r->srbf_used == SL_SRBF_METHOD_XU ? SL_SRBF_METHOD_XU : SL_SRBF_METHOD_FAST,
        .segments = r->fw.segments,
        .tables = &r->tables,
        .ren = &r->ren,
        .ren_mem = &r->ren_mem,
    };
    return sl_shade_run(&env, c, p, e);
}

/* The shading rate of this frame (r->rate_k) from quality.shading_rate and the view pass. */
static int shading_rate(const sl_renderer *r, const sl_scene *s) {
    int rate = r->fw.rate;
    if (rate >= 0) return rate;
    /* auto: shading dominates the CPU cost, so shade at strand vertices (interpolated along
     * the strand) unless segments project longer than quality.auto_fragment_px, where the
     * linear interpolation would visibly flatten highlights; segments shorter than a pixel
     * are shaded every k-th vertex, k = floor(2 px / length), so shaded points stay about
     * 2 px apart on screen (k <= 8) */
    float L = r->view.seg_px_median;
    if (L >= s->auto_fragment_px) return 0;
    int k = L > 0 ? (int)floorf(2.0f / L) : 8;
    return k < 1 ? 1 : (k > 8 ? 8 : k);
}

/* Per-lobe sums over lobe j's maps of w x the map's value at point i (one map, w = 1, unless
 * the lobe is broad): T_j into *T and, with B not NULL, the optical depth behind into *B, both
 * nused x n floats (index j n + i), allocated; one lookup per map for both. 0 or -1 with e set. */
static float *to_floats(const double *v, size_t n) {
    float *f = sl_malloc((n + 1) * sizeof *f);
    for (size_t i = 0; i < n; i++)
        f[i] = (float)v[i];
    return f;
}

/* Map m's T (and B) at n points: on the C path serially on the calling thread (the callers
 * below run maps or blocks on threads of their own), on an OpenCL device by one launch (one
 * caller thread). 0, or -1 with e set. */
static int lookup_map(const sl_renderer *r, int m, size_t n, const double *pos, double *T,
                      double *B, sl_err *e) {
    if (r->dev->is_opencl) return sl_shadow_lookup_both(r->dev, &r->light[m], n, pos, T, B, e);
    sl_shadow_lookup_both_serial(&r->light[m], n, pos, T, B);
    return 0;
}

/* Threads for the lookups: the frame's on the C path, 1 on an OpenCL device (its launches
 * fan out), at most MAXW (the workers' scratch). */
enum { MAXW = 16 };
static int lookup_threads(const sl_renderer *r, size_t items) {
    int nt = r->dev->is_opencl ? 1 : sl_frame_threads(r);
    if (nt > MAXW) nt = MAXW;
    if ((size_t)nt > items) nt = (int)items;
    return nt < 1 ? 1 : nt;
}

/* lobe_sums's work: the threads take whole lobes, each lobe's maps in their order (so the sums
 * are the same, bit for bit, for any thread count), each map looked up on the thread that sums
 * it. With a few thousand points per map, threads inside each lookup spent more on starting
 * than on looking up, and the projection ran on one thread. */
typedef struct lobe_sums_job {
    const sl_renderer *r;
    size_t n;
    const double *pos;
    double *st, *sb;             /* nused x n sums */
    double *vt[MAXW], *vb[MAXW]; /* per worker: one map's values */
    int rc;                      /* a failed device lookup (one worker then) */
    sl_err *e;
} lobe_sums_job;

static void lobe_sums_part(void *arg, size_t begin, size_t end, int worker) {
    lobe_sums_job *j = arg;
    const sl_renderer *r = j->r;
    for (size_t lobe = begin; lobe < end && !j->rc; lobe++)
        for (int m = 0; m < r->nlights && !j->rc; m++) {
            if ((size_t)r->light_lobe[m] != lobe) continue;
            double *vt = j->vt[worker], *vb = j->sb ? j->vb[worker] : NULL;
            if ((j->rc = lookup_map(r, m, j->n, j->pos, vt, vb, j->e))) break;
            double *st = j->st + lobe * j->n, *sb = j->sb ? j->sb + lobe * j->n : NULL;
            for (size_t i = 0; i < j->n; i++) {
                st[i] += r->light_w[m] * vt[i];
                if (sb) sb[i] += r->light_w[m] * vb[i];
            }
        }
}

static int lobe_sums(sl_renderer *r, size_t n, const double *pos, int nused, float **T, float **B,
                     sl_err *e) {
    const size_t all = (size_t)nused * n;
    lobe_sums_job job = {r,
                         n,
                         pos,
                         sl_calloc(all + 1, sizeof(double)),
                         B ? sl_calloc(all + 1, sizeof(double)) : NULL,
                         {0},
                         {0},
                         0,
                         e};
    const int nt = lookup_threads(r, (size_t)nused);
    for (int k = 0; k < nt; k++) {
        job.vt[k] = sl_malloc((n + 1) * sizeof *job.vt[k]);
        job.vb[k] = B ? sl_malloc((n + 1) * sizeof *job.vb[k]) : NULL;
    }
    sl_parallel_for(nt, (size_t)nused, 1, lobe_sums_part, &job);
    if (!job.rc) {
        *T = to_floats(job.st, all);
        if (B) *B = to_floats(job.sb, all);
    }
    for (int k = 0; k < nt; k++) {
        free(job.vt[k]);
        free(job.vb[k]);
    }
    free(job.st);
    free(job.sb);
    return job.rc;
}

/* lobe_sums at the points of p, each position looked up once: a bent vertex's two shading
 * points (one per segment, sl_shade_points_build) lie at one position, one after the other. */
static int lobe_sums_unique(sl_renderer *r, const sl_shade_points *p, int nused, float **T,
                            float **B, sl_err *e) {
    const size_t n = p->n;
    uint32_t *u = sl_malloc((n + 1) * sizeof *u);
    double *pos = sl_malloc((3 * n + 1) * sizeof *pos);
    size_t nu = 0;
    for (size_t i = 0; i < n; i++) {
        const double *x = p->pos + 3 * i;
        if (nu && x[0] == pos[3 * nu - 3] && x[1] == pos[3 * nu - 2] && x[2] == pos[3 * nu - 1]) {
            u[i] = (uint32_t)(nu - 1);
            continue;
        }
        memcpy(pos + 3 * nu, x, 3 * sizeof *x);
        u[i] = (uint32_t)nu++;
    }
    float *tu = NULL, *bu = NULL;
    int rc = lobe_sums(r, nu, pos, nused, &tu, B ? &bu : NULL, e);
    if (!rc) {
        *T = sl_malloc(((size_t)nused * n + 1) * sizeof **T);
        if (B) *B = sl_malloc(((size_t)nused * n + 1) * sizeof **B);
        for (int j = 0; j < nused; j++)
            for (size_t i = 0; i < n; i++) {
                (*T)[(size_t)j * n + i] = tu[(size_t)j * nu + u[i]];
                if (B) (*B)[(size_t)j * n + i] = bu[(size_t)j * nu + u[i]];
            }
    }
    free(u);
    free(pos);
    free(tu);
    free(bu);
    return rc;
}

/* Appends to the nlobes x n0 array *a (index j n0 + i) the nlobes x nadd array b: the
 * nlobes x (n0 + nadd) array of both, in place of *a. */
static void append_lobe_rows(float **a, const float *b, int nlobes, size_t n0, size_t nadd) {
    const size_t n = n0 + nadd;
    float *c = sl_malloc(((size_t)nlobes * n + 1) * sizeof *c);
    for (int j = 0; j < nlobes; j++) {
        memcpy(c + (size_t)j * n, *a + (size_t)j * n0, n0 * sizeof *c);
        memcpy(c + (size_t)j * n + n0, b + (size_t)j * nadd, nadd * sizeof *c);
    }
    free(*a);
    *a = c;
}

/* The sharp lobes' lookups, a block of block_px pixels at a time: each block on one thread (its
 * entries' positions, then the sharp maps in their order: the same sums for any split). */
typedef struct sharp_job {
    const sl_renderer *r;
    const sl_hair *h;
    const sl_kbuf_view *kb;
    sl_shade_points *pts;
    size_t block_px;
    double *pos[MAXW], *v[MAXW]; /* per worker */
    int rc;
    sl_err *e;
} sharp_job;

static void sharp_part(void *arg, size_t begin, size_t end, int worker) {
    sharp_job *j = arg;
    const sl_renderer *r = j->r;
    sl_shade_points *pts = j->pts;
    const size_t npx = (size_t)j->kb->w * j->kb->h;
    for (size_t b = begin; b < end && !j->rc; b++) {
        const size_t px0 = b * j->block_px, px1 = px0 + j->block_px < npx ? px0 + j->block_px : npx;
        const size_t e0 = pts->entry_first[px0], n = pts->entry_first[px1] - e0;
        if (!n) continue;
        sl_shade_entry_positions(j->h, j->kb, px0, px1, j->pos[worker]);
        for (int m = 0; m < r->nlights && !j->rc; m++) {
            const int l = sl_shade_sharp_slot(pts, r->light_lobe[m]);
            if (l < 0) continue;
            if ((j->rc = lookup_map(r, m, n, j->pos[worker], j->v[worker], NULL, j->e))) break;
            float *t = pts->entry_T + (size_t)l * pts->nentries + e0;
            for (size_t i = 0; i < n; i++)
                t[i] += (float)(r->light_w[m] * j->v[worker][i]);
        }
    }
}

/* Vertex rate: the lobes whose shadow each K-buffer entry looks up itself (docs/frame.md, "Sharp
 * shadows per entry"): up to quality.sharp_shadows of the most powerful used lobes with width
 * lambda <= SL_FRAME_SHARP_LAMBDA, a share >= SL_FRAME_SHARP_MIN_SHARE and a deep opacity map.
 * Their T at each entry's own position into pts (entry_first, entry_T). 0, or -1 with e set. */
static int sharp_lobes(sl_renderer *r, const sl_scene *s, const sl_hair *h, const sl_kbuf_view *kb,
                       sl_err *e) {
    sl_frame_work *w = &r->fw;
    sl_shade_points *pts = &w->pts;
    pts->nsharp = 0;
    if (r->rate_k < 1 || s->sharp_shadows < 1 || !w->nused) return 0;
    double sum = 0;
    for (int j = 0; j < w->nused; j++)
        sum += w->share[j];
    int nmax = s->sharp_shadows < SL_SHADE_SHARP_MAX ? s->sharp_shadows : SL_SHADE_SHARP_MAX;
    for (int pick = 0; pick < nmax; pick++) {
        int best = -1;
        for (int j = 0; j < w->nused; j++) {
            if (w->fl->lobe[w->used[j]].lambda > SL_FRAME_SHARP_LAMBDA) continue;
            if (!(w->share[j] >= SL_FRAME_SHARP_MIN_SHARE * sum)) continue;
            if (sl_shade_sharp_slot(pts, j) >= 0) continue;
            int mapped = 0;
            for (int m = 0; m < r->nlights; m++)
                mapped |= r->light_lobe[m] == j;
            if (mapped && (best < 0 || w->share[j] > w->share[best])) best = j;
        }
        if (best < 0) break;
        pts->sharp[pts->nsharp] = best;
        pts->sharp_share[pts->nsharp] = (float)(w->share[best] / sum);
        pts->nsharp++;
    }
    if (!pts->nsharp) return 0;
    /* the entries' positions in blocks of pixels: a position array for every entry would be the
     * largest buffer of the pass (24 B per entry) */
    enum { BLOCK_PX = 4096 };
    const size_t npx = (size_t)kb->w * kb->h;
    pts->entry_first = sl_shade_entry_first(kb);
    pts->nentries = pts->entry_first[npx];
    pts->entry_T = sl_calloc((size_t)pts->nsharp * pts->nentries + 1, sizeof *pts->entry_T);
    const size_t nblocks = (npx + BLOCK_PX - 1) / BLOCK_PX;
    sharp_job job = {r, h, kb, pts, BLOCK_PX, {0}, {0}, 0, e};
    const int nt = lookup_threads(r, nblocks);
    for (int k = 0; k < nt; k++) {
        job.pos[k] = sl_malloc((3 * (size_t)BLOCK_PX * kb->K + 1) * sizeof *job.pos[k]);
        job.v[k] = sl_malloc(((size_t)BLOCK_PX * kb->K + 1) * sizeof *job.v[k]);
    }
    sl_parallel_for(nt, nblocks, 1, sharp_part, &job);
    for (int k = 0; k < nt; k++) {
        free(job.pos[k]);
        free(job.v[k]);
    }
    return job.rc;
}

/* Vertex rate: more shading points inside the anchor pairs whose transmittance changes by more
 * than quality.shading_refine along the strand (sl_shade_points_refine), with their own T (and
 * B). 0, or -1 with e set. */
static int refine(sl_renderer *r, const sl_scene *s, const sl_hair *h, const sl_kbuf_view *kb,
                  sl_err *e) {
    sl_frame_work *w = &r->fw;
    sl_shade_points *pts = &w->pts;
    r->refined = 0;
    if (r->rate_k < 1 || !(s->shading_refine > 1) || !w->nused) return 0;
    const size_t n0 = pts->n;
    /* the sharp lobes' T is each entry's own: it needs no points in between */
    double *share = sl_malloc(((size_t)w->nused + 1) * sizeof *share);
    for (int j = 0; j < w->nused; j++)
        share[j] = sl_shade_sharp_slot(pts, j) >= 0 ? 0.0 : w->share[j];
    const size_t add = sl_shade_points_refine(h, kb, r->rate_k, &w->sm, pts, pts->T, w->nused,
                                              share, s->shading_refine);
    free(share);
    if (!add) return 0;
    float *T = NULL, *B = NULL;
    if (lobe_sums(r, add, pts->pos + 3 * n0, w->nused, &T, pts->B ? &B : NULL, e)) return -1;
    append_lobe_rows(&pts->T, T, w->nused, n0, add);
    if (B) append_lobe_rows(&pts->B, B, w->nused, n0, add);
    free(T);
    free(B);
    pts->out = sl_realloc(pts->out, (pts->n * sl_shade_stride(pts) + 1) * sizeof *pts->out);
    r->refined = add;
    return 0;
}

int sl_pass_lookup(sl_renderer *r, const sl_frame_inputs *in, sl_err *e) {
    const sl_hair *h = in->h;
    sl_frame_work *w = &r->fw;
    sl_shade_points *pts = &w->pts;
    sl_shade_map *sm = &w->sm;
    int nused = w->nused;
    r->rate_k = shading_rate(r, in->s);
    sm->strand_of = sl_malloc((h->num_points ? h->num_points : 1) * sizeof *sm->strand_of);
    for (uint32_t st = 0; st < h->num_strands; st++)
        for (uint32_t i = h->strand_first[st]; i < h->strand_first[st + 1]; i++)
            sm->strand_of[i] = st;
    sl_kbuf_view kb = sl_frame_kbuf(r);
    sl_shade_points_build(h, &kb, r->rate_k, sm, pts);
    /* T_j toward each lobe; with MS, the optical depth of the hair behind each point too (the
     * stack of the local backscattering, docs/volume.md) */
    if (lobe_sums_unique(r, pts, nused, &pts->T, r->ms_on ? &pts->B : NULL, e)) return -1;
    if (sharp_lobes(r, in->s, h, &kb, e)) return -1;
    pts->out = sl_malloc((pts->n * sl_shade_stride(pts) + 1) * sizeof *pts->out);
    if (refine(r, in->s, h, &kb, e)) return -1;
    if (r->ms_on && r->have_vol && r->ftex.nlobes == nused &&
        (!r->ftex.tau || r->tau_light_key != r->key[SL_PASSID_LIGHT])) {
        /* the same maps' optical depth at the march's vertices, for the depth-guided T_f
         * (sl_ftex_lookup_guided): once per new maps or march (a new march starts without
         * it), not every frame of an orbit */
        size_t nv = (size_t)r->ftex.m[0] * r->ftex.m[1] * r->ftex.m[2];
        double *vp = sl_ftex_vertex_positions(&r->ftex);
        float *vT = NULL;
        int rc = lobe_sums(r, nv, vp, nused, &vT, NULL, e);
        free(vp);
        if (rc) return -1;
        sl_ftex_set_tau(&r->ftex, vT);
        r->tau_light_key = r->key[SL_PASSID_LIGHT];
        free(vT);
    }
    char refined[120] = "";
    if (r->refined)
        snprintf(refined, sizeof refined,
                 " (%zu inside segments whose T changes by more than %gx, quality.shading_refine)",
                 r->refined, in->s->shading_refine);
    char sharp[160] = "";
    if (pts->nsharp)
        snprintf(
            sharp, sizeof sharp,
            "; %zu visible fragments toward %d sharp lobe%s (lambda %.3g%s, quality.sharp_shadows)",
            pts->nentries, pts->nsharp, pts->nsharp > 1 ? "s" : "",
            w->fl->lobe[w->used[pts->sharp[0]]].lambda, pts->nsharp > 1 ? ", ..." : "");
    sl_frame_why(r, "transmittance of %zu shading points%s toward %d lobes%s%s", pts->n, refined,
                 nused, r->ms_on ? ", and the hair behind them" : "", sharp);
    return 0;
}

int sl_pass_shade(sl_renderer *r, const sl_frame_inputs *in, sl_err *e) {
    const sl_scene *s = in->s;
    const sl_frame_work *w = &r->fw;
    sl_shade_points *pts = &r->fw.pts;
    sl_shade_ctx sc = {&s->material,
                       w->fl,
                       w->used,
                       w->nused,
                       w->share,
                       in->cam,
                       r->ms_on,
                       &r->ftex,
                       &r->vms,
                       s->point_threshold,
                       r->strand_sigma_a,
                       r->have_msn ? &r->msn : NULL,
                       NULL,
                       NULL};
    sl_dual_stack stack[3];
    if (r->ms_on && pts->B && r->dual_ok) { /* the march's tables: the strands' mean sigma_a */
        for (int c = 0; c < 3; c++) {
            double rr, tt, Ab;
            sl_dual_means(&r->dual, c, &rr, &tt, &Ab);
            sl_dual_stack_init(rr, tt, Ab, &stack[c]);
        }
        sc.stack = stack;
    }
    if (r->ms_on && r->dual_ok) sc.deflect = &r->deflect;
    if (sl_frame_shade(r, &sc, pts, e)) return -1;
    double lobes_eval = 0;
    for (size_t i = 0; i < pts->n; i++)
        lobes_eval += pts->out[sl_shade_stride(pts) * i + 13];
    char ratebuf[48];
    if (r->rate_k == 0)
        snprintf(ratebuf, sizeof ratebuf, "fragment");
    else
        snprintf(ratebuf, sizeof ratebuf, "vertex:%d", r->rate_k);
    sl_frame_why(
        r,
        "rate %s (%s; median segment %.2f px): %zu points, %.0f lobe evaluations "
        "(%.1f per point, quality.point_threshold %.3g)%s, SRBF %s on %s",
        ratebuf,
        strcmp(s->shading_rate, "auto") ? "quality.shading_rate" : "auto, quality.auto_fragment_px",
        r->view.seg_px_median, pts->n, lobes_eval, pts->n ? lobes_eval / pts->n : 0.0,
        s->point_threshold, r->strand_sigma_a ? ", per-strand sigma_a" : "",
        sl_render_method_name(r->srbf_used),
        sl_frame_srbf_on_device(r) ? "OpenCL"
        : r->dev->is_opencl ? "C (auto picked a CPU OpenCL device; the C twin is faster there)"
                            : "C");
    return 0;
}
