/* srbf_check.c: the `strandlight kernels` check of the SRBF response: kernels/srbf.cl
 * (host/passes/shade/srbf_cl.c) against its C twin (cpu/srbf_c.c). */
#include "verify/checks/kernel_checks.h"

#include "passes/shade/srbf_cl.h"
#include "srbf_c.h"
#include "verify/report/srbf_sample.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* `strandlight kernels --only srbf`: srbf.cl against the C twin on the stiff sample's
 * configurations (default material), --method fast then xu (m = 4) in one output vector. */
int slchk_srbf(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r, sl_err *e) {
    size_t n = o->size > 0 ? (size_t)o->size : 4096;
    int reps = o->reps > 0 ? o->reps : 3;
    snprintf(r->problem, sizeof r->problem, "%zu lobes x (fast, xu m=4)", n);
    /* Same float code and tables; only the transcendental functions (exp, log, asin, sqrt) of the
     * device's math library differ by an ulp or two, which the sums and bilinear weights carry
     * through: relative 1e-3, or 1e-6 absolute for responses near 0 (I is O(1e-3..1)). */
    r->tol_abs = 1e-6;
    r->tol_rel = 1e-3;
    snprintf(r->note, sizeof r->note,
             "same float code and tables; device exp/log/asin differ by ulps");
    sl_srbf_config *cfg = sl_malloc(n * sizeof *cfg);
    float *in = sl_malloc(n * 5 * sizeof *in), *a = sl_malloc(n * 8 * sizeof *a),
          *b = sl_malloc(n * 8 * sizeof *b);
    sl_srbf_sample(SL_SRBF_SAMPLE_SEED, (int)n, cfg);
    for (size_t i = 0; i < n; i++)
        sl_srbf_config_row(cfg + i, in + 5 * i);
    sl_material m;
    sl_material_default(&m);
    sl_fiber_params fp;
    sl_material_to_fiber(&m, 0, &fp);
    sl_srbf_tables t;
    int rc = sl_srbf_tables_get(&t, 0, e);
    r->c_s = r->cl_s = r->cl_wall_s = INFINITY;
    /* untimed first run: program build */
    if (!rc) rc = slcl_srbf_batch(cl, &fp, &t, SL_SRBF_METHOD_FAST, 4, n, in, a, e);
    for (int k = 0; k < reps && !rc; k++) {
        double t0 = sl_now();
        rc = slcl_srbf_batch(cl, &fp, &t, SL_SRBF_METHOD_FAST, 4, n, in, a, e);
        if (!rc) rc = slcl_srbf_batch(cl, &fp, &t, SL_SRBF_METHOD_XU, 4, n, in, a + 4 * n, e);
        double wall = sl_now() - t0;
        if (wall < r->cl_wall_s) r->cl_wall_s = r->cl_s = wall;
        t0 = sl_now();
        slc_srbf_batch(&fp, t.C, t.H, SL_SRBF_METHOD_FAST, 4, n, in, b);
        slc_srbf_batch(&fp, t.C, t.H, SL_SRBF_METHOD_XU, 4, n, in, b + 4 * n);
        double c = sl_now() - t0;
        if (c < r->c_s) r->c_s = c;
    }
    r->cl_s_is_device = 0;
    if (!rc) sl_kernel_compare(a, b, n * 8, r);
    if (t.C) sl_srbf_tables_free(&t);
    free(cfg);
    free(in);
    free(a);
    free(b);
    return rc;
}
