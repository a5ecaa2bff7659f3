/* fiber_furnace.h: the white-furnace integral (numerics.md sec. 5 `furnace`) in float, shared by
 * the C twin and OpenCL: albedo(omega_o) = integral over the sphere of f(omega_i, omega_o)
 * d omega_i, d omega_i = cos(theta_i) d theta_i d phi_i (theta is the inclination from the normal
 * plane), for either model, by a fixed-node rule:
 *  - theta_i: 8-point Gauss-Legendre panels between breakpoints at each lobe's specular peak and
 *    +-1, 2, 4, 8 lobe widths (panels no longer than 0.5 rad), so a 1 deg lobe is resolved;
 *  - phi_i: the periodic trapezoid rule with n_phi = clamp(4.5 / beta_min, 24, 1024) nodes. For
 * d'Eon it integrates every Gaussian detector of the sampled N_p to ~e^-(n beta)^2/2 ~ 4e-5, so the
 *    N_p quadrature in h needs no resolution of the detector and a fixed 6-panel rule is used.
 * Accuracy (measured, docs/numerics-deon.md): d'Eon with sigma_a = 0 gives 1 within 1e-3 for
 * beta 1..60 deg. The double reference is cpu/reference/furnace_ref.c.
 *
 * Chiang (sl_furnace_chiang): the float f_p is M_p(theta_i) times Nbar_p(phi) (fiber_chiang.h:
 * A_p and Phi depend on theta_o and h only), so the same tensor-product rule (theta_i panels x
 * phi trapezoid) is evaluated as the product of its two 1-D sums, per lobe: theta_i by the
 * panels above (breakpoints at the lobe's cone and the grazing boundary layers), phi by the
 * periodic trapezoid with n_phi = clamp(4.5 / s, 128, 2048), which integrates a sampled logistic
 * of scale s to ~e^{-pi s n_phi} and its trimming kink (slope jump at +-pi, large s) to ~1e-6.
 * Measured: docs/numerics-chiang.md. */
#ifndef SL_FIBER_FURNACE_H
#define SL_FIBER_FURNACE_H

#include "fiber_chiang.h"
#include "fiber_deon.h"
#include "fiber_marschner.h"

#define SL_FURNACE_DEON_PANELS 6
#define SL_FURNACE_MAX_PTS 32

/* Adds the breakpoints centre + k width (k = 0, +-1, 2, 4, 8) that fall inside (-pi/2, pi/2). */
SL_INLINE int sl_furnace_add_peak(float *pts, int n, float centre, float width) {
    const float k[9] = {-8.0f, -4.0f, -2.0f, -1.0f, 0.0f, 1.0f, 2.0f, 4.0f, 8.0f};
    for (int j = 0; j < 9; j++) {
        float x = centre + k[j] * width;
        if (x > -0.5f * SL_PI_F && x < 0.5f * SL_PI_F && n < SL_FURNACE_MAX_PTS) pts[n++] = x;
    }
    return n;
}

/* Integral over phi_i (trapezoid, nphi nodes) of f at one theta_i. */
SL_INLINE float sl_furnace_phi_sum(const sl_fiber_params *fp, float theta_i, float theta_o,
                                   float phi_o, int nphi) {
    float dphi = SL_TWO_PI_F / (float)nphi;
    float sum = 0.0f;
    if (fp->model == 1) {
        /* d'Eon: M_p does not depend on phi; hoist it and the geometry out of the phi loop. */
        int n = fp->orders < SL_DEON_MAX_ORDERS ? fp->orders : SL_DEON_MAX_ORDERS;
        float mp[SL_DEON_MAX_ORDERS + 2];
        for (int p = 0; p <= n; p++) {
            float b = sl_deon_beta(fp, p);
            mp[p] = exp(sl_deon_log_mp(b * b, theta_i, theta_o - 2.0f * sl_deon_alpha(fp, p)));
        }
        sl_deon_geom g;
        sl_deon_geom_init(fp, theta_i, theta_o, &g);
        float np[SL_DEON_MAX_ORDERS + 1];
        float e_rest = 0.0f;
        for (int j = 0; j < nphi; j++) {
            float phi = -SL_PI_F + ((float)j + 0.5f) * dphi;
            sl_deon_azimuthal(fp, &g, phi, n, SL_FURNACE_DEON_PANELS, np, &e_rest);
            float s = 0.0f;
            for (int p = 0; p <= n; p++)
                s += mp[p] * np[p];
            sum += s;
        }
        /* f_rest = M_TRT E_rest / 2pi is constant in phi: its phi integral is M_TRT E_rest. */
        float b = fp->beta[2];
        float mr = exp(sl_deon_log_mp(b * b, theta_i, theta_o - 2.0f * fp->alpha[2]));
        return sum * dphi + mr * e_rest;
    }
    for (int j = 0; j < nphi; j++) {
        float phi = -SL_PI_F + ((float)j + 0.5f) * dphi;
        float out[4];
        sl_marschner_scatter(fp, theta_i, phi_o - phi, theta_o, phi_o, out);
        sum += out[3];
    }
    return sum * dphi;
}

/* Sorts pts[0..n) (insertion sort, n <= SL_FURNACE_MAX_PTS). */
SL_INLINE void sl_furnace_sort(float *pts, int n) {
    for (int i = 1; i < n; i++) {
        float x = pts[i];
        int j = i - 1;
        while (j >= 0 && pts[j] > x) {
            pts[j + 1] = pts[j];
            j--;
        }
        pts[j + 1] = x;
    }
}

/* integral_{-pi/2}^{pi/2} M_p(theta_i) cos theta_i d theta_i of chiang lobe p (0..3) by 8-point
 * Gauss-Legendre panels no longer than 0.5 rad between breakpoints at the cone +-1, 2, 4, 8
 * widths (width sqrt(v_p)) and the same distances from the poles. */
SL_INLINE float sl_furnace_chiang_mp(const sl_fiber_params *fp, int p, float theta_o) {
    float width = fp->beta[p < 2 ? p : 2];
    /* the cone sits at -theta_o'; past a pole it is the direction +-pi - theta_o' (M depends
     * on sin and |cos| only) */
    float c = p < 3 ? 2.0f * fp->alpha[p] - theta_o : -theta_o;
    if (c > 0.5f * SL_PI_F) c = SL_PI_F - c;
    if (c < -0.5f * SL_PI_F) c = -SL_PI_F - c;
    float pts[SL_FURNACE_MAX_PTS];
    int n = 0;
    pts[n++] = -0.5f * SL_PI_F;
    pts[n++] = 0.5f * SL_PI_F;
    n = sl_furnace_add_peak(pts, n, c, width);
    n = sl_furnace_add_peak(pts, n, -0.5f * SL_PI_F, width);
    n = sl_furnace_add_peak(pts, n, 0.5f * SL_PI_F, width);
    sl_furnace_sort(pts, n);
    float total = 0.0f;
    for (int i = 0; i + 1 < n; i++) {
        float a = pts[i], b = pts[i + 1];
        if (!(b > a)) continue;
        int sub = (int)ceil((b - a) / 0.5f);
        float hw = 0.5f * (b - a) / (float)sub;
        for (int k = 0; k < sub; k++) {
            for (int j = 0; j < 8; j++) {
                float ti, w;
                sl_gl8_node(a, hw, k, j, &ti, &w);
                total += w * cos(ti) * exp(sl_chiang_log_mp(fp, p, ti, theta_o));
            }
        }
    }
    return total;
}

/* The chiang albedo: sum_p [integral M_p cos ti d ti] [integral Nbar_p d phi] (+ the rest,
 * whose azimuth is uniform: its phi integral is E_3). Independent of phi_o. */
SL_INLINE float sl_furnace_chiang(const sl_fiber_params *fp, float theta_o) {
    sl_chiang_geom g;
    sl_chiang_geom_init(fp, theta_o, &g);
    int panels = sl_chiang_default_panels(fp);
    int nphi = (int)ceil(4.5f / g.s);
    nphi = nphi < 128 ? 128 : (nphi > 2048 ? 2048 : nphi);
    float dphi = SL_TWO_PI_F / (float)nphi;
    float nint[3] = {0.0f, 0.0f, 0.0f}, e_rest = 0.0f;
    for (int j = 0; j < nphi; j++) {
        float np[3];
        sl_chiang_azimuthal(&g, -SL_PI_F + ((float)j + 0.5f) * dphi, panels, np, &e_rest);
        for (int p = 0; p < 3; p++)
            nint[p] += np[p];
    }
    float total = sl_furnace_chiang_mp(fp, 3, theta_o) * e_rest;
    for (int p = 0; p < 3; p++)
        total += sl_furnace_chiang_mp(fp, p, theta_o) * nint[p] * dphi;
    return total;
}

SL_INLINE float sl_furnace(const sl_fiber_params *fp, float theta_o, float phi_o) {
    if (fp->model == 2) return sl_furnace_chiang(fp, theta_o);
    float pts[SL_FURNACE_MAX_PTS];
    int n = 0;
    pts[n++] = -0.5f * SL_PI_F;
    pts[n++] = 0.5f * SL_PI_F;
    float bmin = 10.0f;
    for (int q = 0; q < 3; q++) {
        if (fp->model == 1) /* M_p(theta_i, theta_o - 2 alpha): cone at -(theta_o - 2 alpha) */
            n = sl_furnace_add_peak(pts, n, 2.0f * fp->alpha[q] - theta_o, fp->beta[q]);
        else /* exp(-(theta_h - alpha)^2/beta^2): std sqrt(2) beta in theta_i */
            n = sl_furnace_add_peak(pts, n, 2.0f * fp->alpha[q] - theta_o,
                                    1.41421356f * fp->beta[q]);
        bmin = sl_minf(bmin, fp->beta[q]);
    }
    sl_furnace_sort(pts, n); /* n <= 29 */
    if (fp->model != 1) bmin = sl_minf(bmin, sl_minf(fp->caustic_width, 0.2f));
    int nphi = (int)ceil(4.5f / sl_maxf(bmin, 1e-4f));
    nphi = nphi < 24 ? 24 : (nphi > 1024 ? 1024 : nphi);
    float total = 0.0f;
    for (int i = 0; i + 1 < n; i++) {
        float a = pts[i], b = pts[i + 1];
        if (!(b > a)) continue;
        int sub = (int)ceil((b - a) / 0.5f);
        float hw = 0.5f * (b - a) / (float)sub;
        for (int s = 0; s < sub; s++) {
            for (int j = 0; j < 8; j++) {
                float ti, w;
                sl_gl8_node(a, hw, s, j, &ti, &w);
                total += w * cos(ti) * sl_furnace_phi_sum(fp, ti, theta_o, phi_o, nphi);
            }
        }
    }
    return total;
}

#endif
