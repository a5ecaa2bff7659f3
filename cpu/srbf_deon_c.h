/* srbf_deon_c.h: batch driver of the C twin (float) for the d'Eon model's fast SRBF response
 * (`eval srbf --method fast` on the c backend with `model: deon`): runs kernels/srbf_deon.h row
 * by row, the same code as kernels/srbf_deon.cl, so C and OpenCL agree to float rounding. */
#ifndef SL_SRBF_DEON_C_H
#define SL_SRBF_DEON_C_H

#include <stddef.h>

#include "fiber_params.h"

/* in: 5 floats per row (theta_o, phi_o, theta_j, phi_j, lambda); out: orders + 3 per row
 * (I_0..I_orders, I_rest, I; orders = fp->orders, at most SL_DEON_MAX_ORDERS). C, H, D: the
 * tables of host/passes/shade/srbf_tables.h (t.C, t.H, t.D). */
void slc_srbf_deon_batch(const sl_fiber_params *fp, const float *C, const float *H, const float *D,
                         size_t n, const float *in, float *out);

/* The renderer's batch (the shape of slc_srbf_rgb_batch, cpu/srbf_c.h): in as above; sigma_a 3
 * floats per row (r, g, b) or NULL for fp->sigma_a; out 9 per row: I_0 rgb, I_1 rgb, and the
 * sum of orders >= 2 and the rest term rgb (the R, TT, TRT slots of the Marschner rows). */
void slc_srbf_deon_rgb_batch(const sl_fiber_params *fp, const float *C, const float *H,
                             const float *D, size_t n, const float *in, const float *sigma_a,
                             float *out);
/* The same, one sl_srbf_deon_rgb_row per row (the reference of the batch's reuse, for tests and
 * benchmarks): equal to slc_srbf_deon_rgb_batch bit for bit. */
void slc_srbf_deon_rgb_scalar(const sl_fiber_params *fp, const float *C, const float *H,
                              const float *D, size_t n, const float *in, const float *sigma_a,
                              float *out);

/* Model chiang's batch of slc_srbf_deon_rgb_batch for one instruction set: avx2 = 0 the x86-64
 * baseline (SSE2), 1 AVX2 + FMA (cpu/srbf_deon_c_avx2.c; only where slc_simd_avx2() is 1). Both
 * give the same bits (cpu/srbf_chiang_batch.inc); slc_srbf_deon_rgb_batch picks by
 * slc_simd_avx2(). */
void slc_srbf_chiang_rgb_batch(int avx2, const sl_fiber_params *fp, const float *C, const float *H,
                               const float *D, size_t n, const float *in, const float *sigma_a,
                               float *out);
void slc_srbf_chiang_rgb_batch_base(const sl_fiber_params *fp, const float *C, const float *H,
                                    const float *D, size_t n, const float *in, const float *sigma_a,
                                    float *out);
void slc_srbf_chiang_rgb_batch_avx2(const sl_fiber_params *fp, const float *C, const float *H,
                                    const float *D, size_t n, const float *in, const float *sigma_a,
                                    float *out);
/* 1 where the CPU has AVX2 and FMA and the environment does not say SL_SIMD=base (the switch
 * for measuring the baseline on the same machine); 0 elsewhere. */
int slc_simd_avx2(void);

#endif
