/* srbf_ren_c.c: the C twin's batch lookup in the Ren 2010 table (see srbf_ren_c.h). */
#include "srbf_ren_c.h"

void slc_srbf_ren_batch(const sl_srbf_ren *t, size_t n, const float *in, float *out) {
    sl_srbf_ren_dims d = t->dims;
    const float *T = t->T;
    for (size_t r = 0; r < n; r++) {
        const float *x = in + 5 * r;
        sl_srbf_ren_lookup(T, &d, x[0], x[1], x[2], x[3], x[4], out + 9 * r);
    }
}
