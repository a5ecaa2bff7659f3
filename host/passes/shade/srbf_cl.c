/* srbf_cl.c: OpenCL driver of the SRBF response (see srbf_cl.h). */
#include "passes/shade/srbf_cl.h"

#include "cl/cl_args.h"
#include "srbf_c.h"
#include "srbf_xu.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* The -D options of srbf.cl for this material and method (its header comment): the method
 * and m as constants, no Xu code for fast, no eccentric TRT for a round fiber. */
void slcl_srbf_options(const sl_fiber_params *fp, int method, int segments, char *buf,
                       size_t size) {
    if (method == SL_SRBF_METHOD_FAST)
        snprintf(buf, size, "-DSL_SRBF_SPEC_METHOD=1 -DSL_SRBF_FAST_ONLY%s",
                 fp->eccentricity == 1.0f ? " -DSL_SRBF_ROUND_ONLY" : "");
    else
        snprintf(buf, size, "-DSL_SRBF_SPEC_METHOD=0 -DSL_SRBF_SPEC_SEGMENTS=%d", segments);
}

/* The job's buffers ('b' in args), in order; stops at the first failure (the rest stay NULL). */
static int srbf_buffers(sl_cl *cl, const slcl_srbf_job *j, cl_mem *buf, int *nbuf, sl_err *e) {
    cl_context ctx = sl_cl_context(cl);
    cl_int err = CL_SUCCESS;
    *nbuf = 0;
    for (const char *c = j->args; *c && err == CL_SUCCESS; c++) {
        if (*c != 'b') continue;
        if (*nbuf == SLCL_SRBF_MAX_BUF) return sl_fail(e, "%s: too many buffers", j->kernel);
        int a = (*nbuf)++;
        buf[a] = clCreateBuffer(
            ctx, j->src[a] ? CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR : CL_MEM_WRITE_ONLY,
            j->size[a] * sizeof(float), (void *)j->src[a], &err);
    }
    return sl_cl_check(err, "clCreateBuffer", e);
}

/* Arguments 0 and 1 (fp, the row count), then those args spells. */
static int srbf_args(cl_kernel k, const sl_fiber_params *fp, const slcl_srbf_job *j,
                     const cl_mem *buf, sl_err *e) {
    cl_uint nn = (cl_uint)j->n, a = 2;
    sl_cl_args args = sl_cl_args_begin(k, e);
    SL_CL_ARG(&args, 0, *fp);
    SL_CL_ARG(&args, 1, nn);
    for (int c = 0, nb = 0, ni = 0; j->args[c]; c++, a++) {
        if (j->args[c] == 'b')
            SL_CL_ARG(&args, a, buf[nb]), nb++;
        else
            SL_CL_ARG(&args, a, j->ints[ni]), ni++;
    }
    return sl_cl_args_end(&args);
}

int slcl_srbf_launch(sl_cl *cl, const sl_fiber_params *fp, const slcl_srbf_job *j, float *out,
                     sl_err *e) {
    if (j->n == 0) return 0;
    if (j->n > 0xffffffffu) return sl_fail(e, "%s: too many rows (%zu)", j->kernel, j->n);
    cl_kernel k;
    int rc = sl_cl_get_kernel(cl, j->file, j->kernel, j->options, &k, e);
    if (rc) return rc;
    cl_mem buf[SLCL_SRBF_MAX_BUF] = {NULL};
    int nbuf;
    cl_command_queue q = sl_cl_queue(cl);
    rc = srbf_buffers(cl, j, buf, &nbuf, e);
    if (!rc) rc = srbf_args(k, fp, j, buf, e);
    if (!rc) {
        size_t local = 64, global;
        size_t maxwg = sl_cl_max_work_group_size(cl);
        if (maxwg && local > maxwg) local = maxwg;
        global = (j->n + local - 1) / local * local;
        rc = sl_cl_check(clEnqueueNDRangeKernel(q, k, 1, NULL, &global, &local, 0, NULL, NULL),
                         j->kernel, e);
    }
    if (!rc)
        rc = sl_cl_check(clEnqueueReadBuffer(q, buf[j->res], CL_TRUE, 0,
                                             j->size[j->res] * sizeof(float), out, 0, NULL, NULL),
                         "clEnqueueReadBuffer", e);
    for (int a = 0; a < nbuf; a++)
        if (buf[a]) clReleaseMemObject(buf[a]);
    return rc;
}

int slcl_srbf_batch(sl_cl *cl, const sl_fiber_params *fp, const sl_srbf_tables *t, int method,
                    int segments, size_t n, const float *in, float *out, sl_err *e) {
    char opts[160];
    slcl_srbf_options(fp, method, segments, opts, sizeof opts);
    /* sl_srbf_eval(fp, n, in, out, C, H, method, segments) */
    const size_t size[] = {n * 5, n * 4, SL_SRBF_C_FLOATS, SL_SRBF_H_FLOATS};
    const float *src[] = {in, NULL, t->C, t->H};
    const cl_int ints[] = {method, segments};
    const slcl_srbf_job j = {"srbf.cl", "sl_srbf_eval", opts, n, "bbbbii", ints, 1, size, src};
    return slcl_srbf_launch(cl, fp, &j, out, e);
}

int slcl_srbf_rgb_batch_ex(sl_cl *cl, const sl_fiber_params *fp, const sl_srbf_tables *t,
                           int method, int segments, size_t n, const float *in,
                           const float *sigma_a, float *out, int generic, sl_err *e) {
    char opts[160] = "";
    if (!generic) slcl_srbf_options(fp, method, segments, opts, sizeof opts);
    /* sl_srbf_eval_rgb(fp, n, in, sigma, has_sigma, out, C, H, method, segments); sigma is a
     * 3-float dummy when NULL (a kernel argument may not be a NULL buffer on every platform) */
    float dummy[3] = {0, 0, 0};
    const size_t size[] = {n * 5, sigma_a ? n * 3 : 3, n * 9, SL_SRBF_C_FLOATS, SL_SRBF_H_FLOATS};
    const float *src[] = {in, sigma_a ? sigma_a : dummy, NULL, t->C, t->H};
    const cl_int ints[] = {sigma_a != NULL, method, segments};
    const slcl_srbf_job j = {"srbf.cl", "sl_srbf_eval_rgb", opts, n, "bbibbbii", ints, 2, size,
                             src};
    return slcl_srbf_launch(cl, fp, &j, out, e);
}

int slcl_srbf_rgb_batch(sl_cl *cl, const sl_fiber_params *fp, const sl_srbf_tables *t, int method,
                        int segments, size_t n, const float *in, const float *sigma_a, float *out,
                        sl_err *e) {
    return slcl_srbf_rgb_batch_ex(cl, fp, t, method, segments, n, in, sigma_a, out, 0, e);
}
