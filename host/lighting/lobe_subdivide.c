/* lobe_subdivide.c: the broad SRBF lobes as one sum of narrower sub-lobes on a fixed direction
 * set (lobe_subdivide.h). */
#include "lighting/lobe_subdivide.h"

#include "lighting/sphere_points.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void sl_subdiv_params_default(sl_subdiv_params *p) {
    p->lambda_min = SL_SUBDIV_LAMBDA_MIN;
    p->ratio = SL_SUBDIV_RATIO;
    p->cut = SL_SUBDIV_CUT;
    p->samples = SL_SUBDIV_SAMPLES;
    p->width = SL_SUBDIV_WIDTH;
}

int sl_subdiv_budget(int narrow, double width) {
    sl_subdiv_params p;
    sl_subdiv_params_default(&p);
    p.width = width;
    return narrow + sl_subdiv_set_size(&p);
}

int sl_subdiv_set_size(const sl_subdiv_params *p) {
    if (!(p->width > 0)) return SL_SUBDIV_MAX;
    double m = ceil(4.0 * M_PI * (p->ratio / p->width) * (p->ratio / p->width));
    return m < SL_SUBDIV_MAX ? (int)m : SL_SUBDIV_MAX;
}

/* Solves the n x n system A x = b (A, b overwritten) by Gaussian elimination with partial
 * pivoting; returns -1 when singular. */
static int solve(double *A, double *b, int n, double *x) {
    for (int c = 0; c < n; c++) {
        int p = c;
        for (int r = c + 1; r < n; r++)
            if (fabs(A[r * n + c]) > fabs(A[p * n + c])) p = r;
        if (fabs(A[p * n + c]) < 1e-300) return -1;
        if (p != c) {
            for (int k = 0; k < n; k++) {
                double t = A[c * n + k];
                A[c * n + k] = A[p * n + k], A[p * n + k] = t;
            }
            double t = b[c];
            b[c] = b[p], b[p] = t;
        }
        for (int r = c + 1; r < n; r++) {
            double f = A[r * n + c] / A[c * n + c];
            for (int k = c; k < n; k++)
                A[r * n + k] -= f * A[c * n + k];
            b[r] -= f * b[c];
        }
    }
    for (int r = n - 1; r >= 0; r--) {
        double s = b[r];
        for (int k = r + 1; k < n; k++)
            s -= A[r * n + k] * x[k];
        x[r] = s / A[r * n + r];
    }
    return 0;
}

/* Non-negative least squares min |A x - b|^2, x >= 0, from the normal equations (G = A^T A,
 * h = A^T b, n <= SL_SUBDIV_MAX): Lawson & Hanson's active-set method. */
static void nnls(const double *G, const double *h, int n, double *x) {
    int P[SL_SUBDIV_MAX] = {0}, idx[SL_SUBDIV_MAX];
    double w[SL_SUBDIV_MAX], z[SL_SUBDIV_MAX], rhs[SL_SUBDIV_MAX], zs[SL_SUBDIV_MAX];
    double *M = sl_malloc(sizeof(double) * SL_SUBDIV_MAX * SL_SUBDIV_MAX);
    for (int i = 0; i < n; i++)
        x[i] = 0;
    double hmax = 0;
    for (int i = 0; i < n; i++)
        hmax = fmax(hmax, fabs(h[i]));
    double tol = 1e-12 * (hmax > 0 ? hmax : 1);
    for (int outer = 0; outer < 3 * n; outer++) {
        int jmax = -1;
        for (int i = 0; i < n; i++) {
            double s = h[i];
            for (int k = 0; k < n; k++)
                s -= G[i * n + k] * x[k];
            w[i] = s;
            if (!P[i] && s > tol && (jmax < 0 || s > w[jmax])) jmax = i;
        }
        if (jmax < 0) break;
        P[jmax] = 1;
        for (int inner = 0; inner < 3 * n; inner++) {
            int m = 0;
            for (int i = 0; i < n; i++)
                if (P[i]) idx[m++] = i;
            for (int a = 0; a < m; a++) {
                rhs[a] = h[idx[a]];
                for (int b = 0; b < m; b++)
                    M[a * m + b] = G[idx[a] * n + idx[b]];
            }
            if (solve(M, rhs, m, zs)) { /* degenerate: drop the newest */
                P[jmax] = 0;
                break;
            }
            for (int i = 0; i < n; i++)
                z[i] = 0;
            int neg = 0;
            for (int a = 0; a < m; a++) {
                z[idx[a]] = zs[a];
                neg |= zs[a] <= 0;
            }
            if (!neg) {
                for (int i = 0; i < n; i++)
                    x[i] = z[i];
                break;
            }
            double alpha = 1;
            for (int i = 0; i < n; i++)
                if (P[i] && z[i] <= 0) alpha = fmin(alpha, x[i] / (x[i] - z[i]));
            for (int i = 0; i < n; i++) {
                x[i] += alpha * (z[i] - x[i]);
                if (P[i] && x[i] <= 1e-15) P[i] = 0, x[i] = 0;
            }
        }
    }
    free(M);
}

/* The broad light's rgb sum at unit w */
static double broad_sum(const sl_lobe *const *b, int nb, const double w[3]) {
    double s = 0;
    for (int j = 0; j < nb; j++) {
        const sl_lobe *l = b[j];
        double d = w[0] * l->dir[0] + w[1] * l->dir[1] + w[2] * l->dir[2];
        s += (l->rgb[0] + l->rgb[1] + l->rgb[2]) * exp(2.0 * (d - 1.0) / (l->lambda * l->lambda));
    }
    return s;
}

/* The set's axis: the broad light's mean direction, sum_b P_b xi_b with P_b the lobe's power
 * (rgb sum x integral of G), normalised. It is linear in the lobes, so every cut of the light
 * gives the same axis, and a single lobe gets its own axis as a pole (the best set for it).
 * When the light is spread all round (the mean below a fifth of the power: a near-uniform map)
 * the direction is ill-conditioned and the world's +Y (the hair's up) is used instead. */
static void set_axis(const sl_lobe *const *b, int nb, double axis[3]) {
    double m[3] = {0, 0, 0}, pw = 0;
    for (int j = 0; j < nb; j++) {
        double p = (b[j]->rgb[0] + b[j]->rgb[1] + b[j]->rgb[2]) * sl_lobe_integral(b[j]->lambda);
        for (int k = 0; k < 3; k++)
            m[k] += p * b[j]->dir[k];
        pw += p;
    }
    double l = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    if (!(l > 0.2 * pw)) {
        axis[0] = 0, axis[1] = 1, axis[2] = 0;
        return;
    }
    for (int k = 0; k < 3; k++)
        axis[k] = m[k] / l;
}

/* Directions of the M-point set about axis where the broad light is >= level: written to d
 * (room for dmax; NULL to count only), returns the count (stops counting past dmax + 1). */
static int set_kept(const sl_lobe *const *b, int nb, const double axis[3], int M, double level,
                    double (*d)[3], int dmax) {
    double u[3], v[3], p[3];
    sl_axis_frame(axis, u, v);
    int k = 0;
    for (int i = 0; i < M && k <= dmax; i++) {
        sl_fib_axis_point(i, M, axis, u, v, p);
        if (broad_sum(b, nb, p) < level) continue;
        if (d && k < dmax) memcpy(d[k], p, sizeof p);
        k++;
    }
    return k;
}

/* The set size M whose kept count fits nmax: from an estimate (nmax over the share of a
 * 4096-point set kept, less a fifth), up to the last M before the first that keeps more than nmax,
 * or down to the first that fits. Deterministic for a given light; 0 when no M keeps
 * SL_SUBDIV_MIN directions. */
static int set_size(const sl_lobe *const *b, int nb, const double axis[3], double level, int nmax) {
    const int big = 4096, top = 1 << 16;
    int kb = set_kept(b, nb, axis, big, level, NULL, big);
    if (kb <= 0) return 0;
    int M = (int)(0.8 * nmax * (double)big / kb);
    if (M < SL_SUBDIV_MIN) M = SL_SUBDIV_MIN;
    if (M > top) M = top;
    int k = set_kept(b, nb, axis, M, level, NULL, nmax);
    while (k > nmax && M > SL_SUBDIV_MIN)
        k = set_kept(b, nb, axis, --M, level, NULL, nmax);
    if (k > nmax) return 0;
    int best = k >= SL_SUBDIV_MIN ? M : 0;
    while (M < top) {
        k = set_kept(b, nb, axis, ++M, level, NULL, nmax);
        if (k > nmax) break;
        if (k >= SL_SUBDIV_MIN) best = M;
    }
    return best;
}

/* c[k * n + s] >= 0 fitting the broad light's channel k with the n sub-lobes d[s] of width
 * lam_s, each channel's power kept exactly; returns the fit's relative L2 (channels together). */
static double fit_weights(const sl_lobe *const *b, int nb, double (*d)[3], int n, double lam_s,
                          int samples, double *c) {
    double *G = sl_calloc((size_t)n * n, sizeof *G), h[3][SL_SUBDIV_MAX] = {{0}}, bb = 0;
    double a[SL_SUBDIV_MAX];
    int nz[SL_SUBDIV_MAX];
    const double c2s = 2.0 / (lam_s * lam_s);
    for (int k = 0; k < samples; k++) {
        /* equal-area samples on the whole sphere, poles on z (not the set's axis), offset by half
         * a band */
        double z = 1.0 - (2.0 * k + 1.0) / samples, r = sqrt(fmax(0.0, 1.0 - z * z)),
               ph = SL_GOLDEN_ANGLE * k;
        double w[3] = {r * cos(ph), r * sin(ph), z}, L[3] = {0, 0, 0};
        for (int j = 0; j < nb; j++) {
            const sl_lobe *l = b[j];
            double g = exp(2.0 * (w[0] * l->dir[0] + w[1] * l->dir[1] + w[2] * l->dir[2] - 1.0) /
                           (l->lambda * l->lambda));
            for (int q = 0; q < 3; q++)
                L[q] += l->rgb[q] * g;
        }
        int m = 0;
        for (int s = 0; s < n; s++) {
            a[s] = exp(c2s * (w[0] * d[s][0] + w[1] * d[s][1] + w[2] * d[s][2] - 1.0));
            if (a[s] > 1e-12) nz[m++] = s;
        }
        for (int x = 0; x < m; x++) {
            int s = nz[x];
            for (int q = 0; q < 3; q++)
                h[q][s] += a[s] * L[q];
            for (int y = 0; y < m; y++)
                G[s * n + nz[y]] += a[s] * a[nz[y]];
        }
        bb += L[0] * L[0] + L[1] * L[1] + L[2] * L[2];
    }
    double e2 = bb;
    for (int q = 0; q < 3; q++) {
        double *x = c + q * n;
        nnls(G, h[q], n, x);
        /* each channel's power kept: sum_s c_s int G_s = sum_b rgb_b int G_b */
        double want = 0, got = 0;
        for (int j = 0; j < nb; j++)
            want += b[j]->rgb[q] * sl_lobe_integral(b[j]->lambda);
        for (int s = 0; s < n; s++)
            got += x[s];
        got *= sl_lobe_integral(lam_s);
        double scale = got > 0 ? want / got : 0;
        for (int s = 0; s < n; s++)
            x[s] *= scale;
        for (int s = 0; s < n; s++) {
            /* |A x - b|^2 = x^T G x - 2 x^T h + b^T b */
            e2 -= 2 * x[s] * h[q][s];
            for (int t = 0; t < n; t++)
                e2 += x[s] * G[s * n + t] * x[t];
        }
    }
    free(G);
    return bb > 0 ? sqrt(fmax(0.0, e2) / bb) : 0;
}

void sl_lobes_subdivide(const sl_lobes *in, const int *idx, int n, int budget,
                        const sl_subdiv_params *p, sl_lobes *out, int *nbroad, int *nsub,
                        double *rel_l2) {
    sl_subdiv_params def;
    if (!p) sl_subdiv_params_default(&def), p = &def;
    memset(out, 0, sizeof *out);
    if (rel_l2) *rel_l2 = 0;
    const sl_lobe **b = sl_malloc((n ? n : 1) * sizeof *b);
    char *broad = sl_calloc(n ? n : 1, 1);
    int nb = 0;
    for (int j = 0; j < n; j++)
        if (in->lobe[idx[j]].lambda > p->lambda_min) broad[j] = 1, nb++;
    /* the set for the broad lobes; a lobe narrower than its sub-lobes would be
     * (lambda' > SL_SUBDIV_MAX_WIDTH lambda) stays whole and the set is planned again for the
     * rest with what is left of the budget (the broad set only shrinks, so this ends) */
    int M = 0, nd = 0;
    double lam_s = 0, level = 0, axis[3] = {0, 1, 0};
    while (nb > 0) {
        int m = 0;
        for (int j = 0; j < n; j++)
            if (broad[j]) b[m++] = &in->lobe[idx[j]];
        int room = budget - (n - nb);
        if (room > SL_SUBDIV_MAX) room = SL_SUBDIV_MAX;
        /* the level: a share of the light's largest value at a lobe axis (not at the set's
         * points, so it does not depend on M) */
        double peak = 0;
        for (int j = 0; j < nb; j++)
            peak = fmax(peak, broad_sum(b, nb, b[j]->dir));
        level = p->cut * peak;
        set_axis(b, nb, axis);
        M = room >= SL_SUBDIV_MIN && peak > 0 ? set_size(b, nb, axis, level, room) : 0;
        if (!M) break;
        int Mw = sl_subdiv_set_size(p); /* no finer than the width asks */
        if (M > Mw) M = Mw;
        lam_s = p->ratio * sqrt(4.0 * M_PI / M);
        int dropped = 0;
        for (int j = 0; j < n; j++)
            if (broad[j] && lam_s > SL_SUBDIV_MAX_WIDTH * in->lobe[idx[j]].lambda)
                broad[j] = 0, nb--, dropped = 1;
        if (!dropped) break;
        M = 0;
    }
    double(*d)[3] = sl_malloc(sizeof(double[3]) * SL_SUBDIV_MAX);
    double *c = sl_malloc(sizeof(double) * 3 * SL_SUBDIV_MAX);
    if (M) nd = set_kept(b, nb, axis, M, level, d, SL_SUBDIV_MAX);
    if (nd > SL_SUBDIV_MAX) nd = SL_SUBDIV_MAX;
    double l2 = 0;
    if (nd >= SL_SUBDIV_MIN) {
        int samples = p->samples > 8 * M ? p->samples : 8 * M;
        l2 = fit_weights(b, nb, d, nd, lam_s, samples, c);
    } else {
        nd = 0, nb = 0;
    }
    out->lobe = sl_malloc((n + nd ? n + nd : 1) * sizeof *out->lobe);
    int o = 0, ns = 0;
    for (int j = 0; j < n; j++)
        if (!nd || !broad[j]) out->lobe[o++] = in->lobe[idx[j]];
    for (int s = 0; s < nd; s++) {
        /* sub-lobes with no weight in any channel are left out */
        if (!(c[s] > 0 || c[nd + s] > 0 || c[2 * nd + s] > 0)) continue;
        sl_lobe *l = &out->lobe[o++];
        memcpy(l->dir, d[s], sizeof l->dir);
        l->lambda = lam_s;
        for (int q = 0; q < 3; q++)
            l->rgb[q] = c[q * nd + s];
        ns++;
    }
    out->count = o;
    out->rel_l2 = out->lobe_conv_rel_l2 = -1;
    if (nbroad) *nbroad = nd ? nb : 0;
    if (nsub) *nsub = ns;
    if (rel_l2) *rel_l2 = l2;
    free(d);
    free(c);
    free(b);
    free(broad);
}
