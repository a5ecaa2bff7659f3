/* frame_shade.c: the shading pass of the frame (frame.h): per shading point, the sum over the
 * used lobes of the SRBF single-scattering response (Xu 2011 Eq. 11; kernels/srbf_fast.h or
 * srbf_xu.h) times the effective transmittance toward the lobe (Ren 2010 Eq. 9, from the light
 * pass), plus multiple scattering: T_f, sigma_f of the volume march (host/volume.h) and the
 * response per fragment and lobe of host/volume_ms.h (Xu 2011 Eq. 27-31). Radiance L = sum_j rgb_j
 * T_j I_j (numerics.md sec. 4: the map is sum_j rgb_j G_j). Rows (point, lobe) are evaluated in
 * chunks, all three colour channels in one RGB batch (slc_srbf_rgb_batch / slcl_srbf_rgb_batch:
 * only the absorption differs between channels, so the rest is computed once), by the C twin in
 * threads or by the OpenCL kernel srbf_eval.cl. Each row carries its point's sigma_a: the
 * strand's override (c->strand_sigma_a, painted or from the file's colours) or the material's. */
#include "frame_internal.h"
#include "srbf_c.h"
#include "srbf_cl.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#define CHUNK_POINTS 4096

typedef struct sjob {
    const sl_fiber_params *fp;
    const sl_srbf_tables *t;
    int method, segments;
    size_t r0, r1;
    const float *in, *sig;
    float *out;
} sjob;

static void *srbf_thread(void *arg) {
    sjob *j = arg;
    slc_srbf_rgb_batch(j->fp, j->t->C, j->t->H, j->method, j->segments, j->r1 - j->r0,
                       j->in + 5 * j->r0, j->sig + 3 * j->r0, j->out + 9 * j->r0);
    return NULL;
}

static void srbf_c(const sl_renderer *r, const sl_fiber_params *fp, size_t n, const float *in,
                   const float *sig, float *out) {
    enum { MAXT = 16 };
    int nt = sl_frame_threads(r);
    if (nt > MAXT) nt = MAXT;
    if (n < 256) nt = 1;
    sjob job[MAXT];
    pthread_t tid[MAXT];
    int started[MAXT] = {0};
    for (int t = 0; t < nt; t++) {
        job[t] = (sjob){
            fp,  &r->tables, r->o.srbf_method, r->o.segments, n * t / nt, n * (t + 1) / nt, in,
            sig, out};
        started[t] = t > 0 && pthread_create(&tid[t], NULL, srbf_thread, &job[t]) == 0;
    }
    for (int t = 0; t < nt; t++)
        if (!started[t]) srbf_thread(&job[t]);
    for (int t = 1; t < nt; t++)
        if (started[t]) pthread_join(tid[t], NULL);
}

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

int sl_frame_srbf_on_device(const sl_renderer *r) {
    /* Under --device auto on a CPU OpenCL device (PoCL), the C twin of the SRBF response runs
     * 2-3x faster than PoCL's build of srbf_eval.cl on the same cores (docs/performance.md), so
     * the planner keeps it on C; an explicitly chosen device is always used. */
    if (!r->dev->is_opencl) return 0;
    return !(sl_device_may_fallback(r->dev) && !sl_cl_is_gpu(r->dev->cl));
}

int sl_frame_shade(sl_renderer *r, const sl_shade_ctx *c, sl_shade_points *p, sl_err *e) {
    /* one fiber parameter set: the channels differ only in sigma_a, which goes per row */
    sl_fiber_params fp;
    sl_material_to_fiber(c->mat, 0, &fp);
    const float msig[3] = {(float)c->mat->sigma_a[0], (float)c->mat->sigma_a[1],
                           (float)c->mat->sigma_a[2]};
    const float *ssig = p->strand ? c->strand_sigma_a : NULL;
    int L = c->nused;
    double share_sum = 0;
    for (int j = 0; j < L; j++)
        share_sum += c->share[j];
    size_t maxrows = (size_t)CHUNK_POINTS * (L ? L : 1);
    float *in = sl_malloc(maxrows * 5 * sizeof *in);
    float *sig = sl_malloc(maxrows * 3 * sizeof *sig);
    float *res = sl_malloc(maxrows * 9 * sizeof *res);
    uint32_t *rpt = sl_malloc(maxrows * sizeof *rpt);
    int *rlobe = sl_malloc(maxrows * sizeof *rlobe);
    memset(p->out, 0, p->n * SL_SHADE_FLOATS * sizeof *p->out);
    int rc = 0;
    int use_cl = sl_frame_srbf_on_device(r);
    for (size_t p0 = 0; p0 < p->n && !rc; p0 += CHUNK_POINTS) {
        size_t p1 = p0 + CHUNK_POINTS < p->n ? p0 + CHUNK_POINTS : p->n, nr = 0;
        for (size_t i = p0; i < p1; i++) {
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
            const float *ps = ssig ? ssig + 3 * (size_t)p->strand[i] : msig;
            double shadow = 0;
            int count = 0;
            for (int j = 0; j < L; j++) {
                float T = p->T[(size_t)j * p->n + i];
                shadow += c->share[j] * T;
                if (T * c->share[j] < c->point_threshold * share_sum) continue;
                const sl_lobe *lb = &c->lobes->lobe[c->used[j]];
                float th_j, ph_j;
                angles(u, v, w, lb->dir, &th_j, &ph_j);
                float *x = in + 5 * nr;
                x[0] = th_o, x[1] = ph_o, x[2] = th_j, x[3] = ph_j, x[4] = (float)lb->lambda;
                sig[3 * nr] = ps[0], sig[3 * nr + 1] = ps[1], sig[3 * nr + 2] = ps[2];
                rpt[nr] = (uint32_t)i;
                rlobe[nr] = j;
                nr++, count++;
            }
            p->out[SL_SHADE_FLOATS * i + 12] = share_sum > 0 ? (float)(shadow / share_sum) : 1.0f;
            p->out[SL_SHADE_FLOATS * i + 13] = (float)count;
        }
        if (nr) {
            int done = 0;
            if (use_cl && r->dev->is_opencl) {
                int k = slcl_srbf_rgb_batch(r->dev->cl, &fp, &r->tables, r->o.srbf_method,
                                            r->o.segments, nr, in, sig, res, e);
                if (k == 0)
                    done = 1;
                else if (!sl_device_try_fallback(r->dev, k, e)) {
                    rc = -1;
                    break;
                }
            }
            if (!done) srbf_c(r, &fp, nr, in, sig, res);
        }
        for (size_t k = 0; k < nr; k++) {
            size_t i = rpt[k];
            int j = rlobe[k];
            const sl_lobe *lb = &c->lobes->lobe[c->used[j]];
            float T = p->T[(size_t)j * p->n + i];
            float *out = p->out + SL_SHADE_FLOATS * i;
            float ms[3] = {0, 0, 0};
            if (c->ms_on) {
                float Tf[3], sf[3];
                sl_ftex_lookup(c->ftex, j, p->pos + 3 * i, Tf, sf);
                const float *x = in + 5 * k;
                sl_volume_ms_response(c->vms, x[0], x[1], x[2], x[3], x[4], Tf, sf, T, ms);
            }
            const float *o = res + 9 * k; /* R rgb, TT rgb, TRT rgb */
            for (int col = 0; col < 3; col++) {
                float g = (float)lb->rgb[col] * T;
                out[0 + col] += g * o[col];
                out[3 + col] += g * o[3 + col];
                out[6 + col] += g * o[6 + col];
                out[9 + col] += (float)lb->rgb[col] * ms[col]; /* ms includes the power */
            }
        }
    }
    free(in);
    free(sig);
    free(res);
    free(rpt);
    free(rlobe);
    return rc;
}
