/* srbf_chiang_tables.c: model chiang's harmonic tables in the D buffer of the SRBF tables
 * (layout: kernels/srbf_deon.h, SL_SRBF_CH_*; use: kernels/srbf_chiang.h, the wide branch),
 * built in double with composite Gauss-Legendre (smooth integrands once written in
 * u = asin h, resp. split at the logistic's scale): about 1e-12 relative, far below float. */
#include "passes/shade/srbf_tables.h"

#include "srbf_deon.h"

#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846
#define NGL 20

/* The harmonics in the kernel's normalisation: h[0] = a_0 / (2 pi), h[n] = a_n / pi, so that a
 * function with cosine coefficients a_n is sum_n h[n] cos(n phi). */
static double norm_n(int n) {
    return n == 0 ? 1.0 / (2.0 * PI) : 1.0 / PI;
}

/* The wide branch's nodes in double: c_i = (1 - cos((2i + 1) pi / 2N)) / 2 (SL_SRBF_CH_C). */
static double node_c(int i) {
    return 0.5 * (1.0 - cos((2.0 * i + 1.0) * PI / (2.0 * SL_SRBF_CH_NODES)));
}

void sl_srbf_chiang_root_harmonics(int p, double x, double *out) {
    /* a_n = 1/2 int_{-1}^{1} L_i(cos u) cos(n Phi(p, h)) dh = int_0^{pi/2} L_i(cos u) cos u
     * cos(n Phi) du (Phi(p, -h) = 2 p pi - Phi(p, h): the integrand is even in u); 32 panels
     * of 20 points (cos(16 Phi) turns by <= 3.2 rad per panel: spectral accuracy) */
    double gx[NGL], gw[NGL];
    sl_srbf_gauss_legendre(NGL, gx, gw);
    memset(out, 0, sizeof(double) * SL_SRBF_CH_NHV * SL_SRBF_CH_NODES);
    double den[SL_SRBF_CH_NODES]; /* the Lagrange basis' denominators */
    for (int i = 0; i < SL_SRBF_CH_NODES; i++) {
        den[i] = 1.0;
        for (int k = 0; k < SL_SRBF_CH_NODES; k++)
            if (k != i) den[i] *= node_c(i) - node_c(k);
    }
    const int panels = 32;
    for (int q = 0; q < panels; q++) {
        double a = 0.5 * PI * q / panels, b = 0.5 * PI * (q + 1) / panels;
        for (int j = 0; j < NGL; j++) {
            double u = 0.5 * (a + b) + 0.5 * (b - a) * gx[j], cu = cos(u);
            double w = 0.5 * (b - a) * gw[j] * cu;
            double L[SL_SRBF_CH_NODES];
            for (int i = 0; i < SL_SRBF_CH_NODES; i++) {
                double v = 1.0;
                for (int k = 0; k < SL_SRBF_CH_NODES; k++)
                    if (k != i) v *= cu - node_c(k);
                L[i] = v / den[i];
            }
            double ph = 2.0 * p * asin(x * sin(u)) - 2.0 * u + p * PI;
            double c1 = cos(ph), cm = 1.0, cn = c1; /* cos(n ph) by the Chebyshev recurrence */
            for (int n = 0; n < SL_SRBF_CH_NHV; n++) {
                double c = (n == 0 ? 1.0 : cn) * w * norm_n(n);
                if (n > 0) {
                    double nx = 2.0 * c1 * cn - cm;
                    cm = cn;
                    cn = nx;
                }
                for (int i = 0; i < SL_SRBF_CH_NODES; i++)
                    out[n * SL_SRBF_CH_NODES + i] += c * L[i];
            }
        }
    }
}

/* d_n(s), n = 0..SL_SRBF_CH_NH: 2 / Z int_0^min(pi, 80 s) L_s(x) cos(n x) dx, Z = tanh(pi / 2s)
 * (the trimmed mass; beyond 80 s the logistic is below e^-80); panels of width <= s / 4 and
 * <= pi / 64. */
static void detector_all(double s, const double *gx, const double *gw, double d[SL_SRBF_CH_NHV]) {
    double top = fmin(PI, 80.0 * s), width = fmin(0.25 * s, PI / 64.0);
    int panels = (int)ceil(top / width);
    double acc[SL_SRBF_CH_NHV] = {0};
    for (int q = 0; q < panels; q++) {
        double a = top * q / panels, b = top * (q + 1) / panels;
        for (int j = 0; j < NGL; j++) {
            double x = 0.5 * (a + b) + 0.5 * (b - a) * gx[j], e = exp(-x / s);
            double w = 0.5 * (b - a) * gw[j] * e / (s * (1.0 + e) * (1.0 + e));
            double c1 = cos(x), cm = 1.0, cn = c1;
            for (int n = 1; n < SL_SRBF_CH_NHV; n++) {
                acc[n] += w * cn;
                double nx = 2.0 * c1 * cn - cm;
                cm = cn;
                cn = nx;
            }
        }
    }
    d[0] = 1.0;
    for (int n = 1; n < SL_SRBF_CH_NHV; n++)
        d[n] = 2.0 * acc[n] / tanh(0.5 * PI / s);
}

double sl_srbf_chiang_detector_exact(double s, int n) {
    double gx[NGL], gw[NGL], d[SL_SRBF_CH_NHV];
    sl_srbf_gauss_legendre(NGL, gx, gw);
    detector_all(s, gx, gw, d);
    return n >= 0 && n < SL_SRBF_CH_NHV ? d[n] : 0.0;
}

static double s_of(double i) {
    return exp(log(SL_SRBF_CH_SMIN) +
               (log(SL_SRBF_CH_SMAX) - log(SL_SRBF_CH_SMIN)) * i / (SL_SRBF_CH_NS - 1));
}

void sl_srbf_chiang_tables_build(float *D, double err[2]) {
    double h[SL_SRBF_CH_NHV * SL_SRBF_CH_NODES];
    double hmax = 0.0, e = 0.0;
    for (int p = 1; p <= 2; p++)
        for (int ix = 0; ix < SL_SRBF_CH_NX; ix++) {
            sl_srbf_chiang_root_harmonics(p, (double)ix / (SL_SRBF_CH_NX - 1), h);
            float *o = D + SL_SRBF_CH_OFF + (p - 1) * SL_SRBF_CH_SLICE +
                       ix * SL_SRBF_CH_NHV * SL_SRBF_CH_NODES;
            for (int n = 0; n < SL_SRBF_CH_NHV; n++)
                for (int i = 0; i < SL_SRBF_CH_NODES; i++) {
                    o[n * SL_SRBF_CH_NODES + i] = (float)h[n * SL_SRBF_CH_NODES + i];
                    hmax = fmax(hmax, fabs(h[n * SL_SRBF_CH_NODES + i]));
                }
        }
    /* the 1/eta' axis' linear interpolation at cell centres (every 8th cell) */
    for (int p = 1; p <= 2; p++)
        for (int ix = 0; ix + 1 < SL_SRBF_CH_NX; ix += 8) {
            sl_srbf_chiang_root_harmonics(p, (ix + 0.5) / (SL_SRBF_CH_NX - 1), h);
            const float *o = D + SL_SRBF_CH_OFF + (p - 1) * SL_SRBF_CH_SLICE +
                             ix * SL_SRBF_CH_NHV * SL_SRBF_CH_NODES;
            for (int k = 0; k < SL_SRBF_CH_NHV * SL_SRBF_CH_NODES; k++) {
                double lin = 0.5 * ((double)o[k] + o[k + SL_SRBF_CH_NHV * SL_SRBF_CH_NODES]);
                e = fmax(e, fabs(lin - h[k]));
            }
        }
    sl_srbf_chiang_root_harmonics(0, 0.0, h);
    for (int n = 0; n < SL_SRBF_CH_NHV; n++)
        for (int i = 0; i < SL_SRBF_CH_NODES; i++)
            D[SL_SRBF_CH_R_OFF + n * SL_SRBF_CH_NODES + i] = (float)h[n * SL_SRBF_CH_NODES + i];
    double ed = 0.0, gx[NGL], gw[NGL], d[SL_SRBF_CH_NHV];
    sl_srbf_gauss_legendre(NGL, gx, gw);
    for (int is = 0; is < SL_SRBF_CH_NS; is++) {
        detector_all(s_of(is), gx, gw, d);
        for (int n = 0; n < SL_SRBF_CH_NHV; n++)
            D[SL_SRBF_CH_DET_OFF + is * SL_SRBF_CH_NHV + n] = (float)d[n];
    }
    /* the log-s axis at cell centres (every 4th cell; d_n is <= 1) */
    for (int is = 0; is + 1 < SL_SRBF_CH_NS; is += 4) {
        detector_all(s_of(is + 0.5), gx, gw, d);
        for (int n = 1; n < SL_SRBF_CH_NHV; n++) {
            const float *b = D + SL_SRBF_CH_DET_OFF + is * SL_SRBF_CH_NHV + n;
            ed = fmax(ed, fabs(0.5 * ((double)b[0] + b[SL_SRBF_CH_NHV]) - d[n]));
        }
    }
    err[0] = e / hmax;
    err[1] = ed;
}
