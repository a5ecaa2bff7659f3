/* srbf_chiang.h: the fast SRBF response of the Chiang 2016 model (`eval srbf --method fast` with
 * `model: chiang`), float; part of the d'Eon fast path (included by kernels/srbf_deon.h after
 * the helpers it shares: the longitudinal lobes, the W and C lookups, R's Fresnel fit).
 * Derivation and measurements: docs/srbf.md, "Chiang fast path".
 *
 * numerics.md sec. 3 "chiang" has d'Eon's structure: f = sum_{p<=2} M_p(v_p, ti, to - 2 alpha_p)
 * N_p(phi) + M(v_2, ti, to) E_3 / (2 pi), N_p = 1/2 int A_p(h) D_s(phi - Phi(p, h)) dh with D_s
 * the logistic of scale s trimmed to (-pi, pi). Unlike d'Eon's, A_p (Fresnel at cos to cos
 * gamma, eta' and absorption from theta_o) and hence N_p do not depend on theta_i: one
 * evaluation of the nodes' A_p per row serves every theta_i. With G = G_th G_ph (Xu appendix A),
 *   I_p = int cos ti G_th M_p N'_p d ti,  N'_p / z = sum_n k_n(ti) cos(n phi) B_n,
 * k_n = rho_n(kappa) d_n(s) the kernel's harmonics (rho_n = I_n / I_0 of the von Mises G_ph,
 * d_n the detector's), B_n = sum_i A_p(c_i) h_p[n][i] (the 4-node root measure's harmonics,
 * tabulated per 1/eta'). Two branches per theta_i:
 *  - wide (|k_NH| < SL_SRBF_CH_EPS): the harmonic sum itself, n <= SL_SRBF_CH_NH: exact in the
 *    detector (its shape, the trimming) and in the SRBF convolution, up to the truncation;
 *  - narrow (a sharp lobe on a sharp detector, s < ~0.23): the W product quadrature of the d'Eon
 *    path with the logistic as the mixture of two Gaussians (std SL_SRBF_CH_MIX_S1 s and _S2 s,
 *    weights w, 1 - w: 0.3 % of the logistic's peak) folded into the width as d'Eon's detector,
 *    lambda3^2 = lambda'^2 + 2 sigma^2 per component (trimming is negligible there).
 * The wide branch's B_n use 8 nodes in c (SL_SRBF_CH_NODES), the narrow branch the W slices'
 * 4. R, narrow: Xu's C_k expansion of the Fresnel fit and the residual through the 4 nodes, as
 * d'Eon's, plus the residual's interpolation error at phi itself (the kernel -> 0 limit, where
 * 4 nodes are up to 6 % off near backscattering). The rest term's lobe (v_2, theta_o unshifted)
 * has a uniform azimuth: N'_3 / z = E_3 / (2 pi) (E_3 by the 8 nodes). */
#ifndef SL_SRBF_CHIANG_H
#define SL_SRBF_CHIANG_H

/* The logistic of unit scale as w N(0, S1^2) + (1 - w) N(0, S2^2): a sup-norm fit on the real
 * line, max error 0.30 % of the logistic's peak (a single Gaussian of the same variance is 12 %
 * off at the peak). */
#ifndef SL_SRBF_CH_MIX_W /* overridable for the measurements of docs/srbf.md */
#define SL_SRBF_CH_MIX_W 0.4449f
#define SL_SRBF_CH_MIX_S1 1.21797f
#define SL_SRBF_CH_MIX_S2 2.12348f
#endif
/* The wide branch is taken when the last harmonic of the kernel is below this (truncation
 * error ~ its size: the harmonics beyond decay faster). */
#ifndef SL_SRBF_CH_EPS
#define SL_SRBF_CH_EPS 1e-4f
#endif
/* 1: the narrow branch adds R's and TT's kernel -> 0 interpolation errors back (0: d'Eon's
 * narrow rule alone, for the measurements of docs/srbf.md). */
#ifndef SL_SRBF_CH_CORRECT
#define SL_SRBF_CH_CORRECT 1
#endif

#if SL_OPENCL
static __constant float sl_srbf_ch_c[SL_SRBF_CH_NODES] = SL_SRBF_CH_C;
static __constant float sl_srbf_ch_s[SL_SRBF_CH_NODES] = SL_SRBF_CH_S;
#else
static const float sl_srbf_ch_c[SL_SRBF_CH_NODES] = SL_SRBF_CH_C;
static const float sl_srbf_ch_s[SL_SRBF_CH_NODES] = SL_SRBF_CH_S;
#endif

/* Colour channels one evaluation serves (the renderer's rows: r, g, b differ in sigma_a only). */
#define SL_SRBF_CH_MAXC 3

/* What the rows of one shading point share (everything but the azimuth phi and the lobe): the
 * renderer's rows come point by point (theta_o and sigma_a fixed, the lobes varying), so the
 * C batch (cpu/srbf_deon_c.c) builds this once per point and the per-row work keeps only what
 * depends on phi or the lobe. R (A_0 = f) does not depend on sigma_a: one R for all channels. */
typedef struct sl_srbf_chiang_point {
    int nch;
    float eta, co, x, ict, s;
    float sig[SL_SRBF_CH_MAXC]; /* the channels' sigma_a */
    float a[6];                 /* R's Fresnel fit at eta */
    float d[SL_SRBF_CH_NHV];    /* the detector's harmonics d_n(s) */
    float AR[SL_SRBF_W_NODES];  /* R, narrow: F - P at the 4 nodes */
    float poly[6];              /* R, narrow: a_j cos^j theta_o / 4, the fit's terms in C_k */
    float bR[SL_SRBF_CH_NHV];   /* R, wide: B_n */
    float A[SL_SRBF_CH_MAXC][2][SL_SRBF_W_NODES]; /* TT, TRT, narrow: A_p at the 4 nodes */
    float b[SL_SRBF_CH_MAXC][2][SL_SRBF_CH_NHV];  /* TT, TRT, wide: B_n */
    float rest[SL_SRBF_CH_MAXC];                  /* N'_3 / z = E_3 / (2 pi) */
    float emax[3]; /* per group the largest energy over the channels, E_p / (2 pi) (R: 1 / 2pi) */
    float restmax; /* the largest rest[ch] */
    float dmax;    /* the trimmed logistic's peak 1 / (4 s tanh(pi / 2s)) */
    sl_srbf_deon_lobe_pre lobe[4]; /* R, TT, TRT, the rest term (TRT's variance, to unshifted) */
} sl_srbf_chiang_point;

/* What one row adds: the terms that depend on phi. */
typedef struct sl_srbf_chiang_row {
    float phi;
    float d_nh;               /* the detector's last harmonic d_NH(s) */
    float r_err;              /* R, narrow: the residual's interpolation error at phi */
    float cR[SL_SRBF_CH_NHV]; /* R, wide: cos(n phi) d_n B_n */
    float c[SL_SRBF_CH_MAXC][2][SL_SRBF_CH_NHV]; /* TT, TRT, wide: cos(n phi) d_n B_n */
    float tt_err[SL_SRBF_CH_MAXC]; /* TT, narrow: the 4 nodes' interpolation error at phi */
} sl_srbf_chiang_row;

/* d_n(s), n = 0..SL_SRBF_CH_NH, from the table (linear in log s); below its range the
 * untrimmed logistic's x / sinh x, x = pi s n (the trimming is e^(-pi/s) < 1e-270 there). */
SL_INLINE void sl_srbf_chiang_detector(SL_GLOBAL const float *D, float s, float d[SL_SRBF_CH_NHV]) {
    if (s < SL_SRBF_CH_SMIN) {
        for (int n = 0; n < SL_SRBF_CH_NHV; n++) {
            float x = SL_PI_F * s * (float)n, x2 = x * x;
            d[n] = 1.0f - x2 * (1.0f / 6.0f) + x2 * x2 * (7.0f / 360.0f); /* x <= 0.26 */
        }
        return;
    }
    int is;
    float fs = sl_srbf_grid(log(s), log(SL_SRBF_CH_SMIN), log(SL_SRBF_CH_SMAX), SL_SRBF_CH_NS, &is);
    SL_GLOBAL const float *b = D + SL_SRBF_CH_DET_OFF + is * SL_SRBF_CH_NHV;
    for (int n = 0; n < SL_SRBF_CH_NHV; n++)
        d[n] = b[n] + (b[n + SL_SRBF_CH_NHV] - b[n]) * fs;
}

/* Lanes of the von Mises harmonics evaluated side by side: 4 per lobe group R, TT, TRT (its 3
 * Gauss points and a pad). */
#define SL_SRBF_CH_VL 12

/* rho[n][l] = I_n(k) / I_0(k), n = 0..SL_SRBF_CH_NH, for SL_SRBF_CH_VL concentrations k[l] at
 * once (the Gauss points of every lobe group of a row): the ratios r_n = I_n / I_(n-1) by the
 * stable downward recurrence r_n = 1 / (2n/k + r_(n+1)), started 8 orders above NH from the mean of
 * Amos's bounds k / (n - 1/2 + sqrt((n -+ 1/2)^2 + k^2)): where the recurrence does not damp the
 * start's error (large k), the bounds' gap (~n / k^2 relative) is below float resolution, and
 * where they are loose (moderate k) the 8 extra steps damp it by prod r_n^2 < 1e-4. The
 * recurrence is a chain of 24 dependent divisions, once the costliest part of a chiang row: the
 * lanes run side by side (branch-free, lane loops innermost, which GCC turns into 3 independent
 * SSE divisions per step), each lane with exactly the operations of one k alone; k <= 1e-30
 * gives rho_n = 0. */
SL_INLINE void sl_srbf_chiang_vmx(const float k[SL_SRBF_CH_VL],
                                  float rho[SL_SRBF_CH_NHV][SL_SRBF_CH_VL]) {
    const int top = SL_SRBF_CH_NH + 8;
    const float nu = (float)top + 1.0f;
    float kk[SL_SRBF_CH_VL], r[SL_SRBF_CH_VL], rr[SL_SRBF_CH_NHV][SL_SRBF_CH_VL];
    for (int l = 0; l < SL_SRBF_CH_VL; l++) {
        kk[l] = k[l] > 1e-30f ? k[l] : 1.0f;
        r[l] = 0.5f * (kk[l] / (nu - 0.5f + sqrt((nu + 0.5f) * (nu + 0.5f) + kk[l] * kk[l])) +
                       kk[l] / (nu - 0.5f + sqrt((nu - 0.5f) * (nu - 0.5f) + kk[l] * kk[l])));
    }
    for (int n = top; n > SL_SRBF_CH_NH; n--)
        for (int l = 0; l < SL_SRBF_CH_VL; l++)
            r[l] = 1.0f / (2.0f * (float)n / kk[l] + r[l]);
    for (int n = SL_SRBF_CH_NH; n >= 1; n--)
        for (int l = 0; l < SL_SRBF_CH_VL; l++)
            rr[n][l] = r[l] = 1.0f / (2.0f * (float)n / kk[l] + r[l]);
    float on[SL_SRBF_CH_VL], q[SL_SRBF_CH_VL];
    for (int l = 0; l < SL_SRBF_CH_VL; l++) {
        on[l] = k[l] > 1e-30f ? 1.0f : 0.0f;
        q[l] = 1.0f;
        rho[0][l] = 1.0f;
    }
    for (int n = 1; n < SL_SRBF_CH_NHV; n++)
        for (int l = 0; l < SL_SRBF_CH_VL; l++) {
            q[l] *= rr[n][l];
            rho[n][l] = on[l] * q[l];
        }
}

/* The same for one k. */
SL_INLINE void sl_srbf_chiang_vm(float k, float rho[SL_SRBF_CH_NHV]) {
    float kv[SL_SRBF_CH_VL], r4[SL_SRBF_CH_NHV][SL_SRBF_CH_VL];
    for (int l = 0; l < SL_SRBF_CH_VL; l++)
        kv[l] = k;
    sl_srbf_chiang_vmx(kv, r4);
    for (int n = 0; n < SL_SRBF_CH_NHV; n++)
        rho[n] = r4[n][0];
}

/* cos gamma_t = sqrt(1 - (h x)^2) at a node of sin gamma sn (sin gamma_t = h / eta'). */
SL_INLINE float sl_srbf_chiang_cgt(float sn, float x) {
    float sg = sn * x;
    return sqrt(sl_maxf(1.0f - sg * sg, 0.0f));
}

/* The point's constants: A_p at the nodes (pbrt-v4 / numerics.md: Fresnel at cos theta_o c,
 * eta' = sqrt(eta^2 - sin^2 to) / cos to, T = exp(-2 sigma_a cos gamma_t / cos theta_t)), the
 * rest term's energy, and per group the wide branch's B_n; for nch channels of absorption
 * sig[ch] (NULL: fp->sigma_a). */
SL_INLINE void sl_srbf_chiang_point_init(const sl_fiber_params *fp, SL_GLOBAL const float *D,
                                         float theta_o, int nch, const float *sig,
                                         sl_srbf_chiang_point *r) {
    float eta = fp->eta, so = sin(theta_o), co = sl_maxf(cos(theta_o), 0.0f);
    /* x = 1/eta' = cos to / sqrt(eta^2 - sin^2 to): 0 at grazing, no division by cos to */
    float x = sl_minf(co / sqrt(sl_maxf(eta * eta - so * so, 1e-30f)), 1.0f);
    float st = so / eta, ict = 2.0f / sqrt(sl_maxf(1.0f - st * st, 1e-30f)); /* 2 / cos t */
    sl_srbf_deon_fit(D, eta, r->a);
    const float *a = r->a;
    r->nch = nch;
    r->eta = eta;
    r->co = co;
    r->x = x;
    r->ict = ict;
    r->s = fp->logistic_s;
    for (int ch = 0; ch < nch; ch++)
        r->sig[ch] = sig ? sig[ch] : fp->sigma_a;
    /* the narrow branch's 4 nodes (the W slices') */
    for (int i = 0; i < SL_SRBF_W_NODES; i++) {
        float ci = co * sl_srbf_w_c[i], F = sl_fresnel_exact(eta, ci);
        float P = a[0] + ci * (a[1] + ci * (a[2] + ci * (a[3] + ci * (a[4] + ci * a[5]))));
        float cg = sl_srbf_chiang_cgt(sl_srbf_w_s[i], x);
        r->AR[i] = F - P;
        for (int ch = 0; ch < nch; ch++) {
            float T = exp(-r->sig[ch] * ict * cg);
            float A1 = (1.0f - F) * (1.0f - F) * T;
            r->A[ch][0][i] = A1;
            r->A[ch][1][i] = A1 * T * F;
        }
    }
    float xp = 0.25f;
    for (int j = 0; j < 6; j++) {
        r->poly[j] = a[j] * xp;
        xp *= co;
    }
    /* the wide branch's 8 nodes; the rest term's energy sum_{p >= 3} A_p = A_2 T f / (1 - T f)
     * by them (h_R[0][i] = the nodes' uniform-azimuth weights omega_i / (2 pi)) */
    float F8[SL_SRBF_CH_NODES], A8[SL_SRBF_CH_MAXC][2][SL_SRBF_CH_NODES];
    float e8[SL_SRBF_CH_MAXC][2];
    for (int ch = 0; ch < nch; ch++)
        r->rest[ch] = e8[ch][0] = e8[ch][1] = 0.0f;
    for (int i = 0; i < SL_SRBF_CH_NODES; i++) {
        float F = sl_fresnel_exact(eta, co * sl_srbf_ch_c[i]);
        float cg = sl_srbf_chiang_cgt(sl_srbf_ch_s[i], x);
        F8[i] = F;
        for (int ch = 0; ch < nch; ch++) {
            float T = exp(-r->sig[ch] * ict * cg);
            float A1 = (1.0f - F) * (1.0f - F) * T, A2 = A1 * T * F, den = 1.0f - T * F;
            A8[ch][0][i] = A1;
            A8[ch][1][i] = A2;
            e8[ch][0] += A1 * D[SL_SRBF_CH_R_OFF + i];
            e8[ch][1] += A2 * D[SL_SRBF_CH_R_OFF + i];
            if (den > 0.0f) r->rest[ch] += A2 * T * F / den * D[SL_SRBF_CH_R_OFF + i];
        }
    }
    r->emax[0] = 1.0f / (2.0f * SL_PI_F);
    r->emax[1] = r->emax[2] = 0.0f;
    for (int ch = 0; ch < nch; ch++)
        for (int g = 0; g < 2; g++)
            r->emax[g + 1] = sl_maxf(r->emax[g + 1], e8[ch][g]);
    r->restmax = 0.0f;
    for (int ch = 0; ch < nch; ch++)
        r->restmax = sl_maxf(r->restmax, r->rest[ch]);
    float s = sl_maxf(fp->logistic_s, 1e-30f);
    r->dmax = 0.25f / (s * tanh(0.5f * SL_PI_F / s));
    sl_srbf_chiang_detector(D, r->s, r->d);
    for (int g = 0; g < 4; g++) {
        int lobe = g < 3 ? g : 2;
        float v = fp->beta[lobe] * fp->beta[lobe];
        sl_srbf_deon_lobe_pre_init(v, g < 3 ? theta_o - 2.0f * fp->alpha[g] : theta_o, &r->lobe[g]);
    }
    int ix;
    float fx = sl_srbf_grid(x, 0.0f, 1.0f, SL_SRBF_CH_NX, &ix);
    for (int n = 0; n < SL_SRBF_CH_NHV; n++) {
        SL_GLOBAL const float *hr = D + SL_SRBF_CH_R_OFF + n * SL_SRBF_CH_NODES;
        float b0 = 0.0f;
        for (int i = 0; i < SL_SRBF_CH_NODES; i++)
            b0 += F8[i] * hr[i];
        r->bR[n] = b0;
        for (int g = 0; g < 2; g++) {
            SL_GLOBAL const float *h0 = D + SL_SRBF_CH_OFF + g * SL_SRBF_CH_SLICE +
                                        (ix * SL_SRBF_CH_NHV + n) * SL_SRBF_CH_NODES;
            SL_GLOBAL const float *h1 = h0 + SL_SRBF_CH_NHV * SL_SRBF_CH_NODES;
            float h[SL_SRBF_CH_NODES];
            for (int i = 0; i < SL_SRBF_CH_NODES; i++)
                h[i] = h0[i] + (h1[i] - h0[i]) * fx;
            for (int ch = 0; ch < nch; ch++) {
                float b = 0.0f;
                for (int i = 0; i < SL_SRBF_CH_NODES; i++)
                    b += A8[ch][g][i] * h[i];
                r->b[ch][g][n] = b;
            }
        }
    }
}

/* The row's terms at azimuth phi: R's narrow-branch correction, TT's, and the wide branch's
 * cos(n phi) d_n B_n. */
SL_INLINE void sl_srbf_chiang_row_init(const sl_srbf_chiang_point *pt, float phi,
                                       sl_srbf_chiang_row *r) {
    const float *a = pt->a;
    float eta = pt->eta, co = pt->co, x = pt->x, ict = pt->ict;
    int nch = pt->nch;
    r->phi = phi;
    r->d_nh = pt->d[SL_SRBF_CH_NH];
    /* R at phi in the kernel -> 0 limit: N_0 = 1/4 c F(cos to c), c = |cos(phi/2)|, where the
     * narrow branch has 1/4 c (P + sum_i L_i(c) (F - P)_i): its error, added back there */
    {
        float c = fabs(cos(0.5f * phi)), ci = co * c;
        float P = a[0] + ci * (a[1] + ci * (a[2] + ci * (a[3] + ci * (a[4] + ci * a[5]))));
        float li = 0.0f;
        for (int i = 0; i < SL_SRBF_W_NODES; i++) {
            float L = 1.0f;
            for (int j = 0; j < SL_SRBF_W_NODES; j++)
                if (j != i) L *= (c - sl_srbf_w_c[j]) / (sl_srbf_w_c[i] - sl_srbf_w_c[j]);
            li += L * pt->AR[i];
        }
        r->r_err = 0.25f * c * (sl_fresnel_exact(eta, ci) - P - li);
    }
    /* TT at phi in the kernel -> 0 limit: Phi(1, h) = pi + 2 asin(x sin g) - 2 g falls
     * monotonically in g = asin h (x < 1), so phi has at most one root; there N_1 = A_1 cos g /
     * (2 |dPhi/dg|), where the narrow branch has the 4 nodes' interpolant of A_1 in place of A_1:
     * its error, added back there (the 4 nodes cannot follow (1 - f)^2 near the band's grazing
     * edge: up to 16 % of I_1 on the stiffest rows) */
    for (int ch = 0; ch < nch; ch++)
        r->tt_err[ch] = 0.0f;
    {
        float t = phi >= 0.0f ? phi : phi + 2.0f * SL_PI_F, lo = 2.0f * asin(x);
        if (t > lo && t < 2.0f * SL_PI_F - lo && x < 0.999f) {
            float g = 0.5f * (SL_PI_F - t), fd = -2.0f; /* the root at x = 0 */
            for (int it = 0; it < 6; it++) {
                float sg = sin(g), cg = cos(g), xs = x * sg;
                float f = SL_PI_F + 2.0f * asin(xs) - 2.0f * g - t;
                fd = 2.0f * x * cg / sqrt(sl_maxf(1.0f - xs * xs, 1e-12f)) - 2.0f;
                g = sl_clampf(g - f / fd, -0.5f * SL_PI_F, 0.5f * SL_PI_F);
            }
            float c = cos(g), sn = fabs(sin(g)), F = sl_fresnel_exact(eta, co * c);
            float L[SL_SRBF_W_NODES];
            for (int i = 0; i < SL_SRBF_W_NODES; i++) {
                L[i] = 1.0f;
                for (int j = 0; j < SL_SRBF_W_NODES; j++)
                    if (j != i) L[i] *= (c - sl_srbf_w_c[j]) / (sl_srbf_w_c[i] - sl_srbf_w_c[j]);
            }
            float cgt = sl_srbf_chiang_cgt(sn, x), wt = c / (2.0f * fabs(fd));
            for (int ch = 0; ch < nch; ch++) {
                float T = exp(-pt->sig[ch] * ict * cgt), li = 0.0f;
                for (int i = 0; i < SL_SRBF_W_NODES; i++)
                    li += L[i] * pt->A[ch][0][i];
                r->tt_err[ch] = wt * ((1.0f - F) * (1.0f - F) * T - li);
            }
        }
    }
    float c1 = cos(phi), cm = 1.0f, cn = c1; /* cos(n phi) by the Chebyshev recurrence */
    for (int n = 0; n < SL_SRBF_CH_NHV; n++) {
        float cosn = n == 0 ? 1.0f : cn;
        if (n > 0) {
            float nx = 2.0f * c1 * cn - cm;
            cm = cn;
            cn = nx;
        }
        float w = cosn * pt->d[n];
        r->cR[n] = w * pt->bR[n];
        for (int g = 0; g < 2; g++)
            for (int ch = 0; ch < nch; ch++)
                r->c[ch][g][n] = w * pt->b[ch][g][n];
    }
}

/* N'_g / z of group g (0 R, 1 TT, 2 TRT), narrow branch, at the von Mises concentration kappa of
 * G_ph (one theta_i), added to v[0..nc-1] (R: v[0] only, the same for every channel). */
SL_INLINE void sl_srbf_chiang_az_narrow(const sl_srbf_chiang_point *pt, const sl_srbf_chiang_row *r,
                                        SL_GLOBAL const float *C, SL_GLOBAL const float *H, int g,
                                        float kappa, float *v) {
    int nc = g == 0 ? 1 : pt->nch;
    /* narrow: the logistic as two Gaussians, each folded into the width */
    float l2 = kappa > 1e-30f ? 2.0f / kappa : 1e30f, s = pt->s;
    for (int k = 0; k < 2; k++) {
        float sk = (k ? SL_SRBF_CH_MIX_S2 : SL_SRBF_CH_MIX_S1) * s;
        float wk = k ? 1.0f - SL_SRBF_CH_MIX_W : SL_SRBF_CH_MIX_W;
        float lam3 = sqrt(sl_minf(l2 + 2.0f * sk * sk, 1e30f)), t = sl_srbf_deon_wide(lam3);
        float W[SL_SRBF_W_NODES];
        sl_srbf_W(H, g == 0 ? 2 : g - 1, pt->x, lam3, r->phi, W);
        for (int i = 0; i < SL_SRBF_W_NODES; i++) /* beyond the tables: see deon_wide */
            W[i] = sl_srbf_deon_u[i] + t * (W[i] - sl_srbf_deon_u[i]);
        if (g == 0) {
            /* R: Xu's C_k of the Fresnel fit, the residual through the 4 nodes */
            float Cn[7], q = 0.0f;
            sl_srbf_C(C, lam3, r->phi, Cn);
            for (int j = 0; j < 6; j++)
                q += pt->poly[j] *
                     (sl_srbf_deon_cu[j + 1] + t * (Cn[j + 1] - sl_srbf_deon_cu[j + 1]));
            for (int i = 0; i < SL_SRBF_W_NODES; i++)
                q += pt->AR[i] * W[i];
            v[0] += wk * q;
            continue;
        }
        for (int ch = 0; ch < nc; ch++) {
            float q = 0.0f;
            for (int i = 0; i < SL_SRBF_W_NODES; i++)
                q += pt->A[ch][g - 1][i] * W[i];
            v[ch] += wk * q;
        }
    }
    if (g == 0 && SL_SRBF_CH_CORRECT) v[0] += r->r_err;
    if (g == 1 && SL_SRBF_CH_CORRECT)
        for (int ch = 0; ch < nc; ch++)
            v[ch] += r->tt_err[ch];
}

/* N'_g / z of group g at the 3 Gauss points of a lobe interval (kappa[4 g + j], j < 3; rho: their
 * harmonics, sl_srbf_chiang_vmx), into fz[ch][j][0] (R: the same for every channel). The wide
 * branch's harmonic sums run for the group's 4 lanes side by side (each lane's sum in the order
 * of n, as one point alone); a point where the kernel's last harmonic is not negligible takes
 * the narrow branch instead. */
SL_INLINE void sl_srbf_chiang_az3(const sl_srbf_chiang_point *pt, const sl_srbf_chiang_row *r,
                                  SL_GLOBAL const float *C, SL_GLOBAL const float *H, int g,
                                  const float kappa[SL_SRBF_CH_VL],
                                  const float rho[SL_SRBF_CH_NHV][SL_SRBF_CH_VL],
                                  float fz[SL_SRBF_CH_MAXC][3][SL_DEON_MAX_ORDERS + 1]) {
    int nc = g == 0 ? 1 : pt->nch, nch = pt->nch, o = 4 * g;
    float wv[SL_SRBF_CH_MAXC][4];
    for (int ch = 0; ch < nc; ch++) {
        const float *cf = g == 0 ? r->cR : r->c[ch][g - 1];
        float acc[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        for (int n = 0; n < SL_SRBF_CH_NHV; n++)
            for (int l = 0; l < 4; l++)
                acc[l] += rho[n][o + l] * cf[n];
        for (int l = 0; l < 4; l++)
            wv[ch][l] = acc[l];
    }
    for (int j = 0; j < 3; j++) {
        float v[SL_SRBF_CH_MAXC];
        if (fabs(rho[SL_SRBF_CH_NH][o + j] * r->d_nh) <
            SL_SRBF_CH_EPS) { /* |k_NH| = rho_NH |d_NH| */
            for (int ch = 0; ch < nc; ch++)
                v[ch] = wv[ch][j];
        } else {
            for (int ch = 0; ch < nc; ch++)
                v[ch] = 0.0f;
            sl_srbf_chiang_az_narrow(pt, r, C, H, g, kappa[o + j], v);
        }
        for (int ch = 0; ch < nch; ch++)
            fz[ch][j][0] = sl_maxf(v[g == 0 ? 0 : ch], 0.0f);
    }
}

/* The response to one SRBF lobe at the point pt (sl_srbf_chiang_point_init of the row's theta_o,
 * absorption and material): out[5 ch + k], ch < pt->nch, k = 0..4: I_0, I_1, I_2, I_rest, I (the
 * d'Eon layout with orders 2). */
SL_INLINE void sl_srbf_chiang_rgb_at(SL_GLOBAL const float *C, SL_GLOBAL const float *H,
                                     const sl_srbf_chiang_point *pt, float phi_o, float theta_j,
                                     float phi_j, float lambda, float *out) {
    int nch = pt->nch;
    float cos_tj = sl_maxf(cos(theta_j), 0.0f), sin_tj = sin(theta_j);
    float inv_l2 = 1.0f / (lambda * lambda);
    float floor_ = sl_srbf_deon_floor(lambda, inv_l2);
    sl_srbf_chiang_row r;
    sl_srbf_chiang_row_init(pt, sl_wrap_pi(phi_o - phi_j), &r);
    for (int k = 0; k < 5 * nch; k++)
        out[k] = 0.0f;
    /* the trimmed logistic's peak pt->dmax bounds every N_p / E_p */
    float dmax = pt->dmax, rest = pt->restmax;
    /* first every group's longitudinal lobe and Gauss points, then their harmonics together */
    sl_srbf_deon_lobe L[3];
    int act[3] = {0, 0, 0};
    float kappa[SL_SRBF_CH_VL];
    for (int l = 0; l < SL_SRBF_CH_VL; l++)
        kappa[l] = 0.0f;
    for (int g = 0; g < 4; g++) {
        /* A group whose contribution cannot reach 1e-4 of the error floor 0.03 int G of
         * numerics.md sec. 5 is skipped: N'_p / z <= max N_p <= E_p dmax (R: <= 1/4), and the
         * longitudinal weights sum to <= 2 pi int cos ti G_th M_p <= 2 pi (M_p is normalised,
         * G_th <= 1); dark hair skips TT, TRT and the rest term before any lobe work */
        float bound = g == 0 ? 0.25f : (g < 3 ? 2.0f * SL_PI_F * pt->emax[g] * dmax : rest);
        if (!(4.0f * SL_PI_F * bound > 1e-4f * floor_)) continue;
        if (g == 3) { /* the rest term (TRT's variance, theta_o unshifted): uniform azimuth */
            sl_srbf_deon_lobe Lr;
            if (!sl_srbf_deon_lobe_init_pre(&pt->lobe[g], theta_j, cos_tj, sin_tj, inv_l2, &Lr))
                continue;
            for (int ch = 0; ch < nch; ch++) /* exact at every node */
                out[5 * ch + 3] += Lr.wsum * pt->rest[ch];
            continue;
        }
        if (!sl_srbf_deon_lobe_init_pre(&pt->lobe[g], theta_j, cos_tj, sin_tj, inv_l2, &L[g]))
            continue;
        if (!(L[g].wsum * bound > 1e-4f * floor_)) continue; /* the same, the actual weights */
        act[g] = 1;
        for (int j = 0; j < 3; j++)
            kappa[4 * g + j] = 2.0f * cos(sl_srbf_deon_lobe_ti(&L[g], j)) * cos_tj * inv_l2;
        kappa[4 * g + 3] = kappa[4 * g + 2];
    }
    if (act[0] || act[1] || act[2]) {
        float rho[SL_SRBF_CH_NHV][SL_SRBF_CH_VL];
        sl_srbf_chiang_vmx(kappa, rho);
        for (int g = 0; g < 3; g++) {
            if (!act[g]) continue;
            float fz[SL_SRBF_CH_MAXC][3][SL_DEON_MAX_ORDERS + 1];
            sl_srbf_chiang_az3(pt, &r, C, H, g, kappa, rho, fz);
            for (int ch = 0; ch < nch; ch++)
                sl_srbf_deon_lobe_add(&L[g], fz[ch], 1, out + 5 * ch + g);
        }
    }
    for (int ch = 0; ch < nch; ch++)
        sl_srbf_deon_total(2, out + 5 * ch);
}

/* The response to one SRBF lobe for nch (1..3) channels of absorption sig[ch] (NULL:
 * fp->sigma_a): out[5 ch + k] as sl_srbf_chiang_rgb_at. Everything but the absorption is
 * computed once for all channels. */
SL_INLINE void sl_srbf_chiang_rgb(const sl_fiber_params *fp, SL_GLOBAL const float *C,
                                  SL_GLOBAL const float *H, SL_GLOBAL const float *D, float theta_o,
                                  float phi_o, float theta_j, float phi_j, float lambda, int nch,
                                  const float *sig, float *out) {
    sl_srbf_chiang_point pt;
    sl_srbf_chiang_point_init(fp, D, theta_o, nch, sig, &pt);
    sl_srbf_chiang_rgb_at(C, H, &pt, phi_o, theta_j, phi_j, lambda, out);
}

/* One channel (fp->sigma_a): out[0..4] = I_0, I_1, I_2, I_rest, I. */
SL_INLINE void sl_srbf_chiang(const sl_fiber_params *fp, SL_GLOBAL const float *C,
                              SL_GLOBAL const float *H, SL_GLOBAL const float *D, float theta_o,
                              float phi_o, float theta_j, float phi_j, float lambda, float *out) {
    sl_srbf_chiang_rgb(fp, C, H, D, theta_o, phi_o, theta_j, phi_j, lambda, 1, (const float *)0,
                       out);
}

#endif
