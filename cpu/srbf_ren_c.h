/* srbf_ren_c.h: the precomputed SRBF response table of Ren 2010 Sec. 4 as the lookups see it,
 * and the C twin's batch lookup (kernels/srbf_ren_lookup.h; the table is built and cached by
 * host/passes/shade/srbf_ren.c, docs/srbf_ren.md). One thread; the per-row work is a fixed 16-corner
 * quadrilinear blend per mode with no branch on the data. */
#ifndef SL_SRBF_REN_C_H
#define SL_SRBF_REN_C_H

#include <stddef.h>
#include <stdint.h>

#include "srbf_ren_lookup.h"

typedef struct sl_srbf_ren {
    sl_srbf_ren_dims dims;
    float *T; /* n_floats: R block (1 channel), TT (3), TRT (3); kernels/srbf_ren_lookup.h */
    size_t n_floats;
    uint64_t key;      /* hash of the material, the table parameters and the fast path's tables */
    uint64_t material; /* hash of the material alone (sl_srbf_ren_material_hash) */
    double build_s;    /* seconds the build took (as stored in the cache) */
    /* its own interpolation error, measured after the build against the closed form it was
     * built from at SL_SRBF_REN_CHECK_POINTS random points (error of numerics.md sec. 5 on the
     * total I, channel r): median, 95th percentile, maximum */
    double err_median, err_p95, err_max;
    char built_on[256]; /* "C path (N threads)" or the OpenCL device's name */
    int from_cache;     /* 1: loaded from the disk cache */
    char path[4096];    /* the cache file ("" when there is no cache directory) */
} sl_srbf_ren;

/* in: 5 floats per row (theta_o, phi_o, theta_j, phi_j, lambda; fiber frame, lambda > 0);
 * out: 9 per row (I_R rgb, I_TT rgb, I_TRT rgb; R is the same in the three channels). */
void slc_srbf_ren_batch(const sl_srbf_ren *t, size_t n, const float *in, float *out);

#endif
