/* prefix_sum_cl.c: enqueues kernels/prefix_sum.cl (see kernels/prefix_sum.h for the algorithm and
 * prefix_sum_cl.h for the two variants); the C twin is cpu/prefix_sum.c. */
#include "passes/light/prefix_sum_cl.h"

#include "cl/cl_args.h"
#include "../cpu/prefix_sum.h"
#include "../kernels/prefix_sum.h"

#include <stdint.h>
#include <string.h>

#define PS_FILE "prefix_sum.cl"

/* Rows of at most this many elements use the serial tile kernel even on GPUs. */
#define PS_NARROW_ROW 64u
/* Local size of the serial and offset kernels. */
#define PS_LOCAL 64u

typedef struct ps_kernels {
    sl_ps_variant variant; /* resolved: WORKGROUP or SERIAL */
    int auto_narrow;       /* AUTO on a non-CPU device: serial for narrow rows */
    cl_kernel tiles, tiles_serial, add, transpose, col_tiles, col_add;
} ps_kernels;

static int get_kernels(sl_cl *cl, sl_ps_variant v, ps_kernels *k, sl_err *e) {
    int rc;
    memset(k, 0, sizeof *k);
    k->auto_narrow = v == SL_PS_AUTO && sl_cl_is_gpu(cl);
    if (v == SL_PS_AUTO) v = sl_cl_is_gpu(cl) ? SL_PS_WORKGROUP : SL_PS_SERIAL;
    k->variant = v;
    if ((rc = sl_cl_get_kernel(cl, PS_FILE, "sl_scan_tiles_serial", NULL, &k->tiles_serial, e)))
        return rc;
    if ((rc = sl_cl_get_kernel(cl, PS_FILE, "sl_scan_add_offsets", NULL, &k->add, e))) return rc;
    if (v == SL_PS_WORKGROUP) {
        if ((rc = sl_cl_get_kernel(cl, PS_FILE, "sl_scan_tiles", NULL, &k->tiles, e))) return rc;
        return sl_cl_get_kernel(cl, PS_FILE, "sl_transpose", NULL, &k->transpose, e);
    }
    if ((rc = sl_cl_get_kernel(cl, PS_FILE, "sl_scan_col_tiles_serial", NULL, &k->col_tiles, e)))
        return rc;
    return sl_cl_get_kernel(cl, PS_FILE, "sl_scan_col_add_offsets", NULL, &k->col_add, e);
}

/* Sets k's n arguments (sizes[i] bytes at vals[i]) and enqueues it over the 2-D range global in
 * work groups of local; with a timer, its event goes there. Errors name the kernel. */
static int launch(sl_cl *cl, cl_kernel k, const char *name, int n, const size_t *sizes,
                  const void *const *vals, const size_t global[2], const size_t local[2],
                  sl_cl_timer *timer, sl_err *e) {
    for (int i = 0; i < n; i++)
        if (sl_cl_set_arg(k, (cl_uint)i, sizes[i], vals[i], NULL, e)) return -1;
    cl_event ev = NULL;
    cl_int err = clEnqueueNDRangeKernel(sl_cl_queue(cl), k, 2, NULL, global, local, 0, NULL,
                                        timer ? &ev : NULL);
    if (sl_cl_check(err, name, e)) return -1;
    if (timer) sl_cl_timer_add(timer, ev);
    return 0;
}

static cl_mem new_buffer(sl_cl *cl, size_t floats, sl_err *e) {
    cl_int err;
    cl_mem m =
        clCreateBuffer(sl_cl_context(cl), CL_MEM_READ_WRITE, floats * sizeof(float), NULL, &err);
    if (err != CL_SUCCESS) {
        char what[128];
        snprintf(what, sizeof what, "prefix sum: clCreateBuffer(%zu floats)", floats);
        sl_cl_check(err, what, e);
        return NULL;
    }
    return m;
}

/* Inclusive scan of each of h rows of w floats: tiles, then (if a row has several tiles) the
 * scan of the tile totals, recursively, added back. */
static int scan_rows(sl_cl *cl, const ps_kernels *k, cl_mem in, cl_mem out, cl_uint w, cl_uint h,
                     sl_cl_timer *timer, sl_err *e) {
    cl_uint nt = sl_scan_num_tiles(w);
    cl_mem sums = new_buffer(cl, (size_t)nt * h, e), scanned = NULL;
    if (!sums) return -1;
    int rc = -1;
    {
        const size_t sz[6] = {sizeof in, sizeof out, sizeof sums, sizeof w, sizeof nt, sizeof h};
        const void *v[6] = {&in, &out, &sums, &w, &nt, &h};
        int serial = k->variant == SL_PS_SERIAL || (k->auto_narrow && w <= PS_NARROW_ROW);
        /* Fixed local sizes everywhere: PoCL generates code per local size at the first enqueue
         * (toolchain.md sec. 2), so letting it choose per image shape recompiles often. */
        const size_t global_wg[2] = {(size_t)nt * SL_SCAN_WG, h}, local_wg[2] = {SL_SCAN_WG, 1};
        const size_t global_serial[2] = {nt, sl_cl_round_up(h, PS_LOCAL)},
                     local_serial[2] = {1, PS_LOCAL};
        cl_kernel kt = serial ? k->tiles_serial : k->tiles;
        const char *name = serial ? "sl_scan_tiles_serial" : "sl_scan_tiles";
        if (launch(cl, kt, name, serial ? 6 : 5, sz, v, serial ? global_serial : global_wg,
                   serial ? local_serial : local_wg, timer, e))
            goto done;
    }
    if (nt > 1) {
        if (!(scanned = new_buffer(cl, (size_t)nt * h, e))) goto done;
        if (scan_rows(cl, k, sums, scanned, nt, h, timer, e)) goto done;
        const size_t sz[4] = {sizeof out, sizeof scanned, sizeof w, sizeof nt};
        const void *v[4] = {&out, &scanned, &w, &nt};
        const size_t global[2] = {sl_cl_round_up(w, PS_LOCAL), h}, local[2] = {PS_LOCAL, 1};
        if (launch(cl, k->add, "sl_scan_add_offsets", 4, sz, v, global, local, timer, e)) goto done;
    }
    rc = 0;
done:
    /* Released buffers live on until the commands that use them have finished. */
    if (scanned) clReleaseMemObject(scanned);
    clReleaseMemObject(sums);
    return rc;
}

/* Inclusive scan down each of w columns of an h x w image (serial variant, no transposes): tiles
 * of rows, then the column scan of the tile totals (an ntiles x w image), recursively. */
static int scan_cols(sl_cl *cl, const ps_kernels *k, cl_mem in, cl_mem out, cl_uint w, cl_uint h,
                     sl_cl_timer *timer, sl_err *e) {
    cl_uint nt = sl_scan_num_tiles(h);
    cl_mem sums = new_buffer(cl, (size_t)nt * w, e), scanned = NULL;
    if (!sums) return -1;
    int rc = -1;
    {
        const size_t sz[5] = {sizeof in, sizeof out, sizeof sums, sizeof w, sizeof h};
        const void *v[5] = {&in, &out, &sums, &w, &h};
        const size_t global[2] = {sl_cl_round_up(w, PS_LOCAL), nt}, local[2] = {PS_LOCAL, 1};
        if (launch(cl, k->col_tiles, "sl_scan_col_tiles_serial", 5, sz, v, global, local, timer, e))
            goto done;
    }
    if (nt > 1) {
        if (!(scanned = new_buffer(cl, (size_t)nt * w, e))) goto done;
        if (scan_cols(cl, k, sums, scanned, w, nt, timer, e)) goto done;
        const size_t sz[3] = {sizeof out, sizeof scanned, sizeof w};
        const void *v[3] = {&out, &scanned, &w};
        const size_t global[2] = {sl_cl_round_up(w, PS_LOCAL), h}, local[2] = {PS_LOCAL, 1};
        if (launch(cl, k->col_add, "sl_scan_col_add_offsets", 3, sz, v, global, local, timer, e))
            goto done;
    }
    rc = 0;
done:
    if (scanned) clReleaseMemObject(scanned);
    clReleaseMemObject(sums);
    return rc;
}

static int transpose(sl_cl *cl, const ps_kernels *k, cl_mem in, cl_mem out, cl_uint w, cl_uint h,
                     sl_cl_timer *timer, sl_err *e) {
    const size_t sz[4] = {sizeof in, sizeof out, sizeof w, sizeof h};
    const void *v[4] = {&in, &out, &w, &h};
    const size_t global[2] = {sl_cl_round_up(w, SL_TRANSPOSE_TILE),
                              sl_cl_round_up(h, SL_TRANSPOSE_TILE)};
    const size_t local[2] = {SL_TRANSPOSE_TILE, SL_TRANSPOSE_TILE};
    return launch(cl, k->transpose, "sl_transpose", 4, sz, v, global, local, timer, e);
}

static int check_size(sl_cl *cl, const ps_kernels *k, size_t w, size_t h, sl_err *e) {
    if (w < 1 || h < 1 || w >= (1u << 31) || h >= (1u << 31) || w > SIZE_MAX / sizeof(float) / h)
        return sl_fail(e, "prefix sum: bad image size %zu x %zu", w, h);
    if ((cl_ulong)w * h * sizeof(float) > sl_cl_max_alloc(cl))
        return sl_fail(e,
                       "prefix sum: %zu x %zu image exceeds the device's largest buffer (%llu "
                       "bytes)",
                       w, h, (unsigned long long)sl_cl_max_alloc(cl));
    if (k->variant == SL_PS_WORKGROUP &&
        sl_cl_max_work_group_size(cl) < SL_TRANSPOSE_TILE * SL_TRANSPOSE_TILE)
        return sl_fail(e, "prefix sum: device work-groups hold %zu work-items, need %u",
                       sl_cl_max_work_group_size(cl), SL_TRANSPOSE_TILE * SL_TRANSPOSE_TILE);
    return 0;
}

/* Work-group variant: rows, transpose, rows (the columns), transpose back. Serial variant: rows
 * into out, then columns in place. in == out is fine either way. */
static int prefix_sum_buf(sl_cl *cl, const ps_kernels *k, cl_mem in, cl_mem out, size_t w, size_t h,
                          sl_cl_timer *timer, sl_err *e) {
    if (check_size(cl, k, w, h, e)) return -1;
    if (k->variant == SL_PS_SERIAL)
        return scan_rows(cl, k, in, out, (cl_uint)w, (cl_uint)h, timer, e) ||
                       scan_cols(cl, k, out, out, (cl_uint)w, (cl_uint)h, timer, e)
                   ? -1
                   : 0;
    cl_mem t1 = new_buffer(cl, w * h, e), t2 = t1 ? new_buffer(cl, w * h, e) : NULL;
    int rc = -1;
    if (t1 && t2 && scan_rows(cl, k, in, t1, (cl_uint)w, (cl_uint)h, timer, e) == 0 &&
        transpose(cl, k, t1, t2, (cl_uint)w, (cl_uint)h, timer, e) == 0 &&
        scan_rows(cl, k, t2, t1, (cl_uint)h, (cl_uint)w, timer, e) == 0 &&
        transpose(cl, k, t1, out, (cl_uint)h, (cl_uint)w, timer, e) == 0)
        rc = 0;
    if (t1) clReleaseMemObject(t1);
    if (t2) clReleaseMemObject(t2);
    return rc;
}

int slcl_prefix_sum_2d_buf(sl_cl *cl, cl_mem in, cl_mem out, size_t w, size_t h, sl_cl_timer *timer,
                           sl_err *e) {
    ps_kernels k;
    int rc = get_kernels(cl, SL_PS_AUTO, &k, e);
    if (rc) return rc;
    return prefix_sum_buf(cl, &k, in, out, w, h, timer, e);
}

int slcl_prefix_sum_2d(sl_cl *cl, const float *in, float *out, size_t w, size_t h, double *kernel_s,
                       sl_err *e) {
    return slcl_prefix_sum_2d_variant(cl, in, out, w, h, SL_PS_AUTO, kernel_s, e);
}

int slcl_prefix_sum_2d_variant(sl_cl *cl, const float *in, float *out, size_t w, size_t h,
                               sl_ps_variant variant, double *kernel_s, sl_err *e) {
    ps_kernels k;
    int rc = get_kernels(cl, variant, &k, e);
    if (rc) return rc;
    if (check_size(cl, &k, w, h, e)) return -1;
    cl_int err;
    cl_mem buf = clCreateBuffer(sl_cl_context(cl), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR,
                                w * h * sizeof(float), (void *)in, &err);
    if (sl_cl_check(err, "prefix sum: clCreateBuffer", e)) return -1;
    sl_cl_timer timer;
    sl_cl_timer_start(&timer, cl);
    rc = prefix_sum_buf(cl, &k, buf, buf, w, h, &timer, e);
    double s = sl_cl_timer_stop(&timer, NULL);
    if (rc == 0 && sl_cl_check(clEnqueueReadBuffer(sl_cl_queue(cl), buf, CL_TRUE, 0,
                                                   w * h * sizeof(float), out, 0, NULL, NULL),
                               "prefix sum: clEnqueueReadBuffer", e))
        rc = -1;
    clReleaseMemObject(buf);
    if (kernel_s) *kernel_s = s;
    return rc;
}

int sl_prefix_sum_2d(sl_device *dev, const float *in, float *out, size_t w, size_t h, sl_err *e) {
    if (dev->is_opencl) {
        int rc = slcl_prefix_sum_2d(dev->cl, in, out, w, h, NULL, e);
        if (rc == 0) return 0;
        if (!sl_device_try_fallback(dev, rc, e)) return -1;
    }
    if (w < 1 || h < 1 || w > SIZE_MAX / sizeof(float) / h)
        return sl_fail(e, "prefix sum: bad image size %zu x %zu", w, h);
    slc_prefix_sum_2d(in, out, w, h);
    return 0;
}
