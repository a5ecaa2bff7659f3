/* srbf_ref.h: the exact single-scattering response of a fiber to one SRBF light (numerics.md
 * sec. 4, Xu 2011 Eq. 11) in double precision, the `eval srbf --backend reference --method exact`
 * path and the yardstick of every closed form (docs/srbf.md):
 *
 *   I_t(omega_o; omega_j, lambda) = integral over the sphere of G(omega_i) f_t(omega_i, omega_o)
 *                                   d omega_i,   G = exp(2 (omega_i . omega_j - 1) / lambda^2).
 *
 * Adaptive (vector Gauss-Kronrod) in theta_i of an inner azimuthal integral; relative error
 * <= 1e-4 of max(I_t, 0.03 int G) (measured in test/passes/shade/test_srbf.c). Slow: milliseconds to seconds
 * per value (d'Eon with many orders and eccentric fibers: seconds). */
#ifndef SL_SRBF_REF_H
#define SL_SRBF_REF_H

#include "scene/material.h"

/* out receives sl_eval_num_outputs(SL_EVAL_SRBF, m) values: marschner I_R, I_TT, I_TRT, I;
 * deon I_0..I_orders, I_rest, I; chiang I_0, I_1, I_2, I_rest, I. Angles in the fiber frame (numerics.md sec. 1), lambda > 0,
 * colour channel ch (sigma_a[ch]). Never NaN/Inf for inputs in range. */
void slref_srbf(const sl_material *m, int ch, double theta_o, double phi_o, double theta_j,
                double phi_j, double lambda, double *out);

/* int G d omega = pi lambda^2 (1 - exp(-4/lambda^2)) (numerics.md sec. 5: error floor). */
double slref_srbf_lobe_integral(double lambda);

/* The error measure of numerics.md sec. 5: |x - exact| / max(exact, 0.03 int G). */
double slref_srbf_error(double x, double exact, double lambda);

#endif
