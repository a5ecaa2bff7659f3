/* srbf_ren_lookup.h: lookup in the precomputed SRBF response table of Ren et al. 2010 Sec. 4 (the
 * `table` fast path, docs/srbf_ren.md), float, shared by the C twin (cpu/srbf_ren_c.c) and the
 * OpenCL kernel (kernels/srbf_ren.cl) so both agree to float rounding.
 *
 * For one fixed material the response I_t(omega_o; omega_j, lambda) of numerics.md sec. 4 is
 * baked (host/passes/shade/srbf_ren.c, from the `fast` closed form) over four axes in the fiber
 * frame:
 *  - h = (theta_o + theta_j) / 2, warped per mode and lambda slice around alpha_t: the
 *    response is a lobe centred on h = alpha_t of width w = sqrt(beta_t^2 + lambda^2 / 4)
 *    (M_t(theta_h) convolved with the SRBF, Xu 2011 Eq. 11), so the nodes crowd there:
 *    y = (h - alpha_t) / w, s = y / (1 + |y| / K), s uniform;
 *  - t = d / (pi/2 - |h|), d = (theta_j - theta_o) / 2, in [-1, 1]: maps the diamond
 *    |h| + |d| <= pi/2 of valid (theta_o, theta_j) onto a rectangle (no node is wasted); warped
 *    (sl_srbf_ren_twarp) so the nodes crowd towards the poles at t = +-1;
 *  - dphi = |wrap(phi_j - phi_o)| in [0, pi]: a round fiber's response depends on the azimuths
 *    only through their difference (Ren Eq. 8; N_t depends on phi_o - phi_i and the SRBF on
 *    phi_i - phi_j) and is even in it (N_t is even), which halves the table;
 *  - log lambda, uniform, storing I / int G (int G = pi lambda^2 (1 - e^(-4/lambda^2))): the
 *    normalised response tends to f(omega_j, omega_o) for small lambda and to the albedo / 4 pi
 *    for wide lobes, smooth over the decades where I itself spans six. lambda outside the
 *    table range is clamped in the normalised value (then multiplied by the exact int G).
 * Layout: the h-warp constants (4 floats per mode and lambda node), then the blocks R (1 channel:
 * A_R = F has no sigma_a), TT and TRT (rgb and a zero pad, so the blend of 4 floats vectorises),
 * each [lambda][dphi][t][h][channel]. Quadrilinear interpolation, no branch on the data. */
#ifndef SL_SRBF_REN_LOOKUP_H
#define SL_SRBF_REN_LOOKUP_H

#include "sl_compat.h"

/* K of the h warp (s in (-K, K)): node spacing grows as (1 + |y|/K)^2 away from the lobe. */
#define SL_SRBF_REN_K 6.0f

/* Geometry of one table; 4-byte scalars only (passed by value to the kernel). */
typedef struct sl_srbf_ren_dims {
    sl_int n_h, n_t, n_p, n_l; /* nodes per axis (each >= 2) */
    sl_int off[3];             /* float offset of the R, TT, TRT blocks */
    sl_int nc[3];              /* floats per node of each block: 1, 4, 4 (rgb + pad) */
    float alpha[3];            /* h warp centre per mode (alpha_t) */
    float beta2[3];            /* beta_t^2: the warp's width is sqrt(beta_t^2 + lambda^2 / 4) */
    float lmin, lmax;          /* lambda range of the table */
    float log_lmin, l_scale;   /* fl = (log lambda - log_lmin) * l_scale */
    float t_scale, p_scale;    /* (n_t - 1) / 2, (n_p - 1) / pi */
    sl_int r_log;              /* 1: the R block holds ln(value + r_eps), interpolated so */
    float r_eps;
} sl_srbf_ren_dims;

/* min / max as selects (C's fminf/fmaxf are library calls at -O2; NaN handling is not needed
 * here: sl_srbf_ren_cell catches NaN) */
SL_INLINE float sl_srbf_ren_min(float a, float b) {
    return a < b ? a : b;
}
SL_INLINE float sl_srbf_ren_max(float a, float b) {
    return a > b ? a : b;
}

/* The warp s(y) of the h axis (y = (h - alpha_t) / beta_t). */
SL_INLINE float sl_srbf_ren_warp(float y) {
    return y / (1.0f + fabs(y) * (1.0f / SL_SRBF_REN_K));
}

/* The warp u(t) of the t axis, u uniform: 1 - |t| = (1 - |u|)^2. At t = +1 the lobe sits at the
 * pole (theta_j = pi/2), at t = -1 the view (theta_o = pi/2), and the response varies with
 * sqrt(cos theta) there (the azimuthal blur lambda' = lambda / sqrt(cos theta_i cos theta_j)),
 * i.e. with sqrt(1 - |t|): linear in u. */
SL_INLINE float sl_srbf_ren_twarp(float t) {
    return copysign(1.0f - sqrt(sl_srbf_ren_max(1.0f - fabs(t), 0.0f)), t);
}

/* Integer cell and fraction of a coordinate f clamped to [0, n - 1] (NaN -> 0, so a bad input
 * never indexes outside the table). */
SL_INLINE int sl_srbf_ren_cell(float f, int n, float *frac) {
    f = f >= 0.0f ? f : 0.0f;
    int i = (int)f;
    i = i > n - 2 ? n - 2 : i;
    *frac = f - (float)i;
    return i;
}

/* Bit casts for the polynomial log and exp below (identical float operations in C and OpenCL, so
 * both twins compute the same coordinates; libm's logf/expf were a third of the lookup's time). */
#if SL_OPENCL
SL_INLINE sl_uint sl_srbf_ren_bits(float x) {
    return as_uint(x);
}
SL_INLINE float sl_srbf_ren_float(sl_uint u) {
    return as_float(u);
}
#else
SL_INLINE sl_uint sl_srbf_ren_bits(float x) {
    union {
        float f;
        sl_uint u;
    } v;
    v.f = x;
    return v.u;
}
SL_INLINE float sl_srbf_ren_float(sl_uint u) {
    union {
        float f;
        sl_uint u;
    } v;
    v.u = u;
    return v.f;
}
#endif

/* ln x for normal x > 0: x = m 2^e with m in [sqrt(1/2), sqrt(2)), ln m = 2 atanh(s),
 * s = (m - 1) / (m + 1), |s| <= 0.172, series to s^9 (truncation < 2e-9): float accuracy. */
SL_INLINE float sl_srbf_ren_log(float x) {
    sl_uint u = sl_srbf_ren_bits(x);
    int e = (int)((u >> 23) & 255u) - 127;
    float m = sl_srbf_ren_float((u & 0x007fffffu) | 0x3f800000u); /* [1, 2) */
    int big = m > 1.41421356f;
    m = big ? 0.5f * m : m;
    e += big;
    float s = (m - 1.0f) / (m + 1.0f), s2 = s * s;
    float p = 2.0f * s *
              (1.0f + s2 * (1.0f / 3.0f + s2 * (1.0f / 5.0f + s2 * (1.0f / 7.0f + s2 / 9.0f))));
    return p + (float)e * 0.693147180559945f;
}

/* e^x for x <= 88 (0 below -87; named for its first use, int G's exp(-4 / lambda^2)):
 * 2^(x log2 e) = 2^n 2^f, f in [0, 1), 2^f by its degree-6 Taylor polynomial in f ln 2
 * (relative error < 2e-7). */
SL_INLINE float sl_srbf_ren_exp_neg(float x) {
    float y = sl_srbf_ren_max(x, -87.0f) * 1.44269504088896f;
    float fy = (float)(int)y; /* y <= 0: truncation rounds up */
    fy = fy > y ? fy - 1.0f : fy;
    float f = (y - fy) * 0.693147180559945f;
    float q = 1.0f + f * (1.0f + f * (0.5f + f * (1.0f / 6.0f +
                                                  f * (1.0f / 24.0f + f * (1.0f / 120.0f +
                                                                           f * (1.0f / 720.0f))))));
    float r = q * sl_srbf_ren_float((sl_uint)((int)fy + 127) << 23);
    return x < -87.0f ? 0.0f : r;
}

/* Blend of one block at the 16 corners: 1 channel (R) and 3 channels (TT, TRT). */
SL_INLINE float sl_srbf_ren_blend1(SL_GLOBAL const float *B, const int o8[8], const float w8[8],
                                   const int ih[2], const float wh[2]) {
    float a = 0.0f;
    for (int c = 0; c < 8; c++) {
        int o = o8[c] + ih[c >> 2];
        a += w8[c] * (B[o] + wh[c >> 2] * (B[o + 1] - B[o]));
    }
    return a;
}
SL_INLINE void sl_srbf_ren_blend3(SL_GLOBAL const float *B, const int o8[8], const float w8[8],
                                  const int ih[2], const float wh[2], float norm, float *out) {
    /* 4 floats per node (rgb + a zero pad): the four accumulators vectorise */
    float a[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    for (int c = 0; c < 8; c++) {
        SL_GLOBAL const float *q = B + 4 * (o8[c] + ih[c >> 2]);
        float w = wh[c >> 2];
        for (int k = 0; k < 4; k++)
            a[k] += w8[c] * (q[k] + w * (q[k + 4] - q[k]));
    }
    out[0] = a[0] * norm;
    out[1] = a[1] * norm;
    out[2] = a[2] * norm;
}

/* Cell of mode m's warped h axis in lambda slice il at s = warp(y), y = (h - alpha_t) / w. The
 * warp's width follows the lobe, w = sqrt(beta_t^2 + lambda^2 / 4), so the lobe has the same shape
 * in y in every slice; the lookup reads both lambda slices at the y of the query's own w (not at
 * its h), so the lambda interpolation blends like with like (a displacement interpolation: the
 * tails of a lobe that widens with lambda move, they do not fade in and out). Near |h| = pi/2
 * the same y is a different geometry (the (theta_o, theta_j) diamond is narrow there), so within
 * 2 widths of it the reading point slides linearly (weight g) to the query's h itself (plain
 * interpolation), reached 1 width from it; dh = h - alpha_t. The constants lead the table: T[4 (m
 * n_l + il) + 0, 1, 2] = 1 / w_il, s(-pi/2), (n_h - 1) / (s(pi/2) - s(-pi/2)). */
SL_INLINE int sl_srbf_ren_hcell(SL_GLOBAL const float *T, const sl_srbf_ren_dims *d, int m, int il,
                                float y, float dh, float g, float *wh) {
    SL_GLOBAL const float *q = T + 4 * (m * d->n_l + il);
    float s = sl_srbf_ren_warp(y + g * (dh * q[0] - y));
    float fh = sl_srbf_ren_min((s - q[1]) * q[2], (float)(d->n_h - 1));
    return sl_srbf_ren_cell(fh, d->n_h, wh);
}

/* Where one row reads the table: the 8 (lambda, dphi, t) corners shared by the modes (offset o8,
 * weight w8), the h cell and fraction of each mode in both lambda slices (ih, wh: [2 m + slice])
 * and int G. Split from the blend so the C batch can compute the next rows' corners and prefetch
 * them while it blends this one (cpu/srbf_ren_c.c); sl_srbf_ren_lookup runs both in turn. */
typedef struct sl_srbf_ren_pt {
    int o8[8];
    float w8[8];
    int ih[6];
    float wh[6];
    float norm;
} sl_srbf_ren_pt;

/* Angles in the fiber frame, lambda > 0. */
SL_INLINE void sl_srbf_ren_coords(SL_GLOBAL const float *T, const sl_srbf_ren_dims *d,
                                  float theta_o, float phi_o, float theta_j, float phi_j,
                                  float lambda, sl_srbf_ren_pt *q) {
    const float half_pi = 0.5f * SL_PI_F;
    float h = sl_clampf(0.5f * (theta_o + theta_j), -half_pi, half_pi);
    float r = sl_srbf_ren_max(half_pi - fabs(h), 1e-30f);
    float tt = sl_clampf(0.5f * (theta_j - theta_o) / r, -1.0f, 1.0f);
    float wt, wp, wl;
    int it = sl_srbf_ren_cell((sl_srbf_ren_twarp(tt) + 1.0f) * d->t_scale, d->n_t, &wt);
    /* |wrap(phi_j - phi_o)| in [0, pi]; floor by truncation of a positive number (azimuths are
     * within [-pi, pi] or a few turns of it; further ones clamp to 0 or pi) */
    float x = (phi_j - phi_o) * (0.5f * SL_INV_PI_F) + 0.5f;
    x = x > -7.0f ? x : -7.0f; /* (NaN -> -7: never an undefined conversion) */
    x = x < 9.0f ? x : 9.0f;
    x = fabs(x - (float)((int)(x + 8.0f) - 8) - 0.5f) * (2.0f * SL_PI_F);
    int ip = sl_srbf_ren_cell(sl_srbf_ren_min(x * d->p_scale, (float)(d->n_p - 1)), d->n_p, &wp);
    float lam = sl_clampf(lambda, 1e-18f, 1e18f);
    float fl =
        sl_clampf((sl_srbf_ren_log(lam) - d->log_lmin) * d->l_scale, 0.0f, (float)(d->n_l - 1));
    int il = sl_srbf_ren_cell(fl, d->n_l, &wl);
    float l2 = lam * lam;
    q->norm = SL_PI_F * l2 * (1.0f - sl_srbf_ren_exp_neg(-4.0f / l2)); /* int G d omega */
    /* the 8 (lambda, dphi, t) corners, shared by the three modes */
    int st = d->n_h, sp = d->n_h * d->n_t, sl = sp * d->n_p;
    int base = il * sl + ip * sp + it * st;
    for (int c = 0; c < 8; c++) {
        int bl = c >> 2, bp = (c >> 1) & 1, bt = c & 1;
        q->w8[c] = (bl ? wl : 1.0f - wl) * (bp ? wp : 1.0f - wp) * (bt ? wt : 1.0f - wt);
        q->o8[c] = base + bl * sl + bp * sp + bt * st;
    }
    float lc = sl_clampf(lam, d->lmin, d->lmax); /* the lambda the normalised value is read at */
    for (int m = 0; m < 3; m++) {
        float w = sqrt(d->beta2[m] + 0.25f * lc * lc), dh = h - d->alpha[m], y = dh / w;
        /* displacement (same y in both slices) while the lobe is 2 widths from |h| = pi/2,
         * plain interpolation (same h) within 1 width of it, linear in between */
        float g = sl_clampf((fabs(h) + 2.0f * w - half_pi) / w, 0.0f, 1.0f);
        q->ih[2 * m] = sl_srbf_ren_hcell(T, d, m, il, y, dh, g, &q->wh[2 * m]);
        q->ih[2 * m + 1] = sl_srbf_ren_hcell(T, d, m, il + 1, y, dh, g, &q->wh[2 * m + 1]);
    }
}

/* The normalised R at the corners q: interpolated linearly, or for a table whose R block holds
 * logarithms (d->r_log: models deon and chiang, whose R rises by orders of magnitude towards the
 * diamond's edges, where linear interpolation overshoots; docs/srbf_ren.md) log-linearly. */
SL_INLINE float sl_srbf_ren_blend_r(SL_GLOBAL const float *T, const sl_srbf_ren_dims *d,
                                    const sl_srbf_ren_pt *q) {
    float v = sl_srbf_ren_blend1(T + d->off[0], q->o8, q->w8, q->ih, q->wh);
    /* exp by the polynomial above (relative error < 2e-7 for any argument in [-87, 88], which
     * holds the stored logarithms: ln r_eps and ln of a normalised response) */
    return d->r_log ? sl_srbf_ren_max(sl_srbf_ren_exp_neg(v) - d->r_eps, 0.0f) : v;
}

/* out: R rgb, TT rgb, TRT rgb (R replicated) at the corners q. */
SL_INLINE void sl_srbf_ren_blend(SL_GLOBAL const float *T, const sl_srbf_ren_dims *d,
                                 const sl_srbf_ren_pt *q, float out[9]) {
    float vr = sl_srbf_ren_blend_r(T, d, q) * q->norm;
    out[0] = out[1] = out[2] = vr;
    sl_srbf_ren_blend3(T + d->off[1], q->o8, q->w8, q->ih + 2, q->wh + 2, q->norm, out + 3);
    sl_srbf_ren_blend3(T + d->off[2], q->o8, q->w8, q->ih + 4, q->wh + 4, q->norm, out + 6);
}

/* out: R rgb, TT rgb, TRT rgb (R replicated). Angles in the fiber frame, lambda > 0. */
SL_INLINE void sl_srbf_ren_lookup(SL_GLOBAL const float *T, const sl_srbf_ren_dims *d,
                                  float theta_o, float phi_o, float theta_j, float phi_j,
                                  float lambda, float out[9]) {
    sl_srbf_ren_pt q;
    sl_srbf_ren_coords(T, d, theta_o, phi_o, theta_j, phi_j, lambda, &q);
    sl_srbf_ren_blend(T, d, &q, out);
}

#endif
