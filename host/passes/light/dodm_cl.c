/* dodm_cl.c: enqueues kernels/dodm.cl (see kernels/dodm.h; C twin cpu/dodm.c). */
#include "passes/light/dodm_cl.h"

#include "cl/cl_args.h"

#include <string.h>

#define DODM_FILE "dodm.cl"
#define LOCAL 64u

int slcl_dodm_tables_buf(sl_cl *cl, cl_mem bins, int w, int h, unsigned K, unsigned nl,
                         sl_cl_timer *timer, sl_err *e) {
    cl_kernel kc, kr, kcol;
    int rc;
    if ((rc = sl_cl_get_kernel(cl, DODM_FILE, "sl_dodm_cumulate", NULL, &kc, e))) return rc;
    if ((rc = sl_cl_get_kernel(cl, DODM_FILE, "sl_dodm_scan_rows", NULL, &kr, e))) return rc;
    if ((rc = sl_cl_get_kernel(cl, DODM_FILE, "sl_dodm_scan_cols", NULL, &kcol, e))) return rc;
    /* the scans see the nl * K planes as one stack: rows = nl K h, columns = nl K w */
    cl_uint plane = (cl_uint)((size_t)w * h), kk = K, cw = (cl_uint)w, ch = (cl_uint)h,
            rows = (cl_uint)((size_t)nl * K * h), nk = K * nl, l = nl;
    sl_cl_args a = sl_cl_args_begin(kc, e);
    SL_CL_ARG(&a, 0, bins);
    SL_CL_ARG(&a, 1, plane);
    SL_CL_ARG(&a, 2, kk);
    SL_CL_ARG(&a, 3, l);
    a.kernel = kr;
    SL_CL_ARG(&a, 0, bins);
    SL_CL_ARG(&a, 1, cw);
    SL_CL_ARG(&a, 2, rows);
    a.kernel = kcol;
    SL_CL_ARG(&a, 0, bins);
    SL_CL_ARG(&a, 1, cw);
    SL_CL_ARG(&a, 2, ch);
    SL_CL_ARG(&a, 3, nk);
    if (sl_cl_args_end(&a)) return -1;
    if (sl_cl_run1d(cl, kc, "dodm: sl_dodm_cumulate", (size_t)plane * nl, LOCAL, timer, e))
        return -1;
    if (sl_cl_run1d(cl, kr, "dodm: sl_dodm_scan_rows", rows, LOCAL, timer, e)) return -1;
    return sl_cl_run1d(cl, kcol, "dodm: sl_dodm_scan_cols", (size_t)w * nk, LOCAL, timer, e);
}

int slcl_dodm_tables(sl_cl *cl, uint64_t *bins, int w, int h, unsigned K, double *kernel_s,
                     sl_err *e) {
    size_t bytes = (size_t)K * w * h * sizeof *bins;
    cl_int err;
    cl_mem b = clCreateBuffer(sl_cl_context(cl), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, bytes,
                              bins, &err);
    if (sl_cl_check(err, "dodm: clCreateBuffer", e)) return -1;
    sl_cl_timer t;
    sl_cl_timer_start(&t, cl);
    int rc = slcl_dodm_tables_buf(cl, b, w, h, K, 1, &t, e);
    double s = sl_cl_timer_stop(&t, NULL);
    if (kernel_s) *kernel_s = s;
    if (!rc &&
        sl_cl_check(clEnqueueReadBuffer(sl_cl_queue(cl), b, CL_TRUE, 0, bytes, bins, 0, NULL, NULL),
                    "dodm: read tables", e))
        rc = -1;
    clReleaseMemObject(b);
    return rc;
}

/* The point kernels of dodm.cl over host arrays: sl_dodm_lookup (T; B NULL) or
 * sl_dodm_lookup_both (T and B). */
static int lookup_points(sl_cl *cl, const uint32_t *z0bits, const uint64_t *sat, int w, int h,
                         unsigned K, float d, float rfac, float inv_scale, const float *pts,
                         size_t n, float *T, float *B, sl_err *e) {
    if (n == 0) return 0;
    if (n > 0xffffffffu) return sl_fail(e, "dodm: %zu points is too many", n);
    const char *kname = B ? "sl_dodm_lookup_both" : "sl_dodm_lookup";
    cl_kernel k;
    int rc = sl_cl_get_kernel(cl, DODM_FILE, kname, NULL, &k, e);
    if (rc) return rc;
    cl_context ctx = sl_cl_context(cl);
    size_t plane = (size_t)w * h;
    cl_int err;
    cl_mem bz = NULL, bs = NULL, bp = NULL, bt = NULL, bb = NULL;
    rc = -1;
    bz = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, plane * sizeof *z0bits,
                        (void *)z0bits, &err);
    if (sl_cl_check(err, "dodm: clCreateBuffer(z0)", e)) goto done;
    bs = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, K * plane * sizeof *sat,
                        (void *)sat, &err);
    if (sl_cl_check(err, "dodm: clCreateBuffer(tables)", e)) goto done;
    bp = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, 3 * n * sizeof *pts,
                        (void *)pts, &err);
    if (sl_cl_check(err, "dodm: clCreateBuffer(points)", e)) goto done;
    bt = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, n * sizeof *T, NULL, &err);
    if (sl_cl_check(err, "dodm: clCreateBuffer(T)", e)) goto done;
    if (B) {
        bb = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, n * sizeof *B, NULL, &err);
        if (sl_cl_check(err, "dodm: clCreateBuffer(B)", e)) goto done;
    }
    cl_uint kk = K, nn = (cl_uint)n;
    sl_cl_args a = sl_cl_args_begin(k, e);
    SL_CL_ARG(&a, 0, bz);
    SL_CL_ARG(&a, 1, bs);
    SL_CL_ARG(&a, 2, w);
    SL_CL_ARG(&a, 3, h);
    SL_CL_ARG(&a, 4, kk);
    SL_CL_ARG(&a, 5, d);
    SL_CL_ARG(&a, 6, rfac);
    SL_CL_ARG(&a, 7, inv_scale);
    SL_CL_ARG(&a, 8, bp);
    SL_CL_ARG(&a, 9, nn);
    SL_CL_ARG(&a, 10, bt);
    if (B) SL_CL_ARG(&a, 11, bb);
    if (sl_cl_args_end(&a)) goto done;
    if (sl_cl_run1d(cl, k, kname, n, LOCAL, NULL, e)) goto done;
    if (sl_cl_check(
            clEnqueueReadBuffer(sl_cl_queue(cl), bt, CL_TRUE, 0, n * sizeof *T, T, 0, NULL, NULL),
            "dodm: read T", e))
        goto done;
    if (B && sl_cl_check(clEnqueueReadBuffer(sl_cl_queue(cl), bb, CL_TRUE, 0, n * sizeof *B, B, 0,
                                             NULL, NULL),
                         "dodm: read B", e))
        goto done;
    rc = 0;
done:
    if (bz) clReleaseMemObject(bz);
    if (bs) clReleaseMemObject(bs);
    if (bp) clReleaseMemObject(bp);
    if (bt) clReleaseMemObject(bt);
    if (bb) clReleaseMemObject(bb);
    return rc;
}

int slcl_dodm_lookup(sl_cl *cl, const uint32_t *z0bits, const uint64_t *sat, int w, int h,
                     unsigned K, float d, float rfac, float inv_scale, const float *pts, size_t n,
                     float *T, sl_err *e) {
    return lookup_points(cl, z0bits, sat, w, h, K, d, rfac, inv_scale, pts, n, T, NULL, e);
}

int slcl_dodm_lookup_both(sl_cl *cl, const uint32_t *z0bits, const uint64_t *sat, int w, int h,
                          unsigned K, float d, float rfac, float inv_scale, const float *pts,
                          size_t n, float *T, float *B, sl_err *e) {
    return lookup_points(cl, z0bits, sat, w, h, K, d, rfac, inv_scale, pts, n, T, B, e);
}

int slcl_dodm_lookup_lobes_buf(sl_cl *cl, cl_mem z0bits, cl_mem sat, int w, int h, unsigned K,
                               cl_mem params, cl_mem views, cl_mem pts, cl_mem lobe, size_t n,
                               unsigned nl, unsigned lobe0, size_t stride, cl_mem T,
                               sl_cl_timer *timer, sl_err *e) {
    if (n == 0) return 0;
    size_t work = lobe ? n : n * nl;
    if (work > 0xffffffffu || stride > 0xffffffffu)
        return sl_fail(e, "dodm: %zu points is too many", n);
    cl_kernel k;
    int rc = sl_cl_get_kernel(cl, DODM_FILE, "sl_dodm_lookup_lobes", NULL, &k, e);
    if (rc) return rc;
    cl_uint kk = K, nn = (cl_uint)n, l = nl, l0 = lobe0, st = (cl_uint)stride;
    cl_int all = lobe == NULL;
    cl_mem lb = lobe ? lobe : pts; /* unread when all != 0 */
    sl_cl_args a = sl_cl_args_begin(k, e);
    SL_CL_ARG(&a, 0, z0bits);
    SL_CL_ARG(&a, 1, sat);
    SL_CL_ARG(&a, 2, w);
    SL_CL_ARG(&a, 3, h);
    SL_CL_ARG(&a, 4, kk);
    SL_CL_ARG(&a, 5, params);
    SL_CL_ARG(&a, 6, views);
    SL_CL_ARG(&a, 7, pts);
    SL_CL_ARG(&a, 8, lb);
    SL_CL_ARG(&a, 9, all);
    SL_CL_ARG(&a, 10, nn);
    SL_CL_ARG(&a, 11, l);
    SL_CL_ARG(&a, 12, l0);
    SL_CL_ARG(&a, 13, st);
    SL_CL_ARG(&a, 14, T);
    if (sl_cl_args_end(&a)) return -1;
    return sl_cl_run1d(cl, k, "dodm: sl_dodm_lookup_lobes", work, LOCAL, timer, e);
}
