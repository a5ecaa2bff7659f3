/* raster_cl.c: enqueues kernels/raster.cl (see kernels/raster.h; C twin cpu/raster.c): the
 * projection of segments into records, the first-depth pass with its min-filter window, and the
 * layer pass, for a batch of lobes whose maps are stacked in one buffer. */
#include "passes/light/raster_cl.h"

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
    cl_int err = 0;
    err |= clSetKernelArg(k, 0, sizeof pos, &pos);
    err |= clSetKernelArg(k, 1, sizeof seg, &seg);
    err |= clSetKernelArg(k, 2, sizeof hw, &hw);
    err |= clSetKernelArg(k, 3, sizeof views, &views);
    err |= clSetKernelArg(k, 4, sizeof n, &n);
    err |= clSetKernelArg(k, 5, sizeof l, &l);
    err |= clSetKernelArg(k, 6, sizeof mscale, &mscale);
    err |= clSetKernelArg(k, 7, sizeof recs, &recs);
    if (sl_cl_check(err, "raster: sl_raster_project_k arguments", e)) return -1;
    return sl_cl_run1d(cl, k, "raster: sl_raster_project_k", nseg * nl, LOCAL, timer, e);
}

/* dst = the min filter of src along x (dx = 1) or y (dx = 0), half-size m, nl planes. */
static int z0_min(sl_cl *cl, cl_mem src, cl_mem dst, int w, int h, unsigned nl, int m, int dx,
                  sl_cl_timer *timer, sl_err *e) {
    cl_kernel k;
    int rc;
    if ((rc = sl_cl_get_kernel(cl, RASTER_FILE, "sl_raster_z0_min", RASTER_OPTS, &k, e))) return rc;
    cl_uint l = nl;
    cl_int err = 0;
    err |= clSetKernelArg(k, 0, sizeof src, &src);
    err |= clSetKernelArg(k, 1, sizeof dst, &dst);
    err |= clSetKernelArg(k, 2, sizeof w, &w);
    err |= clSetKernelArg(k, 3, sizeof h, &h);
    err |= clSetKernelArg(k, 4, sizeof l, &l);
    err |= clSetKernelArg(k, 5, sizeof m, &m);
    err |= clSetKernelArg(k, 6, sizeof dx, &dx);
    if (sl_cl_check(err, "raster: sl_raster_z0_min arguments", e)) return -1;
    return sl_cl_run1d(cl, k, "raster: sl_raster_z0_min", (size_t)w * h * nl, LOCAL, timer, e);
}

int slcl_raster_buf(sl_cl *cl, cl_mem recs, size_t nseg, unsigned nl, int w, int h, unsigned K,
                    cl_mem d, int z0_radius, cl_mem z0bits, cl_mem bins, sl_cl_timer *timer,
                    sl_err *e) {
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
    cl_int err = 0;
    err |= clSetKernelArg(kz, 0, sizeof recs, &recs);
    err |= clSetKernelArg(kz, 1, sizeof n, &n);
    err |= clSetKernelArg(kz, 2, sizeof l, &l);
    err |= clSetKernelArg(kz, 3, sizeof w, &w);
    err |= clSetKernelArg(kz, 4, sizeof h, &h);
    err |= clSetKernelArg(kz, 5, sizeof z0bits, &z0bits);
    if (sl_cl_check(err, "raster: sl_raster_z0 arguments", e)) return -1;
    if (sl_cl_run1d(cl, kz, "raster: sl_raster_z0", nseg * nl, LOCAL, timer, e)) return -1;
    if (z0_radius > 0) { /* rows into a scratch buffer, columns back into z0bits */
        cl_mem tmp = clCreateBuffer(sl_cl_context(cl), CL_MEM_READ_WRITE,
                                    nl * plane * sizeof(cl_uint), NULL, &err);
        if (sl_cl_check(err, "raster: clCreateBuffer(z0 scratch)", e)) return -1;
        rc = z0_min(cl, z0bits, tmp, w, h, nl, z0_radius, 1, timer, e);
        if (!rc) rc = z0_min(cl, tmp, z0bits, w, h, nl, z0_radius, 0, timer, e);
        clReleaseMemObject(tmp); /* freed once the queued kernels using it have finished */
        if (rc) return rc;
    }
    err = 0;
    err |= clSetKernelArg(kl, 0, sizeof recs, &recs);
    err |= clSetKernelArg(kl, 1, sizeof n, &n);
    err |= clSetKernelArg(kl, 2, sizeof l, &l);
    err |= clSetKernelArg(kl, 3, sizeof w, &w);
    err |= clSetKernelArg(kl, 4, sizeof h, &h);
    err |= clSetKernelArg(kl, 5, sizeof kk, &kk);
    err |= clSetKernelArg(kl, 6, sizeof d, &d);
    err |= clSetKernelArg(kl, 7, sizeof z0bits, &z0bits);
    err |= clSetKernelArg(kl, 8, sizeof bins, &bins);
    if (sl_cl_check(err, "raster: sl_raster_layers arguments", e)) return -1;
    return sl_cl_run1d(cl, kl, "raster: sl_raster_layers", nseg * nl, LOCAL, timer, e);
}

int slcl_raster(sl_cl *cl, const float *recs, size_t nseg, int w, int h, unsigned K, float d,
                int z0_radius, uint32_t *z0bits, uint64_t *bins, double *kernel_s, sl_err *e) {
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
    rc = slcl_raster_buf(cl, br, nseg, 1, w, h, K, bd, z0_radius, bz, bb, &t, e);
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
