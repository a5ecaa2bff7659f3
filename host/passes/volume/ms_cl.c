/* ms_cl.c: see ms_cl.h. */
#include "passes/volume/ms_cl.h"

#include "cl/cl_args.h"
#include "ms_table.h"

#define LOCAL 64u

/* Both kernels of ms.cl: the table's (exact = 0) reads one buffer, the direct one two. */
static int rows(sl_cl *cl, const sl_volume_ms *ms, int ch, int exact, size_t n, const float *in,
                float *out, sl_err *e) {
    if (n == 0) return 0;
    if (ch < 0 || ch > 2) return sl_fail(e, "ms response: channel %d (expected 0-2)", ch);
    if (n > 0xffffffffu) return sl_fail(e, "ms response: %zu rows is too many", n);
    cl_kernel k;
    int rc = sl_cl_get_kernel(cl, "ms.cl", exact ? "sl_ms_response_rows" : "sl_ms_table_rows", NULL,
                              &k, e);
    if (rc) return rc;
    cl_context ctx = sl_cl_context(cl);
    cl_int err = 0;
    cl_mem b[4] = {0};
    if (exact) {
        b[0] = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                              SL_DUAL_TABLE_FLOATS * sizeof(float), (void *)ms->dt.tab[ch], &err);
        if (!err)
            b[1] = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                  SL_MSR_TABLE_FLOATS * sizeof(float),
                                  (void *)(ms->ng + (size_t)ch * SL_MSR_TABLE_FLOATS), &err);
    } else {
        b[0] = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                              SL_MST_FLOATS * sizeof(float),
                              (void *)(ms->mt + (size_t)ch * SL_MST_FLOATS), &err);
    }
    if (!err)
        b[2] = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, 6 * n * sizeof(float),
                              (void *)in, &err);
    if (!err) b[3] = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, 2 * n * sizeof(float), NULL, &err);
    cl_uint nn = (cl_uint)n, a = 0;
    int args_failed = 0;
    if (!err) {
        sl_cl_args args = sl_cl_args_begin(k, e);
        SL_CL_ARG(&args, a++, ms->fp[ch]);
        SL_CL_ARG(&args, a++, b[0]);
        if (exact) SL_CL_ARG(&args, a++, b[1]);
        SL_CL_ARG(&args, a++, nn);
        SL_CL_ARG(&args, a++, b[2]);
        SL_CL_ARG(&args, a++, b[3]);
        args_failed = sl_cl_args_end(&args);
    }
    size_t local = LOCAL, global = (n + LOCAL - 1) / LOCAL * LOCAL;
    if (!err && !args_failed)
        err = clEnqueueNDRangeKernel(sl_cl_queue(cl), k, 1, NULL, &global, &local, 0, NULL, NULL);
    if (!err && !args_failed)
        err = clEnqueueReadBuffer(sl_cl_queue(cl), b[3], CL_TRUE, 0, 2 * n * sizeof(float), out, 0,
                                  NULL, NULL);
    rc = args_failed ? -1 : sl_cl_check(err, "ms response: opencl", e);
    for (int i = 0; i < 4; i++)
        if (b[i]) clReleaseMemObject(b[i]);
    return rc;
}

int slcl_ms_response_rows(sl_cl *cl, const sl_volume_ms *ms, int ch, size_t n, const float *in,
                          float *out, sl_err *e) {
    return rows(cl, ms, ch, 0, n, in, out, e);
}

int slcl_ms_response_rows_exact(sl_cl *cl, const sl_volume_ms *ms, int ch, size_t n,
                                const float *in, float *out, sl_err *e) {
    return rows(cl, ms, ch, 1, n, in, out, e);
}
