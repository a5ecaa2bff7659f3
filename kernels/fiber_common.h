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

#endif
