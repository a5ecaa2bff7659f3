/* fiber_common.h: the fiber-frame quantities every scattering model shares (numerics.md sec. 1-3),
 * written once and instantiated twice: in float with prefix `sl_` (OpenCL C and the C backend),
 * and in C only also in double with prefix `sld_` (the reference backend, via fiber_common_d.h).
 *
 * Conventions (numerics.md): angles in radians; theta is the inclination from the fiber's normal
 * plane; h in [-1, 1] is the offset of the ray in the cross-section; p = 0, 1, 2 is R, TT, TRT;
 * eta' and eta'' are Bravais' indices for the projected (normal-plane) problem; sigma_a is the
 * absorption per unit fiber radius. */
#ifndef SL_FIBER_COMMON_H
#define SL_FIBER_COMMON_H

#include "sl_compat.h"

#define SL_R float
#define SL_F(name) sl_##name
#define SL_K(x) x##f
#include "fiber_common.inc"
#undef SL_R
#undef SL_F
#undef SL_K

/* Abramowitz & Stegun 9.8.1 and 9.8.2, the one copy of their coefficients (d'Eon's log M_p,
 * the SRBF fast paths' i0e): I0(x) = sl_as_i0_small(t^2) with t = x / 3.75 for |x| <= 3.75
 * (A&S: |eps| < 1.6e-7), and sqrt(x) e^-x I0(x) = sl_as_i0e_large(u) with u = 3.75 / x for
 * x >= 3.75 (A&S: |eps| < 1.9e-7). */
#define SL_AS_I0_SPLIT 3.75f /* below: sl_as_i0_small, from here on: sl_as_i0e_large */
SL_INLINE float sl_as_i0_small(float t2) {
    return 1.0f +
           t2 *
               (3.5156229f +
                t2 * (3.0899424f +
                      t2 * (1.2067492f + t2 * (0.2659732f + t2 * (0.0360768f + t2 * 0.0045813f)))));
}
SL_INLINE float sl_as_i0e_large(float u) {
    return 0.39894228f +
           u * (0.01328592f +
                u * (0.00225319f +
                     u * (-0.00157565f +
                          u * (0.00916281f +
                               u * (-0.02057706f +
                                    u * (0.02635537f + u * (-0.01647633f + u * 0.00392377f)))))));
}

/* Node j (0..7) of the 8-point Gauss-Legendre rule on panel k of width 2 hw starting at a
 * (centre a + (2k + 1) hw): its abscissa *x and weight *w (the composite rules of
 * fiber_deon.h, fiber_chiang.h and fiber_furnace.h). */
SL_INLINE void sl_gl8_node(float a, float hw, int k, int j, float *x, float *w) {
    const float gx[4] = {0.1834346425f, 0.5255324099f, 0.7966664774f, 0.9602898565f};
    const float gw[4] = {0.3626837834f, 0.3137066459f, 0.2223810345f, 0.1012285363f};
    float mid = a + (2.0f * (float)k + 1.0f) * hw;
    *x = mid + (j < 4 ? -gx[j] : gx[j - 4]) * hw;
    *w = gw[j < 4 ? j : j - 4] * hw;
}

#endif
