/* frame.h: the real frame of `strandlight render`: the passes and the planner that runs, reuses
 * or skips them (docs/frame.md).
 *
 *   view pass   camera projection -> fragments with coverage AA (shared rasterizer) -> K-buffer
 *   light pass  per lobe: deep opacity map (host/passes/light/shadow.h), cached while geometry, lobes and
 *               shadow quality are unchanged (a camera orbit reuses every one)
 *   dual        dual-scattering material tables (host/passes/volume/dual.h), cached per material
 *   srbf        the SRBF method (auto: Ren 2010's precomputed table, built / loaded / kept, or
 *               the fast closed form; docs/frame.md "SRBF method", sl_renderer_set_editing)
 *   shade       per shading point (fragment, or strand vertex / every k-th vertex, interpolated):
 *               sum over lobes of SRBF response (kernels/srbf_fast.h, srbf_xu.h or the table
 *               of host/passes/shade/srbf_ren.h; C twins or OpenCL kernels) x effective transmittance T_j,
 *               plus multiple scattering (voxel grid + shadow-path march, host/passes/volume/volume.h, and
 *               the response per fragment and lobe, host/passes/volume/volume_ms.h)
 *   resolve     front-to-back compositing of each pixel's K entries into beauty + AOVs
 *               (host/passes/resolve/resolve.h)
 *
 *   sl_renderer *r = sl_renderer_create(&dev, NULL);
 *   sl_fbuf fb = {0};
 *   if (sl_renderer_frame(r, scene, hair, lobes, &cam, &fb, &e)) ...;
 *   sl_renderer_explain(r, stderr);        // each pass: run / cached / skipped, why, time, key
 *   sl_fbuf_free(&fb); sl_renderer_free(r);
 *
 * The passes are data (plan/passes.h): calling sl_renderer_frame again with the same renderer
 * reuses whatever still matches (each keyed pass: a hash of the inputs it declares and its own
 * settings). Results are deterministic: they do not depend on the
 * thread count, and a frame rendered alone equals the same frame rendered after others. */
#ifndef SL_FRAME_H
#define SL_FRAME_H

#include "scene/camera.h"
#include "cl/clrt.h"
#include "passes/volume/dual.h"
#include "io/hair/hair.h"
#include "kbuffer.h"
#include "lighting/lobes_json.h"
#include "scene/scene.h"
#include "passes/light/shadow.h"
#include "srbf_c.h"
#include "passes/shade/srbf_ren.h"
#include "passes/shade/srbf_tables.h"
#include "passes/volume/volume.h"
#include "passes/volume/volume_ms.h"
#include "passes/volume/volume_ms_nodes.h"
#include "passes/resolve/resolve.h"

#include <stdio.h>

/* Planner thresholds (docs/frame.md): SL_FRAME_LOBE_THRESHOLD, SL_FRAME_POINT_THRESHOLD,
 * SL_FRAME_MS_AUTO_THRESHOLD and SL_FRAME_AUTO_FRAGMENT_PX are the defaults of the scene keys
 * quality.lobe_threshold, point_threshold, ms_auto_threshold, auto_fragment_px (host/scene/scene.h). */

/* SRBF response methods of the shading pass: SL_SRBF_METHOD_XU (0) and _FAST (1) of
 * cpu/srbf_c.h, plus Ren 2010's precomputed table (host/passes/shade/srbf_ren.h) and the planner's choice
 * between table and fast (docs/frame.md, "SRBF method"). */
#define SL_RENDER_SRBF_TABLE 2
#define SL_RENDER_SRBF_AUTO 3
/* Parses "auto", "fast", "xu" or "table" into *method. Returns 0 or -1 with e set. */
int sl_render_method_parse(const char *s, int *method, sl_err *e);
/* "xu", "fast", "table", "auto". */
const char *sl_render_method_name(int method);

/* auto picks the table when frames x rows x SL_FRAME_TABLE_SAVING exceeds the table's build
 * cost in `fast` evaluations (sl_srbf_ren_build_rows): the table lookup costs about a tenth of a
 * `fast` RGB row (docs/srbf_ren.md, "Speed"), so each row shaded from the table saves 0.9 of
 * one, and a build row costs about one (the same closed form, one channel). */
#define SL_FRAME_TABLE_SAVING 0.9

typedef struct sl_render_opts {
    int srbf_method;       /* SL_RENDER_SRBF_AUTO (default), SL_SRBF_METHOD_FAST or _XU, or
                              SL_RENDER_SRBF_TABLE */
    int segments;          /* m for xu; 0 (default): the scene's quality.segments_m */
    int shadow_size;       /* deep opacity map size, 0: auto (256, 512 above 1M pixels) */
    double lobe_threshold; /* < 0 (default): the scene's quality.lobe_threshold; >= 0 overrides */
    int threads;           /* 0: every online CPU */
    int quiet;             /* no notes */
    /* frames the caller will render with this material (render: --orbit N; 0: one), which the
     * auto method weighs a table build against */
    int frames;
    /* the table's parameters (size, disk cache directory, build threads); NULL: the defaults
     * (sl_srbf_ren_params_default, disk cache of sl_cache_dir_find) with `threads` */
    const sl_srbf_ren_params *table_params;
} sl_render_opts;
void sl_render_opts_default(sl_render_opts *o);


enum { SL_PASS_RUN = 0, SL_PASS_CACHED = 1, SL_PASS_SKIPPED = 2 };
typedef struct sl_pass_rec {
    char name[24];
    int state;
    char why[600];
    double seconds;
} sl_pass_rec;
#define SL_FRAME_MAX_PASSES 16

/* The renderer: the passes' caches and the last frame's plan (its state is private to
 * host/plan and host/passes, plan/renderer.h). */
typedef struct sl_renderer sl_renderer;

/* A renderer on dev (which must outlive it) with options o (NULL: the defaults). */
sl_renderer *sl_renderer_create(sl_device *dev, const sl_render_opts *o);
/* Frees r and its caches; NULL is allowed. */
void sl_renderer_free(sl_renderer *r);
/* Renders one frame of s (its material, quality and image size; the camera is cam) into out
 * (allocated here; free with sl_fbuf_free). Returns 0 or -1 with e set. */
int sl_renderer_frame(sl_renderer *r, const sl_scene *s, const sl_hair *h, const sl_lobes *lobes,
                      const sl_camera *cam, sl_fbuf *out, sl_err *e);
/* Per-strand sigma_a overrides: n strands x 3 floats (copied), or sigma_a == NULL to clear.
 * n must equal the hair's strand count at the next frame (checked there). Returns 0 or -1. */
int sl_renderer_set_strand_sigma_a(sl_renderer *r, const float *sigma_a, uint32_t n, sl_err *e);
/* The material is being edited (1: every frame until cleared uses `fast` under the auto method,
 * so no table is built or loaded while sliders move) or has settled (0). The viewer sets it
 * while the material changes. */
void sl_renderer_set_editing(sl_renderer *r, int editing);
/* Text put before the pass on the status line a frame shows on a terminal (render: "frame 3 of
 * 36, eta 1m05s"); NULL or "" for none. Copied (at most 127 bytes). */
void sl_renderer_set_status(sl_renderer *r, const char *label);
/* The last frame's plan, one line per pass: name, run/cached/skipped, why, seconds. */
void sl_renderer_explain(const sl_renderer *r, FILE *f);
/* The record of pass `name` in the last plan, NULL if it has none. */
const sl_pass_rec *sl_renderer_pass(const sl_renderer *r, const char *name);
/* The last plan's records, in order: sl_renderer_npass of them, record i (NULL out of range). */
int sl_renderer_npass(const sl_renderer *r);
const sl_pass_rec *sl_renderer_pass_at(const sl_renderer *r, int i);

/* What the last frame decided: the lobes it shaded (after quality.lobe_threshold, before any
 * subdivision), whether multiple scattering was on, the shading rate (0 fragment, k >= 1 every
 * k-th vertex) and the SRBF method used (SL_SRBF_METHOD_XU, _FAST or SL_RENDER_SRBF_TABLE). */
int sl_renderer_lobes_used(const sl_renderer *r);
int sl_renderer_ms_on(const sl_renderer *r);
int sl_renderer_shading_rate(const sl_renderer *r);
int sl_renderer_srbf_used(const sl_renderer *r);
/* The last frame's wall time in seconds: every pass and the planner (explain's "total"). */
double sl_renderer_frame_seconds(const sl_renderer *r);
/* The last view pass's K-buffer (w x h pixels, K entries each, kcount[px] of them filled),
 * owned by r. take: the same, handed over to the caller (free both with free()); the next
 * frame re-runs the view pass. Return 0, or -1 when there is none. */
int sl_renderer_kbuffer(const sl_renderer *r, int *w, int *h, int *K, const sl_kfrag **kbuf,
                        const uint8_t **kcount);
int sl_renderer_take_kbuffer(sl_renderer *r, int *w, int *h, int *K, sl_kfrag **kbuf,
                             uint8_t **kcount);

/* Memory the frame of scene s needs, from the same size rules the passes allocate with (so the
 * estimate cannot drift from the allocations): the frame buffer (SL_FBUF_FLOATS per pixel), the
 * K-buffer (sl_frame_oit_k), the fragment-rate shade map, one deep opacity map per lobe
 * (sl_frame_shadow_size, quality.layers) and the voxel grid. shadow_size_opt > 0 overrides the
 * scene's map size (sl_render_opts.shadow_size). cmd_render refuses requests over budget. */
typedef struct sl_frame_need {
    double host;              /* bytes, every buffer together */
    double largest;           /* bytes, the largest single buffer */
    const char *largest_what; /* "K-buffer", "frame buffer", "deep opacity map", "voxel grid" */
    const char *setting;      /* the scene setting that shrinks the largest buffer */
    const char *host_setting; /* the setting that shrinks the biggest contributor */
} sl_frame_need;
void sl_frame_estimate(const sl_scene *s, int shadow_size_opt, sl_frame_need *n);
/* The total of sl_frame_estimate in bytes. */
size_t sl_frame_estimate_bytes(const sl_scene *s, int shadow_size_opt);
/* K-buffer entries per pixel for s: quality.oit_layers clamped to [1, SL_KBUFFER_MAX]. */
int sl_frame_oit_k(const sl_scene *s);
/* Deep opacity map size (texels per side): opt > 0, else quality.shadow_size, else 256 (512
 * above 1 M pixels). */
int sl_frame_shadow_size(const sl_scene *s, int opt);
/* Deep opacity map layers: quality.layers clamped to [1, SL_SHADOW_MAX_LAYERS]. */
int sl_frame_shadow_layers(const sl_scene *s);

/* Parses a shading rate ("auto", "fragment", "vertex", "vertex:K"): *k = -1 auto, 0 fragment,
 * K >= 1 every K-th vertex. Returns 0 or -1 with e set. */
int sl_shading_rate_parse(const char *s, int *k, sl_err *e);

#endif
