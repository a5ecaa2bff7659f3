/* material.c: material defaults (numerics.md section 2). */
#include "material.h"

#include <string.h>

#define DEG (3.14159265358979323846 / 180.0)

void sl_material_default(sl_material *m) {
    memset(m, 0, sizeof *m);
    m->model = SL_MODEL_MARSCHNER;
    m->fresnel = SL_FRESNEL_EXACT;
    m->orders = 8;
    m->eta = 1.55;
    /* Xu 2011 Sec. 6: alpha_TT = -alpha_R/2, alpha_TRT = -3 alpha_R/2, beta_TT = beta_R/2,
     * beta_TRT = 2 beta_R. */
    m->alpha[0] = -7.5 * DEG;
    m->alpha[1] = 3.75 * DEG;
    m->alpha[2] = 11.25 * DEG;
    m->beta[0] = 7.5 * DEG;
    m->beta[1] = 3.75 * DEG;
    m->beta[2] = 15.0 * DEG;
    m->sigma_a[0] = m->sigma_a[1] = m->sigma_a[2] = 0.36;
    m->eccentricity = 1.0;
    m->caustic_width = 15.0 * DEG;
}
