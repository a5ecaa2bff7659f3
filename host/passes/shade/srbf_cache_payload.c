/* srbf_cache_payload.c: see srbf_cache_payload.h. */
#include "passes/shade/srbf_cache_payload.h"

#include "srbf_deon.h"
#include "srbf_xu.h"

#include <stdlib.h>
#include <string.h>

size_t sl_srbf_tables_payload_bytes(void) {
    return sizeof(sl_srbf_tables_meta) +
           (SL_SRBF_C_FLOATS + SL_SRBF_H_FLOATS + SL_SRBF_DEON_FLOATS) * sizeof(float);
}

int sl_srbf_tables_from_payload(sl_srbf_tables *t, const void *data, size_t n) {
    const size_t nC = SL_SRBF_C_FLOATS * sizeof(float), nH = SL_SRBF_H_FLOATS * sizeof(float),
                 nD = SL_SRBF_DEON_FLOATS * sizeof(float);
    sl_srbf_tables_meta h;
    if (n != sizeof h + nC + nH + nD) return -1;
    const unsigned char *d = data;
    memcpy(&h, d, sizeof h);
    t->C = sl_malloc(nC);
    t->H = sl_malloc(nH);
    t->D = sl_malloc(nD);
    memcpy(t->C, d + sizeof h, nC);
    memcpy(t->H, d + sizeof h + nC, nH);
    memcpy(t->D, d + sizeof h + nC + nH, nD);
    t->build_s_C = h.build_s_C;
    t->build_s_H = h.build_s_H;
    t->err_C = h.err_C;
    t->err_H = h.err_H;
    t->build_s_W = h.build_s_W;
    t->err_W = h.err_W;
    t->err_D = h.err_D;
    t->err_Ch_x = h.err_Ch_x;
    t->err_Ch_s = h.err_Ch_s;
    t->from_cache = 1;
    return 0;
}

int sl_srbf_ren_from_payload(sl_srbf_ren *t, const void *data, size_t n) {
    sl_srbf_ren_meta h;
    /* n_floats comes from the caller's parameters; a product that overflows cannot match n */
    if (t->n_floats > (SIZE_MAX - sizeof h) / sizeof(float)) return -1;
    const size_t nT = t->n_floats * sizeof(float);
    const unsigned char *d = data;
    if (n != sizeof h + nT) return -1;
    memcpy(&h, d, sizeof h);
    if (h.n_floats != t->n_floats || memcmp(&h.dims, &t->dims, sizeof h.dims) != 0) return -1;
    t->T = sl_malloc(nT);
    memcpy(t->T, d + sizeof h, nT);
    t->build_s = h.build_s;
    t->err_median = h.err_median;
    t->err_p95 = h.err_p95;
    t->err_max = h.err_max;
    memcpy(t->built_on, h.built_on, sizeof t->built_on);
    t->built_on[sizeof t->built_on - 1] = 0;
    t->from_cache = 1;
    return 0;
}
