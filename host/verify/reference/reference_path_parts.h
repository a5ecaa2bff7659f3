/* reference_path_parts.h: the pieces of sl_path_run (reference_path.h) shared by its two files:
 * reference_path.c (inputs, the pass loop, the frame) and reference_path_record.c (key, EXR,
 * JSON, cache). Not for other callers. */
#ifndef SL_REFERENCE_PATH_PARTS_H
#define SL_REFERENCE_PATH_PARTS_H

#include "env_ref.h"
#include "io/envmap/envmap.h"
#include "io/hair/hair.h"
#include "raytrace_ref.h"
#include "scene/camera.h"
#include "verify/reference/reference_path.h"

typedef struct sl_path_prep {
    sl_hair hair;
    sl_envmap map;
    sl_camera cam;
    float *strand_sa; /* material.strand_sigma_a: 3 per strand, or NULL */
    slref_rt *rt;     /* built at the first render */
    slref_env env;    /* likewise */
    int threads;
} sl_path_prep;

/* Loads the hair and camera (framed as `render` frames them) and the map; checks settings. */
int sl_path_prepare(const sl_scene *s, const sl_path_settings *set, sl_path_prep *p, sl_err *e);
void sl_path_prep_free(sl_path_prep *p);
/* Renders p's scene (fills r's figures, not its key). */
int sl_path_render_prepared(const sl_scene *s, const sl_path_settings *set, sl_path_prep *p,
                            sl_path_frame *out, sl_path_result *r, sl_err *e);
/* The cache key of the image at spp samples with seed: content (ref_record.h) + what the path
 * tracer reads besides (the chiang logistic scale, rotation, intensity) + spp, seed and its
 * depth settings. A time-budget run records the key of the spp it reached, which is the key of
 * the fixed-spp render it equals. */
uint64_t sl_path_key(const sl_scene *s, const sl_path_prep *p, int spp, uint64_t seed);

#endif
