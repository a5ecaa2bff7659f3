/* envfit_error.c: the two errors `strandlight fit` and `sample` report.
 *
 * rel_l2: sqrt(sum_p Omega_p |L_p - M_p|^2 / sum_p Omega_p |L_p|^2) over every pixel of the map,
 * Omega_p the exact pixel solid angle, lobes evaluated without cut-off.
 *
 * lobe_conv_rel_l2: the same for E(nu) = integral L(omega) G(omega; nu, conv_lambda) d omega, the
 * radiance a fiber lobe of width conv_lambda gathers (what the renderer's shading integrals see).
 * nu runs over a subset of pixel centres (EFL_NU_W x EFL_NU_H, about 4 degrees apart, finer than
 * the 10-degree kernel), weighted by sin(theta). The map side is the midpoint rule on the full
 * map (for a fixed pair of rows the kernel depends only on the column difference, so one table
 * of exponentials serves a row pair); the lobe side is exact: integral G_j G_nu in closed form
 * (envfit_gram.c), or rgb_j G(omega_j; nu) for directional lights (lambda_j = 0). */
#include "lighting/envfit_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define EFL_NU_W 64
#define EFL_NU_H 32

double sl_envfit_rel_l2(const sl_envmap *map, const sl_lobe *lobes, int n, int threads) {
    efl_level lv = {0};
    efl_level_geometry(&lv, map->width, map->height);
    lv.rgb = map->rgb; /* borrowed */
    double energy = 0;
    for (int y = 0; y < lv.h; y++) {
        double row = 0;
        const float *p = map->rgb + (size_t)y * lv.w * 3;
        for (int i = 0; i < lv.w * 3; i++)
            row += (double)p[i] * p[i];
        energy += row * lv.om[y];
    }
    efl_eval ev = {&lv, threads, 40.0, NULL, NULL};
    ev.res = sl_malloc(sizeof(double) * 3 * (size_t)lv.w * lv.h);
    double F = efl_objective(&ev, lobes, n);
    free(ev.res);
    lv.rgb = NULL;
    efl_level_free(&lv);
    if (energy <= 0) return F > 0 ? INFINITY : 0.0;
    return sqrt(2 * F / energy);
}

typedef struct conv_grid {
    int nw, nh;
    int *xs, *ys; /* map pixel of each nu column / row */
    double *wgt;  /* per nu row: sin(theta) */
} conv_grid;

typedef struct conv_job {
    const efl_level *lv;
    const conv_grid *g;
    double a;
    double *E; /* nh x nw x 3 */
} conv_job;

static void conv_row(void *ctx, int Y) {
    conv_job *jb = ctx;
    const efl_level *lv = jb->lv;
    int w = lv->w, yn = jb->g->ys[Y];
    double a = jb->a, dmin = 1.0 - 20.0 / a; /* drop kernel values below e^-20 */
    double *t = sl_malloc(sizeof(double) * (size_t)w);
    double *E = jb->E + (size_t)Y * jb->g->nw * 3;
    memset(E, 0, sizeof(double) * 3 * (size_t)jb->g->nw);
    for (int y = 0; y < lv->h; y++) {
        double A = lv->ct[y] * lv->ct[yn], B = lv->st[y] * lv->st[yn];
        if (A + B < dmin) continue;
        int D;
        if (A - B >= dmin || B <= 0)
            D = w; /* the whole row */
        else {
            double q = (dmin - A) / B;
            D = q <= -1 ? w : (int)floor(acos(fmin(1.0, q)) * w / (2 * M_PI)) + 1;
        }
        int klo = -D, khi = D;
        if (2 * D + 1 >= w) {
            klo = 0;
            khi = w - 1;
        }
        for (int k = klo; k <= khi; k++)
            t[k < 0 ? k + w : k] = exp(a * (A + B * cos(2 * M_PI * k / w) - 1));
        const float *L = lv->rgb + (size_t)y * w * 3;
        double om = lv->om[y];
        for (int X = 0; X < jb->g->nw; X++) {
            int xc = jb->g->xs[X];
            double s0 = 0, s1 = 0, s2 = 0;
            for (int k = klo; k <= khi; k++) {
                int x = xc + k;
                x = x < 0 ? x + w : (x >= w ? x - w : x);
                double tk = t[k < 0 ? k + w : k];
                s0 += tk * L[x * 3 + 0];
                s1 += tk * L[x * 3 + 1];
                s2 += tk * L[x * 3 + 2];
            }
            E[X * 3 + 0] += om * s0;
            E[X * 3 + 1] += om * s1;
            E[X * 3 + 2] += om * s2;
        }
    }
    free(t);
}

double sl_envfit_conv_rel_l2(const sl_envmap *map, const sl_lobe *lobes, int n, double conv_lambda,
                             int threads) {
    efl_level lv = {0};
    efl_level_geometry(&lv, map->width, map->height);
    lv.rgb = map->rgb; /* borrowed */
    conv_grid g;
    g.nw = lv.w < EFL_NU_W ? lv.w : EFL_NU_W;
    g.nh = lv.h < EFL_NU_H ? lv.h : EFL_NU_H;
    g.xs = sl_malloc(sizeof(int) * g.nw);
    g.ys = sl_malloc(sizeof(int) * g.nh);
    g.wgt = sl_malloc(sizeof(double) * g.nh);
    for (int X = 0; X < g.nw; X++)
        g.xs[X] = (int)((X + 0.5) * lv.w / g.nw);
    for (int Y = 0; Y < g.nh; Y++) {
        g.ys[Y] = (int)((Y + 0.5) * lv.h / g.nh);
        g.wgt[Y] = lv.st[g.ys[Y]];
    }
    double a = 2.0 / (conv_lambda * conv_lambda);
    double *E = sl_malloc(sizeof(double) * 3 * (size_t)g.nw * g.nh);
    conv_job jb = {&lv, &g, a, E};
    efl_parallel(threads, g.nh, conv_row, &jb);
    double num = 0, den = 0;
    for (int Y = 0; Y < g.nh; Y++) {
        double rn = 0, rd = 0;
        for (int X = 0; X < g.nw; X++) {
            double nu[3], m[3] = {0, 0, 0};
            efl_pixel_dir(&lv, g.xs[X], g.ys[Y], nu);
            for (int j = 0; j < n; j++) {
                double k;
                if (lobes[j].lambda > 0)
                    k = efl_sg_inner(lobes[j].dir, 2.0 / (lobes[j].lambda * lobes[j].lambda), nu,
                                     a);
                else
                    k = exp(a * (nu[0] * lobes[j].dir[0] + nu[1] * lobes[j].dir[1] +
                                 nu[2] * lobes[j].dir[2] - 1));
                for (int ch = 0; ch < 3; ch++)
                    m[ch] += lobes[j].rgb[ch] * k;
            }
            for (int ch = 0; ch < 3; ch++) {
                double e = E[((size_t)Y * g.nw + X) * 3 + ch];
                rn += (m[ch] - e) * (m[ch] - e);
                rd += e * e;
            }
        }
        num += g.wgt[Y] * rn;
        den += g.wgt[Y] * rd;
    }
    free(E);
    free(g.xs);
    free(g.ys);
    free(g.wgt);
    lv.rgb = NULL;
    efl_level_free(&lv);
    if (den <= 0) return num > 0 ? INFINITY : 0.0;
    return sqrt(num / den);
}

void sl_lobes_eval(const sl_lobe *lobes, int n, const double omega[3], double rgb[3]) {
    rgb[0] = rgb[1] = rgb[2] = 0;
    for (int j = 0; j < n; j++) {
        if (!(lobes[j].lambda > 0)) continue;
        double d =
            omega[0] * lobes[j].dir[0] + omega[1] * lobes[j].dir[1] + omega[2] * lobes[j].dir[2];
        double G = exp(2 * (d - 1) / (lobes[j].lambda * lobes[j].lambda));
        for (int ch = 0; ch < 3; ch++)
            rgb[ch] += lobes[j].rgb[ch] * G;
    }
}
