/* view_cl.c: see view_cl.h. Counting sort of the fragments by pixel on the host (stable), one
 * work-item per pixel on the device. */
#include "passes/view/view_cl.h"

#include "cl/cl_args.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int slcl_kbuffer_build(sl_cl *cl, const slc_frag_list *l, int w, int h, int K, sl_kfrag *kbuf,
                       uint8_t *count, size_t *merges, sl_err *e) {
    return slcl_kbuffer_build_ex(cl, l, w, h, K, 1, kbuf, count, merges, NULL, e);
}

int slcl_kbuffer_build_ex(sl_cl *cl, const slc_frag_list *l, int w, int h, int K, int specialised,
                          sl_kfrag *kbuf, uint8_t *count, size_t *merges, double *kernel_s,
                          sl_err *e) {
    size_t npx = (size_t)w * h;
    if (l->n > 0xffffffffu) return sl_fail(e, "view: %zu fragments is too many", l->n);
    if (K < 1 || K > SL_KBUFFER_MAX)
        return sl_fail(e, "view: K %d is out of [1, %d]", K, SL_KBUFFER_MAX);
    char opts[64];
    snprintf(opts, sizeof opts, "-DSL_KB_K=%d", K);
    cl_kernel k;
    int rc = sl_cl_get_kernel(cl, "view.cl", "sl_kbuffer_fill", specialised ? opts : NULL, &k, e);
    if (rc) return rc;
    uint32_t *start = sl_calloc(npx + 1, sizeof *start);
    for (size_t i = 0; i < l->n; i++)
        start[l->pix[i] + 1]++;
    *merges = 0;
    for (size_t p = 0; p < npx; p++)
        start[p + 1] += start[p];
    sl_kfrag *sorted = sl_malloc((l->n ? l->n : 1) * sizeof *sorted);
    uint32_t *next = sl_malloc((npx + 1) * sizeof *next);
    memcpy(next, start, (npx + 1) * sizeof *next);
    for (size_t i = 0; i < l->n; i++)
        sorted[next[l->pix[i]]++] = l->f[i];
    free(next);
    cl_context ctx = sl_cl_context(cl);
    cl_command_queue q = sl_cl_queue(cl);
    cl_int e1 = 0, e2 = 0, e3 = 0, e4 = 0;
    cl_mem bf = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                               (l->n ? l->n : 1) * sizeof *sorted, sorted, &e1);
    cl_mem bs = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                               (npx + 1) * sizeof *start, start, &e2);
    cl_mem bk = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, npx * K * sizeof *kbuf, NULL, &e3);
    cl_mem bc = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, npx, NULL, &e4);
    rc = -1;
    if (sl_cl_check(e1 ? e1 : (e2 ? e2 : (e3 ? e3 : e4)), "view: clCreateBuffer", e)) goto done;
    cl_uint n = (cl_uint)npx;
    sl_cl_args a = sl_cl_args_begin(k, e);
    SL_CL_ARG(&a, 0, bf);
    SL_CL_ARG(&a, 1, bs);
    SL_CL_ARG(&a, 2, n);
    SL_CL_ARG(&a, 3, bk);
    SL_CL_ARG(&a, 4, bc);
    cl_int kk = K;
    SL_CL_ARG(&a, 5, kk);
    if (sl_cl_args_end(&a)) goto done;
    size_t local = 64, global = (npx + local - 1) / local * local;
    double t0 = sl_now();
    if (sl_cl_check(clEnqueueNDRangeKernel(q, k, 1, NULL, &global, &local, 0, NULL, NULL),
                    "view: sl_kbuffer_fill", e) ||
        sl_cl_check(clFinish(q), "view: sl_kbuffer_fill", e))
        goto done;
    if (kernel_s) *kernel_s = sl_now() - t0;
    if (sl_cl_check(clEnqueueReadBuffer(q, bc, CL_TRUE, 0, npx, count, 0, NULL, NULL),
                    "view: read counts", e) ||
        sl_cl_check(
            clEnqueueReadBuffer(q, bk, CL_TRUE, 0, npx * K * sizeof *kbuf, kbuf, 0, NULL, NULL),
            "view: read K-buffer", e))
        goto done;
    /* the fragments that are no entry of their own (merged on overflow or hidden behind full
     * coverage), as the C fill counts them: all of them less the entries kept */
    size_t kept = 0;
    for (size_t p = 0; p < npx; p++)
        kept += count[p];
    *merges = l->n - kept;
    rc = 0;
done:
    if (bf) clReleaseMemObject(bf);
    if (bs) clReleaseMemObject(bs);
    if (bk) clReleaseMemObject(bk);
    if (bc) clReleaseMemObject(bc);
    free(sorted);
    free(start);
    return rc;
}
