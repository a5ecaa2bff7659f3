/* envmap.h: environment maps (lat-long radiance) loaded from OpenEXR or Radiance .hdr.
 *
 * Layout and frame (numerics.md sec. 4): rgb is W*H*3 floats, row 0 at the top; pixel (x, y) has
 * polar angle th = pi (y+0.5)/H from +Y and azimuth ph = 2pi (x+0.5)/W - pi, direction
 * (sin th sin ph, cos th, -sin th cos ph): the image centre looks down -Z.
 * Negative values (lossy EXR ringing) are clamped to 0 with a warning that states how many;
 * NaN/Inf pixels are an error naming how many unless clamp_nonfinite is set (then 0 + warning). */
#ifndef SL_ENVMAP_H
#define SL_ENVMAP_H

#include "common.h"

typedef struct sl_envmap {
    int width, height;
    float *rgb;          /* width*height*3, linear radiance, >= 0, finite */
    char format[64];     /* e.g. "OpenEXR half RGB (DWAB)" or "Radiance RGBE" */
    int channels;        /* channels in the file (3 or 4) */
    long negatives;      /* values clamped from < 0 to 0 at load */
    long nonfinite;      /* non-finite values replaced (only with clamp_nonfinite) */
    uint64_t hash;       /* hash of the decoded pixels (cache keys for fitted lobes) */
} sl_envmap;

int sl_envmap_load(const char *path, int clamp_nonfinite, sl_envmap *out, sl_err *e);
void sl_envmap_free(sl_envmap *m);

/* World direction of the centre of pixel (x, y) of a w x h map (numerics.md sec. 4). */
void sl_envmap_dir(int w, int h, double x, double y, double dir[3]);
/* Solid angle of one pixel in row y. */
double sl_envmap_pixel_solid_angle(int w, int h, int y);

/* `strandlight info` for an environment map: size, channels, min/max/mean luminance,
 * non-finite pixel count. Returns 0 or -1 with e set. */
int sl_envmap_info(const char *path, FILE *out, sl_err *e);

#endif
