/* clrt.h: the OpenCL runtime: device choice (OpenCL GPU, PoCL CPU or the C path), kernel
 * location, program build with an in-memory and an on-disk binary cache, event timing.
 *
 * Typical use (see docs/opencl.md):
 *
 *     sl_device dev;
 *     if (sl_device_open(device_spec, &dev, &e)) return -1;     // "auto", "pocl", "c", ...
 *     int rc = -1;
 *     if (dev.is_opencl) {
 *         rc = slcl_thing(dev.cl, ..., &e);
 *         if (rc && !sl_device_try_fallback(&dev, rc, &e)) goto fail; // auto: switches to C
 *     }
 *     if (!dev.is_opencl) slc_thing(...);                        // the C twin
 *     sl_device_close(&dev);
 *
 * Not thread-safe: one sl_cl per thread (or guard it yourself). */
#ifndef SL_CLRT_H
#define SL_CLRT_H

#include "base/common.h"
#include "base/disk_cache.h"

#include <CL/cl.h>

typedef struct sl_cl sl_cl; /* opaque: platform, device, context, queue, program/kernel cache */
typedef struct sl_device {
    int is_opencl; /* 0: the C path */
    sl_cl *cl;     /* non-NULL when is_opencl */
    char
        name[256]; /* human-readable choice, e.g. "PoCL CPU (pthread-skylake-avx512)" or "C path" */
    /* Set by sl_device_open under "auto": this device may switch to the C path. A device made
     * by hand around someone else's sl_cl ({0} + .cl = cl) never does, so a fallback can never
     * release an sl_cl its owner still uses. */
    int auto_chosen;
} sl_device;

/* spec: "auto" (GPU OpenCL device, else PoCL CPU device, else C; prints the choice and why on
 * stderr), "gpu", "pocl", "c", "opencl" (any OpenCL device, GPU preferred; error if none),
 * "P:D" or "N" (platform/device index as listed by `strandlight devices`). NULL means "auto".
 * An explicitly requested device that is not available is an error (-1, e set). */
int sl_device_open(const char *spec, sl_device *dev, sl_err *e);
/* Releases every OpenCL object (kernels, programs, queue, context); dev becomes the C path. */
void sl_device_close(sl_device *dev);

/* Returned (instead of -1) by sl_cl_get_kernel, and passed on by drivers that call it, when a
 * kernel could not be made: kernel directory or .cl file missing, build failure (the build log
 * has been printed to stderr), or no kernel of that name. Under `auto` the caller may fall back
 * to the C path (sl_device_try_fallback); any other failure is -1. */
#define SL_CL_EKERNEL (-2)

/* True when dev was chosen by "auto" and may therefore switch to the C path. */
int sl_device_may_fallback(const sl_device *dev);
/* Switches dev to the C path: prints "strandlight: warning: <why>; falling back to the C path",
 * releases every OpenCL object (kernels handed out before become invalid: release your own
 * buffers and events first). */
void sl_device_fallback_to_c(sl_device *dev, const char *why);
/* For pipeline code after an OpenCL step returned rc: when rc == SL_CL_EKERNEL (or -1 with a
 * run-time device failure in e->msg, see sl_cl_fault) and dev may fall back, switches dev to
 * the C path (the warning quotes e->msg) and returns 1 (redo the step on C); otherwise returns
 * 0 and leaves everything as it was. */
int sl_device_try_fallback(sl_device *dev, int rc, const sl_err *e);

/* Returns a kernel from kernels/<cl_file> built with extra_options (plus -I<kernel dir>
 * -cl-std=CL1.2); programs are built once per (file, options) and cached in memory, and as
 * binaries on disk by a hash of the source + every kernels/ *.h and *.inc + device + driver +
 * platform + options. The sl_cl owns the kernel: do not release it.
 * Returns 0, -1 or SL_CL_EKERNEL (see above). */
int sl_cl_get_kernel(sl_cl *cl, const char *cl_file, const char *kernel_name,
                     const char *extra_options, cl_kernel *kernel, sl_err *e);
cl_context sl_cl_context(sl_cl *cl);
cl_command_queue sl_cl_queue(sl_cl *cl);
cl_device_id sl_cl_device_id(sl_cl *cl);

/* ---- extras ---- */

/* Device facts captured at open time. */
const char *sl_cl_device_name(const sl_cl *cl);
/* "platform name|platform version|device name|driver version": what identifies a device across
 * runs, for caches of per-device measurements (host/plan/auto_device.h). */
void sl_cl_identity(const sl_cl *cl, char *out, size_t out_size);
int sl_cl_is_gpu(const sl_cl *cl);
int sl_cl_has_fp64(const sl_cl *cl);
size_t sl_cl_max_work_group_size(const sl_cl *cl);
cl_ulong sl_cl_max_alloc(const sl_cl *cl);
/* True when the queue was created with CL_QUEUE_PROFILING_ENABLE. */
int sl_cl_profiling(const sl_cl *cl);
/* The kernel directory in use ("" if none could be found). */
const char *sl_cl_kernel_dir(const sl_cl *cl);

/* Counters since open, for tests and `strandlight kernels`: programs built from source, programs
 * loaded from the disk cache, and seconds spent in those builds. Any pointer may be NULL. */
void sl_cl_build_stats(const sl_cl *cl, int *from_source, int *from_cache, double *build_s);

/* Kernel enqueues that succeeded in this process (every clEnqueueNDRangeKernel, whatever the
 * caller: the count is kept in the interposed entry point below), for tests: an OpenCL-vs-C
 * test takes it before its OpenCL run and checks that it grew, so a run that quietly went to
 * the C path fails. */
unsigned long sl_cl_kernels_enqueued(void);

/* Fault injection, for tests only (docs/robustness.md): SL_CL_FAULT=build makes every program
 * build of a device opened afterwards fail (SL_CL_EKERNEL, "... (simulated: SL_CL_FAULT=build)");
 * =enqueue makes every clEnqueueNDRangeKernel return CL_OUT_OF_RESOURCES; =lost lets the first
 * kernel enqueue of the process through, then every kernel enqueue and buffer read returns
 * CL_DEVICE_NOT_AVAILABLE (a device gone mid-run). Run-time device failures like these
 * (CL_DEVICE_NOT_AVAILABLE, CL_MEM_OBJECT_ALLOCATION_FAILURE, CL_OUT_OF_RESOURCES,
 * CL_OUT_OF_HOST_MEMORY in e->msg) fall back to the C path under auto like SL_CL_EKERNEL does. */
enum { SL_CL_FAULT_NONE = 0, SL_CL_FAULT_BUILD, SL_CL_FAULT_ENQUEUE, SL_CL_FAULT_LOST };
int sl_cl_fault(void); /* the SL_CL_FAULT mode now */

/* "CL_OUT_OF_RESOURCES" etc. (static string; "unknown OpenCL error" for unknown codes). */
const char *sl_cl_strerror(cl_int err);
/* If err != CL_SUCCESS: sets e to "<what>: <name> (<code>)" and returns -1; else returns 0. */
int sl_cl_check(cl_int err, const char *what, sl_err *e);

/* Kernel timing: device time from profiling events when the queue has profiling enabled (and the
 * driver reports nonzero timestamps), else wall clock from start to stop (stop calls clFinish).
 *     sl_cl_timer t; sl_cl_timer_start(&t, cl);
 *     clEnqueueNDRangeKernel(..., &ev); sl_cl_timer_add(&t, ev);   // takes ownership of ev
 *     double s = sl_cl_timer_stop(&t); */
typedef struct sl_cl_timer {
    sl_cl *cl;
    double wall_start;
    cl_event *events; /* held until stop (profiling info exists only once an event is done) */
    int num_events, cap_events;
} sl_cl_timer;
void sl_cl_timer_start(sl_cl_timer *t, sl_cl *cl);
void sl_cl_timer_add(sl_cl_timer *t, cl_event ev);
/* Seconds (always call it: it releases the events): device time when every event had profiling
 * info, else wall time. *is_device (may be NULL) tells which. */
double sl_cl_timer_stop(sl_cl_timer *t, int *is_device);

/* Rounds x up to a multiple of m (a 1-D launch's global size). */
size_t sl_cl_round_up(size_t x, size_t m);
/* Enqueues kernel k (already given its arguments) over n work-items (at least 1) in work-groups
 * of `local`; the global size is rounded up, so kernels guard their index. With a timer, the
 * launch's event is added to it. `name` goes into the error message. */
int sl_cl_run1d(sl_cl *cl, cl_kernel k, const char *name, size_t n, size_t local,
                sl_cl_timer *timer, sl_err *e);

/* Duration END - START of one finished event in seconds, or -1 when unavailable. */
double sl_cl_event_seconds(cl_event ev);

/* ---- device inventory (used by `strandlight devices` and sl_device_open) ---- */

typedef struct sl_cl_devinfo {
    int platform_index, device_index, global_index; /* P:D and N in the --device syntax */
    cl_platform_id platform;
    cl_device_id device;
    cl_device_type type;
    int is_pocl;
    char name[256], vendor[256], version[256], driver_version[256], opencl_c_version[256];
    cl_uint compute_units, max_clock_mhz;
    cl_ulong global_mem, local_mem, max_alloc;
    size_t max_work_group;
    int fp64, gl_sharing, images;
} sl_cl_devinfo;

typedef struct sl_cl_platinfo {
    cl_platform_id platform;
    char name[256], vendor[256], version[256];
    int is_pocl;
    cl_int device_err; /* clGetDeviceIDs result (CL_DEVICE_NOT_FOUND for empty platforms) */
    int num_devices;
} sl_cl_platinfo;

typedef struct sl_cl_inventory {
    cl_int platform_err; /* clGetPlatformIDs result; -1001 when no ICD is installed */
    int num_platforms;
    sl_cl_platinfo *platforms;
    int num_devices; /* over all platforms, in listing order */
    sl_cl_devinfo *devices;
} sl_cl_inventory;

/* Lists every platform and device. Never fails: no platforms is an empty inventory with
 * platform_err set. Free with sl_cl_inventory_free. */
void sl_cl_inventory_get(sl_cl_inventory *inv);
void sl_cl_inventory_free(sl_cl_inventory *inv);
/* The device `auto` picks (index into inv->devices) or -1 for the C path; why gets the reason
 * ("no GPU OpenCL device found", ...). */
int sl_cl_inventory_auto(const sl_cl_inventory *inv, char *why, size_t why_size);
/* "GPU", "CPU", "accelerator", ... for a device type. */
const char *sl_cl_type_name(cl_device_type type);
/* A human-readable device label: "PoCL CPU (pthread-...)", "GPU (NVIDIA H200)". */
void sl_cl_device_label(const sl_cl_devinfo *d, char *out, size_t out_size);

/* ---- kernel location and disk cache (host/cl/clrt_cache.c) ---- */

/* Kernel directory: env STRANDLIGHT_KERNELS if set (must be a directory), else
 * <directory of /proc/self/exe>/../kernels if it exists, else the compiled-in SL_KERNEL_DIR. */
int sl_kernel_dir_find(char *out, size_t out_size, sl_err *e);
/* The disk cache directory (sl_cache_dir_find) and its entries: base/disk_cache.h. */

/* What a program build needs to know about the device (for the cache key). */
typedef struct sl_cl_build_target {
    cl_context ctx;
    cl_device_id device;
    const char *device_name, *driver_version, *platform_name, *platform_version;
    const char *kernel_dir; /* where cl_file and the headers live */
    const char *cache_dir;  /* NULL or "": no disk cache */
} sl_cl_build_target;
/* Builds kernel_dir/cl_file with "-I<kernel_dir> -cl-std=CL1.2 <options>", from the disk cache
 * when a valid entry exists (a corrupt one is ignored, rebuilt and rewritten). Build failures
 * print the log to stderr and return SL_CL_EKERNEL. *from_cache tells where it came from. */
int sl_cl_build_program(const sl_cl_build_target *t, const char *cl_file, const char *options,
                        cl_program *prog, int *from_cache, sl_err *e);

#endif
