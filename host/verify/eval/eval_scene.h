/* eval_scene.h: what the scene-based `eval` quantities (transmittance, forward-transmittance)
 * share: the loaded scene, hair and lobes (the lobes as the renderer turns them), the check that
 * every input row's lobe index names one of them, and the device their c / opencl backends run
 * on. */
#ifndef SL_EVAL_SCENE_H
#define SL_EVAL_SCENE_H

#include "cl/clrt.h"
#include "verify/eval/fiber_eval.h"
#include "lighting/lobes_json.h"
#include "io/hair/hair.h"
#include "scene/scene.h"

/* Rows are (x, y, z, lobe). Loads environment.lobes (or fits and caches quality.lobes lobes),
 * turns them by environment.rotation_deg, and fails naming the input line of the first row whose
 * lobe index is out of range. */
int sl_eval_scene_lobes(const sl_scene *s, size_t n, const double *rows, const long *line_no,
                        sl_lobes *lobes, sl_err *e);
/* The lobe check alone, for each further chunk of rows of a streamed eval. */
int sl_eval_scene_check_rows(const sl_lobes *lobes, size_t n, const double *rows,
                             const long *line_no, sl_err *e);

/* What a scene-based eval quantity works on: the scene, its hair and its lobes (turned). */
typedef struct sl_eval_scene_data {
    sl_scene *scene; /* on the heap: an sl_scene holds several paths of 4096 bytes */
    sl_hair hair;
    sl_lobes lobes;
} sl_eval_scene_data;

/* A quantity's own test of the loaded scene before the lobes are loaded (or fitted) and the hair
 * read: 0, or -1 with a message naming path. */
typedef int (*sl_eval_scene_check)(const sl_scene *s, const char *path, sl_err *e);

/* The preamble of `eval transmittance` and `eval forward-transmittance`: loads the scene at path,
 * runs check on it (NULL: none), then sl_eval_scene_lobes on the rows, then the scene's hair. On
 * failure frees what it loaded (d is left safe to pass to sl_eval_scene_free) and returns -1. */
int sl_eval_scene_load(const char *path, sl_eval_scene_check check, size_t n, const double *rows,
                       const long *line_no, sl_eval_scene_data *d, sl_err *e);
void sl_eval_scene_free(sl_eval_scene_data *d);

/* The device the c / opencl backends run the scene's passes on: the C path, or the eval command's
 * OpenCL context (an explicit device: it never falls back). Fails when opencl has no context. */
int sl_eval_scene_device(sl_eval_backend b, sl_cl *cl, sl_device *dev, sl_err *e);

#endif
