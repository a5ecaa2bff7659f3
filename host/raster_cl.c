/* raster_cl.c: enqueues kernels/raster.cl (see kernels/raster.h; C twin cpu/raster.c). */
#include "raster_cl.h"

#include "../kernels/raster.h"

#include <string.h>

#define RASTER_FILE "raster.cl"
#define LOCAL 64u

static size_t round_up(size_t x, size_t m) {
    return (x + m - 1) / m * m;
}

int slcl_raster_buf(sl_cl *cl, cl_mem recs, size_t nseg, int w, int h, unsigned K, float d,
                    cl_mem z0bits, cl_mem bins, sl_cl_timer *timer, sl_err *e) {
    cl_kernel kz, kl;
    int rc;
    if ((rc = sl_cl_get_kernel(cl, RASTER_FILE, "sl_raster_z0", NULL, &kz, e))) return rc;
    if ((rc = sl_cl_get_kernel(cl, RASTER_FILE, "sl_raster_layers", NULL, &kl, e))) return rc;
    if (nseg > 0xffffffffu) return sl_fail(e, "raster: %zu segments is too many", nseg);
    cl_command_queue q = sl_cl_queue(cl);
    const size_t plane = (size_t)w * h;
    cl_uint empty = SL_RASTER_Z_EMPTY, n = (cl_uint)nseg, kk = K;
    cl_ulong zero = 0;
    cl_event ev = NULL;
    if (sl_cl_check(clEnqueueFillBuffer(q, z0bits, &empty, sizeof empty, 0, plane * sizeof empty, 0,
                                        NULL, timer ? &ev : NULL),
                    "raster: fill z0", e))
        return -1;
    if (timer) sl_cl_timer_add(timer, ev);
    if (sl_cl_check(clEnqueueFillBuffer(q, bins, &zero, sizeof zero, 0, K * plane * sizeof zero, 0,
                                        NULL, timer ? &ev : NULL),
                    "raster: fill bins", e))
        return -1;
    if (timer) sl_cl_timer_add(timer, ev);
    if (nseg == 0) return 0;
    size_t global = round_up(nseg, LOCAL), local = LOCAL;
    cl_int err = 0;
    err |= clSetKernelArg(kz, 0, sizeof recs, &recs);
    err |= clSetKernelArg(kz, 1, sizeof n, &n);
    err |= clSetKernelArg(kz, 2, sizeof w, &w);
    err |= clSetKernelArg(kz, 3, sizeof h, &h);
    err |= clSetKernelArg(kz, 4, sizeof z0bits, &z0bits);
    if (sl_cl_check(err, "raster: sl_raster_z0 arguments", e)) return -1;
    if (sl_cl_check(
            clEnqueueNDRangeKernel(q, kz, 1, NULL, &global, &local, 0, NULL, timer ? &ev : NULL),
            "raster: sl_raster_z0", e))
        return -1;
    if (timer) sl_cl_timer_add(timer, ev);
    err = 0;
    err |= clSetKernelArg(kl, 0, sizeof recs, &recs);
    err |= clSetKernelArg(kl, 1, sizeof n, &n);
    err |= clSetKernelArg(kl, 2, sizeof w, &w);
    err |= clSetKernelArg(kl, 3, sizeof h, &h);
    err |= clSetKernelArg(kl, 4, sizeof kk, &kk);
    err |= clSetKernelArg(kl, 5, sizeof d, &d);
    err |= clSetKernelArg(kl, 6, sizeof z0bits, &z0bits);
    err |= clSetKernelArg(kl, 7, sizeof bins, &bins);
    if (sl_cl_check(err, "raster: sl_raster_layers arguments", e)) return -1;
    if (sl_cl_check(
            clEnqueueNDRangeKernel(q, kl, 1, NULL, &global, &local, 0, NULL, timer ? &ev : NULL),
            "raster: sl_raster_layers", e))
        return -1;
    if (timer) sl_cl_timer_add(timer, ev);
    return 0;
}

int slcl_raster(sl_cl *cl, const float *recs, size_t nseg, int w, int h, unsigned K, float d,
                uint32_t *z0bits, uint64_t *bins, double *kernel_s, sl_err *e) {
    cl_context ctx = sl_cl_context(cl);
    const size_t plane = (size_t)w * h;
    cl_int err;
    cl_mem br = NULL, bz = NULL, bb = NULL;
    int rc = -1;
    br = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                        (nseg ? nseg : 1) * SL_RASTER_REC * sizeof(float),
                        nseg ? (void *)recs : (void *)&plane, &err);
    if (sl_cl_check(err, "raster: clCreateBuffer(records)", e)) goto done;
    bz = clCreateBuffer(ctx, CL_MEM_READ_WRITE, plane * sizeof(cl_uint), NULL, &err);
    if (sl_cl_check(err, "raster: clCreateBuffer(z0)", e)) goto done;
    bb = clCreateBuffer(ctx, CL_MEM_READ_WRITE, K * plane * sizeof(cl_ulong), NULL, &err);
    if (sl_cl_check(err, "raster: clCreateBuffer(layers)", e)) goto done;
    sl_cl_timer t;
    sl_cl_timer_start(&t, cl);
    rc = slcl_raster_buf(cl, br, nseg, w, h, K, d, bz, bb, &t, e);
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
    if (bz) clReleaseMemObject(bz);
    if (bb) clReleaseMemObject(bb);
    return rc;
}
