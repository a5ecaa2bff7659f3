/* shadow_eval.h: `strandlight eval transmittance --scene S.json` (numerics.md sec. 5 and 7). */
#ifndef SL_SHADOW_EVAL_H
#define SL_SHADOW_EVAL_H

#include "cl/clrt.h"
#include "verify/eval/fiber_eval.h"

/* Reference Monte Carlo directions per row (fixed seed per row): standard error <= 0.5/64. */
#define SL_SHADOW_REF_SAMPLES 4096

/* n rows of (x, y, z, lobe) -> out[i] = T_j(x) for the scene's hair and lobes. backend
 * reference: ray-traced fibers, Monte Carlo over the lobe; c / opencl: the DODM light pass
 * (map 512^2, the scene's quality.layers and quality.kappa). line_no (may be NULL) gives each
 * row's input line for messages. The scene must name environment.lobes. */
int sl_shadow_eval_transmittance(const char *scene_path, sl_eval_backend b, sl_cl *cl, size_t n,
                                 const double *in, const long *line_no, double *out, sl_err *e);

#endif
