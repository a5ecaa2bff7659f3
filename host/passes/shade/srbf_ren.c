/* srbf_ren.c: builds, checks and caches the Ren 2010 Sec. 4 SRBF response table (see srbf_ren.h,
 * kernels/srbf_ren_lookup.h for the axes, docs/srbf_ren.md for the choices and measurements),
 * and evaluates it.
 *
 * Marschner: every node is one `fast` evaluation (kernels/srbf_fast.h) per mode and channel: the
 * modes have their own warped h axis, so a node of the TT block is not a node of the R block.
 * Rows go to slcl_srbf_batch (device) or slc_srbf_batch (C, split over threads) in chunks, which
 * drive the progress bar. Models deon and chiang: every node is one RGB row of their fast path
 * (kernels/srbf_deon.h, srbf_chiang.h; slcl_srbf_deon_rgb_batch or slc_srbf_deon_rgb_batch) per
 * mode, its three slots being the table's modes (I_0, I_1, orders >= 2 with the rest). The OpenCL
 * lookup is srbf_ren_cl.c. */
#include "passes/shade/srbf_ren.h"

#include "base/disk_cache.h"
#include "passes/shade/srbf_cache_payload.h"
#include "base/parallel.h"

#include "srbf_c.h"
#include "srbf_deon_c.h"
#include "passes/shade/srbf_cl.h"
#include "passes/shade/srbf_deon_cl.h"
#include "srbf_deon.h"
#include "srbf_fast.h"
#include "passes/shade/srbf_tables.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define PI 3.14159265358979323846
#define CHUNK_ROWS (1 << 17)

void sl_srbf_ren_params_default(sl_srbf_ren_params *p) {
    memset(p, 0, sizeof *p);
    p->n_h = 48;
    p->n_t = 20;
    p->n_phi = 24;
    p->n_lambda = 20;
    p->lambda_min = 0.02;
    p->lambda_max = 3.0;
}

static double lobe_integral(double lam) {
    return PI * lam * lam * (1.0 - exp(-4.0 / (lam * lam)));
}

uint64_t sl_srbf_ren_material_hash(const sl_material *m) {
    char s[1024];
    snprintf(s, sizeof s,
             "model %d fresnel %d orders %d eta %.17g alpha %.17g %.17g %.17g beta %.17g %.17g "
             "%.17g sigma_a %.17g %.17g %.17g ecc %.17g wc %.17g",
             m->model, m->fresnel, m->orders, m->eta, m->alpha[0], m->alpha[1], m->alpha[2],
             m->beta[0], m->beta[1], m->beta[2], m->sigma_a[0], m->sigma_a[1], m->sigma_a[2],
             m->eccentricity, m->caustic_width);
    /* chiang's azimuthal logistic (absent from the Marschner and d'Eon keys, so their hashes,
     * and the disk-cache names of their tables, stay what they were) */
    if (m->model == SL_MODEL_CHIANG)
        snprintf(s + strlen(s), sizeof s - strlen(s), " logistic_s %.17g", m->logistic_s);
    return sl_hash64(s, strlen(s), 0x52454e4d41543031ull);
}

int sl_srbf_ren_matches(const sl_srbf_ren *t, const sl_material *m) {
    return t->T != NULL && t->material == sl_srbf_ren_material_hash(m);
}

/* Floats ahead of the blocks: the h-warp constants, 4 per mode and lambda node. */
static size_t warp_floats(const sl_srbf_ren_params *p) {
    return (size_t)12 * p->n_lambda;
}

static double lambda_node(const sl_srbf_ren_dims *d, int il) {
    return exp(d->log_lmin + il / (double)d->l_scale);
}

/* The table geometry for material m (kernels/srbf_ren_lookup.h). */
static void make_dims(const sl_material *m, const sl_srbf_ren_params *p, sl_srbf_ren_dims *d) {
    memset(d, 0, sizeof *d);
    d->n_h = p->n_h;
    d->n_t = p->n_t;
    d->n_p = p->n_phi;
    d->n_l = p->n_lambda;
    size_t nodes = (size_t)p->n_h * p->n_t * p->n_phi * p->n_lambda;
    d->nc[0] = 1;
    d->nc[1] = d->nc[2] = 4;
    d->off[0] = (sl_int)warp_floats(p);
    d->off[1] = (sl_int)(d->off[0] + nodes);
    d->off[2] = (sl_int)(d->off[1] + 4 * nodes);
    /* The h warp's centre and width per mode. Marschner's M_t is a Gaussian in theta_h = h of
     * width beta; the d'Eon form's M_p (deon, chiang: theta_o shifted by -2 alpha, variance v =
     * beta^2, fiber_params.h) tends to a Gaussian in theta_i + theta_o - 2 alpha of variance v,
     * i.e. in h around alpha of width beta / 2 (cos(theta_i + theta_o - 2 alpha) / v in the
     * exponent once I_0 is replaced by its asymptote). */
    double wscale = m->model == SL_MODEL_MARSCHNER ? 1.0 : 0.5;
    for (int k = 0; k < 3; k++) {
        double b = wscale * m->beta[k];
        d->alpha[k] = (float)m->alpha[k];
        d->beta2[k] = (float)(b * b);
    }
    d->lmin = (float)p->lambda_min;
    d->lmax = (float)p->lambda_max;
    d->log_lmin = (float)log(p->lambda_min);
    d->l_scale = (float)((p->n_lambda - 1) / (log(p->lambda_max) - log(p->lambda_min)));
    d->t_scale = 0.5f * (float)(p->n_t - 1);
    /* deon, chiang: R stored as ln(v + eps) (kernels/srbf_ren_lookup.h sl_srbf_ren_blend_r; eps
     * far below the error measure's floor, 0.03 of a normalised value) */
    d->r_log = m->model != SL_MODEL_MARSCHNER;
    d->r_eps = d->r_log ? SL_SRBF_REN_R_EPS : 0.0f;
    d->p_scale = (float)((p->n_phi - 1) / PI);
}

/* The h-warp constants at the head of T: per mode k and lambda node il, the lobe width
 * w = sqrt(beta^2 + lambda^2 / 4) in h (kernels/srbf_ren_lookup.h). */
static void make_warps(const sl_srbf_ren_dims *d, float *T) {
    for (int k = 0; k < 3; k++)
        for (int il = 0; il < d->n_l; il++) {
            double lam = lambda_node(d, il);
            double w = sqrt((double)d->beta2[k] + 0.25 * lam * lam);
            float inv_w = (float)(1.0 / w);
            double lo = (double)sl_srbf_ren_warp((-0.5f * SL_PI_F - d->alpha[k]) * inv_w);
            double hi = (double)sl_srbf_ren_warp((0.5f * SL_PI_F - d->alpha[k]) * inv_w);
            float *q = T + 4 * (k * d->n_l + il);
            q[0] = inv_w;
            q[1] = (float)lo;
            q[2] = (float)((d->n_h - 1) / (hi - lo));
            q[3] = 0.0f;
        }
}

/* Node q of mode k's block as a `fast` input row (psi: phi_o + phi_j, only eccentric fibers
 * depend on it); returns the node's lambda. The h node inverts the lookup's warp with the same
 * float constants, so a lookup at the node lands on it. */
static double node_row(const sl_srbf_ren_dims *d, const float *T, int k, size_t q, double psi,
                       float *row) {
    int ih = (int)(q % (size_t)d->n_h);
    size_t r = q / (size_t)d->n_h;
    int it = (int)(r % (size_t)d->n_t);
    r /= (size_t)d->n_t;
    int ip = (int)(r % (size_t)d->n_p);
    int il = (int)(r / (size_t)d->n_p);
    const float *wq = T + 4 * (k * d->n_l + il);
    double s = wq[1] + ih / (double)wq[2];
    double kk = SL_SRBF_REN_K;
    double y = s / (1.0 - fabs(s) / kk); /* inverse of y / (1 + |y| / K) */
    double h = d->alpha[k] + y / (double)wq[0];
    if (ih == 0) h = -0.5 * PI;
    if (ih == d->n_h - 1) h = 0.5 * PI;
    h = fmin(fmax(h, -0.5 * PI), 0.5 * PI);
    double u = -1.0 + it / (double)d->t_scale, au = 1.0 - fabs(u);
    double tt = copysign(1.0 - au * au, u); /* inverse of sl_srbf_ren_twarp */
    double dd = tt * (0.5 * PI - fabs(h));
    double dphi = ip / (double)d->p_scale;
    double lam = lambda_node(d, il);
    row[0] = (float)fmin(fmax(h - dd, -0.5 * PI), 0.5 * PI);
    row[1] = (float)(0.5 * (psi - dphi));
    row[2] = (float)fmin(fmax(h + dd, -0.5 * PI), 0.5 * PI);
    row[3] = (float)(0.5 * (psi + dphi));
    row[4] = (float)lam;
    return lam;
}

/* ---- evaluation of `fast` rows: C threads or the OpenCL device ---- */

typedef struct fast_job {
    const sl_fiber_params *fp;
    const sl_srbf_tables *ft;
    const float *in;
    float *out;
} fast_job;

static void fast_part(void *arg, size_t begin, size_t end, int part) {
    (void)part;
    const fast_job *j = arg;
    slc_srbf_batch(j->fp, j->ft->C, j->ft->H, SL_SRBF_METHOD_FAST, 4, end - begin,
                   j->in + 5 * begin, j->out + 4 * begin);
}

/* Contiguous parts of the rows, one a thread: every row's output depends on that row alone
 * (slc_srbf_batch), so any split gives the same table (sl_parallel_parts bounds the threads). */
static void fast_c(const sl_fiber_params *fp, const sl_srbf_tables *ft, int threads, size_t n,
                   const float *in, float *out) {
    fast_job job = {fp, ft, in, out};
    sl_parallel_parts(threads, n, fast_part, &job);
}

/* Evaluates n rows of `fast` for fp on dev (OpenCL, falling back to C where dev may) or C. */
static int fast_rows(sl_device *dev, const sl_fiber_params *fp, const sl_srbf_tables *ft,
                     int threads, size_t n, const float *in, float *out, sl_err *e) {
    if (dev && dev->is_opencl) {
        int rc = slcl_srbf_batch(dev->cl, fp, ft, SL_SRBF_METHOD_FAST, 4, n, in, out, e);
        if (rc == 0) return 0;
        if (!sl_device_try_fallback(dev, rc, e)) return -1;
    }
    fast_c(fp, ft, threads, n, in, out);
    return 0;
}

/* ---- models deon and chiang: RGB rows of the d'Eon fast path ---- */

typedef struct rgb_job {
    const sl_fiber_params *fp;
    const sl_srbf_tables *ft;
    const float *in, *sig;
    float *out;
} rgb_job;

static void rgb_part(void *arg, size_t begin, size_t end, int part) {
    (void)part;
    const rgb_job *j = arg;
    slc_srbf_deon_rgb_batch(j->fp, j->ft->C, j->ft->H, j->ft->D, end - begin, j->in + 5 * begin,
                            j->sig + 3 * begin, j->out + 9 * begin);
}

/* n rows of the d'Eon-family fast path (sig: 3 absorptions per row; out: 9 per row, the slots
 * I_0 rgb, I_1 rgb, orders >= 2 and the rest rgb) on dev (OpenCL, falling back to C where dev
 * may) or C threads (contiguous parts: a row's output depends on that row alone, bit for bit
 * the scalar path's, cpu/srbf_deon_c.h). */
static int rgb_rows(sl_device *dev, const sl_fiber_params *fp, const sl_srbf_tables *ft,
                    int threads, size_t n, const float *in, const float *sig, float *out,
                    sl_err *e) {
    if (dev && dev->is_opencl) {
        int rc = slcl_srbf_deon_rgb_batch(dev->cl, fp, ft, n, in, sig, out, e);
        if (rc == 0) return 0;
        if (!sl_device_try_fallback(dev, rc, e)) return -1;
    }
    rgb_job job = {fp, ft, in, sig, out};
    sl_parallel_parts(threads, n, rgb_part, &job);
    return 0;
}

/* The material's absorption as the frame's rows carry it (float per channel), once per row. */
static float *material_sig(const sl_material *m, size_t n) {
    float *sig = sl_malloc((n ? n : 1) * 3 * sizeof *sig);
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++)
            sig[3 * i + (size_t)c] = (float)m->sigma_a[c];
    return sig;
}

/* Channel 0's total I of n rows of material m's closed form (the self-check's reference):
 * `fast` for Marschner, the d'Eon fast path for deon and chiang. */
static int closed_form_total(sl_device *dev, const sl_material *m, const sl_srbf_tables *ft,
                             int threads, size_t n, const float *in, double *tot, sl_err *e) {
    sl_fiber_params fp;
    sl_material_to_fiber(m, 0, &fp);
    int rc;
    if (m->model == SL_MODEL_MARSCHNER) {
        float *o = sl_malloc((n ? n : 1) * 4 * sizeof *o);
        rc = fast_rows(dev, &fp, ft, threads, n, in, o, e);
        for (size_t i = 0; !rc && i < n; i++)
            tot[i] = o[4 * i + 3];
        free(o);
    } else {
        float *o = sl_malloc((n ? n : 1) * 9 * sizeof *o), *sig = material_sig(m, n);
        rc = rgb_rows(dev, &fp, ft, threads, n, in, sig, o, e);
        for (size_t i = 0; !rc && i < n; i++)
            tot[i] = (double)o[9 * i] + o[9 * i + 3] + o[9 * i + 6];
        free(o);
        free(sig);
    }
    return rc;
}

static int online_cpus(void) {
    int n = sl_parallel_cpus();
    return n > 64 ? 64 : n;
}

static int cmp_d(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The table's own error against the closed form at SL_SRBF_REN_CHECK_POINTS random points
 * (fixed seed) over the whole domain, lambda in the table range: error of numerics.md sec. 5 on
 * the total I of channel r. */
static int self_check(sl_device *dev, const sl_material *m, const sl_srbf_tables *ft, int threads,
                      const sl_srbf_ren_params *p, sl_srbf_ren *t, sl_err *e) {
    enum { N = SL_SRBF_REN_CHECK_POINTS };
    float *in = sl_malloc(N * 5 * sizeof *in), *got = sl_malloc(N * 9 * sizeof *got);
    double *ref = sl_malloc(N * sizeof *ref);
    double *err = sl_malloc(N * sizeof *err);
    uint64_t s = 0x9e3779b97f4a7c15ull;
    for (int i = 0; i < N; i++) {
        double u[5];
        for (int k = 0; k < 5; k++) {
            s = s * 6364136223846793005ull + 1442695040888963407ull;
            u[k] = (double)(s >> 11) / 9007199254740992.0;
        }
        in[5 * i + 0] = (float)(PI * (u[0] - 0.5));
        in[5 * i + 1] = (float)(2.0 * PI * (u[1] - 0.5));
        in[5 * i + 2] = (float)(PI * (u[2] - 0.5));
        in[5 * i + 3] = (float)(2.0 * PI * (u[3] - 0.5));
        in[5 * i + 4] =
            (float)exp(log(p->lambda_min) + u[4] * (log(p->lambda_max) - log(p->lambda_min)));
    }
    int rc = closed_form_total(dev, m, ft, threads, N, in, ref, e);
    if (!rc) {
        slc_srbf_ren_batch(t, N, in, got);
        for (int i = 0; i < N; i++) {
            double x = (double)got[9 * i] + got[9 * i + 3] + got[9 * i + 6];
            double lam = in[5 * i + 4];
            err[i] = fabs(x - ref[i]) / fmax(ref[i], 0.03 * lobe_integral(lam));
        }
        qsort(err, N, sizeof *err, cmp_d);
        t->err_median = err[N / 2];
        t->err_p95 = err[(int)(0.95 * (N - 1))];
        t->err_max = err[N - 1];
    }
    free(in);
    free(ref);
    free(got);
    free(err);
    return rc;
}

/* Marschner: every block from `fast`, mode by mode and channel by channel (R once: it does not
 * depend on sigma_a). */
static int fill_marschner(sl_device *dev, const sl_material *m, const sl_srbf_tables *ft,
                          int threads, sl_srbf_ren *t, sl_progress *pg, sl_err *e) {
    const sl_srbf_ren_dims *d = &t->dims;
    size_t nodes = (size_t)d->n_h * d->n_t * d->n_p * d->n_l;
    int nch = m->sigma_a[0] == m->sigma_a[1] && m->sigma_a[0] == m->sigma_a[2] ? 1 : 3;
    /* eccentric fibers depend on phi_o + phi_j too (numerics.md sec. 3); the table stores the
     * response averaged over the fiber's rotation psi = phi_o + phi_j (4 samples, Ren 2010 drops
     * eccentricity altogether, their Sec. 9) */
    int npsi = m->eccentricity != 1.0 ? 4 : 1;
    size_t total = nodes * (size_t)npsi * (size_t)(1 + 2 * nch), done = 0;
    size_t chunk_nodes = CHUNK_ROWS / (size_t)npsi;
    float *in = sl_malloc(chunk_nodes * (size_t)npsi * 5 * sizeof *in);
    float *out = sl_malloc(chunk_nodes * (size_t)npsi * 4 * sizeof *out);
    double *lam = sl_malloc(chunk_nodes * sizeof *lam);
    int rc = 0;
    for (int k = 0; k < 3 && !rc; k++) {
        int nc = k == 0 ? 1 : nch;
        for (int ch = 0; ch < nc && !rc; ch++) {
            sl_fiber_params fp;
            sl_material_to_fiber(m, ch, &fp);
            for (size_t q0 = 0; q0 < nodes && !rc; q0 += chunk_nodes) {
                size_t nq = nodes - q0 < chunk_nodes ? nodes - q0 : chunk_nodes;
                for (size_t q = 0; q < nq; q++)
                    for (int ps = 0; ps < npsi; ps++)
                        lam[q] = node_row(d, t->T, k, q0 + q, 2.0 * PI * ps / npsi,
                                          in + 5 * (q * (size_t)npsi + (size_t)ps));
                rc = fast_rows(dev, &fp, ft, threads, nq * (size_t)npsi, in, out, e);
                if (rc) break;
                float *B = t->T + d->off[k];
                for (size_t q = 0; q < nq; q++) {
                    double acc = 0.0;
                    for (int ps = 0; ps < npsi; ps++)
                        acc += out[4 * (q * (size_t)npsi + (size_t)ps) + k];
                    float v = (float)(acc / npsi / lobe_integral(lam[q]));
                    size_t o = (q0 + q) * (size_t)d->nc[k];
                    if (d->nc[k] == 1)
                        B[o] = v;
                    else
                        for (int c = ch; c < 3; c += nc) /* one channel, or all three alike; the
                                                           pad (channel 3) stays 0 */
                            B[o + (size_t)c] = v;
                }
                done += nq * (size_t)npsi;
                sl_progress_update(pg, (double)done / (double)total);
            }
        }
    }
    free(in);
    free(out);
    free(lam);
    return rc;
}

/* Models deon and chiang: mode k's block from slot k of one RGB row per node of k's axis (the
 * row carries the material's three absorptions as the frame's rows do; R, slot 0, does not
 * depend on them and is stored once, channel 0's). No rotation: the d'Eon fast path has no
 * eccentricity. */
static int fill_deon(sl_device *dev, const sl_material *m, const sl_srbf_tables *ft, int threads,
                     sl_srbf_ren *t, sl_progress *pg, sl_err *e) {
    const sl_srbf_ren_dims *d = &t->dims;
    size_t nodes = (size_t)d->n_h * d->n_t * d->n_p * d->n_l;
    size_t chunk = CHUNK_ROWS, total = 3 * nodes, done = 0;
    float *in = sl_malloc(chunk * 5 * sizeof *in), *out = sl_malloc(chunk * 9 * sizeof *out);
    float *sig = material_sig(m, chunk);
    double *lam = sl_malloc(chunk * sizeof *lam);
    sl_fiber_params fp;
    sl_material_to_fiber(m, 0, &fp);
    int rc = 0;
    for (int k = 0; k < 3 && !rc; k++)
        for (size_t q0 = 0; q0 < nodes && !rc; q0 += chunk) {
            size_t nq = nodes - q0 < chunk ? nodes - q0 : chunk;
            for (size_t q = 0; q < nq; q++)
                lam[q] = node_row(d, t->T, k, q0 + q, 0.0, in + 5 * q);
            rc = rgb_rows(dev, &fp, ft, threads, nq, in, sig, out, e);
            if (rc) break;
            float *B = t->T + d->off[k];
            for (size_t q = 0; q < nq; q++) {
                double g = lobe_integral(lam[q]);
                size_t o = (q0 + q) * (size_t)d->nc[k];
                for (int c = 0; c < d->nc[k] && c < 3; c++) { /* the pad (channel 3) stays 0 */
                    double v = out[9 * q + 3 * (size_t)k + (size_t)c] / g;
                    B[o + (size_t)c] =
                        (float)(k == 0 && d->r_log ? log(fmax(v, 0.0) + d->r_eps) : v);
                }
            }
            done += nq;
            sl_progress_update(pg, (double)done / (double)total);
        }
    free(in);
    free(out);
    free(sig);
    free(lam);
    return rc;
}

/* Builds t (t->dims, key and material already set). */
static int build(sl_device *dev, const sl_material *m, const sl_srbf_ren_params *p,
                 const sl_srbf_tables *ft, sl_srbf_ren *t, sl_err *e) {
    const sl_srbf_ren_dims *d = &t->dims;
    size_t nodes = (size_t)d->n_h * d->n_t * d->n_p * d->n_l;
    t->n_floats = warp_floats(p) + 9 * nodes;
    t->T = sl_calloc(t->n_floats, sizeof(float));
    make_warps(d, t->T);
    int threads = p->threads > 0 ? p->threads : online_cpus();
    double t0 = sl_now();
    sl_progress pg;
    sl_progress_begin(&pg, "srbf table");
    int was_cl = dev && dev->is_opencl;
    int rc = m->model == SL_MODEL_MARSCHNER ? fill_marschner(dev, m, ft, threads, t, &pg, e)
                                            : fill_deon(dev, m, ft, threads, t, &pg, e);
    sl_progress_end(&pg);
    t->build_s = sl_now() - t0;
    if (dev && dev->is_opencl)
        snprintf(t->built_on, sizeof t->built_on, "%s", dev->name);
    else
        snprintf(t->built_on, sizeof t->built_on, "C path (%d thread%s)%s", threads,
                 threads == 1 ? "" : "s", was_cl ? " after an OpenCL fallback" : "");
    if (!rc) rc = self_check(dev, m, ft, threads, p, t, e);
    if (rc) {
        free(t->T);
        t->T = NULL;
        return -1;
    }
    return 0;
}

/* ---- disk cache ---- */

/* The payload: what the build measured and the table's shape, then the table's floats
 * (base/disk_cache.h adds the key and the integrity hash). Bump when this layout changes. */
#define REN_FORMAT 3u /* 3: dims.r_log, r_eps */

static uint64_t ren_key(const sl_material *m, const sl_srbf_ren_params *p,
                        const sl_srbf_tables *ft) {
    uint64_t tab = sl_hash64(ft->C, SL_SRBF_C_FLOATS * sizeof(float), 1);
    tab = sl_hash64(ft->H, SL_SRBF_H_FLOATS * sizeof(float), tab);
    /* the d'Eon fast path's own table (deon, chiang; not part of a Marschner key, so those keys
     * stay what they were) */
    if (m->model != SL_MODEL_MARSCHNER)
        tab = sl_hash64(ft->D, SL_SRBF_DEON_FLOATS * sizeof(float), tab);
    char s[1024];
    snprintf(s, sizeof s,
             "strandlight srbf ren table v3 (h warp per lambda, displacement): fast (nodes %d) "
             "tables %016llx material %016llx "
             "h %d t %d phi %d lambda %d [%.17g, %.17g] K %.9g",
             SL_SRBF_FAST_NODES, (unsigned long long)tab,
             (unsigned long long)sl_srbf_ren_material_hash(m), p->n_h, p->n_t, p->n_phi,
             p->n_lambda, p->lambda_min, p->lambda_max, (double)SL_SRBF_REN_K);
    return sl_hash64(s, strlen(s), 0x52454e5441423031ull);
}

static int try_load(sl_srbf_ren *t, const char *path) {
    const size_t nT = t->n_floats * sizeof(float);
    void *data = NULL;
    size_t n = 0;
    if (sl_cache_read(path, REN_FORMAT, (sl_cache_key){t->key, 0}, sizeof(sl_srbf_ren_meta) + nT,
                      &data, &n, NULL))
        return -1;
    int rc = sl_srbf_ren_from_payload(t, data, n);
    free(data);
    return rc;
}

static void save(const sl_srbf_ren *t) {
    sl_srbf_ren_meta h;
    memset(&h, 0, sizeof h);
    h.n_floats = t->n_floats;
    h.dims = t->dims;
    h.build_s = t->build_s;
    h.err_median = t->err_median;
    h.err_p95 = t->err_p95;
    h.err_max = t->err_max;
    memcpy(h.built_on, t->built_on, sizeof h.built_on);
    sl_cache_part parts[2] = {{&h, sizeof h}, {t->T, t->n_floats * sizeof(float)}};
    sl_err e2 = {{0}};
    if (sl_cache_write(t->path, REN_FORMAT, (sl_cache_key){t->key, 0}, parts, 2, 0, &e2))
        sl_warn("srbf table: not cached: %s", e2.msg);
}

static int check_params(const sl_srbf_ren_params *p, sl_err *e) {
    if (p->n_h < 2 || p->n_t < 2 || p->n_phi < 2 || p->n_lambda < 2)
        return sl_fail(e,
                       "srbf table: every axis needs at least 2 nodes (h %d, t %d, phi %d, "
                       "lambda %d)",
                       p->n_h, p->n_t, p->n_phi, p->n_lambda);
    double nodes = (double)p->n_h * p->n_t * p->n_phi * p->n_lambda;
    if (nodes * 9.0 > 2.0e8)
        return sl_fail(e, "srbf table: %.0f nodes is too many (at most %.0f)", nodes, 2.0e8 / 9);
    if (!(p->lambda_min > 0.0) || !(p->lambda_max > p->lambda_min) || !isfinite(p->lambda_max))
        return sl_fail(e, "srbf table: lambda range [%g, %g] must satisfy 0 < min < max",
                       p->lambda_min, p->lambda_max);
    return 0;
}

int sl_srbf_ren_get(sl_device *dev, const sl_material *m, const sl_srbf_ren_params *p_in,
                    sl_srbf_ren *t, sl_err *e) {
    memset(t, 0, sizeof *t);
    sl_srbf_ren_params p;
    if (p_in)
        p = *p_in;
    else
        sl_srbf_ren_params_default(&p);
    for (int k = 0; k < 3; k++)
        if (!(m->beta[k] > 0.0))
            return sl_fail(e, "srbf table: beta[%d] must be > 0 (got %g)", k, m->beta[k]);
    if (check_params(&p, e)) return -1;
    sl_srbf_tables ft;
    if (sl_srbf_tables_get(&ft, 0, e)) return -1;
    make_dims(m, &p, &t->dims);
    t->n_floats = warp_floats(&p) + 9 * (size_t)p.n_h * p.n_t * p.n_phi * p.n_lambda;
    t->key = ren_key(m, &p, &ft);
    t->material = sl_srbf_ren_material_hash(m);
    char dir[4000];
    int have_dir = 0;
    if (p.cache_dir)
        have_dir = p.cache_dir[0] != 0 && snprintf(dir, sizeof dir, "%s", p.cache_dir) > 0;
    else
        have_dir = sl_cache_dir_find(dir, sizeof dir);
    if (have_dir) {
        if (sl_cache_path(t->path, sizeof t->path, dir, "srbf-ren", (sl_cache_key){t->key, 0},
                          REN_FORMAT) &&
            try_load(t, t->path) == 0) {
            sl_srbf_tables_free(&ft);
            return 0;
        }
    }
    int rc = build(dev, m, &p, &ft, t, e);
    sl_srbf_tables_free(&ft);
    if (rc) return -1;
    if (p.verbose)
        sl_note("srbf table built on %s: %dx%dx%dx%d nodes, %.1f MB, %.2f s; error against the "
                "fast closed form: median %.2g, p95 %.2g, max %.2g%s%s",
                t->built_on, p.n_h, p.n_t, p.n_phi, p.n_lambda, t->n_floats * sizeof(float) / 1e6,
                t->build_s, t->err_median, t->err_p95, t->err_max,
                t->path[0] ? "; cached in " : "; not cached", t->path);
    if (t->path[0]) save(t);
    return 0;
}

double sl_srbf_ren_build_rows(const sl_material *m, const sl_srbf_ren_params *p_in) {
    sl_srbf_ren_params p;
    if (p_in)
        p = *p_in;
    else
        sl_srbf_ren_params_default(&p);
    /* deon, chiang: one RGB row per node and mode (an RGB row of the d'Eon fast path costs
     * about what a single-channel `fast` row does: the absorption is the cheap part) */
    if (m->model != SL_MODEL_MARSCHNER) return 3.0 * p.n_h * p.n_t * p.n_phi * p.n_lambda;
    /* Marschner: the count build() evaluates: R once, TT and TRT per distinct channel, 4
     * rotations for an eccentric fiber */
    int nch = m->sigma_a[0] == m->sigma_a[1] && m->sigma_a[0] == m->sigma_a[2] ? 1 : 3;
    int npsi = m->eccentricity != 1.0 ? 4 : 1;
    return (double)p.n_h * p.n_t * p.n_phi * p.n_lambda * npsi * (1 + 2 * nch);
}

int sl_srbf_ren_cached(const sl_material *m, const sl_srbf_ren_params *p_in,
                       const sl_srbf_tables *ft_in) {
    sl_srbf_ren_params p;
    if (p_in)
        p = *p_in;
    else
        sl_srbf_ren_params_default(&p);
    if (check_params(&p, NULL)) return 0;
    char dir[4000];
    int have_dir;
    if (p.cache_dir)
        have_dir = p.cache_dir[0] != 0 && snprintf(dir, sizeof dir, "%s", p.cache_dir) > 0;
    else
        have_dir = sl_cache_dir_find(dir, sizeof dir);
    if (!have_dir) return 0;
    sl_srbf_tables own;
    const sl_srbf_tables *ft = ft_in;
    if (!ft) {
        sl_err e2 = {{0}};
        if (sl_srbf_tables_get(&own, 0, &e2)) return 0;
        ft = &own;
    }
    uint64_t key = ren_key(m, &p, ft);
    if (!ft_in) sl_srbf_tables_free(&own);
    char path[4200];
    /* the header only (format, key, size): sl_srbf_ren_get still verifies the payload's hash
     * and rebuilds a damaged file, so a 1 here is a promise of a cheap load, not of a valid
     * table */
    size_t n_floats = warp_floats(&p) + 9 * (size_t)p.n_h * p.n_t * p.n_phi * p.n_lambda;
    return sl_cache_path(path, sizeof path, dir, "srbf-ren", (sl_cache_key){key, 0}, REN_FORMAT) &&
           sl_cache_probe(path, REN_FORMAT, (sl_cache_key){key, 0},
                          sizeof(sl_srbf_ren_meta) + n_floats * sizeof(float));
}

void sl_srbf_ren_free(sl_srbf_ren *t) {
    free(t->T);
    t->T = NULL;
}

/* ---- the eval helper (the OpenCL lookup: srbf_ren_cl.c) ---- */

int sl_srbf_ren_eval(sl_cl *cl, const sl_srbf_ren *t, int ch, size_t n, const float *in, float *out,
                     sl_err *e) {
    cl_mem table = NULL;
    int rc = sl_srbf_ren_eval_keep(cl, t, &table, ch, n, in, out, e);
    slcl_srbf_ren_table_release(&table);
    return rc;
}

int sl_srbf_ren_eval_keep(sl_cl *cl, const sl_srbf_ren *t, cl_mem *table, int ch, size_t n,
                          const float *in, float *out, sl_err *e) {
    if (ch < 0 || ch > 2) return sl_fail(e, "srbf table: channel %d is not 0..2", ch);
    float *o9 = sl_malloc((n ? n : 1) * 9 * sizeof *o9);
    int rc = 0;
    if (cl)
        rc = slcl_srbf_ren_rows(cl, t, table, "clCreateBuffer", n, in, o9, e);
    else
        slc_srbf_ren_batch(t, n, in, o9);
    if (!rc)
        for (size_t i = 0; i < n; i++) {
            float r = o9[9 * i + ch], tt = o9[9 * i + 3 + ch], trt = o9[9 * i + 6 + ch];
            out[4 * i] = r;
            out[4 * i + 1] = tt;
            out[4 * i + 2] = trt;
            out[4 * i + 3] = r + tt + trt;
        }
    free(o9);
    return rc;
}
