/* scene.h: the scene file (../shared/spec/scene.md) loaded and validated with cJSON.
 *
 * Every error names the file and the key path ("scene.json: camera.fov_deg: expected a number").
 * Relative paths are resolved against the scene file's directory. Unknown keys are errors. */
#ifndef SL_SCENE_H
#define SL_SCENE_H

#include "base/common.h"
#include "scene/material.h"

/* Planner thresholds: defaults of the quality.* keys below (docs/frame.md, docs/formats.md). */
#define SL_FRAME_LOBE_THRESHOLD 1e-3  /* skip lobes below this share of the total lobe power */
#define SL_FRAME_POINT_THRESHOLD 1e-4 /* per point: skip lobe j when T_j x its share is below */
#define SL_FRAME_SHADING_REFINE                                                                    \
    3.0 /* vertex rate: most a T may change along one interpolated span */
/* quality.sharp_shadows: at vertex rate, the most compact lobes (width lambda at most
 * SL_FRAME_SHARP_LAMBDA) whose transmittance each visible fragment looks up itself
 * (docs/frame.md, "Sharp shadows per entry"); at most SL_SHADE_SHARP_MAX (2) */
#define SL_FRAME_SHARP_SHADOWS 2
#define SL_FRAME_SHARP_LAMBDA 0.1
/* ... and carrying at least this share of the shaded lobes' power */
#define SL_FRAME_SHARP_MIN_SHARE 0.02
/* quality.multiple_scattering "auto": run the volume passes when sl_dual_ms_share(material) is at
 * least this (docs/dual.md: black hair 0.004, brown 0.041, blond 0.28). */
#define SL_FRAME_MS_AUTO_THRESHOLD 0.02
/* shading_rate auto: shade per fragment when segments project longer than this (pixels) */
#define SL_FRAME_AUTO_FRAGMENT_PX 24.0

enum { SL_MS_AUTO = 0, SL_MS_ON = 1, SL_MS_OFF = 2 };
/* quality.broad_lobes (docs/shadow.md, "Broad lobes"): a broad lobe is shaded as narrower
 * sub-lobes (host/lighting/lobe_subdivide.h), or keeps one lobe with a split transmittance
 * (host/passes/light/shadow_split.h) */
enum { SL_BROAD_SUBDIVIDE = 0, SL_BROAD_SPLIT = 1 };

typedef struct sl_scene {
    char path[4096]; /* the scene file itself */

    /* hair: exactly one of file / procedural */
    char hair_file[4096];
    int hair_procedural; /* 1 when procedural */
    int proc_style;      /* 0 straight, 1 wavy, 2 curly */
    uint32_t proc_strands, proc_points, proc_seed;
    int up_z;      /* file's up axis is +Z (converted to the world's +Y) */
    double radius; /* > 0 overrides the file's thickness; 0 = from file */
    /* hair.transparency "file": the view pass composites the file's per-point transparency
     * (.hair); "opaque" (default, 0): it is dropped at load, fibers are opaque as in the
     * shadows, the references and Cycles (docs/formats.md "Transparency") */
    int file_transparency;
    int has_follow;
    int follow_per_guide;
    double follow_root_radius, follow_tip_spread;

    sl_material material;
    /* material.strand_sigma_a (docs/formats.md): per-strand absorption overrides, resolved
     * against the hair by sl_scene_strand_sigma_a (host/scene/scene_strands.h). Empty: none. */
    int strand_sigma_a_colors; /* 1: "colors", from the hair file's per-point colours */
    char strand_sigma_a[4096]; /* the CSV path (resolved against the scene's directory) */

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
    /* planner thresholds (docs/frame.md; defaults SL_FRAME_* of host/plan/frame.h) */
    double lobe_threshold;    /* quality.lobe_threshold: skip lobes below this power share */
    double point_threshold;   /* quality.point_threshold: per point, skip lobe j if T_j share < */
    double shading_refine;    /* quality.shading_refine: vertex rate, cut a segment whose T changes
                                 by more than this factor (<= 1: never) */
    int sharp_shadows;        /* quality.sharp_shadows: lobes shadowed per K-buffer entry (0..2) */
    double ms_auto_threshold; /* quality.ms_auto_threshold: "auto" MS when ms share >= this */
    double auto_fragment_px;  /* quality.auto_fragment_px: shading_rate auto -> fragment above */
    int broad_lobes;          /* quality.broad_lobes: SL_BROAD_SUBDIVIDE (default) or _SPLIT */
    double sublobe_width;     /* quality.sublobe_width: the sub-lobes' lambda (lobe_subdivide.h) */

    /* output */
    char out_exr[4096], out_png[4096];
    int exr_float;
    double exposure; /* output.exposure: stops applied to the PNG preview only (0) */
    char aovs[16][32];
    int num_aovs;
} sl_scene;

void sl_scene_default(sl_scene *s);
/* Loads and validates a scene file. */
int sl_scene_load(const char *path, sl_scene *s, sl_err *e);
/* Parses a scene from memory (file_name is used in messages and to resolve relative paths). */
int sl_scene_parse(const char *text, size_t len, const char *file_name, sl_scene *s, sl_err *e);
/* The files a scene reads, for the check that an output is none of them (sl_output_not_input):
 * the scene file itself, hair.file, material.strand_sigma_a, environment.file and .lobes ("" where
 * the scene has none). */
#define SL_SCENE_FILES 5
void sl_scene_files(const sl_scene *s, const char *files[SL_SCENE_FILES]);

#endif
