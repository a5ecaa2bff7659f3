/* srbf_cl.c: OpenCL driver of the SRBF response (see srbf_cl.h). */
#include "srbf_cl.h"

#include "srbf_xu.h"

int slcl_srbf_batch(sl_cl *cl, const sl_fiber_params *fp, const sl_srbf_tables *t, int method,
                    int segments, size_t n, const float *in, float *out, sl_err *e) {
    if (n == 0) return 0;
    if (n > 0xffffffffu) return sl_fail(e, "sl_srbf_eval: too many rows (%zu)", n);
    cl_kernel k;
    int rc = sl_cl_get_kernel(cl, "srbf_eval.cl", "sl_srbf_eval", "", &k, e);
    if (rc) return rc;
    cl_context ctx = sl_cl_context(cl);
    cl_command_queue q = sl_cl_queue(cl);
    cl_int err;
    cl_mem buf[4] = {NULL, NULL, NULL, NULL};
    buf[0] = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * 5 * sizeof(float),
                            (void *)in, &err);
    if (err == CL_SUCCESS)
        buf[1] = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, n * 4 * sizeof(float), NULL, &err);
    if (err == CL_SUCCESS)
        buf[2] = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                SL_SRBF_C_FLOATS * sizeof(float), t->C, &err);
    if (err == CL_SUCCESS)
        buf[3] = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                SL_SRBF_H_FLOATS * sizeof(float), t->H, &err);
    rc = sl_cl_check(err, "clCreateBuffer", e);
    cl_uint nn = (cl_uint)n;
    cl_int meth = method, seg = segments;
    if (!rc) {
        err = clSetKernelArg(k, 0, sizeof *fp, fp);
        if (err == CL_SUCCESS) err = clSetKernelArg(k, 1, sizeof nn, &nn);
        for (cl_uint a = 0; a < 4 && err == CL_SUCCESS; a++)
            err = clSetKernelArg(k, 2 + a, sizeof(cl_mem), &buf[a]);
        if (err == CL_SUCCESS) err = clSetKernelArg(k, 6, sizeof meth, &meth);
        if (err == CL_SUCCESS) err = clSetKernelArg(k, 7, sizeof seg, &seg);
        rc = sl_cl_check(err, "clSetKernelArg", e);
    }
    if (!rc) {
        size_t local = 64, global;
        size_t maxwg = sl_cl_max_work_group_size(cl);
        if (maxwg && local > maxwg) local = maxwg;
        global = (n + local - 1) / local * local;
        rc = sl_cl_check(clEnqueueNDRangeKernel(q, k, 1, NULL, &global, &local, 0, NULL, NULL),
                         "sl_srbf_eval", e);
    }
    if (!rc)
        rc = sl_cl_check(
            clEnqueueReadBuffer(q, buf[1], CL_TRUE, 0, n * 4 * sizeof(float), out, 0, NULL, NULL),
            "clEnqueueReadBuffer", e);
    for (int a = 0; a < 4; a++)
        if (buf[a]) clReleaseMemObject(buf[a]);
    return rc;
}
