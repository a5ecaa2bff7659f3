/* mp_sample.c: see mp_sample.h. */
#include "mp_sample.h"

#include <math.h>

#define PI 3.14159265358979323846

double slref_mp_sample(double v, double theta_op, double u1, double u2) {
    /* log(u1 + (1 - u1) e^(-2/v)) as a log-sum-exp, so it stays finite when e^(-2/v)
     * underflows (narrow lobes) and u1 -> 0. lg is in [-2/v, 0]. */
    double a = log(u1), b = log1p(-u1) - 2.0 / v;
    double mx = a > b ? a : b, lg = mx + log1p(exp(-fabs(a - b)));
    if (!(lg > -2.0 / v)) lg = -2.0 / v;
    if (lg > 0) lg = 0;
    double one_m_cos = -v * lg; /* 1 - cos, in [0, 2] */
    double c = 1.0 - one_m_cos;
    /* sin^2 = (1 - cos)(1 + cos): no cancellation when the lobe is narrow */
    double s = sqrt(fmax(0.0, one_m_cos * (2.0 - one_m_cos)));
    double st = -c * sin(theta_op) + s * cos(2.0 * PI * u2) * cos(theta_op);
    if (st > 1) st = 1;
    if (st < -1) st = -1;
    return asin(st);
}
