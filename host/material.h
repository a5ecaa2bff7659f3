/* material.h: the fiber material of numerics.md section 2, in double on the host (the reference
 * needs the exact decimal values; the float backends convert with sl_material_to_fiber()). */
#ifndef SL_MATERIAL_H
#define SL_MATERIAL_H

#include "common.h"

enum { SL_MODEL_MARSCHNER = 0, SL_MODEL_DEON = 1 };
enum { SL_FRESNEL_EXACT = 0, SL_FRESNEL_SCHLICK = 1 };

typedef struct sl_material {
    int model;           /* SL_MODEL_* */
    int fresnel;         /* SL_FRESNEL_* */
    int orders;          /* d'Eon explicit orders p = 0..orders (>= 2) */
    double eta;          /* index of refraction, > 1 */
    double alpha[3];     /* R, TT, TRT shifts, radians */
    double beta[3];      /* R, TT, TRT widths, radians (Marschner: Gaussian width; d'Eon: std) */
    double sigma_a[3];   /* absorption per unit radius, r g b */
    int sigma_a_rgb;     /* 1 when given as [r,g,b] or from melanin: outputs get _r/_g/_b */
    double eccentricity; /* a of Xu Eq. 24 (TRT only) */
    double caustic_width;/* w_c, radians */
} sl_material;

/* The defaults of numerics.md section 2. */
void sl_material_default(sl_material *m);

#endif
