/* reference_path.h: `strandlight reference --path` (docs/reference.md, "Path tracer"): the
 * unbiased path tracer of cpu/reference/path_ref.h on a scene, the ground truth that includes
 * every order of scattering among the real fibers. The same camera and pixels as `render` and
 * the pixel-mode reference (scene/scene_inputs.h framing), the environment map at full
 * resolution (environment.file; rotation_deg and intensity applied), the scene's material
 * (models marschner, deon, chiang). Samples are taken in whole passes (one sample of every
 * pixel each); --time stops at a time budget after the last pass that fits.
 *
 *   sl_path_settings set; sl_path_settings_default(&set); set.spp = 64;
 *   sl_path_result r;
 *   if (sl_path_run(&scene, &set, "ref.exr", 0, &r, &e)) ...   (EXR + ref.exr.json, cached)
 *   sl_reference_frame f; sl_reference_load("ref.exr", &f, &e);  (reads a path EXR too) */
#ifndef SL_REFERENCE_PATH_H
#define SL_REFERENCE_PATH_H

#include "base/common.h"
#include "scene/scene.h"

#include <signal.h>
#include <stdint.h>

typedef struct sl_path_settings {
    int spp;             /* samples per pixel (>= 1); with time_s > 0 the most taken */
    double time_s;       /* > 0: stop after the last whole pass that fits in this budget */
    uint64_t seed;       /* random streams (path_rng.h) */
    int threads;         /* 0: every online CPU; the image does not depend on it */
    int width, height;   /* 0: the scene's */
    int progress;        /* 1: progress line on stderr when it is a terminal */
    int clamp_nonfinite; /* map: NaN/Inf pixels become 0 instead of an error */
    const volatile sig_atomic_t *cancel; /* non-zero (SIGINT): stop, write nothing */
} sl_path_settings;

/* 16 spp, no time budget, seed 1, all CPUs, progress on */
void sl_path_settings_default(sl_path_settings *s);

/* The image, premultiplied by coverage (misses count 0), row 0 at the top. */
typedef struct sl_path_frame {
    int width, height;
    float *rgba;     /* 4 per pixel: rgb = mean radiance over the pixel's samples, a = coverage */
    float *depth;    /* nearest view depth (+inf: empty) */
    float *direct;   /* 3 per pixel: light that scattered once */
    float *indirect; /* 3 per pixel: light that scattered more than once */
    float *lobes;    /* 12 per pixel: R, TT, TRT, rest rgb: by the first event's lobe */
} sl_path_frame;

typedef struct sl_path_result {
    int cached;         /* 1: the EXR of this key was there, nothing rendered */
    int interrupted;    /* 1: cancelled (SIGINT); nothing written */
    uint64_t key;       /* content + spp + seed (path_ref's settings) */
    int spp, spp_asked; /* samples reached (a time budget may stop early) and asked */
    double wall_s;      /* render wall time (without loading) */
    double cpu_s;       /* process CPU time of the render */
    double paths_per_s; /* camera paths (pixel samples) per wall second */
    double events_per_path;
    int threads;                        /* worker threads used */
    long long paths, capped;            /* paths traced; cut at the depth cap */
    double noise, noise_4x4, noise_8x8; /* path_noise.h (NaN below 2 spp) */
    double mean_rgb[3], coverage;
} sl_path_result;

/* Renders into out (no files). Returns 0, or -1 with e set (r->interrupted when cancelled). */
int sl_path_render(const sl_scene *s, const sl_path_settings *set, sl_path_frame *out,
                   sl_path_result *r, sl_err *e);
void sl_path_frame_free(sl_path_frame *f);

/* Renders and writes exr_path (float: R G B A Z, direct.*, indirect.*, MS.* (= indirect, the
 * name the pixel-mode reference and `report` read), R_mode.*, TT.*, TRT.*, rest.*) and
 * exr_path.json; without a time budget, a record with the same key and a matching EXR is reused
 * (force = 0). An interrupted render writes nothing. */
int sl_path_run(const sl_scene *s, const sl_path_settings *set, const char *exr_path, int force,
                sl_path_result *r, sl_err *e);

#endif
