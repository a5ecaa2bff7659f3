/* dual_material.h: the dual-scattering material terms (Zinke et al. 2008, as Xu 2011 Sec. 4.3.2 Eq.
 * 29-33 uses them) in float, shared by the C twin (cpu/dual_c.c, host/passes/volume/dual.c) and
 * OpenCL: the averaged forward/backward attenuations a_f, a_b, shifts alpha_f, alpha_b, widths
 * beta_f, beta_b and the local backscattering terms A_b, Delta_b, sigma_b, as 1-D tables over
 * theta_d with 1-D SATs of Delta_b and sigma_b (Xu Eq. 31). The double reference is
 * cpu/reference/dual_ref.c; the definitions and every choice are in docs/dual.md:
 *
 *  a_{f,t}(td) = 1/pi int_{-pi/2}^{pi/2} dphi_i int_{pi/2}^{3pi/2} dphi_o N_t(td, phi_o - phi_i)
 *              = 2/pi int_0^pi phi N_t(td, phi) dphi,      a_{b,t}: (pi - phi) instead of phi
 *  (the azimuthal factor of Xu Eq. 33; its longitudinal factor is replaced by 1, i.e. Zinke's
 *  unit-mass lobe, which removes the doubling of Marschner's theta_h-normalised M, d'Eon 2011
 *  Sec. 3; so a_{f,t} + a_{b,t} = int N_t dphi = 1/2 int A_t dh, the energy of mode t).
 *
 * Here they are computed in h, not phi: int w(phi) N_t(phi) dphi = 1/2 int A_t(h) w(Phi_t(h)) dh
 * for any weight w, with w = |phi| (forward) or pi - |phi| (backward); for TRT the caustic
 * convolution moves onto the weight: (|.| * G)(x) = pi/2 - 4/pi sum_{k odd} rho_k cos(kx) / k^2,
 * rho_k = I_k(kappa)/I_0(kappa), kappa = 2/w_c^2 (Fourier series of the von Mises density).
 * The integrand is then smooth in u = asin(h): 8 panels of 8-point Gauss-Legendre on [0, umax]
 * (A and |Phi| are even in h). Eccentricity: TRT is averaged over the fiber's roll (eta* over
 * cos(phi_o + phi_i) uniform on the circle), 8-point Gauss-Legendre in the roll angle. */
#ifndef SL_DUAL_MATERIAL_H
#define SL_DUAL_MATERIAL_H

#include "fiber_marschner.h"

/* Table nodes over theta_d in [0, pi/2] (every term is even in theta_d), uniform; Xu Sec. 5 uses
 * 128 texels. Rows of one channel's table, each SL_DUAL_N floats: */
#define SL_DUAL_N 129
enum {
    SL_DUAL_AF = 0,
    SL_DUAL_AB,
    SL_DUAL_ALPHA_F,
    SL_DUAL_ALPHA_B,
    SL_DUAL_BETA_F,
    SL_DUAL_BETA_B,
    SL_DUAL_A_B,
    SL_DUAL_DELTA_B,
    SL_DUAL_SIGMA_B,
    SL_DUAL_SAT_DELTA_B, /* int_0^td Delta_b, of the piecewise-linear table (Xu Eq. 31) */
    SL_DUAL_SAT_SIGMA_B, /* int_0^td sigma_b */
    SL_DUAL_ROWS
};
#define SL_DUAL_TABLE_FLOATS (SL_DUAL_ROWS * SL_DUAL_N)
/* Backscattering density factor d_b of Zinke 2008 (Xu Sec. 3: "between 0.6-0.8"); the material
 * has no key for it (numerics.md sec. 2), so it is this constant. */
#define SL_DUAL_DB 0.7f
/* Odd Fourier terms of the smoothed TRT weight: k = 1, 3, ..., 2 * SL_DUAL_MAXJ - 1. */
#define SL_DUAL_MAXJ 128
#define SL_DUAL_PANELS 8
#define SL_DUAL_HALF_PI 1.57079632679489661923f

/* The longitudinal width of mode t in the Marschner form every dual-scattering and
 * multiple-scattering formula here is written in (Xu Table 1: M(theta_h) = exp(-(theta_h -
 * alpha)^2 / beta^2) / (sqrt(pi) beta), a Gaussian of standard deviation sqrt(2) beta in theta_i):
 * the marschner width itself; for deon and chiang, whose beta is the standard deviation of M_p
 * in theta (sqrt(v_p)), the width with that spread, beta / sqrt(2) (docs/dual.md). */
SL_INLINE float sl_dual_ms_beta(const sl_fiber_params *fp, int t) {
    return fp->model == 0 ? fp->beta[t] : 0.70710678118654752f * fp->beta[t];
}

/* rho_k = I_k(kappa)/I_0(kappa) for odd k (rho[j], k = 2j + 1), kappa = 2/w^2, by the backward
 * recurrence of q_k = I_k/I_{k-1} = 1/(2k/kappa + q_{k+1}) started with the uniform asymptotic
 * ratio kappa / (k - 1/2 + sqrt((k + 1/2)^2 + kappa^2)). Returns the number of terms needed
 * (rho_k / k^2 < 1e-8), at most SL_DUAL_MAXJ. */
SL_INLINE int sl_dual_vm_coefs(float w, float *rho) {
    float kappa = 2.0f / (w * w);
    const int kmax = 2 * SL_DUAL_MAXJ; /* q_1 .. q_kmax are needed */
    float q[2 * SL_DUAL_MAXJ];
    float ks = (float)(kmax + 24);
    float r = kappa / (ks - 0.5f + sqrt((ks + 0.5f) * (ks + 0.5f) + kappa * kappa));
    for (int k = kmax + 23; k >= 1; k--) {
        r = 1.0f / (2.0f * (float)k / kappa + r);
        if (k <= kmax) q[k - 1] = r;
    }
    float prod = 1.0f;
    int nj = SL_DUAL_MAXJ;
    for (int k = 1; k <= kmax; k++) {
        prod *= q[k - 1];
        if (k & 1) {
            rho[k >> 1] = prod;
            if (prod < 1e-8f * (float)k * (float)k && nj == SL_DUAL_MAXJ) nj = (k >> 1) + 1;
        }
    }
    return nj;
}

/* (|.| * G)(x): the forward weight |phi| convolved with the normalised circular Gaussian of the
 * TRT caustics, from the first nj odd Fourier terms (cos(kx) by the Chebyshev recurrence). */
SL_INLINE float sl_dual_wf_conv(const float *rho, int nj, float x) {
    float c = cos(x), c2 = 2.0f * (2.0f * c * c - 1.0f); /* 2 cos 2x */
    float ck = c, ckm2 = c;                              /* cos(kx), cos((k-2)x) with cos(-x) */
    float sum = 0.0f;
    for (int j = 0; j < nj; j++) {
        float k = (float)(2 * j + 1);
        sum += rho[j] * ck / (k * k);
        float next = c2 * ck - ckm2;
        ckm2 = ck;
        ck = next;
    }
    return SL_DUAL_HALF_PI - (4.0f / SL_PI_F) * sum;
}

/* deon and chiang (they use sl_dual_wf_conv for their smoothed forward weight) */
#include "dual_ec.h"

/* Forward and backward attenuation of mode t (0 R, 1 TT, 2 TRT) with index eta_t at theta_d:
 * *af = 1/pi int_0^umax A_t(sin u) W(Phi_t) cos u du, *ab likewise with pi - W. */
SL_INLINE void sl_dual_mode_ab(const sl_fiber_params *fp, int t, float eta_t, float theta_d,
                               const float *rho, int nj, float *af, float *ab) {
    float cos_td = cos(theta_d), sin_td = sin(theta_d);
    sl_mq_mode c;
    *af = 0.0f;
    *ab = 0.0f;
    if (!sl_mq_mode_setup(&c, fp, t, eta_t, sl_maxf(cos_td, 0.0f), fabs(sin_td))) return;
    float umax = c.inv_etap > 1.0f ? asin(1.0f / c.inv_etap) : SL_DUAL_HALF_PI;
    float hw = 0.5f * umax / (float)SL_DUAL_PANELS, sf = 0.0f, sb = 0.0f;
    for (int k = 0; k < SL_DUAL_PANELS; k++) {
        float mid = hw * (float)(2 * k + 1);
        for (int j = 0; j < 8; j++) {
            float x = sl_mq_glx[j & 3], wt = sl_mq_glw[j & 3];
            float u = mid + ((j & 4) ? -x : x) * hw;
            float su = sin(u), cu = cos(u);
            float W;
            if (t == 0)
                W = 2.0f * u; /* |Phi_R| = 2|u| <= pi */
            else if (t == 1)
                W = SL_PI_F + sl_mq_psi(1, c.inv_etap, u); /* Phi_TT - pi = psi_1 in (-pi, 0] */
            else
                W = sl_dual_wf_conv(rho, nj, sl_mq_psi(2, c.inv_etap, u));
            W = sl_clampf(W, 0.0f, SL_PI_F);
            float a = wt * sl_mq_A(&c, su, cu) * cu;
            sf += a * W;
            sb += a * (SL_PI_F - W);
        }
    }
    *af = sf * hw * SL_INV_PI_F;
    *ab = sb * hw * SL_INV_PI_F;
}

/* 8-point Gauss-Legendre nodes/weights on [0, pi] for the roll average of an eccentric TRT. */
SL_INLINE float sl_dual_roll_node(int j, float *wt) {
    float x = sl_mq_glx[j & 3];
    *wt = 0.5f * sl_mq_glw[j & 3]; /* weights of (1/pi) int_0^pi ds: sum to 1 */
    return SL_DUAL_HALF_PI * (1.0f + ((j & 4) ? -x : x));
}

/* Per-mode a_{f,t}, a_{b,t} at theta_d. rho/nj: sl_dual_vm_coefs(caustic width). */
SL_INLINE void sl_dual_attenuations(const sl_fiber_params *fp, float theta_d, const float *rho,
                                    int nj, float af[3], float ab[3]) {
    for (int t = 0; t < 2; t++)
        sl_dual_mode_ab(fp, t, fp->eta, theta_d, rho, nj, &af[t], &ab[t]);
    if (fp->eccentricity == 1.0f) {
        sl_dual_mode_ab(fp, 2, fp->eta, theta_d, rho, nj, &af[2], &ab[2]);
        return;
    }
    af[2] = ab[2] = 0.0f;
    for (int j = 0; j < 8; j++) {
        float wt, f, b;
        float s = sl_dual_roll_node(j, &wt);
        float eta = sl_eta_star(fp->eta, fp->eccentricity, s);
        sl_dual_mode_ab(fp, 2, eta, theta_d, rho, nj, &f, &b);
        af[2] += wt * f;
        ab[2] += wt * b;
    }
}

/* The nine terms from the per-mode attenuations (out in SL_DUAL_* row order):
 *  a_f = sum_t a_{f,t}; alpha_f = sum a_{f,t} alpha_t / a_f; beta_f^2 = sum a_{f,t} beta_t^2 / a_f
 *  (Xu Sec. 4.3.2, Zinke 2008); b likewise; then Zinke 2008's local backscattering:
 *  A_b = A_1 + A_3, A_1 = a_b a_f^2 / (1 - a_f^2), A_3 = a_b^3 a_f^2 / (1 - a_f^2)^3,
 *  Delta_b = alpha_b (1 - 2 a_b^2 / (1 - a_f^2)^2)
 *          + alpha_f (2 (1 - a_f^2)^2 + 4 a_f^2 a_b^2) / (1 - a_f^2)^3,
 *  sigma_b = (1 + d_b a_f^2) (a_b sqrt(2 beta_f^2 + beta_b^2) + a_b^3 sqrt(2 beta_f^2 + 3
 * beta_b^2)) / (a_b + a_b^3 (2 beta_f + 3 beta_b))        (as printed; docs/dual.md). */
SL_INLINE void sl_dual_combine(const float af_t[3], const float ab_t[3], const float *alpha,
                               const float *beta, float out[9]) {
    float af = 0.0f, ab = 0.0f, waf = 0.0f, wab = 0.0f, wbf = 0.0f, wbb = 0.0f;
    for (int t = 0; t < 3; t++) {
        af += af_t[t];
        ab += ab_t[t];
        waf += af_t[t] * alpha[t];
        wab += ab_t[t] * alpha[t];
        wbf += af_t[t] * beta[t] * beta[t];
        wbb += ab_t[t] * beta[t] * beta[t];
    }
    /* No energy in a hemisphere (cannot happen for R, kept safe): plain means. */
    float mean_a = (alpha[0] + alpha[1] + alpha[2]) / 3.0f;
    float mean_b2 = (beta[0] * beta[0] + beta[1] * beta[1] + beta[2] * beta[2]) / 3.0f;
    float alpha_f = af > 0.0f ? waf / af : mean_a, alpha_b = ab > 0.0f ? wab / ab : mean_a;
    float beta_f = sqrt(af > 0.0f ? wbf / af : mean_b2);
    float beta_b = sqrt(ab > 0.0f ? wbb / ab : mean_b2);
    float af2 = sl_minf(af * af, 0.999999f), ab2 = ab * ab, ab3 = ab2 * ab;
    float om = 1.0f - af2, om2 = om * om, om3 = om2 * om;
    float A1 = ab * af2 / om, A3 = ab3 * af2 / om3;
    float delta =
        alpha_b * (1.0f - 2.0f * ab2 / om2) + alpha_f * (2.0f * om2 + 4.0f * af2 * ab2) / om3;
    float bf2 = beta_f * beta_f, bb2 = beta_b * beta_b;
    float den = ab + ab3 * (2.0f * beta_f + 3.0f * beta_b);
    float sigma =
        den > 0.0f ? (1.0f + SL_DUAL_DB * af2) *
                         (ab * sqrt(2.0f * bf2 + bb2) + ab3 * sqrt(2.0f * bf2 + 3.0f * bb2)) / den
                   : (1.0f + SL_DUAL_DB * af2) * sqrt(2.0f * bf2 + bb2);
    out[SL_DUAL_AF] = af;
    out[SL_DUAL_AB] = ab;
    out[SL_DUAL_ALPHA_F] = alpha_f;
    out[SL_DUAL_ALPHA_B] = alpha_b;
    out[SL_DUAL_BETA_F] = beta_f;
    out[SL_DUAL_BETA_B] = beta_b;
    out[SL_DUAL_A_B] = A1 + A3;
    out[SL_DUAL_DELTA_B] = delta;
    out[SL_DUAL_SIGMA_B] = sigma;
}

/* The roughness kernels of a material's three modes (marschner: the TRT caustic only, rho[2];
 * deon, chiang: every mode, kernels/dual_ec.h). */
typedef struct sl_dual_kern {
    float rho[3 * SL_DUAL_MAXJ];
    int nj[3];
} sl_dual_kern;

SL_INLINE void sl_dual_kern_init(const sl_fiber_params *fp, sl_dual_kern *k) {
    if (fp->model == 0) {
        k->nj[0] = k->nj[1] = 0;
        k->nj[2] = sl_dual_vm_coefs(fp->caustic_width, k->rho + 2 * SL_DUAL_MAXJ);
        return;
    }
    for (int t = 0; t < 3; t++)
        k->nj[t] = sl_ec_kernel_coefs(fp, t, k->rho + t * SL_DUAL_MAXJ, SL_DUAL_MAXJ);
}

/* The nine terms of any model at one theta_d (k: sl_dual_kern_init). */
SL_INLINE void sl_dual_terms_k(const sl_fiber_params *fp, float theta_d, const sl_dual_kern *k,
                               float out[9]) {
    float af[3], ab[3], beta[3];
    if (fp->model == 0)
        sl_dual_attenuations(fp, theta_d, k->rho + 2 * SL_DUAL_MAXJ, k->nj[2], af, ab);
    else
        sl_ec_attenuations(fp, theta_d, k->rho, k->nj, af, ab);
    for (int t = 0; t < 3; t++)
        beta[t] = sl_dual_ms_beta(fp, t);
    sl_dual_combine(af, ab, fp->alpha, beta, out);
}

/* The nine terms at one theta_d, directly (no table). */
SL_INLINE void sl_dual_terms(const sl_fiber_params *fp, float theta_d, const float *rho, int nj,
                             float out[9]) {
    float af[3], ab[3];
    sl_dual_attenuations(fp, theta_d, rho, nj, af, ab);
    sl_dual_combine(af, ab, fp->alpha, fp->beta, out);
}

/* Theta_d of table node i: theta_i = pi/2 sin(pi/2 i/(N-1)), denser toward grazing incidence
 * where the Fresnel terms change fastest (uniform nodes: 9e-3 relative interpolation error of
 * A_b in the last interval; these: docs/dual.md). */
SL_INLINE float sl_dual_node(int i) {
    return SL_DUAL_HALF_PI * sin(SL_DUAL_HALF_PI * (float)i / (float)(SL_DUAL_N - 1));
}

/* Interval index i (node i <= |theta| <= node i+1) and the fraction *t inside it. */
SL_INLINE int sl_dual_locate(float theta, float *t) {
    float a = sl_minf(fabs(theta) / SL_DUAL_HALF_PI, 1.0f);
    float x = asin(a) * ((float)(SL_DUAL_N - 1) / SL_DUAL_HALF_PI);
    int i = (int)x;
    if (i > SL_DUAL_N - 2) i = SL_DUAL_N - 2;
    float t0 = sl_dual_node(i), t1 = sl_dual_node(i + 1);
    *t = sl_clampf((sl_minf(fabs(theta), SL_DUAL_HALF_PI) - t0) / (t1 - t0), 0.0f, 1.0f);
    return i;
}

/* Fills the two SAT rows of one channel's table from its Delta_b and sigma_b rows: the exact
 * integral from 0 of the piecewise-linear interpolant (trapezoid sums, Xu Eq. 31). */
SL_INLINE void sl_dual_build_sats(float *tab) {
    for (int r = 0; r < 2; r++) {
        const float *f = tab + (SL_DUAL_DELTA_B + r) * SL_DUAL_N;
        float *s = tab + (SL_DUAL_SAT_DELTA_B + r) * SL_DUAL_N;
        float acc = 0.0f;
        s[0] = 0.0f;
        for (int i = 1; i < SL_DUAL_N; i++) {
            acc += 0.5f * (sl_dual_node(i) - sl_dual_node(i - 1)) * (f[i - 1] + f[i]);
            s[i] = acc;
        }
    }
}

/* Linear interpolation of row `row` at theta_d (even in theta_d, clamped to [-pi/2, pi/2]). */
SL_INLINE float sl_dual_lookup(SL_GLOBAL const float *tab, int row, float theta_d) {
    float t;
    int i = sl_dual_locate(theta_d, &t);
    SL_GLOBAL const float *f = tab + row * SL_DUAL_N;
    return f[i] + t * (f[i + 1] - f[i]);
}

/* int_0^theta of a table row (row SL_DUAL_DELTA_B or SL_DUAL_SIGMA_B) by its SAT: exact for the
 * piecewise-linear interpolant; odd in theta since the row is even. */
SL_INLINE float sl_dual_integral(SL_GLOBAL const float *tab, int row, float theta) {
    float t;
    int i = sl_dual_locate(theta, &t);
    float h = sl_dual_node(i + 1) - sl_dual_node(i);
    SL_GLOBAL const float *f = tab + row * SL_DUAL_N;
    SL_GLOBAL const float *s = tab + (row + 2) * SL_DUAL_N; /* its SAT row */
    float v = s[i] + h * t * (f[i] + 0.5f * t * (f[i + 1] - f[i]));
    return theta < 0.0f ? -v : v;
}

/* Mean of Delta_b or sigma_b over theta_d in [a, b] (Xu Eq. 31, the 1-D SAT lookup). */
SL_INLINE float sl_dual_mean(SL_GLOBAL const float *tab, int row, float a, float b) {
    if (fabs(b - a) < 1e-4f) return sl_dual_lookup(tab, row, 0.5f * (a + b));
    return (sl_dual_integral(tab, row, b) - sl_dual_integral(tab, row, a)) / (b - a);
}

#endif
