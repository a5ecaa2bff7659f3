/* srbf_deon.h: the fast SRBF response of the d'Eon model (`eval srbf --method fast` with
 * `model: deon`), float, shared by the C twin (cpu/srbf_deon_c.c) and OpenCL
 * (kernels/srbf_deon.cl). Derivation and measurements: docs/srbf.md, "d'Eon fast path".
 *
 *   I_p = int cos ti G_th(ti) M_p(v_p, ti, to - 2 alpha_p) N'_p(ti) d ti
 *   N'_p = int G_ph(phi_i) N_p(phi_o - phi_i) d phi_i                    (Xu 2011 appendix A)
 *
 * with G = G_th G_ph the exact split of the SRBF (G_ph a von Mises of concentration
 * kappa = 2 cos ti cos tj / lambda^2) and d'Eon's M_p (Eq. 7) and N_p (Eq. 10-11):
 *  - azimuth: N_p = 1/2 int A_p(h) D_beta(phi - Phi(p, h)) dh, so N'_p is the W product
 *    quadrature of kernels/srbf_fast.h (A_p at 4 Chebyshev nodes in c = cos gamma_i, exactly
 *    convolved weights per 1/eta', width and phi) with the detector folded into the width:
 *    lambda3^2 = lambda'^2 + 2 beta_p^2 (variances add: a von Mises of concentration 2/l^2 has
 *    variance l^2/2, the detector beta^2). R keeps Xu's exact C_k expansion for Schlick's part
 *    and the exact Fresnel's residual through W, as the Marschner fast path does. Orders 1, 2
 *    read the W slices of TT and TRT, orders 3..SL_SRBF_DEON_MAX_P the extra slices D built by
 *    host/passes/shade/srbf_tables.c; orders above that and the rest term have a uniform azimuth
 * (exact for the rest term; for p > SL_SRBF_DEON_MAX_P an approximation, see docs/srbf.md).
 *  - longitudinal: G_th M_p = K exp(a cos ti + b sin ti) i0e(cos ti cos to' / v) exactly, a von
 *    Mises lobe in ti of centre atan2(b, a) and concentration |(a, b)|: 8 Gauss-Legendre nodes
 *    on centre +- 3.5 / sqrt(|(a, b)|) clipped to [-pi/2, pi/2], G_th M_p (log space) and
 *    z = int G_ph = 2 pi i0e(kappa) exact at the nodes, the smooth normalised azimuthal factor
 *    N'_p / z at the 3 Gauss points of the same interval, interpolated by its quadratic. Orders
 *    >= 2 and the rest term share TRT's lobe (alpha, beta), hence its nodes and its Fresnel /
 *    absorption evaluations.
 *  - R's Fresnel: a least-squares degree-5 polynomial per eta (table in D) instead of Schlick's
 *    in the exact C_k expansion, the residual through W.
 * Model chiang (Chiang 2016, numerics.md sec. 3) has this structure too and shares the
 * longitudinal lobes, the tables and the drivers; its azimuth (theta_i-independent A_p, the
 * trimmed logistic detector, the unshifted rest lobe) is kernels/srbf_chiang.h, included below
 * the shared helpers and called from sl_srbf_deon by fp->model. */
#ifndef SL_SRBF_DEON_H
#define SL_SRBF_DEON_H

#include "fiber_deon.h"
#include "srbf_fast.h"

/* Highest order with its own W slice; p = 3..SL_SRBF_DEON_MAX_P live in the D buffer,
 * [ix][il][ip][p - 3][node] with the grid of the TT / TRT slices (kernels/srbf_xu.h): the orders
 * of one grid point are contiguous, so one lookup of all orders touches 4 x 2 cache-line runs
 * instead of 4 per order (the lookups are memory-bound). */
#define SL_SRBF_DEON_MAX_P 8
#define SL_SRBF_DEON_NORD (SL_SRBF_DEON_MAX_P - 2)
#define SL_SRBF_DEON_CELL (SL_SRBF_DEON_NORD * SL_SRBF_W_NODES) /* floats per grid point */
#define SL_SRBF_DEON_SLICE (SL_SRBF_W_NX * SL_SRBF_W_NL * SL_SRBF_W_NP * SL_SRBF_W_NODES)
/* Then R's Fresnel fit: per eta (SL_SRBF_DEON_FIT_NETA, log-uniform in [SL_SRBF_ETAMIN,
 * SL_SRBF_ETAMAX]) the 6 coefficients (+ 2 pad) of the least-squares degree-5 polynomial in
 * x = cos i on [0, 1] of the exact Fresnel F(eta, x); it replaces Schlick's polynomial in Xu's
 * C_k expansion, so the residual left to the 4-node W rule is 4x smaller (eta 1.55: max 0.008
 * against Schlick's 0.033; the residual is steep at grazing, where 4 nodes in c cannot follow). */
#define SL_SRBF_DEON_FIT_NETA 128
#define SL_SRBF_DEON_FIT_OFF (SL_SRBF_DEON_NORD * SL_SRBF_DEON_SLICE)
/* Then model chiang's harmonic tables (kernels/srbf_chiang.h, its "wide" branch): there
 * N'_p / z = sum_n k_n cos(n phi) B_n with the kernel's harmonics k_n (SRBF times detector) and
 * B_n = sum_i A_p(c_i) h_p[n][i] over SL_SRBF_CH_NODES Chebyshev nodes c_i in c = cos gamma
 * (8, not the W slices' 4: one evaluation per row, and 8 nodes follow R's exact Fresnel to
 * 0.3 % at normal incidence where 4 are 35 % off), h_p the cosine coefficients of the nodes'
 * root measure of order p in the normalisation h[0][i] = a_0 / (2 pi), h[n][i] = a_n / pi
 * (a_n = 1/2 int L_i(c(h)) cos(n Phi(p, h)) dh), n = 0..SL_SRBF_CH_NH:
 *  - TT, TRT: [p - 1][ix][n][node], SL_SRBF_CH_NX points of 1/eta' in [0, 1] (linear; Phi's
 *    harmonics turn with n, so the axis is 16x finer than the W slices');
 *  - R: [n][node] (Phi(0, h) has no eta');
 *  - [is][n]: the trimmed logistic detector's harmonics d_n(s) = int D_s(x) cos(n x) dx over
 *    (-pi, pi], SL_SRBF_CH_NS scales log-uniform in [SL_SRBF_CH_SMIN, SL_SRBF_CH_SMAX]. */
#define SL_SRBF_CH_NH 16
#define SL_SRBF_CH_NHV (SL_SRBF_CH_NH + 1)
#define SL_SRBF_CH_NODES 8
#define SL_SRBF_CH_NX 512
#define SL_SRBF_CH_NS 128
#define SL_SRBF_CH_SMIN 0.005f
#define SL_SRBF_CH_SMAX 8.0f
#define SL_SRBF_CH_SLICE (SL_SRBF_CH_NX * SL_SRBF_CH_NHV * SL_SRBF_CH_NODES)
#define SL_SRBF_CH_OFF (SL_SRBF_DEON_FIT_OFF + SL_SRBF_DEON_FIT_NETA * 8)
#define SL_SRBF_CH_R_OFF (SL_SRBF_CH_OFF + 2 * SL_SRBF_CH_SLICE)
#define SL_SRBF_CH_DET_OFF (SL_SRBF_CH_R_OFF + SL_SRBF_CH_NHV * SL_SRBF_CH_NODES)
#define SL_SRBF_CH_FLOATS                                                                          \
    (2 * SL_SRBF_CH_SLICE + SL_SRBF_CH_NHV * SL_SRBF_CH_NODES + SL_SRBF_CH_NS * SL_SRBF_CH_NHV)
/* The wide branch's nodes c_i = (1 - cos((2i + 1) pi / 16)) / 2 and sqrt(1 - c_i^2). */
#define SL_SRBF_CH_C                                                                               \
    {                                                                                              \
        0.009607359798385f, 0.084265193848727f, 0.222214883490199f, 0.402454838991936f,            \
            0.597545161008064f, 0.777785116509801f, 0.915734806151273f, 0.990392640201615f         \
    }
#define SL_SRBF_CH_S                                                                               \
    {                                                                                              \
        0.999953848253860f, 0.996443363722011f, 0.974997715666779f, 0.915439841044716f,            \
            0.801835257740545f, 0.628530279728698f, 0.401783231112364f, 0.138283832151390f         \
    }
#define SL_SRBF_DEON_FLOATS (SL_SRBF_CH_OFF + SL_SRBF_CH_FLOATS)
/* Outputs per row: I_0..I_orders, I_rest, I. */
#define SL_SRBF_DEON_NOUT (SL_DEON_MAX_ORDERS + 3)

/* U_i = omega_i / (2 pi), omega_i = int_0^{pi/2} L_i(cos u) cos u du = 1/2 int L_i(c(h)) dh:
 * the W weights of a uniform azimuth (lambda -> infinity), so E = sum A(c_i) omega_i is the
 * product rule for the energy 1/2 int A dh (test/passes/shade/test_srbf_deon.c checks them by
 * quadrature). */
#define SL_SRBF_DEON_U                                                                             \
    {                                                                                              \
        0.00659695314057874f / 6.28318530717958648f, 0.116919608856975f / 6.28318530717958648f,    \
            0.347620381786066f / 6.28318530717958648f, 0.528863056218942f / 6.28318530717958648f   \
    }
/* The uniform-azimuth limit of the normalised C_k (k = 0..6): the mean of |cos(x/2)|^k,
 * (1/pi) int_{-pi/2}^{pi/2} cos^k y dy. */
#define SL_SRBF_DEON_CU                                                                            \
    { 1.0f, 0.636619772367581f, 0.5f, 0.424413181578388f, 0.375f, 0.339530545262710f, 0.3125f }
/* 8-point Gauss-Legendre (outer rule) and the 3-point Gauss abscissae (azimuthal factor). */
#define SL_SRBF_DEON_GLX                                                                           \
    {                                                                                              \
        -0.960289856497536f, -0.796666477413627f, -0.525532409916329f, -0.183434642495650f,        \
            0.183434642495650f, 0.525532409916329f, 0.796666477413627f, 0.960289856497536f         \
    }
#define SL_SRBF_DEON_GLW                                                                           \
    {                                                                                              \
        0.101228536290376f, 0.222381034453374f, 0.313706645877887f, 0.362683783378362f,            \
            0.362683783378362f, 0.313706645877887f, 0.222381034453374f, 0.101228536290376f         \
    }
#define SL_SRBF_DEON_Q3 0.774596669241483f /* sqrt(3/5) */
/* The quadratic's Lagrange weights at the 8 nodes u_k (sl_srbf_deon_lobe_add): l0 = u (u - q) /
 * 2q^2, l2 = u (u + q) / 2q^2, folded at compile time (the same float operations, so the same
 * values as computing them per node). */
#define SL_SRBF_DEON_LQ(u, sg)                                                                     \
    ((u) * ((u)sg SL_SRBF_DEON_Q3) / (2.0f * SL_SRBF_DEON_Q3 * SL_SRBF_DEON_Q3))
#define SL_SRBF_DEON_LQ8(sg)                                                                       \
    {                                                                                              \
        SL_SRBF_DEON_LQ(-0.960289856497536f, sg), SL_SRBF_DEON_LQ(-0.796666477413627f, sg),        \
            SL_SRBF_DEON_LQ(-0.525532409916329f, sg), SL_SRBF_DEON_LQ(-0.183434642495650f, sg),    \
            SL_SRBF_DEON_LQ(0.183434642495650f, sg), SL_SRBF_DEON_LQ(0.525532409916329f, sg),      \
            SL_SRBF_DEON_LQ(0.796666477413627f, sg), SL_SRBF_DEON_LQ(0.960289856497536f, sg)       \
    }
#if SL_OPENCL
static __constant float sl_srbf_deon_u[SL_SRBF_W_NODES] = SL_SRBF_DEON_U;
static __constant float sl_srbf_deon_cu[7] = SL_SRBF_DEON_CU;
static __constant float sl_srbf_deon_glx[8] = SL_SRBF_DEON_GLX;
static __constant float sl_srbf_deon_glw[8] = SL_SRBF_DEON_GLW;
static __constant float sl_srbf_deon_l0[8] = SL_SRBF_DEON_LQ8(-);
static __constant float sl_srbf_deon_l2[8] = SL_SRBF_DEON_LQ8(+);
#else
static const float sl_srbf_deon_u[SL_SRBF_W_NODES] = SL_SRBF_DEON_U;
static const float sl_srbf_deon_cu[7] = SL_SRBF_DEON_CU;
static const float sl_srbf_deon_glx[8] = SL_SRBF_DEON_GLX;
static const float sl_srbf_deon_glw[8] = SL_SRBF_DEON_GLW;
static const float sl_srbf_deon_l0[8] = SL_SRBF_DEON_LQ8(-);
static const float sl_srbf_deon_l2[8] = SL_SRBF_DEON_LQ8(+);
#endif

/* Beyond the tables' widest lobe (SL_SRBF_LMAX): a normalised circular Gaussian of
 * concentration k has harmonics I_n(k)/I_0(k) ~ k/2 for n = 1 and O(k^2) above, so the
 * smoothed function at width l > LMAX is the uniform mean plus (LMAX/l)^2 of the deviation at
 * LMAX (exact as l -> infinity, i.e. at the poles, where kappa = 0). Returns that factor. */
SL_INLINE float sl_srbf_deon_wide(float lam) {
    return lam > SL_SRBF_LMAX ? (SL_SRBF_LMAX / lam) * (SL_SRBF_LMAX / lam) : 1.0f;
}

/* The trilinear cell of one (1/eta', width, |phi|) point in a W slice (grid of kernels/srbf_xu.h);
 * every slice p >= 3 shares it. */
typedef struct sl_srbf_deon_cell {
    int off;
    float fx, fl, fp;
} sl_srbf_deon_cell;

SL_INLINE void sl_srbf_deon_cell_init(float x, float lam, float phi, sl_srbf_deon_cell *c) {
    int ix, il, ip;
    c->fx = sl_srbf_grid(x, 0.0f, 1.0f, SL_SRBF_W_NX, &ix);
    c->fl = sl_srbf_grid(log(sl_maxf(lam, 1e-30f)), log(SL_SRBF_W_LMIN), log(SL_SRBF_LMAX),
                         SL_SRBF_W_NL, &il);
    c->fp = sl_srbf_grid(fabs(phi), 0.0f, SL_PI_F, SL_SRBF_W_NP, &ip);
    c->off = ((ix * SL_SRBF_W_NL + il) * SL_SRBF_W_NP + ip) * SL_SRBF_DEON_CELL;
}

/* sum_i A_i W_i of order p (3..SL_SRBF_DEON_MAX_P) at the cell (trilinear of the dot product:
 * it is linear). */
SL_INLINE float sl_srbf_deon_cell_dot(SL_GLOBAL const float *D, int p, const sl_srbf_deon_cell *c,
                                      const float A[SL_SRBF_W_NODES]) {
    const int sp = SL_SRBF_DEON_CELL, sl = SL_SRBF_W_NP * SL_SRBF_DEON_CELL,
              sx = SL_SRBF_W_NL * SL_SRBF_W_NP * SL_SRBF_DEON_CELL;
    SL_GLOBAL const float *b = D + c->off + (p - 3) * SL_SRBF_W_NODES;
    float v[8];
    for (int j = 0; j < 8; j++) {
        SL_GLOBAL const float *q = b + ((j & 1) ? sp : 0) + ((j & 2) ? sl : 0) + ((j & 4) ? sx : 0);
        float s = 0.0f;
        for (int k = 0; k < SL_SRBF_W_NODES; k++)
            s += A[k] * q[k];
        v[j] = s;
    }
    float a00 = v[0] + (v[1] - v[0]) * c->fp, a01 = v[2] + (v[3] - v[2]) * c->fp;
    float a10 = v[4] + (v[5] - v[4]) * c->fp, a11 = v[6] + (v[7] - v[6]) * c->fp;
    float a0 = a00 + (a01 - a00) * c->fl, a1 = a10 + (a11 - a10) * c->fl;
    return a0 + (a1 - a0) * c->fx;
}

/* The Fresnel fit's coefficients a_0..a_5 at eta (linear in log eta). */
SL_INLINE void sl_srbf_deon_fit(SL_GLOBAL const float *D, float eta, float a[6]) {
    int ie;
    float fe = sl_srbf_grid(log(sl_maxf(eta, 1e-30f)), log(SL_SRBF_ETAMIN), log(SL_SRBF_ETAMAX),
                            SL_SRBF_DEON_FIT_NETA, &ie);
    SL_GLOBAL const float *b = D + SL_SRBF_DEON_FIT_OFF + ie * 8;
    for (int k = 0; k < 6; k++)
        a[k] = b[k] + (b[k + 8] - b[k]) * fe;
}

/* sum_i A_i W_i of the Marschner fast path's slices (mode 0 TT, 1 TRT, 2 R; kernels/srbf_fast.h)
 * at width lam, with the wide-lobe limit above SL_SRBF_LMAX. */
SL_INLINE float sl_srbf_deon_W3(SL_GLOBAL const float *H, int mode, float x, float lam, float phi,
                                const float A[SL_SRBF_W_NODES]) {
    float W[SL_SRBF_W_NODES], t = sl_srbf_deon_wide(lam), s = 0.0f;
    sl_srbf_W(H, mode, x, lam, phi, W);
    for (int i = 0; i < SL_SRBF_W_NODES; i++)
        s += A[i] * (sl_srbf_deon_u[i] + t * (W[i] - sl_srbf_deon_u[i]));
    return s;
}

/* The azimuthal factors N'_p / z (z = int G_ph = 2 pi i0e(kappa), applied by the caller) at one
 * theta_i for lobe group g: g = 0 writes az[0] (R), g = 1 az[0] (TT), g = 2 az[0..n-2] (orders
 * 2..n) and az[n-1] (the rest term). kappa: the von Mises concentration of G_ph at ti. */
SL_INLINE void sl_srbf_deon_az(const sl_fiber_params *fp, SL_GLOBAL const float *C,
                               SL_GLOBAL const float *H, SL_GLOBAL const float *D, float theta_o,
                               float phi, float kappa, float ti, int g, int n, float *az) {
    sl_deon_geom gm;
    sl_deon_geom_init(fp, ti, theta_o, &gm);
    float beta = fp->beta[g];
    /* lambda3^2 = lambda'^2 + 2 beta^2, lambda'^2 = 2 / kappa */
    float l2 = kappa > 1e-30f ? 2.0f / kappa : 1e30f;
    float lam3 = sqrt(sl_minf(l2 + 2.0f * beta * beta, 1e30f));
    float x = 1.0f / gm.etap;
    float A[SL_SRBF_W_NODES], F[SL_SRBF_W_NODES], T[SL_SRBF_W_NODES];
    if (g == 0) {
        /* R: N_0 = 1/4 |cos(phi/2)| F(cos td |cos(phi/2)|) (Phi(0, h) = -2 asin h) smoothed.
         * The fitted polynomial P(x) = sum a_j x^j of F goes through Xu's C_k expansion (exact:
         * C_k is the smoothed |cos(phi/2)|^k), the residual F - P (small) through W. */
        float Cn[7], a[6], t = sl_srbf_deon_wide(lam3);
        sl_srbf_C(C, lam3, phi, Cn);
        sl_srbf_deon_fit(D, gm.eta, a);
        float r = 0.0f, xp = 0.25f;
        for (int j = 0; j < 6; j++) {
            r += a[j] * xp * (sl_srbf_deon_cu[j + 1] + t * (Cn[j + 1] - sl_srbf_deon_cu[j + 1]));
            xp *= gm.cos_td;
        }
        for (int i = 0; i < SL_SRBF_W_NODES; i++) {
            float ci = gm.cos_td * sl_srbf_w_c[i];
            float P = a[0] + ci * (a[1] + ci * (a[2] + ci * (a[3] + ci * (a[4] + ci * a[5]))));
            A[i] = sl_fresnel_exact(gm.eta, ci) - P;
        }
        az[0] = sl_maxf(r + sl_srbf_deon_W3(H, 2, 0.0f, lam3, phi, A), 0.0f);
        return;
    }
    for (int i = 0; i < SL_SRBF_W_NODES; i++)
        sl_deon_fT(&gm, sl_srbf_w_s[i], sl_srbf_w_c[i], &F[i], &T[i]);
    if (g == 1) {
        for (int i = 0; i < SL_SRBF_W_NODES; i++)
            A[i] = (1.0f - F[i]) * (1.0f - F[i]) * T[i];
        az[0] = sl_maxf(sl_srbf_deon_W3(H, 0, x, lam3, phi, A), 0.0f);
        return;
    }
    /* orders 2..n: A_p = (1-f)^2 f^(p-1) T^p by multiplication from A_2 */
    for (int i = 0; i < SL_SRBF_W_NODES; i++)
        A[i] = (1.0f - F[i]) * (1.0f - F[i]) * F[i] * T[i] * T[i];
    az[0] = sl_maxf(sl_srbf_deon_W3(H, 1, x, lam3, phi, A), 0.0f);
    sl_srbf_deon_cell cell;
    sl_srbf_deon_cell_init(x, lam3, phi, &cell);
    float t = sl_srbf_deon_wide(lam3);
    for (int p = 3; p <= n; p++) {
        float s = 0.0f;
        for (int i = 0; i < SL_SRBF_W_NODES; i++) {
            A[i] *= F[i] * T[i];
            s += A[i] * sl_srbf_deon_u[i];
        }
        if (p <= SL_SRBF_DEON_MAX_P) /* uniform mean + t x the tabulated deviation */
            s += t * (sl_srbf_deon_cell_dot(D, p, &cell, A) - s);
        az[p - 2] = sl_maxf(s, 0.0f);
    }
    /* rest: sum_{p>n} A_p = A_{n+1} / (1 - f T) (docs/numerics-deon.md), uniform azimuth */
    float r = 0.0f;
    for (int i = 0; i < SL_SRBF_W_NODES; i++) {
        float den = 1.0f - F[i] * T[i];
        if (den > 0.0f) r += A[i] * F[i] * T[i] / den * sl_srbf_deon_u[i];
    }
    az[n - 1] = r;
}

/* The longitudinal part of one lobe group (variance v, shifted view angle tho) against the SRBF:
 * the product lobe exp(a cos ti + b sin ti), its interval [c - h, c + h] and the weights wk[k] =
 * (8-point Gauss-Legendre weight) x cos ti G_th M_p z at its nodes (z = 2 pi i0e(kappa) exact
 * there), wsum their sum. Shared by the d'Eon and Chiang paths (both use d'Eon's M_p). */
typedef struct sl_srbf_deon_lobe {
    float c, h, wsum;
    float wk[8];
} sl_srbf_deon_lobe;

/* What a lobe group's longitudinal part takes from the view alone (variance v, shifted view angle
 * tho): cos tho, sin tho and the ti-independent constant cv of log M_p; the renderer's rows of one
 * point share it (kernels/srbf_chiang.h builds it once per point). */
typedef struct sl_srbf_deon_lobe_pre {
    float v, cto, sto, cv;
    float sho, cho; /* sin, cos of tho / 2 (the half-angle forms of M_p's numerator) */
} sl_srbf_deon_lobe_pre;

SL_INLINE void sl_srbf_deon_lobe_pre_init(float v, float tho, sl_srbf_deon_lobe_pre *P) {
    P->v = v;
    P->cto = cos(tho);
    P->sto = sin(tho);
    P->sho = sin(0.5f * tho);
    P->cho = cos(0.5f * tho);
    /* log M_p = cv - num / v + log i0e(|cos ti cos to'| / v) (sl_deon_log_mp's form of
     * Eq. 7) with the ti-independent cv hoisted and i0e applied directly (no log)
     * (cv <= 80: exp(cv) stays finite in float even for a denormal v, where the lobe is a
     * delta far below float resolution anyway; beta >= 1e-17 rad is unaffected) */
    P->cv = sl_minf(-log(v) - log(-expm1(-2.0f / v)), 80.0f);
}

/* Returns 0 when the lobe interval is empty. theta_j's cos (clamped >= 0) and sin, 1/lambda^2. */
SL_INLINE int sl_srbf_deon_lobe_init_pre(const sl_srbf_deon_lobe_pre *P, float theta_j,
                                         float cos_tj, float sin_tj, float inv_l2,
                                         sl_srbf_deon_lobe *L) {
    float v = P->v, cv = P->cv, cto = P->cto;
    /* the product lobe exp(a cos ti + b sin ti): G_th's 2 cos(ti - tj) / lambda^2 plus
     * log M's -sin ti sin to' / v + |cos ti cos to'| / v (log I0(y) = y + log i0e(y)) */
    float a = 2.0f * cos_tj * inv_l2 + fabs(cto) / v;
    float b = 2.0f * sin_tj * inv_l2 - P->sto / v;
    float R = sqrt(a * a + b * b);
    float mu = atan2(b, a), s = 1.0f / sqrt(sl_maxf(R, 1e-6f));
    float lo = sl_maxf(mu - 3.5f * s, -0.5f * SL_PI_F), hi = sl_minf(mu + 3.5f * s, 0.5f * SL_PI_F);
    L->wsum = 0.0f;
    if (!(hi > lo)) return 0;
    float c = 0.5f * (lo + hi), h = 0.5f * (hi - lo);
    L->c = c;
    L->h = h;
    /* Per node sin and cos of ti / 2 (|ti / 2| <= pi / 4) and one exp, all branch-free
     * polynomials (kernels/srbf_fast.h: sl_srbf_sin_hp, sl_srbf_cos_hp, sl_srbf_exp) and both
     * branches of i0e computed and one selected, so that in C the 8 nodes run as vector lanes
     * (the per-row lobe setup was a third of a chiang row as scalar libm calls); cos ti and the
     * three half-angle sines and cosines below by the angle-addition formulas (absolute error
     * ~1e-7, which the exponents scale by at most 4 / lambda^2 and 1 / v), and the exponentials
     * of both i0e factors folded into exp(lg) (one exp of the sum: it also stays finite where
     * exp(lg) alone overflowed; lg <= cv <= 80). */
    float shj = sin(0.5f * theta_j), chj = cos(0.5f * theta_j);
    float cho = P->cho, sho = P->sho, inv_v = 1.0f / v;
    for (int k = 0; k < 8; k++) {
        float hti = 0.5f * (c + h * sl_srbf_deon_glx[k]);
        float sa = sl_srbf_sin_hp(hti), ca = sl_srbf_cos_hp(hti);
        float cti = (ca - sa) * (ca + sa);
        float sd = sa * chj - ca * shj; /* sin((ti - theta_j) / 2) */
        float cc = cti * cto;
        float sp = sa * cho + ca * sho; /* sin((ti + tho) / 2) */
        float cm = ca * cho + sa * sho; /* cos((ti - tho) / 2) */
        float num = cc >= 0.0f ? 2.0f * sp * sp : 2.0f * cm * cm;
        float y2 = fabs(2.0f * cti * cos_tj * inv_l2), y1 = fabs(cc) * inv_v;
        float p2 = sl_srbf_i0e_sel(y2), p1 = sl_srbf_i0e_sel(y1);
        float lg = -4.0f * sd * sd * inv_l2 + cv - num * inv_v;
        lg -= y2 < SL_AS_I0_SPLIT ? y2 : 0.0f; /* sl_srbf_i0e_sel left out e^-y there */
        lg -= y1 < SL_AS_I0_SPLIT ? y1 : 0.0f;
        float w = sl_srbf_deon_glw[k] * h * cti * (2.0f * SL_PI_F * p2) * sl_srbf_exp(lg) * p1;
        int ok = (cti > 0.0f) & (w > 0.0f) & (w <= SL_FLT_MAX);
        L->wk[k] = ok ? w : 0.0f;
    }
    for (int k = 0; k < 8; k++)
        L->wsum += L->wk[k];
    return 1;
}

/* The same from the variance v and shifted view angle tho. */
SL_INLINE int sl_srbf_deon_lobe_init(float v, float tho, float theta_j, float cos_tj, float sin_tj,
                                     float inv_l2, sl_srbf_deon_lobe *L) {
    sl_srbf_deon_lobe_pre P;
    sl_srbf_deon_lobe_pre_init(v, tho, &P);
    return sl_srbf_deon_lobe_init_pre(&P, theta_j, cos_tj, sin_tj, inv_l2, L);
}

/* theta_i of Gauss point j (0..2) of the lobe's interval, where the azimuthal factor is
 * evaluated. */
SL_INLINE float sl_srbf_deon_lobe_ti(const sl_srbf_deon_lobe *L, int j) {
    return L->c + L->h * SL_SRBF_DEON_Q3 * (float)(j - 1);
}

/* out[m] += sum_k wk[k] x (the quadratic through the normalised azimuthal factors fz[0..2][m] at
 * the 3 Gauss points -q, 0, q, at node k), m = 0..nz-1. */
SL_INLINE void sl_srbf_deon_lobe_add(const sl_srbf_deon_lobe *L,
                                     const float fz[3][SL_DEON_MAX_ORDERS + 1], int nz,
                                     float *out) {
    /* per output a local sum over the nodes in their order (out may alias nothing the loop
     * reads, but the compiler cannot know: a store and reload per node otherwise) */
    for (int m = 0; m < nz; m++) {
        float acc = out[m];
        for (int k = 0; k < 8; k++) {
            if (!(L->wk[k] > 0.0f)) continue;
            float l0 = sl_srbf_deon_l0[k], l2 = sl_srbf_deon_l2[k], l1 = 1.0f - l0 - l2;
            acc += L->wk[k] * (l0 * fz[0][m] + l1 * fz[1][m] + l2 * fz[2][m]);
        }
        out[m] = acc;
    }
}

/* Outputs 0..n+1 made finite and non-negative, their sum into out[n + 2]. */
SL_INLINE void sl_srbf_deon_total(int n, float *out) {
    float total = 0.0f;
    for (int k = 0; k <= n + 1; k++) {
        float y = out[k];
        if (!(y >= 0.0f && y <= SL_FLT_MAX)) y = y > 0.0f ? SL_FLT_MAX : 0.0f;
        out[k] = y;
        total += y;
    }
    out[n + 2] = total;
}

/* the error floor of numerics.md sec. 5: 0.03 int G, int G = pi lambda^2 (1 - e^(-4/l^2)) */
SL_INLINE float sl_srbf_deon_floor(float lambda, float inv_l2) {
    return 0.03f * SL_PI_F * lambda * lambda * (-expm1(-4.0f * inv_l2));
}

/* The explicit orders n of a row (outputs I_0..I_n, I_rest, I): the material's, clamped to
 * 2..SL_DEON_MAX_ORDERS; model chiang always 2 (p >= 3 is its rest term). */
SL_INLINE int sl_srbf_deon_orders(const sl_fiber_params *fp) {
    if (fp->model == 2) return 2;
    return fp->orders > SL_DEON_MAX_ORDERS ? SL_DEON_MAX_ORDERS : (fp->orders < 2 ? 2 : fp->orders);
}

#include "srbf_chiang.h"

/* The response to one SRBF lobe: out[p] = I_p (p = 0..orders), out[orders+1] = I_rest,
 * out[orders+2] = I (orders clamped to SL_DEON_MAX_ORDERS). C, H: the tables of
 * host/passes/shade/srbf_tables.h (C_k; H_k then W), D: its d'Eon slices (SL_SRBF_DEON_FLOATS).
 * Model chiang (fp->model 2) goes to its own azimuth (kernels/srbf_chiang.h), orders 2. */
SL_INLINE void sl_srbf_deon(const sl_fiber_params *fp, SL_GLOBAL const float *C,
                            SL_GLOBAL const float *H, SL_GLOBAL const float *D, float theta_o,
                            float phi_o, float theta_j, float phi_j, float lambda, float *out) {
    if (fp->model == 2) {
        sl_srbf_chiang(fp, C, H, D, theta_o, phi_o, theta_j, phi_j, lambda, out);
        return;
    }
    int n = sl_srbf_deon_orders(fp);
    float cos_tj = sl_maxf(cos(theta_j), 0.0f), sin_tj = sin(theta_j);
    float inv_l2 = 1.0f / (lambda * lambda);
    float phi = sl_wrap_pi(phi_o - phi_j);
    float floor_ = sl_srbf_deon_floor(lambda, inv_l2);
    for (int k = 0; k < n + 3; k++)
        out[k] = 0.0f;
    for (int g = 0; g < 3; g++) {
        float v = fp->beta[g] * fp->beta[g], tho = theta_o - 2.0f * fp->alpha[g];
        sl_srbf_deon_lobe L;
        if (!sl_srbf_deon_lobe_init(v, tho, theta_j, cos_tj, sin_tj, inv_l2, &L)) continue;
        int nz = g < 2 ? 1 : n; /* outputs of this group */
        int o0 = g < 2 ? g : 2; /* its first output */
        /* Skip the azimuthal part (the expensive one) when even the largest possible N'_p / z
         * cannot lift the group above 1e-4 of the error floor 0.03 int G of numerics.md sec. 5:
         * N'_p / z is an average of N_p, and sum_p N_p <= (sum_p E_p <= 1) x max D_beta <=
         * 1 / (sqrt(2 pi) beta) + 1 / (2 pi) (the wrapped detector's peak; R: <= 1/4). */
        float bound = g == 0 ? 0.25f : 0.3989423f / fp->beta[g] + 0.1591549f;
        if (!(L.wsum * bound > 1e-4f * floor_)) continue;
        /* normalised azimuthal factors N'_p / z at the 3 Gauss points; z = 2 pi i0e(kappa)
         * itself is applied exactly at each node (near a pole it falls from 2 pi to ~0.1 over
         * the interval, which a quadratic does not follow: 10 % errors at grazing views) */
        float fz[3][SL_DEON_MAX_ORDERS + 1];
        for (int j = 0; j < 3; j++) {
            float ti = sl_srbf_deon_lobe_ti(&L, j);
            float kappa = 2.0f * cos(ti) * cos_tj * inv_l2;
            sl_srbf_deon_az(fp, C, H, D, theta_o, phi, kappa, ti, g, n, fz[j]);
        }
        sl_srbf_deon_lobe_add(&L, fz, nz, out + o0);
    }
    sl_srbf_deon_total(n, out);
}

/* Chiang's outputs of nch channels (sl_srbf_chiang_rgb: 5 per channel; nch 1: the same for r, g,
 * b) as the renderer's row: I_0 rgb, I_1 rgb, I_2 + I_rest rgb. */
SL_INLINE void sl_srbf_chiang_rgb_out(int nch, const float *o, float out[9]) {
    for (int ch = 0; ch < 3; ch++) {
        const float *c = o + 5 * (nch > 1 ? ch : 0);
        out[ch] = c[0];
        out[3 + ch] = c[1];
        out[6 + ch] = c[2] + c[3];
    }
}

/* The renderer's row (the shape of sl_srbf_rgb_row, kernels/srbf_fast.h): three absorption
 * coefficients sig[0..2] (NULL: fp->sigma_a for all), out[9] = I_0 rgb, I_1 rgb, then orders
 * >= 2 and the rest term summed, rgb (the "R, TT, TRT" slots of the Marschner row). A row whose
 * three sigma_a are equal is evaluated once. */
SL_INLINE void sl_srbf_deon_rgb_row(const sl_fiber_params *fp, SL_GLOBAL const float *C,
                                    SL_GLOBAL const float *H, SL_GLOBAL const float *D,
                                    float theta_o, float phi_o, float theta_j, float phi_j,
                                    float lambda, const float *sig, float out[9]) {
    if (fp->model == 2) { /* chiang: one evaluation for the three channels */
        float o[5 * SL_SRBF_CH_MAXC];
        int nch = sig ? 3 : 1;
        sl_srbf_chiang_rgb(fp, C, H, D, theta_o, phi_o, theta_j, phi_j, lambda, nch, sig, o);
        sl_srbf_chiang_rgb_out(nch, o, out);
        return;
    }
    int n = sl_srbf_deon_orders(fp);
    sl_fiber_params q = *fp;
    float o[SL_SRBF_DEON_NOUT];
    for (int ch = 0; ch < 3; ch++) {
        if (sig) q.sigma_a = sig[ch];
        if (ch == 0 || (sig && sig[ch] != sig[ch - 1])) /* o still holds channel ch - 1 */
            sl_srbf_deon(&q, C, H, D, theta_o, phi_o, theta_j, phi_j, lambda, o);
        float rest = 0.0f;
        for (int p = 2; p <= n + 1; p++)
            rest += o[p];
        out[ch] = o[0];
        out[3 + ch] = o[1];
        out[6 + ch] = rest;
    }
}

#endif
