/* clrt.c: OpenCL device inventory and choice, the sl_cl object (context, queue, in-memory
 * program/kernel cache), the C fallback and event timing. Program building and the disk cache
 * live in clrt_cache.c. Facts this relies on: ../shared/design/toolchain.md sec. 2 (no ICD gives
 * -1001; mesa platforms with 0 devices answer CL_DEVICE_NOT_FOUND and are skipped). */
#define _GNU_SOURCE /* RTLD_NEXT, for the test-only fault layer at the end of this file */
#include "cl/clrt.h"

#include <dlfcn.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

typedef struct sl_cl_prog {
    char *file, *options;
    cl_program prog; /* NULL when the build failed: the failure is remembered */
    char err[1024];  /* the failure message, replayed on later requests */
} sl_cl_prog;

typedef struct sl_cl_kern {
    int prog; /* index into progs */
    char *name;
    cl_kernel kernel;
} sl_cl_kern;

struct sl_cl {
    cl_platform_id platform;
    cl_device_id device;
    cl_context ctx;
    cl_command_queue queue;
    int profiling, auto_chosen, is_gpu, fp64;
    int fault; /* SL_CL_FAULT=build (tests only): every program build fails, see sl_cl_fault */
    size_t max_wg;
    cl_ulong max_alloc;
    char device_name[256], driver_version[256], platform_name[256], platform_version[256];
    char kernel_dir[4096], kernel_dir_err[1024], cache_dir[4096];
    sl_cl_prog *progs;
    int num_progs;
    sl_cl_kern *kerns;
    int num_kerns;
    int built_from_source, built_from_cache;
    double build_s;
};

/* Copies src into dst (size n), truncating. */
static void copy_str(char *dst, size_t n, const char *src) {
    size_t l = strlen(src);
    if (l >= n) l = n - 1;
    memcpy(dst, src, l);
    dst[l] = 0;
}

/* ---------------------------------------------------------------- error names */

const char *sl_cl_strerror(cl_int err) {
    switch (err) {
#define E(x)                                                                                       \
    case x:                                                                                        \
        return #x;
        E(CL_SUCCESS)
        E(CL_DEVICE_NOT_FOUND)
        E(CL_DEVICE_NOT_AVAILABLE)
        E(CL_COMPILER_NOT_AVAILABLE)
        E(CL_MEM_OBJECT_ALLOCATION_FAILURE)
        E(CL_OUT_OF_RESOURCES)
        E(CL_OUT_OF_HOST_MEMORY)
        E(CL_PROFILING_INFO_NOT_AVAILABLE)
        E(CL_MEM_COPY_OVERLAP)
        E(CL_IMAGE_FORMAT_MISMATCH)
        E(CL_IMAGE_FORMAT_NOT_SUPPORTED)
        E(CL_BUILD_PROGRAM_FAILURE)
        E(CL_MAP_FAILURE)
        E(CL_MISALIGNED_SUB_BUFFER_OFFSET)
        E(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST)
        E(CL_COMPILE_PROGRAM_FAILURE)
        E(CL_LINKER_NOT_AVAILABLE)
        E(CL_LINK_PROGRAM_FAILURE)
        E(CL_DEVICE_PARTITION_FAILED)
        E(CL_KERNEL_ARG_INFO_NOT_AVAILABLE)
        E(CL_INVALID_VALUE)
        E(CL_INVALID_DEVICE_TYPE)
        E(CL_INVALID_PLATFORM)
        E(CL_INVALID_DEVICE)
        E(CL_INVALID_CONTEXT)
        E(CL_INVALID_QUEUE_PROPERTIES)
        E(CL_INVALID_COMMAND_QUEUE)
        E(CL_INVALID_HOST_PTR)
        E(CL_INVALID_MEM_OBJECT)
        E(CL_INVALID_IMAGE_FORMAT_DESCRIPTOR)
        E(CL_INVALID_IMAGE_SIZE)
        E(CL_INVALID_SAMPLER)
        E(CL_INVALID_BINARY)
        E(CL_INVALID_BUILD_OPTIONS)
        E(CL_INVALID_PROGRAM)
        E(CL_INVALID_PROGRAM_EXECUTABLE)
        E(CL_INVALID_KERNEL_NAME)
        E(CL_INVALID_KERNEL_DEFINITION)
        E(CL_INVALID_KERNEL)
        E(CL_INVALID_ARG_INDEX)
        E(CL_INVALID_ARG_VALUE)
        E(CL_INVALID_ARG_SIZE)
        E(CL_INVALID_KERNEL_ARGS)
        E(CL_INVALID_WORK_DIMENSION)
        E(CL_INVALID_WORK_GROUP_SIZE)
        E(CL_INVALID_WORK_ITEM_SIZE)
        E(CL_INVALID_GLOBAL_OFFSET)
        E(CL_INVALID_EVENT_WAIT_LIST)
        E(CL_INVALID_EVENT)
        E(CL_INVALID_OPERATION)
        E(CL_INVALID_GL_OBJECT)
        E(CL_INVALID_BUFFER_SIZE)
        E(CL_INVALID_MIP_LEVEL)
        E(CL_INVALID_GLOBAL_WORK_SIZE)
        E(CL_INVALID_PROPERTY)
        E(CL_INVALID_IMAGE_DESCRIPTOR)
        E(CL_INVALID_COMPILER_OPTIONS)
        E(CL_INVALID_LINKER_OPTIONS)
        E(CL_INVALID_DEVICE_PARTITION_COUNT)
#undef E
    case -1001:
        return "CL_PLATFORM_NOT_FOUND_KHR";
    default:
        return "unknown OpenCL error";
    }
}

int sl_cl_check(cl_int err, const char *what, sl_err *e) {
    if (err == CL_SUCCESS) return 0;
    return sl_fail(e, "%s: %s (%d)", what, sl_cl_strerror(err), (int)err);
}

/* ---------------------------------------------------------------- inventory */

static void info_str(cl_device_id d, cl_device_info what, char *out, size_t n) {
    out[0] = 0;
    if (clGetDeviceInfo(d, what, n - 1, out, NULL) != CL_SUCCESS) out[0] = 0;
    out[n - 1] = 0;
}

static void plat_str(cl_platform_id p, cl_platform_info what, char *out, size_t n) {
    out[0] = 0;
    if (clGetPlatformInfo(p, what, n - 1, out, NULL) != CL_SUCCESS) out[0] = 0;
    out[n - 1] = 0;
}

/* Whole-word search in a space-separated extension list. */
static int has_word(const char *list, const char *word) {
    size_t n = strlen(word);
    for (const char *p = list; (p = strstr(p, word)) != NULL; p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == 0 || p[n] == ' ')) return 1;
    return 0;
}

static int contains_ci(const char *s, const char *word) {
    size_t n = strlen(word);
    for (; *s; s++)
        if (strncasecmp(s, word, n) == 0) return 1;
    return 0;
}

static void fill_device(sl_cl_devinfo *d, cl_device_id id, const sl_cl_platinfo *p) {
    d->device = id;
    d->platform = p->platform;
    d->is_pocl = p->is_pocl;
    info_str(id, CL_DEVICE_NAME, d->name, sizeof d->name);
    info_str(id, CL_DEVICE_VENDOR, d->vendor, sizeof d->vendor);
    info_str(id, CL_DEVICE_VERSION, d->version, sizeof d->version);
    info_str(id, CL_DRIVER_VERSION, d->driver_version, sizeof d->driver_version);
    info_str(id, CL_DEVICE_OPENCL_C_VERSION, d->opencl_c_version, sizeof d->opencl_c_version);
    if (clGetDeviceInfo(id, CL_DEVICE_TYPE, sizeof d->type, &d->type, NULL)) d->type = 0;
    if (clGetDeviceInfo(id, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof(cl_uint), &d->compute_units, NULL))
        d->compute_units = 0;
    if (clGetDeviceInfo(id, CL_DEVICE_MAX_CLOCK_FREQUENCY, sizeof(cl_uint), &d->max_clock_mhz,
                        NULL))
        d->max_clock_mhz = 0;
    if (clGetDeviceInfo(id, CL_DEVICE_GLOBAL_MEM_SIZE, sizeof(cl_ulong), &d->global_mem, NULL))
        d->global_mem = 0;
    if (clGetDeviceInfo(id, CL_DEVICE_LOCAL_MEM_SIZE, sizeof(cl_ulong), &d->local_mem, NULL))
        d->local_mem = 0;
    if (clGetDeviceInfo(id, CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof(cl_ulong), &d->max_alloc, NULL))
        d->max_alloc = 0;
    if (clGetDeviceInfo(id, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof(size_t), &d->max_work_group,
                        NULL))
        d->max_work_group = 1;
    cl_bool img = CL_FALSE;
    if (clGetDeviceInfo(id, CL_DEVICE_IMAGE_SUPPORT, sizeof img, &img, NULL)) img = CL_FALSE;
    d->images = img == CL_TRUE;
    size_t n = 0;
    if (clGetDeviceInfo(id, CL_DEVICE_EXTENSIONS, 0, NULL, &n) == CL_SUCCESS && n > 0) {
        char *ext = sl_calloc(n + 1, 1);
        if (clGetDeviceInfo(id, CL_DEVICE_EXTENSIONS, n, ext, NULL) == CL_SUCCESS) {
            d->fp64 = has_word(ext, "cl_khr_fp64");
            d->gl_sharing = has_word(ext, "cl_khr_gl_sharing");
        }
        free(ext);
    }
}

void sl_cl_inventory_get(sl_cl_inventory *inv) {
    memset(inv, 0, sizeof *inv);
    cl_uint np = 0;
    inv->platform_err = clGetPlatformIDs(0, NULL, &np);
    if (inv->platform_err != CL_SUCCESS || np == 0) return;
    cl_platform_id *ids = sl_calloc(np, sizeof *ids);
    inv->platform_err = clGetPlatformIDs(np, ids, NULL);
    if (inv->platform_err != CL_SUCCESS) {
        free(ids);
        return;
    }
    inv->platforms = sl_calloc(np, sizeof *inv->platforms);
    inv->num_platforms = (int)np;
    for (cl_uint i = 0; i < np; i++) {
        sl_cl_platinfo *p = &inv->platforms[i];
        p->platform = ids[i];
        plat_str(ids[i], CL_PLATFORM_NAME, p->name, sizeof p->name);
        plat_str(ids[i], CL_PLATFORM_VENDOR, p->vendor, sizeof p->vendor);
        plat_str(ids[i], CL_PLATFORM_VERSION, p->version, sizeof p->version);
        p->is_pocl =
            contains_ci(p->name, "Portable Computing Language") || contains_ci(p->version, "pocl");
        cl_uint nd = 0;
        p->device_err = clGetDeviceIDs(ids[i], CL_DEVICE_TYPE_ALL, 0, NULL, &nd);
        if (p->device_err != CL_SUCCESS || nd == 0) continue; /* rusticl/clover: 0 devices */
        cl_device_id *dids = sl_calloc(nd, sizeof *dids);
        p->device_err = clGetDeviceIDs(ids[i], CL_DEVICE_TYPE_ALL, nd, dids, NULL);
        if (p->device_err == CL_SUCCESS) {
            inv->devices = sl_realloc(inv->devices,
                                      (size_t)(inv->num_devices + (int)nd) * sizeof *inv->devices);
            for (cl_uint j = 0; j < nd; j++) {
                sl_cl_devinfo *d = &inv->devices[inv->num_devices];
                memset(d, 0, sizeof *d);
                d->platform_index = (int)i;
                d->device_index = (int)j;
                d->global_index = inv->num_devices;
                fill_device(d, dids[j], p);
                inv->num_devices++;
            }
            p->num_devices = (int)nd;
        }
        free(dids);
    }
    free(ids);
}

void sl_cl_inventory_free(sl_cl_inventory *inv) {
    free(inv->platforms);
    free(inv->devices);
    memset(inv, 0, sizeof *inv);
}

const char *sl_cl_type_name(cl_device_type type) {
    if (type & CL_DEVICE_TYPE_GPU) return "GPU";
    if (type & CL_DEVICE_TYPE_CPU) return "CPU";
    if (type & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
    if (type & CL_DEVICE_TYPE_CUSTOM) return "custom";
    return "unknown";
}

void sl_cl_device_label(const sl_cl_devinfo *d, char *out, size_t out_size) {
    snprintf(out, out_size, "%s%s (%s)", d->is_pocl ? "PoCL " : "", sl_cl_type_name(d->type),
             d->name);
}

/* Why there is no OpenCL device at all, for messages. */
static void no_platform_reason(const sl_cl_inventory *inv, char *out, size_t n) {
    if (inv->platform_err != CL_SUCCESS)
        snprintf(out, n, "no OpenCL platforms: clGetPlatformIDs returned %s (%d)%s",
                 sl_cl_strerror(inv->platform_err), (int)inv->platform_err,
                 inv->platform_err == -1001
                     ? ", no OpenCL driver (ICD) is installed or OCL_ICD_VENDORS points nowhere"
                     : "");
    else if (inv->num_platforms == 0)
        snprintf(out, n, "no OpenCL platforms");
    else
        snprintf(out, n, "no OpenCL devices on %d platform%s", inv->num_platforms,
                 inv->num_platforms == 1 ? "" : "s");
}

static int first_of(const sl_cl_inventory *inv, cl_device_type type, int need_pocl) {
    for (int i = 0; i < inv->num_devices; i++)
        if ((inv->devices[i].type & type) && (!need_pocl || inv->devices[i].is_pocl)) return i;
    return -1;
}

int sl_cl_inventory_auto(const sl_cl_inventory *inv, char *why, size_t why_size) {
    int i = first_of(inv, CL_DEVICE_TYPE_GPU, 0);
    if (i >= 0) {
        snprintf(why, why_size, "first GPU OpenCL device");
        return i;
    }
    if ((i = first_of(inv, CL_DEVICE_TYPE_CPU, 1)) >= 0) {
        snprintf(why, why_size, "no GPU OpenCL device found");
        return i;
    }
    if ((i = first_of(inv, CL_DEVICE_TYPE_CPU, 0)) >= 0) {
        snprintf(why, why_size, "no GPU or PoCL OpenCL device found");
        return i;
    }
    if (inv->num_devices == 0)
        no_platform_reason(inv, why, why_size);
    else
        snprintf(why, why_size, "no GPU or CPU OpenCL device found");
    return -1;
}

/* ---------------------------------------------------------------- sl_cl */

static void cl_destroy(sl_cl *cl) {
    if (!cl) return;
    for (int i = 0; i < cl->num_kerns; i++) {
        clReleaseKernel(cl->kerns[i].kernel);
        free(cl->kerns[i].name);
    }
    for (int i = 0; i < cl->num_progs; i++) {
        if (cl->progs[i].prog) clReleaseProgram(cl->progs[i].prog);
        free(cl->progs[i].file);
        free(cl->progs[i].options);
    }
    free(cl->kerns);
    free(cl->progs);
    if (cl->queue) clReleaseCommandQueue(cl->queue);
    if (cl->ctx) clReleaseContext(cl->ctx);
    free(cl);
}

static int cl_create(const sl_cl_devinfo *d, const sl_cl_inventory *inv, sl_cl **out, sl_err *e) {
    char label[512];
    sl_cl_device_label(d, label, sizeof label);
    sl_cl *cl = sl_calloc(1, sizeof *cl);
    cl->platform = d->platform;
    cl->device = d->device;
    cl->is_gpu = (d->type & CL_DEVICE_TYPE_GPU) != 0;
    cl->fp64 = d->fp64;
    cl->max_wg = d->max_work_group;
    cl->max_alloc = d->max_alloc;
    snprintf(cl->device_name, sizeof cl->device_name, "%s", d->name);
    snprintf(cl->driver_version, sizeof cl->driver_version, "%s", d->driver_version);
    const sl_cl_platinfo *p = &inv->platforms[d->platform_index];
    snprintf(cl->platform_name, sizeof cl->platform_name, "%s", p->name);
    snprintf(cl->platform_version, sizeof cl->platform_version, "%s", p->version);

    cl_int err;
    cl_context_properties props[] = {CL_CONTEXT_PLATFORM, (cl_context_properties)d->platform, 0};
    cl->ctx = clCreateContext(props, 1, &d->device, NULL, NULL, &err);
    if (err != CL_SUCCESS) {
        cl->ctx = NULL;
        cl_destroy(cl);
        char what[600];
        snprintf(what, sizeof what, "%s: clCreateContext", label);
        return sl_cl_check(err, what, e);
    }
    cl->queue = clCreateCommandQueue(cl->ctx, d->device, CL_QUEUE_PROFILING_ENABLE, &err);
    cl->profiling = err == CL_SUCCESS;
    if (err != CL_SUCCESS) cl->queue = clCreateCommandQueue(cl->ctx, d->device, 0, &err);
    if (err != CL_SUCCESS) {
        cl->queue = NULL;
        cl_destroy(cl);
        char what[600];
        snprintf(what, sizeof what, "%s: clCreateCommandQueue", label);
        return sl_cl_check(err, what, e);
    }
    sl_err ke;
    if (sl_kernel_dir_find(cl->kernel_dir, sizeof cl->kernel_dir, &ke)) {
        cl->kernel_dir[0] = 0;
        copy_str(cl->kernel_dir_err, sizeof cl->kernel_dir_err, ke.msg);
    }
    if (!sl_cache_dir_find(cl->cache_dir, sizeof cl->cache_dir)) cl->cache_dir[0] = 0;
    cl->fault = sl_cl_fault() == SL_CL_FAULT_BUILD;
    *out = cl;
    return 0;
}

/* ---------------------------------------------------------------- sl_device */

static void set_c_path(sl_device *dev) {
    dev->is_opencl = 0;
    dev->cl = NULL;
    snprintf(dev->name, sizeof dev->name, "C path");
}

/* Lists the devices there are (for "not available" messages). */
static void describe_devices(const sl_cl_inventory *inv, char *out, size_t n) {
    if (inv->num_devices == 0) {
        no_platform_reason(inv, out, n);
        return;
    }
    size_t used = (size_t)snprintf(out, n, "available:");
    for (int i = 0; i < inv->num_devices && used < n; i++) {
        char label[512];
        sl_cl_device_label(&inv->devices[i], label, sizeof label);
        used +=
            (size_t)snprintf(out + used, n - used, "%s %d:%d %s", i ? "," : "",
                             inv->devices[i].platform_index, inv->devices[i].device_index, label);
    }
}

static int parse_index(const char *s, long *v) {
    char *end;
    if (*s < '0' || *s > '9') return 0;
    *v = strtol(s, &end, 10);
    return *end == 0 && *v < 1000000;
}

int sl_device_open(const char *spec, sl_device *dev, sl_err *e) {
    memset(dev, 0, sizeof *dev);
    set_c_path(dev);
    if (!spec || !*spec) spec = "auto";
    enum { AUTO, GPU, POCL, OPENCL, INDEX } kind;
    long pi = -1, di = -1;
    const char *colon = strchr(spec, ':');
    if (strcmp(spec, "c") == 0) return 0;
    if (strcmp(spec, "auto") == 0)
        kind = AUTO;
    else if (strcmp(spec, "gpu") == 0)
        kind = GPU;
    else if (strcmp(spec, "pocl") == 0)
        kind = POCL;
    else if (strcmp(spec, "opencl") == 0)
        kind = OPENCL;
    else if (colon) {
        char head[32];
        if ((size_t)(colon - spec) >= sizeof head) goto bad;
        memcpy(head, spec, (size_t)(colon - spec));
        head[colon - spec] = 0;
        if (!parse_index(head, &pi) || !parse_index(colon + 1, &di)) goto bad;
        kind = INDEX;
    } else if (parse_index(spec, &di))
        kind = INDEX;
    else
        goto bad;

    sl_cl_inventory inv;
    sl_cl_inventory_get(&inv);
    char why[1024], avail[2048];
    int pick = -1;
    describe_devices(&inv, avail, sizeof avail);
    switch (kind) {
    case AUTO:
        pick = sl_cl_inventory_auto(&inv, why, sizeof why);
        break;
    case GPU:
        pick = first_of(&inv, CL_DEVICE_TYPE_GPU, 0);
        if (pick < 0) sl_fail(e, "--device gpu: no GPU OpenCL device (%s)", avail);
        break;
    case POCL:
        pick = first_of(&inv, CL_DEVICE_TYPE_CPU, 1);
        if (pick < 0) pick = first_of(&inv, CL_DEVICE_TYPE_ALL, 1);
        if (pick < 0) sl_fail(e, "--device pocl: no PoCL OpenCL device (%s)", avail);
        break;
    case OPENCL:
        pick = first_of(&inv, CL_DEVICE_TYPE_GPU, 0);
        if (pick < 0) pick = first_of(&inv, CL_DEVICE_TYPE_ALL, 0);
        if (pick < 0) sl_fail(e, "--device opencl: no OpenCL device (%s)", avail);
        break;
    case INDEX:
        for (int i = 0; i < inv.num_devices; i++) {
            const sl_cl_devinfo *d = &inv.devices[i];
            if (pi >= 0 ? (d->platform_index == pi && d->device_index == di)
                        : d->global_index == di)
                pick = i;
        }
        if (pick < 0) sl_fail(e, "--device %s: no such OpenCL device (%s)", spec, avail);
        break;
    }
    if (pick < 0 && kind != AUTO) {
        sl_cl_inventory_free(&inv);
        return -1;
    }
    if (pick < 0) {
        sl_note("device: C path (%s)", why);
        sl_cl_inventory_free(&inv);
        return 0;
    }
    sl_cl *cl = NULL;
    const sl_cl_devinfo *d = &inv.devices[pick];
    char label[512];
    sl_cl_device_label(d, label, sizeof label);
    if (cl_create(d, &inv, &cl, e)) {
        sl_cl_inventory_free(&inv);
        if (kind != AUTO) return -1;
        sl_warn("%s; falling back to the C path", e ? e->msg : "cannot open the OpenCL device");
        return 0;
    }
    cl->auto_chosen = kind == AUTO;
    if (kind == AUTO)
        sl_note("device: %s%s '%s' (%s)", d->is_pocl ? "PoCL " : "", sl_cl_type_name(d->type),
                d->name, why);
    dev->is_opencl = 1;
    dev->cl = cl;
    dev->auto_chosen = kind == AUTO;
    copy_str(dev->name, sizeof dev->name, label);
    sl_cl_inventory_free(&inv);
    return 0;

bad:
    return sl_fail(e, "--device '%s': expected auto, gpu, pocl, opencl, c, P:D or N", spec);
}

void sl_device_close(sl_device *dev) {
    if (!dev) return;
    if (dev->cl) {
        clFinish(dev->cl->queue);
        cl_destroy(dev->cl);
    }
    set_c_path(dev);
}

int sl_device_may_fallback(const sl_device *dev) {
    return dev && dev->is_opencl && dev->cl && dev->auto_chosen && dev->cl->auto_chosen;
}

void sl_device_fallback_to_c(sl_device *dev, const char *why) {
    sl_warn("%s; falling back to the C path", why && *why ? why : "OpenCL failed");
    sl_device_close(dev);
}

/* A run-time failure of the device itself (sl_cl_check's "NAME (code)"), as opposed to a bad
 * argument: out of resources or memory at enqueue, a device gone (NVIDIA reports a lost device
 * as CL_OUT_OF_RESOURCES, others as CL_DEVICE_NOT_AVAILABLE). */
static int is_device_failure(const char *msg) {
    static const char *const codes[] = {"CL_DEVICE_NOT_AVAILABLE (-2)",
                                        "CL_MEM_OBJECT_ALLOCATION_FAILURE (-4)",
                                        "CL_OUT_OF_RESOURCES (-5)", "CL_OUT_OF_HOST_MEMORY (-6)"};
    for (size_t i = 0; msg && i < sizeof codes / sizeof codes[0]; i++)
        if (strstr(msg, codes[i])) return 1;
    return 0;
}

int sl_device_try_fallback(sl_device *dev, int rc, const sl_err *e) {
    int device_failed = rc == -1 && e && is_device_failure(e->msg);
    if ((rc != SL_CL_EKERNEL && !device_failed) || !sl_device_may_fallback(dev)) return 0;
    sl_device_fallback_to_c(dev, e ? e->msg : NULL);
    return 1;
}

/* ---------------------------------------------------------------- kernels */

int sl_cl_get_kernel(sl_cl *cl, const char *cl_file, const char *kernel_name,
                     const char *extra_options, cl_kernel *kernel, sl_err *e) {
    *kernel = NULL;
    if (!cl || !cl_file || !kernel_name) return sl_fail(e, "sl_cl_get_kernel: missing argument");
    const char *opts = extra_options ? extra_options : "";
    int pi = -1;
    for (int i = 0; i < cl->num_progs; i++)
        if (strcmp(cl->progs[i].file, cl_file) == 0 && strcmp(cl->progs[i].options, opts) == 0)
            pi = i;
    if (pi < 0) {
        cl->progs = sl_realloc(cl->progs, (size_t)(cl->num_progs + 1) * sizeof *cl->progs);
        sl_cl_prog *p = &cl->progs[cl->num_progs];
        memset(p, 0, sizeof *p);
        p->file = sl_strdup(cl_file);
        p->options = sl_strdup(opts);
        pi = cl->num_progs++;
        sl_err be = {{0}};
        if (!cl->kernel_dir[0]) {
            snprintf(p->err, sizeof p->err, "%.200s: %.800s", cl_file, cl->kernel_dir_err);
        } else if (cl->fault) {
            snprintf(p->err, sizeof p->err,
                     "%.200s: OpenCL build failed on '%.200s': CL_BUILD_PROGRAM_FAILURE (-11) "
                     "(simulated: SL_CL_FAULT=build)",
                     cl_file, cl->device_name);
        } else {
            sl_cl_build_target t = {
                cl->ctx,           cl->device,           cl->device_name, cl->driver_version,
                cl->platform_name, cl->platform_version, cl->kernel_dir,  cl->cache_dir};
            int from_cache = 0;
            double t0 = sl_now();
            int rc = sl_cl_build_program(&t, cl_file, opts, &p->prog, &from_cache, &be);
            cl->build_s += sl_now() - t0;
            if (rc == 0) {
                if (from_cache)
                    cl->built_from_cache++;
                else
                    cl->built_from_source++;
            } else {
                p->prog = NULL;
                copy_str(p->err, sizeof p->err, be.msg);
                if (rc == -1) { /* not a kernel problem (out of memory, ...): retry next time */
                    free(p->file);
                    free(p->options);
                    cl->num_progs--;
                    return sl_fail(e, "%s", be.msg);
                }
            }
        }
    }
    sl_cl_prog *p = &cl->progs[pi];
    if (!p->prog) {
        sl_fail(e, "%s", p->err);
        return SL_CL_EKERNEL;
    }
    for (int i = 0; i < cl->num_kerns; i++)
        if (cl->kerns[i].prog == pi && strcmp(cl->kerns[i].name, kernel_name) == 0) {
            *kernel = cl->kerns[i].kernel;
            return 0;
        }
    cl_int err;
    cl_kernel k = clCreateKernel(p->prog, kernel_name, &err);
    if (err != CL_SUCCESS) {
        char what[512];
        snprintf(what, sizeof what, "%s: kernel '%s': clCreateKernel", cl_file, kernel_name);
        sl_cl_check(err, what, e);
        return err == CL_INVALID_KERNEL_NAME ? SL_CL_EKERNEL : -1;
    }
    cl->kerns = sl_realloc(cl->kerns, (size_t)(cl->num_kerns + 1) * sizeof *cl->kerns);
    cl->kerns[cl->num_kerns].prog = pi;
    cl->kerns[cl->num_kerns].name = sl_strdup(kernel_name);
    cl->kerns[cl->num_kerns].kernel = k;
    cl->num_kerns++;
    *kernel = k;
    return 0;
}

cl_context sl_cl_context(sl_cl *cl) {
    return cl ? cl->ctx : NULL;
}
cl_command_queue sl_cl_queue(sl_cl *cl) {
    return cl ? cl->queue : NULL;
}
cl_device_id sl_cl_device_id(sl_cl *cl) {
    return cl ? cl->device : NULL;
}
const char *sl_cl_device_name(const sl_cl *cl) {
    return cl ? cl->device_name : "";
}
void sl_cl_identity(const sl_cl *cl, char *out, size_t out_size) {
    if (!cl) {
        snprintf(out, out_size, "C path");
        return;
    }
    snprintf(out, out_size, "%s|%s|%s|%s", cl->platform_name, cl->platform_version, cl->device_name,
             cl->driver_version);
}
int sl_cl_is_gpu(const sl_cl *cl) {
    return cl && cl->is_gpu;
}
int sl_cl_has_fp64(const sl_cl *cl) {
    return cl && cl->fp64;
}
size_t sl_cl_max_work_group_size(const sl_cl *cl) {
    return cl ? cl->max_wg : 1;
}
cl_ulong sl_cl_max_alloc(const sl_cl *cl) {
    return cl ? cl->max_alloc : 0;
}
int sl_cl_profiling(const sl_cl *cl) {
    return cl && cl->profiling;
}
const char *sl_cl_kernel_dir(const sl_cl *cl) {
    return cl ? cl->kernel_dir : "";
}

void sl_cl_build_stats(const sl_cl *cl, int *from_source, int *from_cache, double *build_s) {
    if (from_source) *from_source = cl ? cl->built_from_source : 0;
    if (from_cache) *from_cache = cl ? cl->built_from_cache : 0;
    if (build_s) *build_s = cl ? cl->build_s : 0;
}

/* ---------------------------------------------------------------- timing */

double sl_cl_event_seconds(cl_event ev) {
    cl_ulong t0 = 0, t1 = 0;
    if (!ev) return -1;
    if (clGetEventProfilingInfo(ev, CL_PROFILING_COMMAND_START, sizeof t0, &t0, NULL) !=
            CL_SUCCESS ||
        clGetEventProfilingInfo(ev, CL_PROFILING_COMMAND_END, sizeof t1, &t1, NULL) != CL_SUCCESS)
        return -1;
    /* llvmpipe (rusticl) reports zero timestamps: treat as unavailable (toolchain.md sec. 2). */
    if (t1 < t0 || (t0 == 0 && t1 == 0)) return -1;
    return 1e-9 * (double)(t1 - t0);
}

void sl_cl_timer_start(sl_cl_timer *t, sl_cl *cl) {
    memset(t, 0, sizeof *t);
    t->cl = cl;
    t->wall_start = sl_now();
}

void sl_cl_timer_add(sl_cl_timer *t, cl_event ev) {
    if (!ev) return;
    if (t->num_events == t->cap_events) {
        t->cap_events = t->cap_events ? 2 * t->cap_events : 16;
        t->events = sl_realloc(t->events, (size_t)t->cap_events * sizeof *t->events);
    }
    t->events[t->num_events++] = ev;
}

double sl_cl_timer_stop(sl_cl_timer *t, int *is_device) {
    if (t->cl) clFinish(t->cl->queue);
    double wall = sl_now() - t->wall_start, dev = 0;
    int ok = t->cl && t->cl->profiling && t->num_events > 0;
    for (int i = 0; i < t->num_events; i++) {
        double s = ok ? sl_cl_event_seconds(t->events[i]) : -1;
        if (s < 0) ok = 0;
        dev += s;
        clReleaseEvent(t->events[i]);
    }
    free(t->events);
    t->events = NULL;
    t->num_events = t->cap_events = 0;
    if (is_device) *is_device = ok;
    return ok ? dev : wall;
}

/* ---------------------------------------------------------------- fault injection (tests) */

int sl_cl_fault(void) {
    const char *v = getenv("SL_CL_FAULT");
    if (!v || !*v) return SL_CL_FAULT_NONE;
    if (strcmp(v, "build") == 0) return SL_CL_FAULT_BUILD;
    if (strcmp(v, "enqueue") == 0) return SL_CL_FAULT_ENQUEUE;
    if (strcmp(v, "lost") == 0) return SL_CL_FAULT_LOST;
    return SL_CL_FAULT_NONE;
}

/* The enqueue and lost faults interpose the OpenCL entry points the drivers call (this
 * definition in the executable wins over libOpenCL's; the real one is found with RTLD_NEXT), so
 * no driver needs to know about them. Without SL_CL_FAULT they only forward (and count the
 * kernel enqueues). Process-wide state (tests only): the number of kernel enqueues seen in "lost"
 * mode, and the successful kernel enqueues. */
static atomic_int lost_enqueues;
static atomic_ulong kernels_enqueued; /* successful kernel enqueues (sl_cl_kernels_enqueued) */

unsigned long sl_cl_kernels_enqueued(void) { return atomic_load(&kernels_enqueued); }

typedef cl_int (*ndrange_fn)(cl_command_queue, cl_kernel, cl_uint, const size_t *, const size_t *,
                             const size_t *, cl_uint, const cl_event *, cl_event *);
typedef cl_int (*read_fn)(cl_command_queue, cl_mem, cl_bool, size_t, size_t, void *, cl_uint,
                          const cl_event *, cl_event *);

/* The fault for this call, or CL_SUCCESS. `kernel` counts toward "lost" (the first kernel
 * enqueue succeeds: the device disappears mid-run, after work was queued). */
static cl_int injected(int kernel) {
    switch (sl_cl_fault()) {
    case SL_CL_FAULT_ENQUEUE:
        return kernel ? CL_OUT_OF_RESOURCES : CL_SUCCESS;
    case SL_CL_FAULT_LOST:
        if (kernel && atomic_fetch_add(&lost_enqueues, 1) == 0) return CL_SUCCESS;
        return atomic_load(&lost_enqueues) > 0 ? CL_DEVICE_NOT_AVAILABLE : CL_SUCCESS;
    default:
        return CL_SUCCESS;
    }
}

CL_API_ENTRY cl_int CL_API_CALL clEnqueueNDRangeKernel(cl_command_queue q, cl_kernel k, cl_uint dim,
                                                       const size_t *offset, const size_t *global,
                                                       const size_t *local, cl_uint nwait,
                                                       const cl_event *wait, cl_event *ev) {
    cl_int f = injected(1);
    if (f != CL_SUCCESS) return f;
    ndrange_fn real = (ndrange_fn)dlsym(RTLD_NEXT, "clEnqueueNDRangeKernel");
    if (!real) return CL_INVALID_OPERATION;
    cl_int err = real(q, k, dim, offset, global, local, nwait, wait, ev);
    if (err == CL_SUCCESS) atomic_fetch_add(&kernels_enqueued, 1);
    return err;
}

CL_API_ENTRY cl_int CL_API_CALL clEnqueueReadBuffer(cl_command_queue q, cl_mem buf,
                                                    cl_bool blocking, size_t offset, size_t size,
                                                    void *ptr, cl_uint nwait, const cl_event *wait,
                                                    cl_event *ev) {
    cl_int f = injected(0);
    if (f != CL_SUCCESS) return f;
    read_fn real = (read_fn)dlsym(RTLD_NEXT, "clEnqueueReadBuffer");
    if (!real) return CL_INVALID_OPERATION;
    return real(q, buf, blocking, offset, size, ptr, nwait, wait, ev);
}

size_t sl_cl_round_up(size_t x, size_t m) { return (x + m - 1) / m * m; }

int sl_cl_run1d(sl_cl *cl, cl_kernel k, const char *name, size_t n, size_t local,
                sl_cl_timer *timer, sl_err *e) {
    size_t global = sl_cl_round_up(n ? n : 1, local);
    cl_event ev = NULL;
    if (sl_cl_check(clEnqueueNDRangeKernel(sl_cl_queue(cl), k, 1, NULL, &global, &local, 0, NULL,
                                           timer ? &ev : NULL),
                    name, e))
        return -1;
    if (timer) sl_cl_timer_add(timer, ev);
    return 0;
}
