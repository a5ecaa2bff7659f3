/* ms_table.h: the per-material table of the multiple-scattering response (kernels/ms_response.h,
 * Xu 2011 Eq. 27-31) and its lookup, float, shared by C (host/passes/volume/volume_ms.c builds it
 * and looks it up per fragment and lobe) and OpenCL (kernels/ms.cl), so both agree to float
 * rounding. The idea is Ren 2010's precomputed single-scattering table (kernels/srbf_ren_lookup.h);
 * layout, size and error: docs/volume.md, "The response table".
 *
 * What the response depends on (per channel): theta_o, theta_j, s_F = sqrt(lambda^2 + sigma_f^2)
 * (lambda and sigma_f enter only through s_F, Xu Eq. 5) and D = |wrap(phi_o - phi_j)| (N^G is
 * even in D). Separable, hence not tabulated: 1 / cos theta_j (psi_f's normalisation), the local
 * term's azimuthal overlap (pi - D) / pi^2 (Xu Eq. 30), and, per mode t of the global term, the
 * narrow Gaussian of theta_j + theta_o around 2 alpha_t (the SRBF lobe's g times M_t, width
 * sqrt(s_F^2 + 4 beta_t^2): 0.13 rad for TT, far too narrow for a coarse grid):
 *   M^G = 1/cos theta_j sum_t G_t A_t(theta_o, theta_j, s_F, D),
 *   G_t = 2 / (sqrt(pi) w_t) exp(-(theta_j + theta_o - 2 alpha_t)^2 / w_t^2),
 *   w_t^2 = s_F^2 + 4 beta_t^2,
 * with A_t the 6-point Gauss-Hermite sum of cos^2 theta_i / cos^2 theta_d N^G_t(theta_d, D)
 * (smooth: no narrow factor left), and likewise for the local term (Xu Eq. 29-31)
 *   M^L = 2 / cos theta_j (pi - D) / pi^2 G_b L(theta_o, theta_j, s_F),
 *   G_b = 1 / (sqrt(pi) w_b) exp(-(theta_j + theta_o - ~Delta_b)^2 / w_b^2),
 *   w_b^2 = s_F^2 + ~sigma_b^2,
 * with ~Delta_b, ~sigma_b (Xu Eq. 31: means over theta_d in (theta_j - theta_o +- s_F) / 2)
 * functions of u = theta_j - theta_o and s_F only: a second, 2-D table; L is the Gauss-Hermite
 * sum of A_b(theta_d) cos^2 theta_i / cos^2 theta_d.
 *
 * Axes: theta_o and theta_j uniform on [-pi/2, pi/2]; s_F by x = s_F / (s_F + S0) uniform on
 * [0, x(SMAX)] (dense for narrow lobes, where A_t and L change fastest; s_F > SMAX is clamped
 * in the table coordinate only, the analytic factors use the true s_F); D uniform on [0, pi] on
 * every (SL_MSR_ND - 1) / (SL_MST_ND - 1)-th node of the N^G table, where the global term is
 * linear in the N^G values (so its D interpolation adds no error beyond N^G's own at those
 * nodes); u uniform on [-pi, pi].
 * Layout per channel: node (o, j, s) holds SL_MST_STRIDE floats: (A_R, A_TT, A_TRT) at each of
 * the SL_MST_ND D nodes in turn, then L; nodes in the order [o][j][s]. The three modes of two
 * neighbouring D nodes are 6 consecutive floats, one cache line mostly, where [mode][D] spread
 * a lookup's corner over three (the lookups are memory-bound: 7 MB per channel). Then the 2-D
 * table, [u][s] pairs (~Delta_b, ~sigma_b). Quadrilinear (and bilinear) interpolation. */
#ifndef SL_MS_TABLE_H
#define SL_MS_TABLE_H

#include "ms_response.h"

#define SL_MST_NO 33     /* theta_o nodes */
#define SL_MST_NJ 33     /* theta_j nodes */
#define SL_MST_NS 16     /* s_F nodes */
#define SL_MST_ND 33     /* D nodes: every (SL_MSR_ND - 1) / (SL_MST_ND - 1)-th N^G node */
#define SL_MST_S0 0.25f  /* s_F axis: x = s_F / (s_F + S0) */
#define SL_MST_SMAX 4.0f /* s_F beyond: clamped in the table coordinate */
#define SL_MST_NU 65     /* u = theta_j - theta_o nodes of the (~Delta_b, ~sigma_b) table */
#define SL_MST_NSB 61    /* its s_F nodes (same x axis; every 4th is a main node) */
#define SL_MST_STRIDE (3 * SL_MST_ND + 1)
#define SL_MST_MAIN (SL_MST_NO * SL_MST_NJ * SL_MST_NS * SL_MST_STRIDE)
#define SL_MST_FLOATS (SL_MST_MAIN + SL_MST_NU * SL_MST_NSB * 2)

/* s_F of node s of n (the inverse of x = s_F / (s_F + S0) on the uniform x nodes). */
SL_INLINE float sl_mst_node_s(int s, int n) {
    float xmax = SL_MST_SMAX / (SL_MST_SMAX + SL_MST_S0);
    float x = xmax * (float)s / (float)(n - 1);
    return SL_MST_S0 * x / (1.0f - x);
}

/* theta of node i of an axis of n uniform nodes on [-pi/2, pi/2]. */
SL_INLINE float sl_mst_node_theta(int i, int n) {
    return -SL_DUAL_HALF_PI + SL_PI_F * (float)i / (float)(n - 1);
}

/* Cell index and fraction of coordinate f (in node units) clamped to [0, n - 1]; NaN -> 0, so a
 * bad input never indexes outside the table. */
SL_INLINE int sl_mst_cell(float f, int n, float *frac) {
    f = f >= 0.0f ? f : 0.0f;
    f = f <= (float)(n - 1) ? f : (float)(n - 1);
    int i = (int)f;
    i = i > n - 2 ? n - 2 : i;
    *frac = f - (float)i;
    return i;
}

/* Where a row reads the table, apart from s_F: the cells and fractions of theta_o, theta_j, D and
 * u = theta_j - theta_o, and cos theta_j. */
typedef struct sl_mst_row {
    int io, ij, id, iu;
    float fo, fj, fd, fu, ctj, D;
} sl_mst_row;

SL_INLINE void sl_mst_row_init(float theta_o, float phi_o, float theta_j, float phi_j,
                               sl_mst_row *r) {
    r->ctj = cos(theta_j);
    r->D = sl_minf(fabs(sl_wrap_pi(phi_o - phi_j)), SL_PI_F);
    r->io = sl_mst_cell((theta_o + SL_DUAL_HALF_PI) * ((float)(SL_MST_NO - 1) / SL_PI_F), SL_MST_NO,
                        &r->fo);
    r->ij = sl_mst_cell((theta_j + SL_DUAL_HALF_PI) * ((float)(SL_MST_NJ - 1) / SL_PI_F), SL_MST_NJ,
                        &r->fj);
    r->id = sl_mst_cell(r->D * ((float)(SL_MST_ND - 1) / SL_PI_F), SL_MST_ND, &r->fd);
    r->iu = sl_mst_cell((theta_j - theta_o + SL_PI_F) * ((float)(SL_MST_NU - 1) / (2.0f * SL_PI_F)),
                        SL_MST_NU, &r->fu);
}

/* The table coordinate of s_F (in [0, 1], clamped at SL_MST_SMAX). */
SL_INLINE float sl_mst_xs(float sF) {
    float xmax = SL_MST_SMAX / (SL_MST_SMAX + SL_MST_S0);
    return sF / (sF + SL_MST_S0) / xmax;
}

/* Corner c (0..7) of row r's cell at the s_F cell is, fraction fs: its node's floats and its
 * trilinear weight *w. */
SL_INLINE SL_GLOBAL const float *sl_mst_corner(SL_GLOBAL const float *mt, const sl_mst_row *r,
                                               int is, float fs, int c, float *w) {
    int a = c & 1, b = (c >> 1) & 1, e = c >> 2;
    *w = (a ? r->fo : 1.0f - r->fo) * (b ? r->fj : 1.0f - r->fj) * (e ? fs : 1.0f - fs);
    return mt +
           ((size_t)((r->io + a) * SL_MST_NJ + r->ij + b) * SL_MST_NS + is + e) * SL_MST_STRIDE;
}

/* M^G of row r at s2 = s_F^2 (the top of the file). */
SL_INLINE float sl_mst_global(const sl_fiber_params *fp, SL_GLOBAL const float *mt,
                              const sl_mst_row *r, float theta_o, float theta_j, float s2) {
    float sF = sqrt(s2);
    /* Separable Gaussians of the global term, per mode (the top of the file). */
    float G[3];
    for (int t = 0; t < 3; t++) {
        float bt = sl_dual_ms_beta(fp, t);
        float w2 = s2 + 4.0f * bt * bt, d = theta_j + theta_o - 2.0f * fp->alpha[t];
        G[t] = 2.0f / (SL_SQRT_PI_F * sqrt(w2)) * exp(-d * d / w2);
    }
    float fs;
    int is = sl_mst_cell(sl_mst_xs(sF) * (float)(SL_MST_NS - 1), SL_MST_NS, &fs);
    float mg = 0.0f;
    for (int c = 0; c < 8; c++) {
        float w;
        SL_GLOBAL const float *v = sl_mst_corner(mt, r, is, fs, c, &w);
        float g = 0.0f;
        SL_GLOBAL const float *q = v + 3 * r->id; /* the 3 modes at D nodes id, id + 1 */
        for (int t = 0; t < 3; t++)
            g += G[t] * (q[t] + r->fd * (q[3 + t] - q[t]));
        mg += w * g;
    }
    return mg / r->ctj;
}

/* M^L of row r at s2 = s_F^2 (the top of the file). */
SL_INLINE float sl_mst_local(SL_GLOBAL const float *mt, const sl_mst_row *r, float theta_o,
                             float theta_j, float s2) {
    float xs = sl_mst_xs(sqrt(s2)), fs, fb;
    int is = sl_mst_cell(xs * (float)(SL_MST_NS - 1), SL_MST_NS, &fs);
    /* The local term's Gaussian from the 2-D table (bilinear in u, s). */
    int ib = sl_mst_cell(xs * (float)(SL_MST_NSB - 1), SL_MST_NSB, &fb);
    SL_GLOBAL const float *b0 = mt + SL_MST_MAIN + (size_t)(r->iu * SL_MST_NSB + ib) * 2;
    SL_GLOBAL const float *b1 = b0 + SL_MST_NSB * 2;
    float fu = r->fu;
    float dB =
        (1.0f - fu) * ((1.0f - fb) * b0[0] + fb * b0[2]) + fu * ((1.0f - fb) * b1[0] + fb * b1[2]);
    float sB =
        (1.0f - fu) * ((1.0f - fb) * b0[1] + fb * b0[3]) + fu * ((1.0f - fb) * b1[1] + fb * b1[3]);
    float wb2 = s2 + sB * sB, db = theta_j + theta_o - dB;
    float Gb = exp(-db * db / wb2) / (SL_SQRT_PI_F * sqrt(wb2));
    float ml = 0.0f;
    for (int c = 0; c < 8; c++) {
        float w;
        SL_GLOBAL const float *v = sl_mst_corner(mt, r, is, fs, c, &w);
        ml += w * v[3 * SL_MST_ND];
    }
    return 2.0f / r->ctj * (SL_PI_F - r->D) / (SL_PI_F * SL_PI_F) * Gb * ml;
}

/* One row of one channel's table at three spreads (sigma_g, sigma_i for M^G, sigma_l for M^L;
 * docs/volume.md "Where the scattered light goes"): each value is sl_ms_table_1's at that spread,
 * the row's cells found once. need: SL_MST_NEED_G | _GI | _L, the values wanted (the others are 0
 * and cost nothing: a row whose light arrives unscattered needs no M^G). */
#define SL_MST_NEED_G 1
#define SL_MST_NEED_GI 2
#define SL_MST_NEED_L 4
SL_INLINE void sl_ms_table_spread(const sl_fiber_params *fp, SL_GLOBAL const float *mt,
                                  float theta_o, float phi_o, float theta_j, float phi_j,
                                  float lambda, float sigma_g, float sigma_i, float sigma_l,
                                  int need, float *MG, float *MGi, float *ML) {
    float l2 = lambda * lambda;
    float sg2 = l2 + sigma_g * sigma_g, si2 = l2 + sigma_i * sigma_i, sl2 = l2 + sigma_l * sigma_l;
    sl_mst_row r;
    sl_mst_row_init(theta_o, phi_o, theta_j, phi_j, &r);
    *MG = *MGi = *ML = 0.0f;
    if (!(r.ctj > 1e-4f)) return;
    if ((need & SL_MST_NEED_G) && sqrt(sg2) > 0.0f)
        *MG = sl_mst_global(fp, mt, &r, theta_o, theta_j, sg2);
    if ((need & SL_MST_NEED_GI) && sqrt(si2) > 0.0f)
        *MGi = sl_mst_global(fp, mt, &r, theta_o, theta_j, si2);
    if ((need & SL_MST_NEED_L) && sqrt(sl2) > 0.0f)
        *ML = sl_mst_local(mt, &r, theta_o, theta_j, sl2);
}

/* M^G and M^L of one channel from its table mt (SL_MST_FLOATS; __global in OpenCL): the same
 * arguments and meaning as sl_ms_response_1 (kernels/ms_response.h), which is the reference. */
SL_INLINE void sl_ms_table_1(const sl_fiber_params *fp, SL_GLOBAL const float *mt, float theta_o,
                             float phi_o, float theta_j, float phi_j, float lambda, float sigma_f,
                             float *MG, float *ML) {
    float unused;
    sl_ms_table_spread(fp, mt, theta_o, phi_o, theta_j, phi_j, lambda, sigma_f, sigma_f, sigma_f,
                       SL_MST_NEED_G | SL_MST_NEED_L, MG, &unused, ML);
}

#endif
