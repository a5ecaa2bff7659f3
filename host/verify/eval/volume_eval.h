/* volume_eval.h: `strandlight eval forward-transmittance --scene S.json` (numerics.md sec. 5, 7;
 * definition in docs/volume.md).
 *
 *   sl_volume_eval *v;
 *   if (sl_volume_eval_open(scene, backend, cl, n0, rows0, line0, &v, &e)) ...  (loads once)
 *   for each chunk: sl_volume_eval_rows(v, n, rows, line_no, out, &e);
 *   sl_volume_eval_close(v);
 *
 * The scene, its hair, material and lobes are loaded once for the whole input, and the voxel
 * grid and dual-scattering tables built once, however many chunks it comes in. */
#ifndef SL_VOLUME_EVAL_H
#define SL_VOLUME_EVAL_H

#include "cl/clrt.h"
#include "verify/eval/fiber_eval.h"

typedef struct sl_volume_eval sl_volume_eval;

/* Loads the scene at scene_path (model marschner only), its lobes and hair; the first chunk's
 * n rows are checked against the lobes before the hair is read. */
int sl_volume_eval_open(const char *scene_path, sl_eval_backend b, sl_cl *cl, size_t n,
                        const double *in, const long *line_no, sl_volume_eval **v, sl_err *e);
/* n rows of (x, y, z, lobe) -> T_f, sigma_f per colour channel of the scene's material: out
 * holds nch blocks (nch = sl_eval_num_channels) of n rows x 2 values, channel-major, as
 * `eval` prints them. reference: the actual fibers in double (cpu/reference/march_ref.h);
 * c / opencl: voxelization (quality.voxels) + the shadow-path march of the lobes the rows have
 * used so far, in order of first use (the march's random streams are keyed by that place, so it
 * is rebuilt, all of them, only when a chunk uses a new lobe) + trilinear lookup. line_no (may
 * be NULL) gives each row's input line for messages. */
int sl_volume_eval_rows(sl_volume_eval *v, size_t n, const double *in, const long *line_no,
                        double *out, sl_err *e);
void sl_volume_eval_close(sl_volume_eval *v); /* NULL is fine */

#endif
