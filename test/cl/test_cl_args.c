/* test_cl_args.c: checked kernel arguments (host/cl/cl_args.h): a failing argument is named by
 * kernel, index and spelling, the first failure of a block wins and the later arguments are
 * skipped. Needs an OpenCL device: PoCL (or $SL_TEST_DEVICE), else SKIP. */
#include "test.h"

#include "cl/cl_args.h"
#include "cl/clrt.h"

#include <stdlib.h>
#include <string.h>

static int open_transpose(sl_device *dev, cl_kernel *k, sl_err *e) {
    const char *v = getenv("SL_TEST_DEVICE");
    if (sl_device_open(v && *v ? v : "pocl", dev, e)) return -1;
    if (sl_cl_get_kernel(dev->cl, "prefix_sum.cl", "sl_transpose", NULL, k, e)) {
        sl_device_close(dev);
        return -1;
    }
    return 0;
}

TEST(cl_args_names_kernel_and_argument) {
    sl_device dev;
    cl_kernel k;
    sl_err e = {{0}};
    if (open_transpose(&dev, &k, &e)) SKIP(e.msg);
    cl_uint rows = 4, cols = 8;
    sl_cl_args a = sl_cl_args_begin(k, &e);
    SL_CL_ARG(&a, 99, rows); /* no such argument */
    SL_CL_ARG(&a, 98, cols); /* skipped: the first failure is the one reported */
    CHECK(sl_cl_args_end(&a) == -1);
    CHECK_MSG(strcmp(e.msg, "sl_transpose: argument 99 (rows): CL_INVALID_ARG_INDEX (-49)") == 0,
              "%s", e.msg);
    /* one argument on its own, unnamed */
    CHECK(sl_cl_set_arg(k, 97, sizeof cols, &cols, NULL, &e) == -1);
    CHECK_MSG(strcmp(e.msg, "sl_transpose: argument 97: CL_INVALID_ARG_INDEX (-49)") == 0, "%s",
              e.msg);
    /* a wrong size for a buffer argument */
    char c = 0;
    a = sl_cl_args_begin(k, &e);
    SL_CL_ARG(&a, 0, c);
    CHECK(sl_cl_args_end(&a) == -1);
    CHECK_MSG(strncmp(e.msg, "sl_transpose: argument 0 (c): ", 30) == 0, "%s", e.msg);
    sl_device_close(&dev);
}

TEST(cl_args_all_set) {
    sl_device dev;
    cl_kernel k;
    sl_err e = {{0}};
    if (open_transpose(&dev, &k, &e)) SKIP(e.msg);
    cl_mem none = NULL; /* a NULL buffer is a valid argument value */
    sl_cl_args a = sl_cl_args_begin(k, &e);
    SL_CL_ARG(&a, 0, none);
    CHECK_MSG(sl_cl_args_end(&a) == 0, "%s", e.msg);
    sl_device_close(&dev);
}
