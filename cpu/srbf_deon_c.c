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

void slc_srbf_deon_rgb_scalar(const sl_fiber_params *fp, const float *C, const float *H,
                              const float *D, size_t n, const float *in, const float *sigma_a,
                              float *out) {
    for (size_t r = 0; r < n; r++) {
        const float *x = in + 5 * r;
        sl_srbf_deon_rgb_row(fp, C, H, D, x[0], x[1], x[2], x[3], x[4],
                             sigma_a ? sigma_a + 3 * r : NULL, out + 9 * r);
    }
}

/* Model chiang: the renderer's rows come point by point (theta_o and sigma_a repeat while the
 * lobes vary), so the point's constants (sl_srbf_chiang_point: Fresnel, absorption and the
 * harmonic sums B_n at 12 nodes, about half of a row's work) are built when theta_o or sigma_a
 * change and reused otherwise: the same operations on the same values as the row by row
 * sl_srbf_deon_rgb_row, so the results are bit for bit those of slc_srbf_deon_rgb_scalar. */
static void chiang_rgb_batch(const sl_fiber_params *fp, const float *C, const float *H,
                             const float *D, size_t n, const float *in, const float *sigma_a,
                             float *out) {
    sl_srbf_chiang_point pt;
    int nch = sigma_a ? 3 : 1, have = 0;
    float key[4] = {0, 0, 0, 0};
    for (size_t r = 0; r < n; r++) {
        const float *x = in + 5 * r, *sg = sigma_a ? sigma_a + 3 * r : NULL;
        int same = have && x[0] == key[0];
        for (int c = 0; c < nch && sg; c++)
            same = same && sg[c] == key[1 + c];
        if (!same) {
            sl_srbf_chiang_point_init(fp, D, x[0], nch, sg, &pt);
            key[0] = x[0];
            for (int c = 0; c < nch && sg; c++)
                key[1 + c] = sg[c];
            have = 1;
        }
        float o[5 * SL_SRBF_CH_MAXC];
        sl_srbf_chiang_rgb_at(C, H, &pt, x[1], x[2], x[3], x[4], o);
        sl_srbf_chiang_rgb_out(nch, o, out + 9 * r);
    }
}

void slc_srbf_deon_rgb_batch(const sl_fiber_params *fp, const float *C, const float *H,
                             const float *D, size_t n, const float *in, const float *sigma_a,
                             float *out) {
    if (fp->model == 2)
        chiang_rgb_batch(fp, C, H, D, n, in, sigma_a, out);
    else
        slc_srbf_deon_rgb_scalar(fp, C, H, D, n, in, sigma_a, out);
}
