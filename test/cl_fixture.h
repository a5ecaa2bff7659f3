/* cl_fixture.h: the one device setting of the OpenCL unit tests, and the check that an OpenCL
 * run really ran kernels.
 *
 *   sl_device dev;
 *   sl_err e;
 *   SL_TEST_OPEN_CL(&dev, &e);                // SKIP without an OpenCL device, FAIL when one is
 *                                             // listed (or $SL_TEST_DEVICE names one) but fails
 *   // or, with clean-up first: int rc = sl_test_open_cl(&dev, &e);
 *   //                          if (rc) { ...; SL_TEST_CL_LEAVE(rc, &e); }
 *   unsigned long k0 = sl_cl_kernels_enqueued();
 *   ... the OpenCL run ...
 *   CHECK_CL_RAN(k0);                         // FAIL when no kernel was enqueued since k0
 *
 * The device: $SL_TEST_DEVICE when set (any --device spec), else the first GPU OpenCL device,
 * else PoCL, else any OpenCL device: the order of `--device auto` without its C fallback, so a
 * GPU-only machine runs these tests too. Static inline: every test file includes it into the
 * one unit_tests binary. */
#ifndef SL_TEST_CL_FIXTURE_H
#define SL_TEST_CL_FIXTURE_H

#include "test.h"

#include "cl/clrt.h"

#include <stdlib.h>

/* 1 when $SL_TEST_DEVICE is set (an explicit choice: not finding it is a failure). */
static inline int sl_test_cl_env_set(void) {
    const char *v = getenv("SL_TEST_DEVICE");
    return v && v[0];
}

/* The number of OpenCL devices this machine lists (`strandlight devices`). */
static inline int sl_test_cl_listed(void) {
    sl_cl_inventory inv;
    sl_cl_inventory_get(&inv);
    int n = inv.num_devices;
    sl_cl_inventory_free(&inv);
    return n;
}

/* The --device spec of the OpenCL tests: $SL_TEST_DEVICE, else "gpu" when a GPU OpenCL device
 * is listed, else "pocl" when a PoCL device is, else "opencl". */
static inline const char *sl_test_cl_spec(void) {
    if (sl_test_cl_env_set()) return getenv("SL_TEST_DEVICE");
    sl_cl_inventory inv;
    sl_cl_inventory_get(&inv);
    int gpu = 0, pocl = 0;
    for (int i = 0; i < inv.num_devices; i++) {
        gpu |= (inv.devices[i].type & CL_DEVICE_TYPE_GPU) != 0;
        pocl |= inv.devices[i].is_pocl;
    }
    sl_cl_inventory_free(&inv);
    return gpu ? "gpu" : pocl ? "pocl" : "opencl";
}

/* Opens the test device (sl_test_cl_spec) on dev. Returns 0 with dev on OpenCL; 1 when this
 * machine has no OpenCL device to test (or $SL_TEST_DEVICE names the C path): skip; -1 when an
 * OpenCL device is listed or $SL_TEST_DEVICE names one and it could not be opened: fail. e gets
 * the reason. */
static inline int sl_test_open_cl(sl_device *dev, sl_err *e) {
    const char *spec = sl_test_cl_spec();
    if (sl_device_open(spec, dev, e)) return sl_test_cl_env_set() || sl_test_cl_listed() ? -1 : 1;
    if (!dev->is_opencl) {
        sl_device_close(dev);
        sl_fail(e, "--device %s is the C path, not an OpenCL device", spec);
        return 1;
    }
    return 0;
}

/* Leaves the test after sl_test_open_cl returned rc != 0 (clean up first): SKIP when rc > 0,
 * FAIL when rc < 0. */
#define SL_TEST_CL_LEAVE(rc, e)                                                                    \
    do {                                                                                           \
        if ((rc) > 0) SKIP((e)->msg);                                                              \
        sl_test_fail(__FILE__, __LINE__, "the OpenCL test device is not usable: %s",          \
                     (e)->msg);                                                                    \
        return;                                                                                    \
    } while (0)

/* Opens the test device or leaves the test: SKIP without one, FAIL when it should be there. */
#define SL_TEST_OPEN_CL(dev, e)                                                                    \
    do {                                                                                           \
        int cl_rc_ = sl_test_open_cl((dev), (e));                                                  \
        if (cl_rc_) SL_TEST_CL_LEAVE(cl_rc_, (e));                                                 \
    } while (0)

/* Fails the test when no OpenCL kernel was enqueued since `before` (sl_cl_kernels_enqueued):
 * the "OpenCL" side of an OpenCL-vs-C test ran on the C path. */
#define CHECK_CL_RAN(before)                                                                       \
    CHECK_MSG(sl_cl_kernels_enqueued() > (before),                                                 \
              "no OpenCL kernel was enqueued (%lu before and after): the OpenCL run used C",       \
              (unsigned long)(before))

#endif
