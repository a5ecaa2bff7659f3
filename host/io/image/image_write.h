/* image_write.h: image output. OpenEXR (any named float channels, for beauty + AOVs) through
 * OpenEXRCore, and 8-bit sRGB PNG (tone mapped) through stb_image_write. Both are written to a
 * temporary name beside the target and renamed when complete (parent directories are created),
 * so a failed write never leaves a partial file or a temporary behind. */
#ifndef SL_IMAGE_WRITE_H
#define SL_IMAGE_WRITE_H

#include "base/common.h"

typedef struct {
    const char *name;  /* EXR channel name, e.g. "R", "A", "R_mode.R", "depth.Z" */
    const float *data; /* planar w*h, row 0 top */
} sl_exr_channel;

/* Writes a single-part scanline EXR with ZIP compression, data window = display window =
 * (0,0)-(w-1,h-1). Channels are stored HALF, or FLOAT when use_float is set; a channel named "Z"
 * (depth) is always FLOAT. Half output
 * clamps finite values to +-65504 (the largest half) instead of overflowing to Inf; NaN and
 * Inf pass through. Names must be non-empty, unique and at most 255 bytes; OpenEXR stores the
 * channels sorted by name whatever the order given. Returns 0 or -1 with e set. */
int sl_exr_write(const char *path, int w, int h, const sl_exr_channel *ch, int nch, int use_float,
                 sl_err *e);

/* Writes an 8-bit RGBA PNG from linear, premultiplied RGBA floats (4*w*h, row 0 top).
 * Per pixel:
 *   1. un-premultiply: c = rgb / a where a > 0 (PNG stores straight alpha);
 *   2. exposure: c *= 2^exposure (exposure in stops; 0 leaves the values alone);
 *   3. tone map each channel with the ACES filmic fit of Narkowicz (2015),
 *      t(x) = x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), clamped to [0, 1]
 *      (negative and NaN inputs give 0, +Inf gives 1);
 *   4. exact sRGB OETF (IEC 61966-2-1): 12.92 t for t <= 0.0031308, else 1.055 t^(1/2.4) - 0.055;
 *   5. round to nearest of 0..255. Alpha is clamped to [0, 1], stays linear, rounded the same.
 * Returns 0 or -1 with e set. */
int sl_png_write(const char *path, int w, int h, const float *rgba, float exposure, sl_err *e);

/* The same two writers without the rename (issue 21, base/output_set.h): the file is written
 * completely and fsynced under a temporary name beside path, recorded in af (af->path, the
 * temporary af->tmp_path), for sl_output_set_commit to put in place together with others (a
 * render's EXR and PNG). On failure nothing is left and af->tmp_path is empty. */
int sl_exr_write_temp(const char *path, int w, int h, const sl_exr_channel *ch, int nch,
                      int use_float, sl_atomic_file *af, sl_err *e);
int sl_png_write_temp(const char *path, int w, int h, const float *rgba, float exposure,
                      sl_atomic_file *af, sl_err *e);

/* The per-channel display transform of steps 3-4 (tone map + sRGB OETF) as a value in [0, 1]. */
float sl_tonemap_srgb(float x);

#endif
