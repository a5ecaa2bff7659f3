/* raster_cl.c: enqueues kernels/raster.cl (see kernels/raster.h; C twin cpu/raster.c): the
 * projection of segments into records, the first-depth pass with its min-filter window, and the
 * layer pass, for a batch of lobes whose maps are stacked in one buffer. */
#include "passes/light/raster_cl.h"

#include "cl/cl_args.h"
#include "../kernels/raster.h"

#include <string.h>

#define RASTER_FILE "raster.cl"
/* sl_raster_record_f divides and takes a square root: correctly rounded as in C, so records (and
 * so maps) are bit-identical to the C twin's (OpenCL 1.2 otherwise allows 2.5-3 ulp). */
#define RASTER_OPTS "-cl-fp32-correctly-rounded-divide-sqrt"
#define LOCAL 64u

int slcl_raster_project_buf(sl_cl *cl, cl_mem pos, cl_mem seg, cl_mem hw, cl_mem views, size_t nseg,
                            unsigned nl, float mscale, cl_mem recs, sl_cl_timer *timer, sl_err *e) {
    cl_kernel k;
    int rc;
    if ((rc = sl_cl_get_kernel(cl, RASTER_FILE, "sl_raster_project_k", RASTER_OPTS, &k, e)))
        return rc;
    if (nseg * nl > 0xffffffffu) return sl_fail(e, "raster: %zu segments is too many", nseg);
    if (nseg == 0) return 0;
    cl_uint n = (cl_uint)nseg, l = nl;
    sl_cl_args a = sl_cl_args_begin(k, e);
    SL_CL_ARG(&a, 0, pos);
    SL_CL_ARG(&a, 1, seg);
    SL_CL_ARG(&a, 2, hw);
    SL_CL_ARG(&a, 3, views);
    SL_CL_ARG(&a, 4, n);
    SL_CL_ARG(&a, 5, l);
    SL_CL_ARG(&a, 6, mscale);
    SL_CL_ARG(&a, 7, recs);
    if (sl_cl_args_end(&a)) return -1;
    return sl_cl_run1d(cl, k, "raster: sl_raster_project_k", nseg * nl, LOCAL, timer, e);
}

/* dst = the min filter of src along x (dx = 1) or y (dx = 0), half-size m, nl planes. */
static int z0_min(sl_cl *cl, cl_mem src, cl_mem dst, int w, int h, unsigned nl, int m, int dx,
                  sl_cl_timer *timer, sl_err *e) {
    cl_kernel k;
    int rc;
    if ((rc = sl_cl_get_kernel(cl, RASTER_FILE, "sl_raster_z0_min", RASTER_OPTS, &k, e))) return rc;
    cl_uint l = nl;
    sl_cl_args a = sl_cl_args_begin(k, e);
    SL_CL_ARG(&a, 0, src);
    SL_CL_ARG(&a, 1, dst);
    SL_CL_ARG(&a, 2, w);
    SL_CL_ARG(&a, 3, h);
    SL_CL_ARG(&a, 4, l);
    SL_CL_ARG(&a, 5, m);
    SL_CL_ARG(&a, 6, dx);
    if (sl_cl_args_end(&a)) return -1;
    return sl_cl_run1d(cl, k, "raster: sl_raster_z0_min", (size_t)w * h * nl, LOCAL, timer, e);
}

/* z0bits = the column pass of the fractional window over the row passes rows_m and rows_m1. */
static int z0_min_blend(sl_cl *cl, cl_mem rows_m, cl_mem rows_m1, cl_mem z0bits, int w, int h,
                        unsigned nl, int m, float frac, sl_cl_timer *timer, sl_err *e) {
    cl_kernel k;
    int rc;
    if ((rc = sl_cl_get_kernel(cl, RASTER_FILE, "sl_raster_z0_min_blend", RASTER_OPTS, &k, e)))
        return rc;
    cl_uint l = nl;
    sl_cl_args a = sl_cl_args_begin(k, e);
    SL_CL_ARG(&a, 0, rows_m);
    SL_CL_ARG(&a, 1, rows_m1);
    SL_CL_ARG(&a, 2, z0bits);
    SL_CL_ARG(&a, 3, w);
    SL_CL_ARG(&a, 4, h);
    SL_CL_ARG(&a, 5, l);
    SL_CL_ARG(&a, 6, m);
    SL_CL_ARG(&a, 7, frac);
    if (sl_cl_args_end(&a)) return -1;
    return sl_cl_run1d(cl, k, "raster: sl_raster_z0_min_blend", (size_t)w * h * nl, LOCAL, timer,
                       e);
}

int slcl_raster_buf(sl_cl *cl, cl_mem recs, size_t nseg, unsigned nl, int w, int h, unsigned K,
                    cl_mem d, int z0_radius, float z0_frac, cl_mem z0bits, cl_mem bins,
                    sl_cl_timer *timer, sl_err *e) {
    cl_kernel kz, kl;
    int rc;
    if ((rc = sl_cl_get_kernel(cl, RASTER_FILE, "sl_raster_z0", RASTER_OPTS, &kz, e))) return rc;
    if ((rc = sl_cl_get_kernel(cl, RASTER_FILE, "sl_raster_layers", RASTER_OPTS, &kl, e)))
        return rc;
    if (nseg * nl > 0xffffffffu) return sl_fail(e, "raster: %zu segments is too many", nseg);
    cl_command_queue q = sl_cl_queue(cl);
    const size_t plane = (size_t)w * h;
    cl_uint empty = SL_RASTER_Z_EMPTY, n = (cl_uint)nseg, kk = K, l = nl;
    cl_ulong zero = 0;
    cl_event ev = NULL;
    if (sl_cl_check(clEnqueueFillBuffer(q, z0bits, &empty, sizeof empty, 0,
                                        nl * plane * sizeof empty, 0, NULL, timer ? &ev : NULL),
                    "raster: fill z0", e))
        return -1;
    if (timer) sl_cl_timer_add(timer, ev);
    if (sl_cl_check(clEnqueueFillBuffer(q, bins, &zero, sizeof zero, 0,
                                        (size_t)nl * K * plane * sizeof zero, 0, NULL,
                                        timer ? &ev : NULL),
                    "raster: fill bins", e))
        return -1;
    if (timer) sl_cl_timer_add(timer, ev);
    if (nseg == 0) return 0;
    sl_cl_args a = sl_cl_args_begin(kz, e);
    SL_CL_ARG(&a, 0, recs);
    SL_CL_ARG(&a, 1, n);
    SL_CL_ARG(&a, 2, l);
    SL_CL_ARG(&a, 3, w);
    SL_CL_ARG(&a, 4, h);
    SL_CL_ARG(&a, 5, z0bits);
    if (sl_cl_args_end(&a)) return -1;
    if (sl_cl_run1d(cl, kz, "raster: sl_raster_z0", nseg * nl, LOCAL, timer, e)) return -1;
    if (z0_radius > 0 || z0_frac > 0.0f) {
        /* rows into a scratch buffer, columns back into z0bits; a fractional window also takes
         * the rows at m + 1 and blends the two column minima (cpu/raster.c, the C twin) */
        const int m = z0_radius > 0 ? z0_radius : 0, blend = z0_frac > 0.0f;
        const size_t bytes = nl * plane * sizeof(cl_uint);
        cl_int err, err2 = CL_SUCCESS;
        cl_mem tmp = clCreateBuffer(sl_cl_context(cl), CL_MEM_READ_WRITE, bytes, NULL, &err);
        cl_mem tmp2 =
            blend ? clCreateBuffer(sl_cl_context(cl), CL_MEM_READ_WRITE, bytes, NULL, &err2) : NULL;
        rc = sl_cl_check(err, "raster: clCreateBuffer(z0 scratch)", e) ||
                     sl_cl_check(err2, "raster: clCreateBuffer(z0 scratch)", e)
                 ? -1
                 : 0;
        if (!rc) rc = z0_min(cl, z0bits, tmp, w, h, nl, m, 1, timer, e);
        if (!rc && blend) rc = z0_min(cl, z0bits, tmp2, w, h, nl, m + 1, 1, timer, e);
        if (!rc)
            rc = blend ? z0_min_blend(cl, tmp, tmp2, z0bits, w, h, nl, m, z0_frac, timer, e)
                       : z0_min(cl, tmp, z0bits, w, h, nl, m, 0, timer, e);
        if (tmp) clReleaseMemObject(tmp); /* freed once the queued kernels have finished */
        if (tmp2) clReleaseMemObject(tmp2);
        if (rc) return rc;
    }
    a = sl_cl_args_begin(kl, e);
    SL_CL_ARG(&a, 0, recs);
    SL_CL_ARG(&a, 1, n);
    SL_CL_ARG(&a, 2, l);
    SL_CL_ARG(&a, 3, w);
    SL_CL_ARG(&a, 4, h);
    SL_CL_ARG(&a, 5, kk);
    SL_CL_ARG(&a, 6, d);
    SL_CL_ARG(&a, 7, z0bits);
    SL_CL_ARG(&a, 8, bins);
    if (sl_cl_args_end(&a)) return -1;
    return sl_cl_run1d(cl, kl, "raster: sl_raster_layers", nseg * nl, LOCAL, timer, e);
}

int slcl_raster(sl_cl *cl, const float *recs, size_t nseg, int w, int h, unsigned K, float d,
                int z0_radius, float z0_frac, uint32_t *z0bits, uint64_t *bins, double *kernel_s,
                sl_err *e) {
    cl_context ctx = sl_cl_context(cl);
    const size_t plane = (size_t)w * h;
    cl_int err;
    cl_mem br = NULL, bz = NULL, bb = NULL, bd = NULL;
    int rc = -1;
    br = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                        (nseg ? nseg : 1) * SL_RASTER_REC * sizeof(float),
                        nseg ? (void *)recs : (void *)&plane, &err);
    if (sl_cl_check(err, "raster: clCreateBuffer(records)", e)) goto done;
    bd = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof d, &d, &err);
    if (sl_cl_check(err, "raster: clCreateBuffer(d)", e)) goto done;
    bz = clCreateBuffer(ctx, CL_MEM_READ_WRITE, plane * sizeof(cl_uint), NULL, &err);
    if (sl_cl_check(err, "raster: clCreateBuffer(z0)", e)) goto done;
    bb = clCreateBuffer(ctx, CL_MEM_READ_WRITE, K * plane * sizeof(cl_ulong), NULL, &err);
    if (sl_cl_check(err, "raster: clCreateBuffer(layers)", e)) goto done;
    sl_cl_timer t;
    sl_cl_timer_start(&t, cl);
    rc = slcl_raster_buf(cl, br, nseg, 1, w, h, K, bd, z0_radius, z0_frac, bz, bb, &t, e);
    double s = sl_cl_timer_stop(&t, NULL);
    if (kernel_s) *kernel_s = s;
    if (rc) goto done;
    cl_command_queue q = sl_cl_queue(cl);
    if (sl_cl_check(
            clEnqueueReadBuffer(q, bz, CL_TRUE, 0, plane * sizeof(cl_uint), z0bits, 0, NULL, NULL),
            "raster: read z0", e) ||
        sl_cl_check(clEnqueueReadBuffer(q, bb, CL_TRUE, 0, K * plane * sizeof(cl_ulong), bins, 0,
                                        NULL, NULL),
                    "raster: read layers", e))
        rc = -1;
done:
    if (br) clReleaseMemObject(br);
    if (bd) clReleaseMemObject(bd);
    if (bz) clReleaseMemObject(bz);
    if (bb) clReleaseMemObject(bb);
    return rc;
}
