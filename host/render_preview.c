/* render_preview.c: see render_preview.h (placeholder renderer). */
#include "render_preview.h"

#include "fiber_deon.h"
#include "fiber_marschner.h"
#include "fiber_params.h"

#include <math.h>
#include <pthread.h>
#include <unistd.h>
#include <stdlib.h>
#include <string.h>

void sl_material_to_fiber(const sl_material *m, int channel, sl_fiber_params *fp);

int sl_frame_alloc(sl_frame *f, int width, int height) {
    f->width = width;
    f->height = height;
    size_t n = (size_t)width * height;
    f->rgba = sl_calloc(4 * n, sizeof(float));
    f->depth = sl_malloc(n * sizeof(float));
    for (size_t i = 0; i < n; i++) f->depth[i] = INFINITY;
    return 0;
}

void sl_frame_free(sl_frame *f) {
    free(f->rgba);
    free(f->depth);
    memset(f, 0, sizeof *f);
}

/* Unit tangent of point i of a strand [a, b): central difference, falling back to any
 * neighbouring non-degenerate segment, then +Y (near-zero-length segments exist in real files). */
static void tangent(const float *pos, uint32_t a, uint32_t b, uint32_t i, double t[3]) {
    for (uint32_t r = 1; r < b - a; r++) {
        uint32_t i0 = i >= a + r ? i - r : a, i1 = i + r < b ? i + r : b - 1;
        double d[3], l = 0;
        for (int k = 0; k < 3; k++) {
            d[k] = (double)pos[3 * i1 + k] - pos[3 * i0 + k];
            l += d[k] * d[k];
        }
        if (l > 1e-20) {
            l = sqrt(l);
            for (int k = 0; k < 3; k++) t[k] = d[k] / l;
            return;
        }
    }
    t[0] = 0, t[1] = 1, t[2] = 0;
}

/* Angles of a world direction in the fiber frame (u, v, w) of numerics.md sec. 1. */
static void fiber_angles(const double u[3], const double v[3], const double w[3], const float d[3],
                         double *theta, double *phi) {
    double su = d[0] * u[0] + d[1] * u[1] + d[2] * u[2];
    double sv = d[0] * v[0] + d[1] * v[1] + d[2] * v[2];
    double sw = d[0] * w[0] + d[1] * w[1] + d[2] * w[2];
    su = su > 1 ? 1 : (su < -1 ? -1 : su);
    *theta = asin(su);
    *phi = atan2(sw, sv);
}

static void shade_vertices(const sl_material *mat, const sl_hair *h, const sl_lights *L,
                           const sl_camera *cam, uint32_t s_begin, uint32_t s_end, float *col) {
    sl_fiber_params fp[3];
    for (int c = 0; c < 3; c++) sl_material_to_fiber(mat, c, &fp[c]);
    float out[SL_DEON_MAX_ORDERS + 3];
    int nout = mat->model == SL_MODEL_DEON ? mat->orders + 3 : 4;
    for (uint32_t s = s_begin; s < s_end; s++) {
        uint32_t a = h->strand_first[s], b = h->strand_first[s + 1];
        for (uint32_t i = a; i < b; i++) {
            double u[3], v[3], w[3];
            tangent(h->pos, a, b, i, u);
            /* v: a stable normal from a world axis not parallel to u. */
            double ref[3] = {0, 1, 0};
            if (fabs(u[1]) > 0.9) ref[0] = 1, ref[1] = 0;
            double ru = ref[0] * u[0] + ref[1] * u[1] + ref[2] * u[2], vl = 0;
            for (int k = 0; k < 3; k++) {
                v[k] = ref[k] - ru * u[k];
                vl += v[k] * v[k];
            }
            vl = sqrt(vl);
            for (int k = 0; k < 3; k++) v[k] /= vl;
            w[0] = u[1] * v[2] - u[2] * v[1];
            w[1] = u[2] * v[0] - u[0] * v[2];
            w[2] = u[0] * v[1] - u[1] * v[0];
            float wo[3];
            double ol = 0;
            for (int k = 0; k < 3; k++) {
                wo[k] = (float)(cam->eye[k] - h->pos[3 * i + k]);
                ol += (double)wo[k] * wo[k];
            }
            ol = sqrt(ol);
            for (int k = 0; k < 3; k++) wo[k] = (float)(wo[k] / ol);
            double th_o, ph_o;
            fiber_angles(u, v, w, wo, &th_o, &ph_o);
            double acc[3] = {0, 0, 0};
            for (int l = 0; l < L->count; l++) {
                double th_i, ph_i;
                fiber_angles(u, v, w, L->light[l].dir, &th_i, &ph_i);
                for (int c = 0; c < 3; c++) {
                    if (mat->model == SL_MODEL_DEON)
                        sl_deon_scatter(&fp[c], (float)th_i, (float)ph_i, (float)th_o, (float)ph_o,
                                        out);
                    else
                        sl_marschner_scatter(&fp[c], (float)th_i, (float)ph_i, (float)th_o,
                                             (float)ph_o, out);
                    float f = out[nout - 1];
                    if (isfinite(f)) acc[c] += (double)f * L->light[l].rgb[c];
                }
            }
            for (int c = 0; c < 3; c++) col[3 * i + c] = (float)acc[c];
        }
    }
}

/* Shading is independent per vertex: split the strands over threads (deterministic, each thread
 * writes its own vertices). */
typedef struct shade_job {
    const sl_material *mat;
    const sl_hair *h;
    const sl_lights *L;
    const sl_camera *cam;
    uint32_t s_begin, s_end;
    float *col;
} shade_job;

static void *shade_thread(void *arg) {
    shade_job *j = arg;
    shade_vertices(j->mat, j->h, j->L, j->cam, j->s_begin, j->s_end, j->col);
    return NULL;
}

static void shade_parallel(const sl_material *mat, const sl_hair *h, const sl_lights *L,
                           const sl_camera *cam, float *col) {
    enum { MAX_THREADS = 16 };
    long ncpu = sysconf(_SC_NPROCESSORS_ONLN);
    int nt = ncpu < 1 ? 1 : (ncpu > MAX_THREADS ? MAX_THREADS : (int)ncpu);
    if (h->num_strands < 64) nt = 1;
    pthread_t tid[MAX_THREADS];
    shade_job job[MAX_THREADS];
    int started[MAX_THREADS] = {0};
    for (int t = 0; t < nt; t++) {
        job[t] = (shade_job){mat, h, L, cam, (uint32_t)((uint64_t)h->num_strands * t / nt),
                             (uint32_t)((uint64_t)h->num_strands * (t + 1) / nt), col};
        started[t] = t > 0 && pthread_create(&tid[t], NULL, shade_thread, &job[t]) == 0;
    }
    for (int t = 0; t < nt; t++)
        if (!started[t]) shade_thread(&job[t]); /* thread 0, or a thread that failed to start */
    for (int t = 1; t < nt; t++)
        if (started[t]) pthread_join(tid[t], NULL);
}

/* Weighted blended OIT accumulation (McGuire & Bavoil 2013): order-independent, so the
 * placeholder needs no per-pixel sorting; the depth weight favours near fragments. */
typedef struct accum {
    float *rgb, *a, *reveal;
} accum;

static void splat_segment(const sl_camera *cam, const double p0[3], const double p1[3],
                          const float c0[3], const float c1[3], double r0, double r1, float a0,
                          float a1, accum *acc, float *depth) {
    double x0, y0, z0, x1, y1, z1;
    if (!sl_camera_project(cam, p0, &x0, &y0, &z0) || !sl_camera_project(cam, p1, &x1, &y1, &z1))
        return;
    double w0 = 2 * r0 * cam->focal / z0, w1 = 2 * r1 * cam->focal / z1; /* width in pixels */
    double wmax = (w0 > w1 ? w0 : w1), ext = 0.5 * (wmax > 1 ? wmax : 1) + 1;
    int xa = (int)floor((x0 < x1 ? x0 : x1) - ext), xb = (int)ceil((x0 > x1 ? x0 : x1) + ext);
    int ya = (int)floor((y0 < y1 ? y0 : y1) - ext), yb = (int)ceil((y0 > y1 ? y0 : y1) + ext);
    if (xa < 0) xa = 0;
    if (ya < 0) ya = 0;
    if (xb > cam->width - 1) xb = cam->width - 1;
    if (yb > cam->height - 1) yb = cam->height - 1;
    double dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy;
    for (int y = ya; y <= yb; y++)
        for (int x = xa; x <= xb; x++) {
            double px = x + 0.5, py = y + 0.5;
            double t = len2 > 0 ? ((px - x0) * dx + (py - y0) * dy) / len2 : 0;
            t = t < 0 ? 0 : (t > 1 ? 1 : t);
            double ex = x0 + t * dx - px, ey = y0 + t * dy - py;
            double dist = sqrt(ex * ex + ey * ey);
            double wpx = w0 + t * (w1 - w0);
            double we = wpx > 1 ? wpx : 1;
            /* Box-filtered coverage of a ribbon of width wpx: sub-pixel ribbons keep their area. */
            double cov = (0.5 * we + 0.5 - dist);
            cov = cov < 0 ? 0 : (cov > 1 ? 1 : cov);
            cov *= wpx < 1 ? wpx : 1;
            if (cov <= 0) continue;
            float alpha = (float)(cov * (a0 + t * (a1 - a0)));
            double z = z0 + t * (z1 - z0);
            size_t k = (size_t)y * cam->width + x;
            float wz = (float)(alpha * 1.0 / (1e-3 + pow(z / 100.0, 4.0)));
            for (int c = 0; c < 3; c++)
                acc->rgb[3 * k + c] += (float)(c0[c] + t * (c1[c] - c0[c])) * alpha * wz;
            acc->a[k] += alpha * wz;
            acc->reveal[k] *= 1 - alpha;
            if (z < depth[k]) depth[k] = (float)z;
        }
}

int sl_render_preview(const sl_material *mat, const sl_hair *h, const sl_lights *lights,
                      const sl_camera *cam, sl_frame *f, sl_err *e) {
    if (mat->model == SL_MODEL_DEON && mat->orders > SL_DEON_MAX_ORDERS)
        return sl_fail(e, "render: d'Eon orders %d above the float backends' limit %d",
                       mat->orders, SL_DEON_MAX_ORDERS);
    sl_frame_alloc(f, cam->width, cam->height);
    float *col = sl_malloc((size_t)h->num_points * 3 * sizeof(float));
    shade_parallel(mat, h, lights, cam, col);
    size_t n = (size_t)f->width * f->height;
    accum acc = {sl_calloc(3 * n, sizeof(float)), sl_calloc(n, sizeof(float)),
                 sl_malloc(n * sizeof(float))};
    for (size_t i = 0; i < n; i++) acc.reveal[i] = 1;
    for (uint32_t s = 0; s < h->num_strands; s++) {
        for (uint32_t i = h->strand_first[s]; i + 1 < h->strand_first[s + 1]; i++) {
            double p0[3], p1[3];
            for (int k = 0; k < 3; k++) p0[k] = h->pos[3 * i + k], p1[k] = h->pos[3 * i + 3 + k];
            double r0 = h->radius ? h->radius[i] : h->default_radius;
            double r1 = h->radius ? h->radius[i + 1] : h->default_radius;
            float a0 = 1 - (h->transparency ? h->transparency[i] : h->default_transparency);
            float a1 = 1 - (h->transparency ? h->transparency[i + 1] : h->default_transparency);
            splat_segment(cam, p0, p1, col + 3 * i, col + 3 * i + 3, r0, r1, a0, a1, &acc,
                          f->depth);
        }
    }
    for (size_t k = 0; k < n; k++) {
        float alpha = 1 - acc.reveal[k];
        for (int c = 0; c < 3; c++) f->rgba[4 * k + c] = acc.a[k] > 0 ? alpha * acc.rgb[3 * k + c] / acc.a[k] : 0;
        f->rgba[4 * k + 3] = alpha;
    }
    free(acc.rgb);
    free(acc.a);
    free(acc.reveal);
    free(col);
    return 0;
}
