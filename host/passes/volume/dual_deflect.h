/* dual_deflect.h: how far a fiber turns the light it scatters about its own axis, per material
 * and colour channel, for the spread of multiply-scattered light among fibers that are not
 * parallel (docs/volume.md, "Where the scattered light goes").
 *
 * A fiber keeps the component of the light's direction along its axis and turns the rest about
 * it by the azimuthal deflection (phi - pi in the fiber's angles, both directions pointing away:
 * phi = pi goes straight through). Seen from another fiber at a small angle delta to this one,
 * the light's inclination then changes by a random amount of variance (1 + cos phi) |delta|^2, so
 * in the width convention of sigma_f (exp(-x^2 / s^2), variance s^2 / 2) each event adds
 *     2 E[1 + cos phi] |delta|^2
 * to the squared spread. E is taken over the light the fiber scatters forward (weight |phi| / pi,
 * the split of a_f) or backward (1 - |phi| / pi, a_b), for light incident from every direction
 * (weight cos theta_i, as sl_dual_means) and scattered into every direction (f cos theta_o). */
#ifndef SL_DUAL_DEFLECT_H
#define SL_DUAL_DEFLECT_H

#include "passes/volume/dual.h"
#include "fiber_params.h"
#include "scene/material.h"

#define SL_DEFLECT_NMU 129 /* theta_j nodes on [-pi/2, pi/2] */
#define SL_DEFLECT_NS 65   /* s nodes, uniform in s / (s + 1) on [0, 6 / 7] */

typedef struct sl_dual_deflect {
    /* per channel: 2 E[1 + cos phi] over the forward and the backward scattered light, the
     * squared spread an event adds per unit squared tilt (0..4) */
    float kf[3], kb[3];
    /* per channel: the mean squared longitudinal width of one layer's backscattering, sigma_b^2
     * of the dual tables weighted by a_b cos theta_d (the width convention of sigma_f) */
    float sb2[3];
} sl_dual_deflect;

/* The share of light arriving at inclination theta_j with spread s (the Gaussian
 * exp(-(x - theta_j)^2 / s^2) / (sqrt(pi) s) of Xu's psi_f) that lies on the sphere,
 *     N(theta_j, s) = integral_{-pi/2}^{pi/2} g(x; theta_j, s) cos x dx,
 * from a table of SL_DEFLECT_NMU x SL_DEFLECT_NS nodes (bilinear in theta_j and s / (s + 1);
 * s >= 6 read at 6; material-independent, built on the first call, thread-safe). Xu's psi_f divides
 * by cos theta_j, N's limit for a narrow spread: a wider spread moves light to where cos is
 * smaller and cuts it at the poles, so the response of a widened spread is scaled by
 * N(theta_j, s_0) / N(theta_j, s) to carry the same energy as at the march's own s_0. */
float sl_dual_deflect_norm(float theta_j, float s);

/* Computes d for material m with its dual tables t (sl_dual_tables_build of the same m): E by a
 * midpoint rule over theta_i (8), theta_o (24) and phi (48) of the float fiber function
 * (cpu/fiber_c.h), the theta_i rows on every CPU. */
void sl_dual_deflect_build(const sl_material *m, const sl_dual_tables *t, sl_dual_deflect *d);
/* kf, kb of one channel's fiber (fp) with ni x no x np midpoint nodes (the build's resolution
 * check uses a finer rule). */
void sl_dual_deflect_moments(const sl_fiber_params *fp, int ni, int no, int np, float *kf,
                             float *kb);

#endif
