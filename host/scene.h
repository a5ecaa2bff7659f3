/* scene.h: the scene file (../shared/spec/scene.md) loaded and validated with cJSON.
 *
 * Every error names the file and the key path ("scene.json: camera.fov_deg: expected a number").
 * Relative paths are resolved against the scene file's directory. Unknown keys are errors. */
#ifndef SL_SCENE_H
#define SL_SCENE_H

#include "common.h"
#include "material.h"

enum { SL_MS_AUTO = 0, SL_MS_ON = 1, SL_MS_OFF = 2 };

typedef struct sl_scene {
    char path[4096]; /* the scene file itself */

    /* hair: exactly one of file / procedural */
    char hair_file[4096];
    int hair_procedural; /* 1 when procedural */
    int proc_style;      /* 0 straight, 1 wavy, 2 curly */
    uint32_t proc_strands, proc_points, proc_seed;
    int up_z;            /* file's up axis is +Z (converted to the world's +Y) */
    double radius;       /* > 0 overrides the file's thickness; 0 = from file */
    int has_follow;
    int follow_per_guide;
    double follow_root_radius, follow_tip_spread;

    sl_material material;

    /* environment: a map file and/or a lobes file */
    char env_file[4096];
    char env_lobes[4096];
    double env_rotation_deg, env_intensity;

    /* camera: eye may be omitted (has_eye = 0): then framed from target along -Z */
    int has_eye, has_target;
    double eye[3], target[3], up[3], fov_deg;

    int width, height;

    /* quality */
    int lobes, layers, segments_m, voxels, oit_layers;
    int shadow_size; /* quality.shadow_size: light-map (DODM) width = height, texels; 0: unset */
    double kappa;
    int multiple_scattering; /* SL_MS_* */
    char shading_rate[32];   /* "auto", "fragment", "vertex" or "vertex:K" */

    /* output */
    char out_exr[4096], out_png[4096];
    int exr_float;
    char aovs[16][32];
    int num_aovs;
} sl_scene;

void sl_scene_default(sl_scene *s);
/* Loads and validates a scene file. */
int sl_scene_load(const char *path, sl_scene *s, sl_err *e);
/* Parses a scene from memory (file_name is used in messages and to resolve relative paths). */
int sl_scene_parse(const char *text, size_t len, const char *file_name, sl_scene *s, sl_err *e);

#endif
