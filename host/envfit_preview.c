/* envfit_preview.c: `fit --preview`: original | reconstruction | |error| side by side, one PNG
 * (tone mapped by sl_png_write at the same exposure, so the panels compare directly). Panels
 * wider than 1024 pixels are box-filtered down by an integer factor. */
#include "envfit.h"
#include "image_write.h"

#include <math.h>
#include <stdlib.h>

int sl_envfit_preview(const char *path, const sl_envmap *map, const sl_lobe *lobes, int n,
                      double exposure, sl_err *e) {
    int f = 1;
    while (map->width / f > 1024 && map->height / (f * 2) >= 1) f *= 2;
    int w = map->width / f, h = map->height / f, W = 3 * w;
    if (w < 1 || h < 1) return sl_fail(e, "%s: map too small for a preview", path);
    float *img = sl_calloc((size_t)W * h * 4, sizeof(float));
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double orig[3] = {0, 0, 0}, fit[3] = {0, 0, 0};
            for (int sy = 0; sy < f; sy++)
                for (int sx = 0; sx < f; sx++) {
                    int px = x * f + sx, py = y * f + sy;
                    const float *p = map->rgb + ((size_t)py * map->width + px) * 3;
                    double d[3], m[3];
                    sl_envmap_dir(map->width, map->height, px, py, d);
                    sl_lobes_eval(lobes, n, d, m);
                    for (int c = 0; c < 3; c++) {
                        orig[c] += p[c];
                        fit[c] += m[c];
                    }
                }
            for (int c = 0; c < 3; c++) {
                orig[c] /= f * f;
                fit[c] /= f * f;
                img[((size_t)y * W + x) * 4 + c] = (float)orig[c];
                img[((size_t)y * W + w + x) * 4 + c] = (float)fit[c];
                img[((size_t)y * W + 2 * w + x) * 4 + c] = (float)fabs(fit[c] - orig[c]);
            }
            for (int k = 0; k < 3; k++) img[((size_t)y * W + k * w + x) * 4 + 3] = 1.0f;
        }
    int rc = sl_png_write(path, W, h, img, (float)exposure, e);
    free(img);
    return rc;
}
