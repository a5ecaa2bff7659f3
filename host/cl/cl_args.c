/* cl_args.c: checked kernel arguments (see cl_args.h). */
#include "cl/cl_args.h"

#include "cl/clrt.h"

int sl_cl_set_arg(cl_kernel k, cl_uint index, size_t size, const void *value, const char *name,
                  sl_err *e) {
    cl_int err = clSetKernelArg(k, index, size, value);
    if (err == CL_SUCCESS) return 0;
    char kname[128];
    if (clGetKernelInfo(k, CL_KERNEL_FUNCTION_NAME, sizeof kname, kname, NULL) != CL_SUCCESS)
        snprintf(kname, sizeof kname, "kernel");
    kname[sizeof kname - 1] = '\0';
    if (name)
        return sl_fail(e, "%s: argument %u (%s): %s (%d)", kname, (unsigned)index, name,
                       sl_cl_strerror(err), (int)err);
    return sl_fail(e, "%s: argument %u: %s (%d)", kname, (unsigned)index, sl_cl_strerror(err),
                   (int)err);
}

sl_cl_args sl_cl_args_begin(cl_kernel k, sl_err *e) {
    sl_cl_args a = {k, e, 0};
    return a;
}

void sl_cl_arg(sl_cl_args *a, cl_uint index, size_t size, const void *value, const char *name) {
    if (a->failed) return;
    if (sl_cl_set_arg(a->kernel, index, size, value, name, a->e)) a->failed = 1;
}

int sl_cl_args_end(const sl_cl_args *a) { return a->failed ? -1 : 0; }
