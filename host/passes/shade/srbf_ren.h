/* srbf_ren.h: Ren 2010 Sec. 4's precomputed SRBF convolution table, the renderer's second fast
 * path for SRBF lights (docs/srbf_ren.md): for one fixed material the single-scattering response
 * I_t(omega_o; omega_j, lambda) (numerics.md sec. 4) is baked from the `fast` closed form
 * (kernels/srbf_fast.h) over (h, t, dphi, lambda) in the fiber frame, on the OpenCL device when
 * there is one, else on the C path (threads), with a progress bar, and cached on disk by a hash of
 * the material, the table parameters and the fast path's own tables. Lookups: C
 * (slc_srbf_ren_batch, cpu/srbf_ren_c.h) and OpenCL (slcl_srbf_ren_batch), 16-corner
 * quadrilinear per mode. Use it while the material is unchanged; while editing, use `fast`.
 *
 *   sl_srbf_ren t;
 *   if (sl_srbf_ren_get(dev, &material, NULL, &t, &e)) ...;      (NULL: default parameters)
 *   slc_srbf_ren_batch(&t, n, in, out);    in: 5 floats per row, out: 9 (R rgb, TT rgb, TRT rgb)
 *   if (!sl_srbf_ren_matches(&t, &material)) ... rebuild or use fast ...
 *   sl_srbf_ren_free(&t); */
#ifndef SL_SRBF_REN_HOST_H
#define SL_SRBF_REN_HOST_H

#include "cl/clrt.h"
#include "base/common.h"
#include "scene/material.h"
#include "srbf_ren_c.h"
#include "passes/shade/srbf_tables.h"

/* Floor of the logarithmic R block of models deon and chiang (normalised values, docs/srbf_ren.md).
 */
#define SL_SRBF_REN_R_EPS 1e-4f

/* Random points at which a freshly built table checks itself against the closed form. */
#define SL_SRBF_REN_CHECK_POINTS 4096

typedef struct sl_srbf_ren_params {
    int n_h, n_t, n_phi, n_lambda; /* nodes per axis (kernels/srbf_ren_lookup.h), each >= 2 */
    double lambda_min, lambda_max; /* log-spaced lambda range (clamped outside) */
    int threads;                   /* C build: 0 = every online CPU */
    int verbose;                   /* 1: a note with size, build time and error when built */
    const char *cache_dir;         /* NULL: sl_cache_dir_find(); "": no disk cache */
} sl_srbf_ren_params;

/* The defaults (docs/srbf_ren.md: chosen by measured error against size). */
void sl_srbf_ren_params_default(sl_srbf_ren_params *p);

/* Loads the table for material m from the disk cache, or builds it (dev: the OpenCL device when
 * dev && dev->is_opencl, falling back to C when dev may; else the C path) and caches it (temp +
 * rename; a corrupt, truncated or foreign cache file is rebuilt and replaced, never trusted).
 * p NULL: defaults. Every model: Marschner's table from `fast`, deon's and chiang's from the
 * d'Eon fast path (their three modes: I_0, I_1, and orders >= 2 with the rest term). Returns 0,
 * or -1 with e set (cache write problems are warnings). */
int sl_srbf_ren_get(sl_device *dev, const sl_material *m, const sl_srbf_ren_params *p,
                    sl_srbf_ren *t, sl_err *e);
void sl_srbf_ren_free(sl_srbf_ren *t);

/* 1 when a cache file for material m and parameters p (NULL: defaults) exists with the right
 * header and size (sl_srbf_ren_get would load it rather than build; it still verifies the data).
 * ft: the fast path's tables (part of the key), NULL to load them here. The frame planner's
 * "cached on disk" test (docs/frame.md). */
int sl_srbf_ren_cached(const sl_material *m, const sl_srbf_ren_params *p, const sl_srbf_tables *ft);
/* `fast` evaluations a build of the table for m costs (the planner weighs it against the rows a
 * sequence of frames would shade): Marschner nodes x rotations (4 when eccentric) x (1 + 2 x
 * channels); deon and chiang nodes x 3 (one RGB row per node and mode). */
double sl_srbf_ren_build_rows(const sl_material *m, const sl_srbf_ren_params *p);

/* Hash of every material field the response depends on; sl_srbf_ren_matches: 1 when t was built
 * for exactly this material (the frame planner's "material unchanged since the build"). */
uint64_t sl_srbf_ren_material_hash(const sl_material *m);
int sl_srbf_ren_matches(const sl_srbf_ren *t, const sl_material *m);

/* ---- OpenCL (srbf_ren_cl.c) ---- */

/* OpenCL twin of slc_srbf_ren_batch (kernels/srbf_ren.cl): uploads rows and table, one
 * work-item per row, blocking read. Returns 0, -1 (e set) or SL_CL_EKERNEL. */
int slcl_srbf_ren_batch(sl_cl *cl, const sl_srbf_ren *t, size_t n, const float *in, float *out,
                        sl_err *e);

/* The same on buffers already on the device (the frame keeps the table resident: upload t->T,
 * t->n_floats floats, once per material): enqueues the kernel on sl_cl_queue(cl), no wait.
 * in: 5 floats per row, out: 9. Returns 0, -1 or SL_CL_EKERNEL. */
int slcl_srbf_ren_enqueue(sl_cl *cl, const sl_srbf_ren_dims *d, cl_mem T, size_t n, cl_mem in,
                          cl_mem out, sl_err *e);

/* Lookups of n rows with t resident on the device: *table (NULL at first) gets t's upload and
 * keeps it for the next calls (table_what names its upload's errors); rows (in: 5 floats each)
 * and results (out: 9) travel per call, blocking read. Returns 0, -1 or SL_CL_EKERNEL. */
int slcl_srbf_ren_rows(sl_cl *cl, const sl_srbf_ren *t, cl_mem *table, const char *table_what,
                       size_t n, const float *in, float *out, sl_err *e);
/* Releases a table slcl_srbf_ren_rows uploaded (if any) and clears *table. */
void slcl_srbf_ren_table_release(cl_mem *table);

/* `eval srbf --method table` on a float backend (cl NULL: C): out gets 4 floats per row for
 * colour channel ch: I_R, I_TT, I_TRT, I (the columns of `eval srbf`). */
int sl_srbf_ren_eval(sl_cl *cl, const sl_srbf_ren *t, int ch, size_t n, const float *in, float *out,
                     sl_err *e);
/* The same keeping the table on the device between calls (eval's chunks): *table as for
 * slcl_srbf_ren_rows (NULL at first; the caller releases it with slcl_srbf_ren_table_release). */
int sl_srbf_ren_eval_keep(sl_cl *cl, const sl_srbf_ren *t, cl_mem *table, int ch, size_t n,
                          const float *in, float *out, sl_err *e);

#endif
