/* srbf_c.h: batch driver of the C twin (float) for the SRBF response (`eval srbf` on the c
 * backend, the frame's shading pass): runs kernels/srbf_xu.h (and the fast path) row by row, the
 * same code as kernels/srbf.cl, so C and OpenCL agree to float rounding. */
#ifndef SL_SRBF_C_H
#define SL_SRBF_C_H

#include <stddef.h>

#include "fiber_params.h"

/* Methods of slc_srbf_batch. */
enum { SL_SRBF_METHOD_XU = 0, SL_SRBF_METHOD_FAST = 1 };

/* in: 5 floats per row (theta_o, phi_o, theta_j, phi_j, lambda); out: 4 per row (I_R, I_TT,
 * I_TRT, I). C, H: the tables of host/passes/shade/srbf_tables.h. segments: m of Xu Sec. 4.2.2
 * (1..8). */
void slc_srbf_batch(const sl_fiber_params *fp, const float *C, const float *H, int method,
                    int segments, size_t n, const float *in, float *out);

/* Three absorption coefficients per row at once (colour channels, per-strand painting): in as
 * above; sigma_a: 3 floats per row (r, g, b), or NULL for fp->sigma_a in all three; out: 9 per
 * row, I_R rgb, I_TT rgb, I_TRT rgb. Every other parameter comes from fp. The fast path shares
 * all channel-independent work (only the absorption exp is per channel; a row whose three
 * sigma_a are equal costs one channel); xu runs per channel. Row r equals slc_srbf_batch with
 * fp->sigma_a = sigma_a[3r + ch] to float rounding. */
void slc_srbf_rgb_batch(const sl_fiber_params *fp, const float *C, const float *H, int method,
                        int segments, size_t n, const float *in, const float *sigma_a, float *out);
/* The same, one sl_srbf_rgb_row per row: the reference the batch is tested and benchmarked
 * against (test/passes/shade/test_srbf_batch.c, test/bench/bench_srbf.sh). */
void slc_srbf_rgb_scalar(const sl_fiber_params *fp, const float *C, const float *H, int method,
                         int segments, size_t n, const float *in, const float *sigma_a, float *out);

#endif
