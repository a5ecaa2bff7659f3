/* shadow_eval.h: `strandlight eval transmittance --scene S.json` (numerics.md sec. 5 and 7).
 *
 *   sl_shadow_eval *t;
 *   if (sl_shadow_eval_open(scene, backend, cl, n0, rows0, line0, &t, &e)) ...  (loads once)
 *   for each chunk: sl_shadow_eval_rows(t, row0, n, rows, line_no, T, &e);
 *   sl_shadow_eval_close(t);
 *
 * The scene, its hair and lobes are loaded once for the whole input, however many chunks it
 * comes in (eval streams its rows, docs/eval.md). */
#ifndef SL_SHADOW_EVAL_H
#define SL_SHADOW_EVAL_H

#include "cl/clrt.h"
#include "verify/eval/fiber_eval.h"

/* Reference Monte Carlo directions per row (fixed seed per row): standard error <= 0.5/64. */
#define SL_SHADOW_REF_SAMPLES 4096

typedef struct sl_shadow_eval sl_shadow_eval;

/* Loads the scene at scene_path (it must name environment.lobes), its lobes and hair; the first
 * chunk's n rows are checked against the lobes between the two, so a bad lobe index is reported
 * before the hair is read. */
int sl_shadow_eval_open(const char *scene_path, sl_eval_backend b, sl_cl *cl, size_t n,
                        const double *in, const long *line_no, sl_shadow_eval **t, sl_err *e);
/* n rows of (x, y, z, lobe) -> out[i] = T_j(x). row0: the index of the first of them in the
 * whole input (the reference's Monte Carlo seed is row index + 1). backend reference:
 * ray-traced fibers, Monte Carlo over the lobe; c / opencl: the DODM light pass (map 512^2, the
 * scene's quality.layers and quality.kappa), one batch of the lobes the rows have used so far,
 * in order of first use (rebuilt only when a chunk uses a new lobe; each lobe's maps do not
 * depend on the others in the batch). line_no (may be NULL) gives each row's input line. */
int sl_shadow_eval_rows(sl_shadow_eval *t, size_t row0, size_t n, const double *in,
                        const long *line_no, double *out, sl_err *e);
void sl_shadow_eval_close(sl_shadow_eval *t); /* NULL is fine */

#endif
