/* fiber_hit.h: the geometry of a ray meeting a fiber, for the path tracer (docs/reference.md,
 * "Path tracer"): angles in the fiber frame (numerics.md sec. 1, the frame of
 * slref_fiber_frame) and the offset h of the ray across the fiber.
 *
 * Sign of h: with omega_o = -d (toward the viewer) and o_n its unit projection on the normal
 * plane, h = ((o - p0) . (u x o_n)) / r, the ray's signed distance from the axis along u x o_n.
 * Then the specular reflection at h leaves with phi_o - phi_i = -2 asin h = Phi(0, h) (the
 * reflected direction is omega_i of the path): the convention of chiang_hit.h and of d'Eon's
 * Phi(p, h), checked by the unit test path_offset_reflection_phi. */
#ifndef SL_FIBER_HIT_H
#define SL_FIBER_HIT_H

/* th in [-pi/2, pi/2], ph in (-pi, pi] of the unit world direction d in the frame (u, v, w). */
void slref_frame_angles(const double u[3], const double v[3], const double w[3], const double d[3],
                        double *th, double *ph);
/* The unit world direction (sin th, cos th cos ph, cos th sin ph) in the frame (u, v, w). */
void slref_frame_dir(const double u[3], const double v[3], const double w[3], double th, double ph,
                     double d[3]);
/* h in [-1, 1] of the ray o + t d (d unit) on the fiber of axis p0 + s u (u unit) and radius r.
 * Computed from the ray and the axis, not from the hit point, so the float distance of the hit
 * does not enter; 0 for a ray along the axis. Clamped: a hit on a joint's cap may lie outside. */
double slref_fiber_offset(const double o[3], const double d[3], const double p0[3],
                          const double u[3], double r);

#endif
