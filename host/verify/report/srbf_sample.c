/* srbf_sample.c: the stiff SRBF sample (see srbf_sample.h). A private xorshift generator keeps
 * it identical on every platform (no rand()). */
#include "verify/report/srbf_sample.h"

#include <math.h>

#define PI 3.14159265358979323846
#define DEG (PI / 180.0)

static const char *const names[SL_SRBF_SAMPLE_MATERIALS] = {"default", "dark", "blond-sharp",
                                                            "sharp", "eccentric"};

const char *sl_srbf_sample_material_name(int i) {
    return i >= 0 && i < SL_SRBF_SAMPLE_MATERIALS ? names[i] : "?";
}

void sl_srbf_sample_material(int i, sl_material *m) {
    sl_material_default(m);
    switch (i) {
    case 1: /* dark: TT and TRT nearly absorbed, R dominates */
        m->sigma_a[0] = m->sigma_a[1] = m->sigma_a[2] = 3.0;
        break;
    case 2: /* blond, sharp: little absorption, beta_R = 2.5 deg (TT 1.25, TRT 5) */
        m->sigma_a[0] = m->sigma_a[1] = m->sigma_a[2] = 0.08;
        m->beta[0] = 2.5 * DEG;
        m->beta[1] = 1.25 * DEG;
        m->beta[2] = 5.0 * DEG;
        break;
    case 3: /* sharp: beta_R = 4 deg */
        m->beta[0] = 4.0 * DEG;
        m->beta[1] = 2.0 * DEG;
        m->beta[2] = 8.0 * DEG;
        break;
    case 4: /* eccentric (Xu Eq. 24) */
        m->eccentricity = 0.85;
        break;
    default:
        break;
    }
}

static double next(unsigned long long *s) {
    unsigned long long x = *s;
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    *s = x;
    return (double)(x >> 11) * (1.0 / 9007199254740992.0); /* [0, 1) */
}

static double wrap(double a) {
    return a - 2.0 * PI * floor((a + PI) / (2.0 * PI));
}

void sl_srbf_sample(unsigned seed, int n, sl_srbf_config *cfg) {
    unsigned long long s = 0x9e3779b97f4a7c15ull ^ ((unsigned long long)seed << 17);
    for (int w = 0; w < 8; w++)
        next(&s);
    for (int i = 0; i < n; i++) {
        sl_srbf_config *c = cfg + i;
        c->material = i % SL_SRBF_SAMPLE_MATERIALS;
        sl_material m;
        sl_srbf_sample_material(c->material, &m);
        c->lambda = exp(log(0.05) + (log(1.0) - log(0.05)) * next(&s));
        double u = next(&s);
        double sign = next(&s) < 0.5 ? -1.0 : 1.0;
        c->theta_o =
            sign * (u < 1.0 / 3.0 ? (60.0 + 20.0 * next(&s)) * DEG : 60.0 * DEG * next(&s));
        c->phi_o = wrap(2.0 * PI * next(&s));
        double kind = next(&s);
        if (kind < 0.15) { /* a lobe at a pole */
            c->theta_j = next(&s) < 0.5 ? -0.5 * PI : 0.5 * PI;
            c->phi_j = wrap(2.0 * PI * next(&s));
        } else {
            /* on mode t's cone: theta_j = 2 alpha_t - theta_o + offset (a few widths) */
            int t = (int)(3.0 * next(&s));
            if (t > 2) t = 2;
            double width = sqrt(c->lambda * c->lambda + 4.0 * m.beta[t] * m.beta[t]);
            double off = (2.0 * next(&s) - 1.0) * 1.5 * width;
            double tj = 2.0 * m.alpha[t] - c->theta_o + off;
            if (tj > 0.5 * PI) tj = 0.5 * PI;
            if (tj < -0.5 * PI) tj = -0.5 * PI;
            c->theta_j = tj;
            /* azimuth: R anywhere, TT near forward scattering (phi_o - phi_j ~ pi), TRT anywhere */
            double dphi = t == 1 ? PI + (2.0 * next(&s) - 1.0) * 1.2 : wrap(2.0 * PI * next(&s));
            c->phi_j = wrap(c->phi_o - dphi);
        }
    }
}

void sl_srbf_config_row(const sl_srbf_config *c, float row[5]) {
    row[0] = (float)c->theta_o;
    row[1] = (float)c->phi_o;
    row[2] = (float)c->theta_j;
    row[3] = (float)c->phi_j;
    row[4] = (float)c->lambda;
}
