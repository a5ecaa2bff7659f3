/* shadow_cl.c: the light pass on OpenCL (shadow_internal.h): buffers, the raster and DODM
 * drivers' launches, lookups and read-backs of the maps the device keeps. */
#include "passes/light/shadow_internal.h"

#include "../kernels/dodm.h"
#include "../kernels/raster.h"
#include "passes/light/dodm_cl.h"
#include "passes/light/raster_cl.h"

#include <string.h>

void slcl_shadow_group_release(struct sl_shadow_group *g) {
    cl_mem *ms[] = {&g->bz, &g->bs, &g->bviews, &g->bparams};
    for (int i = 0; i < 4; i++)
        if (*ms[i]) clReleaseMemObject(*ms[i]), *ms[i] = NULL;
}

static cl_mem upload(sl_cl *cl, const void *p, size_t bytes, const char *what, sl_err *e) {
    cl_int err;
    static const char zero[16];
    cl_mem m = clCreateBuffer(sl_cl_context(cl), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                              bytes ? bytes : sizeof zero, bytes ? (void *)p : (void *)zero, &err);
    if (err != CL_SUCCESS) {
        sl_cl_check(err, what, e);
        return NULL;
    }
    return m;
}

int slcl_shadow_build(sl_cl *cl, const sl_hair *h, const prep *p, sl_shadow_batch *b, sl_err *e) {
    cl_context ctx = sl_cl_context(cl);
    const int w = b->map[0].view.w, hh = b->map[0].view.h;
    const size_t plane = (size_t)w * hh;
    const unsigned K = b->map[0].K;
    const unsigned nmax = b->n < SL_SHADOW_BATCH ? (unsigned)b->n : SL_SHADOW_BATCH;
    cl_int err;
    cl_mem bpos = NULL, bseg = NULL, bhw = NULL, brec = NULL, bd = NULL;
    int rc = -1;
    sl_cl_timer t;
    sl_cl_timer_start(&t, cl);
    double t0 = sl_now();
    if (!(bpos =
              upload(cl, h->pos, 3 * (size_t)h->num_points * sizeof(float), "shadow: points", e)) ||
        !(bseg = upload(cl, p->seg, p->nseg * sizeof *p->seg, "shadow: segments", e)) ||
        !(bhw = upload(cl, p->hw, p->nseg * sizeof *p->hw, "shadow: widths", e)))
        goto done;
    brec =
        clCreateBuffer(ctx, CL_MEM_READ_WRITE,
                       (p->nseg ? p->nseg : 1) * nmax * SL_RASTER_REC * sizeof(float), NULL, &err);
    if (sl_cl_check(err, "shadow: clCreateBuffer(records)", e)) goto done;
    b->upload_s = sl_now() - t0;
    for (int gi = 0; gi < b->ngroups; gi++) {
        struct sl_shadow_group *g = &b->group[gi];
        float d[SL_SHADOW_BATCH];
        for (unsigned l = 0; l < g->nl; l++)
            d[l] = g->params[l * SL_DODM_PARAMS];
        if (bd) clReleaseMemObject(bd);
        bd = NULL;
        if (!(g->bviews = upload(cl, g->views, g->nl * SL_RASTER_VIEW * sizeof(float),
                                 "shadow: views", e)) ||
            !(g->bparams = upload(cl, g->params, g->nl * SL_DODM_PARAMS * sizeof(float),
                                  "shadow: parameters", e)) ||
            !(bd = upload(cl, d, g->nl * sizeof(float), "shadow: layer depths", e)))
            goto done;
        g->bz = clCreateBuffer(ctx, CL_MEM_READ_WRITE, g->nl * plane * sizeof(cl_uint), NULL, &err);
        if (sl_cl_check(err, "shadow: clCreateBuffer(z0)", e)) goto done;
        g->bs = clCreateBuffer(ctx, CL_MEM_READ_WRITE, (size_t)g->nl * K * plane * sizeof(cl_ulong),
                               NULL, &err);
        if (sl_cl_check(err, "shadow: clCreateBuffer(tables)", e)) goto done;
        sl_cl_timer_start(&t, cl);
        rc = slcl_raster_project_buf(cl, bpos, bseg, bhw, g->bviews, p->nseg, g->nl,
                                     (float)p->scale, brec, &t, e);
        b->project_s += sl_cl_timer_stop(&t, NULL);
        if (rc) goto done;
        sl_cl_timer_start(&t, cl);
        rc = slcl_raster_buf(cl, brec, p->nseg, g->nl, w, hh, K, bd, p->z0_radius, p->z0_frac,
                             g->bz, g->bs, &t, e);
        b->raster_s += sl_cl_timer_stop(&t, NULL);
        if (rc) goto done;
        sl_cl_timer_start(&t, cl);
        rc = slcl_dodm_tables_buf(cl, g->bs, w, hh, K, g->nl, &t, e);
        b->tables_s += sl_cl_timer_stop(&t, NULL);
        if (rc) goto done;
    }
    rc = 0;
done:
    if (bpos) clReleaseMemObject(bpos);
    if (bseg) clReleaseMemObject(bseg);
    if (bhw) clReleaseMemObject(bhw);
    if (brec) clReleaseMemObject(brec);
    if (bd) clReleaseMemObject(bd);
    return rc;
}

int slcl_shadow_lookup(const sl_shadow_batch *b, size_t n, const float *pts, const uint32_t *lb,
                       size_t nout, float *t, sl_err *e) {
    const int w = b->map[0].view.w, hh = b->map[0].view.h;
    const unsigned K = b->map[0].K;
    sl_cl *cl = b->cl;
    cl_int err;
    cl_mem bp = NULL, bl = NULL, bt = NULL;
    int rc = -1;
    if (!(bp = upload(cl, pts, 3 * n * sizeof *pts, "shadow: lookup points", e))) goto done;
    if (lb && !(bl = upload(cl, lb, n * sizeof *lb, "shadow: lookup lobes", e))) goto done;
    bt = clCreateBuffer(sl_cl_context(cl), CL_MEM_WRITE_ONLY, nout * sizeof *t, NULL, &err);
    if (sl_cl_check(err, "shadow: clCreateBuffer(T)", e)) goto done;
    for (int gi = 0; gi < b->ngroups; gi++) {
        const struct sl_shadow_group *g = &b->group[gi];
        if (slcl_dodm_lookup_lobes_buf(cl, g->bz, g->bs, w, hh, K, g->bparams, g->bviews, bp, bl, n,
                                       g->nl, g->l0, (size_t)b->n, bt, NULL, e))
            goto done;
    }
    if (sl_cl_check(clEnqueueReadBuffer(sl_cl_queue(cl), bt, CL_TRUE, 0, nout * sizeof *t, t, 0,
                                        NULL, NULL),
                    "shadow: read T", e))
        goto done;
    rc = 0;
done:
    if (bp) clReleaseMemObject(bp);
    if (bl) clReleaseMemObject(bl);
    if (bt) clReleaseMemObject(bt);
    return rc;
}

int slcl_shadow_read(const sl_shadow_batch *b, const struct sl_shadow_group *g, unsigned l,
                     uint32_t *z0bits, uint64_t *sat, sl_err *e) {
    const int j = (int)(g->l0 + l);
    const unsigned K = b->map[j].K;
    const size_t plane = (size_t)b->map[j].view.w * b->map[j].view.h;
    cl_command_queue q = sl_cl_queue(b->cl);
    if (sl_cl_check(clEnqueueReadBuffer(q, g->bz, CL_TRUE, l * plane * sizeof(cl_uint),
                                        plane * sizeof(cl_uint), z0bits, 0, NULL, NULL),
                    "shadow: read z0", e) ||
        sl_cl_check(clEnqueueReadBuffer(q, g->bs, CL_TRUE, (size_t)l * K * plane * sizeof(cl_ulong),
                                        K * plane * sizeof(cl_ulong), sat, 0, NULL, NULL),
                    "shadow: read tables", e))
        return -1;
    return 0;
}
