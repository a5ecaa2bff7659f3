/* fiber_bsdf.c: see fiber_bsdf.h; one model file each (chiang_sample.c, deon_hit.c,
 * marschner_sample.c). */
#include "fiber_bsdf.h"

#include "chiang_sample.h"
#include "deon_hit.h"
#include "marschner_sample.h"

#include <string.h>

void slref_bsdf_init(slref_bsdf *b, const sl_material *m, double theta_o, double phi_o, double h) {
    b->m = m;
    b->nch = (m->sigma_a[0] == m->sigma_a[1] && m->sigma_a[1] == m->sigma_a[2]) ? 1 : 3;
    b->theta_o = theta_o, b->phi_o = phi_o;
    b->h = h > 1 ? 1 : (h < -1 ? -1 : h);
    if (m->model == SL_MODEL_CHIANG) {
        slref_chiang_bsdf_init(b);
        for (int c = b->nch; c < 3; c++)
            b->ck[c] = b->ck[0];
    } else if (m->model == SL_MODEL_DEON) {
        slref_deon_bsdf_init(b);
    } else {
        slref_marschner_bsdf_init(b);
    }
}

void slref_bsdf_eval(const slref_bsdf *b, double theta_i, double phi_i, double f[3],
                     double lobes[SLREF_NLOBES][3]) {
    if (b->m->model == SL_MODEL_CHIANG)
        slref_chiang_bsdf_eval(b, theta_i, phi_i, f, lobes);
    else if (b->m->model == SL_MODEL_DEON)
        slref_deon_bsdf_eval(b, theta_i, phi_i, f, lobes);
    else
        slref_marschner_bsdf_eval(b, theta_i, phi_i, f, lobes);
}

double slref_bsdf_pdf(const slref_bsdf *b, double theta_i, double phi_i) {
    if (b->m->model == SL_MODEL_CHIANG) return slref_chiang_bsdf_pdf(b, theta_i, phi_i);
    if (b->m->model == SL_MODEL_DEON) return slref_deon_bsdf_pdf(b, theta_i, phi_i);
    return slref_marschner_bsdf_pdf(b, theta_i, phi_i);
}

int slref_bsdf_sample(const slref_bsdf *b, slref_rng *r, double *theta_i, double *phi_i,
                      double *pdf) {
    int ok;
    if (b->m->model == SL_MODEL_CHIANG)
        ok = slref_chiang_bsdf_sample(b, r, theta_i, phi_i);
    else if (b->m->model == SL_MODEL_DEON)
        ok = slref_deon_bsdf_sample(b, r, theta_i, phi_i);
    else
        ok = slref_marschner_bsdf_sample(b, r, theta_i, phi_i);
    *pdf = ok ? slref_bsdf_pdf(b, *theta_i, *phi_i) : 0.0;
    return ok && *pdf > 0;
}
