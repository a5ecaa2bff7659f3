/* fiber_cl.c: OpenCL batch drivers (see fiber_cl.h). One generic runner: upload in, set the
 * kernel's arguments, run one work-item per row, read out back, then release the buffers or keep
 * them for the caller's next batch. */
#include "passes/shade/fiber_cl.h"

#include "cl/cl_args.h"

#include <string.h>

#include "fiber_c.h"

#define SLCL_FILE "fiber.cl"

/* A buffer of at least `bytes`: the kept one when it is large enough, else a new one (kept in *m
 * when keep, the old one released). */
static int row_buffer(cl_context ctx, cl_mem_flags flags, size_t bytes, cl_mem *m, size_t *have,
                      const char *what, sl_err *e) {
    if (*m && *have >= bytes) return 0;
    if (*m) clReleaseMemObject(*m);
    *m = NULL;
    *have = 0;
    cl_int err;
    cl_mem b = clCreateBuffer(ctx, flags, bytes, NULL, &err);
    if (sl_cl_check(err, what, e)) return -1;
    *m = b;
    *have = bytes;
    return 0;
}

void slcl_rows_bufs_release(slcl_rows_bufs *b) {
    if (b->in) clReleaseMemObject(b->in);
    if (b->out) clReleaseMemObject(b->out);
    memset(b, 0, sizeof *b);
}

/* Runs `name` over n rows of in_w floats giving out_w floats each. fp (may be NULL) is passed
 * by value as argument 0; then n, in, out and, when width_arg, out_w and in_w. keep (may be
 * NULL): the caller's buffers to reuse. */
static int run_rows(sl_cl *cl, const char *name, const sl_fiber_params *fp, size_t n,
                    const float *in, size_t in_w, float *out, size_t out_w, int width_arg,
                    slcl_rows_bufs *keep, sl_err *e) {
    if (n == 0) return 0;
    if (n > 0xffffffffu) return sl_fail(e, "%s: too many rows (%zu)", name, n);
    cl_kernel k;
    int rc = sl_cl_get_kernel(cl, SLCL_FILE, name, "", &k, e);
    if (rc) return rc;
    cl_context ctx = sl_cl_context(cl);
    cl_command_queue q = sl_cl_queue(cl);
    slcl_rows_bufs local_bufs = {0}, *bufs = keep ? keep : &local_bufs;
    size_t in_bytes = n * in_w * sizeof(float), out_bytes = n * out_w * sizeof(float);
    if (row_buffer(ctx, CL_MEM_READ_ONLY, in_bytes, &bufs->in, &bufs->in_bytes,
                   "clCreateBuffer(in)", e) ||
        row_buffer(ctx, CL_MEM_WRITE_ONLY, out_bytes, &bufs->out, &bufs->out_bytes,
                   "clCreateBuffer(out)", e)) {
        if (!keep) slcl_rows_bufs_release(&local_bufs);
        return -1;
    }
    cl_mem bin = bufs->in, bout = bufs->out;
    /* blocking: the caller frees `in` as soon as this returns, also on an error below (a
     * non-blocking write was still reading it then: a use-after-free under SL_CL_FAULT=lost) */
    rc = sl_cl_check(clEnqueueWriteBuffer(q, bin, CL_TRUE, 0, in_bytes, in, 0, NULL, NULL),
                     "clEnqueueWriteBuffer(in)", e);
    cl_uint nn = (cl_uint)n, ww = (cl_uint)out_w, iw = (cl_uint)in_w, a = 0;
    if (!rc) {
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
    }
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
        rc = sl_cl_check(clEnqueueReadBuffer(q, bout, CL_TRUE, 0, out_bytes, out, 0, NULL, NULL),
                         "clEnqueueReadBuffer", e);
    if (!keep) slcl_rows_bufs_release(&local_bufs);
    return rc;
}

int slcl_scatter_batch(sl_cl *cl, const sl_fiber_params *fp, size_t n, const float *in, float *out,
                       sl_err *e) {
    return slcl_scatter_rows(cl, fp, n, in, 4, out, NULL, e);
}

int slcl_deon_mp_batch(sl_cl *cl, size_t n, const float *in, float *out, sl_err *e) {
    return slcl_deon_mp_rows(cl, n, in, out, NULL, e);
}

int slcl_furnace_batch(sl_cl *cl, const sl_fiber_params *fp, size_t n, const float *in, float *out,
                       sl_err *e) {
    return slcl_furnace_rows(cl, fp, n, in, out, NULL, e);
}

int slcl_scatter_rows(sl_cl *cl, const sl_fiber_params *fp, size_t n, const float *in, size_t in_w,
                      float *out, slcl_rows_bufs *b, sl_err *e) {
    return run_rows(cl, "sl_scatter_eval", fp, n, in, in_w, out, slc_scatter_width(fp), 1, b, e);
}

int slcl_deon_mp_rows(sl_cl *cl, size_t n, const float *in, float *out, slcl_rows_bufs *b,
                      sl_err *e) {
    return run_rows(cl, "sl_deon_mp_eval", NULL, n, in, 3, out, 2, 0, b, e);
}

int slcl_furnace_rows(sl_cl *cl, const sl_fiber_params *fp, size_t n, const float *in, float *out,
                      slcl_rows_bufs *b, sl_err *e) {
    return run_rows(cl, "sl_furnace_eval", fp, n, in, 2, out, 1, 0, b, e);
}
