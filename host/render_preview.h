/* render_preview.h: the PLACEHOLDER frame renderer used by `strandlight render` until the real
 * passes (deep opacity shadows, SRBF shading, multiple scattering, K-buffer) land.
 *
 * What it does: shades every strand vertex with the real Marschner/d'Eon fiber function
 * (kernels/fiber_*.h, C twin) against a few directional lights cut from the environment map
 * (host/lights.h), with NO shadowing and NO multiple scattering; then rasterizes the segments
 * as camera-facing ribbons with coverage antialiasing (sub-pixel strands keep their coverage)
 * and composites them with weighted blended order-independent transparency. */
#ifndef SL_RENDER_PREVIEW_H
#define SL_RENDER_PREVIEW_H

#include "camera.h"
#include "hair.h"
#include "lights.h"
#include "material.h"

typedef struct sl_frame {
    int width, height;
    float *rgba;  /* 4 * w * h, linear, rgb premultiplied by alpha (as OpenEXR stores it), row 0 top */
    float *depth; /* w * h, view depth of the nearest fragment, +inf where empty */
} sl_frame;

int sl_frame_alloc(sl_frame *f, int width, int height);
void sl_frame_free(sl_frame *f);

int sl_render_preview(const sl_material *mat, const sl_hair *h, const sl_lights *lights,
                      const sl_camera *cam, sl_frame *f, sl_err *e);

#endif
