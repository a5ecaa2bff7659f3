/* fiber_bsdf.h: the fiber at one hit of the path tracer (docs/reference.md, "Path tracer"), in
 * double: evaluation of f (numerics.md sec. 3's measure: L_o = integral L_i f d omega_i, so f
 * holds cos theta_i), its split into lobes, and importance sampling with the exact density of
 * what is sampled (solid angle), so a path's weight f / pdf is exact:
 *
 *   chiang (model 2): per hit offset h (chiang_hit.h); lobe p by the channel mean of A_p(h),
 *     M_p exactly (mp_sample.h), the azimuth by the trimmed logistic (pbrt-v4 HairBxDF);
 *   deon (model 1): per hit offset h (deon_hit.h), sampled in two stages of exact densities
 *     (deon_hit.h says which), weighted by the true f / pdf;
 *   marschner (model 0): the width-averaged f (marschner_ref.h; its azimuth is a sum over roots,
 *     with no per-h form), sampled with a proposal (marschner_sample.h).
 *
 * Angles are in the hit's fiber frame (numerics.md sec. 1); omega_o is fixed at init. Lobes:
 * R, TT, TRT and the rest (chiang p >= 3; deon the orders p >= 3 and f_rest; marschner none). */
#ifndef SL_FIBER_BSDF_H
#define SL_FIBER_BSDF_H

#include "path_rng.h"
#include "scene/material.h"

#include "chiang_hit.h"

enum { SLREF_LOBE_R = 0, SLREF_LOBE_TT, SLREF_LOBE_TRT, SLREF_LOBE_REST, SLREF_NLOBES };

/* deon: explicit orders 0..orders, plus the rest */
#define SLREF_DEON_LOBES_MAX (SL_MATERIAL_MAX_ORDERS + 2)

typedef struct slref_bsdf {
    const sl_material *m;
    int nch; /* colour channels evaluated: 1 when sigma_a is grey (copied to the others) */
    double theta_o, phi_o, h;
    /* chiang: the hit per channel, the lobe probabilities */
    slref_chiang_hit ck[3];
    double ap_pdf[4];
    /* deon: probabilities of the longitudinal lobes R, TT, TRT (deon_hit.h) */
    double dw[3];
    /* marschner: lobe probabilities, in-range mass of each theta_h Gaussian */
    double mw[3], mz[3];
} slref_bsdf;

/* The fiber of material m seen from omega_o = (theta_o, phi_o) at offset h in [-1, 1]. */
void slref_bsdf_init(slref_bsdf *b, const sl_material *m, double theta_o, double phi_o, double h);

/* f(omega_i, omega_o) per channel; lobes (may be NULL): lobes[l][c], summing to f. */
void slref_bsdf_eval(const slref_bsdf *b, double theta_i, double phi_i, double f[3],
                     double lobes[SLREF_NLOBES][3]);

/* The density (per solid angle) with which slref_bsdf_sample draws omega_i. */
double slref_bsdf_pdf(const slref_bsdf *b, double theta_i, double phi_i);

/* Draws omega_i = (theta_i, phi_i) from r with density *pdf (slref_bsdf_pdf). Returns 0 when no
 * direction came out (then the sample's weight is 0; the density stays exact for the others). */
int slref_bsdf_sample(const slref_bsdf *b, slref_rng *r, double *theta_i, double *phi_i,
                      double *pdf);

#endif
