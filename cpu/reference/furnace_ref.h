/* furnace_ref.h: the white-furnace integral (numerics.md sec. 5 `furnace`) in double: the
 * albedo integral over the sphere of f(omega_i, omega_o) d omega_i for either model, adaptive,
 * <= 1e-6 relative (chiang: a product of three adaptive 1-D integrals). d omega_i = cos(theta_i) d theta_i d phi_i because theta is the inclination
 * from the normal plane. Method and accuracy: docs/numerics-deon.md, docs/numerics-chiang.md. */
#ifndef SL_FURNACE_REF_H
#define SL_FURNACE_REF_H

#include "scene/material.h"

/* Albedo for outgoing direction (theta_o, phi_o), colour channel ch. With model deon,
 * sigma_a = 0 and all orders (explicit + rest), the exact value is 1 when every order shares one
 * alpha and beta (otherwise it differs from 1 by the alpha/beta mismatch only). With model chiang
 * and sigma_a = 0 it is 1 for every material (docs/numerics-chiang.md). */
double slref_furnace(const sl_material *m, int ch, double theta_o, double phi_o);

#endif
