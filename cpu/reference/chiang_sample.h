/* chiang_sample.h: model chiang at one hit for fiber_bsdf.h: evaluation from chiang_hit.h with
 * the channel-independent M_p and N_p computed once, and pbrt-v4's HairBxDF::Sample_f / Pdf
 * (Chiang 2016 Sec. 4): lobe p with probability ap_pdf[p] = mean_c A_p / sum_p mean_c A_p,
 * theta_i from M_p exactly (mp_sample.h), phi = Phi(p, h) + a trimmed logistic sample (p < 3) or
 * uniform (p = 3). pdf = sum_p ap_pdf[p] M_p N_p: then f / pdf = sum_p A_p for a grey sigma_a. */
#ifndef SL_CHIANG_SAMPLE_H
#define SL_CHIANG_SAMPLE_H

#include "fiber_bsdf.h"

void slref_chiang_bsdf_init(slref_bsdf *b);
void slref_chiang_bsdf_eval(const slref_bsdf *b, double theta_i, double phi_i, double f[3],
                            double lobes[SLREF_NLOBES][3]);
double slref_chiang_bsdf_pdf(const slref_bsdf *b, double theta_i, double phi_i);
int slref_chiang_bsdf_sample(const slref_bsdf *b, slref_rng *r, double *theta_i, double *phi_i);

#endif
