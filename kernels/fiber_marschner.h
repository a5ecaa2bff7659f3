/* fiber_marschner.h: the Marschner scattering function of numerics.md sec. 3 (Xu 2011 Eq. 6-10,
 * eccentricity Eq. 24, TRT caustics convolved with a normalised circular Gaussian of width w_c),
 * in float, shared by the C twin (cpu/fiber_c.c) and OpenCL (kernels/fiber.cl). The
 * double reference is cpu/reference/marschner_ref.c; docs/numerics.md states the tolerances.
 *
 * Numerical choices (see docs/numerics.md):
 *  - every mode works in u = asin(h): Phi(p, sin u) is smooth with bounded dPhi/du, and
 *    1/|dPhi/dh| = cos u / |dPhi/du| is finite and -> 0 at |h| = 1;
 *  - the even constant p*pi of Phi is dropped (targets are taken mod 2 pi), which keeps float
 *    Phi values small and accurate;
 *  - cos/sin(theta_d) are compensated for the rounding of (theta_o - theta_i)/2, so grazing
 *    pairs (cos theta_d ~ 1e-6) keep their relative accuracy;
 *  - R: h = -sin(phi/2) in closed form; TT: one root by safeguarded Newton; TRT: the convolution
 *    1/2 int A(h) G(phi - Phi(2,h)) dh / Z over the windows where G > 1e-9 (preimages of
 *    [phi - 4.6 w, phi + 4.6 w] on each monotone piece of Phi, between the caustic points),
 *    each by SL_MQ_TRT_PANELS panels of 8-point Gauss-Legendre in u. */
#ifndef SL_FIBER_MARSCHNER_H
#define SL_FIBER_MARSCHNER_H

#include "fiber_common.h"
#include "fiber_params.h"

#if SL_OPENCL
#define SL_MQ_TABLE static __constant
#else
#define SL_MQ_TABLE static const
#endif

/* Panels of 8-point Gauss-Legendre per TRT window (measured: see docs/numerics.md). */
#ifndef SL_MQ_TRT_PANELS
#define SL_MQ_TRT_PANELS 6
#endif
/* Half-width of a TRT window in units of w_c: G(4.6 w) = exp(-21.2) ~ 6e-10. */
#define SL_MQ_WINDOW 4.6f
#define SL_MQ_TWO_PI 6.28318530717958647692f
#define SL_MQ_HALF_PI 1.57079632679489661923f

/* 8-point Gauss-Legendre on [-1, 1], positive half. */
SL_MQ_TABLE float sl_mq_glx[4] = {0.183434642495649805f, 0.525532409916328986f,
                                  0.796666477413626740f, 0.960289856497536232f};
SL_MQ_TABLE float sl_mq_glw[4] = {0.362683783378361983f, 0.313706645877887287f,
                                  0.222381034453374471f, 0.101228536290376259f};

/* e^-x I0(x), x >= 0: power series below 12, asymptotic expansion (A&S 9.7.1) above. */
SL_INLINE float sl_mq_i0e(float x) {
    x = fabs(x);
    float sum = 1.0f, term = 1.0f;
    if (x < 12.0f) {
        float q = 0.25f * x * x;
        for (int j = 1; j < 48; j++) {
            term *= q / (float)(j * j);
            sum += term;
            if (term < 1e-8f * sum) break;
        }
        return sum * exp(-x);
    }
    for (int j = 1; j < 16; j++) {
        float r = (float)((2 * j - 1) * (2 * j - 1)) / (8.0f * x * (float)j);
        term *= r;
        sum += term;
        if (term < 1e-8f * sum) break;
    }
    return sum / sqrt(SL_MQ_TWO_PI * x);
}

/* One mode's constants at this theta_d. */
typedef struct sl_mq_mode {
    float eta;      /* eta, or eta* for an eccentric TRT */
    float cos_td;   /* cos theta_d */
    float inv_etap; /* 1/eta' = cos td / sqrt(eta^2 - sin^2 td) (finite as cos td -> 0) */
    float sigma_p;  /* sigma_a' = sigma_a / cos theta_t */
    int t;          /* 0 R, 1 TT, 2 TRT */
    int schlick;    /* 1: Schlick Fresnel */
} sl_mq_mode;

/* Returns 0 when eta^2 <= sin^2 td (only possible for eta* < 1): total internal reflection
 * for every h, so the mode carries nothing. */
SL_INLINE int sl_mq_mode_setup(sl_mq_mode *c, const sl_fiber_params *fp, int t, float eta,
                               float cos_td, float sin_td) {
    float q = eta * eta - sin_td * sin_td;
    c->eta = eta;
    c->cos_td = cos_td;
    c->t = t;
    c->schlick = fp->fresnel == 1;
    c->inv_etap = 0.0f;
    c->sigma_p = 0.0f;
    if (!(eta > 0.0f) || !(q > 0.0f)) return 0;
    float sq = sqrt(q);
    c->inv_etap = cos_td / sq;
    c->sigma_p = fp->sigma_a * eta / sq; /* sigma_a / cos theta_t, cos theta_t = sqrt(q)/eta */
    return 1;
}

/* Fresnel reflectance F at incidence cosine cos_i (numerics.md: exact unpolarised, or Schlick)
 * and *tr = 1 - F computed without cancellation: at grazing incidence (cos theta_d ~ 1e-6) F is
 * within 1e-6 of 1 and a float 1 - F would keep only a couple of digits. Same values as
 * sl_fresnel_exact / sl_fresnel_schlick of fiber_common.h otherwise. */
SL_INLINE float sl_mq_fresnel(float eta, float cos_i, int schlick, float *tr) {
    float ci = sl_minf(fabs(cos_i), 1.0f);
    if (schlick) {
        float f0 = (eta - 1.0f) / (eta + 1.0f);
        f0 *= f0;
        float c = 1.0f - ci, c2 = c * c;
        *tr = (1.0f - f0) * ci * (1.0f + c + c2 + c2 * c + c2 * c2); /* (1-f0)(1 - c^5) */
        return f0 + (1.0f - f0) * c2 * c2 * c;
    }
    float s2t = (1.0f - ci) * (1.0f + ci) / (eta * eta);
    if (s2t >= 1.0f) {
        *tr = 0.0f;
        return 1.0f;
    }
    float ct = sqrt(1.0f - s2t), a = eta * ct, b = eta * ci;
    float rs = (ci - a) / (ci + a), rp = (b - ct) / (b + ct);
    float ts = 4.0f * ci * a / ((ci + a) * (ci + a)), tp = 4.0f * b * ct / ((b + ct) * (b + ct));
    *tr = 0.5f * (ts + tp); /* 1 - rs^2 = 4 ci a / (ci + a)^2, likewise for rp */
    return 0.5f * (rs * rs + rp * rp);
}

/* A_t (Xu Eq. 10) at h = sin u (su = sin u, cu = cos u = cos gamma_i). */
SL_INLINE float sl_mq_A(const sl_mq_mode *c, float su, float cu) {
    float tr;
    float F = sl_mq_fresnel(c->eta, c->cos_td * cu, c->schlick, &tr);
    if (c->t == 0) return F;
    float s = su * c->inv_etap, q = sl_maxf(1.0f - s * s, 0.0f);
    float T = exp(-2.0f * c->sigma_p * sqrt(q));
    float g = tr * tr;
    return c->t == 1 ? g * T : g * F * T * T;
}

/* psi_p(u) = Phi(p, sin u) - p pi = 2p asin(sin u / eta') - 2u, and its u-derivative. */
SL_INLINE float sl_mq_psi(int p, float inv_etap, float u) {
    return 2.0f * (float)p * asin(sl_clamp_unit(sin(u) * inv_etap)) - 2.0f * u;
}
SL_INLINE float sl_mq_dpsi(int p, float inv_etap, float u) {
    float s = sin(u) * inv_etap, q = 1.0f - s * s;
    if (q <= 0.0f) return 0.0f; /* infinite slope: the caller bisects */
    return 2.0f * (float)p * cos(u) * inv_etap / sqrt(q) - 2.0f;
}

/* Solves psi_p(u) = y on [a, b] where psi_p is monotone and brackets y: Newton from x0,
 * safeguarded by bisection of the shrinking bracket (converges for any start). */
SL_INLINE float sl_mq_solve(int p, float inv_etap, float y, float a, float b, float x0) {
    float fa = sl_mq_psi(p, inv_etap, a) - y;
    float lo = a, hi = b;
    float x = sl_clampf(x0, sl_minf(a, b), sl_maxf(a, b));
    for (int it = 0; it < 40; it++) {
        float fx = sl_mq_psi(p, inv_etap, x) - y;
        if (fx == 0.0f) break;
        if ((fx < 0.0f) == (fa < 0.0f))
            lo = x;
        else
            hi = x;
        float xn = x - fx / sl_mq_dpsi(p, inv_etap, x);
        float mn = sl_minf(lo, hi), mx = sl_maxf(lo, hi);
        if (!(xn > mn && xn < mx)) xn = 0.5f * (lo + hi);
        float step = fabs(xn - x);
        x = xn;
        if (step <= 2.5e-7f || mx - mn <= 2.5e-7f) break;
    }
    return x;
}

/* N_R: the one root h = -sin(phi/2), cos gamma_i = cos(phi/2), 1/|dPhi/dh| = cos(phi/2)/2, at
 * phi + phi_lo: near phi = +-pi (h -> +-1, R's far tail) cos(phi/2) is below one float spacing
 * of phi, so phi_lo enters to first order (next term below 1e-14 relative). */
SL_INLINE float sl_mq_N_R(const sl_mq_mode *c, float phi, float phi_lo) {
    float ch = cos(0.5f * phi), sh = sin(0.5f * phi), d = 0.5f * phi_lo;
    float cu = fabs(ch - sh * d);
    return sl_mq_A(c, -(sh + ch * d), cu) * cu * 0.25f;
}

/* wrap(phi_o - phi_i) to (-pi, pi] as *lo + the returned float, from inputs phi + phi_lo: TwoSum
 * for the difference and 2 pi split in two floats (float(2 pi) is 1.7e-7 off), so phi near +-pi
 * keeps its distance to the wrap point. */
SL_INLINE float sl_mq_phi_lo(float phi_i, float pi_lo, float phi_o, float po_lo, float *lo) {
    const float two_pi_hi = 6.28318548202514648438f, two_pi_lo = -1.74845553146951715e-7f;
    const float pi_hi = 3.14159274101257324219f, pi_lo_c = -8.74227765734758577e-8f;
    float s = phi_o - phi_i, bb = s - phi_o;
    float e = (phi_o - (s - bb)) + (-phi_i - bb) + (po_lo - pi_lo);
    /* s in [-2 pi, 2 pi]: s -+ two_pi_hi is exact there (Sterbenz) */
    if ((s - pi_hi) + (e - pi_lo_c) > 0.0f) {
        s -= two_pi_hi;
        e -= two_pi_lo;
    } else if ((s + pi_hi) + (e + pi_lo_c) <= 0.0f) {
        s += two_pi_hi;
        e += two_pi_lo;
    }
    *lo = e;
    return s;
}

/* N_TT: psi_1 decreases from pi - 2 asin(1/eta') to its negative over u in [-pi/2, pi/2]. */
SL_INLINE float sl_mq_N_TT(const sl_mq_mode *c, float phi) {
    float y = sl_wrap_pi(phi - SL_PI_F);
    float ymax = SL_PI_F - 2.0f * asin(sl_minf(c->inv_etap, 1.0f));
    if (!(fabs(y) < ymax)) return 0.0f;
    float slope0 = 2.0f * c->inv_etap - 2.0f; /* dpsi/du at 0, < 0 */
    float u = sl_mq_solve(1, c->inv_etap, y, -SL_MQ_HALF_PI, SL_MQ_HALF_PI, y / slope0);
    float cu = cos(u), d = fabs(sl_mq_dpsi(1, c->inv_etap, u));
    if (!(cu > 0.0f) || !(d > 0.0f)) return 0.0f;
    return sl_mq_A(c, sin(u), cu) * cu / (2.0f * d);
}

/* Sum over SL_MQ_TRT_PANELS Gauss-Legendre panels on [ua, ub] of A cos u G(phi - psi_2(u)),
 * with G(x) = exp(2(cos x - 1)/w^2) = exp(-4 sin^2(x/2) / w^2) (periodic: the dropped 2 pi of
 * Phi does not matter). */
SL_INLINE float sl_mq_trt_panels(const sl_mq_mode *c, float phi, float inv_w2, float ua, float ub) {
    float hw = 0.5f * (ub - ua) / (float)SL_MQ_TRT_PANELS, sum = 0.0f;
    for (int k = 0; k < SL_MQ_TRT_PANELS; k++) {
        float mid = ua + hw * (float)(2 * k + 1);
        for (int j = 0; j < 8; j++) {
            float x = sl_mq_glx[j & 3], wt = sl_mq_glw[j & 3];
            float u = mid + ((j & 4) ? -x : x) * hw;
            float su = sin(u), cu = cos(u);
            float sh = sin(0.5f * (phi - sl_mq_psi(2, c->inv_etap, u)));
            float g = exp(-4.0f * sh * sh * inv_w2);
            sum += wt * sl_mq_A(c, su, cu) * cu * g;
        }
    }
    return sum * hw;
}

/* N_TRT convolved with the normalised circular Gaussian of width w (numerics.md sec. 3):
 * (N * G)(phi) = 1/2 int A(h) G(phi - Phi(2, h)) dh / (2 pi i0e(2/w^2)). */
SL_INLINE float sl_mq_N_TRT(const sl_mq_mode *c, float phi, float w) {
    float inv = c->inv_etap;
    float umax = inv <= 1.0f ? SL_MQ_HALF_PI : asin(1.0f / inv); /* |h| < min(1, eta') */
    float cuts[4];
    int nc = 0;
    cuts[nc++] = -umax;
    if (inv < 1.0f && inv > 0.5f) { /* 1 < eta' < 2: caustic at h_c^2 = (4 - eta'^2)/3 */
        float hc2 = (4.0f - 1.0f / (inv * inv)) / 3.0f;
        float uc = asin(sqrt(sl_clampf(hc2, 0.0f, 1.0f)));
        if (uc > 0.0f && uc < umax) {
            cuts[nc++] = -uc;
            cuts[nc++] = uc;
        }
    }
    cuts[nc++] = umax;
    float inv_w2 = 1.0f / (w * w);
    float W = SL_MQ_WINDOW * w, sum = 0.0f;
    for (int i = 0; i + 1 < nc; i++) {
        float a = cuts[i], b = cuts[i + 1];
        if (W >= SL_PI_F) {
            sum += sl_mq_trt_panels(c, phi, inv_w2, a, b);
            continue;
        }
        float ya = sl_mq_psi(2, inv, a), yb = sl_mq_psi(2, inv, b);
        float lo = sl_minf(ya, yb), hi = sl_maxf(ya, yb);
        /* |psi_2| <= pi and |phi| <= pi: only k = -1, 0, 1 can reach the piece. */
        for (int k = -1; k <= 1; k++) {
            float c0 = phi + SL_MQ_TWO_PI * (float)k;
            float t1 = sl_maxf(c0 - W, lo), t2 = sl_minf(c0 + W, hi);
            if (!(t1 < t2)) continue;
            float u1 =
                t1 <= lo ? (ya <= yb ? a : b) : sl_mq_solve(2, inv, t1, a, b, 0.5f * (a + b));
            float u2 =
                t2 >= hi ? (ya <= yb ? b : a) : sl_mq_solve(2, inv, t2, a, b, 0.5f * (a + b));
            sum += sl_mq_trt_panels(c, phi, inv_w2, sl_minf(u1, u2), sl_maxf(u1, u2));
        }
    }
    float z = SL_MQ_TWO_PI * sl_mq_i0e(2.0f * inv_w2);
    return 0.5f * sum / z;
}

/* M_t = exp(-(theta_h - alpha_t)^2 / beta_t^2) / (sqrt(pi) beta_t) (Xu Table 1, Eq. 7). */
SL_INLINE float sl_mq_M(float theta_h, float alpha, float beta) {
    float x = (theta_h - alpha) / beta;
    return exp(-x * x) / (SL_SQRT_PI_F * beta);
}

/* out = f_R, f_TT, f_TRT, f (numerics.md sec. 3) for one colour channel, at the angles
 * theta_i + theta_i_lo, phi_i + phi_i_lo, ...: the _lo parts are what float rounding took off a
 * double input (|lo| <= one float spacing, 1.2e-7 near pi/2; 0 when the input is a float).
 * Near a pole cos theta ~ pi/2 - |theta| is below that spacing, so without them a float input
 * cannot say how close to the pole it is, and cos theta_i / cos^2 theta_d (Marschner's
 * projection factor, unbounded at opposite poles) is off by up to a factor of 1e9 (issue #21,
 * docs/numerics.md "Poles and tails"); likewise N_R ~ cos(phi/2) near phi = +-pi. They enter to
 * first order (cos(x + lo) = cos x - lo sin x; the next term is below 1e-14 relative). */
SL_INLINE void sl_marschner_scatter_lo(const sl_fiber_params *fp, float theta_i, float theta_i_lo,
                                       float phi_i, float phi_i_lo, float theta_o, float theta_o_lo,
                                       float phi_o, float phi_o_lo, float out[4]) {
    /* theta_d with its rounding error (TwoSum) and the inputs' lo parts, so cos theta_d stays
     * accurate near +-pi/2. */
    float s = theta_o - theta_i, bb = s - theta_o;
    float err = (theta_o - (s - bb)) + (-theta_i - bb) + (theta_o_lo - theta_i_lo);
    float td = 0.5f * s, td_lo = 0.5f * err;
    float ctd0 = cos(td), std0 = sin(td);
    float cos_td = ctd0 - std0 * td_lo, sin_td = std0 + ctd0 * td_lo;
    float theta_h = 0.5f * (theta_o + theta_i) + 0.5f * (theta_o_lo + theta_i_lo);
    float phi_lo, phi = sl_mq_phi_lo(phi_i, phi_i_lo, phi_o, phi_o_lo, &phi_lo);
    cos_td = sl_maxf(cos_td, 1e-12f);
    float cti = sl_maxf(cos(theta_i) - sin(theta_i) * theta_i_lo, 0.0f);
    float geo = (cti / cos_td) / cos_td; /* cos theta_i / cos^2 theta_d */
    float eta_trt =
        fp->eccentricity == 1.0f ? fp->eta : sl_eta_star(fp->eta, fp->eccentricity, phi_o + phi_i);
    float total = 0.0f;
    for (int t = 0; t < 3; t++) {
        float M = sl_mq_M(theta_h, fp->alpha[t], fp->beta[t]);
        float f = 0.0f;
        sl_mq_mode c;
        if (M > 0.0f && geo > 0.0f &&
            sl_mq_mode_setup(&c, fp, t, t == 2 ? eta_trt : fp->eta, cos_td, sin_td)) {
            float N =
                t == 0 ? sl_mq_N_R(&c, phi, phi_lo)
                       : (t == 1 ? sl_mq_N_TT(&c, phi) : sl_mq_N_TRT(&c, phi, fp->caustic_width));
            f = M * N * geo;
            if (!(f <= SL_FLT_MAX)) f = 0.0f; /* NaN or Inf: cannot happen for inputs in range */
        }
        out[t] = f;
        total += f;
    }
    out[3] = total;
}

/* The same at float angles (no lo parts). */
SL_INLINE void sl_marschner_scatter(const sl_fiber_params *fp, float theta_i, float phi_i,
                                    float theta_o, float phi_o, float out[4]) {
    sl_marschner_scatter_lo(fp, theta_i, 0.0f, phi_i, 0.0f, theta_o, 0.0f, phi_o, 0.0f, out);
}

#endif
