/* srbf_tables.h: the material-independent 2-D tables of Xu 2011 Sec. 4.2 / 5 (C_k(lambda', phi)
 * of Eq. 14 and H_k^TT, H_k^TRT(eta, theta_d) of Eq. 19, 23) in the layout of kernels/srbf_xu.h,
 * built once in double, cached on disk by a hash of their definition (a base/disk_cache.h entry
 * in sl_cache_dir_find's directory), each reporting its build time and interpolation error; and
 * the srbf dispatch of `eval` to the float backends (cpu/srbf_c.h, host/passes/shade/srbf_cl.h).
 *
 *   sl_srbf_tables t;
 *   if (sl_srbf_tables_get(&t, 1, &e)) ...;   (t.C, t.H, t.D: SL_SRBF_C_FLOATS, SL_SRBF_H_FLOATS,
 *                                              SL_SRBF_DEON_FLOATS of kernels/srbf_deon.h)
 *   ... sl_srbf_tables_free(&t); */
#ifndef SL_SRBF_TABLES_H
#define SL_SRBF_TABLES_H

#include "base/common.h"
#include "scene/material.h"

typedef struct sl_cl sl_cl;

typedef struct sl_srbf_tables {
    float *C;         /* SL_SRBF_C_FLOATS */
    float *H;         /* SL_SRBF_H_FLOATS: H_k, then the fast path's W */
    double build_s_C; /* seconds it took to build each table (as stored in the cache) */
    double build_s_H;
    double err_C;     /* max |bilinear - exact| at cell centres (C_k normalised, <= 1) */
    double err_H;     /* the same for H_k, relative to max H_0 */
    double build_s_W; /* the fast path's W table (appended to H, kernels/srbf_xu.h) */
    double err_W;     /* max |trilinear - exact| at cell centres, relative to max |W| */
    float *D;         /* SL_SRBF_DEON_FLOATS: the d'Eon W slices p = 3..SL_SRBF_DEON_MAX_P
                       * (kernels/srbf_deon.h; built with W, build_s_W covers both) */
    double err_D;     /* the same as err_W for the d'Eon slices */
    double err_Ch_x;  /* chiang's root harmonics: linear in 1/eta' at cell centres, of max |h| */
    double err_Ch_s;  /* chiang's detector harmonics d_n: linear in log s at cell centres */
    int from_cache;   /* 1: loaded from the disk cache */
    char path[4096];  /* the cache file ("" when there is no cache directory) */
} sl_srbf_tables;

/* Builds the tables in memory (about a second). */
void sl_srbf_tables_build(sl_srbf_tables *t);
/* Loads them from the disk cache or builds and caches them (a corrupt or foreign cache file is
 * rebuilt and replaced). verbose: print a note with build time and error when they are built.
 * Returns 0, or -1 with e set (cache write errors are warnings, not errors). */
int sl_srbf_tables_get(sl_srbf_tables *t, int verbose, sl_err *e);
void sl_srbf_tables_free(sl_srbf_tables *t);

/* The exact (double) table functions, for tests and error reports: the normalised C_k, i.e.
 * int |cos^k((phi - x)/2)| g^c(x; 0, lam) dx / int g^c(x; 0, lam) dx, and
 * H_k = int_{-1}^{1} (1-F)^2 [F if mode == 1] h^k dh (mode 0 TT, 1 TRT; schlick: Schlick F). */
double sl_srbf_C_exact(int k, double lam, double phi);
double sl_srbf_H_exact(int schlick, int mode, int k, double eta, double theta_d);
/* W_i of the fast path (kernels/srbf_xu.h) by a direct quadrature (slow: 0.4 M steps), mode 0 TT
 * / 1 TRT / 2 R, x = 1/eta' (ignored for R). */
double sl_srbf_W_exact(int mode, int i, double x, double lam, double phi);
/* The same for any order p (Phi(p, h); p = 0 R, 1 TT, 2 TRT, >= 3 the d'Eon slices). */
double sl_srbf_W_exact_order(int p, int i, double x, double lam, double phi);

/* Gauss-Legendre nodes/weights on [-1, 1] (Newton on P_n), in double: the tables' quadrature
 * (srbf_tables.c, srbf_chiang_tables.c). */
void sl_srbf_gauss_legendre(int n, double *x, double *w);

/* Model chiang's harmonic tables (kernels/srbf_chiang.h) into their region of the D buffer
 * (D: SL_SRBF_DEON_FLOATS floats); err[0], err[1]: err_Ch_x, err_Ch_s. */
void sl_srbf_chiang_tables_build(float *D, double err[2]);
/* Their exact definitions, for tests: the 8-node root measure's harmonics of order p (0..2) at
 * x = 1/eta', out[n * 8 + i] (n = 0..SL_SRBF_CH_NH, the kernel's normalisation h[0] = a_0 / 2pi,
 * h[n] = a_n / pi); the trimmed logistic's harmonic d_n(s). */
void sl_srbf_chiang_root_harmonics(int p, double x, double *out);
double sl_srbf_chiang_detector_exact(double s, int n);

/* `eval srbf` on a float backend: cl == NULL runs the C twin, else OpenCL. xu: 1 for Xu's
 * closed form (segments 1..8, 0 for the default 4), 0 for the fast path. in: 5 floats per row
 * (theta_o, phi_o, theta_j, phi_j, lambda), out: 4 per row (I_R, I_TT, I_TRT, I); model deon:
 * orders + 3 per row (I_0..I_orders, I_rest, I), fast path only (xu: an error); model chiang:
 * the same with orders 2 (I_0, I_1, I_2, I_rest, I). */
int sl_srbf_eval(sl_cl *cl, const sl_material *m, int ch, int xu, int segments, size_t n,
                 const float *in, float *out, sl_err *e);
/* The same keeping the tables between calls, so that a caller evaluating many chunks of rows
 * (eval's streaming, docs/eval.md) loads or builds them once: while *got is 0 they are got into
 * *t (after the method is checked) and *got set to 1; the caller frees *t when *got. */
int sl_srbf_eval_keep(sl_cl *cl, const sl_material *m, sl_srbf_tables *t, int *got, int ch, int xu,
                      int segments, size_t n, const float *in, float *out, sl_err *e);

#endif
