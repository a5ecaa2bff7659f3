/* envfit_preview.c: `fit --preview`: original | reconstruction | |error| side by side, one PNG
 * (tone mapped by sl_png_write at the same exposure, so the panels compare directly). The
 * reconstruction is the fit's pixel model (each lobe averaged over each pixel, envfit_eval.c),
 * so a sub-pixel sun shows as the pixel it lights. Panels wider than 1024 pixels are
 * box-filtered down by an integer factor. */
#include "lighting/envfit_internal.h"
#include "io/image/image_write.h"

#include <math.h>
#include <stdlib.h>

int sl_envfit_preview(const char *path, const sl_envmap *map, const sl_lobe *lobes, int n,
                      double exposure, sl_err *e) {
    int f = 1;
    while (map->width / f > 1024 && map->height / (f * 2) >= 1)
        f *= 2;
    int w = map->width / f, h = map->height / f, W = 3 * w;
    if (w < 1 || h < 1) return sl_fail(e, "%s: map too small for a preview", path);
    efl_level lv = {0};
    efl_level_geometry(&lv, map->width, map->height);
    lv.rgb = map->rgb; /* borrowed */
    efl_eval ev = {&lv, 2, 40.0, NULL, NULL};
    ev.res = sl_malloc(sizeof(double) * 3 * (size_t)map->width * map->height);
    efl_objective(&ev, lobes, n); /* res = model - map */
    float *img = sl_calloc((size_t)W * h * 4, sizeof(float));
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double orig[3] = {0, 0, 0}, fit[3] = {0, 0, 0};
            for (int sy = 0; sy < f; sy++)
                for (int sx = 0; sx < f; sx++) {
                    size_t i = ((size_t)(y * f + sy) * map->width + x * f + sx) * 3;
                    for (int c = 0; c < 3; c++) {
                        orig[c] += map->rgb[i + c];
                        fit[c] += map->rgb[i + c] + ev.res[i + c];
                    }
                }
            for (int c = 0; c < 3; c++) {
                orig[c] /= f * f;
                fit[c] /= f * f;
                img[((size_t)y * W + x) * 4 + c] = (float)orig[c];
                img[((size_t)y * W + w + x) * 4 + c] = (float)fit[c];
                img[((size_t)y * W + 2 * w + x) * 4 + c] = (float)fabs(fit[c] - orig[c]);
            }
            for (int k = 0; k < 3; k++)
                img[((size_t)y * W + k * w + x) * 4 + 3] = 1.0f;
        }
    free(ev.res);
    lv.rgb = NULL;
    efl_level_free(&lv);
    int rc = sl_png_write(path, W, h, img, (float)exposure, e);
    free(img);
    return rc;
}
