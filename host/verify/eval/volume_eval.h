/* volume_eval.h: `strandlight eval forward-transmittance --scene S.json` (numerics.md sec. 5, 7;
 * definition in docs/volume.md). */
#ifndef SL_VOLUME_EVAL_H
#define SL_VOLUME_EVAL_H

#include "cl/clrt.h"
#include "verify/eval/fiber_eval.h"

/* n rows of (x, y, z, lobe) -> T_f, sigma_f per colour channel of the scene's material: out
 * holds nch blocks (nch = sl_eval_num_channels) of n rows x 2 values, channel-major, as
 * `eval` prints them. reference: the actual fibers in double (cpu/reference/march_ref.h);
 * c / opencl: voxelization (quality.voxels) + the shadow-path march + trilinear lookup. line_no
 * (may be NULL) gives each row's input line for messages. */
int sl_volume_eval_forward(const char *scene_path, sl_eval_backend b, sl_cl *cl, size_t n,
                           const double *in, const long *line_no, double *out, sl_err *e);

#endif
