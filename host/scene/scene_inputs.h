/* scene_inputs.h: everything a scene file brings to a frame, loaded one way for `render`,
 * `reference`, `report`, `eval` and the viewer: the scene (with the command line's image size),
 * its hair (scene_hair.h), the environment lobes rotated and scaled (env_lighting.h), the
 * per-strand absorption (scene_strands.h) and the camera, framed by sl_scene_camera (the one
 * place of the "camera.eye omitted: frame the hair along -Z" rule, scene.md), so that the
 * reference frames exactly as render does.
 *
 *   sl_scene_inputs_opts o = {.width = w, .height = h, .lobes = 1, .strand_sigma_a = 1};
 *   sl_scene_inputs in;
 *   if (sl_scene_inputs_load("scene.json", &o, &in, &e)) ...
 *   ... in.scene, in.hair, in.lobes, in.cam ...
 *   sl_scene_inputs_free(&in);                         (after a failure too: always free)
 *
 * A caller that checks the scene's settings before any file is read (render's memory limits and
 * device) splits the load: sl_scene_inputs_open, its checks, then sl_scene_inputs_finish; the
 * errors then come in the same order as before the split. */
#ifndef SL_SCENE_INPUTS_H
#define SL_SCENE_INPUTS_H

#include "io/hair/hair.h"
#include "lighting/lobes_json.h"
#include "scene/camera.h"
#include "scene/scene.h"

typedef struct sl_scene_inputs_opts {
    int width, height;   /* > 0: replaces image.width / image.height (--width, --height) */
    int lobes;           /* 1: load environment.lobes or fit the map (cached) into in->lobes */
    int clamp_nonfinite; /* with lobes: NaN/Inf map pixels become 0 instead of an error */
    int strand_sigma_a;  /* 1: resolve material.strand_sigma_a against the hair */
} sl_scene_inputs_opts;

typedef struct sl_scene_inputs {
    sl_scene *scene;       /* on the heap (an sl_scene holds several 4096-byte paths); owned */
    sl_hair hair;          /* as every pass sees it (sl_scene_load_hair) */
    sl_lobes lobes;        /* rotation and intensity applied; empty unless opts.lobes */
    float *strand_sigma_a; /* 3 per strand, NULL: none (or not asked for) */
    float lo[3], hi[3];    /* the hair's bounds */
    double target[3];      /* camera.target, else the centre of the bounds */
    sl_camera cam;         /* the scene's camera at scene->width x scene->height */
} sl_scene_inputs;

/* The camera of scene s for a hair with bounds [lo, hi] at width x height: camera.target or the
 * bounds' centre (in *target), camera.eye or the bounds framed along -Z. */
void sl_scene_camera(const sl_scene *s, const float lo[3], const float hi[3], int width, int height,
                     double target[3], sl_camera *cam);

/* Replaces s's image size by width / height where they are > 0 (command-line overrides). */
void sl_scene_set_size(sl_scene *s, int width, int height);

/* Loads the scene at path, then the rest (sl_scene_inputs_finish). Returns 0, or -1 with e set
 * (one line naming the file and the key). Either way in holds what was loaded (after a failure
 * in->scene stays valid once the scene itself parsed) and the caller frees it. */
int sl_scene_inputs_load(const char *scene_path, const sl_scene_inputs_opts *o, sl_scene_inputs *in,
                         sl_err *e);

/* The same from a scene already loaded (copied: s is not changed, o's size applies to the copy). */
int sl_scene_inputs_from_scene(const sl_scene *s, const sl_scene_inputs_opts *o,
                               sl_scene_inputs *in, sl_err *e);

/* The first half of sl_scene_inputs_load: the scene file only, with o's image size. */
int sl_scene_inputs_open(const char *scene_path, const sl_scene_inputs_opts *o, sl_scene_inputs *in,
                         sl_err *e);

/* The second half: the hair, the lobes (o->lobes), the camera at the scene's (possibly changed)
 * image size and the per-strand absorption (o->strand_sigma_a), in that order. o's size is not
 * applied again: a caller may have changed in->scene since sl_scene_inputs_open. */
int sl_scene_inputs_finish(sl_scene_inputs *in, const sl_scene_inputs_opts *o, sl_err *e);

void sl_scene_inputs_free(sl_scene_inputs *in);

#endif
