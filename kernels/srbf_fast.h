/* srbf_fast.h: the renderer's own closed-form SRBF response (`--method fast`, the default on c
 * and opencl), float, shared by the C twin and OpenCL. Xu's outer structure (kernels/srbf_xu.h)
 * with every approximation the issue lists replaced (docs/srbf.md, "Fast path"):
 *  - azimuth: the exactly convolved N'_p from the W table (tabulated per 1/eta', lambda', phi
 *    with the material factored out: a product quadrature in h on 4 Chebyshev nodes in
 *    c = cos gamma_i, so Fresnel, absorption, eta, sigma_a stay editable); R keeps Xu's exact
 *    C_k expansion for Schlick's part and adds the exact Fresnel's residual through W; TRT's w_c
 *    enters as lambda3^2 = lambda'^2 + w_c^2;
 *  - longitudinal: the exact circular Gaussian g^c(theta_i; theta_j, lambda) and M_t as is, 8
 *    Gauss-Legendre nodes on the product lobe [mu - 3.5 s, mu + 3.5 s] clipped to [-pi/2, pi/2],
 *    the smooth azimuthal factor evaluated at 3 Gauss points and interpolated;
 *  - circular-Gaussian integrals exact (2 pi e^-k I0(k)).
 * The W table lives in the H buffer after H_k (layout in kernels/srbf_xu.h).
 * Entry points: sl_srbf_fast (one sigma_a), sl_srbf_fast_rgb (1..3 sigma_a sharing all other
 * work: the renderer's RGB batch), sl_srbf_rgb_row (either method, 3 channels); the per-node
 * helpers (sl_srbf_W, sl_srbf_fast_node, sl_srbf_i0e_fast) stay for srbf_deon.h. Speed notes in
 * docs/srbf.md, "Speed". */
#ifndef SL_SRBF_FAST_H
#define SL_SRBF_FAST_H

#include "srbf_xu.h"

#ifndef SL_SRBF_FAST_NODES
#define SL_SRBF_FAST_NODES 8
#endif

/* SL_SRBF_FAST_NODES-point Gauss-Legendre on [-1, 1] (5 or 6). */
#if SL_SRBF_FAST_NODES == 8
#define SL_SRBF_GL_X                                                                               \
    {                                                                                              \
        -0.960289856497536f, -0.796666477413627f, -0.525532409916329f, -0.183434642495650f,        \
            0.183434642495650f, 0.525532409916329f, 0.796666477413627f, 0.960289856497536f         \
    }
#define SL_SRBF_GL_W                                                                               \
    {                                                                                              \
        0.101228536290376f, 0.222381034453374f, 0.313706645877887f, 0.362683783378362f,            \
            0.362683783378362f, 0.313706645877887f, 0.222381034453374f, 0.101228536290376f         \
    }
#elif SL_SRBF_FAST_NODES == 5
#define SL_SRBF_GL_X                                                                               \
    { -0.906179845938664f, -0.538469310105683f, 0.0f, 0.538469310105683f, 0.906179845938664f }
#define SL_SRBF_GL_W                                                                               \
    {                                                                                              \
        0.236926885056189f, 0.478628670499366f, 0.568888888888889f, 0.478628670499366f,            \
            0.236926885056189f                                                                     \
    }
#else
#define SL_SRBF_GL_X                                                                               \
    {                                                                                              \
        -0.932469514203152f, -0.661209386466265f, -0.238619186083197f, 0.238619186083197f,         \
            0.661209386466265f, 0.932469514203152f                                                 \
    }
#define SL_SRBF_GL_W                                                                               \
    {                                                                                              \
        0.171324492379170f, 0.360761573048139f, 0.467913934572691f, 0.467913934572691f,            \
            0.360761573048139f, 0.171324492379170f                                                 \
    }
#endif
#ifndef SL_SRBF_FAST_AZ_NODES
#define SL_SRBF_FAST_AZ_NODES 3
#endif
#define SL_SRBF_AZ3                                                                                \
    { -0.774596669241483f, 0.0f, 0.774596669241483f }
#if SL_OPENCL
static __constant float sl_srbf_az3[3] = SL_SRBF_AZ3;
static __constant float sl_srbf_glx6[SL_SRBF_FAST_NODES] = SL_SRBF_GL_X;
static __constant float sl_srbf_glw6[SL_SRBF_FAST_NODES] = SL_SRBF_GL_W;
#else
static const float sl_srbf_az3[3] = SL_SRBF_AZ3;
static const float sl_srbf_glx6[SL_SRBF_FAST_NODES] = SL_SRBF_GL_X;
static const float sl_srbf_glw6[SL_SRBF_FAST_NODES] = SL_SRBF_GL_W;
#endif

/* e^-x I0(x), x >= 0, by Abramowitz & Stegun 9.8.1-9.8.2 (relative error < 2e-7, below float
 * rounding of what it multiplies), split for callers that fold its exponential into their own:
 * returns p with e^-x I0(x) = p exp(-x) when *with_exp is set (x < 3.75), = p otherwise. No
 * loop, unlike the series of sl_mq_i0e, which cost a third of the fast path's time. */
SL_INLINE float sl_srbf_i0e_poly(float x, int *with_exp) {
    x = fabs(x);
    if (x < SL_AS_I0_SPLIT) {
        float t = x * (1.0f / 3.75f);
        t *= t;
        *with_exp = 1;
        return sl_as_i0_small(t);
    }
    float t = 3.75f / x;
    float p = sl_as_i0e_large(t);
    *with_exp = 0;
    return p / sqrt(x);
}

/* sl_srbf_i0e_poly branch-free for x >= 0: both polynomials computed, one selected (with_exp
 * is then x < SL_AS_I0_SPLIT), so that loops over it vectorise in C. */
SL_INLINE float sl_srbf_i0e_sel(float x) {
    float t = x * (1.0f / 3.75f);
    t *= t;
    float small = sl_as_i0_small(t);
    float xl = x > SL_AS_I0_SPLIT ? x : SL_AS_I0_SPLIT;
    float p = sl_as_i0e_large(3.75f / xl);
    return x < SL_AS_I0_SPLIT ? small : p / sqrt(xl);
}

/* e^-x I0(x), x >= 0 (sl_srbf_i0e_poly with its exponential). */
SL_INLINE float sl_srbf_i0e_fast(float x) {
    int with_exp;
    float p = sl_srbf_i0e_poly(x, &with_exp);
    return with_exp ? p * exp(-fabs(x)) : p;
}

/* Nodes in c = cos gamma_i = sqrt(1 - h^2) of the azimuthal product quadrature (the W table of
 * kernels/srbf_xu.h): Chebyshev points of [0, 1], c_i = (1 - cos((2i+1) pi / 8)) / 2. A_p is
 * smooth in c (Fresnel at cos theta_d c, absorption exp(-2 s sqrt(1 - (1 - c^2)/eta'^2))), unlike
 * in h, where it has a square-root behaviour at |h| = 1. */
#define SL_SRBF_W_C                                                                                \
    { 0.0380602337443566f, 0.308658283817455f, 0.691341716182545f, 0.961939766255643f }
#define SL_SRBF_W_S                                                                                \
    {                                                                                              \
        0.999275446815004f, 0.951172993640412f, 0.722527945110619f, 0.273261570836513f             \
    } /* sqrt(1 - c_i^2) */
#if SL_OPENCL
static __constant float sl_srbf_w_c[SL_SRBF_W_NODES] = SL_SRBF_W_C;
static __constant float sl_srbf_w_s[SL_SRBF_W_NODES] = SL_SRBF_W_S;
#else
static const float sl_srbf_w_c[SL_SRBF_W_NODES] = SL_SRBF_W_C;
static const float sl_srbf_w_s[SL_SRBF_W_NODES] = SL_SRBF_W_S;
#endif

/* W_i (i = 0..SL_SRBF_W_NODES-1) of mode (0 TT, 1 TRT, 2 R) at (x = 1/eta', lambda, |phi|):
 * trilinear, clamped to the table range. Wtab: the H buffer (W starts after H_k).
 * sl_srbf_W_loglam takes log(lambda) (computed once per node and shared by several lookups). */
SL_INLINE void sl_srbf_W_loglam(SL_GLOBAL const float *Htab, int mode, float x, float log_lam,
                                float phi, float out[SL_SRBF_W_NODES]) {
    int ix, il, ip;
    float fx = sl_srbf_grid(x, 0.0f, 1.0f, SL_SRBF_W_NX, &ix);
    int sx = SL_SRBF_W_NL * SL_SRBF_W_NP * SL_SRBF_W_NODES;
    if (mode == 2) { /* R: one slice, no eta' axis */
        ix = 0;
        fx = 0.0f;
        sx = 0;
    }
    float fl = sl_srbf_grid(log_lam, log(SL_SRBF_W_LMIN), log(SL_SRBF_LMAX), SL_SRBF_W_NL, &il);
    float fp = sl_srbf_grid(fabs(phi), 0.0f, SL_PI_F, SL_SRBF_W_NP, &ip);
    SL_GLOBAL const float *b =
        Htab + SL_SRBF_HK_FLOATS +
        (((mode * SL_SRBF_W_NX + ix) * SL_SRBF_W_NL + il) * SL_SRBF_W_NP + ip) * SL_SRBF_W_NODES;
    const int sp = SL_SRBF_W_NODES, sl = SL_SRBF_W_NP * SL_SRBF_W_NODES;
    for (int k = 0; k < SL_SRBF_W_NODES; k++) {
        float a00 = b[k] + (b[k + sp] - b[k]) * fp;
        float a01 = b[k + sl] + (b[k + sl + sp] - b[k + sl]) * fp;
        float a10 = b[k + sx] + (b[k + sx + sp] - b[k + sx]) * fp;
        float a11 = b[k + sx + sl] + (b[k + sx + sl + sp] - b[k + sx + sl]) * fp;
        float a0 = a00 + (a01 - a00) * fl, a1 = a10 + (a11 - a10) * fl;
        out[k] = a0 + (a1 - a0) * fx;
    }
}
SL_INLINE void sl_srbf_W(SL_GLOBAL const float *Htab, int mode, float x, float lam, float phi,
                         float out[SL_SRBF_W_NODES]) {
    sl_srbf_W_loglam(Htab, mode, x, log(sl_maxf(lam, 1e-30f)), phi, out);
}

/* sum_i A_p(c_i) W_i(1/eta', lam_w, phi) for mode c (TT: mode 0, TRT: 1): the exactly convolved
 * N'_p = int g^c(x; 0, lam_w) N_p(phi - x) dx divided by int g^c(lam_w) (the caller multiplies
 * by the normalisation it wants). */
SL_INLINE float sl_srbf_fast_NW(SL_GLOBAL const float *Htab, const sl_mq_mode *c, int mode,
                                float lam_w, float phi) {
    float W[SL_SRBF_W_NODES];
    sl_srbf_W(Htab, mode, c->inv_etap, lam_w, phi, W);
    float sum = 0.0f;
    for (int i = 0; i < SL_SRBF_W_NODES; i++) {
        sum += sl_mq_A(c, sl_srbf_w_s[i], sl_srbf_w_c[i]) * W[i];
    }
    return sum;
}

/* cos^2 ti / cos^2 td N'_t at node ti with exact normalisations (see the header comment). */
SL_INLINE float sl_srbf_fast_node(const sl_fiber_params *fp, SL_GLOBAL const float *C,
                                  SL_GLOBAL const float *H, float theta_o, float phi_o, float phi_j,
                                  float cos_tj, float lambda, float ti, int t) {
    float td, cos_td, sin_td, geo;
    sl_srbf_az a;
    if (!sl_srbf_node_setup(theta_o, phi_o, phi_j, cos_tj, lambda, ti, &td, &cos_td, &sin_td, &geo,
                            &a))
        return 0.0f;
    a.z = 2.0f * SL_PI_F * sl_srbf_i0e_fast(2.0f / (a.lam_p * a.lam_p));
    if (t == 0) {
        /* R: Schlick's part exactly by Xu's C_k expansion (a degree-5 polynomial in
         * c = |cos(phi/2)|), plus the exact Fresnel's residual F - F_schlick, smooth and small,
         * by the product quadrature W (F alone is too steep near c = 0 for 4 nodes in c) */
        float Cn[7];
        sl_srbf_C(C, a.lam_p, a.phi, Cn);
        float r = sl_srbf_xu_R(&a, Cn, fp->eta, cos_td);
        if (fp->fresnel != 1) {
            float W[SL_SRBF_W_NODES], res = 0.0f, tr;
            sl_srbf_W(H, 2, 0.0f, a.lam_p, a.phi, W);
            for (int i = 0; i < SL_SRBF_W_NODES; i++) {
                float ci = cos_td * sl_srbf_w_c[i];
                res += (sl_mq_fresnel(fp->eta, ci, 0, &tr) - sl_mq_fresnel(fp->eta, ci, 1, &tr)) *
                       W[i];
            }
            r += a.z * res;
        }
        return geo * sl_maxf(r, 0.0f);
    }
    if (t == 1) {
        /* TT: the tabulated exact convolution (W), absorption and Fresnel at the nodes */
        sl_mq_mode c;
        if (!sl_mq_mode_setup(&c, fp, 1, fp->eta, cos_td, sin_td)) return 0.0f;
        return geo * a.z * sl_srbf_fast_NW(H, &c, 0, a.lam_p, a.phi);
    }
    float eta_t = sl_srbf_trt_eta(fp, C, &a);
    /* TRT: N_TRT is the root sum convolved with the normalised g^c(w_c) (numerics.md sec. 3);
     * g^c(lambda') * g^c(w_c) / int g^c(w_c) ~ int g^c(lambda') g^c(lambda3) / int g^c(lambda3)
     * with lambda3^2 = lambda'^2 + w_c^2 (variances add; the integral is kept exact). */
    sl_mq_mode c;
    if (!sl_mq_mode_setup(&c, fp, 2, eta_t, cos_td, sin_td)) return 0.0f;
    float wc = fp->caustic_width;
    float l3 = sqrt(a.lam_p * a.lam_p + wc * wc);
    return geo * a.z * sl_srbf_fast_NW(H, &c, 1, l3, a.phi);
}

/* The previous rule (3 azimuthal nodes per mode, 9 per lobe), kept for comparison
 * (-DSL_SRBF_FAST_PERNODE makes sl_srbf_fast use it). */
SL_INLINE void sl_srbf_fast_pernode(const sl_fiber_params *fp, SL_GLOBAL const float *C,
                                    SL_GLOBAL const float *H, float theta_o, float phi_o,
                                    float theta_j, float phi_j, float lambda, float out[4]) {
    float cos_tj = sl_maxf(cos(theta_j), 0.0f);
    float inv_l2 = 1.0f / (lambda * lambda), total = 0.0f;
    /* 1e-5 of the error floor 0.03 pi lambda^2 (1 - e^(-4/lambda^2)) */
#if SL_SRBF_FAST_AZ_NODES != 3
    float skip = 1e-5f * 0.03f * SL_PI_F * lambda * lambda * (1.0f - exp(-4.0f * inv_l2));
#endif
    for (int t = 0; t < 3; t++) {
        float beta = fp->beta[t], mu_m = 2.0f * fp->alpha[t] - theta_o, w2 = 4.0f * beta * beta;
        float l2 = lambda * lambda;
        float mu = (theta_j * w2 + mu_m * l2) / (w2 + l2);
        float s = sqrt(0.5f * l2 * w2 / (l2 + w2)); /* std of the product */
        float lo = sl_maxf(mu - 3.5f * s, -0.5f * SL_PI_F),
              hi = sl_minf(mu + 3.5f * s, 0.5f * SL_PI_F);
        float acc = 0.0f;
        if (hi > lo) {
            float c = 0.5f * (lo + hi), h = 0.5f * (hi - lo);
#if SL_SRBF_FAST_AZ_NODES == 3
            /* the azimuthal factor (the expensive part) is smooth in theta_i: evaluated at the
             * 3 Gauss points of [lo, hi] and interpolated by its quadratic at the 6 nodes, where
             * the sharp g^c M is evaluated exactly */
            float fz[3];
            for (int j = 0; j < 3; j++) {
                float ti = c + h * sl_srbf_az3[j];
                fz[j] = sl_srbf_fast_node(fp, C, H, theta_o, phi_o, phi_j, cos_tj, lambda, ti, t);
            }
#endif
            for (int k = 0; k < SL_SRBF_FAST_NODES; k++) {
                float ti = c + h * sl_srbf_glx6[k];
                float sd = sin(0.5f * (ti - theta_j));
                float g = exp(-4.0f * sd * sd * inv_l2); /* exact g^c(ti; tj, lambda) */
                float M = sl_mq_M(0.5f * (theta_o + ti), fp->alpha[t], beta);
                float wgm = sl_srbf_glw6[k] * g * M;
#if SL_SRBF_FAST_AZ_NODES == 3
                float u = sl_srbf_glx6[k], q = sl_srbf_az3[2]; /* nodes -q, 0, q */
                float l0 = u * (u - q) / (2.0f * q * q), l2 = u * (u + q) / (2.0f * q * q);
                acc += wgm * (l0 * fz[0] + (1.0f - l0 - l2) * fz[1] + l2 * fz[2]);
#else
                /* a node whose longitudinal weight is negligible skips the azimuthal part (the
                 * expensive one): its factor geo z N' is below ~1e2 (z <= 2 pi, N' <= ~2,
                 * geo = cos^2 ti / cos^2 td), so this drops at most 1e-3 of the error floor
                 * 0.03 int G of numerics.md sec. 5 */
                if (!(wgm * h > skip)) continue;
                acc +=
                    wgm * sl_srbf_fast_node(fp, C, H, theta_o, phi_o, phi_j, cos_tj, lambda, ti, t);
#endif
            }
            acc *= h;
        }
        if (!(acc >= 0.0f && acc <= SL_FLT_MAX)) acc = acc > 0.0f ? SL_FLT_MAX : 0.0f;
        out[t] = acc;
        total += acc;
    }
    out[3] = total;
}

/* ---- the multi-channel fast path (the renderer's: issue 5 speed, RGB batches) ----
 * Same rule and formulas as sl_srbf_fast_pernode (3 azimuthal nodes per mode on that mode's
 * product lobe, 8 longitudinal nodes), restructured so that nch absorption coefficients (1..3,
 * the colour channels or per-strand values) share every channel-independent quantity: the
 * longitudinal nodes and g^c M_t, and per azimuthal node the geometry, lambda', i0e, the table
 * lookups (log lambda' once per node, shared by C and W), the 4 Fresnel values and absorption
 * paths sqrt(1 - s_i^2/eta'^2); only exp(-2 n sigma_a' path) is per channel. R does not depend
 * on sigma_a at all.
 * Measured (docs/srbf.md, "Speed"): the cost is dominated by the table lookups (~4 cache lines
 * per trilinear W lookup in a 1.6 MB table, ~50 ns each on random rows), not by arithmetic; so
 * evaluating all modes at shared nodes (4 nodes x 4 lookups instead of 9 nodes x 12 lookups in
 * total) did not pay, and lost accuracy (median 0.0063, max 0.185 on the stiff sample). */
#define SL_SRBF_MAXCH 3

/* Branch-free float exp and sin, so that the loops over the 8 longitudinal nodes and the 4 W
 * nodes vectorise in C (libm's expf/sinf are calls GCC cannot vectorise without -ffast-math) and
 * cost a few multiply-adds on the device. exp: Cephes expf (Cody-Waite reduction, degree-7
 * polynomial; about 1 ulp), 0 below -87 (the callers' weights are then negligible: e^-87 ~ 2e-38),
 * clamped at 88; arguments here are finite and <= 80 (a NaN would give ~2e-38, not NaN).
 * sin: |x| <= pi/2 only, Taylor to x^11 (absolute error <= 6e-8 at pi/2, below the float ulp of
 * 1). */
#if SL_OPENCL
#define sl_srbf_pow2i(n) as_float(((n) + 127) << 23)
#else
SL_INLINE float sl_srbf_pow2i(int32_t n) {
    union {
        int32_t i;
        float f;
    } u;
    u.i = (n + 127) << 23;
    return u.f;
}
#endif
SL_INLINE float sl_srbf_exp(float x) {
    float xc = x > -87.0f ? x : -87.0f;
    xc = xc < 88.0f ? xc : 88.0f;
    /* round to nearest without a branch: adding 1.5 * 2^23 leaves no fraction bits */
    float fn = (xc * 1.44269504088896341f + 12582912.0f) - 12582912.0f;
    int n = (int)fn;
    float r = xc - fn * 0.693359375f + fn * 2.12194440e-4f; /* Cody-Waite ln 2 split */
    float p = 1.9875691500e-4f;
    p = p * r + 1.3981999507e-3f;
    p = p * r + 8.3334519073e-3f;
    p = p * r + 4.1665795894e-2f;
    p = p * r + 1.6666665459e-1f;
    p = p * r + 5.0000001201e-1f;
    float y = (p * r * r + r + 1.0f) * sl_srbf_pow2i(n);
    return x < -87.0f ? 0.0f : y;
}
/* cos: |x| <= pi/2 only, Taylor to x^12 (absolute error <= 7e-9 at pi/2). */
SL_INLINE float sl_srbf_cos_hp(float x) {
    float x2 = x * x;
    float p = 2.0876756988e-9f;
    p = p * x2 - 2.7557319224e-7f;
    p = p * x2 + 2.4801587302e-5f;
    p = p * x2 - 1.3888888889e-3f;
    p = p * x2 + 4.1666666667e-2f;
    p = p * x2 - 0.5f;
    return 1.0f + x2 * p;
}
SL_INLINE float sl_srbf_sin_hp(float x) {
    float x2 = x * x;
    float p = -2.5052108385e-8f;
    p = p * x2 + 2.7557319224e-6f;
    p = p * x2 - 1.9841269841e-4f;
    p = p * x2 + 8.3333333333e-3f;
    p = p * x2 - 1.6666666667e-1f;
    return x + x * x2 * p;
}

/* F and 1 - F of sl_mq_fresnel at cos_i = cos_td c_i (the 4 W nodes; cos_td in (0, 1], so
 * cos_i in (0, 1)), branch-free: the exact one with one division (1/(p q) gives 1/p and 1/q).
 * Same formulas as sl_mq_fresnel; differs by float rounding only. */
SL_INLINE void sl_srbf_fresnel4(float eta, float cos_td, int schlick, float F[SL_SRBF_W_NODES],
                                float tr[SL_SRBF_W_NODES]) {
    if (schlick) {
        float f0 = (eta - 1.0f) / (eta + 1.0f);
        f0 *= f0;
        for (int i = 0; i < SL_SRBF_W_NODES; i++) {
            float ci = cos_td * sl_srbf_w_c[i];
            float c = 1.0f - ci, c2 = c * c;
            tr[i] = (1.0f - f0) * ci * (1.0f + c + c2 + c2 * c + c2 * c2); /* (1-f0)(1 - c^5) */
            F[i] = f0 + (1.0f - f0) * c2 * c2 * c;
        }
        return;
    }
    float e2 = eta * eta;
    for (int i = 0; i < SL_SRBF_W_NODES; i++) {
        float ci = cos_td * sl_srbf_w_c[i];
        float s2t = (1.0f - ci) * (1.0f + ci) / e2; /* as sl_mq_fresnel: 1 - s2t is sensitive */
        float ct = sqrt(s2t < 1.0f ? 1.0f - s2t : 0.0f), a = eta * ct, b = eta * ci;
        float p = ci + a, q = b + ct, inv = 1.0f / (p * q);
        float d1 = q * inv, d2 = p * inv;
        float rs = (ci - a) * d1, rp = (b - ct) * d2;
        float fe = 0.5f * (rs * rs + rp * rp);
        float te = 2.0f * (ci * a * d1 * d1 + b * ct * d2 * d2);
        F[i] = s2t >= 1.0f ? 1.0f : fe;
        tr[i] = s2t >= 1.0f ? 0.0f : te;
    }
}

/* Normalised C_k (k = 0..6) at (lambda', |phi|) from log lambda' (sl_srbf_C of srbf_xu.h). */
SL_INLINE void sl_srbf_C_loglam(SL_GLOBAL const float *C, float log_lam, float phi, float out[7]) {
    int il, ip;
    float fl = sl_srbf_grid(log_lam, log(SL_SRBF_LMIN), log(SL_SRBF_LMAX), SL_SRBF_NL, &il);
    float fp = sl_srbf_grid(fabs(phi), 0.0f, SL_PI_F, SL_SRBF_NPHI, &ip);
    SL_GLOBAL const float *c00 = C + ((il * SL_SRBF_NPHI) + ip) * 8;
    SL_GLOBAL const float *c10 = c00 + SL_SRBF_NPHI * 8;
    for (int k = 0; k < 7; k++) {
        float a = c00[k] + (c00[k + 8] - c00[k]) * fp;
        float b = c10[k] + (c10[k + 8] - c10[k]) * fp;
        out[k] = a + (b - a) * fl;
    }
}

/* cos^2 ti / cos^2 td N'_t of mode t at node ti for nch channels (sig[ch] = sigma_a):
 * out[ch]. The formulas of sl_srbf_fast_node. */
SL_INLINE void sl_srbf_fast_az(const sl_fiber_params *fp, SL_GLOBAL const float *C,
                               SL_GLOBAL const float *H, float theta_o, float phi, float phi_sum,
                               float cos_tj, float lambda, float ti, int t, int nch,
                               const float *sig, float *out) {
    for (int ch = 0; ch < nch; ch++)
        out[ch] = 0.0f;
    float cti = cos(ti);
    if (!(cti > 1e-7f)) return;
    float td = 0.5f * (theta_o - ti);
    float cos_td = cos(td), sin_td = sin(td);
    if (!(cos_td > 1e-7f)) return;
    float geo = cti * cti / (cos_td * cos_td);
    float cc = cti * cos_tj;
    float lam_p = cc > 0.0f ? lambda / sqrt(cc) : SL_SRBF_LMAX;
    lam_p = sl_clampf(lam_p, SL_SRBF_LMIN, SL_SRBF_LMAX);
    float gz = geo * 2.0f * SL_PI_F * sl_srbf_i0e_fast(2.0f / (lam_p * lam_p));
    float llam = log(lam_p);
    int schlick = fp->fresnel == 1;
    float W[SL_SRBF_W_NODES];
    if (t == 0) {
        /* R: Schlick's part exactly by Xu's C_k expansion (a degree-5 polynomial in
         * c = |cos(phi/2)|), plus the exact Fresnel's residual F - F_schlick, smooth and small,
         * by the product quadrature W (F alone is too steep near c = 0 for 4 nodes in c) */
        float Cn[7];
        sl_srbf_C_loglam(C, llam, phi, Cn);
        sl_srbf_az a;
        a.z = 1.0f;
        float r = sl_srbf_xu_R(&a, Cn, fp->eta, cos_td);
        if (!schlick) {
            sl_srbf_W_loglam(H, 2, 0.0f, llam, phi, W);
            float Fe[SL_SRBF_W_NODES], Fs[SL_SRBF_W_NODES], tr[SL_SRBF_W_NODES], res = 0.0f;
            sl_srbf_fresnel4(fp->eta, cos_td, 0, Fe, tr);
            sl_srbf_fresnel4(fp->eta, cos_td, 1, Fs, tr);
            for (int i = 0; i < SL_SRBF_W_NODES; i++)
                res += (Fe[i] - Fs[i]) * W[i];
            r += res;
        }
        float v = gz * sl_maxf(r, 0.0f);
        for (int ch = 0; ch < nch; ch++)
            out[ch] = v;
        return;
    }
    float eta_t = fp->eta, lw = llam;
#ifndef SL_SRBF_ROUND_ONLY
    if (t == 2 && fp->eccentricity != 1.0f) {
        /* Xu's averaged eta* (Eq. 25-26) */
        float Ce[7];
        sl_srbf_C_loglam(C, llam, phi_sum, Ce);
        float mc = 2.0f * Ce[2] / sl_maxf(Ce[0], 1e-30f) - 1.0f;
        float aa = fp->eccentricity, eta = fp->eta;
        float e1 = 2.0f * (eta - 1.0f) * aa * aa - eta + 2.0f;
        float e2 = 2.0f * (eta - 1.0f) / (aa * aa) - eta + 2.0f;
        eta_t = 0.5f * ((e1 + e2) + mc * (e1 - e2));
    }
#endif
    if (t == 2) {
        /* TRT: g^c(lambda') * g^c(w_c) / int g^c(w_c) ~ int g^c(lambda') g^c(lambda3) /
         * int g^c(lambda3), lambda3^2 = lambda'^2 + w_c^2 (variances add) */
        float wc = fp->caustic_width;
        lw = 0.5f * log(lam_p * lam_p + wc * wc);
    }
    /* sl_mq_mode_setup: eta' and sigma_a' = sigma_a / cos theta_t */
    float q = eta_t * eta_t - sin_td * sin_td;
    if (!(eta_t > 0.0f) || !(q > 0.0f)) return;
    float sq = sqrt(q), inv_etap = cos_td / sq, sscale = eta_t / sq;
    sl_srbf_W_loglam(H, t == 1 ? 0 : 1, inv_etap, lw, phi, W);
    /* A_p at the 4 nodes c_i (sl_mq_A): (1-F)^2 [F] T^p, T = exp(-2 sigma_a' r_i) */
    float g[SL_SRBF_W_NODES], rp[SL_SRBF_W_NODES], F[SL_SRBF_W_NODES], tr[SL_SRBF_W_NODES];
    sl_srbf_fresnel4(eta_t, cos_td, schlick, F, tr);
    for (int i = 0; i < SL_SRBF_W_NODES; i++) {
        float s = sl_srbf_w_s[i] * inv_etap, q2 = 1.0f - s * s;
        rp[i] = sqrt(q2 > 0.0f ? q2 : 0.0f);
        g[i] = tr[i] * tr[i] * (t == 2 ? F[i] : 1.0f) * W[i];
    }
    float kabs = (t == 2 ? -4.0f : -2.0f) * sscale;
    for (int ch = 0; ch < nch; ch++) {
        float sum = 0.0f, k = kabs * sig[ch];
        for (int i = 0; i < SL_SRBF_W_NODES; i++)
            sum += g[i] * sl_srbf_exp(k * rp[i]);
        out[ch] = gz * sum;
    }
}

/* 3-point Gauss nodes of the azimuthal factor (sl_srbf_az3) and, at each of the
 * SL_SRBF_FAST_NODES longitudinal nodes, the Lagrange weights of the quadratic through them
 * (nodes -q, 0, q: l0 = u (u - q) / 2q^2, l2 = u (u + q) / 2q^2), precomputed. */
SL_INLINE void sl_srbf_fast_lagrange(int k, float *l0, float *l2) {
    float u = sl_srbf_glx6[k], q = sl_srbf_az3[2];
    *l0 = u * (u - q) / (2.0f * q * q);
    *l2 = u * (u + q) / (2.0f * q * q);
}

/* The fast response for nch (1..3) absorption coefficients sig[ch] at once:
 * out[t * nch + ch] = I_t (t = 0 R, 1 TT, 2 TRT). */
SL_INLINE void sl_srbf_fast_rgb(const sl_fiber_params *fp, SL_GLOBAL const float *C,
                                SL_GLOBAL const float *H, float theta_o, float phi_o, float theta_j,
                                float phi_j, float lambda, int nch, const float *sig, float *out) {
    float cos_tj = sl_maxf(cos(theta_j), 0.0f);
    float l2 = lambda * lambda, inv_l2 = 1.0f / l2;
    float phi = sl_wrap_pi(phi_o - phi_j), phi_sum = sl_wrap_pi(phi_o + phi_j);
    for (int t = 0; t < 3; t++) {
        float beta = fp->beta[t], mu_m = 2.0f * fp->alpha[t] - theta_o, w2 = 4.0f * beta * beta;
        float mu = (theta_j * w2 + mu_m * l2) / (w2 + l2);
        float s = sqrt(0.5f * l2 * w2 / (l2 + w2)); /* std of the product */
        float lo = sl_maxf(mu - 3.5f * s, -0.5f * SL_PI_F),
              hi = sl_minf(mu + 3.5f * s, 0.5f * SL_PI_F);
        float acc[SL_SRBF_MAXCH] = {0.0f, 0.0f, 0.0f};
        if (hi > lo) {
            float c = 0.5f * (lo + hi), h = 0.5f * (hi - lo);
            /* the azimuthal factor (the expensive part) is smooth in theta_i: evaluated at the
             * 3 Gauss points of [lo, hi] and interpolated by its quadratic at the 8 nodes, where
             * the sharp g^c M is evaluated exactly */
            float fz[3][SL_SRBF_MAXCH];
            for (int j = 0; j < 3; j++)
                sl_srbf_fast_az(fp, C, H, theta_o, phi, phi_sum, cos_tj, lambda,
                                c + h * sl_srbf_az3[j], t, nch, sig, fz[j]);
            /* sum_k w_k g^c M_t (l0 f0 + l1 f1 + l2 f2) = S0 f0 + S1 f1 + S2 f2: the weighted
             * sums do not depend on the channel; the loop over the nodes is branch-free (it
             * vectorises in C) */
            float inv_b = 1.0f / beta, alpha = fp->alpha[t];
            float S0 = 0.0f, S1 = 0.0f, S2 = 0.0f;
            for (int k = 0; k < SL_SRBF_FAST_NODES; k++) {
                float ti = c + h * sl_srbf_glx6[k];
                float sd = sl_srbf_sin_hp(0.5f * (ti - theta_j)); /* |.| <= pi/2 */
                float xm = (0.5f * (theta_o + ti) - alpha) * inv_b;
                /* exact g^c(ti; tj, lambda) x M_t (Eq. 7) in one exp */
                float wgm = sl_srbf_glw6[k] * sl_srbf_exp(-4.0f * sd * sd * inv_l2 - xm * xm);
                float l0, l2k;
                sl_srbf_fast_lagrange(k, &l0, &l2k);
                S0 += wgm * l0;
                S1 += wgm * (1.0f - l0 - l2k);
                S2 += wgm * l2k;
            }
            float norm = h / (SL_SQRT_PI_F * beta);
            for (int ch = 0; ch < nch; ch++)
                acc[ch] = norm * (S0 * fz[0][ch] + S1 * fz[1][ch] + S2 * fz[2][ch]);
        }
        for (int ch = 0; ch < nch; ch++) {
            float v = acc[ch];
            if (!(v >= 0.0f && v <= SL_FLT_MAX)) v = v > 0.0f ? SL_FLT_MAX : 0.0f;
            out[t * nch + ch] = v;
        }
    }
}

/* out = I_R, I_TT, I_TRT, I for fp's sigma_a (one channel). */
SL_INLINE void sl_srbf_fast(const sl_fiber_params *fp, SL_GLOBAL const float *C,
                            SL_GLOBAL const float *H, float theta_o, float phi_o, float theta_j,
                            float phi_j, float lambda, float out[4]) {
#ifdef SL_SRBF_FAST_PERNODE
    sl_srbf_fast_pernode(fp, C, H, theta_o, phi_o, theta_j, phi_j, lambda, out);
#else
    float sig = fp->sigma_a;
    sl_srbf_fast_rgb(fp, C, H, theta_o, phi_o, theta_j, phi_j, lambda, 1, &sig, out);
    out[3] = out[0] + out[1] + out[2];
#endif
}

/* One row of the RGB batch (cpu/srbf_c.h slc_srbf_rgb_batch, srbf.cl sl_srbf_eval_rgb):
 * out[3 t + ch] = I_t for sigma_a = sig[ch]. method 1: fast (channels share everything but the
 * absorption; equal sigma_a cost one channel); else Xu's closed form per channel. */
SL_INLINE void sl_srbf_rgb_row(const sl_fiber_params *fp, SL_GLOBAL const float *C,
                               SL_GLOBAL const float *H, int method, int segments, float theta_o,
                               float phi_o, float theta_j, float phi_j, float lambda,
                               const float sig[3], float out[9]) {
    if (method == 1) {
        if (sig[0] == sig[1] && sig[0] == sig[2]) {
            float o[3];
            sl_srbf_fast_rgb(fp, C, H, theta_o, phi_o, theta_j, phi_j, lambda, 1, sig, o);
            for (int t = 0; t < 3; t++)
                out[3 * t] = out[3 * t + 1] = out[3 * t + 2] = o[t];
        } else
            sl_srbf_fast_rgb(fp, C, H, theta_o, phi_o, theta_j, phi_j, lambda, 3, sig, out);
        return;
    }
#ifndef SL_SRBF_FAST_ONLY
    sl_fiber_params f = *fp;
    for (int ch = 0; ch < 3; ch++) {
        float o[4];
        f.sigma_a = sig[ch];
        sl_srbf_xu(&f, C, H, segments, theta_o, phi_o, theta_j, phi_j, lambda, o);
        for (int t = 0; t < 3; t++)
            out[3 * t + ch] = o[t];
    }
#endif
}

#endif
