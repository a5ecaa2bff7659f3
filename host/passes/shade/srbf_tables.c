/* srbf_tables.c: builds, checks and caches the SRBF tables (see srbf_tables.h, docs/srbf.md),
 * and dispatches `eval srbf` to the C twin or OpenCL.
 *
 * Both tables are integrals of smooth functions once split at their kinks, so they are computed
 * with composite 20-point Gauss-Legendre on panels placed on the features (the circular
 * Gaussian's centre and shoulders, the kink of |cos^k| at x = phi - pi; h = sin u for H, which
 * removes the square-root behaviour of F at |h| = 1): about 1e-12 relative. The fast paths'
 * W weights (Marschner: TT, TRT, R in H; d'Eon: orders 3..8 and R's Fresnel fit in D,
 * kernels/srbf_deon.h) are exact Fourier-space convolutions of a root-sum histogram; model
 * chiang's harmonic tables, also in D, are built by srbf_chiang_tables.c. `eval srbf` with
 * model deon or chiang goes to the d'Eon fast path (--method xu is refused for them). */
#include "passes/shade/srbf_tables.h"

#include "base/disk_cache.h"
#include "passes/shade/srbf_cache_payload.h"
#include "cl/clrt.h"
#include "fiber_common_d.h"
#include "srbf_c.h"
#include "passes/shade/srbf_cl.h"
#include "srbf_deon.h"
#include "srbf_deon_c.h"
#include "passes/shade/srbf_deon_cl.h"
#include "srbf_fast.h"
#include "srbf_xu.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define NGL 20

void sl_srbf_gauss_legendre(int n, double *x, double *w) {
    for (int i = 0; i < n; i++) {
        double z = cos(PI * (i + 0.75) / (n + 0.5)), pp = 1.0;
        for (int it = 0; it < 100; it++) {
            double p1 = 1.0, p2 = 0.0;
            for (int j = 1; j <= n; j++) {
                double p3 = p2;
                p2 = p1;
                p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
            }
            pp = n * (z * p1 - p2) / (z * z - 1.0);
            double z1 = z;
            z = z1 - p1 / pp;
            if (fabs(z - z1) < 1e-15) break;
        }
        x[i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * pp * pp);
    }
}

static int cmp_d(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* All normalised C_k (k = 0..6) at (lam, phi). */
static void c_exact_all(double lam, double phi, const double *gx, const double *gw, double out[7]) {
    double pts[64];
    int n = 0;
    pts[n++] = -PI;
    pts[n++] = PI;
    pts[n++] = 0.0;
    static const double offs[10] = {0.25, 0.5, 1, 1.5, 2, 3, 4, 6, 8, 12};
    for (int k = 0; k < 10; k++)
        if (offs[k] * lam < PI) {
            pts[n++] = offs[k] * lam;
            pts[n++] = -offs[k] * lam;
        }
    pts[n++] = sld_wrap_pi(phi - PI); /* |cos((phi - x)/2)| has its kink here */
    for (int k = 1; k < 16; k++)
        pts[n++] = -PI + 2.0 * PI * k / 16.0;
    qsort(pts, (size_t)n, sizeof *pts, cmp_d);
    double acc[7] = {0}, z = 0.0;
    double inv_l2 = 1.0 / (lam * lam);
    for (int i = 0; i + 1 < n; i++) {
        double a = pts[i], b = pts[i + 1];
        if (!(b > a)) continue;
        double c = 0.5 * (a + b), h = 0.5 * (b - a);
        for (int j = 0; j < NGL; j++) {
            double x = c + h * gx[j];
            double s = sin(0.5 * x);
            double g = exp(-4.0 * s * s * inv_l2) * gw[j] * h; /* g^c(x; 0, lam) */
            if (g == 0.0) continue;
            double cc = fabs(cos(0.5 * (phi - x))), p = 1.0;
            z += g;
            for (int k = 0; k < 7; k++) {
                acc[k] += g * p;
                p *= cc;
            }
        }
    }
    for (int k = 0; k < 7; k++)
        out[k] = z > 0.0 ? acc[k] / z : 0.0;
}

double sl_srbf_C_exact(int k, double lam, double phi) {
    double gx[NGL], gw[NGL], out[7];
    sl_srbf_gauss_legendre(NGL, gx, gw);
    c_exact_all(lam, phi, gx, gw, out);
    return k >= 0 && k < 7 ? out[k] : 0.0;
}

/* H_0, H_2, H_4 of mode at (eta, theta_d): 2 int_0^{pi/2} (1-F)^2 [F] sin^k u cos u du. */
static void h_exact_all(int schlick, int mode, double eta, double td, const double *gx,
                        const double *gw, double out[3]) {
    double ctd = cos(td);
    out[0] = out[1] = out[2] = 0.0;
    const int panels = 8;
    for (int p = 0; p < panels; p++) {
        double a = 0.5 * PI * p / panels, b = 0.5 * PI * (p + 1) / panels;
        double c = 0.5 * (a + b), h = 0.5 * (b - a);
        for (int j = 0; j < NGL; j++) {
            double u = c + h * gx[j], su = sin(u), cu = cos(u);
            double ci = ctd * cu;
            double F = schlick ? sld_fresnel_schlick(eta, ci) : sld_fresnel_exact(eta, ci);
            double v = (1.0 - F) * (1.0 - F) * (mode ? F : 1.0) * cu * 2.0 * gw[j] * h;
            double s2 = su * su;
            out[0] += v;
            out[1] += v * s2;
            out[2] += v * s2 * s2;
        }
    }
}

double sl_srbf_H_exact(int schlick, int mode, int k, double eta, double theta_d) {
    double gx[NGL], gw[NGL], out[3];
    sl_srbf_gauss_legendre(NGL, gx, gw);
    h_exact_all(schlick, mode, eta, theta_d, gx, gw, out);
    return k == 0 ? out[0] : (k == 2 ? out[1] : (k == 4 ? out[2] : 0.0));
}

static double lam_of(double i) {
    return exp(log(SL_SRBF_LMIN) + (log(SL_SRBF_LMAX) - log(SL_SRBF_LMIN)) * i / (SL_SRBF_NL - 1));
}
static double phi_of(double i) {
    return PI * i / (SL_SRBF_NPHI - 1);
}
static double eta_of(double i) {
    return exp(log(SL_SRBF_ETAMAX) * i / (SL_SRBF_NETA - 1));
}
static double td_of(double i) {
    return 0.5 * PI * i / (SL_SRBF_NTD - 1);
}

/* ---- W: the fast path's azimuthal product-quadrature weights (kernels/srbf_xu.h) ---- */

/* Lagrange basis L_i(c) on the nodes sl_srbf_w_c. */
static void w_lagrange(double c, double L[SL_SRBF_W_NODES]) {
    for (int i = 0; i < SL_SRBF_W_NODES; i++) {
        double v = 1.0;
        for (int j = 0; j < SL_SRBF_W_NODES; j++)
            if (j != i) v *= (c - sl_srbf_w_c[j]) / ((double)sl_srbf_w_c[i] - sl_srbf_w_c[j]);
        L[i] = v;
    }
}

/* Phi(p, h) with h = sin u: 2p asin(x sin u) - 2u + p pi, wrapped to [-pi, pi). */
static double w_Phi(int p, double x, double u) {
    double v = 2.0 * p * asin(x * sin(u)) - 2.0 * u + p * PI;
    return v - 2.0 * PI * floor((v + PI) / (2.0 * PI));
}

/* The histogram of the root sum: bins of width 2 pi / nb centred on -pi + b d; weights
 * 1/2 L_i(cos u) cos u du of a midpoint rule in u (ns steps), split linearly between the two
 * nearest bins. hist: nb * SL_SRBF_W_NODES, [b][i]. */
static void w_histogram(int p, double x, int nb, int ns, double *hist) {
    memset(hist, 0, (size_t)nb * SL_SRBF_W_NODES * sizeof *hist);
    double du = PI / ns, d = 2.0 * PI / nb;
    for (int k = 0; k < ns; k++) {
        double u = -0.5 * PI + (k + 0.5) * du, c = cos(u), L[SL_SRBF_W_NODES];
        w_lagrange(c, L);
        double pos = (w_Phi(p, x, u) + PI) / d;
        int b0 = (int)floor(pos);
        double f = pos - b0, w = 0.5 * c * du;
        int b1 = (b0 + 1) % nb;
        b0 = ((b0 % nb) + nb) % nb;
        for (int i = 0; i < SL_SRBF_W_NODES; i++) {
            hist[b0 * SL_SRBF_W_NODES + i] += w * L[i] * (1.0 - f);
            hist[b1 * SL_SRBF_W_NODES + i] += w * L[i] * f;
        }
    }
}

/* The convolution with g^c(.; 0, lam) / int g^c is done in Fourier space, where it is exact:
 * the normalised circular Gaussian has coefficients I_n(k) / I_0(k), k = 2 / lam^2. The
 * histogram's cosine coefficients a_n (N_p is even in phi) are divided by the tent's sinc^2 so
 * the linear splitting between bins does not blur. */
#define W_NB 2048
#define W_NS 65536
#define W_NMAX 640 /* 12 / W_LMIN = 600 harmonics carry the narrowest lobe to e^-36 */

/* a[n * NODES + i] = sum_b hist[b][i] cos(n phi_b) / sinc^2(n d / 2), n = 0..W_NMAX. */
static void w_cosines(const double *hist, const double *ct, double *a) {
    double d = 2.0 * PI / W_NB;
    for (int n = 0; n <= W_NMAX; n++) {
        double acc[SL_SRBF_W_NODES] = {0};
        for (int b = 0; b < W_NB; b++) {
            double c = ct[(int)(((long)n * b) % W_NB)];
            for (int i = 0; i < SL_SRBF_W_NODES; i++)
                acc[i] += c * hist[b * SL_SRBF_W_NODES + i];
        }
        double sgn = (n & 1) ? -1.0 : 1.0, x = 0.5 * n * d;
        double sinc = n ? sin(x) / x : 1.0;
        for (int i = 0; i < SL_SRBF_W_NODES; i++)
            a[n * SL_SRBF_W_NODES + i] = sgn * acc[i] / (sinc * sinc);
    }
}

/* r[n] = I_n(k) / I_0(k), n = 0..W_NMAX (Miller's backward recurrence); returns the last n with
 * r[n] > 1e-15. */
static int w_ratios(double lam, double *r) {
    double k = 2.0 / (lam * lam);
    int top = 2 * W_NMAX + 60;
    double ip1 = 0.0, in = 1e-300;
    for (int n = top; n >= 1; n--) {
        double im1 = ip1 + 2.0 * n / k * in; /* I_{n-1} = I_{n+1} + (2n/k) I_n */
        ip1 = in;
        in = im1;
        if (n - 1 <= W_NMAX) r[n - 1] = in;
        if (in > 1e250) { /* rescale everything kept so far */
            for (int j = n - 1; j <= W_NMAX && j <= top; j++)
                r[j] *= 1e-250;
            in *= 1e-250;
            ip1 *= 1e-250;
        }
    }
    int last = 0;
    for (int n = W_NMAX; n >= 0; n--) {
        r[n] /= r[0] == 0.0 ? 1.0 : r[0];
    }
    r[0] = 1.0;
    for (int n = 0; n <= W_NMAX; n++)
        if (r[n] > 1e-15) last = n;
    return last;
}

/* W at phi from the coefficients a and the ratios r (up to n = last). */
static void w_eval(const double *a, const double *r, int last, double phi,
                   double out[SL_SRBF_W_NODES]) {
    double acc[SL_SRBF_W_NODES];
    for (int i = 0; i < SL_SRBF_W_NODES; i++)
        acc[i] = 0.5 * a[i];
    double c1 = cos(phi), cn_1 = 1.0, cn = c1; /* cos(n phi) by the Chebyshev recurrence */
    for (int n = 1; n <= last; n++) {
        for (int i = 0; i < SL_SRBF_W_NODES; i++)
            acc[i] += a[n * SL_SRBF_W_NODES + i] * r[n] * cn;
        double nx = 2.0 * c1 * cn - cn_1;
        cn_1 = cn;
        cn = nx;
    }
    for (int i = 0; i < SL_SRBF_W_NODES; i++)
        out[i] = acc[i] / PI;
}

static double w_x_of(double i) {
    return i / (SL_SRBF_W_NX - 1);
}
static double w_lam_of(double i) {
    return exp(log(SL_SRBF_W_LMIN) +
               (log(SL_SRBF_LMAX) - log(SL_SRBF_W_LMIN)) * i / (SL_SRBF_W_NL - 1));
}

double sl_srbf_W_exact(int mode, int i, double x, double lam, double phi) {
    return sl_srbf_W_exact_order(mode == 2 ? 0 : mode + 1, i, x, lam, phi);
}

double sl_srbf_W_exact_order(int p, int i, double x, double lam, double phi) {
    /* independent of the grid: a direct midpoint rule in u (400000 steps) of
     * 1/2 L_i(cos u) g^c(phi - Phi) cos u over the exact int g^c = 2 pi e^-k I0(k) */
    int n = 400000;
    double s = 0.0, du = PI / n;
    for (int k = 0; k < n; k++) {
        double u = -0.5 * PI + (k + 0.5) * du, c = cos(u), L[SL_SRBF_W_NODES];
        w_lagrange(c, L);
        double sd = sin(0.5 * (phi - w_Phi(p, x, u)));
        s += 0.5 * L[i] * c * exp(-4.0 * sd * sd / (lam * lam)) * du;
    }
    double kk = 2.0 / (lam * lam), i0 = 0.0;
    if (kk < 30.0) {
        double term = 1.0;
        i0 = 1.0;
        for (int j = 1; j < 200; j++) {
            term *= 0.25 * kk * kk / ((double)j * j);
            i0 += term;
        }
        i0 *= exp(-kk);
    } else {
        double term = 1.0;
        i0 = 1.0;
        for (int j = 1; j < 12; j++) {
            term *= (2.0 * j - 1) * (2.0 * j - 1) / (8.0 * kk * j);
            i0 += term;
        }
        i0 /= sqrt(2.0 * PI * kk);
    }
    return s / (2.0 * PI * i0);
}

/* One eta'-dependent W slice of order p ([ix][il][ip] points, SL_SRBF_W_NX x 1/eta', each
 * SL_SRBF_W_NODES floats at out + point * stride). wmax: the largest |W| so far (updated). */
static void build_slice(int p, float *out, int stride, double *hist, double *a, const double *ct,
                        double *wmax) {
    double r[W_NMAX + 1];
    for (int ix = 0; ix < SL_SRBF_W_NX; ix++) {
        w_histogram(p, w_x_of(ix), W_NB, W_NS, hist);
        w_cosines(hist, ct, a);
        for (int il = 0; il < SL_SRBF_W_NL; il++) {
            int last = w_ratios(w_lam_of(il), r);
            for (int ip = 0; ip < SL_SRBF_W_NP; ip++) {
                double v[SL_SRBF_W_NODES];
                w_eval(a, r, last, PI * ip / (SL_SRBF_W_NP - 1), v);
                float *o = out + ((ix * SL_SRBF_W_NL + il) * SL_SRBF_W_NP + ip) * stride;
                for (int i = 0; i < SL_SRBF_W_NODES; i++) {
                    o[i] = (float)v[i];
                    *wmax = fmax(*wmax, fabs(v[i]));
                }
            }
        }
    }
}

/* Interpolation error of a slice of order p: its trilinear lookup (lookup(x, lam, phi, got))
 * against the same construction at cell centres, on every 6th x cell, every 3rd lambda cell and
 * every phi cell; returns the largest absolute difference. */
typedef void (*w_lookup_fn)(const float *tab, int p, float x, float lam, float phi,
                            float out[SL_SRBF_W_NODES]);

static double slice_error(int p, const float *tab, w_lookup_fn lookup, double *hist, double *a,
                          const double *ct) {
    double r[W_NMAX + 1], e = 0.0;
    for (int ix = 0; ix + 1 < SL_SRBF_W_NX; ix += 6) {
        double x = w_x_of(ix + 0.5);
        w_histogram(p, x, W_NB, W_NS, hist);
        w_cosines(hist, ct, a);
        for (int il = 0; il + 1 < SL_SRBF_W_NL; il += 3) {
            double lam = w_lam_of(il + 0.5);
            int last = w_ratios(lam, r);
            for (int ip = 0; ip + 1 < SL_SRBF_W_NP; ip++) {
                double v[SL_SRBF_W_NODES], phi = PI * (ip + 0.5) / (SL_SRBF_W_NP - 1);
                w_eval(a, r, last, phi, v);
                float got[SL_SRBF_W_NODES];
                lookup(tab, p, (float)x, (float)lam, (float)phi, got);
                for (int i = 0; i < SL_SRBF_W_NODES; i++)
                    e = fmax(e, fabs(got[i] - v[i]));
            }
        }
    }
    return e;
}

/* Lookups for slice_error: the Marschner fast path's (tab = the H buffer, p = 1, 2) and the
 * d'Eon slices' (tab = D, p >= 3), each with the kernel code that reads them. */
static void lookup_H(const float *tab, int p, float x, float lam, float phi,
                     float out[SL_SRBF_W_NODES]) {
    sl_srbf_W(tab, p - 1, x, lam, phi, out);
}
static void lookup_D(const float *tab, int p, float x, float lam, float phi,
                     float out[SL_SRBF_W_NODES]) {
    sl_srbf_deon_cell c;
    sl_srbf_deon_cell_init(x, lam, phi, &c);
    for (int i = 0; i < SL_SRBF_W_NODES; i++) {
        float A[SL_SRBF_W_NODES] = {0};
        A[i] = 1.0f;
        out[i] = sl_srbf_deon_cell_dot(tab, p, &c, A);
    }
}

/* W (TT, TRT, R) into the H buffer after H_k; the d'Eon slices p = 3..SL_SRBF_DEON_MAX_P into D
 * (when D != NULL). Errors relative to the largest |W| of the tables they cover. */
static void build_W(float *H, float *D, double *err, double *err_D) {
    double *hist = sl_malloc((size_t)W_NB * SL_SRBF_W_NODES * sizeof *hist);
    double *a = sl_malloc((size_t)(W_NMAX + 1) * SL_SRBF_W_NODES * sizeof *a);
    double *ct = sl_malloc((size_t)W_NB * sizeof *ct), r[W_NMAX + 1];
    for (int k = 0; k < W_NB; k++)
        ct[k] = cos(2.0 * PI * k / W_NB);
    float *W = H + SL_SRBF_HK_FLOATS;
    double wmax = 0.0, e = 0.0;
    for (int mode = 0; mode < 2; mode++)
        build_slice(mode + 1, W + mode * SL_SRBF_DEON_SLICE, SL_SRBF_W_NODES, hist, a, ct, &wmax);
    /* R (p = 0): one slice */
    w_histogram(0, 0.0, W_NB, W_NS, hist);
    w_cosines(hist, ct, a);
    for (int il = 0; il < SL_SRBF_W_NL; il++) {
        int last = w_ratios(w_lam_of(il), r);
        for (int ip = 0; ip < SL_SRBF_W_NP; ip++) {
            double v[SL_SRBF_W_NODES];
            w_eval(a, r, last, PI * ip / (SL_SRBF_W_NP - 1), v);
            float *o = W + SL_SRBF_W_TRT_FLOATS + (il * SL_SRBF_W_NP + ip) * SL_SRBF_W_NODES;
            for (int i = 0; i < SL_SRBF_W_NODES; i++)
                o[i] = (float)v[i];
        }
    }
    for (int p = 1; p <= 2; p++)
        e = fmax(e, slice_error(p, H, lookup_H, hist, a, ct));
    *err = e / wmax;
    if (D) {
        double dmax = 0.0, ed = 0.0;
        for (int p = 3; p <= SL_SRBF_DEON_MAX_P; p++)
            build_slice(p, D + (p - 3) * SL_SRBF_W_NODES, SL_SRBF_DEON_CELL, hist, a, ct, &dmax);
        for (int p = 3; p <= SL_SRBF_DEON_MAX_P; p++)
            ed = fmax(ed, slice_error(p, D, lookup_D, hist, a, ct));
        *err_D = ed / dmax;
    }
    free(hist);
    free(a);
    free(ct);
}

/* R's Fresnel fit (kernels/srbf_deon.h): per eta the least-squares degree-5 polynomial of the
 * exact Fresnel F(eta, x) over x in [0, 1] (400 midpoints; normal equations solved in double
 * with partial pivoting: the monomial Gram matrix on [0, 1] has condition ~1e7, far inside
 * double precision). out: SL_SRBF_DEON_FIT_NETA x 8 floats. */
static void build_fresnel_fit(float *out) {
    for (int ie = 0; ie < SL_SRBF_DEON_FIT_NETA; ie++) {
        double eta = exp(log(SL_SRBF_ETAMIN) + (log(SL_SRBF_ETAMAX) - log(SL_SRBF_ETAMIN)) * ie /
                                                   (SL_SRBF_DEON_FIT_NETA - 1));
        double M[6][7] = {{0}};
        for (int k = 0; k < 400; k++) {
            double x = (k + 0.5) / 400.0, f = sld_fresnel_exact(eta, x), pw[11];
            pw[0] = 1.0;
            for (int j = 1; j < 11; j++)
                pw[j] = pw[j - 1] * x;
            for (int i = 0; i < 6; i++) {
                for (int j = 0; j < 6; j++)
                    M[i][j] += pw[i + j];
                M[i][6] += f * pw[i];
            }
        }
        for (int i = 0; i < 6; i++) {
            int pv = i;
            for (int r = i + 1; r < 6; r++)
                if (fabs(M[r][i]) > fabs(M[pv][i])) pv = r;
            for (int c = 0; c < 7; c++) {
                double tmp = M[i][c];
                M[i][c] = M[pv][c];
                M[pv][c] = tmp;
            }
            for (int r = 0; r < 6; r++)
                if (r != i) {
                    double f = M[r][i] / M[i][i];
                    for (int c = i; c < 7; c++)
                        M[r][c] -= f * M[i][c];
                }
        }
        for (int i = 0; i < 8; i++)
            out[ie * 8 + i] = i < 6 ? (float)(M[i][6] / M[i][i]) : 0.0f;
    }
}

void sl_srbf_tables_build(sl_srbf_tables *t) {
    double gx[NGL], gw[NGL];
    sl_srbf_gauss_legendre(NGL, gx, gw);
    t->C = sl_calloc(SL_SRBF_C_FLOATS, sizeof(float));
    t->H = sl_calloc(SL_SRBF_H_FLOATS, sizeof(float));
    t->D = sl_calloc(SL_SRBF_DEON_FLOATS, sizeof(float));
    t->from_cache = 0;
    double t0 = sl_now();
    for (int il = 0; il < SL_SRBF_NL; il++)
        for (int ip = 0; ip < SL_SRBF_NPHI; ip++) {
            double v[7];
            c_exact_all(lam_of(il), phi_of(ip), gx, gw, v);
            for (int k = 0; k < 7; k++)
                t->C[(il * SL_SRBF_NPHI + ip) * 8 + k] = (float)v[k];
        }
    /* Error: bilinear lookup against the exact value at cell centres (every other cell). */
    double err = 0.0;
    for (int il = 0; il + 1 < SL_SRBF_NL; il += 2)
        for (int ip = 0; ip + 1 < SL_SRBF_NPHI; ip += 2) {
            double lam = lam_of(il + 0.5), phi = phi_of(ip + 0.5), v[7];
            float got[7];
            c_exact_all(lam, phi, gx, gw, v);
            sl_srbf_C(t->C, (float)lam, (float)phi, got);
            for (int k = 0; k < 7; k++)
                err = fmax(err, fabs(got[k] - v[k]));
        }
    double t1 = sl_now();
    t->build_s_C = t1 - t0;
    t->err_C = err;
    double hmax = 0.0;
    for (int s = 0; s < 2; s++)
        for (int mode = 0; mode < 2; mode++)
            for (int ie = 0; ie < SL_SRBF_NETA; ie++)
                for (int it = 0; it < SL_SRBF_NTD; it++) {
                    double v[3];
                    h_exact_all(s, mode, eta_of(ie), td_of(it), gx, gw, v);
                    float *o = t->H + (((s * 2 + mode) * SL_SRBF_NETA + ie) * SL_SRBF_NTD + it) * 4;
                    for (int k = 0; k < 3; k++)
                        o[k] = (float)v[k];
                    hmax = fmax(hmax, v[0]);
                }
    err = 0.0;
    for (int s = 0; s < 2; s++)
        for (int mode = 0; mode < 2; mode++)
            for (int ie = 0; ie + 1 < SL_SRBF_NETA; ie += 2)
                for (int it = 0; it + 1 < SL_SRBF_NTD; it += 2) {
                    double eta = eta_of(ie + 0.5), td = td_of(it + 0.5), v[3];
                    float got[3];
                    h_exact_all(s, mode, eta, td, gx, gw, v);
                    sl_srbf_H(t->H, s, mode, (float)eta, (float)td, got);
                    for (int k = 0; k < 3; k++)
                        err = fmax(err, fabs(got[k] - v[k]) / hmax);
                }
    t->build_s_H = sl_now() - t1;
    t->err_H = err;
    double t2 = sl_now();
    build_W(t->H, t->D, &t->err_W, &t->err_D);
    build_fresnel_fit(t->D + SL_SRBF_DEON_FIT_OFF);
    double ech[2];
    sl_srbf_chiang_tables_build(t->D, ech);
    t->err_Ch_x = ech[0];
    t->err_Ch_s = ech[1];
    t->build_s_W = sl_now() - t2;
}

void sl_srbf_tables_free(sl_srbf_tables *t) {
    free(t->C);
    free(t->H);
    free(t->D);
    t->C = t->H = t->D = NULL;
}

/* ---- disk cache ---- */

/* The payload: build times and errors, then C, H and D as floats (base/disk_cache.h adds the key
 * and the integrity hash). Bump when this layout changes; the contents are tables_key's. */
#define TABLES_FORMAT 5u

/* Hash of everything that defines the tables' contents. */
static uint64_t tables_key(void) {
    char def[1024];
    snprintf(
        def, sizeof def,
        "strandlight srbf tables v3 (W with R; chiang 8 nodes): C_k normalised k0..6 NL=%d NPHI=%d "
        "lam=[%.9g,%.9g] log, "
        "phi=[0,pi]; H_k TT/TRT exact/schlick NETA=%d NTD=%d eta=[%.9g,%.9g] log, td=[0,pi/2];"
        " GL%d; W TT/TRT NX=%d NL=%d NP=%d nodes=%d lam=[%.9g,..] c-Chebyshev, hist NB=%d"
        " NS=%d; d'Eon W p=3..%d same grid, orders interleaved per point; R Fresnel LSQ deg 5"
        " NETA=%d; chiang harmonics n<=%d NX=%d, R, |cos|^k, trimmed logistic NS=%d"
        " s=[%.9g,%.9g] log",
        SL_SRBF_NL, SL_SRBF_NPHI, (double)SL_SRBF_LMIN, (double)SL_SRBF_LMAX, SL_SRBF_NETA,
        SL_SRBF_NTD, (double)SL_SRBF_ETAMIN, (double)SL_SRBF_ETAMAX, NGL, SL_SRBF_W_NX,
        SL_SRBF_W_NL, SL_SRBF_W_NP, SL_SRBF_W_NODES, (double)SL_SRBF_W_LMIN, W_NB, W_NS,
        SL_SRBF_DEON_MAX_P, SL_SRBF_DEON_FIT_NETA, SL_SRBF_CH_NH, SL_SRBF_CH_NX, SL_SRBF_CH_NS,
        (double)SL_SRBF_CH_SMIN, (double)SL_SRBF_CH_SMAX);
    return sl_hash64(def, strlen(def), 0x5352424654424c31ull);
}

static int try_load(sl_srbf_tables *t, const char *path, uint64_t key) {
    const size_t want = sl_srbf_tables_payload_bytes();
    void *data = NULL;
    size_t n = 0;
    if (sl_cache_read(path, TABLES_FORMAT, (sl_cache_key){key, 0}, want, &data, &n, NULL))
        return -1;
    int rc = sl_srbf_tables_from_payload(t, data, n);
    free(data);
    return rc;
}

static void save(const sl_srbf_tables *t, const char *path, uint64_t key) {
    sl_srbf_tables_meta h;
    memset(&h, 0, sizeof h);
    h.build_s_C = t->build_s_C;
    h.build_s_H = t->build_s_H;
    h.err_C = t->err_C;
    h.err_H = t->err_H;
    h.build_s_W = t->build_s_W;
    h.err_W = t->err_W;
    h.err_D = t->err_D;
    h.err_Ch_x = t->err_Ch_x;
    h.err_Ch_s = t->err_Ch_s;
    sl_cache_part parts[4] = {{&h, sizeof h},
                              {t->C, SL_SRBF_C_FLOATS * sizeof(float)},
                              {t->H, SL_SRBF_H_FLOATS * sizeof(float)},
                              {t->D, SL_SRBF_DEON_FLOATS * sizeof(float)}};
    sl_err e2 = {{0}};
    if (sl_cache_write(path, TABLES_FORMAT, (sl_cache_key){key, 0}, parts, 4, 0, &e2))
        sl_warn("srbf tables: not cached: %s", e2.msg);
}

int sl_srbf_tables_get(sl_srbf_tables *t, int verbose, sl_err *e) {
    (void)e;
    memset(t, 0, sizeof *t);
    uint64_t key = tables_key();
    char dir[4000];
    if (sl_cache_dir_find(dir, sizeof dir)) {
        if (sl_cache_path(t->path, sizeof t->path, dir, "srbf-tables", (sl_cache_key){key, 0},
                          TABLES_FORMAT) &&
            try_load(t, t->path, key) == 0)
            return 0;
    }
    sl_srbf_tables_build(t);
    if (verbose)
        sl_note(
            "srbf tables built: C_k %dx%d in %.2f s (max interpolation error %.2g), H_k "
            "2x2x%dx%d in %.2f s (max error %.2g of max H_0), W 2x%dx%dx%d in %.2f s (max error "
            "%.2g of max W; d'Eon slices p=3..%d: %.2g; chiang harmonics %.2g, detector %.2g)%s%s",
            SL_SRBF_NL, SL_SRBF_NPHI, t->build_s_C, t->err_C, SL_SRBF_NETA, SL_SRBF_NTD,
            t->build_s_H, t->err_H, SL_SRBF_W_NX, SL_SRBF_W_NL, SL_SRBF_W_NP, t->build_s_W,
            t->err_W, SL_SRBF_DEON_MAX_P, t->err_D, t->err_Ch_x, t->err_Ch_s,
            t->path[0] ? "; cached in " : "; not cached", t->path);
    if (t->path[0]) save(t, t->path, key);
    return 0;
}

/* ---- eval dispatch ---- */

int sl_srbf_eval(sl_cl *cl, const sl_material *m, int ch, int xu, int segments, size_t n,
                 const float *in, float *out, sl_err *e) {
    sl_srbf_tables t;
    int got = 0;
    int rc = sl_srbf_eval_keep(cl, m, &t, &got, ch, xu, segments, n, in, out, e);
    if (got) sl_srbf_tables_free(&t);
    return rc;
}

int sl_srbf_eval_keep(sl_cl *cl, const sl_material *m, sl_srbf_tables *t, int *got, int ch, int xu,
                      int segments, size_t n, const float *in, float *out, sl_err *e) {
    if (m->model != SL_MODEL_MARSCHNER) {
        /* Xu's closed form is a construction for the Marschner model (its C_k/H_k fits and
         * Gaussian M); d'Eon and Chiang have the fast path only (docs/srbf.md, "d'Eon fast
         * path", "Chiang fast path") */
        const char *name = m->model == SL_MODEL_CHIANG ? "chiang" : "deon";
        if (xu)
            return sl_fail(e,
                           "eval: srbf --method xu is Xu's closed form of the Marschner "
                           "model; model %s has --method fast (c, opencl) and exact "
                           "(reference)",
                           name);
        if (!*got && sl_srbf_tables_get(t, 1, e)) return -1;
        *got = 1;
        sl_fiber_params fp;
        sl_material_to_fiber(m, ch, &fp);
        int rc = 0;
        if (cl)
            rc = slcl_srbf_deon_batch(cl, &fp, t, n, in, out, e);
        else
            slc_srbf_deon_batch(&fp, t->C, t->H, t->D, n, in, out);
        return rc ? -1 : 0;
    }
    if (segments == 0) segments = 4;
    if (segments < 1 || segments > SL_SRBF_MAX_SEGMENTS)
        return sl_fail(e, "eval: --segments must be 1..%d (got %d)", SL_SRBF_MAX_SEGMENTS,
                       segments);
    if (!*got && sl_srbf_tables_get(t, 1, e)) return -1;
    *got = 1;
    sl_fiber_params fp;
    sl_material_to_fiber(m, ch, &fp);
    int method = xu ? SL_SRBF_METHOD_XU : SL_SRBF_METHOD_FAST;
    int rc = 0;
    if (cl)
        rc = slcl_srbf_batch(cl, &fp, t, method, segments, n, in, out, e);
    else
        slc_srbf_batch(&fp, t->C, t->H, method, segments, n, in, out);
    return rc ? -1 : 0;
}
