/* lobe_subdivide.c: a broad SRBF lobe as a sum of narrower sub-lobes (lobe_subdivide.h). */
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
    int P[SL_SUBDIV_MAX] = {0};
    double w[SL_SUBDIV_MAX], z[SL_SUBDIV_MAX], M[SL_SUBDIV_MAX * SL_SUBDIV_MAX], rhs[SL_SUBDIV_MAX],
        zs[SL_SUBDIV_MAX];
    int idx[SL_SUBDIV_MAX];
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
}

/* The set for a lobe of width lam allotted nmax sub-lobes: returns M (0: not subdivided), the
 * sub-lobe width *lam_s and the cut *zc (directions with z >= zc along the axis are kept). */
static int plan(double lam, int nmax, const sl_subdiv_params *p, double *lam_s, double *zc) {
    if (nmax > SL_SUBDIV_MAX) nmax = SL_SUBDIV_MAX;
    if (!(lam > p->lambda_min) || nmax < SL_SUBDIV_MIN) return 0;
    /* directions kept: z >= zc where G(z) = exp(2 (z - 1) / lambda^2) >= cut */
    *zc = 1.0 + lam * lam * log(p->cut) / 2.0;
    /* the largest M whose kept count floor((1 - zc) (M - 1) / 2) + 1 fits nmax */
    int M = 0;
    for (int m = 2; m < 100000; m++) {
        int kept = *zc <= -1.0 ? m : (int)floor((1.0 - *zc) * (m - 1) / 2.0 + 1e-9) + 1;
        if (kept > nmax) break;
        M = m;
    }
    if (M < SL_SUBDIV_MIN) return 0;
    *lam_s = p->ratio * sqrt(4.0 * M_PI / M);
    /* sub-lobes about as wide as the lobe gain nothing */
    if (*lam_s > SL_SUBDIV_MAX_WIDTH * lam) return 0;
    return M;
}

/* The smallest allotment that subdivides a lobe of width lam, 0 when none up to SL_SUBDIV_MAX. */
static int min_count(double lam, const sl_subdiv_params *p) {
    double ls, zc;
    for (int n = SL_SUBDIV_MIN; n <= SL_SUBDIV_MAX; n++)
        if (plan(lam, n, p, &ls, &zc)) return n;
    return 0;
}

int sl_lobe_subdivide_one(const sl_lobe *in, int nmax, const sl_subdiv_params *p, sl_lobe *out,
                          double *rel_l2) {
    sl_subdiv_params def;
    if (!p) sl_subdiv_params_default(&def), p = &def;
    if (rel_l2) *rel_l2 = 0;
    out[0] = *in;
    if (nmax > SL_SUBDIV_MAX) nmax = SL_SUBDIV_MAX;
    double lam = in->lambda, lam_s, zc;
    int M = plan(lam, nmax, p, &lam_s, &zc);
    if (!M) return 1;
    double u[3], v[3], d[SL_SUBDIV_MAX][3];
    sl_axis_frame(in->dir, u, v);
    int n = 0;
    for (int i = 0; i < M && n < nmax; i++) {
        double z = 1.0 - 2.0 * i / (M - 1.0);
        if (z < zc && zc > -1.0) break;
        sl_fib_axis_point(i, M, in->dir, u, v, d[n++]);
    }
    if (n < SL_SUBDIV_MIN) return 1;
    /* normal equations on equal-area samples w_k (Fibonacci set on the whole sphere) */
    double G[SL_SUBDIV_MAX * SL_SUBDIV_MAX] = {0}, h[SL_SUBDIV_MAX] = {0}, a[SL_SUBDIV_MAX];
    double bb = 0;
    int S = p->samples > 16 ? p->samples : 16;
    double c2 = 2.0 / (lam * lam), c2s = 2.0 / (lam_s * lam_s);
    for (int k = 0; k < S; k++) {
        /* sample frame independent of the lobe axis, offset by half a band */
        double z = 1.0 - (2.0 * k + 1.0) / S, r = sqrt(fmax(0.0, 1.0 - z * z)),
               ph = SL_GOLDEN_ANGLE * k;
        double w[3] = {r * cos(ph), r * sin(ph), z};
        double b = exp(c2 * (w[0] * in->dir[0] + w[1] * in->dir[1] + w[2] * in->dir[2] - 1.0));
        for (int s = 0; s < n; s++)
            a[s] = exp(c2s * (w[0] * d[s][0] + w[1] * d[s][1] + w[2] * d[s][2] - 1.0));
        for (int s = 0; s < n; s++) {
            h[s] += a[s] * b;
            for (int t = 0; t < n; t++)
                G[s * n + t] += a[s] * a[t];
        }
        bb += b * b;
    }
    double c[SL_SUBDIV_MAX];
    nnls(G, h, n, c);
    /* total power kept exactly: sum c_s int G_s = int G */
    double pw = 0;
    for (int s = 0; s < n; s++)
        pw += c[s];
    pw *= sl_lobe_integral(lam_s);
    if (!(pw > 0)) return 1;
    double scale = sl_lobe_integral(lam) / pw;
    for (int s = 0; s < n; s++)
        c[s] *= scale;
    if (rel_l2) {
        /* |A c - b|^2 = c^T G c - 2 c^T h + b^T b */
        double e2 = bb;
        for (int s = 0; s < n; s++) {
            e2 -= 2 * c[s] * h[s];
            for (int t = 0; t < n; t++)
                e2 += c[s] * G[s * n + t] * c[t];
        }
        *rel_l2 = sqrt(fmax(0.0, e2) / bb);
    }
    /* sub-lobes with no weight are left out */
    int m = 0;
    for (int s = 0; s < n; s++) {
        if (!(c[s] > 0)) continue;
        sl_lobe *o = &out[m++];
        memcpy(o->dir, d[s], sizeof o->dir);
        o->lambda = lam_s;
        for (int k = 0; k < 3; k++)
            o->rgb[k] = c[s] * in->rgb[k];
    }
    return m;
}

typedef struct broad_order {
    int pos;
    double power;
} broad_order;

static int broad_cmp(const void *a, const void *b) {
    const broad_order *x = a, *y = b;
    if (x->power != y->power) return x->power > y->power ? -1 : 1;
    return x->pos - y->pos; /* ties: input order, so the result is deterministic */
}

void sl_lobes_subdivide(const sl_lobes *in, const int *idx, int n, int budget,
                        const sl_subdiv_params *p, sl_lobes *out, int **parent, int *nbroad,
                        int *nsub) {
    sl_subdiv_params def;
    if (!p) sl_subdiv_params_default(&def), p = &def;
    memset(out, 0, sizeof *out);
    int *want = sl_malloc((n ? n : 1) * sizeof *want);
    broad_order *ord = sl_malloc((n ? n : 1) * sizeof *ord);
    int nb = 0;
    for (int j = 0; j < n; j++) {
        const sl_lobe *lb = &in->lobe[idx[j]];
        want[j] = 1;
        if (lb->lambda > p->lambda_min)
            ord[nb++] = (broad_order){j, (lb->rgb[0] + lb->rgb[1] + lb->rgb[2]) *
                                             sl_lobe_integral(lb->lambda)};
    }
    qsort(ord, (size_t)nb, sizeof *ord, broad_cmp);
    /* the extras in rounds, broad lobes in order of decreasing power: first the smallest
     * allotment that subdivides each (while the budget lasts), then the rest in proportion to
     * power, then what rounding left, each lobe up to SL_SUBDIV_MAX */
    int extra = budget - n;
    double ptot = 0;
    for (int b = 0; b < nb; b++) {
        int m = min_count(in->lobe[idx[ord[b].pos]].lambda, p);
        if (m < 1 || m - 1 > extra) continue;
        want[ord[b].pos] = m;
        extra -= m - 1;
        ptot += ord[b].power;
    }
    int rest = extra;
    for (int b = 0; b < nb && extra > 0 && ptot > 0; b++) {
        if (want[ord[b].pos] < 2) continue;
        int give = (int)floor(rest * ord[b].power / ptot);
        if (give > SL_SUBDIV_MAX - want[ord[b].pos]) give = SL_SUBDIV_MAX - want[ord[b].pos];
        if (give > extra) give = extra;
        want[ord[b].pos] += give;
        extra -= give;
    }
    for (int b = 0; b < nb && extra > 0; b++) {
        if (want[ord[b].pos] < 2) continue;
        int give = SL_SUBDIV_MAX - want[ord[b].pos];
        if (give > extra) give = extra;
        want[ord[b].pos] += give;
        extra -= give;
    }
    int cap = 0;
    for (int j = 0; j < n; j++)
        cap += want[j];
    out->lobe = sl_malloc((cap ? cap : 1) * sizeof *out->lobe);
    int *par = sl_malloc((cap ? cap : 1) * sizeof *par);
    int m = 0, broad = 0, sub = 0;
    for (int j = 0; j < n; j++) {
        int c = sl_lobe_subdivide_one(&in->lobe[idx[j]], want[j], p, out->lobe + m, NULL);
        if (c > 1) broad++, sub += c;
        for (int q = 0; q < c; q++)
            par[m + q] = j;
        m += c;
    }
    out->count = m;
    out->rel_l2 = out->lobe_conv_rel_l2 = -1;
    if (parent)
        *parent = par;
    else
        free(par);
    if (nbroad) *nbroad = broad;
    if (nsub) *nsub = sub;
    free(want);
    free(ord);
}
