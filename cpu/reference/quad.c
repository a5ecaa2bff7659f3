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
