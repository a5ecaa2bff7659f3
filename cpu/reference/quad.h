/* quad.h: adaptive Gauss-Kronrod (G7/K15) quadrature in double with error control, for the
 * reference backend (Marschner TRT convolution, d'Eon N_p, furnace integrals, SRBF exact
 * integrals). Pure functions, no global state; the scalar forms do not allocate (fixed-size
 * interval stack), the vector form does. */
#ifndef SL_QUAD_H
#define SL_QUAD_H

#include <stddef.h>

typedef double (*slq_fn)(double x, void *ctx);

/* Integrates f over [a, b] (a > b gives the negative) by globally adaptive G7/K15: the interval
 * with the largest error estimate is bisected until the summed estimate is <= max(abs_tol,
 * rel_tol * |I|), or until max_depth bisection levels (<= 50) / 4000 intervals are reached.
 * *err_est (may be NULL) receives the final estimated absolute error. Non-finite integrand
 * values are treated as 0 and never propagate. */
double slq_integrate(slq_fn f, void *ctx, double a, double b, double rel_tol, double abs_tol,
                     int max_depth, double *err_est);

/* The same over [a, b] split at the given breakpoints (any order, duplicates and points outside
 * (a, b) ignored; at most 64 used): pieces share one global error budget, so a narrow feature
 * between breakpoints is resolved without over-refining smooth pieces. Bracket a narrow
 * feature (a spike of width s at x0: breakpoints near x0 - s and x0 + s): a breakpoint at its
 * centre alone can miss it, since no rule samples an interval's endpoints. */
double slq_integrate_pts(slq_fn f, void *ctx, double a, double b, const double *pts, size_t npts,
                         double rel_tol, double abs_tol, int max_depth, double *err_est);

/* One fixed 15-point Gauss-Kronrod rule on [a, b] (no adaptivity); *err_est = |K15 - G7|. */
double slq_gk15(slq_fn f, void *ctx, double a, double b, double *err_est);

/* A vector integrand: writes n values at x into out. */
typedef void (*slq_vfn)(double x, void *ctx, double *out);

/* Integrates the n-vector f over [a, b] (a < b) split at pts (any order; outside points ignored)
 * by globally adaptive G7/K15 on one shared interval tree, until every component k has summed
 * error <= max(rel |I_k|, abs_tol[k]) or max_iv intervals exist; bisects the interval with the
 * largest error relative to its component's tolerance. Results in res[0..n-1] (allocates). */
void slq_integrate_vec(slq_vfn f, void *ctx, int n, double a, double b, const double *pts,
                       size_t npts, double rel, const double *abs_tol, int max_iv, double *res);

/* x in [a, b] with f(x) = u by bisection, f monotone on [a, b] and u between f(a) and f(b):
 * at most 200 halvings, until b - a <= 1e-15; returns the last interval's midpoint. */
double slq_bisect(slq_fn f, void *ctx, double a, double b, double u);

/* A growable list of breakpoints for slq_integrate_pts: push appends (aborts when out of
 * memory), sort puts them in ascending order; start from {0}, free v when done. */
typedef struct slq_pts {
    double *v;
    size_t n, cap;
} slq_pts;
void slq_pts_push(slq_pts *l, double x);
void slq_pts_sort(slq_pts *l);

#endif
