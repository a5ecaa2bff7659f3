/* lights.h: directional lights that stand in for the SRBF lobes in the placeholder renderer
 * (host/render_preview.c) until the SRBF integration pass lands: each lobe becomes one light at
 * its centre carrying the lobe's power (rgb x integral of G over the sphere), i.e. the lobe's
 * response in the limit lambda -> 0. */
#ifndef SL_LIGHTS_H
#define SL_LIGHTS_H

#include "lobes_json.h"

typedef struct sl_dirlight {
    float dir[3]; /* unit, world frame, pointing from the scene toward the light */
    float rgb[3]; /* irradiance-like power: integral of radiance over the cell's solid angle */
} sl_dirlight;

typedef struct sl_lights {
    int count;
    sl_dirlight *light;
} sl_lights;

int sl_lights_from_lobes(const sl_lobes *l, sl_lights *out, sl_err *e);
void sl_lights_free(sl_lights *l);

#endif
