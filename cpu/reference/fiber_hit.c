/* fiber_hit.c: see fiber_hit.h. */
#include "fiber_hit.h"

#include <math.h>

static double dot3(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

void slref_frame_angles(const double u[3], const double v[3], const double w[3], const double d[3],
                        double *th, double *ph) {
    double s = dot3(d, u);
    *th = asin(s > 1 ? 1 : (s < -1 ? -1 : s));
    *ph = atan2(dot3(d, w), dot3(d, v));
}

void slref_frame_dir(const double u[3], const double v[3], const double w[3], double th, double ph,
                     double d[3]) {
    double st = sin(th), ct = cos(th), cp = cos(ph), sp = sin(ph);
    for (int k = 0; k < 3; k++)
        d[k] = st * u[k] + ct * (cp * v[k] + sp * w[k]);
}

double slref_fiber_offset(const double o[3], const double d[3], const double p0[3],
                          const double u[3], double r) {
    /* o_n = the part of -d normal to u, normalised; n = u x o_n. (o + t d - p0) . n does not
     * depend on t because d . n = 0, so the ray origin gives the distance exactly. */
    double du = dot3(d, u), on[3], l = 0;
    for (int k = 0; k < 3; k++) {
        on[k] = -(d[k] - du * u[k]);
        l += on[k] * on[k];
    }
    if (!(l > 1e-24) || !(r > 0)) return 0.0;
    l = sqrt(l);
    double n[3] = {(u[1] * on[2] - u[2] * on[1]) / l, (u[2] * on[0] - u[0] * on[2]) / l,
                   (u[0] * on[1] - u[1] * on[0]) / l};
    double q[3] = {o[0] - p0[0], o[1] - p0[1], o[2] - p0[2]};
    double h = dot3(q, n) / r;
    return h > 1 ? 1 : (h < -1 ? -1 : h);
}
