/* srbf_c.c: the C twin's SRBF batch drivers (see srbf_c.h). This file neither reads errno nor
 * FP exception flags, so it is compiled without math-errno (sqrt becomes one instruction instead
 * of a guarded libm call) and without trapping math (branch-free selects may be if-converted):
 * that lets GCC vectorise the 8-node longitudinal loop and the 4-node loops of
 * kernels/srbf_fast.h with SSE2 (measured: the longitudinal part 420 -> 190 ns per lobe). Same
 * IEEE arithmetic, no fast-math, no reassociation: results equal the scalar code's. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("no-math-errno", "no-trapping-math")
#endif
#include "srbf_c.h"

#include "srbf_fast.h"
#include "srbf_xu.h"

void slc_srbf_batch(const sl_fiber_params *fp, const float *C, const float *H, int method,
                    int segments, size_t n, const float *in, float *out) {
    for (size_t r = 0; r < n; r++) {
        const float *x = in + 5 * r;
        if (method == SL_SRBF_METHOD_FAST)
            sl_srbf_fast(fp, C, H, x[0], x[1], x[2], x[3], x[4], out + 4 * r);
        else
            sl_srbf_xu(fp, C, H, segments, x[0], x[1], x[2], x[3], x[4], out + 4 * r);
    }
}

void slc_srbf_rgb_scalar(const sl_fiber_params *fp, const float *C, const float *H, int method,
                         int segments, size_t n, const float *in, const float *sigma_a,
                         float *out) {
    for (size_t r = 0; r < n; r++) {
        const float *x = in + 5 * r;
        float sig[3] = {fp->sigma_a, fp->sigma_a, fp->sigma_a};
        if (sigma_a)
            sig[0] = sigma_a[3 * r], sig[1] = sigma_a[3 * r + 1], sig[2] = sigma_a[3 * r + 2];
        float *o = out + 9 * r;
        sl_srbf_rgb_row(fp, C, H, method, segments, x[0], x[1], x[2], x[3], x[4], sig, o);
    }
}

void slc_srbf_rgb_batch(const sl_fiber_params *fp, const float *C, const float *H, int method,
                        int segments, size_t n, const float *in, const float *sigma_a, float *out) {
    slc_srbf_rgb_scalar(fp, C, H, method, segments, n, in, sigma_a, out);
}
