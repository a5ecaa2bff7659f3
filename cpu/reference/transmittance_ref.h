/* transmittance_ref.h: the double-precision reference of the effective transmittance
 * (numerics.md sec. 7): fibers are ray-traced as the actual geometry (every segment a capsule,
 * i.e. a cylinder with round caps, of the segment's radius; consecutive capsules join smoothly),
 * and T_j(x) = integral G_j T(x, .) / integral G_j is estimated by Monte Carlo with directions
 * drawn exactly from G_j (a von Mises-Fisher lobe of concentration 2 / lambda^2) from a fixed
 * seed: the estimate is an average of 0/1 visibilities, with standard error sqrt(T (1-T) / n).
 * A fiber that contains x itself is ignored (x on a fiber's surface is not shadowed by it). */
#ifndef SL_TRANSMITTANCE_REF_H
#define SL_TRANSMITTANCE_REF_H

#include "io/hair/hair.h"

#include <stdint.h>

typedef struct slref_fibers slref_fibers; /* segments in a uniform grid */

int slref_fibers_build(const sl_hair *h, slref_fibers **out, sl_err *e);
void slref_fibers_free(slref_fibers *f);
/* 1 when the ray from o along the unit vector dir meets a fiber. */
int slref_fibers_occluded(const slref_fibers *f, const double o[3], const double dir[3]);
/* T_j(x) for the lobe (unit dir toward the light, lambda) from n samples; *std_err (may be NULL)
 * gets the estimate's standard error sqrt(T (1 - T) / n). */
double slref_transmittance(const slref_fibers *f, const double x[3], const double dir[3],
                           double lambda, int n, uint64_t seed, double *std_err);

#endif
