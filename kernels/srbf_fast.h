/* srbf_fast.h: the renderer's own closed-form SRBF response (`--method fast`, the default on c
 * and opencl), float, shared by the C twin and OpenCL. Xu's outer structure (kernels/srbf_xu.h)
 * with every approximation the issue lists replaced (docs/srbf.md, "Fast path"):
 *  - azimuth: the exactly convolved N'_p from the W table (tabulated per 1/eta', lambda', phi
 *    with the material factored out: a product quadrature in h on 4 Chebyshev nodes in
 *    c = cos gamma_i, so Fresnel, absorption, eta, sigma_a stay editable); R keeps Xu's exact
 *    C_k expansion for Schlick's part and adds the exact Fresnel's residual through W; TRT's w_c
 *    enters as lambda3^2 = lambda'^2 + w_c^2;
 *  - longitudinal: the exact circular Gaussian g^c(theta_i; theta_j, lambda) and M_t as is, 6
 *    Gauss-Legendre nodes on the product lobe [mu - 3.5 s, mu + 3.5 s] clipped to [-pi/2, pi/2],
 *    the smooth azimuthal factor evaluated at 3 of them and interpolated;
 *  - circular-Gaussian integrals exact (2 pi e^-k I0(k)).
 * The W table lives in the H buffer after H_k (layout in kernels/srbf_xu.h). */
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
 * rounding of what it multiplies): no loop, unlike the series of sl_mq_i0e, which cost a third of
 * the fast path's time. */
SL_INLINE float sl_srbf_i0e_fast(float x) {
    x = fabs(x);
    if (x < 3.75f) {
        float t = x * (1.0f / 3.75f);
        t *= t;
        float p =
            1.0f +
            t * (3.5156229f +
                 t * (3.0899424f +
                      t * (1.2067492f + t * (0.2659732f + t * (0.0360768f + t * 0.0045813f)))));
        return p * exp(-x);
    }
    float t = 3.75f / x;
    float p =
        0.39894228f +
        t * (0.01328592f +
             t * (0.00225319f +
                  t * (-0.00157565f +
                       t * (0.00916281f +
                            t * (-0.02057706f +
                                 t * (0.02635537f + t * (-0.01647633f + t * 0.00392377f)))))));
    return p / sqrt(x);
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

/* W_i (i = 0..SL_SRBF_W_NODES-1) of mode (0 TT, 1 TRT) at (x = 1/eta', lambda, |phi|):
 * trilinear, clamped to the table range. Wtab: the H buffer (W starts after H_k). */
SL_INLINE void sl_srbf_W(SL_GLOBAL const float *Htab, int mode, float x, float lam, float phi,
                         float out[SL_SRBF_W_NODES]) {
    int ix, il, ip;
    float fx = sl_srbf_grid(x, 0.0f, 1.0f, SL_SRBF_W_NX, &ix);
    int sx = SL_SRBF_W_NL * SL_SRBF_W_NP * SL_SRBF_W_NODES;
    if (mode == 2) { /* R: one slice, no eta' axis */
        ix = 0;
        fx = 0.0f;
        sx = 0;
    }
    float fl = sl_srbf_grid(log(sl_maxf(lam, 1e-30f)), log(SL_SRBF_W_LMIN), log(SL_SRBF_LMAX),
                            SL_SRBF_W_NL, &il);
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
    float cti = cos(ti);
    if (!(cti > 1e-7f)) return 0.0f;
    float td = 0.5f * (theta_o - ti);
    float cos_td = cos(td), sin_td = sin(td);
    if (!(cos_td > 1e-7f)) return 0.0f;
    float geo = cti * cti / (cos_td * cos_td);
    sl_srbf_az a;
    a.phi = sl_wrap_pi(phi_o - phi_j);
    a.phi_sum = sl_wrap_pi(phi_o + phi_j);
    float cc = cti * cos_tj;
    a.lam_p = cc > 0.0f ? lambda / sqrt(cc) : SL_SRBF_LMAX;
    a.lam_p = sl_clampf(a.lam_p, SL_SRBF_LMIN, SL_SRBF_LMAX);
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
    float eta_t = fp->eta;
    if (fp->eccentricity != 1.0f) {
        float Ce[7];
        sl_srbf_C(C, a.lam_p, a.phi_sum, Ce);
        float mc = 2.0f * Ce[2] / sl_maxf(Ce[0], 1e-30f) - 1.0f;
        float aa = fp->eccentricity, eta = fp->eta;
        float e1 = 2.0f * (eta - 1.0f) * aa * aa - eta + 2.0f;
        float e2 = 2.0f * (eta - 1.0f) / (aa * aa) - eta + 2.0f;
        eta_t = 0.5f * ((e1 + e2) + mc * (e1 - e2));
    }
    /* TRT: N_TRT is the root sum convolved with the normalised g^c(w_c) (numerics.md sec. 3);
     * g^c(lambda') * g^c(w_c) / int g^c(w_c) ~ int g^c(lambda') g^c(lambda3) / int g^c(lambda3)
     * with lambda3^2 = lambda'^2 + w_c^2 (variances add; the integral is kept exact). */
    sl_mq_mode c;
    if (!sl_mq_mode_setup(&c, fp, 2, eta_t, cos_td, sin_td)) return 0.0f;
    float wc = fp->caustic_width;
    float l3 = sqrt(a.lam_p * a.lam_p + wc * wc);
    return geo * a.z * sl_srbf_fast_NW(H, &c, 1, l3, a.phi);
}

SL_INLINE void sl_srbf_fast(const sl_fiber_params *fp, SL_GLOBAL const float *C,
                            SL_GLOBAL const float *H, float theta_o, float phi_o, float theta_j,
                            float phi_j, float lambda, float out[4]) {
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

#endif
