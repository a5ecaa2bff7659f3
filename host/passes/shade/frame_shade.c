/* frame_shade.c: the shading pass of the frame (frame_shade.h): per shading point, the sum over the
 * used lobes of the SRBF single-scattering response (Xu 2011 Eq. 11; kernels/srbf_fast.h or
 * srbf_xu.h) times the effective transmittance toward the lobe (Ren 2010 Eq. 9, from the light
 * pass), plus multiple scattering: T_f, sigma_f of the volume march (host/passes/volume/volume.h)
 * and the response per fragment and lobe of host/passes/volume/volume_ms.h (Xu 2011 Eq. 27-31).
 * Radiance L = sum_j rgb_j T_j I_j (numerics.md sec. 4: the map is sum_j rgb_j G_j). Rows (point,
 * lobe) are evaluated in blocks, all three colour channels in one RGB batch (slc_srbf_rgb_batch /
 * slcl_srbf_rgb_batch: only the absorption differs between channels, so the rest is computed once),
 * or, when the planner chose Ren 2010's precomputed table (env->table, docs/frame.md "SRBF
 * method"), by table lookups (slc_srbf_ren_batch / srbf_ren.cl with the table resident). Each row
 * carries its point's sigma_a: the strand's override (c->strand_sigma_a, painted or from the file's
 * colours) or the material's; the table holds the material's only, so rows of strands with another
 * sigma_a use the closed form. C path: each thread shades a contiguous range of points end to end
 * (rows, response, multiple scattering, accumulation). OpenCL: blocks in turn, one launch per
 * block. */
#include "passes/shade/frame_shade.h"

#include "base/parallel.h"
#include "srbf_c.h"
#include "srbf_deon_c.h"
#include "passes/shade/srbf_deon_cl.h"
#include "passes/shade/srbf_cl.h"
#include "passes/shade/srbf_ren.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CHUNK_POINTS 4096

/* Angles of world direction d in the fiber frame u (tangent), v, w (numerics.md sec. 1). */
static void angles(const float u[3], const float v[3], const float w[3], const double d[3],
                   float *theta, float *phi) {
    double su = d[0] * u[0] + d[1] * u[1] + d[2] * u[2];
    double sv = d[0] * v[0] + d[1] * v[1] + d[2] * v[2];
    double sw = d[0] * w[0] + d[1] * w[1] + d[2] * w[2];
    su = su > 1 ? 1 : (su < -1 ? -1 : su);
    *theta = (float)asin(su);
    *phi = (float)atan2(sw, sv);
}

/* v: a normal of u from a fixed world axis (deterministic), w = u x v. */
static void fiber_frame(const float u[3], float v[3], float w[3]) {
    float ref[3] = {0, 1, 0};
    if (fabsf(u[1]) > 0.9f) ref[0] = 1, ref[1] = 0;
    float ru = ref[0] * u[0] + ref[1] * u[1] + ref[2] * u[2], l = 0;
    for (int k = 0; k < 3; k++) {
        v[k] = ref[k] - ru * u[k];
        l += v[k] * v[k];
    }
    l = sqrtf(l);
    for (int k = 0; k < 3; k++)
        v[k] /= l;
    w[0] = u[1] * v[2] - u[2] * v[1];
    w[1] = u[2] * v[0] - u[0] * v[2];
    w[2] = u[0] * v[1] - u[1] * v[0];
}

int sl_shade_on_device(const sl_device *dev) {
    /* Under --device auto on a CPU OpenCL device (PoCL), the C twin of the SRBF response runs
     * 2-3x faster than PoCL's build of srbf.cl on the same cores (docs/performance.md), so
     * the planner keeps it on C; an explicitly chosen device is always used. */
    if (!dev->is_opencl) return 0;
    return !(sl_device_may_fallback(dev) && !sl_cl_is_gpu(dev->cl));
}

/* Rows of one block of shading points: the inputs of every (point, lobe) row (in: 5 floats,
 * sig: 3, rpt / rlobe: its point and used-lobe index) and their results (res: R, TT, TRT rgb).
 * With the table on, the rows whose sigma_a is the material's are also gathered into tin (tidx:
 * their row), the others (painted strands) into fin / fsig (fidx), each with its own results. */
typedef struct rowbuf {
    size_t cap, nr, nt, nf;
    float *in, *sig, *res;
    uint32_t *rpt;
    int *rlobe;
    float *tin, *tres, *fin, *fsig, *fres;
    uint32_t *tidx, *fidx;
} rowbuf;

static void rowbuf_init(rowbuf *b, size_t cap, int table) {
    memset(b, 0, sizeof *b);
    b->cap = cap ? cap : 1;
    b->in = sl_malloc(b->cap * 5 * sizeof *b->in);
    b->sig = sl_malloc(b->cap * 3 * sizeof *b->sig);
    b->res = sl_malloc(b->cap * 9 * sizeof *b->res);
    b->rpt = sl_malloc(b->cap * sizeof *b->rpt);
    b->rlobe = sl_malloc(b->cap * sizeof *b->rlobe);
    if (table) {
        b->tin = sl_malloc(b->cap * 5 * sizeof *b->tin);
        b->tres = sl_malloc(b->cap * 9 * sizeof *b->tres);
        b->tidx = sl_malloc(b->cap * sizeof *b->tidx);
        b->fin = sl_malloc(b->cap * 5 * sizeof *b->fin);
        b->fsig = sl_malloc(b->cap * 3 * sizeof *b->fsig);
        b->fres = sl_malloc(b->cap * 9 * sizeof *b->fres);
        b->fidx = sl_malloc(b->cap * sizeof *b->fidx);
    }
}

static void rowbuf_free(rowbuf *b) {
    free(b->in);
    free(b->sig);
    free(b->res);
    free(b->rpt);
    free(b->rlobe);
    free(b->tin);
    free(b->tres);
    free(b->tidx);
    free(b->fin);
    free(b->fsig);
    free(b->fres);
    free(b->fidx);
}

/* What every block of one frame shares. */
typedef struct shade_common {
    const sl_shade_env *env;
    const sl_shade_ctx *c;
    sl_shade_points *p;
    sl_fiber_params fp; /* one parameter set: the channels differ only in sigma_a (per row) */
    float msig[3];
    const float *ssig;
    double share_sum;
    int table, method;
} shade_common;

/* Rows of points [i0, i1) into b (and each point's shadow and lobe count into p->out). */
static void build_rows(const shade_common *sc, size_t i0, size_t i1, rowbuf *b) {
    const sl_shade_ctx *c = sc->c;
    const sl_shade_points *p = sc->p;
    int L = c->nused;
    b->nr = b->nt = b->nf = 0;
    for (size_t i = i0; i < i1; i++) {
        const float *u = p->tan + 3 * i;
        float v[3], w[3];
        fiber_frame(u, v, w);
        double wo[3], l = 0;
        for (int k = 0; k < 3; k++) {
            wo[k] = c->cam->eye[k] - p->pos[3 * i + k];
            l += wo[k] * wo[k];
        }
        l = sqrt(l);
        for (int k = 0; k < 3; k++)
            wo[k] /= l > 0 ? l : 1;
        float th_o, ph_o;
        angles(u, v, w, wo, &th_o, &ph_o);
        const float *ps = sc->ssig ? sc->ssig + 3 * (size_t)p->strand[i] : sc->msig;
        int own = ps[0] == sc->msig[0] && ps[1] == sc->msig[1] && ps[2] == sc->msig[2];
        double shadow = 0;
        int count = 0;
        for (int j = 0; j < L; j++) {
            /* a sharp lobe's T is the entry's (sl_shade_entry): its row counts at T = 1 */
            const int sharp = sl_shade_sharp_slot(p, j) >= 0;
            float T = sharp ? 1.0f : p->T[(size_t)j * p->n + i];
            if (!sharp) shadow += c->share[j] * T;
            if (T * c->share[j] < c->point_threshold * sc->share_sum) continue;
            const sl_lobe *lb = &c->lobes->lobe[c->used[j]];
            float th_j, ph_j;
            angles(u, v, w, lb->dir, &th_j, &ph_j);
            size_t nr = b->nr;
            float *x = b->in + 5 * nr;
            x[0] = th_o, x[1] = ph_o, x[2] = th_j, x[3] = ph_j, x[4] = (float)lb->lambda;
            memcpy(b->sig + 3 * nr, ps, 3 * sizeof *ps);
            if (sc->table && own) {
                memcpy(b->tin + 5 * b->nt, x, 5 * sizeof *x);
                b->tidx[b->nt++] = (uint32_t)nr;
            } else if (sc->table) {
                memcpy(b->fin + 5 * b->nf, x, 5 * sizeof *x);
                memcpy(b->fsig + 3 * b->nf, ps, 3 * sizeof *ps);
                b->fidx[b->nf++] = (uint32_t)nr;
            }
            b->rpt[nr] = (uint32_t)i;
            b->rlobe[nr] = j;
            b->nr++, count++;
        }
        float *out = p->out + sl_shade_stride(p) * i;
        out[12] = sc->share_sum > 0 ? (float)(shadow / sc->share_sum) : 1.0f;
        out[13] = (float)count;
    }
}

/* The closed-form RGB response of n rows on the C twins: Marschner (fast or xu) or, for models
 * deon and chiang, the d'Eon fast path (kernels/srbf_deon.h, srbf_chiang.h; 9 floats per row:
 * order 0, order 1, orders >= 2 + rest, as R, TT, TRT). */
static void closed_form_c(const shade_common *sc, size_t n, const float *in, const float *sig,
                          float *res) {
    const sl_shade_env *r = sc->env;
    if (sc->fp.model != SL_MODEL_MARSCHNER)
        slc_srbf_deon_rgb_batch(&sc->fp, r->tables->C, r->tables->H, r->tables->D, n, in, sig, res);
    else
        slc_srbf_rgb_batch(&sc->fp, r->tables->C, r->tables->H, sc->method, r->segments, n, in, sig,
                           res);
}

/* The SRBF response of b's rows on the C twins, in this thread. */
static void eval_rows_c(const shade_common *sc, rowbuf *b) {
    const sl_shade_env *r = sc->env;
    if (!sc->table) {
        closed_form_c(sc, b->nr, b->in, b->sig, b->res);
        return;
    }
    if (b->nf) closed_form_c(sc, b->nf, b->fin, b->fsig, b->fres);
    if (b->nt) slc_srbf_ren_batch(r->ren, b->nt, b->tin, b->tres);
}

/* Table lookups of n rows on the OpenCL device, the table resident (uploaded once per table, kept
 * in env->ren_mem); rows and results travel per block. Returns 0, -1 or SL_CL_EKERNEL. */
static int ren_cl(const sl_shade_env *r, size_t n, const float *in, float *out, sl_err *e) {
    return slcl_srbf_ren_rows(r->dev->cl, r->ren, r->ren_mem, "clCreateBuffer (srbf table)", n, in,
                              out, e);
}

/* The SRBF response of b's rows on the OpenCL device (the caller falls back to eval_rows_c when
 * the device may and this fails). Returns 0, -1 or SL_CL_EKERNEL. */
static int eval_rows_cl(const shade_common *sc, rowbuf *b, sl_err *e) {
    const sl_shade_env *r = sc->env;
    const float *cin = sc->table ? b->fin : b->in, *csig = sc->table ? b->fsig : b->sig;
    float *cres = sc->table ? b->fres : b->res;
    size_t nc = sc->table ? b->nf : b->nr;
    int k = 0;
    if (nc && sc->fp.model != SL_MODEL_MARSCHNER)
        k = slcl_srbf_deon_rgb_batch(r->dev->cl, &sc->fp, r->tables, nc, cin, csig, cres, e);
    else if (nc)
        k = slcl_srbf_rgb_batch(r->dev->cl, &sc->fp, r->tables, sc->method, r->segments, nc, cin,
                                csig, cres, e);
    if (!k && sc->table && b->nt) k = ren_cl(r, b->nt, b->tin, b->tres, e);
    return k;
}

/* M^G and M^L of one row x (theta_o, phi_o, theta_j, phi_j, lambda) at spread sf: from the
 * strand's sigma_a nodes (sa) or the material's table (sa NULL). */
static void ms_terms(const sl_shade_ctx *c, const float *sa, const float *x, const float sf[3],
                     float MG[3], float ML[3]) {
    if (sa)
        sl_volume_ms_nodes_terms(c->msn, sa, x[0], x[1], x[2], x[3], x[4], sf, MG, ML);
    else
        sl_volume_ms_terms(c->vms, x[0], x[1], x[2], x[3], x[4], sf, MG, ML);
}

/* M^G, M^G of the interreflected light (MGi) and M^L of row x (lobe j, point at cn) with the
 * spreads of docs/volume.md "Where the scattered light goes": the march's sigma_f widened by
 * the tilt of the fibers the light crossed (kf tilt2), the local term by the tilts of the fiber
 * and those behind it (kb 2 dev2), the interreflected light by two backscatterings (2 (sb2 + kb
 * 2 dev2)); each scaled to carry the energy of the march's own spread (sl_dual_deflect_norm). */
static void ms_spread_terms(const sl_shade_ctx *c, const float *sa, const float *x,
                            const sl_ftex_corners *cn, int j, const float sf[3],
                            const float dev2[3], int need, float MG[3], float MGi[3], float ML[3]) {
    const sl_dual_deflect *d = c->deflect;
    float tilt2[3], sg[3], sl[3], si[3], unused[3];
    sl_ftex_tilt_at(c->ftex, j, cn, tilt2);
    for (int col = 0; col < 3; col++) {
        float g2 = sf[col] * sf[col] + d->kf[col] * tilt2[col];
        float loc = d->kb[col] * 2.0f * dev2[col]; /* two fibers' tilts */
        sg[col] = sqrtf(g2);
        sl[col] = sqrtf(g2 + loc);
        si[col] = sqrtf(g2 + 2.0f * (d->sb2[col] + loc));
    }
    if (sa) {
        ms_terms(c, sa, x, sg, MG, unused);
        ms_terms(c, sa, x, sl, unused, ML);
        ms_terms(c, sa, x, si, MGi, unused);
    } else {
        sl_volume_ms_terms_spread(c->vms, x[0], x[1], x[2], x[3], x[4], sg, si, sl, need, MG, MGi,
                                  ML);
    }
    float l2 = x[4] * x[4];
    for (int col = 0; col < 3; col++) {
        float n0 = sl_dual_deflect_norm(x[2], sqrtf(l2 + sf[col] * sf[col]));
        MG[col] *= n0 / sl_dual_deflect_norm(x[2], sqrtf(l2 + sg[col] * sg[col]));
        ML[col] *= n0 / sl_dual_deflect_norm(x[2], sqrtf(l2 + sl[col] * sl[col]));
        MGi[col] *= n0 / sl_dual_deflect_norm(x[2], sqrtf(l2 + si[col] * si[col]));
    }
}

/* Adds b's rows (SRBF x transmittance x lobe power, plus multiple scattering) into p->out. */
static void accumulate(const shade_common *sc, rowbuf *b) {
    const sl_shade_ctx *c = sc->c;
    const sl_shade_points *p = sc->p;
    if (sc->table) {
        for (size_t k = 0; k < b->nt; k++)
            memcpy(b->res + 9 * (size_t)b->tidx[k], b->tres + 9 * k, 9 * sizeof *b->res);
        for (size_t k = 0; k < b->nf; k++)
            memcpy(b->res + 9 * (size_t)b->fidx[k], b->fres + 9 * k, 9 * sizeof *b->res);
    }
    sl_ftex_corners cn; /* where point i reads the lobes' T_f textures: rows of a point are */
    size_t cn_pt = (size_t)-1; /* consecutive, so once per point */
    float dev2[3];             /* the fibers' spread around point dev2_pt (with deflect) */
    size_t dev2_pt = (size_t)-1;
    for (size_t k = 0; k < b->nr; k++) {
        size_t i = b->rpt[k];
        int j = b->rlobe[k];
        const sl_lobe *lb = &c->lobes->lobe[c->used[j]];
        float T = p->T[(size_t)j * p->n + i];
        float *out = p->out + sl_shade_stride(p) * i;
        float ms[3] = {0, 0, 0};
        const int slot = sl_shade_sharp_slot(p, j);
        /* a sharp lobe's row is there for its single scattering whatever the point's T; its
         * multiple scattering keeps the rule of the others (T_j share_j >= point_threshold) */
        const int ms_row = slot < 0 || T * c->share[j] >= c->point_threshold * sc->share_sum;
        if (c->ms_on && ms_row) {
            float Tf[3], sf[3], f[3] = {1.0f, 1.0f, 1.0f};
            if (cn_pt != i) sl_ftex_at(c->ftex, p->pos + 3 * i, &cn), cn_pt = i;
            sl_ftex_lookup_guided(c->ftex, j, &cn, sl_ftex_tau_of(T), Tf, sf);
            const float *x = b->in + 5 * k;
            const float *sa = sc->ssig && c->msn ? sc->ssig + 3 * (size_t)p->strand[i] : NULL;
            if (!(sa && (sa[0] != sc->msig[0] || sa[1] != sc->msig[1] || sa[2] != sc->msig[2])))
                sa = NULL; /* the material's own sigma_a: its table */
            float MG[3], ML[3], MGi[3], lf[3] = {1.0f, 1.0f, 1.0f};
            if (c->stack && p->B) {
                float nb = p->B[(size_t)j * p->n + i];
                double nf = T > 1e-30f ? -log((double)T) : 69.0;
                for (int col = 0; col < 3; col++) {
                    lf[col] = (float)sl_dual_stack_local_factor(&c->stack[col], nb);
                    f[col] = (float)sl_dual_stack_incident_factor(&c->stack[col], nf, nb);
                }
            }
            if (c->deflect) {
                /* light arriving unscattered (T_f f <= T_j) needs no M^G, no interreflection
                 * (f <= 1) no M^Gi */
                int need = sl_volume_ms_split_need(Tf, f, T);
                if (dev2_pt != i) sl_ftex_dev2_at(c->ftex, &cn, dev2), dev2_pt = i;
                ms_spread_terms(c, sa, x, &cn, j, sf, dev2, need, MG, MGi, ML);
            } else {
                ms_terms(c, sa, x, sf, MG, ML);
                memcpy(MGi, MG, sizeof MG);
            }
            for (int col = 0; col < 3; col++)
                ML[col] *= lf[col];
            sl_volume_ms_combine_split(x[4], Tf, f, T, MG, MGi, ML, ms);
        }
        const float *o = b->res + 9 * k; /* R rgb, TT rgb, TRT rgb */
        /* a sharp lobe's single scattering goes to its slot without T: each K-buffer entry
         * multiplies it by its own (sl_shade_entry) */
        float *so = slot < 0 ? out : out + SL_SHADE_BASE_FLOATS + 9 * slot;
        const float Ts = slot < 0 ? T : 1.0f;
        for (int col = 0; col < 3; col++) {
            float g = (float)lb->rgb[col] * Ts;
            so[0 + col] += g * o[col];
            so[3 + col] += g * o[3 + col];
            so[6 + col] += g * o[6 + col];
            out[9 + col] += (float)lb->rgb[col] * ms[col]; /* ms includes the power */
        }
    }
}

/* C path: each thread shades its own contiguous range of points, block by block (rows, SRBF,
 * multiple scattering, accumulation): every output belongs to one point, so the threads never
 * write the same memory, and a point's rows are evaluated alike whatever the split (the batches
 * are row-independent), so the frame does not depend on the thread count. */
typedef struct shade_job {
    const shade_common *sc;
    size_t i0; /* the first point of the range split into parts */
} shade_job;

static void shade_part(void *arg, size_t begin, size_t end, int part) {
    (void)part;
    const shade_job *j = arg;
    const shade_common *sc = j->sc;
    const size_t i1 = j->i0 + end;
    int L = sc->c->nused;
    rowbuf b;
    rowbuf_init(&b, (size_t)CHUNK_POINTS * (L ? L : 1), sc->table);
    for (size_t p0 = j->i0 + begin; p0 < i1; p0 += CHUNK_POINTS) {
        size_t p1 = p0 + CHUNK_POINTS < i1 ? p0 + CHUNK_POINTS : i1;
        build_rows(sc, p0, p1, &b);
        eval_rows_c(sc, &b);
        accumulate(sc, &b);
    }
    rowbuf_free(&b);
}

static void shade_c(const sl_shade_env *env, const shade_common *sc, size_t i0, size_t i1) {
    enum { MAXT = 16 };
    int nt = env->threads;
    if (nt > MAXT) nt = MAXT;
    if (i1 - i0 < 64) nt = 1;
    shade_job job = {sc, i0};
    sl_parallel_parts(nt, i1 - i0, shade_part, &job);
}

int sl_shade_run(const sl_shade_env *env, const sl_shade_ctx *c, sl_shade_points *p, sl_err *e) {
    shade_common sc;
    memset(&sc, 0, sizeof sc);
    sc.env = env;
    sc.c = c;
    sc.p = p;
    sl_material_to_fiber(c->mat, 0, &sc.fp);
    for (int k = 0; k < 3; k++)
        sc.msig[k] = (float)c->mat->sigma_a[k];
    sc.ssig = p->strand ? c->strand_sigma_a : NULL;
    for (int j = 0; j < c->nused; j++)
        sc.share_sum += c->share[j];
    /* the table (env->table, the planner's choice): rows whose sigma_a is the material's come
     * from it, the rest (painted strands) from the closed form */
    sc.table = env->table;
    sc.method = env->method;
    memset(p->out, 0, p->n * sl_shade_stride(p) * sizeof *p->out);
    if (!env->on_device || !env->dev->is_opencl) {
        shade_c(env, &sc, 0, p->n);
        return 0;
    }
    /* OpenCL: blocks of points in turn, each block's rows in one launch; on a failure the
     * device may fall back from, the rest (this block included) runs on the C path */
    int L = c->nused, rc = 0;
    rowbuf b;
    rowbuf_init(&b, (size_t)CHUNK_POINTS * (L ? L : 1), sc.table);
    size_t p0 = 0;
    for (; p0 < p->n; p0 += CHUNK_POINTS) {
        size_t p1 = p0 + CHUNK_POINTS < p->n ? p0 + CHUNK_POINTS : p->n;
        build_rows(&sc, p0, p1, &b);
        int k = eval_rows_cl(&sc, &b, e);
        if (k) {
            if (!sl_device_try_fallback(env->dev, k, e)) rc = -1;
            break;
        }
        accumulate(&sc, &b);
    }
    rowbuf_free(&b);
    if (!rc && p0 < p->n) shade_c(env, &sc, p0, p->n);
    return rc;
}
