/* dual_cl.c: see dual_cl.h. */
#include "passes/volume/dual_cl.h"

#include "cl/cl_args.h"
#include "dual_material.h"

#include <stdlib.h>

#define LOCAL 64u

int slcl_dual_table(sl_cl *cl, const sl_fiber_params *fp, float *tab, sl_err *e) {
    cl_kernel k;
    int rc = sl_cl_get_kernel(cl, "dual.cl", "sl_dual_table_nodes", NULL, &k, e);
    if (rc) return rc;
    cl_int err;
    cl_mem b = clCreateBuffer(sl_cl_context(cl), CL_MEM_WRITE_ONLY,
                              SL_DUAL_TABLE_FLOATS * sizeof(float), NULL, &err);
    if (sl_cl_check(err, "dual: clCreateBuffer", e)) return -1;
    sl_cl_args args = sl_cl_args_begin(k, e);
    SL_CL_ARG(&args, 0, *fp);
    SL_CL_ARG(&args, 1, b);
    if (sl_cl_args_end(&args)) {
        clReleaseMemObject(b);
        return -1;
    }
    size_t local = LOCAL, global = sl_cl_round_up(SL_DUAL_N, LOCAL);
    if (!err)
        err = clEnqueueNDRangeKernel(sl_cl_queue(cl), k, 1, NULL, &global, &local, 0, NULL, NULL);
    if (!err)
        err = clEnqueueReadBuffer(sl_cl_queue(cl), b, CL_TRUE, 0,
                                  SL_DUAL_ROWS * SL_DUAL_N * sizeof(float), tab, 0, NULL, NULL);
    clReleaseMemObject(b);
    if (sl_cl_check(err, "dual: sl_dual_table_nodes", e)) return -1;
    sl_dual_build_sats(tab); /* the twin's own code: the same sums */
    return 0;
}

int slcl_ms_material_batch(sl_cl *cl, const sl_fiber_params *fp, size_t n, const float *in,
                           float *out, sl_err *e) {
    if (n == 0) return 0;
    if (n > 0xffffffffu) return sl_fail(e, "ms-material: %zu rows is too many", n);
    float *tab = sl_malloc(SL_DUAL_TABLE_FLOATS * sizeof *tab);
    int rc = slcl_dual_table(cl, fp, tab, e);
    if (!rc) rc = slcl_ms_material_lookup(cl, tab, n, in, out, e);
    free(tab);
    return rc;
}

int slcl_ms_material_lookup(sl_cl *cl, const float *tab, size_t n, const float *in, float *out,
                            sl_err *e) {
    if (n == 0) return 0;
    if (n > 0xffffffffu) return sl_fail(e, "ms-material: %zu rows is too many", n);
    cl_kernel k;
    int rc = sl_cl_get_kernel(cl, "dual.cl", "sl_dual_lookup_rows", NULL, &k, e);
    if (rc) return rc;
    cl_context ctx = sl_cl_context(cl);
    cl_int err = 0;
    cl_mem bt = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                               SL_DUAL_TABLE_FLOATS * sizeof(float), (void *)tab, &err);
    cl_mem bi = NULL, bo = NULL;
    if (!err)
        bi = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(float),
                            (void *)in, &err);
    if (!err) bo = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, 9 * n * sizeof(float), NULL, &err);
    cl_uint nn = (cl_uint)n;
    int args_failed = 0;
    if (!err) {
        sl_cl_args args = sl_cl_args_begin(k, e);
        SL_CL_ARG(&args, 0, bt);
        SL_CL_ARG(&args, 1, nn);
        SL_CL_ARG(&args, 2, bi);
        SL_CL_ARG(&args, 3, bo);
        args_failed = sl_cl_args_end(&args);
    }
    size_t local = LOCAL, global = sl_cl_round_up(n, LOCAL);
    if (!err && !args_failed)
        err = clEnqueueNDRangeKernel(sl_cl_queue(cl), k, 1, NULL, &global, &local, 0, NULL, NULL);
    if (!err && !args_failed)
        err = clEnqueueReadBuffer(sl_cl_queue(cl), bo, CL_TRUE, 0, 9 * n * sizeof(float), out, 0,
                                  NULL, NULL);
    rc = args_failed ? -1 : sl_cl_check(err, "ms-material: opencl", e);
    if (bt) clReleaseMemObject(bt);
    if (bi) clReleaseMemObject(bi);
    if (bo) clReleaseMemObject(bo);
    return rc;
}
