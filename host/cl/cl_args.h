/* cl_args.h: the one checked way to set a kernel's arguments.
 *
 * clSetKernelArg results ORed together report a meaningless code and no argument; these name
 * the kernel (its function name, asked of the kernel) and the first argument that failed:
 *     "sl_raster_project_k: argument 3 (views): CL_INVALID_MEM_OBJECT (-38)"
 *
 *     sl_cl_args a = sl_cl_args_begin(k, e);
 *     SL_CL_ARG(&a, 0, d_pos);           // sizeof d_pos bytes at &d_pos, named "d_pos"
 *     SL_CL_ARG(&a, 1, n);
 *     if (sl_cl_args_end(&a)) return -1; // -1 when an argument failed (e filled by the first)
 *
 * Once an argument has failed, the later ones are not set. */
#ifndef SL_CL_ARGS_H
#define SL_CL_ARGS_H

#include "base/common.h"

#include <CL/cl.h>

typedef struct sl_cl_args {
    cl_kernel kernel;
    sl_err *e;
    int failed;
} sl_cl_args;

sl_cl_args sl_cl_args_begin(cl_kernel k, sl_err *e);
/* Sets argument index (size bytes at value) unless an earlier one failed; name (may be NULL)
 * goes into the error message. */
void sl_cl_arg(sl_cl_args *a, cl_uint index, size_t size, const void *value, const char *name);
/* The argument is an lvalue: its size, its address and its spelling. */
#define SL_CL_ARG(a, index, var) sl_cl_arg((a), (index), sizeof(var), &(var), #var)
/* 0 when every argument was set, else -1 (e holds the first failure). */
int sl_cl_args_end(const sl_cl_args *a);

/* One argument on its own: 0, or -1 with e set as above. */
int sl_cl_set_arg(cl_kernel k, cl_uint index, size_t size, const void *value, const char *name,
                  sl_err *e);

#endif
