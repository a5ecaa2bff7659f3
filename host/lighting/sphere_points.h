/* sphere_points.h: the direction set both broad-lobe mechanisms place around a lobe axis (the
 * shadow split, shadow_split.c, and the sub-lobes, lobe_subdivide.c): a spherical Fibonacci set
 * of M points with both poles on the axis, in a deterministic orthonormal frame of the axis. */
#ifndef SL_SPHERE_POINTS_H
#define SL_SPHERE_POINTS_H

#include <math.h>

/* pi (3 - sqrt 5): the golden angle between consecutive Fibonacci points */
#define SL_GOLDEN_ANGLE (M_PI * (3.0 - sqrt(5.0)))

/* An orthonormal frame (u, v) around the unit vector d (u from d x +X, or d x +Y near +-X). */
static inline void sl_axis_frame(const double d[3], double u[3], double v[3]) {
    double a[3] = {1, 0, 0};
    if (fabs(d[0]) > 0.9) a[0] = 0, a[1] = 1;
    u[0] = a[1] * d[2] - a[2] * d[1];
    u[1] = a[2] * d[0] - a[0] * d[2];
    u[2] = a[0] * d[1] - a[1] * d[0];
    double l = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int k = 0; k < 3; k++)
        u[k] /= l;
    v[0] = d[1] * u[2] - d[2] * u[1];
    v[1] = d[2] * u[0] - d[0] * u[2];
    v[2] = d[0] * u[1] - d[1] * u[0];
}

/* Point i of the M-point set with both poles on d (z = 1 - 2 i / (M - 1) along d; (u, v) from
 * sl_axis_frame). */
static inline void sl_fib_axis_point(int i, int M, const double d[3], const double u[3],
                                     const double v[3], double out[3]) {
    double z = 1.0 - 2.0 * i / (M - 1.0), r = sqrt(fmax(0.0, 1.0 - z * z)),
           ph = SL_GOLDEN_ANGLE * i;
    for (int k = 0; k < 3; k++)
        out[k] = z * d[k] + r * (cos(ph) * u[k] + sin(ph) * v[k]);
}

#endif
