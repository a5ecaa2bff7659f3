/* lights.c: see lights.h. */
#include "lights.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct cell {
    double dir[3], rgb[3], lum;
} cell;

static int by_lum_desc(const void *a, const void *b) {
    double la = ((const cell *)a)->lum, lb = ((const cell *)b)->lum;
    return la < lb ? 1 : (la > lb ? -1 : 0);
}

int sl_lights_from_envmap(const sl_envmap *m, int cells_x, int cells_y, int max_lights,
                          double rotation_deg, double intensity, sl_lights *out, sl_err *e) {
    memset(out, 0, sizeof *out);
    if (cells_x < 1 || cells_y < 1 || max_lights < 1)
        return sl_fail(e, "lights: invalid cell grid %dx%d / %d lights", cells_x, cells_y,
                       max_lights);
    int nc = cells_x * cells_y;
    cell *c = sl_calloc((size_t)nc, sizeof *c);
    double rot = rotation_deg * 3.14159265358979323846 / 180.0, cr = cos(rot), sr = sin(rot);
    for (int y = 0; y < m->height; y++) {
        double dw = sl_envmap_pixel_solid_angle(m->width, m->height, y);
        int cy = y * cells_y / m->height;
        for (int x = 0; x < m->width; x++) {
            const float *px = m->rgb + 3 * ((size_t)y * m->width + x);
            double d[3];
            sl_envmap_dir(m->width, m->height, x, y, d);
            double rd[3] = {cr * d[0] + sr * d[2], d[1], -sr * d[0] + cr * d[2]};
            cell *k = &c[cy * cells_x + x * cells_x / m->width];
            double lum = 0.2126 * px[0] + 0.7152 * px[1] + 0.0722 * px[2];
            for (int i = 0; i < 3; i++) {
                k->rgb[i] += px[i] * dw * intensity;
                k->dir[i] += rd[i] * (lum * dw + 1e-12 * dw);
            }
            k->lum += lum * dw * intensity;
        }
    }
    for (int i = 0; i < nc; i++) {
        double l = sqrt(c[i].dir[0] * c[i].dir[0] + c[i].dir[1] * c[i].dir[1] +
                        c[i].dir[2] * c[i].dir[2]);
        for (int k = 0; k < 3; k++) c[i].dir[k] = l > 0 ? c[i].dir[k] / l : (k == 1);
    }
    qsort(c, (size_t)nc, sizeof *c, by_lum_desc);
    int keep = nc < max_lights ? nc : max_lights;
    /* Merge each dropped cell's power into the kept light closest in direction. */
    for (int i = keep; i < nc; i++) {
        int best = 0;
        double bd = -2;
        for (int j = 0; j < keep; j++) {
            double d = c[i].dir[0] * c[j].dir[0] + c[i].dir[1] * c[j].dir[1] +
                       c[i].dir[2] * c[j].dir[2];
            if (d > bd) bd = d, best = j;
        }
        for (int k = 0; k < 3; k++) c[best].rgb[k] += c[i].rgb[k];
    }
    out->count = keep;
    out->light = sl_calloc((size_t)keep, sizeof *out->light);
    for (int i = 0; i < keep; i++)
        for (int k = 0; k < 3; k++) {
            out->light[i].dir[k] = (float)c[i].dir[k];
            out->light[i].rgb[k] = (float)c[i].rgb[k];
        }
    free(c);
    return 0;
}

void sl_lights_free(sl_lights *l) {
    free(l->light);
    memset(l, 0, sizeof *l);
}
