/* srbf_xu.h: Xu et al. 2011 Sec. 4.2 closed-form SRBF response of the Marschner model (the
 * `--method xu` path), in float, shared by the C twin (cpu/srbf_c.c) and OpenCL
 * (kernels/srbf.cl). Every reading of an ambiguity of the paper is in docs/srbf.md; the
 * tables (C_k, H_k) are built on the host by host/passes/shade/srbf_tables.c with the layout below.
 *
 *   I_t ~ int g(theta_i; theta_j, lambda) M_t(theta_h) cos^2 theta_i / cos^2 theta_d
 *             N'_t(lambda', phi_o - phi_j, theta_d) d theta_i                       (Xu Eq. 11)
 * with lambda' = lambda / sqrt(cos theta_i cos theta_j), the inner azimuthal integral N'_t in
 * closed form (R: Eq. 13-14, TT: Eq. 16-19, TRT: Eq. 20-23, eccentricity: Eq. 25-26) and the
 * outer one by the m-segment piecewise-linear Gaussian quadrature of Sec. 4.2.2. */
#ifndef SL_SRBF_XU_H
#define SL_SRBF_XU_H

#include "fiber_marschner.h"

/* ---- table layout (host/passes/shade/srbf_tables.c fills them; docs/srbf.md) ---- */
#define SL_SRBF_NL 128   /* lambda' samples, log-uniform in [SL_SRBF_LMIN, SL_SRBF_LMAX] */
#define SL_SRBF_NPHI 64  /* |phi| samples, uniform in [0, pi] */
#define SL_SRBF_NETA 128 /* eta samples, log-uniform in [1, 10] */
#define SL_SRBF_NTD 64   /* |theta_d| samples, uniform in [0, pi/2] */
#define SL_SRBF_LMIN 0.001f
#define SL_SRBF_LMAX 10.0f
#define SL_SRBF_ETAMIN 1.0f
#define SL_SRBF_ETAMAX 10.0f
/* C: [il][ip][8] (k = 0..6, one pad): the mean of |cos^k((phi - x)/2)| under the normalised
 * circular Gaussian g^c(x; 0, lambda'), i.e. C_k of Xu Eq. 14 divided by int g^c. */
#define SL_SRBF_C_FLOATS (SL_SRBF_NL * SL_SRBF_NPHI * 8)
/* H: [fresnel 0 exact / 1 schlick][mode 0 TT / 1 TRT][ieta][itd][4] (k = 0, 2, 4, one pad):
 * H_k^TT = int_{-1}^{1} (1-F)^2 h^k dh, H_k^TRT = int (1-F)^2 F h^k dh (Xu Eq. 19, 23). */
#define SL_SRBF_HK_FLOATS (2 * 2 * SL_SRBF_NETA * SL_SRBF_NTD * 4)
/* W (the fast path, kernels/srbf_fast.h), stored in the same buffer right after H_k so that every
 * caller that passes H passes it too: [mode 0 TT / 1 TRT][ix][il][ip][SL_SRBF_W_NODES] (and R
 * below), the
 * azimuthal product-quadrature weights
 *   W_i(x, lambda, phi) = 1/2 int_{-1}^{1} L_i(sqrt(1 - h^2)) g^c(phi - Phi(p, h); 0, lambda) dh
 *                         / int g^c(.; 0, lambda)
 * with x = 1/eta' uniform in [0, 1], lambda log-uniform in [SL_SRBF_W_LMIN, SL_SRBF_LMAX], |phi|
 * uniform in [0, pi], and L_i the Lagrange polynomials in c = cos gamma_i on the nodes
 * sl_srbf_w_c[] (kernels/srbf_fast.h): so the exactly convolved N'_p of any A_p(h) smooth in c is
 * sum_i A_p(c_i) W_i (docs/srbf.md, "fast"). */
#define SL_SRBF_W_NX 32
#define SL_SRBF_W_NL 24
#define SL_SRBF_W_NP 64
#define SL_SRBF_W_NODES 4
#define SL_SRBF_W_LMIN 0.02f
#define SL_SRBF_W_TRT_FLOATS (2 * SL_SRBF_W_NX * SL_SRBF_W_NL * SL_SRBF_W_NP * SL_SRBF_W_NODES)
/* then mode 2, R (p = 0: Phi(0, h) = -2 asin h does not depend on eta'): [il][ip][node] */
#define SL_SRBF_W_FLOATS (SL_SRBF_W_TRT_FLOATS + SL_SRBF_W_NL * SL_SRBF_W_NP * SL_SRBF_W_NODES)
/* The whole H buffer: H_k, then W. */
#define SL_SRBF_H_FLOATS (SL_SRBF_HK_FLOATS + SL_SRBF_W_FLOATS)

/* Width of the smoothstep that blends TRT's caustic width w_c into lambda_3 above eta' = 2
 * (Xu 4.2.4: "typically between 0.2 and 0.4"). */
#define SL_SRBF_DELTA_ETAP 0.3f
#define SL_SRBF_MAX_SEGMENTS 8

/* ---- table lookups (bilinear, clamped to the table range) ---- */

SL_INLINE float sl_srbf_grid(float x, float x0, float x1, int n, int *i) {
    float t = (x - x0) / (x1 - x0) * (float)(n - 1);
    t = sl_clampf(t, 0.0f, (float)(n - 1));
    int k = (int)t;
    if (k > n - 2) k = n - 2;
    *i = k;
    return t - (float)k;
}

/* Normalised C_k (k = 0..6) at (lambda', |phi|). */
SL_INLINE void sl_srbf_C(SL_GLOBAL const float *C, float lam, float phi, float out[7]) {
    int il, ip;
    float fl = sl_srbf_grid(log(sl_maxf(lam, 1e-30f)), log(SL_SRBF_LMIN), log(SL_SRBF_LMAX),
                            SL_SRBF_NL, &il);
    float fp = sl_srbf_grid(fabs(phi), 0.0f, SL_PI_F, SL_SRBF_NPHI, &ip);
    SL_GLOBAL const float *c00 = C + ((il * SL_SRBF_NPHI) + ip) * 8;
    SL_GLOBAL const float *c01 = c00 + 8;
    SL_GLOBAL const float *c10 = c00 + SL_SRBF_NPHI * 8;
    SL_GLOBAL const float *c11 = c10 + 8;
    for (int k = 0; k < 7; k++) {
        float a = c00[k] + (c01[k] - c00[k]) * fp;
        float b = c10[k] + (c11[k] - c10[k]) * fp;
        out[k] = a + (b - a) * fl;
    }
}

/* H_0, H_2, H_4 of mode (0 TT, 1 TRT) at (eta, |theta_d|). */
SL_INLINE void sl_srbf_H(SL_GLOBAL const float *H, int schlick, int mode, float eta, float td,
                         float out[3]) {
    int ie, it;
    float fe =
        sl_srbf_grid(log(sl_maxf(eta, 1e-30f)), 0.0f, log(SL_SRBF_ETAMAX), SL_SRBF_NETA, &ie);
    float ft = sl_srbf_grid(fabs(td), 0.0f, 0.5f * SL_PI_F, SL_SRBF_NTD, &it);
    SL_GLOBAL const float *base = H + (schlick * 2 + mode) * SL_SRBF_NETA * SL_SRBF_NTD * 4;
    SL_GLOBAL const float *h00 = base + (ie * SL_SRBF_NTD + it) * 4;
    SL_GLOBAL const float *h01 = h00 + 4;
    SL_GLOBAL const float *h10 = h00 + SL_SRBF_NTD * 4;
    SL_GLOBAL const float *h11 = h10 + 4;
    for (int k = 0; k < 3; k++) {
        float a = h00[k] + (h01[k] - h00[k]) * ft;
        float b = h10[k] + (h11[k] - h10[k]) * ft;
        out[k] = a + (b - a) * fe;
    }
}

/* ---- circular Gaussians (Xu appendix C, F) ---- */

/* int over the circle of g^c(x; 0, l1) g^c(x; mu, l2): appendix C gives b g^c(x; mu3, l3) with
 * 2 / l3^2 = R = |k1 + k2 e^(i mu)| (k = 2 / l^2; the printed l3 = 1/sqrt(m^2+n^2) drops a square
 * root, docs/srbf.md) and b = exp(R - k1 - k2); the remaining integral of g^c(l3) is sqrt(pi) l3
 * (appendix F) when exact_norm == 0, else 2 pi e^-R I0(R) exactly. */
SL_INLINE float sl_srbf_cg_prod(float l1, float l2, float mu, int exact_norm) {
    float k1 = 2.0f / (l1 * l1), k2 = 2.0f / (l2 * l2);
    float s = sin(0.5f * mu), s2 = s * s;
    float r2 = (k1 + k2) * (k1 + k2) - 4.0f * k1 * k2 * s2;
    float R = sqrt(sl_maxf(r2, 0.0f));
    float den = k1 + k2 + R;
    float lb = den > 0.0f ? -4.0f * k1 * k2 * s2 / den : 0.0f; /* R - k1 - k2, no cancellation */
    float norm = exact_norm ? 2.0f * SL_PI_F * sl_mq_i0e(R)
                            : (R > 0.0f ? SL_SQRT_PI_F * sqrt(2.0f / R) : 2.0f * SL_PI_F);
    return exp(lb) * norm;
}

/* erf: Abramowitz & Stegun 7.1.25 as printed in Xu's appendix E (|error| <= 2.5e-5). */
SL_INLINE float sl_srbf_erf_as(float x) {
    float ax = fabs(x), t = 1.0f / (1.0f + 0.47047f * ax);
    float y = 1.0f - t * (0.3480242f + t * (-0.0958798f + t * 0.7478556f)) * exp(-ax * ax);
    return x < 0.0f ? -y : y;
}

/* ---- the azimuthal closed forms at one theta_i (Xu 4.2.1-4.2.5) ---- */

typedef struct sl_srbf_az {
    float phi;     /* phi_o - phi_j, wrapped */
    float phi_sum; /* phi_o + phi_j, wrapped (eccentricity) */
    float lam_p;   /* lambda' */
    float z;       /* int g^c(x; 0, lambda') dx = 2 pi i0e(2 / lambda'^2) */
} sl_srbf_az;

/* N'_R (Eq. 13-14): N_R = 1/4 |cos(phi/2)| F_schlick(cos theta_d |cos(phi/2)|) expanded in
 * powers of c = |cos(phi/2)|: C_1 = 1/4, C_{j+1} = 1/4 (1 - F0) binom(5, j) (-cos theta_d)^j. */
SL_INLINE float sl_srbf_xu_R(const sl_srbf_az *a, const float Cn[7], float eta, float cos_td) {
    float f0 = (eta - 1.0f) / (eta + 1.0f);
    f0 *= f0;
    const float binom[6] = {1.0f, 5.0f, 10.0f, 10.0f, 5.0f, 1.0f};
    float sum = 0.25f * Cn[1], x = 1.0f;
    for (int j = 1; j <= 5; j++) {
        x *= -cos_td;
        sum += 0.25f * (1.0f - f0) * binom[j] * x * Cn[j + 1];
    }
    return sum * a->z;
}

/* 1/2 sum_k t_k H_k with the 4th-order Taylor coefficients of T^n in h (Eq. 18, 22):
 * T^n = exp(-2 n s sqrt(1 - h^2/eta'^2)) ~ e^(-2 n s) (1 + n s q + (n s / 4 + (n s)^2 / 2) q^2),
 * q = h^2 / eta'^2 (s = sigma_a'). */
SL_INLINE float sl_srbf_energy(const float Hk[3], float nsig, float inv_etap) {
    float e = exp(-2.0f * nsig), q = inv_etap * inv_etap;
    float t2 = nsig * q, t4 = (0.25f * nsig + 0.5f * nsig * nsig) * q * q;
    return 0.5f * e * (Hk[0] + t2 * Hk[1] + t4 * Hk[2]);
}

/* N'_TT (Eq. 15-19): b_tt g^c(phi; pi, lambda_tt) with b_tt = N_TT(pi) (root h = 0) and lambda_tt
 * from the energy E = 1/2 sum a_k H_k^TT: lambda_tt = E / (sqrt(pi) b_tt). */
SL_INLINE float sl_srbf_xu_TT(const sl_srbf_az *a, const sl_fiber_params *fp,
                              SL_GLOBAL const float *H, float cos_td, float sin_td, float td) {
    sl_mq_mode c;
    if (!sl_mq_mode_setup(&c, fp, 1, fp->eta, cos_td, sin_td)) return 0.0f;
    float A0 = sl_mq_A(&c, 0.0f, 1.0f);
    float d = 2.0f - 2.0f * c.inv_etap; /* |dPhi/dh| at h = 0 */
    if (!(A0 > 0.0f) || !(d > 0.0f)) return 0.0f;
    float btt = A0 / (2.0f * d);
    float Hk[3];
    sl_srbf_H(H, fp->fresnel == 1, 0, fp->eta, td, Hk);
    float E = sl_srbf_energy(Hk, c.sigma_p, c.inv_etap);
    float ltt = E / (SL_SQRT_PI_F * btt);
    if (!(ltt > 1e-6f)) return 0.0f;
    return btt * sl_srbf_cg_prod(a->lam_p, ltt, a->phi - SL_PI_F, 0);
}

/* N_TRT(0) of Eq. 9 (no w_c smoothing): the root h = 0 and, for sqrt(2) < eta' < 2, the two
 * roots beyond the caustic where 4 asin(h/eta') = 2 asin(h). */
SL_INLINE float sl_srbf_trt_root0(const sl_mq_mode *c) {
    float inv = c->inv_etap;
    float d0 = fabs(4.0f * inv - 2.0f);
    float n = d0 > 0.0f ? sl_mq_A(c, 0.0f, 1.0f) / (2.0f * d0) : 0.0f;
    if (inv > 0.5f && inv < 0.70710678f) {
        float hc2 = (4.0f - 1.0f / (inv * inv)) / 3.0f;
        float uc = asin(sqrt(sl_clampf(hc2, 0.0f, 1.0f)));
        float ub = 0.5f * SL_PI_F;
        if (sl_mq_psi(2, inv, uc) > 0.0f && sl_mq_psi(2, inv, ub) < 0.0f) {
            float u = sl_mq_solve(2, inv, 0.0f, uc, ub, 0.5f * (uc + ub));
            float cu = cos(u), d = fabs(sl_mq_dpsi(2, inv, u));
            if (cu > 0.0f && d > 0.0f) n += 2.0f * sl_mq_A(c, sin(u), cu) * cu / (2.0f * d);
        }
    }
    return n;
}

SL_INLINE float sl_srbf_smoothstep(float e0, float e1, float x) {
    float t = sl_clampf((x - e0) / (e1 - e0), 0.0f, 1.0f);
    return t * t * (3.0f - 2.0f * t);
}

/* N'_TRT (Eq. 20-23) with index eta_t (eta, or the averaged eta* of Eq. 26). exact_norm: 1 for
 * the exact circular-Gaussian integrals (fast path), 0 for appendix F (as printed). */
SL_INLINE float sl_srbf_xu_TRT(const sl_srbf_az *a, const sl_fiber_params *fp,
                               SL_GLOBAL const float *H, float eta_t, float cos_td, float sin_td,
                               float td, int exact_norm) {
    sl_mq_mode c;
    if (!sl_mq_mode_setup(&c, fp, 2, eta_t, cos_td, sin_td)) return 0.0f;
    float Hk[3];
    sl_srbf_H(H, fp->fresnel == 1, 1, eta_t, td, Hk);
    float E = sl_srbf_energy(Hk, 2.0f * c.sigma_p, c.inv_etap);
    if (!(E > 0.0f)) return 0.0f;
    float etap = 1.0f / c.inv_etap, wc = fp->caustic_width;
    float lp = a->lam_p, phi = a->phi;
    if (etap < 2.0f) {
        float hs = sqrt(sl_clampf((4.0f - etap * etap) / 3.0f, 0.0f, 1.0f));
        float ps = fabs(sl_wrap_pi(sl_mq_psi(2, c.inv_etap, asin(hs))));
        float g0 = exp(2.0f * (cos(ps) - 1.0f) / (wc * wc));
        float b2 = sl_srbf_trt_root0(&c) * (1.0f - g0) * (1.0f - g0);
        float b1 = (E - b2 * SL_SQRT_PI_F * ps) / (2.0f * SL_SQRT_PI_F * wc);
        float r = b1 * (sl_srbf_cg_prod(lp, wc, phi - ps, exact_norm) +
                        sl_srbf_cg_prod(lp, wc, phi + ps, exact_norm));
        if (ps > 1e-4f) r += b2 * sl_srbf_cg_prod(lp, ps, phi, exact_norm);
        return r;
    }
    /* eta' >= 2: one Gaussian at 0; b3 lambda3 = E / sqrt(pi), width blended from w_c. */
    float b3 = sl_srbf_trt_root0(&c);
    float l3 = b3 > 0.0f ? E / (SL_SQRT_PI_F * b3) : 0.0f;
    float t = sl_srbf_smoothstep(2.0f, 2.0f + SL_SRBF_DELTA_ETAP, etap);
    float l3p = wc + (l3 - wc) * t;
    if (!(l3p > 1e-6f)) return 0.0f;
    return E / (SL_SQRT_PI_F * l3p) * sl_srbf_cg_prod(lp, l3p, phi, exact_norm);
}

/* The start of a quadrature node at theta_i = ti that both methods share (this file's
 * sl_srbf_xu_node, srbf_fast.h's sl_srbf_fast_node): theta_d = (theta_o - ti) / 2 with its cos
 * and sin, the factor cos^2 theta_i / cos^2 theta_d, and the lobe's azimuths and lambda' (a->z is
 * left to the caller: each method has its own i0e). Returns 0 where the node contributes nothing
 * (cos theta_i or cos theta_d ~ 0). */
SL_INLINE int sl_srbf_node_setup(float theta_o, float phi_o, float phi_j, float cos_tj,
                                 float lambda, float ti, float *td, float *cos_td, float *sin_td,
                                 float *geo, sl_srbf_az *a) {
    float cti = cos(ti);
    if (!(cti > 1e-7f)) return 0;
    *td = 0.5f * (theta_o - ti);
    *cos_td = cos(*td);
    *sin_td = sin(*td);
    if (!(*cos_td > 1e-7f)) return 0;
    *geo = cti * cti / (*cos_td * *cos_td);
    a->phi = sl_wrap_pi(phi_o - phi_j);
    a->phi_sum = sl_wrap_pi(phi_o + phi_j);
    float cc = cti * cos_tj;
    /* lambda' = lambda / sqrt(cos ti cos tj), clamped to the table range (Xu Sec. 5) */
    a->lam_p = cc > 0.0f ? lambda / sqrt(cc) : SL_SRBF_LMAX;
    a->lam_p = sl_clampf(a->lam_p, SL_SRBF_LMIN, SL_SRBF_LMAX);
    return 1;
}

/* The TRT eta' at a node (both methods): fp->eta for a round fiber; for an elliptic one Eq. 26,
 * cos(2 phi_h) = 2 cos^2((x + phi_j + phi_o)/2) - 1 averaged with C_0, C_2. */
SL_INLINE float sl_srbf_trt_eta(const sl_fiber_params *fp, SL_GLOBAL const float *C,
                                const sl_srbf_az *a) {
    if (fp->eccentricity == 1.0f) return fp->eta;
    float Ce[7];
    sl_srbf_C(C, a->lam_p, a->phi_sum, Ce);
    float mc = 2.0f * Ce[2] / sl_maxf(Ce[0], 1e-30f) - 1.0f;
    float aa = fp->eccentricity, eta = fp->eta;
    float e1 = 2.0f * (eta - 1.0f) * aa * aa - eta + 2.0f;
    float e2 = 2.0f * (eta - 1.0f) / (aa * aa) - eta + 2.0f;
    return 0.5f * ((e1 + e2) + mc * (e1 - e2));
}

/* cos^2 theta_i / cos^2 theta_d N'_t at one quadrature node theta_i for mode t. */
SL_INLINE float sl_srbf_xu_node(const sl_fiber_params *fp, SL_GLOBAL const float *C,
                                SL_GLOBAL const float *H, float theta_o, float phi_o, float phi_j,
                                float cos_tj, float lambda, float ti, int t) {
    float td, cos_td, sin_td, geo;
    sl_srbf_az a;
    if (!sl_srbf_node_setup(theta_o, phi_o, phi_j, cos_tj, lambda, ti, &td, &cos_td, &sin_td, &geo,
                            &a))
        return 0.0f;
    a.z = 2.0f * SL_PI_F * sl_mq_i0e(2.0f / (a.lam_p * a.lam_p));
    if (t == 0) {
        float Cn[7];
        sl_srbf_C(C, a.lam_p, a.phi, Cn);
        return geo * sl_srbf_xu_R(&a, Cn, fp->eta, cos_td);
    }
    if (t == 1) return geo * sl_srbf_xu_TT(&a, fp, H, cos_td, sin_td, td);
    float eta_t = sl_srbf_trt_eta(fp, C, &a);
    return geo * sl_srbf_xu_TRT(&a, fp, H, eta_t, cos_td, sin_td, td, 0);
}

/* int_{x0}^{x1} g(x; mu, l) (f0 + (f1 - f0)(x - x0)/(x1 - x0)) dx with g = exp(-(x-mu)^2/l^2)
 * (Xu appendix E: erf and the Gaussian's antiderivative of x g). */
SL_INLINE float sl_srbf_lin_seg(float x0, float x1, float f0, float f1, float mu, float l) {
    if (!(x1 > x0)) return 0.0f;
    float e0 = sl_srbf_erf_as((x0 - mu) / l), e1 = sl_srbf_erf_as((x1 - mu) / l);
    float gi = 0.5f * SL_SQRT_PI_F * l * (e1 - e0); /* int g */
    float z0 = (x0 - mu) / l, z1 = (x1 - mu) / l;
    float xg = -0.5f * l * l * (exp(-z1 * z1) - exp(-z0 * z0)); /* int (x - mu) g */
    float slope = (f1 - f0) / (x1 - x0);
    return f0 * gi + slope * (xg + (mu - x0) * gi);
}

/* out = I_R, I_TT, I_TRT, I by Xu Sec. 4.2 with m = segments (1..8). */
SL_INLINE void sl_srbf_xu(const sl_fiber_params *fp, SL_GLOBAL const float *C,
                          SL_GLOBAL const float *H, int segments, float theta_o, float phi_o,
                          float theta_j, float phi_j, float lambda, float out[4]) {
    int m = segments < 1 ? 1 : (segments > SL_SRBF_MAX_SEGMENTS ? SL_SRBF_MAX_SEGMENTS : segments);
    float cos_tj = sl_maxf(cos(theta_j), 0.0f);
    float total = 0.0f;
    for (int t = 0; t < 3; t++) {
        /* g(theta_i; theta_j, lambda) M_t = b / (sqrt(pi) beta) g(theta_i; mu3, l3) (appendix B),
         * M_t = g(theta_i; 2 alpha - theta_o, 2 beta) / (sqrt(pi) beta) (Eq. 7). */
        float beta = fp->beta[t], mu_m = 2.0f * fp->alpha[t] - theta_o, w2 = 4.0f * beta * beta;
        float l2 = lambda * lambda;
        float mu = (theta_j * w2 + mu_m * l2) / (w2 + l2);
        float l3 = sqrt(l2 * w2 / (l2 + w2));
        float dm = theta_j - mu_m;
        float b = exp(-dm * dm / (l2 + w2)) / (SL_SQRT_PI_F * beta);
        /* nodes: -pi/2, m - 1 points uniform in [mu - (m-2) l3/2, mu + (m-2) l3/2], pi/2 */
        float xs[SL_SRBF_MAX_SEGMENTS + 1];
        xs[0] = -0.5f * SL_PI_F;
        for (int k = 0; k < m - 1; k++)
            xs[k + 1] = sl_clampf(mu + ((float)k - 0.5f * (float)(m - 2)) * l3, -0.5f * SL_PI_F,
                                  0.5f * SL_PI_F);
        xs[m] = 0.5f * SL_PI_F;
        float acc = 0.0f, fprev = 0.0f;
        for (int k = 0; k <= m; k++) {
            float nv = sl_srbf_xu_node(fp, C, H, theta_o, phi_o, phi_j, cos_tj, lambda, xs[k], t);
            if (k > 0) acc += sl_srbf_lin_seg(xs[k - 1], xs[k], fprev, nv, mu, l3);
            fprev = nv;
        }
        float v = b * acc;
        if (!(v >= 0.0f && v <= SL_FLT_MAX)) v = v > 0.0f ? SL_FLT_MAX : 0.0f;
        out[t] = v;
        total += v;
    }
    out[3] = total;
}

#endif
