/* fiber_chiang.h: Chiang, Bitterli, Tappan, Burley 2016 (pbrt-v4's HairBxDF, Blender's Principled
 * Hair) averaged over the fiber's width, in float, shared by the C twin and the OpenCL kernels
 * (numerics.md sec. 3 "chiang"). The double reference is cpu/reference/chiang_ref.c; formulas,
 * quadrature choices and measured errors: docs/numerics-chiang.md.
 *
 *   f = sum_{p=0..2} M_p(v_p, theta_i, theta_o - 2 alpha_p) Nbar_p(phi) + M(v_2, ti, to) E_3 / 2pi
 *   Nbar_p(phi) = 1/2 integral_{-1}^{1} A_p(h) L_s(phi - Phi(p, h)) dh,  E_3 = 1/2 int A_3 dh
 *
 * M_p is d'Eon's Eq. 7 in log space (sl_deon_log_mp). A_p and Phi depend on theta_o and h only:
 * Fresnel at cos theta_o cos gamma_o with the true eta, sin gamma_t = h / eta' with eta' from
 * theta_o, T = exp(-sigma_a 2 cos gamma_t / cos theta_t), A_0 = f, A_1 = (1-f)^2 T,
 * A_2 = A_1 T f, A_3 = A_2 T f / (1 - T f) (pbrt). L_s is the logistic of scale s trimmed to
 * (-pi, pi) and wrapped. The width integral runs over gamma = asin(h) with composite 8-point
 * Gauss-Legendre panels (as fiber_deon.h's N_p), folded to [0, pi/2] by the symmetry
 * Phi(p, -g) = 2 p pi - Phi(p, g); the panel count grows as 1/s so that each logistic peak, at
 * least s/2 wide in gamma (|dPhi/dgamma| <= 2), spans a panel or more. */
#ifndef SL_FIBER_CHIANG_H
#define SL_FIBER_CHIANG_H

#include "fiber_common.h"
#include "fiber_deon.h"
#include "fiber_params.h"

/* Panels over gamma in [0, pi/2]: ceil(SL_CHIANG_PANEL_C / s), at least SL_CHIANG_PANELS_MIN,
 * at most SL_CHIANG_PANELS_MAX (docs/numerics-chiang.md has the errors that chose these). */
#define SL_CHIANG_PANELS_MIN 8
#define SL_CHIANG_PANEL_C 0.6f
#define SL_CHIANG_PANELS_MAX 512

/* The per-query constants (they depend on theta_o only). */
typedef struct sl_chiang_geom {
    float eta, cos_o;
    float inv_etap;  /* 1/eta' = cos theta_o / sqrt(eta^2 - sin^2 theta_o): 0 at grazing, no inf */
    float tscale;    /* 2 sigma_a / cos theta_t */
    float s, inv_sz; /* logistic scale, 1 / (s tanh(pi / 2s)) (trimmed normalisation) */
} sl_chiang_geom;

/* At theta_o + to_lo (to_lo: what rounding a double angle to float took off; 0 for a float
 * input): near a pole 1 - f ~ cos theta_o, so A_1, A_2 ~ cos^2 theta_o, and only to_lo says what
 * cos theta_o is there (docs/numerics.md "Poles and tails"). */
SL_INLINE void sl_chiang_geom_init_lo(const sl_fiber_params *fp, float theta_o, float to_lo,
                                      sl_chiang_geom *g) {
    float eta = fp->eta, so = sin(theta_o), co = cos(theta_o);
    co -= so * to_lo;
    so += cos(theta_o) * to_lo;
    g->eta = eta;
    g->cos_o = co;
    g->inv_etap = co / sqrt(eta * eta - so * so);
    float st = so / eta;
    g->tscale = 2.0f * fp->sigma_a / sqrt(1.0f - st * st);
    float s = sl_maxf(fp->logistic_s, 1e-6f);
    g->s = s;
    /* 1 - 2 cdf(-pi) = tanh(pi / 2s): no cancellation for small s */
    g->inv_sz = 1.0f / (s * tanh(0.5f * SL_PI_F / s));
}

SL_INLINE void sl_chiang_geom_init(const sl_fiber_params *fp, float theta_o, sl_chiang_geom *g) {
    sl_chiang_geom_init_lo(fp, theta_o, 0.0f, g);
}

/* The trimmed logistic at x in [-2pi, 2pi] (wrapped here to [-pi, pi]): e^{-|x|/s} / (s (1 +
 * e^{-|x|/s})^2) / tanh(pi / 2s). */
SL_INLINE float sl_chiang_logistic(const sl_chiang_geom *g, float x) {
    float ax = fabs(x);
    if (ax > SL_PI_F) ax = SL_TWO_PI_F - ax;
    float e = exp(-ax / g->s);
    float d = 1.0f + e;
    return e * g->inv_sz / (d * d);
}

/* Exact unpolarised Fresnel reflectance f (as sl_fresnel_exact) and its complement 1 - f
 * without cancellation: 1 - rs^2 = 4 ci eta ct / (ci + eta ct)^2 and 1 - rp^2 = 4 eta ci ct /
 * (eta ci + ct)^2. At grazing (theta_o within 1e-6 of a pole, cos i ~ 1e-6) f is 1 - 4e-6 and
 * 1 - f in float would keep two digits; A_1 = (1 - f)^2 T needs all of them. */
SL_INLINE void sl_chiang_fresnel(float eta, float cos_i, float *f, float *t) {
    float ci = sl_minf(fabs(cos_i), 1.0f);
    float sin2_t = (1.0f - ci * ci) / (eta * eta); /* eta > 1: never total reflection */
    float ct = sqrt(1.0f - sin2_t);
    float ds = ci + eta * ct, dp = eta * ci + ct;
    float rs = (ci - eta * ct) / ds, rp = (eta * ci - ct) / dp;
    *f = 0.5f * (rs * rs + rp * rp);
    *t = 2.0f * eta * ci * ct * (1.0f / (ds * ds) + 1.0f / (dp * dp));
}

/* Default panel count for the width integral: ~SL_CHIANG_PANEL_C / s. */
SL_INLINE int sl_chiang_default_panels(const sl_fiber_params *fp) {
    float n = SL_CHIANG_PANEL_C / sl_maxf(fp->logistic_s, 1e-6f);
    if (n < (float)SL_CHIANG_PANELS_MIN) return SL_CHIANG_PANELS_MIN;
    if (n > (float)SL_CHIANG_PANELS_MAX) return SL_CHIANG_PANELS_MAX;
    return (int)ceil(n);
}

/* A_0, A_1, A_2 and A_3 (the sum over p >= 3) at h = sin g (sg, cg = sin, cos of g), and
 * gamma_t into *gt: A_0 = f, A_1 = (1-f)^2 T, A_2 = A_1 T f, A_3 = A_2 T f / (1 - T f) (pbrt). */
SL_INLINE void sl_chiang_node_A(const sl_chiang_geom *g, float sg, float cg, float A[4],
                                float *gt) {
    float f, t; /* t = 1 - f */
    sl_chiang_fresnel(g->eta, g->cos_o * cg, &f, &t);
    float sgt = sg * g->inv_etap;
    *gt = asin(sl_clamp_unit(sgt));
    float x = g->tscale * sqrt(sl_maxf(1.0f - sgt * sgt, 0.0f));
    float T = exp(-x);
    A[0] = f;
    A[1] = t * t * T;
    A[2] = A[1] * T * f;
    /* 1 - T f = (1 - T) + T (1 - f): no cancellation when T and f are both near 1 */
    float den = -expm1(-x) + T * t;
    A[3] = den > 0.0f ? A[2] * T * f / den : 0.0f;
}

/* Nbar_p(phi) for p = 0, 1, 2 into np[] and E_3 into *e_rest, with `panels` 8-point
 * Gauss-Legendre panels over gamma in [0, pi/2]:
 *   Nbar_p(phi) = integral_0^{pi/2} A_p(sin g) cos g [L(phi - Phi_p) + L(-phi - Phi_p)] / 2 dg
 * (A_p is even in h, and L(phi - Phi(p, -g)) = L(-phi - Phi(p, g)) since L is even and
 * 2pi-periodic). phi in (-pi, pi]. */
SL_INLINE void sl_chiang_azimuthal(const sl_chiang_geom *g, float phi, int panels, float *np,
                                   float *e_rest) {
    float n0 = 0.0f, n1 = 0.0f, n2 = 0.0f, er = 0.0f;
    float hw = (0.5f * SL_PI_F / (float)panels) * 0.5f; /* half panel width */
    for (int k = 0; k < panels; k++) {
        for (int j = 0; j < 8; j++) {
            float gam, w;
            sl_gl8_node(0.0f, hw, k, j, &gam, &w);
            float cg = cos(gam), A[4], gt;
            sl_chiang_node_A(g, sin(gam), cg, A, &gt);
            float a0 = A[0], a1 = A[1], a2 = A[2], a3 = A[3];
            float wc = 0.5f * w * cg; /* 1/2 of [L(+) + L(-)] and dh = cos g dg */
            /* Phi_0 = -2g, Phi_{p+1} = Phi_p + 2 gt + pi, each kept in (-pi, pi] (float phase) */
            float ph = -2.0f * gam;
            n0 += wc * a0 * (sl_chiang_logistic(g, phi - ph) + sl_chiang_logistic(g, -phi - ph));
            float step = 2.0f * gt + SL_PI_F;
            ph += step;
            if (ph > SL_PI_F) ph -= SL_TWO_PI_F;
            n1 += wc * a1 * (sl_chiang_logistic(g, phi - ph) + sl_chiang_logistic(g, -phi - ph));
            ph += step;
            if (ph > SL_PI_F) ph -= SL_TWO_PI_F;
            n2 += wc * a2 * (sl_chiang_logistic(g, phi - ph) + sl_chiang_logistic(g, -phi - ph));
            er += w * cg * a3;
        }
    }
    np[0] = n0;
    np[1] = n1;
    np[2] = n2;
    *e_rest = er;
}

/* log M of lobe p = 0, 1, 2 (shifted, v_p = beta_p^2) or 3 (the rest: v_2, unshifted). */
SL_INLINE float sl_chiang_log_mp(const sl_fiber_params *fp, int p, float theta_i, float theta_o) {
    float b = fp->beta[p < 2 ? p : 2];
    float to = p < 3 ? theta_o - 2.0f * fp->alpha[p] : theta_o;
    return sl_deon_log_mp(b * b, theta_i, to);
}

/* The scattering function with an explicit panel count: out = f_0, f_1, f_2, f_rest, f. */
SL_INLINE void sl_chiang_scatter_panels_lo(const sl_fiber_params *fp, float theta_i, float phi_i,
                                           float theta_o, float to_lo, float phi_o, int panels,
                                           float *out) {
    sl_chiang_geom g;
    sl_chiang_geom_init_lo(fp, theta_o, to_lo, &g);
    float np[3], e_rest;
    sl_chiang_azimuthal(&g, sl_wrap_pi(phi_o - phi_i), panels, np, &e_rest);
    float total = 0.0f;
    for (int p = 0; p < 3; p++) {
        float v = exp(sl_chiang_log_mp(fp, p, theta_i, theta_o)) * np[p];
        out[p] = v;
        total += v;
    }
    float fr = exp(sl_chiang_log_mp(fp, 3, theta_i, theta_o)) * e_rest * (1.0f / SL_TWO_PI_F);
    out[3] = fr;
    out[4] = total + fr;
}

SL_INLINE void sl_chiang_scatter_panels(const sl_fiber_params *fp, float theta_i, float phi_i,
                                        float theta_o, float phi_o, int panels, float *out) {
    sl_chiang_scatter_panels_lo(fp, theta_i, phi_i, theta_o, 0.0f, phi_o, panels, out);
}

/* The same at theta_o + to_lo (see sl_chiang_geom_init_lo; M_p does not need theta's lo parts:
 * it is smooth at the poles). */
SL_INLINE void sl_chiang_scatter_lo(const sl_fiber_params *fp, float theta_i, float phi_i,
                                    float theta_o, float to_lo, float phi_o, float *out) {
    sl_chiang_scatter_panels_lo(fp, theta_i, phi_i, theta_o, to_lo, phi_o,
                                sl_chiang_default_panels(fp), out);
}

/* numerics.md sec. 3 "chiang": 5 values f_0, f_1, f_2, f_rest, f. */
SL_INLINE void sl_chiang_scatter(const sl_fiber_params *fp, float theta_i, float phi_i,
                                 float theta_o, float phi_o, float *out) {
    sl_chiang_scatter_panels(fp, theta_i, phi_i, theta_o, phi_o, sl_chiang_default_panels(fp), out);
}

#endif
