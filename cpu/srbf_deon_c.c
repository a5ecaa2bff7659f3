/* srbf_deon_c.c: the C twin's batch driver of the d'Eon fast SRBF response (see srbf_deon_c.h). */
#include "srbf_deon_c.h"

#include "srbf_deon.h"

#include <stdlib.h>
#include <string.h>

void slc_srbf_deon_batch(const sl_fiber_params *fp, const float *C, const float *H, const float *D,
                         size_t n, const float *in, float *out) {
    int no = sl_srbf_deon_orders(fp);
    size_t stride = (size_t)no + 3;
    float o[SL_SRBF_DEON_NOUT];
    for (size_t r = 0; r < n; r++) {
        const float *x = in + 5 * r;
        sl_srbf_deon(fp, C, H, D, x[0], x[1], x[2], x[3], x[4], o);
        for (size_t k = 0; k < stride; k++)
            out[stride * r + k] = o[k];
    }
}

void slc_srbf_deon_rgb_scalar(const sl_fiber_params *fp, const float *C, const float *H,
                              const float *D, size_t n, const float *in, const float *sigma_a,
                              float *out) {
    for (size_t r = 0; r < n; r++) {
        const float *x = in + 5 * r;
        sl_srbf_deon_rgb_row(fp, C, H, D, x[0], x[1], x[2], x[3], x[4],
                             sigma_a ? sigma_a + 3 * r : NULL, out + 9 * r);
    }
}

#define SLC_CHIANG_BATCH slc_srbf_chiang_rgb_batch_base
#include "srbf_chiang_batch.inc"

int slc_simd_avx2(void) {
#if defined(__x86_64__) && defined(__GNUC__)
    const char *v = getenv("SL_SIMD");
    if (v && strcmp(v, "base") == 0) return 0;
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
    return 0;
#endif
}

void slc_srbf_chiang_rgb_batch(int avx2, const sl_fiber_params *fp, const float *C, const float *H,
                               const float *D, size_t n, const float *in, const float *sigma_a,
                               float *out) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (avx2) {
        slc_srbf_chiang_rgb_batch_avx2(fp, C, H, D, n, in, sigma_a, out);
        return;
    }
#else
    (void)avx2;
#endif
    slc_srbf_chiang_rgb_batch_base(fp, C, H, D, n, in, sigma_a, out);
}

void slc_srbf_deon_rgb_batch(const sl_fiber_params *fp, const float *C, const float *H,
                             const float *D, size_t n, const float *in, const float *sigma_a,
                             float *out) {
    if (fp->model == 2)
        slc_srbf_chiang_rgb_batch(slc_simd_avx2(), fp, C, H, D, n, in, sigma_a, out);
    else
        slc_srbf_deon_rgb_scalar(fp, C, H, D, n, in, sigma_a, out);
}
