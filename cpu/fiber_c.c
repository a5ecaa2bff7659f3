/* fiber_c.c: the C twin's batch drivers (see fiber_c.h). Each row calls the float entry point of
 * kernels/fiber_marschner.h, kernels/fiber_deon.h, kernels/fiber_chiang.h or
 * kernels/fiber_furnace.h, exactly as the OpenCL kernels in kernels/fiber.cl do. The per-row
 * work is branchy (root solves, adaptive windows), so SSE lanes across rows do not pay here: it is
 * plain scalar float. */
#include "fiber_c.h"

#include "fiber_chiang.h"
#include "fiber_deon.h"
#include "fiber_furnace.h"
#include "fiber_marschner.h"

size_t slc_scatter_width(const sl_fiber_params *fp) {
    if (fp->model == 2) return 5; /* chiang: f_0, f_1, f_2, f_rest, f */
    return fp->model == 1 ? (size_t)fp->orders + 3 : 4;
}

void slc_scatter_batch(const sl_fiber_params *fp, size_t n, const float *in, float *out) {
    slc_scatter_rows(fp, n, in, 4, out);
}

void slc_scatter_rows(const sl_fiber_params *fp, size_t n, const float *in, size_t in_w,
                      float *out) {
    size_t w = slc_scatter_width(fp);
    for (size_t i = 0; i < n; i++) {
        const float *r = in + in_w * i;
        float *o = out + w * i;
        if (fp->model == 2 && in_w >= 8)
            sl_chiang_scatter_lo(fp, r[0], r[1], r[2], r[5], r[3], o);
        else if (fp->model == 2)
            sl_chiang_scatter(fp, r[0], r[1], r[2], r[3], o);
        else if (fp->model == 1 && in_w >= 8)
            sl_deon_scatter_lo(fp, r[0], r[4], r[1], r[2], r[5], r[3], o);
        else if (fp->model == 1)
            sl_deon_scatter(fp, r[0], r[1], r[2], r[3], o);
        else if (in_w >= 8)
            sl_marschner_scatter_lo(fp, r[0], r[4], r[1], r[6], r[2], r[5], r[3], r[7], o);
        else
            sl_marschner_scatter(fp, r[0], r[1], r[2], r[3], o);
    }
}

void slc_deon_mp_batch(size_t n, const float *in, float *out) {
    for (size_t i = 0; i < n; i++) {
        float lm = sl_deon_log_mp(in[3 * i], in[3 * i + 1], in[3 * i + 2]);
        out[2 * i] = exp(lm); /* may underflow to 0; log_M stays finite */
        out[2 * i + 1] = lm;
    }
}

void slc_furnace_batch(const sl_fiber_params *fp, size_t n, const float *in, float *out) {
    for (size_t i = 0; i < n; i++) {
        out[i] = sl_furnace(fp, in[2 * i], in[2 * i + 1]);
    }
}
