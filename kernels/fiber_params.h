/* fiber_params.h: one colour channel of a fiber material as the float backends (C twin and
 * OpenCL) consume it; filled from the host's double sl_material by sl_material_to_fiber().
 * Layout is shared byte for byte between host and device: keep members 4-byte scalars. */
#ifndef SL_FIBER_PARAMS_H
#define SL_FIBER_PARAMS_H

#include "sl_compat.h"

typedef struct sl_fiber_params {
    sl_int model;   /* 0 marschner, 1 deon, 2 chiang */
    sl_int fresnel; /* 0 exact, 1 schlick */
    sl_int orders;  /* d'Eon explicit orders */
    sl_int pad0;
    float eta;
    float eccentricity;
    float caustic_width; /* w_c, radians */
    float sigma_a;       /* this channel's absorption per unit radius */
    float alpha[3];      /* R, TT, TRT shifts, radians */
    float beta[3];       /* R, TT, TRT widths, radians */
    float logistic_s;    /* chiang: azimuthal logistic scale s (numerics.md sec. 3) */
    float pad1;
} sl_fiber_params;

/* model 2 (chiang) stores its lobes in the d'Eon form: theta_o' = theta_o - 2 alpha[p] and
 * v_p = beta[p]^2 for p = 0, 1, 2 (R: alpha[0] = offset, TT: alpha[1] = -offset/2, TRT:
 * alpha[2] = -2 offset, i.e. R theta shifted by -2 offset, TT by +offset, TRT by +4 offset); the
 * p >= 3 term uses v_2 with no shift (pbrt-v4's HairBxDF), and orders is 2. */

#endif
