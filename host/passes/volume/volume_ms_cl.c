/* volume_ms_cl.c: see volume_ms_cl.h. */
#include "passes/volume/volume_ms_cl.h"

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
    if (!err) err = clSetKernelArg(k, a++, sizeof ms->fp[ch], &ms->fp[ch]);
    if (!err) err = clSetKernelArg(k, a++, sizeof b[0], &b[0]);
    if (!err && exact) err = clSetKernelArg(k, a++, sizeof b[1], &b[1]);
    if (!err) err = clSetKernelArg(k, a++, sizeof nn, &nn);
    if (!err) err = clSetKernelArg(k, a++, sizeof b[2], &b[2]);
    if (!err) err = clSetKernelArg(k, a++, sizeof b[3], &b[3]);
    size_t local = LOCAL, global = (n + LOCAL - 1) / LOCAL * LOCAL;
    if (!err)
        err = clEnqueueNDRangeKernel(sl_cl_queue(cl), k, 1, NULL, &global, &local, 0, NULL, NULL);
    if (!err)
        err = clEnqueueReadBuffer(sl_cl_queue(cl), b[3], CL_TRUE, 0, 2 * n * sizeof(float), out, 0,
                                  NULL, NULL);
    rc = sl_cl_check(err, "ms response: opencl", e);
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
