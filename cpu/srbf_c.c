/* srbf_c.c: the C twin's SRBF batch driver (see srbf_c.h). */
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
