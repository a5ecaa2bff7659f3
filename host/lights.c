/* lights.c: see lights.h. */
#include "lights.h"

#include <stdlib.h>
#include <string.h>

int sl_lights_from_lobes(const sl_lobes *l, sl_lights *out, sl_err *e) {
    memset(out, 0, sizeof *out);
    if (l->count < 1) return sl_fail(e, "environment: no lobes to light the scene with");
    out->count = l->count;
    out->light = sl_calloc((size_t)l->count, sizeof *out->light);
    for (int i = 0; i < l->count; i++) {
        double w = sl_lobe_integral(l->lobe[i].lambda);
        for (int k = 0; k < 3; k++) {
            out->light[i].dir[k] = (float)l->lobe[i].dir[k];
            out->light[i].rgb[k] = (float)(l->lobe[i].rgb[k] * w);
        }
    }
    return 0;
}

void sl_lights_free(sl_lights *l) {
    free(l->light);
    memset(l, 0, sizeof *l);
}
