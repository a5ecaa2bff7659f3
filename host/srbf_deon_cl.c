/* srbf_deon_cl.c: OpenCL driver of the d'Eon fast SRBF response (see srbf_deon_cl.h). */
#include "srbf_deon_cl.h"

#include "srbf_deon.h"

int slcl_srbf_deon_batch(sl_cl *cl, const sl_fiber_params *fp, const sl_srbf_tables *t, size_t n,
                         const float *in, float *out, sl_err *e) {
    if (n == 0) return 0;
    if (n > 0xffffffffu) return sl_fail(e, "sl_srbf_deon_eval: too many rows (%zu)", n);
    int no = fp->orders > SL_DEON_MAX_ORDERS ? SL_DEON_MAX_ORDERS : fp->orders;
    size_t stride = (size_t)no + 3;
    cl_kernel k;
    int rc = sl_cl_get_kernel(cl, "srbf_deon_eval.cl", "sl_srbf_deon_eval", "", &k, e);
    if (rc) return rc;
    cl_context ctx = sl_cl_context(cl);
    cl_int err;
    cl_mem buf[5] = {NULL, NULL, NULL, NULL, NULL};
    const size_t sizes[5] = {n * 5, n * stride, SL_SRBF_C_FLOATS, SL_SRBF_H_FLOATS,
                             SL_SRBF_DEON_FLOATS};
    const float *src[5] = {in, NULL, t->C, t->H, t->D};
    err = CL_SUCCESS;
    for (int a = 0; a < 5 && err == CL_SUCCESS; a++)
        buf[a] = clCreateBuffer(
            ctx, src[a] ? CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR : CL_MEM_WRITE_ONLY,
            sizes[a] * sizeof(float), (void *)src[a], &err);
    rc = sl_cl_check(err, "clCreateBuffer", e);
    cl_uint nn = (cl_uint)n;
    if (!rc) {
        err = clSetKernelArg(k, 0, sizeof *fp, fp);
        if (err == CL_SUCCESS) err = clSetKernelArg(k, 1, sizeof nn, &nn);
        for (cl_uint a = 0; a < 5 && err == CL_SUCCESS; a++)
            err = clSetKernelArg(k, 2 + a, sizeof(cl_mem), &buf[a]);
        rc = sl_cl_check(err, "clSetKernelArg", e);
    }
    if (!rc) rc = sl_cl_run1d(cl, k, "sl_srbf_deon_eval", n, 64, NULL, e);
    if (!rc)
        rc = sl_cl_check(clEnqueueReadBuffer(sl_cl_queue(cl), buf[1], CL_TRUE, 0,
                                             n * stride * sizeof(float), out, 0, NULL, NULL),
                         "clEnqueueReadBuffer", e);
    for (int a = 0; a < 5; a++)
        if (buf[a]) clReleaseMemObject(buf[a]);
    return rc;
}

int slcl_srbf_deon_rgb_batch(sl_cl *cl, const sl_fiber_params *fp, const sl_srbf_tables *t,
                             size_t n, const float *in, const float *sigma_a, float *out,
                             sl_err *e) {
    if (n == 0) return 0;
    if (n > 0xffffffffu) return sl_fail(e, "sl_srbf_deon_rgb: too many rows (%zu)", n);
    cl_kernel k;
    int rc = sl_cl_get_kernel(cl, "srbf_deon_eval.cl", "sl_srbf_deon_rgb", "", &k, e);
    if (rc) return rc;
    cl_context ctx = sl_cl_context(cl);
    cl_int err = CL_SUCCESS;
    float dummy = 0.0f;
    cl_mem buf[6] = {NULL, NULL, NULL, NULL, NULL, NULL};
    const size_t sizes[6] = {
        n * 5, sigma_a ? n * 3 : 1, n * 9, SL_SRBF_C_FLOATS, SL_SRBF_H_FLOATS, SL_SRBF_DEON_FLOATS};
    const float *src[6] = {in, sigma_a ? sigma_a : &dummy, NULL, t->C, t->H, t->D};
    for (int a = 0; a < 6 && err == CL_SUCCESS; a++)
        buf[a] = clCreateBuffer(
            ctx, src[a] ? CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR : CL_MEM_WRITE_ONLY,
            sizes[a] * sizeof(float), (void *)src[a], &err);
    rc = sl_cl_check(err, "clCreateBuffer", e);
    cl_uint nn = (cl_uint)n;
    cl_int use_sig = sigma_a != NULL;
    if (!rc) {
        err = clSetKernelArg(k, 0, sizeof *fp, fp);
        if (err == CL_SUCCESS) err = clSetKernelArg(k, 1, sizeof nn, &nn);
        if (err == CL_SUCCESS) err = clSetKernelArg(k, 2, sizeof(cl_mem), &buf[0]);
        if (err == CL_SUCCESS) err = clSetKernelArg(k, 3, sizeof(cl_mem), &buf[1]);
        if (err == CL_SUCCESS) err = clSetKernelArg(k, 4, sizeof use_sig, &use_sig);
        for (cl_uint a = 2; a < 6 && err == CL_SUCCESS; a++)
            err = clSetKernelArg(k, 3 + a, sizeof(cl_mem), &buf[a]);
        rc = sl_cl_check(err, "clSetKernelArg", e);
    }
    if (!rc) rc = sl_cl_run1d(cl, k, "sl_srbf_deon_rgb", n, 64, NULL, e);
    if (!rc)
        rc = sl_cl_check(clEnqueueReadBuffer(sl_cl_queue(cl), buf[2], CL_TRUE, 0,
                                             n * 9 * sizeof(float), out, 0, NULL, NULL),
                         "clEnqueueReadBuffer", e);
    for (int a = 0; a < 6; a++)
        if (buf[a]) clReleaseMemObject(buf[a]);
    return rc;
}
