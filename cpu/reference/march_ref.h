/* march_ref.h: the double-precision reference of the forward-scattering transmittance T_f and
 * spread sigma_f (numerics.md sec. 5/7 `forward-transmittance`; definition in docs/volume.md):
 * the shadow path from x toward the lobe centre w is intersected with the actual fibers (every
 * segment a capsule of its radius); each strand the ray passes through (a run of consecutive
 * segments of one strand within their radius of the ray, ahead of x) is one forward-scattering
 * event at the incident inclination theta = asin|w.t| (t: the tangent of the run's closest
 * segment), and
 *     T_f = prod_k a_f(theta_k),   sigma_f = sqrt(sum_k beta_f(theta_k)^2)
 * with a_f, beta_f the reference dual-scattering terms (cpu/reference/dual_ref.h). A strand that
 * contains x is ignored (x on a fiber is not shadowed by it). Brute force over the segments. */
#ifndef SL_MARCH_REF_H
#define SL_MARCH_REF_H

#include "io/hair/hair.h"
#include "scene/material.h"

#include <stddef.h>

/* Inclinations theta (radians, [0, pi/2]) of the events on the ray from x along unit w, in no
 * particular order; at most max are stored, the count is returned. */
size_t slref_march_events(const sl_hair *h, const double x[3], const double w[3], double *theta,
                          size_t max);

/* The last dual-terms evaluation (slref_dual_terms costs ~1-10 ms): reused while theta repeats,
 * as on parallel fibers. Zero-initialise; one per channel. */
typedef struct slref_dual_cache {
    int valid, ch;
    double theta, terms[9];
} slref_dual_cache;

/* T_f and sigma_f of colour channel ch from the event inclinations (material m, marschner).
 * cache may be NULL. */
void slref_forward_from_events(const sl_material *m, int ch, const double *theta, size_t n,
                               slref_dual_cache *cache, double *Tf, double *sigma_f);

#endif
