/* render_ref.c: see render_ref.h. The reference renderer's per-hit shading and its threaded
 * frame loop. Formulas and what is (not) included: docs/reference.md. */
#include "render_ref.h"

#include "chiang_ref.h"
#include "deon_ref.h"
#include "dual_ref.h"
#include "marschner_ref.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { MAX_CROSS = 512 };

static double dot3(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

void slref_fiber_frame(const double u[3], double v[3], double w[3]) {
    double ref[3] = {0, 1, 0};
    if (fabs(u[1]) > 0.9) ref[0] = 1, ref[1] = 0;
    double ru = dot3(ref, u), l = 0;
    for (int k = 0; k < 3; k++) {
        v[k] = ref[k] - ru * u[k];
        l += v[k] * v[k];
    }
    l = sqrt(l);
    for (int k = 0; k < 3; k++)
        v[k] /= l;
    w[0] = u[1] * v[2] - u[2] * v[1];
    w[1] = u[2] * v[0] - u[0] * v[2];
    w[2] = u[0] * v[1] - u[1] * v[0];
}

/* Angles of a unit world direction in the fiber frame (numerics.md sec. 1). */
static void angles(const double u[3], const double v[3], const double w[3], const double d[3],
                   double *th, double *ph) {
    double s = dot3(d, u);
    *th = asin(s > 1 ? 1 : (s < -1 ? -1 : s));
    *ph = atan2(dot3(d, w), dot3(d, v));
}

/* The exact fiber function f (numerics.md sec. 3) of channel ch; mode[0..2] = its R, TT, TRT
 * parts (d'Eon and Chiang: orders p = 0, 1, 2; the higher orders and f_rest are only in f). Each
 * model its own (before session 12 chiang fell through to Marschner's f, ~1.8x the energy: the
 * direct reference of a chiang scene was 1.8-1.9x the path tracer's first bounce; test
 * reference_chiang_matches_path). */
static double fiber_f(const sl_material *m, int ch, double ti, double pi_, double to, double po,
                      double mode[3]) {
    if (m->model == SL_MODEL_CHIANG) {
        double out[5];
        slref_chiang_scatter(m, ch, ti, pi_, to, po, out);
        for (int k = 0; k < 3; k++)
            mode[k] = out[k];
        return out[4];
    }
    if (m->model == SL_MODEL_DEON) {
        double out[SL_MATERIAL_MAX_ORDERS + 3];
        slref_deon_scatter(m, ch, ti, pi_, to, po, out);
        for (int k = 0; k < 3; k++)
            mode[k] = out[k];
        return out[m->orders + 2];
    }
    double out[4];
    slref_marschner_scatter(m, ch, ti, pi_, to, po, out);
    for (int k = 0; k < 3; k++)
        mode[k] = out[k];
    return out[3];
}

/* Normalised Gaussian of variance var. */
static double gauss(double x, double var) {
    return exp(-0.5 * x * x / var) / sqrt(2 * M_PI * var);
}

/* The integrand of the scattered (n >= 1 crossings) dual-scattering response over theta_i
 * (docs/reference.md, Xu 2011 Eq. 27 + 29 with psi_f of Eq. 5), for channels 0..nch-1:
 *   g(theta_i; theta_j, s_c^2) cos^2(theta_i) / cos^2(theta_d) x
 *   [ sum_t M_t(theta_h) N^G_t(theta_d, phi_oj) + d_b 2 A_b g(theta_h - Delta_b, sigma_b^2/2)
 *     (pi - |phi_oj|) / pi^2 ]. */
static void ms_fn(const sl_material *m, const slref_ms_tables *t, int nch, const double var[3],
                  double theta_j, double theta_o, double phi_oj, double ti, double out[3]) {
    double td = 0.5 * (theta_o - ti), th = 0.5 * (theta_o + ti);
    double cd = cos(td), ci = cos(ti);
    for (int c = 0; c < nch; c++)
        out[c] = 0;
    if (cd < 1e-9) return;
    double mt[3], pa = fabs(phi_oj), geo = ci * ci / (cd * cd);
    for (int k = 0; k < 3; k++)
        mt[k] = slref_marschner_M(m, k, th);
    for (int c = 0; c < nch; c++) {
        double glob = 0;
        for (int k = 0; k < 3; k++)
            glob += mt[k] * slref_ms_ng(t, c, k, td, phi_oj);
        double ab = slref_ms_term(t, c, SLREF_DUAL_A_B, td);
        double db = slref_ms_term(t, c, SLREF_DUAL_DELTA_B, td);
        double sb = slref_ms_term(t, c, SLREF_DUAL_SIGMA_B, td);
        double loc =
            SLREF_MS_DB * 2 * ab * gauss(th - db, 0.5 * sb * sb) * (M_PI - pa) / (M_PI * M_PI);
        out[c] = gauss(ti - theta_j, var[c]) * geo * (glob + loc);
    }
}

/* 8-point Gauss-Legendre on [-1, 1] (positive half; symmetric). */
static const double GL8_X[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                0.9602898564975363};
static const double GL8_W[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                0.1012285362903763};

/* int over theta_i of ms_fn on [theta_j - 8 s, theta_j + 8 s] (s the largest channel's spread)
 * clipped to [-pi/2, pi/2]: composite 8-point Gauss-Legendre, panels no wider than s and than
 * 0.08 rad (under the std. dev. of the narrowest lobe of the default material, TT's
 * sqrt(2) beta_TT = 0.093 in theta_i), at most 64 panels. */
static void ms_integral(const sl_material *m, const slref_ms_tables *t, int nch,
                        const double var[3], double theta_j, double theta_o, double phi_oj,
                        double out[3]) {
    double vmax = 0;
    for (int c = 0; c < nch; c++)
        vmax = var[c] > vmax ? var[c] : vmax, out[c] = 0;
    double sd = sqrt(vmax), a = theta_j - 8 * sd, b = theta_j + 8 * sd;
    if (a < -M_PI / 2) a = -M_PI / 2;
    if (b > M_PI / 2) b = M_PI / 2;
    if (!(b > a)) return;
    double pw = sd < 0.08 ? sd : 0.08;
    int np = (int)ceil((b - a) / pw);
    if (np < 2) np = 2;
    if (np > 64) np = 64;
    double h = (b - a) / np;
    for (int p = 0; p < np; p++) {
        double mid = a + (p + 0.5) * h;
        for (int i = 0; i < 4; i++)
            for (int sgn = -1; sgn <= 1; sgn += 2) {
                double v[3];
                ms_fn(m, t, nch, var, theta_j, theta_o, phi_oj, mid + sgn * 0.5 * h * GL8_X[i], v);
                for (int c = 0; c < nch; c++)
                    out[c] += 0.5 * h * GL8_W[i] * v[c];
            }
    }
}

const sl_material *slref_strand_material(const sl_material *m, const float *sa, uint32_t strand,
                                         sl_material *own) {
    if (!sa) return m;
    *own = *m;
    const float *q = sa + 3 * (size_t)strand;
    for (int c = 0; c < 3; c++)
        own->sigma_a[c] = q[c];
    own->sigma_a_rgb = m->sigma_a_rgb || q[0] != q[1] || q[1] != q[2];
    return own;
}

void slref_shade(const slref_shading *sh, const double x[3], const double wo[3], uint32_t prim,
                 double ss[3], double ms[3], double modes[9]) {
    slref_shade_lights(sh, x, wo, prim, 0, 1, ss, ms, modes);
}

void slref_shade_lights(const slref_shading *sh, const double x[3], const double wo[3],
                        uint32_t prim, int l0, int stride, double ss[3], double ms[3],
                        double modes[9]) {
    double u[3], v[3], w[3], to, po;
    uint32_t strand, seg;
    slref_rt_prim_info(sh->rt, prim, &strand, &seg, u);
    sl_material own;
    const sl_material *m = slref_strand_material(sh->m, sh->strand_sa, strand, &own);
    slref_fiber_frame(u, v, w);
    angles(u, v, w, wo, &to, &po);
    int nch = (m->sigma_a[0] == m->sigma_a[1] && m->sigma_a[1] == m->sigma_a[2]) ? 1 : 3;
    /* multiple scattering reads the material's tables (sh->m), single scattering m */
    const sl_material *mm = sh->m;
    int nchm = (mm->sigma_a[0] == mm->sigma_a[1] && mm->sigma_a[1] == mm->sigma_a[2]) ? 1 : 3;
    for (int c = 0; c < 3; c++)
        ss[c] = ms[c] = 0;
    if (modes)
        for (int k = 0; k < 9; k++)
            modes[k] = 0;
    uint32_t cross[MAX_CROSS];
    if (stride < 1) stride = 1;
    for (int l = l0 < 0 ? 0 : l0; l < sh->nl; l += stride) {
        const slref_light *L = &sh->L[l];
        if (L->rgb[0] <= 0 && L->rgb[1] <= 0 && L->rgb[2] <= 0) continue;
        double ti, pi_;
        angles(u, v, w, L->dir, &ti, &pi_);
        int n = sh->ms ? slref_rt_crossings(sh->rt, x, L->dir, strand, seg, cross, MAX_CROSS)
                       : slref_rt_occluded(sh->rt, x, L->dir, strand, seg);
        double f[3] = {0, 0, 0}, fm[3][3] = {{0}};
        if (n == 0) {
            for (int c = 0; c < nch; c++)
                f[c] = fiber_f(m, c, ti, pi_, to, po, fm[c]);
            for (int c = nch; c < 3; c++) {
                f[c] = f[0];
                for (int k = 0; k < 3; k++)
                    fm[c][k] = fm[0][k];
            }
            for (int c = 0; c < 3; c++) {
                ss[c] += f[c] * L->rgb[c];
                if (modes)
                    for (int k = 0; k < 3; k++)
                        modes[3 * k + c] += fm[c][k] * L->rgb[c];
            }
        }
        if (!sh->ms) continue;
        double phi = remainder(po - pi_, 2 * M_PI);
        double td = 0.5 * (to - ti), th = 0.5 * (to + ti), cd = cos(td);
        double rch[3] = {0, 0, 0};
        if (n == 0) {
            /* Direct light: local backscattering only (Zinke's f_back^direct, Xu's S_back). */
            if (cos(phi) > 0 && cd > 1e-9)
                for (int cc = 0; cc < nchm; cc++) {
                    double ab = slref_ms_term(sh->ms, cc, SLREF_DUAL_A_B, td);
                    double db = slref_ms_term(sh->ms, cc, SLREF_DUAL_DELTA_B, td);
                    double sb = slref_ms_term(sh->ms, cc, SLREF_DUAL_SIGMA_B, td);
                    rch[cc] = SLREF_MS_DB * 2 / (cd * cd) * ab / M_PI *
                              gauss(th - db, 0.5 * sb * sb) * cos(ti);
                }
        } else if (n <= MAX_CROSS) {
            /* Forward path: T_f = d_f prod a_f, spread in theta_i: s^2 = sum 2 beta_f^2. */
            double tf[3], var[3];
            int live = 0;
            for (int cc = 0; cc < nchm; cc++)
                tf[cc] = SLREF_MS_DF, var[cc] = 0;
            for (int k = 0; k < n; k++) {
                double uk[3];
                slref_rt_prim_info(sh->rt, cross[k], NULL, NULL, uk);
                double s = fabs(dot3(uk, L->dir));
                double tk = asin(s > 1 ? 1 : s);
                for (int cc = 0; cc < nchm; cc++) {
                    double bf = slref_ms_term(sh->ms, cc, SLREF_DUAL_BETA_F, tk);
                    tf[cc] *= slref_ms_term(sh->ms, cc, SLREF_DUAL_AF, tk);
                    var[cc] += 2 * bf * bf;
                }
            }
            for (int cc = 0; cc < nchm; cc++)
                live += tf[cc] > 1e-12;
            if (live > 0) {
                double cj = cos(ti), integ[3];
                if (cj < 1e-6) cj = 1e-6;
                ms_integral(mm, sh->ms, nchm, var, ti, to, phi, integ);
                for (int cc = 0; cc < nchm; cc++)
                    rch[cc] = tf[cc] / cj * integ[cc];
            }
        }
        for (int c = 0; c < 3; c++)
            ms[c] += rch[c < nchm ? c : 0] * L->rgb[c];
    }
}

void slref_camera_ray(const sl_camera *cam, double px, double py, double dir[3]) {
    double x = px - 0.5 * cam->width, y = 0.5 * cam->height - py, l = 0;
    for (int k = 0; k < 3; k++) {
        dir[k] = cam->focal * cam->fwd[k] + x * cam->right[k] + y * cam->up[k];
        l += dir[k] * dir[k];
    }
    l = sqrt(l);
    for (int k = 0; k < 3; k++)
        dir[k] /= l;
}

/* splitmix64: a per-pixel random stream, independent of the thread that renders it. */
static uint64_t mix(uint64_t *s) {
    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}
static double unit(uint64_t *s) {
    return (mix(s) >> 11) * (1.0 / 9007199254740992.0);
}

typedef struct render_job {
    const slref_shading *sh;
    const sl_camera *cam;
    const slref_render_opts *o;
    int light_split;
    slref_image *img;
} render_job;

static void render_pixel(const render_job *j, int px, int py) {
    const sl_camera *cam = j->cam;
    int aa = j->o->aa, W = cam->width;
    uint64_t st = j->o->seed ^ (0xd1b54a32d192ed03ull * (uint64_t)((size_t)py * W + px + 1));
    double acc[3] = {0, 0, 0}, accm[3] = {0, 0, 0}, accd[9] = {0}, depth = INFINITY;
    int hits = 0, S = aa * aa, split = j->light_split && S > 1;
    /* light_split: a random rotation of which ray shades which light subset, per pixel, from
     * its own stream so that the camera rays are the same with and without the split */
    uint64_t st_rot = st ^ 0x5851f42d4c957f2dull;
    int rot = split ? (int)(mix(&st_rot) % (uint64_t)S) : 0;
    for (int sy = 0; sy < aa; sy++)
        for (int sx = 0; sx < aa; sx++) {
            double jx = j->o->no_jitter ? 0.5 : unit(&st), jy = j->o->no_jitter ? 0.5 : unit(&st);
            double fx = px + (sx + jx) / aa, fy = py + (sy + jy) / aa, d[3];
            slref_camera_ray(cam, fx, fy, d);
            slref_hit hit;
            if (!slref_rt_intersect(j->sh->rt, cam->eye, d, INFINITY, &hit)) continue;
            hits++;
            double x[3], wo[3], ss[3], ms[3], md[9];
            for (int k = 0; k < 3; k++)
                x[k] = cam->eye[k] + hit.t * d[k], wo[k] = -d[k];
            double z = hit.t * dot3(d, cam->fwd);
            if (z < depth) depth = z;
            if (split) {
                slref_shade_lights(j->sh, x, wo, hit.prim, (sy * aa + sx + rot) % S, S, ss, ms, md);
                for (int k = 0; k < 9; k++)
                    md[k] *= S;
                for (int k = 0; k < 3; k++)
                    ss[k] *= S, ms[k] *= S;
            } else {
                slref_shade(j->sh, x, wo, hit.prim, ss, ms, md);
            }
            for (int k = 0; k < 9; k++)
                accd[k] += md[k];
            for (int k = 0; k < 3; k++)
                acc[k] += ss[k] + ms[k], accm[k] += ms[k];
        }
    size_t i = (size_t)py * W + px;
    double n = (double)aa * aa;
    for (int k = 0; k < 3; k++) {
        j->img->rgba[4 * i + k] = (float)(acc[k] / n);
        j->img->ms_rgb[3 * i + k] = (float)(accm[k] / n);
    }
    for (int k = 0; k < 9; k++)
        j->img->mode_rgb[9 * i + k] = (float)(accd[k] / n);
    j->img->rgba[4 * i + 3] = (float)(hits / n);
    j->img->depth[i] = (float)depth;
}

static void render_rows(void *arg, size_t y0, size_t y1, int worker) {
    (void)worker;
    const render_job *j = arg;
    for (size_t y = y0; y < y1; y++)
        for (int x = 0; x < j->cam->width; x++)
            render_pixel(j, x, (int)y);
}

int slref_render(const slref_shading *sh, const sl_camera *cam, const slref_render_opts *o,
                 slref_image *out, sl_err *e) {
    return slref_render_split(sh, cam, o, 0, out, e);
}

int slref_render_split(const slref_shading *sh, const sl_camera *cam, const slref_render_opts *o,
                       int light_split, slref_image *out, sl_err *e) {
    memset(out, 0, sizeof *out);
    if (cam->width < 1 || cam->height < 1 || o->aa < 1)
        return sl_fail(e, "reference: bad image size or sampling (%dx%d, aa %d)", cam->width,
                       cam->height, o->aa);
    slref_image_alloc(out, cam->width, cam->height);
    render_job j = {.sh = sh, .cam = cam, .o = o, .light_split = light_split, .img = out};
    slref_run_rows(render_rows, &j, cam->height, o);
    return 0;
}

void slref_image_alloc(slref_image *img, int w, int h) {
    size_t n = (size_t)w * h;
    img->w = w, img->h = h;
    img->rgba = sl_calloc(4 * n, sizeof(float));
    img->depth = sl_malloc(n * sizeof(float));
    img->ms_rgb = sl_calloc(3 * n, sizeof(float));
    img->mode_rgb = sl_calloc(9 * n, sizeof(float));
}

void slref_run_rows(sl_parallel_fn fn, void *job, int rows, const slref_render_opts *o) {
    int threads = o->threads > 256 ? 256 : o->threads;
    sl_parallel_for_progress(threads, rows > 0 ? (size_t)rows : 0, 1, fn, job, o->progress,
                             o->progress_user);
}

void slref_image_free(slref_image *img) {
    free(img->rgba);
    free(img->depth);
    free(img->ms_rgb);
    free(img->mode_rgb);
    memset(img, 0, sizeof *img);
}
