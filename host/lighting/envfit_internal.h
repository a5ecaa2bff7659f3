/* envfit_internal.h: pieces shared by the envfit_*.c files (not a public interface).
 *
 * A level is one image of the solid-angle-weighted pyramid. Pixel (x, y) of a w x h level has
 * the direction of numerics.md sec. 4, (st_y sp_x, ct_y, -st_y cp_x), and solid angle om_y. */
#ifndef SL_ENVFIT_INTERNAL_H
#define SL_ENVFIT_INTERNAL_H

#include "lighting/envfit.h"

typedef struct efl_level {
    int w, h;
    float *rgb;           /* w*h*3 radiance */
    double *om, *ct, *st; /* per row: pixel solid angle, cos/sin theta */
    double *cp, *sp;      /* per column: cos/sin phi */
    double energy;        /* sum_p om |L_p|^2 over channels */
} efl_level;

/* Pixel directions and solid angles for a w x h grid (rgb left NULL). */
void efl_level_geometry(efl_level *lv, int w, int h);
/* Level 0 = the map itself (copied); level k+1 halves each dimension (rounding up), each pixel
 * the solid-angle-weighted mean of the pixels whose centres fall in it. Stops once the height
 * is <= min_h. Returns the number of levels; *levels is allocated. */
int efl_pyramid(const sl_envmap *map, int min_h, efl_level **levels);
void efl_level_free(efl_level *lv);
void efl_pixel_dir(const efl_level *lv, int x, int y, double d[3]);

/* Runs fn(ctx, b) for b in [0, nblocks) on up to `threads` (at most 16) workers, each taking the
 * next block (sl_parallel_for). Callers give each block its own output slot and reduce the slots
 * in block order, so results never depend on the number of threads or on timing. */
void efl_parallel(int threads, int nblocks, void (*fn)(void *ctx, int block), void *ctx);

/* Exponent cut-off: a lobe's contribution below exp(-EFL_CUT) of its peak is dropped. */
#define EFL_CUT 34.0
/* Lobes narrower than EFL_NARROW pixels are integrated over each pixel in closed form (erf);
 * broader ones are widened by the pixel footprint (envfit_eval.c). */
#define EFL_NARROW 3.0
/* The pixel model of a lobe on a level: amplitude A and exponent a_e of the widened Gaussian. */
void efl_widened(const efl_level *lv, double lambda, double *A, double *a_e);

/* Column span [*x0, *x0 + *nx) (wrapping modulo w) of row y where G(.; mu, lambda) >= exp(-cut);
 * *nx == 0 when the row is outside the lobe's support. mu_th, mu_ph: the lobe's angles. */
void efl_row_span(const efl_level *lv, int y, const double mu[3], double a, double cut, int *x0,
                  int *nx);

/* Closed-form products of two SRBFs, written with x = a mu (a = 2 / lambda^2), so that
 * G(omega) = exp(omega . x - |x|):
 *   I      = integral G1 G2 d omega = 4 pi exp(-a1 - a2) sinh(R) / R,  R = |x1 + x2|
 *   dI_dx1, dI_dx2 = gradients of I with respect to x1 and x2,
 *   M[i][k] = d^2 I / dx1_i dx2_k (the Gauss-Newton block between the two lobes). */
typedef struct efl_pair {
    double I;
    double dI_dx1[3], dI_dx2[3];
    double M[3][3];
} efl_pair;
void efl_sg_pair(const double x1[3], const double x2[3], int want_derivs, efl_pair *p);
double efl_sg_inner(const double mu1[3], double a1, const double mu2[3], double a2);

/* The fit state on one level: residual image and the parameters' bounds. */
typedef struct efl_eval {
    const efl_level *lv;
    int threads;
    double cut;       /* exponent cut-off for lobe supports (EFL_CUT while fitting) */
    double *res;      /* w*h*3: model - map */
    const double *bg; /* optional w*h*3 model of lobes held fixed (added to every model) */
} efl_eval;

/* Residual image and objective F = 1/2 sum_p om_p |model_p - L_p|^2. */
double efl_objective(efl_eval *ev, const sl_lobe *lobes, int n);
/* Gradient of F (after efl_objective on the same lobes) with respect to, per lobe,
 * (c_r, c_g, c_b, u1, u2, s): weights, the direction's tangent-plane coordinates along t1, t2
 * (efl_tangent) and s = ln lambda. grad has 6 n entries. */
void efl_gradient(efl_eval *ev, const sl_lobe *lobes, int n, double *grad);
/* An orthonormal tangent basis at mu (deterministic). */
void efl_tangent(const double mu[3], double t1[3], double t2[3]);

/* Bounded Levenberg-Marquardt on one level. Returns the final F; *iters gets the iterations. */
typedef struct efl_lm_opts {
    int max_iter;
    double rel_tol;        /* stop when a step lowers F by less than rel_tol * F */
    double lam_lo, lam_hi; /* bandwidth bounds */
} efl_lm_opts;
double efl_lm(efl_eval *ev, sl_lobe *lobes, int n, const efl_lm_opts *o, int *iters,
              sl_progress *prog, double prog_lo, double prog_hi);

/* Greedy dictionary on a (coarse) level: correlations of the map with every atom. */
typedef struct efl_dict {
    const efl_level *lv;
    int natoms, nlam, threads;
    double lam[16];
    double *corr; /* natoms x 3: sum_p om_p L_p G_atom(p) */
    double *self; /* natoms: integral of G_atom^2 */
} efl_dict;
void efl_dict_build(efl_dict *d, const efl_level *lv, double lam_lo, double lam_hi, int threads);
void efl_dict_free(efl_dict *d);
void efl_dict_atom(const efl_dict *d, int atom, double mu[3], double *lambda);
/* Adds lobes to `lobes` (which holds n_have already) until n_want, each at the atom with the
 * largest gain for the current residual; all weights are re-solved (non-negative) after each
 * addition. */
void efl_greedy(const efl_dict *d, sl_lobe *lobes, int n_have, int n_want);
/* Non-negative least squares min 1/2 c^T A c - b^T c, c >= 0, for each of 3 channels:
 * A is m x m (row-major, positive diagonal), b and c are m x 3; c holds the start on entry. */
void efl_nnls(const double *A, int m, const double *b, double *c);

/* Splits up to max_suns compact, very bright regions off the map (envfit_sun.c): sky (w*h*3)
 * gets the map without them, suns[] one fitted lobe each. Returns the number of suns. */
int efl_split_suns(const sl_envmap *map, int max_suns, double lam_min, double lam_max, int threads,
                   float *sky, sl_lobe *suns);

#endif
