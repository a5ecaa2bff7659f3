/* image_read.c: see image_read.h. */
#include "io/image/image_read.h"
#include "io/envmap/envmap.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SL_IMAGE_MAX_FILE ((size_t)1 << 32)

int sl_image_read_exr(const char *path, sl_image *img, sl_err *e) {
    return sl_image_read_exr_layer(path, NULL, img, e);
}

int sl_image_read_exr_layer(const char *path, const char *layer, sl_image *img, sl_err *e) {
    memset(img, 0, sizeof *img);
    unsigned char *data = NULL;
    size_t n = 0;
    if (sl_read_file(path, &data, &n, SL_IMAGE_MAX_FILE, e)) return -1;
    int rc =
        sl_exr_decode_layer_rgba(data, n, path, layer, &img->width, &img->height, &img->rgba, e);
    free(data);
    if (rc) return -1;
    /* a statistic over a non-finite pixel is meaningless: say where it is rather than print NaN */
    size_t np = (size_t)img->width * (size_t)img->height;
    for (size_t i = 0; i < 4 * np; i++)
        if (!isfinite(img->rgba[i])) {
            size_t p = i / 4;
            sl_fail(e, "%s: pixel (%zu, %zu) channel %c is not finite (%g)", path,
                    p % (size_t)img->width, p / (size_t)img->width, "RGBA"[i % 4],
                    (double)img -> rgba[i]);
            sl_image_free(img);
            return -1;
        }
    return 0;
}

void sl_image_free(sl_image *img) {
    free(img->rgba);
    memset(img, 0, sizeof *img);
}
