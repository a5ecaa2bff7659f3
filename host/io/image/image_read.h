/* image_read.h: reading back an RGBA image (ours, or another renderer's: Blender Cycles writes
 * R, G, B, A), for `strandlight compare`. The pixels are decoded by the environment-map EXR
 * reader (io/envmap: OpenEXRCore, the C++ shim for DWA), which matches channels by name. */
#ifndef SL_IMAGE_READ_H
#define SL_IMAGE_READ_H

#include "base/common.h"

typedef struct sl_image {
    int width, height;
    float *rgba; /* 4 * width * height, interleaved, row 0 top, as stored (premultiplied) */
} sl_image;

/* Reads channels R, G, B, A of an EXR file. Errors name the file: missing, not an EXR, no A
 * channel, a NaN or infinite value (with its pixel). Returns 0, or -1 with e set and img empty. */
int sl_image_read_exr(const char *path, sl_image *img, sl_err *e);
/* The same with a layer's colour channels LAYER.R, LAYER.G, LAYER.B (an AOV: "MS", the path
 * tracer's "direct", "indirect") and A; layer NULL: R, G, B. */
int sl_image_read_exr_layer(const char *path, const char *layer, sl_image *img, sl_err *e);
void sl_image_free(sl_image *img);

#endif
