/* fiber_eval.h: the quantities of `strandlight eval` (numerics.md sec. 5) and their dispatch to
 * the math entry points of each backend: the double reference (slref_*, per row), the C twin
 * (slc_*_batch, float) and the OpenCL kernels (slcl_*_batch, float).
 *
 *   sl_eval_quantity q; sl_eval_quantity_from_name("scatter", &q);
 *   const sl_eval_input *in; size_t nin = sl_eval_inputs(q, &in);      (column names + ranges)
 *   size_t nout = sl_eval_num_outputs(q, &m);                           (per colour channel)
 *   for ch < sl_eval_num_channels(q, &m):
 *       sl_eval_run(q, backend, cl, &m, ch, nrows, in_rows, out_rows, &e);
 *
 * Inputs and outputs are row-major doubles; the float backends round inputs to float (angles
 * to the nearest float inside their range) and their float results come back widened. */
#ifndef SL_FIBER_EVAL_H
#define SL_FIBER_EVAL_H

#include "base/common.h"
#include "scene/material.h"

typedef struct sl_cl sl_cl; /* host/cl/clrt.h */

typedef enum sl_eval_quantity {
    SL_EVAL_SCATTER = 0,
    SL_EVAL_SRBF,
    SL_EVAL_DEON_MP,
    SL_EVAL_FURNACE,
    SL_EVAL_TRANSMITTANCE,
    SL_EVAL_FORWARD_TRANSMITTANCE,
    SL_EVAL_MS_MATERIAL,
    SL_EVAL_NUM_QUANTITIES
} sl_eval_quantity;

typedef enum sl_eval_backend {
    SL_EVAL_REFERENCE = 0, /* double, adaptive quadrature */
    SL_EVAL_C,             /* the C twin, float */
    SL_EVAL_OPENCL         /* the OpenCL kernels, float */
} sl_eval_backend;

/* Allowed range of an input column (numerics.md sec. 1 and 5). */
typedef enum sl_eval_range {
    SL_RANGE_THETA,    /* [-pi/2, pi/2] */
    SL_RANGE_PHI,      /* (-pi, pi]; -pi itself is accepted (the same direction as pi) */
    SL_RANGE_POSITIVE, /* > 0 (v, lambda) */
    SL_RANGE_ANY,      /* any finite number (x, y, z) */
    SL_RANGE_INDEX     /* an integer >= 0 (lobe) */
} sl_eval_range;

/* Angles at most this far (radians) outside their closed range are clamped onto it instead of
 * rejected, so that a bound printed with 7 or more significant digits (pi as 3.141593, pi/2 as
 * 1.570796327) is still accepted; anything further out is an error. */
#define SL_EVAL_ANGLE_SLACK 1e-6

typedef struct sl_eval_input {
    const char *name;
    sl_eval_range range;
} sl_eval_input;

/* Name <-> enum; from_name returns -1 for an unknown name. */
int sl_eval_quantity_from_name(const char *name, sl_eval_quantity *q);
const char *sl_eval_quantity_name(sl_eval_quantity q);
/* 0 for the quantities that are recognised but not implemented yet. */
int sl_eval_quantity_implemented(sl_eval_quantity q);
/* 1 when q depends on a material (all but deon-mp), 2 when it needs a scene (transmittance). */
int sl_eval_quantity_uses_material(sl_eval_quantity q);
int sl_eval_quantity_needs_scene(sl_eval_quantity q);
int sl_eval_backend_from_name(const char *name, sl_eval_backend *b);
const char *sl_eval_backend_name(sl_eval_backend b);

/* The input columns of q, in the order sl_eval_run reads them from each row. */
size_t sl_eval_inputs(sl_eval_quantity q, const sl_eval_input **inputs);
/* Checks *v against range (clamping within SL_EVAL_ANGLE_SLACK); NULL when fine, else the
 * problem, e.g. "must be in [-pi/2, pi/2]". */
const char *sl_eval_check_input(sl_eval_range range, double *v);

/* Output columns per channel (scatter: 4 for marschner, orders + 3 for deon). */
size_t sl_eval_num_outputs(sl_eval_quantity q, const sl_material *m);
/* Colour channels evaluated: 3 when q uses the material and its sigma_a is [r,g,b]. */
int sl_eval_num_channels(sl_eval_quantity q, const sl_material *m);
/* Name of output column k of channel ch, with the _r/_g/_b suffix when there are 3 channels. */
void sl_eval_output_name(sl_eval_quantity q, const sl_material *m, int ch, size_t k, char *out,
                         size_t n);
/* printf format for the backend's results: "%.17g" (reference, round-trips a double) or
 * "%.9g" (float backends: round-trips a float, so nothing is lost). */
const char *sl_eval_format(sl_eval_backend b);

/* Limits of a backend for this material: the float backends allow orders <= SL_DEON_MAX_ORDERS.
 * where starts the message: "mat.json: orders" or "scene.json: material.orders". */
int sl_eval_check_backend(sl_eval_quantity q, sl_eval_backend b, const sl_material *m,
                          const char *where, sl_err *e);

/* Evaluates n rows of channel ch. in: n * nin values (validated), out: n * nout values.
 * cl is used (and required) only for SL_EVAL_OPENCL. */
int sl_eval_run(sl_eval_quantity q, sl_eval_backend b, sl_cl *cl, const sl_material *m, int ch,
                size_t n, const double *in, double *out, sl_err *e);

/* srbf's --method (numerics.md sec. 5; docs/srbf.md). SL_EVAL_METHOD_DEFAULT: exact on the
 * reference backend, fast on the others. */
typedef enum sl_eval_method {
    SL_EVAL_METHOD_DEFAULT = 0,
    SL_EVAL_METHOD_EXACT,
    SL_EVAL_METHOD_XU,
    SL_EVAL_METHOD_FAST,
    SL_EVAL_METHOD_TABLE /* Ren 2010's precomputed table (host/passes/shade/srbf_ren.h,
                            docs/srbf_ren.md) */
} sl_eval_method;
/* "exact", "xu", "fast", "table" <-> enum; from_name returns -1 for an unknown name. */
int sl_eval_method_from_name(const char *name, sl_eval_method *mt);
/* Whether backend b implements method mt for q (srbf: exact on reference only, xu and fast on
 * c and opencl); NULL when fine, else why not. Other quantities accept and ignore any method. */
const char *sl_eval_method_unsupported(sl_eval_quantity q, sl_eval_backend b, sl_eval_method mt);
/* sl_eval_run with an explicit method (sl_eval_run uses SL_EVAL_METHOD_DEFAULT). srbf_segments
 * is the piecewise-linear quadrature's m of the xu method (1..8; 0: the default 4). */
int sl_eval_run_method(sl_eval_quantity q, sl_eval_backend b, sl_eval_method mt, int srbf_segments,
                       sl_cl *cl, const sl_material *m, int ch, size_t n, const double *in,
                       double *out, sl_err *e);

/* What `eval` keeps between the chunks of one input (it streams its rows, docs/eval.md), so
 * nothing is loaded or built per chunk: srbf's tables and Ren's table of the material, got at
 * the first chunk that needs them. One session serves one material. */
typedef struct sl_eval_session sl_eval_session;
sl_eval_session *sl_eval_session_new(void);
void sl_eval_session_free(sl_eval_session *s); /* NULL is fine */
/* sl_eval_run_method within session s (the same rows give the same values either way). */
int sl_eval_run_session(sl_eval_session *s, sl_eval_quantity q, sl_eval_backend b,
                        sl_eval_method mt, int srbf_segments, sl_cl *cl, const sl_material *m,
                        int ch, size_t n, const double *in, double *out, sl_err *e);

#endif
