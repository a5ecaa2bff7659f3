/* kernel_checks.h: the registry of "OpenCL kernel vs its C twin" checks that `strandlight
 * kernels` runs. To add one: write `int slchk_NAME(sl_cl *cl, const sl_kernel_check_opts *o,
 * sl_kernel_check_result *r, sl_err *e)` in host/verify/checks/ (the <pass>_check.c of its
 * driver), declare it at the end of this header and add a line to the table in
 * host/verify/checks/kernel_checks.c (docs/opencl.md, "Adding a kernel pair"). Verification
 * lives here only: no pass driver includes this header. */
#ifndef SL_KERNEL_CHECKS_H
#define SL_KERNEL_CHECKS_H

#include "cl/clrt.h"

typedef struct sl_kernel_check_opts {
    long size;   /* problem size hint (check-specific meaning); 0: the check's default */
    int reps;    /* timed repetitions (the best one is reported); >= 1 */
    int extreme; /* 1: the check's extreme inputs (only checks with has_extreme read it) */
} sl_kernel_check_opts;

typedef struct sl_kernel_check_result {
    char problem[64];        /* what ran, e.g. "1031x517 image" */
    double max_abs, max_rel; /* kernel vs C twin, over all outputs */
    double tol_abs, tol_rel; /* an output passes when |diff| <= tol_abs or <= tol_rel * |C| */
    size_t compared, bad;    /* outputs compared, outputs outside the tolerance */
    double c_s;              /* best C twin time, seconds */
    double cl_s;             /* best kernel time (profiling events, else wall clock) */
    int cl_s_is_device;      /* cl_s came from profiling events */
    double cl_wall_s;        /* best wall time of the OpenCL call, transfers included */
    int pass;
    char note[256]; /* why the tolerance is what it is */
} sl_kernel_check_result;

/* Runs the check on cl and fills r (r->pass decides PASS/FAIL). Returns 0, or -1 / SL_CL_EKERNEL
 * when it could not run at all (e set). */
typedef int (*sl_kernel_check_fn)(sl_cl *cl, const sl_kernel_check_opts *o,
                                  sl_kernel_check_result *r, sl_err *e);

typedef struct sl_kernel_check {
    const char *name; /* as given to --only */
    const char *what; /* one line */
    sl_kernel_check_fn run;
    int has_extreme; /* the check generates its own extreme inputs when o->extreme is 1; the
                        others are covered by the sl_kernel_extreme sweep */
} sl_kernel_check;

/* The registered checks, in run order. */
const sl_kernel_check *sl_kernel_checks(size_t *count);
const sl_kernel_check *sl_kernel_check_find(const char *name);

/* Compares n kernel outputs against the C twin's with r->tol_abs / r->tol_rel already set: fills
 * max_abs, max_rel, compared, bad and pass (bad == 0). NaN matches NaN, inf matches the same inf.
 */
void sl_kernel_compare(const float *kernel_out, const float *c_out, size_t n,
                       sl_kernel_check_result *r);

/* Deterministic pseudo-random floats in [lo, hi) from a seed (xorshift64*), for check inputs. */
void sl_kernel_check_fill(float *x, size_t n, unsigned long long seed, float lo, float hi);

/* `strandlight kernels --extreme`: degenerate geometry (zero-length segments, coincident
 * strands, a hair collapsed to a point, far from the origin, one strand; lookups inside and far
 * outside the hair; 2-texel maps; sharp and broad lobes) and extreme materials at grazing
 * directions, on the C path and, when cl is non-NULL, on the OpenCL kernels. Prints one
 * "extreme ... PASS|FAIL" line per case to out; returns the number of failed cases (any NaN/Inf
 * output, T outside [0, 1], or an error). */
int sl_kernel_extreme(sl_cl *cl, FILE *out);

/* The checks (one per kernel pair). */
/* kernel_checks.c: prefix_sum.cl, work-group and serial variants. */
int slchk_prefix_sum(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                     sl_err *e);
int slchk_prefix_sum_serial(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                            sl_err *e);
/* shadow_check.c: raster.cl vs cpu/raster.c on procedural hair (bit-identical); the whole DODM
 * path (raster, tables, lookup) vs the C twin. */
int slchk_raster(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r, sl_err *e);
int slchk_dodm(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r, sl_err *e);
int slchk_dodm_behind(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                      sl_err *e);
/* volume_check.c (`strandlight kernels --only voxel|march|ms|dual`). */
int slchk_voxel(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r, sl_err *e);
int slchk_march(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r, sl_err *e);
int slchk_ms_response(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                      sl_err *e);
int slchk_dual_table(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                     sl_err *e);
/* srbf_check.c: srbf.cl vs the C twin (o->size: number of lobes, default 4096). */
int slchk_srbf(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r, sl_err *e);
/* srbf_deon_check.c: srbf_deon.cl (models deon and chiang, per-row and RGB kernels) vs the C
 * twin (o->size: lobes per material, default 1024; o->extreme: poles, lambda 0.005..10, extreme
 * materials). */
int slchk_srbf_deon(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r, sl_err *e);
/* fiber_check.c: fiber.cl's scatter and furnace for model chiang vs the C twin (o->size: scatter
 * rows per material, default 2048; o->extreme: extreme materials). */
int slchk_fiber_chiang(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                       sl_err *e);
/* view_check.c: the -DSL_KB_K build and the generic one against slc_kbuffer_build, bit-exact,
 * on typical or (o->extreme) extreme fragments. */
int slchk_kbuffer(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r, sl_err *e);
int slchk_kbuffer_generic(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                          sl_err *e);

#endif
