/* srbf_cl.c: OpenCL driver of the SRBF response (see srbf_cl.h). */
#include "srbf_cl.h"

#include "srbf_c.h"
#include "srbf_sample.h"
#include "srbf_xu.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* The -D options of srbf_eval.cl for this material and method (its header comment): the method
 * and m as constants, no Xu code for fast, no eccentric TRT for a round fiber. */
void slcl_srbf_options(const sl_fiber_params *fp, int method, int segments, char *buf,
                       size_t size) {
    if (method == SL_SRBF_METHOD_FAST)
        snprintf(buf, size, "-DSL_SRBF_SPEC_METHOD=1 -DSL_SRBF_FAST_ONLY%s",
                 fp->eccentricity == 1.0f ? " -DSL_SRBF_ROUND_ONLY" : "");
    else
        snprintf(buf, size, "-DSL_SRBF_SPEC_METHOD=0 -DSL_SRBF_SPEC_SEGMENTS=%d", segments);
}

/* The read-only copies of the C and H tables both kernels take, created only while *err is
 * CL_SUCCESS (the caller's chain of clCreateBuffer calls). */
static void srbf_table_buffers(cl_context ctx, const sl_srbf_tables *t, cl_mem *c, cl_mem *h,
                               cl_int *err) {
    if (*err == CL_SUCCESS)
        *c = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                            SL_SRBF_C_FLOATS * sizeof(float), t->C, err);
    if (*err == CL_SUCCESS)
        *h = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                            SL_SRBF_H_FLOATS * sizeof(float), t->H, err);
}

/* Unless rc is already an error: launch k over n rows (work groups of 64, or the device's
 * maximum) and read out_floats floats of buffer `res` back into out; then release the nbuf
 * buffers whatever happened. Returns the first error. */
static int srbf_run(sl_cl *cl, cl_kernel k, const char *name, size_t n, cl_mem res,
                    size_t out_floats, float *out, cl_mem *buf, int nbuf, int rc, sl_err *e) {
    cl_command_queue q = sl_cl_queue(cl);
    if (!rc) {
        size_t local = 64, global;
        size_t maxwg = sl_cl_max_work_group_size(cl);
        if (maxwg && local > maxwg) local = maxwg;
        global = (n + local - 1) / local * local;
        rc = sl_cl_check(clEnqueueNDRangeKernel(q, k, 1, NULL, &global, &local, 0, NULL, NULL),
                         name, e);
    }
    if (!rc)
        rc = sl_cl_check(
            clEnqueueReadBuffer(q, res, CL_TRUE, 0, out_floats * sizeof(float), out, 0, NULL, NULL),
            "clEnqueueReadBuffer", e);
    for (int a = 0; a < nbuf; a++)
        if (buf[a]) clReleaseMemObject(buf[a]);
    return rc;
}

int slcl_srbf_batch(sl_cl *cl, const sl_fiber_params *fp, const sl_srbf_tables *t, int method,
                    int segments, size_t n, const float *in, float *out, sl_err *e) {
    if (n == 0) return 0;
    if (n > 0xffffffffu) return sl_fail(e, "sl_srbf_eval: too many rows (%zu)", n);
    cl_kernel k;
    char opts[160];
    slcl_srbf_options(fp, method, segments, opts, sizeof opts);
    int rc = sl_cl_get_kernel(cl, "srbf_eval.cl", "sl_srbf_eval", opts, &k, e);
    if (rc) return rc;
    cl_context ctx = sl_cl_context(cl);
    cl_int err;
    cl_mem buf[4] = {NULL, NULL, NULL, NULL};
    buf[0] = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * 5 * sizeof(float),
                            (void *)in, &err);
    if (err == CL_SUCCESS)
        buf[1] = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, n * 4 * sizeof(float), NULL, &err);
    srbf_table_buffers(ctx, t, &buf[2], &buf[3], &err);
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
    return srbf_run(cl, k, "sl_srbf_eval", n, buf[1], n * 4, out, buf, 4, rc, e);
}

int slcl_srbf_rgb_batch_ex(sl_cl *cl, const sl_fiber_params *fp, const sl_srbf_tables *t,
                           int method, int segments, size_t n, const float *in,
                           const float *sigma_a, float *out, int generic, sl_err *e) {
    if (n == 0) return 0;
    if (n > 0xffffffffu) return sl_fail(e, "sl_srbf_eval_rgb: too many rows (%zu)", n);
    cl_kernel k;
    char opts[160] = "";
    if (!generic) slcl_srbf_options(fp, method, segments, opts, sizeof opts);
    int rc = sl_cl_get_kernel(cl, "srbf_eval.cl", "sl_srbf_eval_rgb", opts, &k, e);
    if (rc) return rc;
    cl_context ctx = sl_cl_context(cl);
    cl_int err;
    /* in, sigma (a 3-float dummy when NULL: a kernel argument may not be a NULL buffer on every
     * platform), out, C, H */
    cl_mem buf[5] = {NULL, NULL, NULL, NULL, NULL};
    float dummy[3] = {0, 0, 0};
    buf[0] = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * 5 * sizeof(float),
                            (void *)in, &err);
    if (err == CL_SUCCESS)
        buf[1] = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                (sigma_a ? n * 3 : 3) * sizeof(float),
                                sigma_a ? (void *)sigma_a : (void *)dummy, &err);
    if (err == CL_SUCCESS)
        buf[2] = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, n * 9 * sizeof(float), NULL, &err);
    srbf_table_buffers(ctx, t, &buf[3], &buf[4], &err);
    rc = sl_cl_check(err, "clCreateBuffer", e);
    cl_uint nn = (cl_uint)n;
    cl_int has = sigma_a != NULL, meth = method, seg = segments;
    if (!rc) {
        err = clSetKernelArg(k, 0, sizeof *fp, fp);
        if (err == CL_SUCCESS) err = clSetKernelArg(k, 1, sizeof nn, &nn);
        if (err == CL_SUCCESS) err = clSetKernelArg(k, 2, sizeof(cl_mem), &buf[0]);
        if (err == CL_SUCCESS) err = clSetKernelArg(k, 3, sizeof(cl_mem), &buf[1]);
        if (err == CL_SUCCESS) err = clSetKernelArg(k, 4, sizeof has, &has);
        for (cl_uint a = 0; a < 3 && err == CL_SUCCESS; a++)
            err = clSetKernelArg(k, 5 + a, sizeof(cl_mem), &buf[2 + a]);
        if (err == CL_SUCCESS) err = clSetKernelArg(k, 8, sizeof meth, &meth);
        if (err == CL_SUCCESS) err = clSetKernelArg(k, 9, sizeof seg, &seg);
        rc = sl_cl_check(err, "clSetKernelArg", e);
    }
    return srbf_run(cl, k, "sl_srbf_eval_rgb", n, buf[2], n * 9, out, buf, 5, rc, e);
}

int slcl_srbf_rgb_batch(sl_cl *cl, const sl_fiber_params *fp, const sl_srbf_tables *t, int method,
                        int segments, size_t n, const float *in, const float *sigma_a, float *out,
                        sl_err *e) {
    return slcl_srbf_rgb_batch_ex(cl, fp, t, method, segments, n, in, sigma_a, out, 0, e);
}

/* `strandlight kernels --only srbf`: srbf_eval.cl against the C twin on the stiff sample's
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
    for (size_t i = 0; i < n; i++) {
        float *p = in + 5 * i;
        p[0] = (float)cfg[i].theta_o;
        p[1] = (float)cfg[i].phi_o;
        p[2] = (float)cfg[i].theta_j;
        p[3] = (float)cfg[i].phi_j;
        p[4] = (float)cfg[i].lambda;
    }
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
