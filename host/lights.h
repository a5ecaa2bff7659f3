/* lights.h: a small set of directional lights that stands in for an environment map in the
 * placeholder renderer (host/render_preview.c) until the SRBF shading passes land: the map is cut
 * into cells of equal angular size, each cell becomes one light carrying the cell's power
 * (sum of radiance x solid angle) from its power-weighted mean direction, and the weakest cells
 * are merged into their nearest kept neighbour so that no energy is lost. */
#ifndef SL_LIGHTS_H
#define SL_LIGHTS_H

#include "envmap.h"

typedef struct sl_dirlight {
    float dir[3]; /* unit, world frame, pointing from the scene toward the light */
    float rgb[3]; /* irradiance-like power: integral of radiance over the cell's solid angle */
} sl_dirlight;

typedef struct sl_lights {
    int count;
    sl_dirlight *light;
} sl_lights;

/* rotation_deg turns the map about +Y; intensity scales it. */
int sl_lights_from_envmap(const sl_envmap *m, int cells_x, int cells_y, int max_lights,
                          double rotation_deg, double intensity, sl_lights *out, sl_err *e);
void sl_lights_free(sl_lights *l);

#endif
