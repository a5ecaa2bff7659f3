/* eval_scene.h: what the scene-based `eval` quantities (transmittance, forward-transmittance)
 * share: the scene's lobes as the renderer turns them, and the check that every input row's
 * lobe index names one of them. */
#ifndef SL_EVAL_SCENE_H
#define SL_EVAL_SCENE_H

#include "lobes_json.h"
#include "scene.h"

/* Rows are (x, y, z, lobe). Loads environment.lobes (or fits and caches quality.lobes lobes),
 * turns them by environment.rotation_deg, and fails naming the input line of the first row whose
 * lobe index is out of range. */
int sl_eval_scene_lobes(const sl_scene *s, size_t n, const double *rows, const long *line_no,
                        sl_lobes *lobes, sl_err *e);

#endif
