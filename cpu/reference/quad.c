/* quad.c: globally adaptive Gauss-Kronrod G7/K15 quadrature in double (see quad.h). The error
 * estimate follows QUADPACK's QK15 (Piessens et al. 1983): err = resasc * min(1,
 * (200 |K15 - G7| / resasc)^1.5), floored by 50 eps resabs, which is conservative for smooth
 * integrands and close to the true error once the rule resolves the integrand. */
#include "quad.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>

/* Kronrod abscissae (positive half, descending) and weights; Gauss weights for the odd nodes. */
static const double xgk[8] = {
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.000000000000000000000000000000000};
static const double wgk[8] = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
    0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
    0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
static const double wg[4] = {
    0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
    0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

static double safe_eval(slq_fn f, void *ctx, double x) {
    double y = f(x, ctx);
    return isfinite(y) ? y : 0.0;
}

double slq_gk15(slq_fn f, void *ctx, double a, double b, double *err_est) {
    double c = 0.5 * (a + b), hl = 0.5 * (b - a), ahl = fabs(hl);
    double fc = safe_eval(f, ctx, c);
    double rk = fc * wgk[7], rg = fc * wg[3], rabs = fabs(rk);
    double fv1[7], fv2[7];
    for (int j = 0; j < 7; j++) {
        double dx = hl * xgk[j];
        fv1[j] = safe_eval(f, ctx, c - dx);
        fv2[j] = safe_eval(f, ctx, c + dx);
        double s = fv1[j] + fv2[j];
        rk += wgk[j] * s;
        rabs += wgk[j] * (fabs(fv1[j]) + fabs(fv2[j]));
        if (j % 2 == 1) rg += wg[j / 2] * s;
    }
    double mean = 0.5 * rk, asc = wgk[7] * fabs(fc - mean);
    for (int j = 0; j < 7; j++)
        asc += wgk[j] * (fabs(fv1[j] - mean) + fabs(fv2[j] - mean));
    double err = fabs((rk - rg) * hl);
    asc *= ahl;
    rabs *= ahl;
    if (asc != 0.0 && err != 0.0) {
        double r = pow(200.0 * err / asc, 1.5);
        err = asc * (r < 1.0 ? r : 1.0);
    }
    if (rabs > DBL_MIN / (50.0 * DBL_EPSILON)) {
        double floor_ = 50.0 * DBL_EPSILON * rabs;
        if (err < floor_) err = floor_;
    }
    if (err_est) *err_est = err;
    return rk * hl;
}

/* A max-heap of intervals keyed by error estimate. */
enum { SLQ_MAX_IV = 2048 };
typedef struct {
    double a, b, val, err;
    int depth;
} slq_iv;

static void heap_push(slq_iv *h, int *n, slq_iv iv) {
    int i = (*n)++;
    h[i] = iv;
    while (i > 0) {
        int p = (i - 1) / 2;
        if (h[p].err >= h[i].err) break;
        slq_iv t = h[p];
        h[p] = h[i];
        h[i] = t;
        i = p;
    }
}

static slq_iv heap_pop(slq_iv *h, int *n) {
    slq_iv top = h[0];
    h[0] = h[--(*n)];
    int i = 0;
    for (;;) {
        int l = 2 * i + 1, r = l + 1, m = i;
        if (l < *n && h[l].err > h[m].err) m = l;
        if (r < *n && h[r].err > h[m].err) m = r;
        if (m == i) break;
        slq_iv t = h[m];
        h[m] = h[i];
        h[i] = t;
        i = m;
    }
    return top;
}

static int cmp_d(const void *x, const void *y) {
    double a = *(const double *)x, b = *(const double *)y;
    return a < b ? -1 : (a > b);
}

double slq_integrate_pts(slq_fn f, void *ctx, double a, double b, const double *pts, size_t npts,
                         double rel_tol, double abs_tol, int max_depth, double *err_est) {
    if (a == b) {
        if (err_est) *err_est = 0.0;
        return 0.0;
    }
    if (a > b) {
        double r = slq_integrate_pts(f, ctx, b, a, pts, npts, rel_tol, abs_tol, max_depth, err_est);
        return -r;
    }
    if (max_depth > 50) max_depth = 50;
    if (max_depth < 0) max_depth = 0;
    /* Sorted, de-duplicated cut points strictly inside (a, b). */
    double cut[66];
    int nc = 0;
    cut[nc++] = a;
    for (size_t i = 0; i < npts && nc < 65; i++)
        if (isfinite(pts[i]) && pts[i] > a && pts[i] < b) cut[nc++] = pts[i];
    qsort(cut + 1, (size_t)(nc - 1), sizeof(double), cmp_d);
    int m = 1;
    for (int i = 1; i < nc; i++)
        if (cut[i] > cut[m - 1]) cut[m++] = cut[i];
    nc = m;
    cut[nc++] = b;

    slq_iv heap[SLQ_MAX_IV];
    int n = 0;
    double total = 0.0, total_err = 0.0, frozen_err = 0.0, frozen_val = 0.0;
    for (int i = 0; i + 1 < nc; i++) {
        slq_iv iv = {cut[i], cut[i + 1], 0.0, 0.0, 0};
        iv.val = slq_gk15(f, ctx, iv.a, iv.b, &iv.err);
        total += iv.val;
        total_err += iv.err;
        heap_push(heap, &n, iv);
    }
    while (n > 0) {
        double tol = fmax(abs_tol, rel_tol * fabs(total));
        if (total_err <= tol) break;
        if (n + 2 > SLQ_MAX_IV) break;
        slq_iv iv = heap_pop(heap, &n);
        double mid = 0.5 * (iv.a + iv.b);
        if (iv.depth >= max_depth || !(mid > iv.a && mid < iv.b)) {
            /* Cannot refine: its error stays in the budget but it leaves the heap. */
            frozen_err += iv.err;
            frozen_val += iv.val;
            if (n == 0) break;
            continue;
        }
        slq_iv l = {iv.a, mid, 0.0, 0.0, iv.depth + 1}, r = {mid, iv.b, 0.0, 0.0, iv.depth + 1};
        l.val = slq_gk15(f, ctx, l.a, l.b, &l.err);
        r.val = slq_gk15(f, ctx, r.a, r.b, &r.err);
        total += l.val + r.val - iv.val;
        total_err += l.err + r.err - iv.err;
        heap_push(heap, &n, l);
        heap_push(heap, &n, r);
    }
    /* Re-sum from the leaves to avoid drift from the running updates. */
    double s = frozen_val, e = frozen_err;
    for (int i = 0; i < n; i++) {
        s += heap[i].val;
        e += heap[i].err;
    }
    if (err_est) *err_est = e;
    return s;
}

double slq_integrate(slq_fn f, void *ctx, double a, double b, double rel_tol, double abs_tol,
                     int max_depth, double *err_est) {
    return slq_integrate_pts(f, ctx, a, b, NULL, 0, rel_tol, abs_tol, max_depth, err_est);
}

/* ---- vector form (all components share the interval tree) ---- */

/* One interval: [a, b], and per component its value and error estimate. */
typedef struct vq_iv {
    double a, b;
    double *val, *err;
} vq_iv;

/* K15 on [a, b] for n components; fv is scratch of 15 n doubles. */
static void vq_gk15(slq_vfn f, void *ctx, int n, double a, double b, double *fv, double *val,
                    double *err) {
    double c = 0.5 * (a + b), hl = 0.5 * (b - a), ahl = fabs(hl);
    f(c, ctx, fv);
    for (int j = 0; j < 7; j++) {
        f(c - hl * xgk[j], ctx, fv + (size_t)(1 + 2 * j) * (size_t)n);
        f(c + hl * xgk[j], ctx, fv + (size_t)(2 + 2 * j) * (size_t)n);
    }
    for (int k = 0; k < n; k++) {
        double fc = isfinite(fv[k]) ? fv[k] : 0.0;
        double rk = fc * wgk[7], rg = fc * wg[3], rabs = fabs(rk);
        double f1[7], f2[7];
        for (int j = 0; j < 7; j++) {
            f1[j] = fv[(size_t)(1 + 2 * j) * (size_t)n + (size_t)k];
            f2[j] = fv[(size_t)(2 + 2 * j) * (size_t)n + (size_t)k];
            if (!isfinite(f1[j])) f1[j] = 0.0;
            if (!isfinite(f2[j])) f2[j] = 0.0;
            rk += wgk[j] * (f1[j] + f2[j]);
            rabs += wgk[j] * (fabs(f1[j]) + fabs(f2[j]));
            if (j % 2 == 1) rg += wg[j / 2] * (f1[j] + f2[j]);
        }
        double mean = 0.5 * rk, asc = wgk[7] * fabs(fc - mean);
        for (int j = 0; j < 7; j++)
            asc += wgk[j] * (fabs(f1[j] - mean) + fabs(f2[j] - mean));
        double e = fabs((rk - rg) * hl);
        asc *= ahl;
        rabs *= ahl;
        if (asc != 0.0 && e != 0.0) {
            double r = pow(200.0 * e / asc, 1.5);
            e = asc * (r < 1.0 ? r : 1.0);
        }
        if (rabs > DBL_MIN / (50.0 * DBL_EPSILON)) e = fmax(e, 50.0 * DBL_EPSILON * rabs);
        val[k] = rk * hl;
        err[k] = e;
    }
}

/* Integrates the n-vector f over [a, b] split at pts (any order; outside points ignored), until
 * every component k has summed error <= max(rel |I_k|, abs_tol[k]) or max_iv intervals exist.
 * Bisects the interval with the largest error relative to its component's tolerance. */
void slq_integrate_vec(slq_vfn f, void *ctx, int n, double a, double b, const double *pts,
                       size_t npts, double rel, const double *abs_tol, int max_iv, double *res) {
    for (int k = 0; k < n; k++)
        res[k] = 0.0;
    if (!(b > a)) return;
    double *cut = malloc((npts + 2) * sizeof *cut);
    size_t nc = 0;
    cut[nc++] = a;
    for (size_t i = 0; i < npts; i++)
        if (isfinite(pts[i]) && pts[i] > a && pts[i] < b) cut[nc++] = pts[i];
    qsort(cut + 1, nc - 1, sizeof *cut, cmp_d);
    size_t m = 1;
    for (size_t i = 1; i < nc; i++)
        if (cut[i] > cut[m - 1] + 1e-15 * (b - a)) cut[m++] = cut[i];
    nc = m;
    cut[nc++] = b;
    int cap = max_iv > (int)nc ? max_iv : (int)nc;
    vq_iv *iv = malloc((size_t)cap * sizeof *iv);
    double *store = malloc((size_t)cap * 2 * (size_t)n * sizeof *store);
    double *fv = malloc(15 * (size_t)n * sizeof *fv);
    double *tot = calloc((size_t)n, sizeof *tot), *terr = calloc((size_t)n, sizeof *terr);
    int niv = 0;
    for (size_t i = 0; i + 1 < nc; i++) {
        vq_iv *v = &iv[niv];
        v->a = cut[i];
        v->b = cut[i + 1];
        v->val = store + (size_t)niv * 2 * (size_t)n;
        v->err = v->val + n;
        vq_gk15(f, ctx, n, v->a, v->b, fv, v->val, v->err);
        for (int k = 0; k < n; k++) {
            tot[k] += v->val[k];
            terr[k] += v->err[k];
        }
        niv++;
    }
    while (niv + 1 < cap) {
        /* Done when every component meets its tolerance. */
        int done = 1;
        for (int k = 0; k < n && done; k++)
            if (terr[k] > fmax(rel * fabs(tot[k]), abs_tol[k])) done = 0;
        if (done) break;
        int best = -1;
        double bs = 0.0;
        for (int i = 0; i < niv; i++) {
            double s = 0.0;
            for (int k = 0; k < n; k++) {
                double t = fmax(rel * fabs(tot[k]), abs_tol[k]);
                s = fmax(s, iv[i].err[k] / t);
            }
            if (s > bs && 0.5 * (iv[i].a + iv[i].b) > iv[i].a &&
                0.5 * (iv[i].a + iv[i].b) < iv[i].b) {
                bs = s;
                best = i;
            }
        }
        if (best < 0) break;
        vq_iv *p = &iv[best], *q = &iv[niv];
        double mid = 0.5 * (p->a + p->b);
        q->val = store + (size_t)niv * 2 * (size_t)n;
        q->err = q->val + n;
        q->a = mid;
        q->b = p->b;
        for (int k = 0; k < n; k++) {
            tot[k] -= p->val[k];
            terr[k] -= p->err[k];
        }
        p->b = mid;
        vq_gk15(f, ctx, n, p->a, p->b, fv, p->val, p->err);
        vq_gk15(f, ctx, n, q->a, q->b, fv, q->val, q->err);
        for (int k = 0; k < n; k++) {
            tot[k] += p->val[k] + q->val[k];
            terr[k] += p->err[k] + q->err[k];
        }
        niv++;
    }
    /* Re-sum from the leaves (no drift from the running updates). */
    for (int i = 0; i < niv; i++)
        for (int k = 0; k < n; k++)
            res[k] += iv[i].val[k];
    free(cut);
    free(iv);
    free(store);
    free(fv);
    free(tot);
    free(terr);
}

void slq_pts_push(slq_pts *l, double x) {
    if (l->n == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 64;
        l->v = realloc(l->v, l->cap * sizeof *l->v);
        if (!l->v) abort();
    }
    l->v[l->n++] = x;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

void slq_pts_sort(slq_pts *l) {
    qsort(l->v, l->n, sizeof *l->v, cmp_double);
}

double slq_bisect(slq_fn f, void *ctx, double a, double b, double u) {
    double fa = f(a, ctx) - u;
    for (int it = 0; it < 200 && b - a > 1e-15; it++) {
        double mid = 0.5 * (a + b), fm = f(mid, ctx) - u;
        if ((fm < 0.0) == (fa < 0.0)) {
            a = mid;
            fa = fm;
        } else {
            b = mid;
        }
    }
    return 0.5 * (a + b);
}
