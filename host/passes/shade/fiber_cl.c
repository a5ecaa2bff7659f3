/* fiber_cl.c: OpenCL batch drivers (see fiber_cl.h). One generic runner: upload in, set the
 * kernel's arguments, run one work-item per row, read out back, release everything. */
#include "passes/shade/fiber_cl.h"

#include "cl/cl_args.h"

#include <string.h>

#include "fiber_c.h"

#define SLCL_FILE "fiber.cl"

/* Runs `name` over n rows of in_w floats giving out_w floats each. fp (may be NULL) is passed
 * by value as argument 0; then n, in, out and, when width_arg, out_w and in_w. */
static int run_rows(sl_cl *cl, const char *name, const sl_fiber_params *fp, size_t n,
                    const float *in, size_t in_w, float *out, size_t out_w, int width_arg,
                    sl_err *e) {
    if (n == 0) return 0;
    if (n > 0xffffffffu) return sl_fail(e, "%s: too many rows (%zu)", name, n);
    cl_kernel k;
    int rc = sl_cl_get_kernel(cl, SLCL_FILE, name, "", &k, e);
    if (rc) return rc;
    cl_context ctx = sl_cl_context(cl);
    cl_command_queue q = sl_cl_queue(cl);
    cl_int err;
    cl_mem bin = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                n * in_w * sizeof(float), (void *)in, &err);
    if (sl_cl_check(err, "clCreateBuffer(in)", e)) return -1;
    cl_mem bout = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, n * out_w * sizeof(float), NULL, &err);
    if (sl_cl_check(err, "clCreateBuffer(out)", e)) {
        clReleaseMemObject(bin);
        return -1;
    }
    cl_uint nn = (cl_uint)n, ww = (cl_uint)out_w, iw = (cl_uint)in_w, a = 0;
    sl_cl_args args = sl_cl_args_begin(k, e);
    if (fp) SL_CL_ARG(&args, a++, *fp);
    SL_CL_ARG(&args, a++, nn);
    SL_CL_ARG(&args, a++, bin);
    SL_CL_ARG(&args, a++, bout);
    if (width_arg) {
        SL_CL_ARG(&args, a++, ww);
        SL_CL_ARG(&args, a++, iw);
    }
    rc = sl_cl_args_end(&args);
    if (!rc) {
        size_t local = 64, global = (n + local - 1) / local * local;
        size_t maxwg = sl_cl_max_work_group_size(cl);
        if (maxwg && local > maxwg) {
            local = maxwg;
            global = (n + local - 1) / local * local;
        }
        rc = sl_cl_check(clEnqueueNDRangeKernel(q, k, 1, NULL, &global, &local, 0, NULL, NULL),
                         name, e);
    }
    if (!rc)
        rc = sl_cl_check(
            clEnqueueReadBuffer(q, bout, CL_TRUE, 0, n * out_w * sizeof(float), out, 0, NULL, NULL),
            "clEnqueueReadBuffer", e);
    clReleaseMemObject(bin);
    clReleaseMemObject(bout);
    return rc;
}

int slcl_scatter_batch(sl_cl *cl, const sl_fiber_params *fp, size_t n, const float *in, float *out,
                       sl_err *e) {
    return slcl_scatter_rows(cl, fp, n, in, 4, out, e);
}

int slcl_scatter_rows(sl_cl *cl, const sl_fiber_params *fp, size_t n, const float *in, size_t in_w,
                      float *out, sl_err *e) {
    return run_rows(cl, "sl_scatter_eval", fp, n, in, in_w, out, slc_scatter_width(fp), 1, e);
}

int slcl_deon_mp_batch(sl_cl *cl, size_t n, const float *in, float *out, sl_err *e) {
    return run_rows(cl, "sl_deon_mp_eval", NULL, n, in, 3, out, 2, 0, e);
}

int slcl_furnace_batch(sl_cl *cl, const sl_fiber_params *fp, size_t n, const float *in, float *out,
                       sl_err *e) {
    return run_rows(cl, "sl_furnace_eval", fp, n, in, 2, out, 1, 0, e);
}
