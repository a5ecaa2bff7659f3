/* frame.h: the real frame of `strandlight render`: the passes and the planner that runs, reuses
 * or skips them (docs/frame.md).
 *
 *   view pass   camera projection -> fragments with coverage AA (shared rasterizer) -> K-buffer
 *   light pass  per lobe: deep opacity map (host/shadow.h), cached while geometry, lobes and
 *               shadow quality are unchanged (a camera orbit reuses every one)
 *   dual        dual-scattering material tables (host/dual.h), cached per material
 *   shade       per shading point (fragment, or strand vertex / every k-th vertex, interpolated):
 *               sum over lobes of SRBF response (kernels/srbf_fast.h or srbf_xu.h; C twin or the
 *               OpenCL kernel srbf_eval.cl) x effective transmittance T_j, plus multiple
 *               scattering (voxel grid + shadow-path march, host/volume.h, and the response
 *               per fragment and lobe, host/volume_ms.h)
 *   resolve     front-to-back compositing of each pixel's K entries into beauty + AOVs
 *
 *   sl_renderer r; sl_renderer_init(&r, &dev, NULL);
 *   sl_fbuf fb = {0};
 *   if (sl_renderer_frame(&r, scene, hair, lobes, &cam, &fb, &e)) ...;
 *   sl_renderer_explain(&r, stderr);       // each pass: run / cached / skipped, why, time
 *   sl_fbuf_free(&fb); sl_renderer_free(&r);
 *
 * Calling sl_renderer_frame again with the same renderer reuses whatever still matches
 * (hashes of the inputs each pass reads). Results are deterministic: they do not depend on the
 * thread count, and a frame rendered alone equals the same frame rendered after others. */
#ifndef SL_FRAME_H
#define SL_FRAME_H

#include "camera.h"
#include "clrt.h"
#include "dual.h"
#include "hair.h"
#include "kbuffer.h"
#include "lobes_json.h"
#include "scene.h"
#include "shadow.h"
#include "srbf_tables.h"
#include "volume.h"
#include "volume_ms.h"

#include <stdio.h>

/* Planner thresholds (docs/frame.md). The scene has no keys for them yet. */
#define SL_FRAME_LOBE_THRESHOLD 1e-3  /* skip lobes below this share of the total lobe power */
#define SL_FRAME_POINT_THRESHOLD 1e-4 /* per point: skip lobe j when T_j x its share is below */
/* quality.multiple_scattering "auto": run the volume passes when sl_dual_ms_share(material) is at
 * least this (docs/dual.md: black hair 0.004, brown 0.041, blond 0.28). */
#define SL_FRAME_MS_AUTO_THRESHOLD 0.02
#define SL_FRAME_AUTO_FRAGMENT_PX                                                                  \
    24.0f /* shading_rate auto: fragments above this segment length                                \
           */

typedef struct sl_render_opts {
    int srbf_method;       /* SL_SRBF_METHOD_FAST (default) or _XU (cpu/srbf_c.h) */
    int segments;          /* m for xu (default 4) */
    int shadow_size;       /* deep opacity map size, 0: auto (256, 512 above 1M pixels) */
    double lobe_threshold; /* default SL_FRAME_LOBE_THRESHOLD */
    int threads;           /* 0: every online CPU */
    int quiet;             /* no notes */
} sl_render_opts;
void sl_render_opts_default(sl_render_opts *o);

/* Beauty and AOVs of one frame, planar, row 0 top, w * h pixels. */
typedef struct sl_fbuf {
    int width, height;
    float *rgba;    /* 4 per pixel, linear, premultiplied */
    float *depth;   /* view depth of the nearest fragment, +inf where empty */
    float *mode[4]; /* R, TT, TRT, MS: 3 per pixel, premultiplied (they sum to rgb) */
    float *shadow;  /* power-weighted mean transmittance toward the lobes, coverage-weighted */
    float *lobes;   /* lobes evaluated per shading point, coverage-weighted mean */
} sl_fbuf;
void sl_fbuf_free(sl_fbuf *f);

enum { SL_PASS_RUN = 0, SL_PASS_CACHED = 1, SL_PASS_SKIPPED = 2 };
typedef struct sl_pass_rec {
    char name[24];
    int state;
    char why[200];
    double seconds;
} sl_pass_rec;
#define SL_FRAME_MAX_PASSES 16

typedef struct sl_renderer {
    sl_device *dev;
    sl_render_opts o;
    /* caches */
    int have_tables;
    sl_srbf_tables tables;
    uint64_t light_key;
    int nlights;     /* lobes with a shadow map */
    int *light_lobe; /* lobe index of each map */
    sl_dodm *light;
    uint64_t dual_key;
    sl_dual_tables dual;
    int dual_ok;
    uint64_t vol_key; /* voxel grid + march textures (geometry, lobes, material, voxels) */
    int have_vol;
    sl_voxel_grid vgrid;
    sl_ftex ftex;
    uint64_t vms_key; /* multiple-scattering response tables (material) */
    int have_vms;
    sl_volume_ms vms;
    uint64_t view_key;
    int vw, vh, vK;
    sl_kfrag *kbuf;
    uint8_t *kcount;
    size_t frags, merges;
    int kbuf_on_device;  /* the last K-buffer fill ran on OpenCL */
    float seg_px_median; /* median projected segment length (pixels) of the last view pass */
    /* per-strand absorption overrides (painted, or from the file's colours; docs/frame.md):
     * 3 floats (sigma_a r, g, b) per strand, or NULL: every strand uses the material's sigma_a.
     * Set with sl_renderer_set_strand_sigma_a; the key is part of the shading pass's inputs
     * only (editing sigma_a re-runs shading, never the view or light passes). */
    float *strand_sigma_a;
    uint32_t strand_sigma_a_n;
    uint64_t strand_key;
    /* last frame's plan */
    int npass;
    sl_pass_rec pass[SL_FRAME_MAX_PASSES];
    int rate_k; /* 0: fragment, k >= 1: every k-th vertex */
    int ms_on, lobes_used;
    double total_s;
} sl_renderer;

void sl_renderer_init(sl_renderer *r, sl_device *dev, const sl_render_opts *o);
void sl_renderer_free(sl_renderer *r);
/* Renders one frame of s (its material, quality and image size; the camera is cam) into out
 * (allocated here; free with sl_fbuf_free). Returns 0 or -1 with e set. */
int sl_renderer_frame(sl_renderer *r, const sl_scene *s, const sl_hair *h, const sl_lobes *lobes,
                      const sl_camera *cam, sl_fbuf *out, sl_err *e);
/* Per-strand sigma_a overrides: n strands x 3 floats (copied), or sigma_a == NULL to clear.
 * n must equal the hair's strand count at the next frame (checked there). Returns 0 or -1. */
int sl_renderer_set_strand_sigma_a(sl_renderer *r, const float *sigma_a, uint32_t n, sl_err *e);
/* The last frame's plan, one line per pass: name, run/cached/skipped, why, seconds. */
void sl_renderer_explain(const sl_renderer *r, FILE *f);
/* The record of pass `name` in the last plan, NULL if it has none. */
const sl_pass_rec *sl_renderer_pass(const sl_renderer *r, const char *name);

/* Parses a shading rate ("auto", "fragment", "vertex", "vertex:K"): *k = -1 auto, 0 fragment,
 * K >= 1 every K-th vertex. Returns 0 or -1 with e set. */
int sl_shading_rate_parse(const char *s, int *k, sl_err *e);

#endif
