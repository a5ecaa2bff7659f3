/* srbf_ren_cl.c: the OpenCL lookup of the SRBF response table (kernels/srbf_ren.cl; see
 * srbf_ren.h): one work-item per row, the table uploaded per batch or kept resident. */
#include "passes/shade/srbf_ren.h"

#include "cl/cl_args.h"

int slcl_srbf_ren_enqueue(sl_cl *cl, const sl_srbf_ren_dims *d, cl_mem T, size_t n, cl_mem in,
                          cl_mem out, sl_err *e) {
    if (n == 0) return 0;
    if (n > 0xffffffffu / 9) return sl_fail(e, "srbf table: too many rows (%zu)", n);
    cl_kernel k;
    int rc = sl_cl_get_kernel(cl, "srbf_ren.cl", "sl_srbf_ren_eval", "", &k, e);
    if (rc) return rc;
    cl_uint nn = (cl_uint)n;
    sl_cl_args args = sl_cl_args_begin(k, e);
    SL_CL_ARG(&args, 0, *d);
    SL_CL_ARG(&args, 1, nn);
    SL_CL_ARG(&args, 2, in);
    SL_CL_ARG(&args, 3, out);
    SL_CL_ARG(&args, 4, T);
    if (sl_cl_args_end(&args)) return -1;
    size_t local = 64, global;
    size_t maxwg = sl_cl_max_work_group_size(cl);
    if (maxwg && local > maxwg) local = maxwg;
    global = (n + local - 1) / local * local;
    return sl_cl_check(
        clEnqueueNDRangeKernel(sl_cl_queue(cl), k, 1, NULL, &global, &local, 0, NULL, NULL),
        "sl_srbf_ren_eval", e);
}

int slcl_srbf_ren_rows(sl_cl *cl, const sl_srbf_ren *t, cl_mem *table, const char *table_what,
                       size_t n, const float *in, float *out, sl_err *e) {
    if (n == 0) return 0;
    if (n > 0xffffffffu / 9) return sl_fail(e, "srbf table: too many rows (%zu)", n);
    cl_context ctx = sl_cl_context(cl);
    cl_int err = CL_SUCCESS;
    if (!*table) {
        *table = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                t->n_floats * sizeof(float), t->T, &err);
        if (sl_cl_check(err, table_what, e)) {
            *table = NULL;
            return -1;
        }
    }
    cl_mem bi = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * 5 * sizeof(float),
                               (void *)in, &err),
           bo = NULL;
    if (err == CL_SUCCESS)
        bo = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, n * 9 * sizeof(float), NULL, &err);
    int rc = sl_cl_check(err, "clCreateBuffer", e);
    if (!rc) rc = slcl_srbf_ren_enqueue(cl, &t->dims, *table, n, bi, bo, e);
    if (!rc)
        rc = sl_cl_check(clEnqueueReadBuffer(sl_cl_queue(cl), bo, CL_TRUE, 0, n * 9 * sizeof(float),
                                             out, 0, NULL, NULL),
                         "clEnqueueReadBuffer", e);
    if (bi) clReleaseMemObject(bi);
    if (bo) clReleaseMemObject(bo);
    return rc;
}

/* One batch with the table uploaded for it alone. */
int slcl_srbf_ren_batch(sl_cl *cl, const sl_srbf_ren *t, size_t n, const float *in, float *out,
                        sl_err *e) {
    cl_mem table = NULL;
    int rc = slcl_srbf_ren_rows(cl, t, &table, "clCreateBuffer", n, in, out, e);
    slcl_srbf_ren_table_release(&table);
    return rc;
}

void slcl_srbf_ren_table_release(cl_mem *table) {
    if (*table) clReleaseMemObject(*table);
    *table = NULL;
}
