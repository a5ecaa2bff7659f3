/* envmap.h: environment maps (lat-long radiance) loaded from OpenEXR or Radiance .hdr.
 *
 * Layout and frame (numerics.md sec. 4): rgb is W*H*3 floats, row 0 at the top; pixel (x, y) has
 * polar angle th = pi (y+0.5)/H from +Y and azimuth ph = 2pi (x+0.5)/W - pi, direction
 * (sin th sin ph, cos th, -sin th cos ph): the image centre looks down -Z.
 * Negative values (lossy EXR ringing) are clamped to 0 with a warning that states how many;
 * NaN/Inf values are an error naming how many unless clamp_nonfinite is set (then 0 + warning).
 *
 * Formats (chosen by the file's magic bytes, not its name):
 * - OpenEXR through OpenEXRCore: RGB or RGBA (alpha ignored), or a single Y channel (grey),
 *   half or float, scanline or tiled (level 0 of a mip/rip-mapped file), any channel order
 *   (matched by name), first part of a multi-part file. DWAA/DWAB, which OpenEXRCore 3.1 cannot
 *   decode, go through the OpenEXR C++ API (host/io/envmap/exr_cxx_shim.h).
 * - Radiance RGBE (.hdr, "#?RADIANCE"/"#?RGBE", FORMAT=32-bit_rle_rgbe, "-Y H +X W") through
 *   stb_image, value = mantissa * 2^(E-136) (stb's convention). The scanline structure is
 *   validated first, so a truncated or corrupt file is an error, never a hang or a read past
 *   the end.
 * Limits: width and height <= SL_ENVMAP_MAX_DIM, width*height <= SL_ENVMAP_MAX_PIXELS, and the
 * declared size must be plausible for the file size (a few bytes cannot hold a gigapixel map);
 * every limit is checked before any pixel buffer is allocated. */
#ifndef SL_ENVMAP_H
#define SL_ENVMAP_H

#include "base/common.h"

#define SL_ENVMAP_MAX_DIM 65536
#define SL_ENVMAP_MAX_PIXELS (1L << 27) /* 16384 x 8192: 1.5 GiB of float RGB */
#define SL_ENVMAP_MAX_FILE ((size_t)1 << 31)

typedef struct sl_envmap {
    int width, height;
    float *rgb;             /* width*height*3, linear radiance, >= 0, finite */
    char format[64];        /* e.g. "OpenEXR half RGB (DWAB)" or "Radiance RGBE" */
    int channels;           /* channels in the file (3 or 4 for RGB[A]; 1 or 2 for Y[A]; more
                               when the file has extra channels, which are ignored) */
    long negatives;         /* values clamped from < 0 to 0 at load */
    long nonfinite;         /* non-finite values replaced (only with clamp_nonfinite) */
    uint64_t hash;          /* hash of the decoded pixels (cache keys for fitted lobes) */
    char channel_names[64]; /* the file's channels in file order, e.g. "B,G,R" or "RGBE" */
} sl_envmap;

int sl_envmap_load(const char *path, int clamp_nonfinite, sl_envmap *out, sl_err *e);
/* The same from bytes already in memory; name is used in messages only (fuzzing, embedded
 * data). */
int sl_envmap_load_memory(const unsigned char *data, size_t n, const char *name,
                          int clamp_nonfinite, sl_envmap *out, sl_err *e);
void sl_envmap_free(sl_envmap *m);

/* World direction of the centre of pixel (x, y) of a w x h map (numerics.md sec. 4). x and y
 * are continuous pixel indices: (0, 0) is the centre of the top-left pixel. */
void sl_envmap_dir(int w, int h, double x, double y, double dir[3]);
/* Inverse of sl_envmap_dir for a unit (or any non-zero) direction: continuous pixel indices,
 * x in [-0.5, w-0.5), y in [-0.5, h-0.5]. */
void sl_envmap_dir_to_pixel(int w, int h, const double dir[3], double *x, double *y);
/* Solid angle of one pixel in row y: exactly (2pi/w)(cos(pi y/h) - cos(pi (y+1)/h)), so the
 * pixels of a map sum to 4pi. */
double sl_envmap_pixel_solid_angle(int w, int h, int y);

/* Statistics of a loaded map; luminance is Rec.709, Y = 0.2126 R + 0.7152 G + 0.0722 B. */
typedef struct sl_envmap_stats {
    double lum_min, lum_max;
    double lum_mean_pixel;       /* plain mean over pixels */
    double lum_mean_solid_angle; /* (1/4pi) sum Y_i Omega_i: mean radiance over the sphere */
    double rgb_mean_pixel[3], rgb_mean_solid_angle[3];
    int max_x, max_y;    /* brightest pixel (largest Y; first in scan order on ties) */
    double max_elev_deg; /* elevation of its centre above the horizon, 90 - th in degrees */
    double max_dir[3];   /* its direction in the world frame */
} sl_envmap_stats;
void sl_envmap_stats_compute(const sl_envmap *m, sl_envmap_stats *s);

/* `strandlight info` for an environment map: format, size, channels, min/max/mean luminance
 * (per pixel and solid-angle weighted), per-channel means, brightest pixel and its direction,
 * negative values clamped, non-finite values (counted, not an error here: they are reported and
 * replaced by 0 for the statistics), hash. Returns 0 or -1 with e set (unreadable or corrupt
 * file). */
int sl_envmap_info(const char *path, FILE *out, sl_err *e);

/* ---- Internals shared by the envmap*.c files and their tests. ---- */

/* Decoders: fill out->width/height/rgb/format/channels/channel_names with the raw decoded
 * values (negatives and non-finite values kept). They never print. */
int sl_envmap_decode_hdr(const unsigned char *data, size_t n, const char *name, sl_envmap *out,
                         sl_err *e);
/* force_cxx: decode through the C++ API even when OpenEXRCore could (tests compare the two). */
int sl_envmap_decode_exr(const unsigned char *data, size_t n, const char *name, int force_cxx,
                         sl_envmap *out, sl_err *e);
/* An EXR image rather than a map: channels R, G, B and A (an error naming the file's channels
 * when one is missing), any compression the map decoder reads, as interleaved RGBA floats
 * (4*w*h, row 0 top, values as stored: nothing clamped). io/image/image_read.h wraps it. */
int sl_exr_decode_rgba(const unsigned char *data, size_t n, const char *name, int *w, int *h,
                       float **rgba, sl_err *e);
/* The same with the colour planes of a layer: LAYER.R, LAYER.G, LAYER.B, and A (layer NULL:
 * R, G, B). */
int sl_exr_decode_layer_rgba(const unsigned char *data, size_t n, const char *name,
                             const char *layer, int *w, int *h, float **rgba, sl_err *e);
/* Decodes by magic bytes (EXR or Radiance), without sanitizing. */
int sl_envmap_decode_memory(const unsigned char *data, size_t n, const char *name, sl_envmap *out,
                            sl_err *e);
/* True when a declared w x h is within SL_ENVMAP_MAX_DIM / SL_ENVMAP_MAX_PIXELS and plausible
 * for a file of n bytes: at most max_pixels_per_byte * n pixels (any file may hold 2^20). */
int sl_envmap_size_ok(long long w, long long h, size_t n, double max_pixels_per_byte);

/* Decode limits from the header, before any pixel is decoded (issue 21: a 49 KB DWAB file
 * declaring 16384 x 8192 cost 13.6 s and 3.16 GB). For a px-pixel image whose file holds
 * raw_bytes_per_px bytes per pixel once decompressed (all its channels) and whose decoder keeps
 * out_bytes_per_px bytes per pixel at its peak:
 * - memory: px x out_bytes_per_px must stay within SL_IMAGE_MAX_MB MiB (default
 *   SL_IMAGE_MAX_MB_DEFAULT: an 8192 x 4096 RGBA map decodes in about 1.4 GiB);
 * - work: the decompressed bytes may exceed SL_IMAGE_MAX_RATIO (default
 *   SL_IMAGE_MAX_RATIO_DEFAULT) times the file's size only below SL_IMAGE_RATIO_FLOOR bytes
 *   (a flat test map of a few KB is fine). Deflate cannot pass 1032:1 and real DWA maps stay
 *   under 50:1, so only a decompression bomb (DWA's flat blocks, PIZ's runs) is refused.
 * Either is a one-line error naming the file, the limit and the variable that raises it. */
#define SL_IMAGE_MAX_MB_DEFAULT 2048
#define SL_IMAGE_MAX_RATIO_DEFAULT 1100
#define SL_IMAGE_RATIO_FLOOR ((double)(16 << 20))
int sl_decode_budget_ok(const char *name, const char *what, long long w, long long h,
                        double raw_bytes_per_px, double out_bytes_per_px, size_t file_bytes,
                        sl_err *e);

/* How sl_envmap_sanitize treats NaN/Inf. */
enum { SL_NONFINITE_ERROR = 0, SL_NONFINITE_CLAMP_WARN = 1, SL_NONFINITE_CLAMP_QUIET = 2 };
/* Counts and clamps negatives (warning unless quiet) and non-finite values (per mode), then
 * computes the hash. Returns -1 with e set in SL_NONFINITE_ERROR mode when any is found. */
int sl_envmap_sanitize(sl_envmap *m, const char *name, int nonfinite_mode, sl_err *e);

#endif
