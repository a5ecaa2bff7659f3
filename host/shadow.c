/* shadow.c: the light pass and lookup of shadow.h: view setup, segment records (host projection,
 * stochastic simplification), and the raster + tables + lookup steps on OpenCL or the C twins. */
#include "shadow.h"

#include "../cpu/dodm.h"
#include "../cpu/raster.h"
#include "../kernels/raster.h"
#include "dodm_cl.h"
#include "raster_cl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void sl_shadow_opts_default(sl_shadow_opts *o) {
    o->size = SL_SHADOW_DEFAULT_SIZE;
    o->layers = SL_SHADOW_DEFAULT_LAYERS;
    o->kappa = 1.0;
    o->seed = 1;
}

double sl_shadow_support_angle(double lambda) {
    /* exp(2 (cos a - 1) / lambda^2) = G  =>  cos a = 1 + lambda^2 ln(G) / 2 */
    double c = 1.0 + lambda * lambda * log(SL_SHADOW_SUPPORT_G) / 2.0;
    return c <= -1.0 ? M_PI : acos(c);
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

/* Records of the kept segments (fixed-point scale applied), their count, the depth range of
 * their end points, and the sample count. */
static size_t make_records(const sl_hair *h, const sl_light_view *v, const sl_shadow_opts *o,
                           float **out, double *scale, double zr[2], size_t *samples) {
    size_t nseg = 0;
    for (uint32_t s = 0; s < h->num_strands; s++)
        if (sl_shadow_strand_kept(s, o->seed, o->kappa))
            nseg += h->strand_first[s + 1] - h->strand_first[s] - 1;
    float *recs = sl_malloc((nseg ? nseg : 1) * SL_RASTER_REC * sizeof *recs);
    double total = 0, wscale = 1.0 / o->kappa; /* Ren: kept fibers widened by 1/kappa */
    zr[0] = INFINITY;
    zr[1] = -INFINITY;
    size_t k = 0;
    *samples = 0;
    for (uint32_t s = 0; s < h->num_strands; s++) {
        if (!sl_shadow_strand_kept(s, o->seed, o->kappa)) continue;
        for (uint32_t i = h->strand_first[s]; i + 1 < h->strand_first[s + 1]; i++, k++) {
            double p0[3], p1[3], a[3], b[3];
            for (int c = 0; c < 3; c++) {
                a[c] = h->pos[3 * i + c];
                b[c] = h->pos[3 * i + 3 + c];
            }
            sl_light_view_project(v, a, p0);
            sl_light_view_project(v, b, p1);
            double hw = seg_radius(h, i) * wscale / v->texel;
            float *rec = recs + k * SL_RASTER_REC;
            slc_raster_record(p0, p1, hw, 1.0, rec);
            total += (double)rec[8] * rec[9] * rec[10];
            *samples += (size_t)rec[9] * (size_t)rec[10];
            zr[0] = fmin(zr[0], fmin(p0[2], p1[2]));
            zr[1] = fmax(zr[1], fmax(p0[2], p1[2]));
        }
    }
    /* Fixed point: the largest power of two keeping the map's total below 2^60 (so every box
     * sum and table entry fits in 64 bits with room for rounding). */
    int ex = total > 0 ? (int)floor(log2(ldexp(1.0, 60) / total)) : 0;
    if (ex > 100) ex = 100;
    *scale = ldexp(1.0, ex);
    for (size_t j = 0; j < nseg; j++)
        recs[j * SL_RASTER_REC + 8] *= (float)*scale;
    *out = recs;
    return nseg;
}

static int build_cl(sl_cl *cl, const float *recs, size_t nseg, sl_dodm *m, sl_err *e) {
    int w = m->view.w, h = m->view.h;
    size_t plane = (size_t)w * h;
    cl_context ctx = sl_cl_context(cl);
    cl_int err;
    cl_mem br = NULL, bz = NULL, bb = NULL;
    int rc = -1;
    br = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                        (nseg ? nseg : 1) * SL_RASTER_REC * sizeof(float), (void *)recs, &err);
    if (sl_cl_check(err, "shadow: clCreateBuffer(records)", e)) goto done;
    bz = clCreateBuffer(ctx, CL_MEM_READ_WRITE, plane * sizeof(cl_uint), NULL, &err);
    if (sl_cl_check(err, "shadow: clCreateBuffer(z0)", e)) goto done;
    bb = clCreateBuffer(ctx, CL_MEM_READ_WRITE, m->K * plane * sizeof(cl_ulong), NULL, &err);
    if (sl_cl_check(err, "shadow: clCreateBuffer(layers)", e)) goto done;
    sl_cl_timer t;
    sl_cl_timer_start(&t, cl);
    rc = slcl_raster_buf(cl, br, nseg, w, h, m->K, m->d, bz, bb, &t, e);
    m->raster_s = sl_cl_timer_stop(&t, NULL);
    if (rc) goto done;
    sl_cl_timer_start(&t, cl);
    rc = slcl_dodm_tables_buf(cl, bb, w, h, m->K, &t, e);
    m->tables_s = sl_cl_timer_stop(&t, NULL);
    if (rc) goto done;
    cl_command_queue q = sl_cl_queue(cl);
    if (sl_cl_check(clEnqueueReadBuffer(q, bz, CL_TRUE, 0, plane * sizeof(cl_uint), m->z0bits, 0,
                                        NULL, NULL),
                    "shadow: read z0", e) ||
        sl_cl_check(clEnqueueReadBuffer(q, bb, CL_TRUE, 0, m->K * plane * sizeof(cl_ulong), m->sat,
                                        0, NULL, NULL),
                    "shadow: read tables", e))
        rc = -1;
done:
    if (br) clReleaseMemObject(br);
    if (bz) clReleaseMemObject(bz);
    if (bb) clReleaseMemObject(bb);
    return rc;
}

int sl_shadow_build(sl_device *dev, const sl_hair *h, const double dir[3], double lambda,
                    const sl_shadow_opts *o, sl_dodm *m, sl_err *e) {
    memset(m, 0, sizeof *m);
    if (o->size < 2 || o->size > SL_SHADOW_MAX_SIZE)
        return sl_fail(e, "shadow: map size %d is out of range [2, %d]", o->size,
                       SL_SHADOW_MAX_SIZE);
    if (o->layers < 1 || o->layers > SL_SHADOW_MAX_LAYERS)
        return sl_fail(e, "shadow: layers %d is out of range [1, %d]", o->layers,
                       SL_SHADOW_MAX_LAYERS);
    if (!(o->kappa > 0 && o->kappa <= 1))
        return sl_fail(e, "shadow: kappa %g is out of range (0, 1]", o->kappa);
    if (!(dot3(dir, dir) > 0)) return sl_fail(e, "shadow: lobe direction is zero");
    float lo[3], hi[3];
    sl_hair_bounds(h, lo, hi);
    double rmax = h->default_radius;
    if (h->radius)
        for (uint32_t i = 0; i < h->num_points; i++)
            rmax = fmax(rmax, h->radius[i]);
    sl_light_view_setup(&m->view, dir, lo, hi, rmax / o->kappa, o->size);
    m->K = (unsigned)o->layers;
    float *recs;
    double zr[2];
    size_t nseg = make_records(h, &m->view, o, &recs, &m->scale, zr, &m->samples);
    m->segments = nseg;
    m->inv_scale = (float)(1.0 / m->scale);
    /* d from the hair's depth extent: the last boundary K (K + 1) d / 2 reaches its far end. */
    double ext = nseg ? zr[1] - zr[0] : 0;
    double d = 2.0 * ext / (m->K * (m->K + 1.0));
    m->d = (float)fmax(d * (1 + 1e-6), 1e-6 * m->view.texel);
    double alpha = sl_shadow_support_angle(lambda);
    m->rfac = alpha >= M_PI / 2 ? INFINITY : (float)(tan(alpha) / (2 * m->view.texel));
    size_t plane = (size_t)m->view.w * m->view.h;
    m->z0bits = sl_malloc(plane * sizeof *m->z0bits);
    m->sat = sl_malloc(m->K * plane * sizeof *m->sat);
    if (dev->is_opencl) {
        int rc = build_cl(dev->cl, recs, nseg, m, e);
        if (rc == 0) {
            free(recs);
            return 0;
        }
        if (!sl_device_try_fallback(dev, rc, e)) {
            free(recs);
            sl_dodm_free(m);
            return -1;
        }
    }
    double t0 = sl_now();
    slc_raster_z0(recs, nseg, m->view.w, m->view.h, m->z0bits);
    slc_raster_layers(recs, nseg, m->view.w, m->view.h, m->K, m->d, m->z0bits, m->sat);
    double t1 = sl_now();
    slc_dodm_cumulate(m->sat, plane, m->K);
    slc_dodm_sat(m->sat, m->view.w, m->view.h, m->K);
    m->raster_s = t1 - t0;
    m->tables_s = sl_now() - t1;
    free(recs);
    return 0;
}

int sl_shadow_lookup(sl_device *dev, const sl_dodm *m, size_t n, const double *xyz, double *T,
                     sl_err *e) {
    float *pts = sl_malloc((n ? n : 1) * 3 * sizeof *pts), *t = sl_malloc((n ? n : 1) * sizeof *t);
    for (size_t i = 0; i < n; i++) {
        double uvz[3];
        sl_light_view_project(&m->view, xyz + 3 * i, uvz);
        for (int c = 0; c < 3; c++)
            pts[3 * i + c] = (float)uvz[c];
    }
    int rc = 0;
    if (dev->is_opencl) {
        rc = slcl_dodm_lookup(dev->cl, m->z0bits, m->sat, m->view.w, m->view.h, m->K, m->d, m->rfac,
                              m->inv_scale, pts, n, t, e);
        if (rc && !sl_device_try_fallback(dev, rc, e))
            rc = -1;
        else
            rc = 0; /* done, or dev is now the C path */
    }
    if (!rc && !dev->is_opencl)
        slc_dodm_lookup(m->z0bits, m->sat, m->view.w, m->view.h, m->K, m->d, m->rfac, m->inv_scale,
                        pts, n, t);
    if (!rc)
        for (size_t i = 0; i < n; i++)
            T[i] = t[i];
    free(pts);
    free(t);
    return rc;
}

void sl_dodm_free(sl_dodm *m) {
    free(m->z0bits);
    free(m->sat);
    m->z0bits = NULL;
    m->sat = NULL;
}
