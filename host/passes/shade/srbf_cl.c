/* srbf_cl.c: OpenCL driver of the SRBF response (see srbf_cl.h). */
#include "passes/shade/srbf_cl.h"

#include "srbf_c.h"
#include "verify/report/srbf_sample.h"
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
    cl_int err = clSetKernelArg(k, 0, sizeof *fp, fp);
    if (err == CL_SUCCESS) err = clSetKernelArg(k, 1, sizeof nn, &nn);
    for (int c = 0, nb = 0, ni = 0; j->args[c] && err == CL_SUCCESS; c++, a++)
        err = j->args[c] == 'b' ? clSetKernelArg(k, a, sizeof(cl_mem), &buf[nb++])
                                : clSetKernelArg(k, a, sizeof(cl_int), &j->ints[ni++]);
    return sl_cl_check(err, "clSetKernelArg", e);
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
    const slcl_srbf_job j = {"srbf_eval.cl", "sl_srbf_eval", opts, n, "bbbbii", ints, 1, size, src};
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
    const slcl_srbf_job j = {
        "srbf_eval.cl", "sl_srbf_eval_rgb", opts, n, "bbibbbii", ints, 2, size, src};
    return slcl_srbf_launch(cl, fp, &j, out, e);
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
