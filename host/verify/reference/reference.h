/* reference.h: the brute-force reference render of a scene (`strandlight reference`, issue 10;
 * docs/reference.md): the environment map as N directional lights (median cut, envsample.h),
 * the exact double-precision fiber function per light, visibility by shadow rays through the
 * actual fibers (Embree), optional dual scattering along the traced shadow rays. The same
 * camera and pixels as `strandlight render` (camera.h, framed the same way).
 *
 * For `strandlight report`:
 *   sl_reference_settings set; sl_reference_settings_default(&set); set.lights = 1000;
 *   sl_reference_result res;
 *   if (sl_reference_run(&scene, &set, "report/x/ref.exr", 1, &res, &e)) ... (cached by key)
 *   sl_reference_frame ref; sl_reference_load("report/x/ref.exr", &ref, &e);
 *   double rmse, p99; sl_image_error(x_rgba, ref.rgba, w, h, &rmse, rgb3, &p99);  */
#ifndef SL_REFERENCE_H
#define SL_REFERENCE_H

#include "base/common.h"
#include "scene/scene.h"

#include <stdint.h>

typedef struct sl_reference_settings {
    int lights;          /* N directional lights cut from environment.file (>= 1) */
    int aa;              /* aa x aa jittered camera rays per pixel (>= 1) */
    uint64_t seed;       /* jitter seed */
    int threads;         /* 0: every online CPU; the image does not depend on it */
    int ms;              /* -1: the scene's quality.multiple_scattering (auto: on for marschner),
                            0 off, 1 on */
    int width, height;   /* 0: the scene's */
    int progress;        /* 1: progress bar with ETA on stderr (when it is a terminal) */
    int clamp_nonfinite; /* environment map: replace NaN/Inf by 0 instead of failing */
    int light_split;     /* 1: the aa x aa rays of a pixel share the lights (slref_render_opts) */
    int fragments;       /* 1: fragment mode (docs/reference.md): shade the fast path's K-buffer
                            entries (cpu/reference/render_ref_frag.h) instead of camera rays;
                            aa, seed and light_split are then unused */
} sl_reference_settings;

/* 256 lights, aa 2, seed 1, light_split on, pixel mode */
void sl_reference_settings_default(sl_reference_settings *s);

typedef struct sl_reference_frame {
    int width, height;
    float *rgba;     /* 4 * w * h, rgb premultiplied by alpha (coverage), row 0 at the top */
    float *depth;    /* w * h, nearest view depth, +inf where empty */
    float *ms_rgb;   /* 3 * w * h, the multiple-scattering part of rgb (premultiplied) */
    float *mode_rgb; /* 9 * w * h: single scattering by mode, R rgb, TT rgb, TRT rgb (d'Eon:
                        orders 0, 1, 2), premultiplied */
    int lights;      /* lights actually used (fewer than asked when the map is tiny) */
    int ms;          /* 1 when multiple scattering was included */
    int fragments;   /* 1: fragment mode */
    double time_s;   /* render time (without loading) */
    uint64_t key;    /* cache key: scene content + settings (sl_reference_key) */
} sl_reference_frame;

/* Renders the scene. Returns 0 or -1 with e set (one line naming the file and the problem). */
int sl_reference_render(const sl_scene *s, const sl_reference_settings *set,
                        sl_reference_frame *out, sl_err *e);
void sl_reference_frame_free(sl_reference_frame *f);

/* Writes float EXR (atomically): R G B A Z, MS.R/G/B, R_mode.R/G/B, TT.R/G/B, TRT.R/G/B (the
 * channel names of `strandlight render`'s AOVs). */
int sl_reference_write_exr(const char *path, const sl_reference_frame *f, sl_err *e);

/* Image error of numerics.md sec. 6 over hair pixels (alpha > 0 in either image):
 * rel_rmse = mean over r, g, b of sqrt(mean((x - ref)^2) / mean(ref^2)) (per channel in
 * rgb3, may be NULL); p99 = 99th percentile over hair pixels of |x - ref|_2 / max(|ref|_2,
 * 0.01 x RMS of |ref|_2 over hair pixels) (the floor keeps near-black pixels from dominating).
 * Both 0 when no pixel is hair. rgba planes are interleaved 4 * w * h. */
void sl_image_error(const float *x, const float *ref, int w, int h, double *rel_rmse,
                    double rgb3[3], double *p99);

/* The same error on b x b pixel blocks: both images box-filtered to ceil(w/b) x ceil(h/b)
 * (premultiplied rgb and alpha averaged over the block's pixels), then sl_image_error. It
 * separates a systematic difference (brightness, shadowing, colour) from pixel-level sampling:
 * a reference that point-samples many sub-pixel fibers with few rays per pixel has a large
 * per-pixel error of its own (glints, docs/results.md) that block means average away.
 * Not numerics.md sec. 6's metric: an additional column of the report. */
void sl_image_error_blocks(const float *x, const float *ref, int w, int h, int b, double *rel_rmse,
                           double *p99);

/* The outcome of sl_reference_run (also written as JSON beside the EXR: PATH.json). */
typedef struct sl_reference_result {
    int cached; /* 1: the EXR with this key was already there, nothing rendered */
    uint64_t key;
    int lights, ms;
    double time_s;      /* render time at N lights (from the JSON when cached) */
    double mean_rgb[3]; /* mean premultiplied rgb over all pixels (JSON "mean_rgb") */
    double coverage;    /* mean alpha over all pixels (JSON "coverage") */
    int has_convergence;
    double conv_rel_rmse; /* image at N vs image at 2N lights and another seed */
    double conv_p99;
    double conv_rel_rmse_4x4; /* the same on 4 x 4 blocks (sl_image_error_blocks) */
    double time_2n_s;
    int fragments;  /* 1: fragment mode (JSON "fragments") */
    int oit_k;      /* fragment mode: K-buffer entries per pixel (JSON "oit_k") */
    double entries; /* fragment mode: K-buffer entries shaded (JSON "entries") */
} sl_reference_result;

/* Renders at set->lights (and, with convergence, at 2N lights with jitter seed + 1 to measure
 * the N image's own error: light cut and camera-ray sampling together; in fragment mode the same
 * fragments at 2N lights: the light cut alone),
 * writes exr_path + exr_path.json; when both exist with the same key (and convergence when
 * asked), nothing is rendered and res comes from the JSON. */
int sl_reference_run(const sl_scene *s, const sl_reference_settings *set, const char *exr_path,
                     int convergence, sl_reference_result *res, sl_err *e);

/* Reads back what sl_reference_run wrote (exr_path and exr_path.json: size, lights, ms, time,
 * key) into out, so a caller that found the result cached gets the pixels. */
int sl_reference_load(const char *exr_path, sl_reference_frame *out, sl_err *e);

#endif
