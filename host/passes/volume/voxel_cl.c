/* voxel_cl.c: enqueues kernels/voxel.cl (see kernels/voxel.h; C twin cpu/voxel_c.c): the
 * accumulation pass (one work-item per segment, 64-bit atomics) then the per-voxel finalize. */
#include "passes/volume/voxel_cl.h"

#include "cl/cl_args.h"
#include "voxel.h"

#include <string.h>

#define LOCAL 64u

int slcl_voxelize(sl_cl *cl, const float *segs, size_t nseg, const int n[3], const float lo[3],
                  float h, float scale, float *out, double *kernel_s, sl_err *e) {
    size_t nvox = (size_t)n[0] * n[1] * n[2];
    if (nseg > 0xffffffffu || nvox > 0xffffffffu)
        return sl_fail(e, "voxelize: %zu segments / %zu voxels is too many", nseg, nvox);
    cl_kernel ka, kf;
    int rc;
    if ((rc = sl_cl_get_kernel(cl, "voxel.cl", "sl_voxel_accumulate", NULL, &ka, e))) return rc;
    if ((rc = sl_cl_get_kernel(cl, "voxel.cl", "sl_voxel_finalize", NULL, &kf, e))) return rc;
    cl_context ctx = sl_cl_context(cl);
    cl_command_queue q = sl_cl_queue(cl);
    cl_int err = 0;
    float dummy = 0.0f;
    cl_mem bs = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                               (nseg ? nseg * SL_VOX_SEG : 1) * sizeof(float),
                               nseg ? (void *)segs : (void *)&dummy, &err);
    if (sl_cl_check(err, "voxelize: clCreateBuffer", e)) return -1;
    cl_mem ba =
        clCreateBuffer(ctx, CL_MEM_READ_WRITE, nvox * SL_VOX_ACC * sizeof(cl_ulong), NULL, &err);
    cl_mem bo = NULL;
    if (!err)
        bo = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, nvox * SL_VOX_FIELDS * sizeof(float), NULL,
                            &err);
    rc = -1;
    sl_cl_timer t;
    sl_cl_timer_start(&t, cl);
    if (sl_cl_check(err, "voxelize: clCreateBuffer", e)) goto done;
    cl_ulong zero = 0;
    cl_event ev = NULL;
    if (sl_cl_check(clEnqueueFillBuffer(q, ba, &zero, sizeof zero, 0,
                                        nvox * SL_VOX_ACC * sizeof(cl_ulong), 0, NULL, &ev),
                    "voxelize: clear", e))
        goto done;
    sl_cl_timer_add(&t, ev);
    cl_uint ns = (cl_uint)nseg, nv = (cl_uint)nvox;
    cl_int nx = n[0], ny = n[1], nz = n[2];
    float inv_scale = 1.0f / scale;
    sl_cl_args a = sl_cl_args_begin(ka, e);
    SL_CL_ARG(&a, 0, bs);
    SL_CL_ARG(&a, 1, ns);
    SL_CL_ARG(&a, 2, nx);
    SL_CL_ARG(&a, 3, ny);
    SL_CL_ARG(&a, 4, nz);
    SL_CL_ARG(&a, 5, lo[0]);
    SL_CL_ARG(&a, 6, lo[1]);
    SL_CL_ARG(&a, 7, lo[2]);
    SL_CL_ARG(&a, 8, h);
    SL_CL_ARG(&a, 9, scale);
    SL_CL_ARG(&a, 10, ba);
    a.kernel = kf;
    SL_CL_ARG(&a, 0, ba);
    SL_CL_ARG(&a, 1, nv);
    SL_CL_ARG(&a, 2, h);
    SL_CL_ARG(&a, 3, inv_scale);
    SL_CL_ARG(&a, 4, bo);
    if (sl_cl_args_end(&a)) goto done;
    size_t local = LOCAL, global = sl_cl_round_up(nseg ? nseg : 1, LOCAL);
    if (nseg) {
        if (sl_cl_check(clEnqueueNDRangeKernel(q, ka, 1, NULL, &global, &local, 0, NULL, &ev),
                        "voxelize: sl_voxel_accumulate", e))
            goto done;
        sl_cl_timer_add(&t, ev);
    }
    global = sl_cl_round_up(nvox, LOCAL);
    if (sl_cl_check(clEnqueueNDRangeKernel(q, kf, 1, NULL, &global, &local, 0, NULL, &ev),
                    "voxelize: sl_voxel_finalize", e))
        goto done;
    sl_cl_timer_add(&t, ev);
    if (sl_cl_check(clEnqueueReadBuffer(q, bo, CL_TRUE, 0, nvox * SL_VOX_FIELDS * sizeof(float),
                                        out, 0, NULL, NULL),
                    "voxelize: read", e))
        goto done;
    rc = 0;
done:;
    double s = sl_cl_timer_stop(&t, NULL);
    if (kernel_s) *kernel_s = s;
    clReleaseMemObject(bs);
    if (ba) clReleaseMemObject(ba);
    if (bo) clReleaseMemObject(bo);
    return rc;
}
