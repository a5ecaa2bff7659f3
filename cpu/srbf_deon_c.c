/* srbf_deon_c.c: the C twin's batch driver of the d'Eon fast SRBF response (see srbf_deon_c.h). */
#include "srbf_deon_c.h"

#include "srbf_deon.h"

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

void slc_srbf_deon_rgb_batch(const sl_fiber_params *fp, const float *C, const float *H,
                             const float *D, size_t n, const float *in, const float *sigma_a,
                             float *out) {
    for (size_t r = 0; r < n; r++) {
        const float *x = in + 5 * r;
        sl_srbf_deon_rgb_row(fp, C, H, D, x[0], x[1], x[2], x[3], x[4],
                             sigma_a ? sigma_a + 3 * r : NULL, out + 9 * r);
    }
}
