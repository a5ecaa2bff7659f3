/* eval_scene.h: what the scene-based `eval` quantities (transmittance, forward-transmittance)
 * share: the scene's lobes as the renderer turns them, and the check that every input row's
 * lobe index names one of them, and the device their c / opencl backends run on. */
#ifndef SL_EVAL_SCENE_H
#define SL_EVAL_SCENE_H

#include "clrt.h"
#include "fiber_eval.h"
#include "lobes_json.h"
#include "scene.h"

/* Rows are (x, y, z, lobe). Loads environment.lobes (or fits and caches quality.lobes lobes),
 * turns them by environment.rotation_deg, and fails naming the input line of the first row whose
 * lobe index is out of range. */
int sl_eval_scene_lobes(const sl_scene *s, size_t n, const double *rows, const long *line_no,
                        sl_lobes *lobes, sl_err *e);

/* The device the c / opencl backends run the scene's passes on: the C path, or the eval command's
 * OpenCL context (an explicit device: it never falls back). Fails when opencl has no context. */
int sl_eval_scene_device(sl_eval_backend b, sl_cl *cl, sl_device *dev, sl_err *e);

#endif
