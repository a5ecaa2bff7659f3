/* viewer.h: the state of `strandlight view` (issue 11, docs/viewer.md) and the operations every
 * control goes through. The mouse, the keys, the ImGui panel (viewer_ui.h) and `--script` all
 * call the same functions, so a script test exercises exactly what a person does:
 *
 *   sl_viewer_set(v, "material.beta_R_deg", "10", &e);   edit the scene document (re-validated)
 *   sl_viewer_orbit / pan / zoom / reset / env_rotate     camera and environment
 *   sl_viewer_paint_at(v, x, y, radius, sigma_a, &e)      brush (one undo step)
 *   sl_viewer_undo(v)                                     undo the last stroke
 *   sl_viewer_step(v, &e)                                 render what is due (preview or refined)
 *   sl_viewer_save(v, "s.json", &e)                       scene JSON + per-strand CSV
 *
 * Rendering: two renderers with their own caches. While inputs change ("interacting") the
 * preview renderer draws at half resolution with at most SL_VIEWER_PREVIEW_LOBES lobes, vertex
 * shading and no multiple scattering; once nothing changed during a step, the full renderer
 * draws the refined frame with the scene's settings (the same frame `strandlight render` makes). */
#ifndef SL_VIEWER_H
#define SL_VIEWER_H

#include "scene/camera.h"
#include "cl/clrt.h"
#include "plan/frame.h"
#include "io/hair/hair.h"
#include "lighting/lobes_json.h"
#include "scene/scene.h"

#include <cjson/cJSON.h>

#define SL_VIEWER_PREVIEW_LOBES 8
#define SL_VIEWER_UNDO_MAX 64

struct sl_viewer_gl; /* viewer_gl.h */

/* One undo step: the strands a stroke changed and what they held before. */
typedef struct sl_paint_step {
    uint32_t n;
    uint32_t *strand;
    float *old_sa;    /* 3 per entry */
    uint8_t *old_set; /* 1 when the strand had its own sigma_a before */
} sl_paint_step;

/* Per-strand absorption: strands with set[i] use sa[3i..3i+2], the others the material's. */
typedef struct sl_paint {
    uint32_t n; /* strands */
    float *sa;
    uint8_t *set;
    uint32_t nset;
    sl_paint_step undo[SL_VIEWER_UNDO_MAX];
    int nundo;
    uint64_t applied_key; /* what the renderers hold (0: nothing) */
} sl_paint;

typedef struct sl_viewer {
    char scene_path[4096];
    cJSON *doc;     /* the scene file as loaded plus every edit */
    sl_scene scene; /* doc parsed and validated (image size from --size when given) */
    int size_w, size_h;
    const char *device_spec;

    sl_hair hair;
    float lo[3], hi[3];
    sl_lobes lobes_raw;     /* as loaded */
    sl_lobes lobes;         /* rotated and scaled (environment.rotation_deg, intensity) */
    sl_lobes lobes_preview; /* the strongest SL_VIEWER_PREVIEW_LOBES of `lobes` */

    double eye[3], target[3], up[3];
    double home_eye[3], home_target[3], home_up[3];

    sl_device dev;
    int have_dev;
    sl_renderer *full, *preview;
    int have_renderers;
    sl_fbuf shown;           /* the frame on screen */
    sl_fbuf last_full;       /* the last refined frame (its depth serves the brush's depth test) */
    sl_camera last_full_cam; /* its camera: the depth test applies only while it is current */
    int dirty;               /* inputs changed since the frame on screen was rendered */
    int refined;             /* the frame on screen is the refined one */
    int shown_preview;       /* the frame on screen came from the preview renderer */

    sl_paint paint;
    int paint_mode, brush_depth_test;
    float brush_radius, brush_sigma[3];

    double t_full, t_preview, t_present; /* seconds of the last frame of each kind */
    int nfull, npreview;

    struct sl_viewer_gl *gl;
    int quit;
    char status[256];
    char save_path[1024];
} sl_viewer;

/* Loads the scene, hair and lobes and opens the device. size_w/h > 0 override image size. */
int sl_viewer_open(sl_viewer *v, const char *scene_path, const char *device, int size_w, int size_h,
                   sl_err *e);
void sl_viewer_close(sl_viewer *v);

/* viewer_doc.c: the scene document. KEY is a dotted path of the scene file (material.*,
 * quality.*, camera.*, environment.*, image.*, hair.*); VALUE is JSON (a number, [r,g,b], "s")
 * or a bare word taken as a string. The edited document is re-validated by the scene loader;
 * on error nothing changes. Reloads hair / lobes only when their keys changed. */
int sl_viewer_parse_doc(sl_viewer *v, sl_err *e); /* v->doc -> v->scene */
int sl_viewer_set(sl_viewer *v, const char *key, const char *value, sl_err *e);
/* A dropped file: hair (.hair .tfx .tfxproj .data) or environment map (.exr .hdr). */
int sl_viewer_drop(sl_viewer *v, const char *path, sl_err *e);
/* Writes the scene JSON (camera, edits, absolute paths) and, when strands are painted,
 * PATH's stem + ".strands.csv" named by material.strand_sigma_a. Atomic. */
int sl_viewer_save(sl_viewer *v, const char *path, sl_err *e);
/* (Re)loads the hair / lobes of v->scene and derives the transformed and preview lobes. */
int sl_viewer_load_hair(sl_viewer *v, sl_err *e);
int sl_viewer_load_lobes(sl_viewer *v, sl_err *e);
void sl_viewer_transform_lobes(sl_viewer *v);
void sl_viewer_camera_from_scene(sl_viewer *v);

/* viewer_camera.c. orbit: yaw degrees about +Y through the target (as `render --orbit`), and
 * pitch degrees about the camera's right axis; pan: moves eye and target so the hair moves by
 * (dx, dy) pixels; zoom: divides the eye-target distance by f. */
void sl_viewer_orbit(sl_viewer *v, double yaw_deg, double pitch_deg);
void sl_viewer_pan(sl_viewer *v, double dx, double dy);
void sl_viewer_zoom(sl_viewer *v, double f);
void sl_viewer_reset(sl_viewer *v);
int sl_viewer_env_rotate(sl_viewer *v, double deg, sl_err *e);
/* The camera for a w x h frame. */
void sl_viewer_camera(const sl_viewer *v, int w, int h, sl_camera *cam);

/* viewer_paint.c. Sets sigma_a on every strand with a vertex in front of the camera whose
 * projection lies within radius pixels of (x, y) of the full-size image (and, when the depth
 * test is on and a refined frame exists, not behind that pixel's nearest fragment). Starts a
 * new undo step unless `continue_stroke`. Returns the number of strands hit, -1 on error. */
long sl_viewer_paint_at(sl_viewer *v, double x, double y, double radius, const float sa[3],
                        int continue_stroke, sl_err *e);
int sl_viewer_undo(sl_viewer *v); /* 0 when there was nothing to undo */
void sl_paint_reset(sl_paint *p, uint32_t nstrands);
void sl_paint_free(sl_paint *p);
/* Loads material.strand_sigma_a of the scene into the paint layer (no undo step). */
int sl_viewer_paint_from_scene(sl_viewer *v, sl_err *e);
/* The per-strand array (3 per strand) with unpainted strands at the material's sigma_a, or NULL
 * when nothing is painted. Caller frees. */
float *sl_viewer_paint_array(const sl_viewer *v);

/* viewer_render.c. Renders the frame that is due (preview when dirty, refined when not yet
 * refined) into v->shown. Returns 1 when a frame was rendered, 0 when nothing was due, -1. */
int sl_viewer_render(sl_viewer *v, sl_err *e);
/* Switches the backend (as --device: auto|gpu|pocl|c|opencl|P:D). On error nothing changes.
 * Both renderers start with empty caches on the new device. */
int sl_viewer_set_device(sl_viewer *v, const char *spec, sl_err *e);
/* The plan of the renderer that drew the frame on screen. */
const sl_renderer *sl_viewer_shown_renderer(const sl_viewer *v);

/* viewer_script.c: runs a --script file (docs/viewer.md lists the commands). Errors name the
 * file and line. The host (cmd_view.c) renders and repaints: step() after every command
 * (until_refined for `wait`), screenshot() for `screenshot` / `screenshot_window`. */
typedef struct sl_viewer_host {
    int (*step)(sl_viewer *v, int until_refined, sl_err *e);
    int (*screenshot)(sl_viewer *v, const char *path, int whole_window, sl_err *e);
} sl_viewer_host;
int sl_viewer_run_script(sl_viewer *v, const char *path, const sl_viewer_host *host, sl_err *e);
/* The same on a script already in memory (len bytes, no NUL needed; path names it in errors):
 * the reading of lines is separate from the file I/O so that test/fuzz/fuzz_viewer_script.c
 * can drive it. */
int sl_viewer_run_script_text(sl_viewer *v, const char *text, size_t len, const char *path,
                              const sl_viewer_host *host, sl_err *e);
/* One script line (comment already stripped); `where` prefixes errors ("s.txt:3"). */
int sl_viewer_command(sl_viewer *v, char *line, const char *where, const sl_viewer_host *host,
                      sl_err *e);

#endif
