/* ms_response.h: the multiple-scattering response of one fragment to one SRBF lobe (dual
 * scattering under SRBF lights: Xu 2011 Eq. 3-5 and 27-31, Ren 2010 Eq. 6-7), in float, shared by
 * C (host/passes/volume/volume_ms.c) and OpenCL (compiles as OpenCL C 1.2). Definitions:
 * docs/volume.md.
 *
 * Lobe j seen from a fragment: centre (theta_j, phi_j) and width lambda_j in the fiber frame;
 * T_f, sigma_f from the march (kernels/march.h). The forward-scattered light arrives spread as
 *   psi_f(w_i) = s_f(phi_i) g(theta_i; theta_j, s_F) / cos theta_j,   s_F^2 = lambda^2 + sigma_f^2
 * (Xu Eq. 5; s_f = 1/pi on the forward half circle |phi_i - phi_j| < pi/2, g the normalised
 * Gaussian exp(-(x - m)^2 / s^2) / (sqrt(pi) s), the material's width convention). Then
 *   M^G = int psi_f f d w_i                                                  (Xu Eq. 27)
 *       = 1/cos theta_j sum_t int g M_t(theta_h) cos^2 theta_i / cos^2 theta_d N^G_t d theta_i
 *   N^G_t(D, theta_d) = 1/pi int_{D - pi/2}^{D + pi/2} N_t(x) dx,  D = phi_o - phi_j  (Xu Eq. 28)
 *                     = 1/(2 pi) int A_t(h) W(Phi_t(h) - D) dh, W the window's indicator
 *                       (TRT: the window convolved with the caustic Gaussian, by its Fourier
 *                       series with the von Mises ratios of kernels/dual_material.h)
 *   M^L = 2/cos theta_j (pi - |D|)/pi^2 int g(theta_i; theta_j, s_F)
 *         g(theta_i; ~Delta_b - theta_o, ~sigma_b) A_b(theta_d) cos^2 theta_i / cos^2 theta_d
 *         d theta_i                                                          (Xu Eq. 29-31)
 * with ~Delta_b, ~sigma_b the means of Delta_b, sigma_b over theta_i in theta_j +- s_F (Xu Eq. 31,
 * the tables' SATs). Each theta_i integral multiplies the two Gaussians analytically and
 * integrates the smooth rest with 6-point Gauss-Hermite (Xu Sec. 4.2.2's idea; nodes outside
 * [-pi/2, pi/2] count 0). N^G is tabulated per material (sl_msr_NG_row: 65 theta_d x 65 D per
 * mode and channel) and read bilinearly; eccentric TRT uses the roll-mean eta*
 * ((eta*_1 + eta*_2) / 2). The renderer reads the whole response from a per-material table built
 * from the pieces below (kernels/ms_table.h); sl_ms_response_1 is its reference. */
#ifndef SL_MS_RESPONSE_H
#define SL_MS_RESPONSE_H

#include "dual_material.h"

#define SL_MSR_H_NODES 96 /* midpoint nodes in u for N^G (R and TT windows are discontinuous) */

/* 6-point Gauss-Hermite (weight exp(-x^2)), positive half; weights divided by sqrt(pi). */
#if SL_OPENCL
#define SL_MSR_TABLE static __constant
#else
#define SL_MSR_TABLE static const
#endif
SL_MSR_TABLE float sl_msr_ghx[3] = {0.436077411927616509f, 1.335849074013696949f,
                                    2.350604973674492222f};
SL_MSR_TABLE float sl_msr_ghw[3] = {0.408828469556029226f, 0.088615746041914527f,
                                    0.002555784402056249f};

/* The measure factor of the theta_i integrals. marschner: f d w_i = M N cos^2 theta_i /
 * cos^2 theta_d d theta_i d phi_i with M in the Marschner form (mass 2 in theta_i). deon and
 * chiang: f d w_i = (M_p cos theta_i) N_p d theta_i d phi_i, and M_p cos theta_i has mass 1 in
 * theta_i (d'Eon's normalisation), taken as the Gaussian of its spread: half the Marschner form
 * of width sl_dual_ms_beta. The local term's lobe g(theta_i; ~Delta_b - theta_o, ~sigma_b) has
 * mass 1 already, so there the energy-conserving factor is 1 (docs/dual.md). */
SL_INLINE float sl_msr_w_global(const sl_fiber_params *fp, float cti, float ctd) {
    return fp->model == 0 ? cti * cti / (ctd * ctd) : 0.5f;
}
SL_INLINE float sl_msr_w_local(const sl_fiber_params *fp, float cti, float ctd) {
    return fp->model == 0 ? cti * cti / (ctd * ctd) : 1.0f;
}

/* Product of exp(-(x - m1)^2 / s1^2) and exp(-(x - m2)^2 / s2^2) = k exp(-(x - m)^2 / s^2). */
SL_INLINE float sl_msr_gprod(float m1, float s1, float m2, float s2, float *m, float *s) {
    float a = s1 * s1, b = s2 * s2, d = m1 - m2;
    *m = (m1 * b + m2 * a) / (a + b);
    *s = sqrt(a * b / (a + b));
    return exp(-d * d / (a + b));
}

/* N^G tables (per channel): [mode t][theta_d node i][D node k], theta_d nodes as the dual tables'
 * (pi/2 sin(pi/2 i/(NT-1)): denser toward grazing), D uniform on [0, pi] (N^G is even in theta_d
 * and in D since N_t is even in phi). */
#define SL_MSR_NT 65
#define SL_MSR_ND 65
#define SL_MSR_TABLE_FLOATS (3 * SL_MSR_NT * SL_MSR_ND)

SL_INLINE float sl_msr_node_td(int i) {
    return SL_DUAL_HALF_PI * sin(SL_DUAL_HALF_PI * (float)i / (float)(SL_MSR_NT - 1));
}

/* Row (theta_d node i, mode t with index eta) of the N^G table: out[k] = N^G_t(D_k, theta_d)
 * = 1/(2 pi) int A_t(h) W(Phi_t(h) - D_k) dh by SL_MSR_H_NODES midpoint nodes in u = asin h over
 * the support; TRT's window is smooth (Fourier series, cos/sin moments of the samples). */
SL_INLINE void sl_msr_NG_row(const sl_fiber_params *fp, int t, float eta, int i, const float *rho,
                             int nj, float *out) {
    float theta_d = sl_msr_node_td(i);
    for (int k = 0; k < SL_MSR_ND; k++)
        out[k] = 0.0f;
    sl_mq_mode c;
    if (!sl_mq_mode_setup(&c, fp, t, eta, sl_maxf(cos(theta_d), 0.0f), fabs(sin(theta_d)))) return;
    float umax = c.inv_etap > 1.0f ? asin(1.0f / c.inv_etap) : SL_DUAL_HALF_PI;
    float du = 2.0f * umax / (float)SL_MSR_H_NODES, dD = SL_PI_F / (float)(SL_MSR_ND - 1);
    float wa[SL_MSR_H_NODES], ph[SL_MSR_H_NODES];
    for (int q = 0; q < SL_MSR_H_NODES; q++) {
        float u = -umax + ((float)q + 0.5f) * du;
        wa[q] = sl_mq_A(&c, sin(u), cos(u)) * cos(u) * du / (2.0f * SL_PI_F);
        ph[q] = sl_wrap_pi(sl_mq_psi(t, c.inv_etap, u) + (float)t * SL_PI_F);
    }
    if (t < 2) {
        for (int k = 0; k < SL_MSR_ND; k++) {
            float D = (float)k * dD, acc = 0.0f;
            for (int q = 0; q < SL_MSR_H_NODES; q++)
                acc += fabs(sl_wrap_pi(ph[q] - D)) <= SL_DUAL_HALF_PI ? wa[q] : 0.0f;
            out[k] = acc;
        }
        return;
    }
    /* W(y) = 1/2 + 2/pi sum_j (-1)^j rho_m cos(m y) / m, m = 2j + 1: with y = Phi - D,
     * sum_q wa W = E/2 + 2/pi sum_j (-1)^j rho_m / m (C_m cos mD + S_m sin mD). */
    float E = 0.0f;
    for (int q = 0; q < SL_MSR_H_NODES; q++)
        E += wa[q];
    for (int k = 0; k < SL_MSR_ND; k++)
        out[k] = 0.5f * E;
    for (int j = 0; j < nj; j++) {
        float m = (float)(2 * j + 1), C = 0.0f, S = 0.0f;
        for (int q = 0; q < SL_MSR_H_NODES; q++) {
            C += wa[q] * cos(m * ph[q]);
            S += wa[q] * sin(m * ph[q]);
        }
        float f = ((j & 1) ? -1.0f : 1.0f) * rho[j] / m * (2.0f / SL_PI_F);
        for (int k = 0; k < SL_MSR_ND; k++) {
            float D = (float)k * dD;
            out[k] += f * (C * cos(m * D) + S * sin(m * D));
        }
    }
}

/* Row i of the theta_d axis of the N^G table and the fraction *fi toward row i + 1. */
SL_INLINE int sl_msr_td_locate(float theta_d, float *fi) {
    float a = sl_minf(fabs(theta_d) / SL_DUAL_HALF_PI, 1.0f);
    float x = asin(a) * ((float)(SL_MSR_NT - 1) / SL_DUAL_HALF_PI);
    int i = (int)x;
    if (i > SL_MSR_NT - 2) i = SL_MSR_NT - 2;
    float t0 = sl_msr_node_td(i), t1 = sl_msr_node_td(i + 1);
    *fi = sl_clampf((sl_minf(fabs(theta_d), SL_DUAL_HALF_PI) - t0) / (t1 - t0), 0.0f, 1.0f);
    return i;
}

/* Bilinear N^G_t(D, theta_d) from a channel's table. */
SL_INLINE float sl_msr_NG(SL_GLOBAL const float *ng, int t, float theta_d, float D) {
    float fi;
    int i = sl_msr_td_locate(theta_d, &fi);
    float y = sl_minf(fabs(sl_wrap_pi(D)), SL_PI_F) * ((float)(SL_MSR_ND - 1) / SL_PI_F);
    int k = (int)y;
    if (k > SL_MSR_ND - 2) k = SL_MSR_ND - 2;
    float fk = y - (float)k;
    SL_GLOBAL const float *r0 = ng + (t * SL_MSR_NT + i) * SL_MSR_ND, *r1 = r0 + SL_MSR_ND;
    float v0 = r0[k] + fk * (r0[k + 1] - r0[k]), v1 = r1[k] + fk * (r1[k + 1] - r1[k]);
    return v0 + fi * (v1 - v0);
}

/* The global term's theta_i integral for mode t (Xu Eq. 27): g(theta_i; theta_j, s_F)
 * M_t((theta_i + theta_o)/2) is a Gaussian in theta_i centred at 2 alpha_t - theta_o of width
 * 2 beta_t times g's; their product is pref times a normalised Gaussian whose 6 Gauss-Hermite
 * nodes give td[q] (theta_d) and wq[q] (weight times cos^2 theta_i / cos^2 theta_d; 0 for nodes
 * outside (-pi/2, pi/2)). Returns pref; the mode's part of cos theta_j M^G is
 * pref sum_q wq[q] N^G_t(td[q], D). */
SL_INLINE float sl_msr_global_nodes(const sl_fiber_params *fp, int t, float theta_o, float theta_j,
                                    float sF, float *td, float *wq) {
    float m, s;
    float bt = sl_dual_ms_beta(fp, t);
    float k = sl_msr_gprod(theta_j, sF, 2.0f * fp->alpha[t] - theta_o, 2.0f * bt, &m, &s);
    float pref = k / (SL_SQRT_PI_F * sF) / (SL_SQRT_PI_F * bt) * SL_SQRT_PI_F * s;
    for (int q = 0; q < 6; q++) {
        float ti = m + s * ((q & 1) ? -sl_msr_ghx[q >> 1] : sl_msr_ghx[q >> 1]);
        td[q] = 0.5f * (theta_o - ti);
        wq[q] = 0.0f;
        if (!(fabs(ti) < SL_DUAL_HALF_PI)) continue;
        float ctd = cos(td[q]), cti = cos(ti);
        wq[q] = sl_msr_ghw[q >> 1] * sl_msr_w_global(fp, cti, ctd);
    }
    return pref;
}

/* The local term's means ~Delta_b, ~sigma_b over theta_d in (theta_j - theta_o +- s_F) / 2
 * (Xu Eq. 31, the tables' SATs). */
SL_INLINE void sl_msr_local_means(SL_GLOBAL const float *tab, float theta_o, float theta_j,
                                  float sF, float *dB, float *sB) {
    float a = 0.5f * (theta_j - sF - theta_o), b = 0.5f * (theta_j + sF - theta_o);
    *dB = sl_dual_mean(tab, SL_DUAL_DELTA_B, a, b);
    *sB = sl_maxf(sl_dual_mean(tab, SL_DUAL_SIGMA_B, a, b), 1e-4f);
}

/* The local term without its separable factors (Xu Eq. 29-31): cos theta_j pi^2 / (2 (pi - |D|))
 * M^L = pref sum_q w_q A_b(theta_d) cos^2 theta_i / cos^2 theta_d, the product of the lobe's
 * g(theta_i; theta_j, s_F) and g(theta_i; ~Delta_b - theta_o, ~sigma_b) (pref times a normalised
 * Gaussian) by Gauss-Hermite. Returns the sum; *pref the product's factor. */
SL_INLINE float sl_msr_local_core(const sl_fiber_params *fp, SL_GLOBAL const float *tab,
                                  float theta_o, float theta_j, float sF, float *pref_out) {
    float dB, sB, m, s;
    sl_msr_local_means(tab, theta_o, theta_j, sF, &dB, &sB);
    float k = sl_msr_gprod(theta_j, sF, dB - theta_o, sB, &m, &s);
    float pref = k / (SL_SQRT_PI_F * sF) / (SL_SQRT_PI_F * sB) * SL_SQRT_PI_F * s;
    float acc = 0.0f;
    for (int q = 0; q < 6; q++) {
        float ti = m + s * ((q & 1) ? -sl_msr_ghx[q >> 1] : sl_msr_ghx[q >> 1]);
        if (!(fabs(ti) < SL_DUAL_HALF_PI)) continue;
        float td = 0.5f * (theta_o - ti), ctd = cos(td), cti = cos(ti);
        acc += sl_msr_ghw[q >> 1] * sl_msr_w_local(fp, cti, ctd) *
               sl_dual_lookup(tab, SL_DUAL_A_B, td);
    }
    *pref_out = pref;
    return acc;
}

/* M^G and M^L of one channel (the top of the file). theta_o, phi_o: the view; theta_j, phi_j,
 * lambda: the lobe; sigma_f: the march's spread; tab: the channel's dual table, ng: its N^G table
 * (SL_MSR_TABLE_FLOATS, sl_msr_NG_row; both __global in OpenCL). */
SL_INLINE void sl_ms_response_1(const sl_fiber_params *fp, SL_GLOBAL const float *tab,
                                SL_GLOBAL const float *ng, float theta_o, float phi_o,
                                float theta_j, float phi_j, float lambda, float sigma_f, float *MG,
                                float *ML) {
    float sF = sqrt(lambda * lambda + sigma_f * sigma_f);
    float ctj = cos(theta_j), D = sl_wrap_pi(phi_o - phi_j);
    *MG = 0.0f;
    *ML = 0.0f;
    if (!(ctj > 1e-4f) || !(sF > 0.0f)) return;
    float mg = 0.0f, td[6], wq[6];
    for (int t = 0; t < 3; t++) { /* Xu Eq. 27 */
        float pref = sl_msr_global_nodes(fp, t, theta_o, theta_j, sF, td, wq);
        if (!(pref > 0.0f)) continue;
        float acc = 0.0f;
        for (int q = 0; q < 6; q++)
            if (wq[q] > 0.0f) acc += wq[q] * sl_msr_NG(ng, t, td[q], D);
        mg += pref * acc;
    }
    *MG = mg / ctj;
    float pl, acc = sl_msr_local_core(fp, tab, theta_o, theta_j, sF, &pl); /* Xu Eq. 29-31 */
    *ML = pl > 0.0f ? 2.0f / ctj * (SL_PI_F - fabs(D)) / (SL_PI_F * SL_PI_F) * pl * acc : 0.0f;
}

#endif
