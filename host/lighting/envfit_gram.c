/* envfit_gram.c: closed-form integrals of products of two SRBFs and their derivatives.
 *
 * With x = a mu, a = 2 / lambda^2, an SRBF is G(omega) = exp(omega . x - |x|) (numerics.md
 * sec. 4). The product of two is exp(omega . v - a1 - a2) with v = x1 + x2, and
 * integral exp(omega . v) d omega = 4 pi sinh(R) / R, R = |v|. Writing f(R) = sinh(R) / R:
 *   I            = 4 pi e^{-a1-a2} f(R)
 *   dI/dx2       = 4 pi e^{-a1-a2} (f'(R)/R v - f(R) mu2)               (d|x2|/dx2 = mu2)
 *   d2I/dx1 dx2  = 4 pi e^{-a1-a2} [ f'/R Id + (f'' - f'/R)/R^2 v v^T
 *                                    - f'/R (v mu2^T + mu1 v^T) + f mu1 mu2^T ]
 * Every f-term is evaluated as e^{-R} f(R) and multiplied by e^{R-a1-a2} so that narrow lobes
 * (a up to ~10^5) neither overflow nor cancel. These are the exact L2(sphere) inner products the
 * Gauss-Newton matrix of the fit needs (the Jacobian columns are dG/dx times dx/dparams). */
#include "lighting/envfit_internal.h"

#include <math.h>

/* e^{-R} f(R), e^{-R} f'(R)/R and e^{-R} (f''(R) - f'(R)/R) / R^2. */
static void scaled_f(double R, double *f0, double *f1r, double *h) {
    if (R < 0.05) {
        /* Taylor series (f = sum R^2n / (2n+1)!); the next terms are below 1e-12 here. */
        double R2 = R * R, er = exp(-R);
        *f0 = er * (1 + R2 / 6 + R2 * R2 / 120 + R2 * R2 * R2 / 5040);
        *f1r = er * (1.0 / 3 + R2 / 30 + R2 * R2 / 840 + R2 * R2 * R2 / 45360);
        *h = er * (1.0 / 15 + R2 / 210 + R2 * R2 / 7560);
        return;
    }
    double q = exp(-2 * R);
    double sh = 0.5 * (1 - q), ch = 0.5 * (1 + q); /* e^{-R} sinh, e^{-R} cosh */
    double iR = 1 / R;
    *f0 = sh * iR;
    double f1 = ch * iR - sh * iR * iR;                             /* e^{-R} f' */
    double f2 = sh * iR - 2 * ch * iR * iR + 2 * sh * iR * iR * iR; /* e^{-R} f'' */
    *f1r = f1 * iR;
    *h = (f2 - *f1r) * iR * iR;
}

void efl_sg_pair(const double x1[3], const double x2[3], int want_derivs, efl_pair *p) {
    double a1 = sqrt(x1[0] * x1[0] + x1[1] * x1[1] + x1[2] * x1[2]);
    double a2 = sqrt(x2[0] * x2[0] + x2[1] * x2[1] + x2[2] * x2[2]);
    double v[3] = {x1[0] + x2[0], x1[1] + x2[1], x1[2] + x2[2]};
    double R = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    double ex = R - a1 - a2;
    if (ex < -700) {
        *p = (efl_pair){0};
        return;
    }
    double s = 4 * M_PI * exp(ex), f0, f1r, h;
    scaled_f(R, &f0, &f1r, &h);
    p->I = s * f0;
    if (!want_derivs) return;
    double m1[3], m2[3];
    for (int k = 0; k < 3; k++) {
        m1[k] = x1[k] / a1;
        m2[k] = x2[k] / a2;
    }
    for (int i = 0; i < 3; i++) {
        p->dI_dx1[i] = s * (f1r * v[i] - f0 * m1[i]);
        p->dI_dx2[i] = s * (f1r * v[i] - f0 * m2[i]);
        for (int k = 0; k < 3; k++)
            p->M[i][k] = s * ((i == k ? f1r : 0) + h * v[i] * v[k] -
                              f1r * (v[i] * m2[k] + m1[i] * v[k]) + f0 * m1[i] * m2[k]);
    }
}

double efl_sg_inner(const double mu1[3], double a1, const double mu2[3], double a2) {
    double x1[3] = {a1 * mu1[0], a1 * mu1[1], a1 * mu1[2]};
    double x2[3] = {a2 * mu2[0], a2 * mu2[1], a2 * mu2[2]};
    efl_pair p;
    efl_sg_pair(x1, x2, 0, &p);
    return p.I;
}
