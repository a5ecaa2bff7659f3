/* path_ref.c: see path_ref.h. */
#include "path_ref.h"

#include "base/parallel.h"
#include "fiber_bsdf.h"
#include "fiber_hit.h"
#include "path_rng.h"
#include "render_ref.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double dot3(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static int positive(const double v[3]) {
    return v[0] > 0 || v[1] > 0 || v[2] > 0;
}

/* Adds radiance `add` (already weighted) that scattered `events` times; the lobe split is the
 * first event's fractions frac[l][c] (f_p / f of the sampled direction). */
static void add_light(slref_path_out *o, int events, const double add[3], double frac[4][3]) {
    for (int c = 0; c < 3; c++) {
        if (!isfinite(add[c])) continue;
        o->rgb[c] += add[c];
        if (events == 1)
            o->direct[c] += add[c];
        else
            o->indirect[c] += add[c];
        for (int l = 0; l < SLREF_NLOBES; l++)
            o->lobes[l][c] += add[c] * frac[l][c];
    }
}

/* The light sample of one event at x (power heuristic against the fiber's density). */
static void light_sample(const slref_path_ctx *c, const slref_bsdf *b, const double fr[3][3],
                         const double x[3], const slref_hit *hit, int k, const double beta[3],
                         double frac[4][3], slref_rng *r, slref_path_out *o) {
    double u[4], l[3], le[3];
    for (int i = 0; i < 4; i++)
        u[i] = slref_rng_unit(r);
    double pl = slref_env_sample(c->env, u, l, le);
    if (!(pl > 0) || !positive(le)) return;
    double ti, pi_, f[3], lob[SLREF_NLOBES][3];
    slref_frame_angles(fr[0], fr[1], fr[2], l, &ti, &pi_);
    slref_bsdf_eval(b, ti, pi_, f, lob);
    if (!positive(f) || slref_rt_occluded(c->rt, x, l, hit->strand, hit->seg)) return;
    double pb = slref_bsdf_pdf(b, ti, pi_), wl = pl * pl / (pl * pl + pb * pb), add[3];
    for (int ch = 0; ch < 3; ch++)
        add[ch] = beta[ch] * f[ch] * le[ch] * wl / pl;
    if (k > 0) {
        add_light(o, k + 1, add, frac);
        return;
    }
    /* the first event: split by the lobes' own values */
    double own[4][3];
    for (int q = 0; q < SLREF_NLOBES; q++)
        for (int ch = 0; ch < 3; ch++)
            own[q][ch] = f[ch] > 0 ? lob[q][ch] / f[ch] : 0;
    add_light(o, 1, add, own);
}

void slref_path_trace(const slref_path_ctx *c, int px, int py, uint32_t sample, slref_path_out *o) {
    memset(o, 0, sizeof *o);
    o->z = INFINITY;
    const sl_camera *cam = c->cam;
    slref_rng r;
    slref_rng_seed(&r, c->seed, (uint64_t)py * (uint64_t)cam->width + (uint64_t)px, sample);
    double jx = slref_rng_unit(&r), jy = slref_rng_unit(&r);
    double org[3] = {cam->eye[0], cam->eye[1], cam->eye[2]}, d[3];
    slref_camera_ray(cam, px + jx, py + jy, d);
    slref_hit hit;
    if (!slref_rt_intersect(c->rt, org, d, INFINITY, &hit)) return;
    o->hit = 1;
    o->z = hit.t * dot3(d, cam->fwd);
    double beta[3] = {1, 1, 1}, frac[4][3] = {{0}};
    for (int k = 0;; k++) {
        if (k >= c->max_events) {
            o->capped = 1;
            break;
        }
        o->events = k + 1;
        double x[3], wo[3], fr[3][3], p0[3], rad, to, po;
        for (int i = 0; i < 3; i++)
            x[i] = org[i] + hit.t * d[i], wo[i] = -d[i];
        slref_rt_prim_info(c->rt, hit.prim, NULL, NULL, fr[0]);
        slref_fiber_frame(fr[0], fr[1], fr[2]);
        slref_rt_prim_axis(c->rt, hit.prim, hit.u, p0, &rad);
        double h = slref_fiber_offset(org, d, p0, fr[0], rad);
        slref_frame_angles(fr[0], fr[1], fr[2], wo, &to, &po);
        slref_bsdf b;
        sl_material own;
        slref_bsdf_init(&b, slref_strand_material(c->m, c->strand_sa, hit.strand, &own), to, po, h);
        light_sample(c, &b, (const double(*)[3])fr, x, &hit, k, beta, frac, &r, o);
        /* the fiber sample: the path's continuation, and the map seen along it */
        double ti, pi_, pb, f[3], lob[SLREF_NLOBES][3];
        if (!slref_bsdf_sample(&b, &r, &ti, &pi_, &pb)) break;
        slref_bsdf_eval(&b, ti, pi_, f, lob);
        if (k == 0)
            for (int q = 0; q < SLREF_NLOBES; q++)
                for (int ch = 0; ch < 3; ch++)
                    frac[q][ch] = f[ch] > 0 ? lob[q][ch] / f[ch] : 0;
        for (int ch = 0; ch < 3; ch++) {
            beta[ch] *= f[ch] / pb;
            if (!isfinite(beta[ch])) beta[ch] = 0;
        }
        if (!positive(beta)) break;
        double nd[3];
        slref_frame_dir(fr[0], fr[1], fr[2], ti, pi_, nd);
        slref_hit nh;
        if (!slref_rt_intersect_excl(c->rt, x, nd, INFINITY, hit.strand, hit.seg, &nh)) {
            double le[3], add[3];
            slref_env_radiance(c->env, nd, le);
            double pl = slref_env_pdf(c->env, nd), wb = pb * pb / (pb * pb + pl * pl);
            for (int ch = 0; ch < 3; ch++)
                add[ch] = beta[ch] * le[ch] * wb;
            add_light(o, k + 1, add, frac);
            break;
        }
        if (k + 1 >= c->rr_events) {
            double q = fmax(beta[0], fmax(beta[1], beta[2]));
            if (q < 1) {
                if (slref_rng_unit(&r) >= q) break;
                for (int ch = 0; ch < 3; ch++)
                    beta[ch] /= q;
            }
        }
        for (int i = 0; i < 3; i++)
            org[i] = x[i], d[i] = nd[i];
        hit = nh;
    }
}

void slref_path_accum_init(slref_path_accum *a, int w, int h) {
    size_t n = (size_t)w * h;
    memset(a, 0, sizeof *a);
    a->w = w, a->h = h;
    a->half[0] = sl_calloc(4 * n, sizeof(double));
    a->half[1] = sl_calloc(4 * n, sizeof(double));
    a->aov = sl_calloc(SLREF_PATH_AOV * n, sizeof(double));
    a->depth = sl_malloc(n * sizeof(float));
    for (size_t i = 0; i < n; i++)
        a->depth[i] = INFINITY;
    a->row_stats = sl_calloc(3 * (size_t)h, sizeof(long long));
}

void slref_path_accum_free(slref_path_accum *a) {
    free(a->half[0]);
    free(a->half[1]);
    free(a->aov);
    free(a->depth);
    free(a->row_stats);
    memset(a, 0, sizeof *a);
}

typedef struct pass_job {
    const slref_path_ctx *c;
    slref_path_accum *a;
    uint32_t sample;
    const volatile sig_atomic_t *cancel;
    volatile int stopped;
} pass_job;

static void pass_rows(void *arg, size_t y0, size_t y1, int worker) {
    (void)worker;
    pass_job *j = arg;
    slref_path_accum *a = j->a;
    double *half = a->half[j->sample & 1];
    for (size_t y = y0; y < y1; y++) {
        if (j->cancel && *j->cancel) {
            j->stopped = 1;
            return;
        }
        long long *st = a->row_stats + 3 * y;
        for (int x = 0; x < a->w; x++) {
            slref_path_out o;
            slref_path_trace(j->c, x, (int)y, j->sample, &o);
            size_t i = y * (size_t)a->w + x;
            for (int k = 0; k < 3; k++)
                half[4 * i + k] += o.rgb[k];
            half[4 * i + 3] += o.hit;
            double *v = a->aov + SLREF_PATH_AOV * i;
            for (int k = 0; k < 3; k++)
                v[k] += o.direct[k], v[3 + k] += o.indirect[k];
            for (int l = 0; l < 4; l++)
                for (int k = 0; k < 3; k++)
                    v[6 + 3 * l + k] += o.lobes[l][k];
            if (o.z < a->depth[i]) a->depth[i] = (float)o.z;
            st[0]++, st[1] += o.events, st[2] += o.capped;
        }
    }
}

int slref_path_pass(const slref_path_ctx *c, slref_path_accum *a, uint32_t sample, int threads,
                    const volatile sig_atomic_t *cancel) {
    pass_job j = {c, a, sample, cancel, 0};
    sl_parallel_for(threads < 1 ? 1 : threads, (size_t)a->h, 1, pass_rows, &j);
    if (j.stopped) return 1;
    a->n[sample & 1]++;
    return 0;
}

void slref_path_stats(const slref_path_accum *a, long long *paths, long long *events,
                      long long *capped) {
    long long s[3] = {0, 0, 0};
    for (int y = 0; y < a->h; y++)
        for (int k = 0; k < 3; k++)
            s[k] += a->row_stats[3 * y + k];
    if (paths) *paths = s[0];
    if (events) *events = s[1];
    if (capped) *capped = s[2];
}
