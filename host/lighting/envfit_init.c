/* envfit_init.c: greedy initialisation of the lobes (matching pursuit on a dictionary).
 *
 * The dictionary is every pixel direction of a coarse level times a geometric ladder of
 * bandwidths. Its correlations with the map, corr_b = sum_p om_p L_p G_b(omega_p), are computed
 * once, row pair by row pair: for a fixed atom row and pixel row the kernel depends only on the
 * column difference, so one table of exponentials serves the whole row pair. Lobes are then added
 * one at a time at the atom with the largest gain max(0, <r, G_b>)^2 / <G_b, G_b> per channel for
 * the residual r; residual correlations are updated with the closed-form inner products
 * <G_b, G_j> (envfit_gram.c), and the weights of all lobes added so far are re-solved by
 * non-negative least squares after each addition (orthogonal matching pursuit, with c >= 0). */
#include "lighting/envfit_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct dict_job {
    const efl_dict *d;
    const double *img; /* w*h*3 */
    double *out;       /* natoms*3 */
} dict_job;

static void dict_row(void *ctx, int Y) {
    const dict_job *jb = ctx;
    const efl_dict *d = jb->d;
    const efl_level *lv = d->lv;
    int w = lv->w, h = lv->h, np = w * h;
    double *t = sl_malloc(sizeof(double) * (size_t)w);
    double *cw = sl_malloc(sizeof(double) * (size_t)w);
    for (int k = 0; k < w; k++)
        cw[k] = cos(2 * M_PI * k / w);
    for (int li = 0; li < d->nlam; li++) {
        double a = 2.0 / (d->lam[li] * d->lam[li]);
        double *out = jb->out + ((size_t)li * np + (size_t)Y * w) * 3;
        memset(out, 0, sizeof(double) * 3 * (size_t)w);
        for (int y = 0; y < h; y++) {
            double A = lv->ct[y] * lv->ct[Y] - 1, B = lv->st[y] * lv->st[Y];
            if (a * (A + B) < -40) continue; /* the whole row pair is negligible */
            int D = 0;
            for (int k = 0; k < w; k++) {
                t[k] = exp(a * (A + B * cw[k]));
                if (t[k] > 1e-17 && (k <= w / 2 ? k : w - k) > D) D = k <= w / 2 ? k : w - k;
            }
            const double *L = jb->img + (size_t)y * w * 3;
            double om = lv->om[y];
            /* Column offsets k in [klo, khi] (all of them once when the span covers the row). */
            int klo = -D, khi = D;
            if (2 * D + 1 >= w) {
                klo = 0;
                khi = w - 1;
            }
            for (int X = 0; X < w; X++) {
                double s0 = 0, s1 = 0, s2 = 0;
                for (int k = klo; k <= khi; k++) {
                    int x = X + k;
                    x = x < 0 ? x + w : (x >= w ? x - w : x);
                    double tk = t[k < 0 ? k + w : k];
                    s0 += tk * L[x * 3 + 0];
                    s1 += tk * L[x * 3 + 1];
                    s2 += tk * L[x * 3 + 2];
                }
                out[X * 3 + 0] += om * s0;
                out[X * 3 + 1] += om * s1;
                out[X * 3 + 2] += om * s2;
            }
        }
    }
    free(t);
    free(cw);
}

void efl_dict_build(efl_dict *d, const efl_level *lv, double lam_lo, double lam_hi, int threads) {
    memset(d, 0, sizeof *d);
    d->lv = lv;
    int np = lv->w * lv->h;
    d->nlam = lam_hi > lam_lo * 1.01 ? 8 : 1;
    for (int i = 0; i < d->nlam; i++)
        d->lam[i] =
            d->nlam == 1 ? lam_lo : lam_lo * pow(lam_hi / lam_lo, (double)i / (d->nlam - 1));
    d->natoms = np * d->nlam;
    d->corr = sl_malloc(sizeof(double) * 3 * (size_t)d->natoms);
    d->self = sl_malloc(sizeof(double) * (size_t)d->natoms);
    for (int li = 0; li < d->nlam; li++) {
        double l2 = d->lam[li] * d->lam[li];
        /* integral of G^2 = integral of G with lambda / sqrt(2) */
        double s = -M_PI * 0.5 * l2 * expm1(-8.0 / l2);
        for (int p = 0; p < np; p++)
            d->self[(size_t)li * np + p] = s;
    }
    d->threads = threads;
    double *img = sl_malloc(sizeof(double) * 3 * (size_t)np);
    for (size_t i = 0; i < 3 * (size_t)np; i++)
        img[i] = lv->rgb[i];
    dict_job jb = {d, img, d->corr};
    efl_parallel(threads, lv->h, dict_row, &jb);
    free(img);
}

void efl_dict_free(efl_dict *d) {
    free(d->corr);
    free(d->self);
    memset(d, 0, sizeof *d);
}

void efl_dict_atom(const efl_dict *d, int atom, double mu[3], double *lambda) {
    int np = d->lv->w * d->lv->h, li = atom / np, p = atom % np;
    efl_pixel_dir(d->lv, p % d->lv->w, p / d->lv->w, mu);
    *lambda = d->lam[li];
}

void efl_nnls(const double *A, int m, const double *b, double *c) {
    /* Cyclic coordinate descent with projection: each update minimises exactly along one
     * coordinate, so the objective never increases; converges for positive definite A. */
    for (int ch = 0; ch < 3; ch++) {
        for (int sweep = 0; sweep < 2000; sweep++) {
            double change = 0, scale = 0;
            for (int i = 0; i < m; i++) {
                double gsum = -b[i * 3 + ch];
                const double *ai = A + (size_t)i * m;
                for (int k = 0; k < m; k++)
                    gsum += ai[k] * c[k * 3 + ch];
                double ci = c[i * 3 + ch] - gsum / ai[i];
                if (ci < 0) ci = 0;
                change += fabs(ci - c[i * 3 + ch]) * sqrt(ai[i]);
                scale += fabs(ci) * sqrt(ai[i]);
                c[i * 3 + ch] = ci;
            }
            if (change <= 1e-10 * scale || scale == 0) break;
        }
    }
}

void efl_greedy(const efl_dict *d, sl_lobe *lobes, int n_have, int n_want) {
    int na = d->natoms, add = n_want - n_have;
    if (add <= 0) return;
    /* Residual correlations after the lobes we already have (kept fixed). */
    double *res0 = sl_malloc(sizeof(double) * 3 * (size_t)na);
    double *res = sl_malloc(sizeof(double) * 3 * (size_t)na);
    double *gcol = sl_malloc(sizeof(double) * (size_t)na * add);
    double(*amu)[3] = sl_malloc(sizeof *amu * (size_t)na);
    double *aa = sl_malloc(sizeof(double) * (size_t)na);
    for (int b = 0; b < na; b++) {
        double lam;
        efl_dict_atom(d, b, amu[b], &lam);
        aa[b] = 2.0 / (lam * lam);
    }
    if (n_have == 0) {
        memcpy(res0, d->corr, sizeof(double) * 3 * (size_t)na);
    } else {
        /* Correlations of the pixel residual of the lobes we have: computing them on the pixels
         * (not as corr - closed-form products) keeps a sub-pixel sun from looking unexplained
         * merely because it is not at its coarse pixel's centre. */
        const efl_level *lv = d->lv;
        size_t np3 = (size_t)3 * lv->w * lv->h;
        double *r = sl_malloc(sizeof(double) * np3);
        efl_eval ev = {lv, d->threads, EFL_CUT, r, NULL};
        efl_objective(&ev, lobes, n_have);
        for (size_t i = 0; i < np3; i++)
            r[i] = -r[i]; /* map - model */
        dict_job jb = {d, r, res0};
        efl_parallel(d->threads, lv->h, dict_row, &jb);
        free(r);
    }
    memcpy(res, res0, sizeof(double) * 3 * (size_t)na);
    int *atom = sl_malloc(sizeof(int) * add);
    double *bb = sl_malloc(sizeof(double) * 3 * add),
           *c = sl_calloc(3 * (size_t)add, sizeof(double));
    double *Am = sl_malloc(sizeof(double) * (size_t)add * add);
    unsigned char *used = sl_calloc((size_t)na, 1);
    for (int m = 0; m < add; m++) {
        int best = -1;
        double bestg = 0;
        for (int b = 0; b < na; b++) {
            if (used[b]) continue;
            double g = 0;
            for (int ch = 0; ch < 3; ch++)
                if (res[b * 3 + ch] > 0) g += res[b * 3 + ch] * res[b * 3 + ch];
            g /= d->self[b];
            if (g > bestg) {
                bestg = g;
                best = b;
            }
        }
        if (best < 0) {
            /* Nothing left to explain (black map or exact fit): park the lobe, unweighted, at
             * the unused atom with the largest correlation so lobes stay distinct. */
            double bc = -1;
            for (int b = 0; b < na; b++) {
                double v = d->corr[b * 3] + d->corr[b * 3 + 1] + d->corr[b * 3 + 2];
                if (!used[b] && v > bc) {
                    bc = v;
                    best = b;
                }
            }
            if (best < 0) best = m % na;
        }
        used[best] = 1;
        atom[m] = best;
        sl_lobe *L = &lobes[n_have + m];
        efl_dict_atom(d, best, L->dir, &L->lambda);
        double *col = gcol + (size_t)m * na;
        for (int b = 0; b < na; b++)
            col[b] = efl_sg_inner(amu[b], aa[b], amu[best], aa[best]);
        for (int ch = 0; ch < 3; ch++) {
            double v = res[best * 3 + ch] / d->self[best];
            c[m * 3 + ch] = v > 0 ? v : 0;
        }
        /* Re-solve the weights of all added lobes: A_ik = <G_i, G_k>, b_i = <r0, G_i>. */
        int k = m + 1;
        for (int i = 0; i < k; i++) {
            for (int q = 0; q < k; q++)
                Am[(size_t)i * k + q] = gcol[(size_t)q * na + atom[i]];
            for (int ch = 0; ch < 3; ch++)
                bb[i * 3 + ch] = res0[atom[i] * 3 + ch];
        }
        efl_nnls(Am, k, bb, c);
        memcpy(res, res0, sizeof(double) * 3 * (size_t)na);
        for (int i = 0; i < k; i++) {
            const double *ci = c + i * 3, *gi = gcol + (size_t)i * na;
            if (ci[0] == 0 && ci[1] == 0 && ci[2] == 0) continue;
            for (int b = 0; b < na; b++)
                for (int ch = 0; ch < 3; ch++)
                    res[b * 3 + ch] -= ci[ch] * gi[b];
        }
    }
    for (int m = 0; m < add; m++)
        for (int ch = 0; ch < 3; ch++)
            lobes[n_have + m].rgb[ch] = c[m * 3 + ch];
    free(Am);
    free(bb);
    free(c);
    free(atom);
    free(used);
    free(res0);
    free(res);
    free(gcol);
    free(amu);
    free(aa);
}
