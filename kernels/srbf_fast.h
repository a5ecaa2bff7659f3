/* srbf_fast.h: the renderer's own closed-form SRBF response (`--method fast`, the default on c
 * and opencl), float, shared by the C twin and OpenCL. Xu's azimuthal closed forms
 * (kernels/srbf_xu.h) with these fixes (docs/srbf.md, "fast"):
 *  - the longitudinal lobe is the exact circular Gaussian g^c(theta_i; theta_j, lambda) and M_t
 *    is evaluated as is (no Gaussian product, appendix D not used);
 *  - the outer integral uses SL_SRBF_FAST_NODES Gauss-Legendre nodes on the product lobe
 *    [mu - 3.5 s, mu + 3.5 s] clipped to [-pi/2, pi/2] (no nodes wasted at +-pi/2, where the
 *    integrand is 0), mu and s the centre and standard width of the Gaussian product;
 *  - circular-Gaussian integrals are exact (2 pi e^-k I0(k)) instead of sqrt(pi) lambda;
 *  - the material's Fresnel in R (through the same C_k expansion: exact Fresnel is applied as a
 *    per-node correction factor F_exact / F_schlick at h = -sin(phi/2)).
 * Not fixed yet (docs/srbf.md "Status"): TT's and TRT's azimuthal fits. */
#ifndef SL_SRBF_FAST_H
#define SL_SRBF_FAST_H

#include "srbf_xu.h"

#ifndef SL_SRBF_FAST_NODES
#define SL_SRBF_FAST_NODES 6
#endif

/* 6-point Gauss-Legendre on [-1, 1]. */
#if SL_OPENCL
static __constant float sl_srbf_glx6[6] = {-0.932469514203152f, -0.661209386466265f,
                                           -0.238619186083197f, 0.238619186083197f,
                                           0.661209386466265f,  0.932469514203152f};
static __constant float sl_srbf_glw6[6] = {0.171324492379170f, 0.360761573048139f,
                                           0.467913934572691f, 0.467913934572691f,
                                           0.360761573048139f, 0.171324492379170f};
#else
static const float sl_srbf_glx6[6] = {-0.932469514203152f, -0.661209386466265f, -0.238619186083197f,
                                      0.238619186083197f,  0.661209386466265f,  0.932469514203152f};
static const float sl_srbf_glw6[6] = {0.171324492379170f, 0.360761573048139f, 0.467913934572691f,
                                      0.467913934572691f, 0.360761573048139f, 0.171324492379170f};
#endif

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
    a.z = 2.0f * SL_PI_F * sl_mq_i0e(2.0f / (a.lam_p * a.lam_p));
    if (t == 0) {
        float Cn[7];
        sl_srbf_C(C, a.lam_p, a.phi, Cn);
        float r = sl_srbf_xu_R(&a, Cn, fp->eta, cos_td);
        if (fp->fresnel != 1) {
            /* exact Fresnel: rescale by F_exact / F_schlick at the lobe's own azimuth */
            float ci = cos_td * fabs(cos(0.5f * a.phi));
            float fs = sl_fresnel_schlick(fp->eta, ci);
            if (fs > 0.0f) r *= sl_fresnel_exact(fp->eta, ci) / fs;
        }
        return geo * r;
    }
    if (t == 1) {
        sl_mq_mode c;
        if (!sl_mq_mode_setup(&c, fp, 1, fp->eta, cos_td, sin_td)) return 0.0f;
        float A0 = sl_mq_A(&c, 0.0f, 1.0f);
        float d = 2.0f - 2.0f * c.inv_etap;
        if (!(A0 > 0.0f) || !(d > 0.0f)) return 0.0f;
        float btt = A0 / (2.0f * d);
        float Hk[3];
        sl_srbf_H(H, fp->fresnel == 1, 0, fp->eta, td, Hk);
        float E = sl_srbf_energy(Hk, c.sigma_p, c.inv_etap);
        /* energy-preserving width with the exact circular integral: solve
         * 2 pi i0e(2/l^2) = E / b_tt by one Newton-free inversion (sqrt(pi) l is its small-l
         * limit; the exact one saturates at 2 pi) */
        float ratio = E / (btt * 2.0f * SL_PI_F);
        if (!(ratio > 0.0f)) return 0.0f;
        ratio = sl_minf(ratio, 0.999f);
        float l = ratio * 2.0f * SL_SQRT_PI_F; /* start: sqrt(pi) l = 2 pi ratio */
        for (int it = 0; it < 6; it++) {       /* fixed point on 2 pi i0e(2/l^2) = 2 pi ratio */
            float f = sl_mq_i0e(2.0f / (l * l));
            l *= ratio / sl_maxf(f, 1e-30f) > 0.0f ? sqrt(ratio / sl_maxf(f, 1e-30f)) : 1.0f;
        }
        return geo * btt * sl_srbf_cg_prod(a.lam_p, l, a.phi - SL_PI_F, 1);
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
    return geo * sl_srbf_xu_TRT(&a, fp, H, eta_t, cos_td, sin_td, td, 1);
}

SL_INLINE void sl_srbf_fast(const sl_fiber_params *fp, SL_GLOBAL const float *C,
                            SL_GLOBAL const float *H, float theta_o, float phi_o, float theta_j,
                            float phi_j, float lambda, float out[4]) {
    float cos_tj = sl_maxf(cos(theta_j), 0.0f);
    float inv_l2 = 1.0f / (lambda * lambda), total = 0.0f;
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
            for (int k = 0; k < SL_SRBF_FAST_NODES; k++) {
                float ti = c + h * sl_srbf_glx6[k];
                float sd = sin(0.5f * (ti - theta_j));
                float g = exp(-4.0f * sd * sd * inv_l2); /* exact g^c(ti; tj, lambda) */
                float M = sl_mq_M(0.5f * (theta_o + ti), fp->alpha[t], beta);
                acc += sl_srbf_glw6[k] * g * M *
                       sl_srbf_fast_node(fp, C, H, theta_o, phi_o, phi_j, cos_tj, lambda, ti, t);
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
