/* dual_c.c: C twin of kernels/dual_material.h: table construction and the `ms-material` batch. */
#include "dual_c.h"

#include <stdlib.h>

#include "dual_material.h"

void slc_dual_table(const sl_fiber_params *fp, float *tab) {
    sl_dual_kern k;
    sl_dual_kern_init(fp, &k);
    for (int i = 0; i < SL_DUAL_N; i++) {
        float v[9];
        sl_dual_terms_k(fp, sl_dual_node(i), &k, v);
        for (int r = 0; r < 9; r++)
            tab[r * SL_DUAL_N + i] = v[r];
    }
    sl_dual_build_sats(tab);
}

void slc_ms_material_batch(const sl_fiber_params *fp, size_t n, const float *in, float *out) {
    float *tab = malloc(SL_DUAL_TABLE_FLOATS * sizeof *tab);
    if (!tab) abort();
    slc_dual_table(fp, tab);
    slc_ms_material_lookup(tab, n, in, out);
    free(tab);
}

void slc_ms_material_lookup(const float *tab, size_t n, const float *in, float *out) {
    for (size_t r = 0; r < n; r++)
        for (int k = 0; k < 9; k++)
            out[r * 9 + (size_t)k] = sl_dual_lookup(tab, k, in[r]);
}
