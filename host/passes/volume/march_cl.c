/* march_cl.c: enqueues kernels/march.cl (see kernels/march.h; C twin cpu/march_c.c): uploads the
 * voxel grid, the dual tables, the vertices and the lobe directions; one work-item per
 * (vertex, lobe). */
#include "passes/volume/march_cl.h"

#include "cl/cl_args.h"
#include "march.h"

#include <string.h>

#define LOCAL 64u

int slcl_march(sl_cl *cl, const float *vox, const int n[3], const float lo[3], float h,
               const float *tabs, const float *verts, const uint32_t *vert_ids, size_t nverts,
               const float *dirs, size_t nlobes, int paths, uint32_t seed, float *outT, float *outS,
               float *outG, double *kernel_s, sl_err *e) {
    size_t nvox = (size_t)n[0] * n[1] * n[2], nout = nverts * nlobes;
    if (kernel_s) *kernel_s = 0;
    if (nout == 0) return 0;
    if (nout > 0xffffffffu) return sl_fail(e, "march: %zu vertices x lobes is too many", nout);
    cl_kernel k;
    int rc = sl_cl_get_kernel(cl, "march.cl", "sl_march", NULL, &k, e);
    if (rc) return rc;
    cl_context ctx = sl_cl_context(cl);
    cl_command_queue q = sl_cl_queue(cl);
    const size_t sizes[5] = {
        nvox * SL_VOX_FIELDS * sizeof(float), SL_MARCH_CH * SL_DUAL_TABLE_FLOATS * sizeof(float),
        nverts * 3 * sizeof(float), nlobes * 3 * sizeof(float), nverts * sizeof(uint32_t)};
    const void *src[5] = {vox, tabs, verts, dirs, vert_ids};
    cl_mem in[5] = {0}, bT = NULL, bS = NULL, bG = NULL;
    cl_int err = 0;
    rc = -1;
    for (int i = 0; i < 5 && !err; i++)
        in[i] = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizes[i],
                               (void *)src[i], &err);
    if (!err)
        bT = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, nout * SL_MARCH_CH * sizeof(float), NULL, &err);
    if (!err)
        bS = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, nout * SL_MARCH_CH * sizeof(float), NULL, &err);
    if (!err)
        bG = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, nout * SL_MARCH_CH * sizeof(float), NULL, &err);
    if (sl_cl_check(err, "march: clCreateBuffer", e)) goto done;
    cl_int nx = n[0], ny = n[1], nz = n[2], cp = paths;
    cl_uint nv = (cl_uint)nverts, nl = (cl_uint)nlobes, sd = seed;
    sl_cl_args a = sl_cl_args_begin(k, e);
    SL_CL_ARG(&a, 0, in[0]);
    SL_CL_ARG(&a, 1, nx);
    SL_CL_ARG(&a, 2, ny);
    SL_CL_ARG(&a, 3, nz);
    SL_CL_ARG(&a, 4, lo[0]);
    SL_CL_ARG(&a, 5, lo[1]);
    SL_CL_ARG(&a, 6, lo[2]);
    SL_CL_ARG(&a, 7, h);
    SL_CL_ARG(&a, 8, in[1]);
    SL_CL_ARG(&a, 9, in[2]);
    SL_CL_ARG(&a, 10, nv);
    SL_CL_ARG(&a, 11, in[3]);
    SL_CL_ARG(&a, 12, nl);
    SL_CL_ARG(&a, 13, cp);
    SL_CL_ARG(&a, 14, sd);
    SL_CL_ARG(&a, 15, in[4]);
    SL_CL_ARG(&a, 16, bT);
    SL_CL_ARG(&a, 17, bS);
    SL_CL_ARG(&a, 18, bG);
    if (sl_cl_args_end(&a)) goto done;
    size_t local = LOCAL, global = (nout + LOCAL - 1) / LOCAL * LOCAL;
    sl_cl_timer t;
    sl_cl_timer_start(&t, cl);
    cl_event ev = NULL;
    err = clEnqueueNDRangeKernel(q, k, 1, NULL, &global, &local, 0, NULL, &ev);
    if (!err) sl_cl_timer_add(&t, ev);
    double s = sl_cl_timer_stop(&t, NULL);
    if (kernel_s) *kernel_s = s;
    if (sl_cl_check(err, "march: sl_march", e)) goto done;
    if (sl_cl_check(clEnqueueReadBuffer(q, bT, CL_TRUE, 0, nout * SL_MARCH_CH * sizeof(float), outT,
                                        0, NULL, NULL),
                    "march: read", e) ||
        sl_cl_check(clEnqueueReadBuffer(q, bS, CL_TRUE, 0, nout * SL_MARCH_CH * sizeof(float), outS,
                                        0, NULL, NULL),
                    "march: read", e) ||
        sl_cl_check(clEnqueueReadBuffer(q, bG, CL_TRUE, 0, nout * SL_MARCH_CH * sizeof(float), outG,
                                        0, NULL, NULL),
                    "march: read", e))
        goto done;
    rc = 0;
done:
    for (int i = 0; i < 5; i++)
        if (in[i]) clReleaseMemObject(in[i]);
    if (bT) clReleaseMemObject(bT);
    if (bS) clReleaseMemObject(bS);
    if (bG) clReleaseMemObject(bG);
    return rc;
}
