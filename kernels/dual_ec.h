/* dual_ec.h: the azimuthal pieces of dual scattering and of the multiple-scattering response for
 * the energy-conserving models (deon: d'Eon 2011, chiang: Chiang 2016), in float, shared by C and
 * OpenCL (included by kernels/dual_material.h). The Marschner model's are in dual_material.h and
 * ms_response.h; docs/dual.md "Energy-conserving models" has the definitions and every choice.
 *
 * Both models write N_p(phi) = integral_0^{pi/2} A_p(sin g) cos g [K_p(phi - Phi_p) +
 * K_p(-phi - Phi_p)] / 2 dg with Phi_p = -2 g + p (2 g_t + pi) and K_p a 2 pi-periodic roughness
 * kernel (deon: the Gaussian detector of standard deviation beta_p; chiang: the trimmed logistic
 * of scale s). For an even weight W, integral W N_p dphi = integral A_p cos g (W * K_p)(Phi_p) dg,
 * and (W * K_p) is W's Fourier series with every odd term k multiplied by rho_k, the kernel's
 * cosine coefficient. So the weights of a_f / a_b (the triangle |phi| / pi) and of N^G (the
 * half-circle window) are smoothed exactly, in h, by the same series the Marschner TRT caustic
 * uses. A kernel too narrow for SL_DUAL_MAXJ terms (standard deviation or scale below ~0.02 rad)
 * is taken as sharp: W itself (an error of the order of the kernel's width over pi).
 *
 * Modes: R (p = 0), TT (p = 1) and TRT (p = 2, with every higher order folded in: deon's p >= 3
 * share TRT's shift and width, chiang's p >= 3 term is uniform in phi and unshifted; the fold
 * gives it TRT's shift, docs/dual.md). A_p depends on theta_d (deon, with theta_i = -theta_d,
 * theta_o = theta_d: the specular cone) or on theta_o (chiang, theta_o = theta_d). */
#ifndef SL_DUAL_EC_H
#define SL_DUAL_EC_H

#include "fiber_chiang.h"
#include "fiber_deon.h"

/* gamma panels (8-point Gauss-Legendre each) for smoothed weights and for sharp ones (the
 * window's indicator is discontinuous in gamma: more nodes). */
#define SL_EC_PANELS 12
#define SL_EC_PANELS_SHARP 32
/* Fourier terms of a kernel are dropped below this; a kernel whose last term is above it is
 * taken as sharp. */
#define SL_EC_RHO_EPS 1e-6f

/* Cosine coefficients rho[j] = integral_{-pi}^{pi} K(x) cos(k x) dx, k = 2j + 1, of mode t's
 * kernel into rho; returns the number of terms, or 0 when the kernel is sharp. maxj is the
 * caller's array size (<= SL_DUAL_MAXJ). */
SL_INLINE int sl_ec_kernel_coefs(const sl_fiber_params *fp, int t, float *rho, int maxj) {
    if (fp->model == 1) { /* wrapped Gaussian of standard deviation b: exp(-k^2 b^2 / 2) */
        float b = fp->beta[t < 2 ? t : 2];
        float kl = (float)(2 * maxj - 1);
        if (exp(-0.5f * kl * kl * b * b) > SL_EC_RHO_EPS) return 0;
        int nj = 0;
        for (int j = 0; j < maxj; j++) {
            float k = (float)(2 * j + 1);
            rho[j] = exp(-0.5f * k * k * b * b);
            nj = j + 1;
            if (rho[j] < SL_EC_RHO_EPS) break;
        }
        return nj;
    }
    /* chiang: the trimmed logistic, whose untrimmed coefficient is pi s k / sinh(pi s k) (the
     * test for "sharp" and for the number of terms); the coefficients themselves by Gauss-Legendre
     * over [0, pi] with panels narrower than s (exact for the trimmed, normalised kernel). */
    float s = sl_maxf(fp->logistic_s, 1e-6f);
    float kl = SL_PI_F * s * (float)(2 * maxj - 1);
    if (kl < 20.0f && kl / sinh(kl) > SL_EC_RHO_EPS) return 0;
    int nj = maxj;
    for (int j = 0; j < maxj; j++) {
        float x = SL_PI_F * s * (float)(2 * j + 1);
        if (x > 20.0f || x / sinh(x) < SL_EC_RHO_EPS) {
            nj = j + 1;
            break;
        }
    }
    for (int j = 0; j < nj; j++)
        rho[j] = 0.0f;
    sl_chiang_geom g;
    sl_chiang_geom_init(fp, 0.0f, &g);
    int panels = (int)ceil(2.0f * SL_PI_F / s);
    panels = panels < 4 ? 4 : (panels > 256 ? 256 : panels);
    float hw = 0.5f * SL_PI_F / (float)panels;
    for (int k = 0; k < panels; k++)
        for (int q = 0; q < 8; q++) {
            float x, w;
            sl_gl8_node(0.0f, hw, k, q, &x, &w);
            float lw = 2.0f * w * sl_chiang_logistic(&g, x);
            float c = cos(x), c2 = 2.0f * (2.0f * c * c - 1.0f), ck = c, ckm2 = c;
            for (int j = 0; j < nj; j++) { /* cos(kx), k odd, by the Chebyshev recurrence */
                rho[j] += lw * ck;
                float next = c2 * ck - ckm2;
                ckm2 = ck;
                ck = next;
            }
        }
    return nj;
}

/* The per-theta_d constants of A_p for either model. */
typedef struct sl_ec_geom {
    sl_int model, n; /* n: explicit orders (deon: fp->orders; chiang: 2) */
    sl_deon_geom dg;
    sl_chiang_geom cg;
} sl_ec_geom;

SL_INLINE void sl_ec_geom_init(const sl_fiber_params *fp, float theta_d, sl_ec_geom *g) {
    g->model = fp->model;
    if (fp->model == 1) {
        g->n = fp->orders < SL_DEON_MAX_ORDERS ? fp->orders : SL_DEON_MAX_ORDERS;
        sl_deon_geom_init(fp, -theta_d, theta_d, &g->dg);
    } else {
        g->n = 2;
        sl_chiang_geom_init(fp, theta_d, &g->cg);
    }
}

/* At gamma: A_p for p = 0..n into A[] (at least 4 floats), the energy of the orders above n into
 * *rest (uniform in phi), and gamma_t into *gt (Phi_p = -2 gamma + p (2 gamma_t + pi)). */
SL_INLINE void sl_ec_node(const sl_ec_geom *g, float gam, float *A, float *rest, float *gt) {
    float sg = sin(gam), cg = cos(gam);
    if (g->model == 1) {
        float f, T;
        sl_deon_fT(&g->dg, sg, cg, &f, &T);
        *gt = asin(sl_clamp_unit(sg / g->dg.etap));
        A[0] = f;
        float a = (1.0f - f) * (1.0f - f) * T;
        for (int p = 1; p <= g->n; p++) {
            A[p] = a;
            a *= f * T;
        }
        float den = 1.0f - f * T;
        *rest = den > 0.0f ? a / den : 0.0f;
        return;
    }
    sl_chiang_node_A(&g->cg, sg, cg, A, gt); /* A[3]: every order p >= 3 together */
    *rest = A[3];
}

/* (W * K)(y) for the triangle weight W(x) = |x| / pi (the forward share of a pair of
 * directions at azimuth difference x): sharp, or by its smoothed series (sl_dual_wf_conv of
 * dual_material.h is pi times it). */
SL_INLINE float sl_ec_forward_weight(const float *rho, int nj, float y) {
    if (nj == 0) return fabs(sl_wrap_pi(y)) * SL_INV_PI_F;
    return sl_clampf(sl_dual_wf_conv(rho, nj, y) * SL_INV_PI_F, 0.0f, 1.0f);
}

/* Per-mode forward and backward attenuations a_{f,t}, a_{b,t} (t = 0, 1, 2 with the higher
 * orders folded into 2) at theta_d: integral N_t W dphi with W = |phi|/pi and 1 - |phi|/pi, so
 * that a_{f,t} + a_{b,t} is the mode's energy. rho/nj: sl_ec_kernel_coefs per mode. */
SL_INLINE void sl_ec_attenuations(const sl_fiber_params *fp, float theta_d,
                                  const float *rho /* 3 x SL_DUAL_MAXJ */, const int *nj,
                                  float af[3], float ab[3]) {
    sl_ec_geom g = {0}; /* zeroed: GCC cannot see that init fills the model's half */
    sl_ec_geom_init(fp, theta_d, &g);
    float e[3] = {0.0f, 0.0f, 0.0f};
    for (int t = 0; t < 3; t++)
        af[t] = 0.0f;
    float hw = 0.25f * SL_PI_F / (float)SL_EC_PANELS;
    for (int k = 0; k < SL_EC_PANELS; k++)
        for (int q = 0; q < 8; q++) {
            float gam, w, A[SL_DEON_MAX_ORDERS + 1], rest, gt;
            sl_gl8_node(0.0f, hw, k, q, &gam, &w);
            sl_ec_node(&g, gam, A, &rest, &gt);
            float wc = w * cos(gam), ph = -2.0f * gam, step = 2.0f * gt + SL_PI_F;
            for (int p = 0; p <= g.n; p++) {
                int t = p < 2 ? p : 2;
                e[t] += wc * A[p];
                af[t] += wc * A[p] * sl_ec_forward_weight(rho + t * SL_DUAL_MAXJ, nj[t], ph);
                ph += step;
                if (ph > SL_PI_F) ph -= 2.0f * SL_PI_F;
            }
            e[2] += wc * rest; /* uniform in phi: half forward */
            af[2] += 0.5f * wc * rest;
        }
    for (int t = 0; t < 3; t++)
        ab[t] = sl_maxf(e[t] - af[t], 0.0f);
}

/* Row (theta_d = td, mode t) of the N^G table (ms_response.h): out[k] = 1/pi integral over
 * |x - D_k| < pi/2 of N_t(x) dx at D_k = k pi / (nd - 1), by the window's series (the odd
 * cosine terms smoothed by rho_k; the two images of the gamma fold average to the cosine
 * moments only) or, for a sharp kernel, the window itself. */
SL_INLINE void sl_ec_NG_row(const sl_fiber_params *fp, int t, float td, const float *rho, int nj,
                            int nd, float *out) {
    sl_ec_geom g = {0}; /* as in sl_ec_attenuations */
    sl_ec_geom_init(fp, td, &g);
    for (int k = 0; k < nd; k++)
        out[k] = 0.0f;
    int panels = nj == 0 ? SL_EC_PANELS_SHARP : SL_EC_PANELS;
    float hw = 0.25f * SL_PI_F / (float)panels, dD = SL_PI_F / (float)(nd - 1);
    float E = 0.0f, C[SL_DUAL_MAXJ];
    for (int j = 0; j < nj; j++)
        C[j] = 0.0f;
    for (int k = 0; k < panels; k++)
        for (int q = 0; q < 8; q++) {
            float gam, w, A[SL_DEON_MAX_ORDERS + 1], rest, gt;
            sl_gl8_node(0.0f, hw, k, q, &gam, &w);
            sl_ec_node(&g, gam, A, &rest, &gt);
            float wc = w * cos(gam) * SL_INV_PI_F, ph = -2.0f * gam, step = 2.0f * gt + SL_PI_F;
            for (int p = 0; p <= g.n; p++) {
                int tp = p < 2 ? p : 2;
                if (tp == t) {
                    float a = wc * A[p];
                    if (nj == 0) {
                        for (int d = 0; d < nd; d++) {
                            float D = (float)d * dD;
                            float in = (fabs(sl_wrap_pi(ph - D)) <= SL_DUAL_HALF_PI ? 0.5f : 0.0f) +
                                       (fabs(sl_wrap_pi(ph + D)) <= SL_DUAL_HALF_PI ? 0.5f : 0.0f);
                            out[d] += a * in;
                        }
                    } else {
                        E += a;
                        float c = cos(ph), c2 = 2.0f * (2.0f * c * c - 1.0f), ck = c, ckm2 = c;
                        for (int j = 0; j < nj; j++) {
                            C[j] += a * ck;
                            float next = c2 * ck - ckm2;
                            ckm2 = ck;
                            ck = next;
                        }
                    }
                }
                ph += step;
                if (ph > SL_PI_F) ph -= 2.0f * SL_PI_F;
            }
            if (t == 2) { /* the uniform rest: half of it in any half-circle window */
                if (nj == 0) {
                    for (int d = 0; d < nd; d++)
                        out[d] += 0.5f * wc * rest;
                } else {
                    E += wc * rest;
                }
            }
        }
    if (nj == 0) return;
    /* W(y) = 1/2 + 2/pi sum_j (-1)^j rho_m cos(m y) / m, m = 2j + 1; the two images give
     * cos(m (Phi - D)) + cos(m (Phi + D)) = 2 cos(m Phi) cos(m D). */
    for (int d = 0; d < nd; d++) {
        float D = (float)d * dD, v = 0.5f * E;
        for (int j = 0; j < nj; j++) {
            float m = (float)(2 * j + 1);
            v += ((j & 1) ? -1.0f : 1.0f) * rho[j] / m * (2.0f / SL_PI_F) * C[j] * cos(m * D);
        }
        out[d] = sl_maxf(v, 0.0f);
    }
}

#endif
