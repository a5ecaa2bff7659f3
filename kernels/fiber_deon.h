/* fiber_deon.h: d'Eon et al. 2011, "An Energy-Conserving Hair Reflectance Model", in float,
 * shared by the C twin and the OpenCL kernels (numerics.md sec. 3 "deon"). The double reference
 * is cpu/reference/deon_ref.c; derivations, tolerances and measurements: docs/numerics-deon.md.
 *
 *   f = sum_{p=0..orders} M_p(beta_p^2, theta_i, theta_o - 2 alpha_p) N_p(phi)
 *       + M_TRT E_rest / (2 pi)
 *
 * M_p is d'Eon Eq. 7 evaluated in log space (finite for every v > 0); N_p is Eq. 10 with the
 * Gaussian detector of Eq. 11, integrated over the fiber offset with composite 8-point
 * Gauss-Legendre panels in gamma_i = asin(h) (h = sin gamma_i makes the integrand smooth at
 * |h| = 1 and bounds dPhi/dgamma, so detector peaks have similar widths everywhere). All orders
 * share one pass over the nodes (one Fresnel, one asin and one exp per node). */
#ifndef SL_FIBER_DEON_H
#define SL_FIBER_DEON_H

#include "fiber_common.h"
#include "fiber_params.h"

/* Most explicit orders the float backends evaluate (output has orders + 3 values). */
#define SL_DEON_MAX_ORDERS 32
/* Panels of the N_p quadrature over gamma in [0, pi/2]: the default for beta_min >= 2 deg, more
 * below (panels ~ SL_DEON_PANEL_C / beta_min) up to SL_DEON_PANELS_MAX (docs/numerics-deon.md
 * has the measured errors that chose these). */
#define SL_DEON_PANELS_MIN 6
#define SL_DEON_PANEL_C 0.55f
#define SL_DEON_PANELS_MAX 64

#define SL_TWO_PI_F 6.28318530717958647692f
/* pi/2 = HI + LO exactly to ~1e-15: (HI - theta) + LO is pi/2 - theta without the 4e-8 error of
 * the float pi/2, which matters for cos(theta_d) when theta_d is within 1e-6 of +-pi/2. */
#define SL_DEON_PIO2_HI 1.57079637050628662109375f
#define SL_DEON_PIO2_LO -4.37113900018624283e-8f

/* log(e^-x I0(x)) for x >= 0: Abramowitz & Stegun 9.8.1 (x < 3.75, |eps| < 1.6e-7) and 9.8.2
 * (x >= 3.75, relative |eps| < 5e-7), i.e. float precision. For large x the caller passes
 * x = a / v as (a, v) so that -1/2 log(x) = -1/2 log(a) + 1/2 log(v) never overflows. */
SL_INLINE float sl_deon_log_i0e_av(float a, float v) {
    float x = a / v;
    if (x < SL_AS_I0_SPLIT) {
        float t = x * (1.0f / 3.75f);
        t *= t;
        float i0 = sl_as_i0_small(t);
        return log(i0) - x;
    }
    float u = 3.75f * (v / a); /* 1/t, in (0, 1] */
    float s = sl_as_i0e_large(u);
    return log(s) - 0.5f * log(a) + 0.5f * log(v);
}

/* log M_p (d'Eon Eq. 7), our convention: omega_i toward the light, specular cone at
 * theta_o = -theta_i, so the paper's sin(-theta_i) sin(theta_r) is -sin ti sin to:
 *   log M = -log v - log(1 - e^{-2/v}) - 2 sin^2((ti+to)/2)/v + log i0e(cos ti cos to / v)
 * (the O(1/v) terms of log csch(1/v), the sine term and log I0 = x + log i0e cancel exactly into
 * the sin^2 term; when cos ti cos to < 0, i.e. a shifted angle past +-pi/2, it is
 * -2 cos^2((ti-to)/2)/v). Finite for every v > 0 (clamped to -FLT_MAX only for denormal v). */
SL_INLINE float sl_deon_log_mp(float v, float theta_i, float theta_o) {
    float cc = cos(theta_i) * cos(theta_o);
    float num;
    if (cc >= 0.0f) {
        float s = sin(0.5f * (theta_i + theta_o));
        num = 2.0f * s * s;
    } else {
        float c = cos(0.5f * (theta_i - theta_o));
        num = 2.0f * c * c;
        cc = -cc;
    }
    float r = -log(v) - log(-expm1(-2.0f / v)) - num / v + sl_deon_log_i0e_av(cc, v);
    if (!(r > -SL_FLT_MAX)) r = -SL_FLT_MAX;
    if (r > SL_FLT_MAX) r = SL_FLT_MAX;
    return r;
}

/* Gaussian detector (d'Eon Eq. 11): sum_k g(beta; x - 2 pi k). beta <= 1: the image nearest to
 * x in (-pi, pi] plus its neighbour across +-pi when within 6 beta (others < e^-19 relative);
 * beta > 1: the dual (theta-function) series (1 + 2 sum e^{-n^2 beta^2/2} cos n x) / 2pi. */
SL_INLINE float sl_deon_detector(float beta, float x) {
    x = sl_wrap_pi(x);
    if (beta > 1.0f) {
        /* w_n = q^(n^2), q = e^{-beta^2/2}, by w_n = w_{n-1} q^(2n-1); cos(n x) by the Chebyshev
         * recurrence: two transcendental calls whatever the number of terms (<= 6 here). */
        float q = exp(-0.5f * beta * beta), q2 = q * q;
        float c1 = cos(x), c_prev = 1.0f, c_n = c1;
        float w = q, qf = q; /* w_1 = q, factor for the next step q^3 */
        float s = 1.0f;
        for (int n = 1; n < 16 && w > 1e-9f; n++) {
            s += 2.0f * w * c_n;
            float c_next = 2.0f * c1 * c_n - c_prev;
            c_prev = c_n;
            c_n = c_next;
            qf *= q2;
            w *= qf;
        }
        return s * (1.0f / SL_TWO_PI_F);
    }
    float ib = 1.0f / beta;
    float y = x * ib;
    float s = exp(-0.5f * y * y);
    float ax = fabs(x);
    if (ax > SL_PI_F - 6.0f * beta) {
        float z = (SL_TWO_PI_F - ax) * ib;
        s += exp(-0.5f * z * z);
    }
    return s * ib * (1.0f / 2.50662827463100050242f);
}

/* The per-query constants of A(p, h): eta, eta', cos theta_d, sigma_a' = sigma_a / cos theta_t. */
typedef struct sl_deon_geom {
    float eta, etap, cos_td, sig;
} sl_deon_geom;

/* At theta_i + ti_lo, theta_o + to_lo (the _lo parts: what rounding a double angle to float took
 * off; 0 for float inputs). 1 - f ~ cos theta_d at grazing, so A(p >= 1) ~ cos^2 theta_d, and
 * near opposite poles only the lo parts say what cos theta_d is (docs/numerics.md "Poles and
 * tails"). */
SL_INLINE void sl_deon_geom_init_lo(const sl_fiber_params *fp, float theta_i, float ti_lo,
                                    float theta_o, float to_lo, sl_deon_geom *g) {
    /* cos theta_d = sin(pi/2 - |theta_d|), pi/2 - |theta_d| = ((pi/2 - hi) + (pi/2 + lo))/2
     * with hi/lo the larger/smaller of theta_i, theta_o: no cancellation near grazing. */
    int o_hi = theta_o >= theta_i;
    float hi = o_hi ? theta_o : theta_i, lo = o_hi ? theta_i : theta_o;
    float hi_l = o_hi ? to_lo : ti_lo, lo_l = o_hi ? ti_lo : to_lo;
    float comp = 0.5f * ((((SL_DEON_PIO2_HI - hi) + SL_DEON_PIO2_LO) - hi_l) +
                         (((SL_DEON_PIO2_HI + lo) + SL_DEON_PIO2_LO) + lo_l));
    float cos_td = sin(sl_maxf(comp, 0.0f));
    float sin_td = sin(0.5f * (theta_o - theta_i));
    float eta = fp->eta;
    g->eta = eta;
    g->cos_td = cos_td;
    g->etap = sqrt(eta * eta - sin_td * sin_td) / sl_maxf(cos_td, 1e-30f);
    float st = sin_td / eta;
    g->sig = fp->sigma_a / sqrt(1.0f - st * st);
}

SL_INLINE void sl_deon_geom_init(const sl_fiber_params *fp, float theta_i, float theta_o,
                                 sl_deon_geom *g) {
    sl_deon_geom_init_lo(fp, theta_i, 0.0f, theta_o, 0.0f, g);
}

/* Fresnel factor f (exact, at cos i = cos theta_d cos gamma_i) and T at h = sin(gamma). */
SL_INLINE void sl_deon_fT(const sl_deon_geom *g, float sin_g, float cos_g, float *f, float *T) {
    *f = sl_fresnel_exact(g->eta, g->cos_td * cos_g);
    float c2t = 1.0f - (sin_g * sin_g) / (g->etap * g->etap); /* cos^2 gamma_t */
    *T = exp(-4.0f * g->sig * c2t);                           /* 1 + cos 2gt = 2 cos^2 gt */
}

SL_INLINE float sl_deon_beta(const sl_fiber_params *fp, int p) {
    return fp->beta[p < 2 ? p : 2];
}
SL_INLINE float sl_deon_alpha(const sl_fiber_params *fp, int p) {
    return fp->alpha[p < 2 ? p : 2];
}

/* Default panel count for N_p: SL_DEON_PANELS_MIN for beta_min >= 2 deg, ~1/beta_min below. */
SL_INLINE int sl_deon_default_panels(const sl_fiber_params *fp) {
    float b = sl_minf(fp->beta[0], sl_minf(fp->beta[1], fp->beta[2]));
    float n = SL_DEON_PANEL_C / sl_maxf(b, 1e-6f);
    if (n < (float)SL_DEON_PANELS_MIN) return SL_DEON_PANELS_MIN;
    if (n > (float)SL_DEON_PANELS_MAX) return SL_DEON_PANELS_MAX;
    return (int)ceil(n);
}

/* N_p(phi) for p = 0..n (n <= SL_DEON_MAX_ORDERS) into np[], and E_rest into *e_rest, with
 * `panels` 8-point Gauss-Legendre panels over gamma in [0, pi/2]. d'Eon's symmetry (Sec. 6):
 * Phi(p,-gamma) = 2p pi - Phi(p,gamma) and A even, so
 *   N_p(phi) = integral_0^{pi/2} A(p, sin g) cos g [D(phi - Phi) + D(-phi - Phi)]/2 dg. */
SL_INLINE void sl_deon_azimuthal(const sl_fiber_params *fp, const sl_deon_geom *g, float phi, int n,
                                 int panels, float *np, float *e_rest) {
    for (int p = 0; p <= n; p++)
        np[p] = 0.0f;
    float er = 0.0f;
    float b0 = fp->beta[0], b1 = fp->beta[1], b2 = fp->beta[2];
    float hw = (0.5f * SL_PI_F / (float)panels) * 0.5f; /* half panel width */
    for (int k = 0; k < panels; k++) {
        for (int j = 0; j < 8; j++) {
            float gam, w;
            sl_gl8_node(0.0f, hw, k, j, &gam, &w);
            float sg = sin(gam), cg = cos(gam);
            float f, T;
            sl_deon_fT(g, sg, cg, &f, &T);
            float gt = asin(sl_clamp_unit(sg / g->etap));
            float wc = 0.5f * w * cg; /* 1/2 of [D(+) + D(-)] and dh = cos g dg */
            /* p = 0 */
            float ph = -2.0f * gam;
            np[0] += wc * f * (sl_deon_detector(b0, phi - ph) + sl_deon_detector(b0, -phi - ph));
            float a = (1.0f - f) * (1.0f - f) * T; /* A(1) */
            float step = 2.0f * gt + SL_PI_F;      /* Phi(p+1) - Phi(p) */
            for (int p = 1; p <= n; p++) {
                ph += step;
                if (ph > SL_PI_F) ph -= SL_TWO_PI_F; /* keep Phi small: float phase accuracy */
                float b = p == 1 ? b1 : b2;
                np[p] += wc * a * (sl_deon_detector(b, phi - ph) + sl_deon_detector(b, -phi - ph));
                a *= f * T;
            }
            /* sum_{p>n} A(p) = (1-f)^2 f^n T^(n+1) / (1 - f T) = a / (1 - fT) (a = A(n+1) now) */
            float den = 1.0f - f * T;
            if (den > 0.0f) er += w * cg * a / den;
        }
    }
    *e_rest = er;
}

/* The scattering function in float: out[p] = f_p (p = 0..orders), out[orders+1] = f_rest,
 * out[orders+2] = f, with an explicit panel count (the furnace uses a small fixed one: the
 * azimuthal integral of the sampled N_p is exact whatever the panel count). */
SL_INLINE void sl_deon_scatter_panels_lo(const sl_fiber_params *fp, float theta_i, float ti_lo,
                                         float phi_i, float theta_o, float to_lo, float phi_o,
                                         int panels, float *out) {
    int n = fp->orders;
    if (n > SL_DEON_MAX_ORDERS) n = SL_DEON_MAX_ORDERS;
    sl_deon_geom g;
    sl_deon_geom_init_lo(fp, theta_i, ti_lo, theta_o, to_lo, &g);
    float np[SL_DEON_MAX_ORDERS + 1];
    float e_rest;
    sl_deon_azimuthal(fp, &g, sl_wrap_pi(phi_o - phi_i), n, panels, np, &e_rest);
    float total = 0.0f;
    for (int p = 0; p <= n; p++) {
        float b = sl_deon_beta(fp, p);
        float lm = sl_deon_log_mp(b * b, theta_i, theta_o - 2.0f * sl_deon_alpha(fp, p));
        float fpv = exp(lm) * np[p];
        out[p] = fpv;
        total += fpv;
    }
    float b = fp->beta[2];
    float lm = sl_deon_log_mp(b * b, theta_i, theta_o - 2.0f * fp->alpha[2]);
    float fr = exp(lm) * e_rest * (1.0f / SL_TWO_PI_F);
    out[n + 1] = fr;
    out[n + 2] = total + fr;
}

SL_INLINE void sl_deon_scatter_panels(const sl_fiber_params *fp, float theta_i, float phi_i,
                                      float theta_o, float phi_o, int panels, float *out) {
    sl_deon_scatter_panels_lo(fp, theta_i, 0.0f, phi_i, theta_o, 0.0f, phi_o, panels, out);
}

/* numerics.md sec. 3 "deon": orders+3 values f_0..f_orders, f_rest, f. */
SL_INLINE void sl_deon_scatter(const sl_fiber_params *fp, float theta_i, float phi_i, float theta_o,
                               float phi_o, float *out) {
    sl_deon_scatter_panels(fp, theta_i, phi_i, theta_o, phi_o, sl_deon_default_panels(fp), out);
}

/* The same at theta_i + ti_lo, theta_o + to_lo (see sl_deon_geom_init_lo). */
SL_INLINE void sl_deon_scatter_lo(const sl_fiber_params *fp, float theta_i, float ti_lo,
                                  float phi_i, float theta_o, float to_lo, float phi_o,
                                  float *out) {
    sl_deon_scatter_panels_lo(fp, theta_i, ti_lo, phi_i, theta_o, to_lo, phi_o,
                              sl_deon_default_panels(fp), out);
}

#endif
