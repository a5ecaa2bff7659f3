/* fiber_params.h: one colour channel of a fiber material as the float backends (C twin and
 * OpenCL) consume it; filled from the host's double sl_material by sl_material_to_fiber().
 * Layout is shared byte for byte between host and device: keep members 4-byte scalars. */
#ifndef SL_FIBER_PARAMS_H
#define SL_FIBER_PARAMS_H

#include "sl_compat.h"

typedef struct sl_fiber_params {
    sl_int model;         /* 0 marschner, 1 deon */
    sl_int fresnel;       /* 0 exact, 1 schlick */
    sl_int orders;        /* d'Eon explicit orders */
    sl_int pad0;
    float eta;
    float eccentricity;
    float caustic_width;  /* w_c, radians */
    float sigma_a;        /* this channel's absorption per unit radius */
    float alpha[3];       /* R, TT, TRT shifts, radians */
    float beta[3];        /* R, TT, TRT widths, radians */
} sl_fiber_params;

#endif
