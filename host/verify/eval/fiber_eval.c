/* fiber_eval.c: the quantity table of `strandlight eval` and its dispatch to the reference
 * (double, one row at a time), the C twin and the OpenCL kernels (float batches); see
 * fiber_eval.h and numerics.md sec. 5. */
#include "verify/eval/fiber_eval.h"

#include "chiang_ref.h"
#include "deon_ref.h"
#include "dual_c.h"
#include "dual_material.h"
#include "passes/volume/dual_cl.h"
#include "dual_ref.h"
#include "fiber_c.h"
#include "passes/shade/fiber_cl.h"
#include "fiber_deon.h"
#include "furnace_ref.h"
#include "marschner_ref.h"
#include "srbf_ref.h"
#include "passes/shade/srbf_ren.h"
#include "passes/shade/srbf_tables.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

typedef struct qdesc {
    const char *name;
    int implemented;
    int uses_material;
    int needs_scene;
    size_t nin;
    sl_eval_input in[5];
} qdesc;

/* numerics.md sec. 5, in the order of sl_eval_quantity. */
static const qdesc quantities[SL_EVAL_NUM_QUANTITIES] = {
    {"scatter",
     1,
     1,
     0,
     4,
     {{"theta_i", SL_RANGE_THETA},
      {"phi_i", SL_RANGE_PHI},
      {"theta_o", SL_RANGE_THETA},
      {"phi_o", SL_RANGE_PHI}}},
    {"srbf",
     1,
     1,
     0,
     5,
     {{"theta_o", SL_RANGE_THETA},
      {"phi_o", SL_RANGE_PHI},
      {"theta_j", SL_RANGE_THETA},
      {"phi_j", SL_RANGE_PHI},
      {"lambda", SL_RANGE_POSITIVE}}},
    {"deon-mp",
     1,
     0,
     0,
     3,
     {{"v", SL_RANGE_POSITIVE}, {"theta_i", SL_RANGE_THETA}, {"theta_o", SL_RANGE_THETA}}},
    {"furnace", 1, 1, 0, 2, {{"theta_o", SL_RANGE_THETA}, {"phi_o", SL_RANGE_PHI}}},
    {"transmittance",
     1, /* evaluated by host/verify/eval/shadow_eval.c (needs the scene), not by sl_eval_run */
     0,
     1,
     4,
     {{"x", SL_RANGE_ANY}, {"y", SL_RANGE_ANY}, {"z", SL_RANGE_ANY}, {"lobe", SL_RANGE_INDEX}}},
    {"forward-transmittance",
     1, /* evaluated by host/verify/eval/volume_eval.c (needs the scene), not by sl_eval_run */
     1,
     1,
     4,
     {{"x", SL_RANGE_ANY}, {"y", SL_RANGE_ANY}, {"z", SL_RANGE_ANY}, {"lobe", SL_RANGE_INDEX}}},
    {"ms-material", 1, 1, 0, 1, {{"theta_d", SL_RANGE_THETA}}},
};

static const char *const backend_names[] = {"reference", "c", "opencl"};

int sl_eval_quantity_from_name(const char *name, sl_eval_quantity *q) {
    for (int i = 0; i < SL_EVAL_NUM_QUANTITIES; i++)
        if (strcmp(name, quantities[i].name) == 0) {
            *q = (sl_eval_quantity)i;
            return 0;
        }
    return -1;
}

const char *sl_eval_quantity_name(sl_eval_quantity q) {
    return quantities[q].name;
}
int sl_eval_quantity_implemented(sl_eval_quantity q) {
    return quantities[q].implemented;
}
int sl_eval_quantity_uses_material(sl_eval_quantity q) {
    return quantities[q].uses_material;
}
int sl_eval_quantity_needs_scene(sl_eval_quantity q) {
    return quantities[q].needs_scene;
}

int sl_eval_backend_from_name(const char *name, sl_eval_backend *b) {
    for (int i = 0; i < 3; i++)
        if (strcmp(name, backend_names[i]) == 0) {
            *b = (sl_eval_backend)i;
            return 0;
        }
    return -1;
}

const char *sl_eval_backend_name(sl_eval_backend b) {
    return backend_names[b];
}

size_t sl_eval_inputs(sl_eval_quantity q, const sl_eval_input **inputs) {
    *inputs = quantities[q].in;
    return quantities[q].nin;
}

/* Clamps *v onto [lo, hi] when it lies at most SL_EVAL_ANGLE_SLACK outside; 0 if further out. */
static int in_closed(double *v, double lo, double hi) {
    if (*v < lo - SL_EVAL_ANGLE_SLACK || *v > hi + SL_EVAL_ANGLE_SLACK) return 0;
    if (*v < lo) *v = lo;
    if (*v > hi) *v = hi;
    return 1;
}

const char *sl_eval_check_input(sl_eval_range range, double *v) {
    switch (range) {
    case SL_RANGE_THETA:
        return in_closed(v, -PI / 2, PI / 2) ? NULL : "must be in [-pi/2, pi/2]";
    case SL_RANGE_PHI:
        return in_closed(v, -PI, PI) ? NULL : "must be in (-pi, pi]";
    case SL_RANGE_POSITIVE:
        return *v > 0 ? NULL : "must be > 0";
    case SL_RANGE_INDEX:
        return *v >= 0 && *v == floor(*v) && *v < 2147483648.0 ? NULL : "must be an integer >= 0";
    case SL_RANGE_ANY:
        break;
    }
    return NULL;
}

size_t sl_eval_num_outputs(sl_eval_quantity q, const sl_material *m) {
    /* chiang has d'Eon's layout with orders = 2: f_0, f_1, f_2, f_rest, f */
    int deon = m && (m->model == SL_MODEL_DEON || m->model == SL_MODEL_CHIANG);
    switch (q) {
    case SL_EVAL_SCATTER:
    case SL_EVAL_SRBF:
        return deon ? (size_t)m->orders + 3 : 4;
    case SL_EVAL_DEON_MP:
        return 2;
    case SL_EVAL_FURNACE:
    case SL_EVAL_TRANSMITTANCE:
        return 1;
    case SL_EVAL_FORWARD_TRANSMITTANCE:
        return 2;
    case SL_EVAL_MS_MATERIAL:
        return 9;
    default:
        return 0;
    }
}

int sl_eval_num_channels(sl_eval_quantity q, const sl_material *m) {
    return quantities[q].uses_material && m && m->sigma_a_rgb ? 3 : 1;
}

void sl_eval_output_name(sl_eval_quantity q, const sl_material *m, int ch, size_t k, char *out,
                         size_t n) {
    static const char *const marschner[] = {"f_R", "f_TT", "f_TRT", "f"};
    static const char *const ms[] = {"a_f",    "a_b", "alpha_f", "alpha_b", "beta_f",
                                     "beta_b", "A_b", "Delta_b", "sigma_b"};
    char base[64] = "";
    const char *prefix = q == SL_EVAL_SRBF ? "I" : "f";
    size_t nout = sl_eval_num_outputs(q, m);
    switch (q) {
    case SL_EVAL_SCATTER:
    case SL_EVAL_SRBF:
        if (m->model != SL_MODEL_MARSCHNER) { /* deon and chiang: per order, rest, total */
            if (k + 2 < nout)
                snprintf(base, sizeof base, "%s_%zu", prefix, k);
            else
                snprintf(base, sizeof base, "%s%s", prefix, k + 2 == nout ? "_rest" : "");
        } else {
            snprintf(base, sizeof base, "%s%s", prefix, marschner[k] + 1);
        }
        break;
    case SL_EVAL_DEON_MP:
        snprintf(base, sizeof base, "%s", k == 0 ? "M" : "log_M");
        break;
    case SL_EVAL_FURNACE:
        snprintf(base, sizeof base, "albedo");
        break;
    case SL_EVAL_TRANSMITTANCE:
        snprintf(base, sizeof base, "T");
        break;
    case SL_EVAL_FORWARD_TRANSMITTANCE:
        snprintf(base, sizeof base, "%s", k == 0 ? "T_f" : "sigma_f");
        break;
    case SL_EVAL_MS_MATERIAL:
        snprintf(base, sizeof base, "%s", ms[k]);
        break;
    default:
        break;
    }
    if (sl_eval_num_channels(q, m) == 3)
        snprintf(out, n, "%s_%c", base, "rgb"[ch]);
    else
        snprintf(out, n, "%s", base);
}

const char *sl_eval_format(sl_eval_backend b) {
    return b == SL_EVAL_REFERENCE ? "%.17g" : "%.9g";
}

int sl_eval_check_backend(sl_eval_quantity q, sl_eval_backend b, const sl_material *m,
                          const char *where, sl_err *e) {
    if (b == SL_EVAL_REFERENCE || !quantities[q].uses_material || !m) return 0;
    if (m->model == SL_MODEL_DEON && m->orders > SL_DEON_MAX_ORDERS)
        return sl_fail(e,
                       "%s: %d is more than the %s backend supports (at most %d; "
                       "--backend reference allows up to %d)",
                       where ? where : "orders", m->orders, backend_names[b], SL_DEON_MAX_ORDERS,
                       SL_MATERIAL_MAX_ORDERS);
    return 0;
}

/* Model marschner's cos theta_i / cos^2 theta_d is 0/0 at the opposite poles (theta_i = -+pi/2,
 * theta_o = +-pi/2) and grows like 1/(distance to the pole) near them, so its value there says
 * more about how an angle was rounded than about the fiber (double(pi/2) is 6.1e-17 short of
 * pi/2, float(pi/2) 4.4e-8 over it). Every backend therefore evaluates scatter at thetas at
 * least SL_EVAL_POLE_GAP from the poles; further in, the contract's formula unchanged
 * (docs/numerics.md "Poles and tails": with the theta_lo parts the float backends resolve the
 * distance to a pole to ~1e-15 rad, measured 4e-5 relative error of f at 1e-10..1e-9 rad,
 * 7e-4 at 1e-11..1e-10, so 1e-10 is the smallest gap that keeps them well inside 2e-3). */
#define SL_EVAL_POLE_GAP 1e-10

static double pole_clamp(double theta) {
    double lim = PI / 2 - SL_EVAL_POLE_GAP;
    return theta > lim ? lim : theta < -lim ? -lim : theta;
}

/* ---- reference: double, one row at a time ---- */

static int run_reference(sl_eval_quantity q, const sl_material *m, int ch, size_t n,
                         const double *in, double *out, sl_err *e) {
    size_t nin = quantities[q].nin, nout = sl_eval_num_outputs(q, m);
    for (size_t r = 0; r < n; r++) {
        const double *x = in + r * nin;
        double *y = out + r * nout;
        switch (q) {
        case SL_EVAL_SCATTER:
            if (m->model == SL_MODEL_CHIANG)
                slref_chiang_scatter(m, ch, x[0], x[1], x[2], x[3], y);
            else if (m->model == SL_MODEL_DEON)
                slref_deon_scatter(m, ch, x[0], x[1], x[2], x[3], y);
            else
                slref_marschner_scatter(m, ch, pole_clamp(x[0]), x[1], pole_clamp(x[2]), x[3], y);
            break;
        case SL_EVAL_DEON_MP:
            y[1] = slref_deon_log_mp(x[0], x[1], x[2]);
            y[0] = exp(y[1]); /* may underflow to 0; log_M stays finite */
            break;
        case SL_EVAL_FURNACE:
            y[0] = slref_furnace(m, ch, x[0], x[1]);
            break;
        case SL_EVAL_MS_MATERIAL:
            slref_dual_terms(m, ch, x[0], y);
            break;
        case SL_EVAL_SRBF:
            slref_srbf(m, ch, x[0], x[1], x[2], x[3], x[4], y);
            break;
        default:
            return sl_fail(e, "eval: %s is not implemented yet", quantities[q].name);
        }
    }
    return 0;
}

/* ---- float backends ---- */

/* Rounds an input to float; an angle whose float would fall outside its range (float(pi/2) >
 * pi/2, float(pi) > pi) moves one float toward zero so the backend sees a valid direction. */
static float to_float(double v, sl_eval_range range) {
    float f = (float)v;
    double bound = range == SL_RANGE_THETA ? PI / 2 : range == SL_RANGE_PHI ? PI : INFINITY;
    if (fabs((double)f) > bound) f = nextafterf(f, 0.0f);
    return f;
}

struct sl_eval_session {
    sl_srbf_tables tables; /* srbf xu / fast */
    int have_tables;
    sl_srbf_ren ren; /* srbf table */
    int have_ren;
    cl_mem ren_table; /* its copy on the OpenCL device, uploaded at the first chunk */
    float *dual[3];   /* ms-material: each channel's dual-scattering table (built on the backend) */
    slcl_rows_bufs rows; /* scatter, deon-mp, furnace on opencl: their row buffers, kept */
};

sl_eval_session *sl_eval_session_new(void) {
    return sl_calloc(1, sizeof(sl_eval_session));
}

void sl_eval_session_free(sl_eval_session *s) {
    if (!s) return;
    if (s->have_tables) sl_srbf_tables_free(&s->tables);
    slcl_srbf_ren_table_release(&s->ren_table);
    slcl_rows_bufs_release(&s->rows);
    if (s->have_ren) sl_srbf_ren_free(&s->ren);
    for (int ch = 0; ch < 3; ch++)
        free(s->dual[ch]);
    free(s);
}

static int run_float(sl_eval_session *s, sl_eval_quantity q, sl_eval_backend b, sl_eval_method mt,
                     int segments, sl_cl *cl, const sl_material *m, int ch, size_t n,
                     const double *in, double *out, sl_err *e) {
    const qdesc *d = &quantities[q];
    size_t nin = d->nin, nout = sl_eval_num_outputs(q, m);
    if (b == SL_EVAL_OPENCL && !cl) return sl_fail(e, "eval: --backend opencl needs a device");
    /* scatter rows carry theta_i_lo, theta_o_lo, phi_i_lo, phi_o_lo after the 4 inputs
     * (cpu/fiber_c.h slc_scatter_rows) */
    size_t fw = q == SL_EVAL_SCATTER ? 8 : nin;
    float *fin = sl_malloc(n * fw * sizeof *fin);
    float *fout = sl_calloc(n * nout, sizeof *fout);
    for (size_t r = 0; r < n; r++)
        for (size_t j = 0; j < nin; j++)
            fin[r * fw + j] = to_float(in[r * nin + j], d->in[j].range);
    sl_fiber_params fp;
    if (m) sl_material_to_fiber(m, ch, &fp);
    if (q == SL_EVAL_SCATTER)
        for (size_t r = 0; r < n; r++)
            for (size_t j = 0; j < 4; j++) { /* theta_i, phi_i, theta_o, phi_o */
                double v = in[r * nin + j];
                sl_eval_range rg = d->in[j].range;
                if (rg == SL_RANGE_THETA && m && m->model == SL_MODEL_MARSCHNER) v = pole_clamp(v);
                float hi = to_float(v, rg);
                fin[r * fw + j] = hi;
                /* lo slots: theta_i 4, theta_o 5, phi_i 6, phi_o 7; v - hi is exact in double */
                fin[r * fw + (rg == SL_RANGE_THETA ? 4 + j / 2 : 6 + j / 2)] =
                    (float)(v - (double)hi);
            }
    int rc = 0;
    if (q == SL_EVAL_SRBF && mt == SL_EVAL_METHOD_TABLE) {
        /* the table of material m (disk cache, or built on the C path; once per session), then
         * its lookup */
        if (m->model != SL_MODEL_MARSCHNER)
            /* the renderer's table of deon and chiang holds three modes (I_0, I_1, and the
             * orders >= 2 with the rest together), not the columns eval srbf prints for them */
            rc = sl_fail(e,
                         "eval: srbf --method table prints the Marschner columns only; model %s's "
                         "table (the renderer's, render --method table) keeps its orders >= 2 and "
                         "the rest term together: use --method fast (c, opencl) or exact "
                         "(reference)",
                         sl_material_model_name(m->model));
        if (!rc && !s->have_ren) {
            rc = sl_srbf_ren_get(NULL, m, NULL, &s->ren, e);
            s->have_ren = 1; /* ren is zeroed first, so freeing it is safe after a failure too */
        }
        if (!rc)
            rc = sl_srbf_ren_eval_keep(b == SL_EVAL_OPENCL ? cl : NULL, &s->ren, &s->ren_table, ch,
                                       n, fin, fout, e);
    } else if (q == SL_EVAL_SRBF) {
        rc = sl_srbf_eval_keep(b == SL_EVAL_OPENCL ? cl : NULL, m, &s->tables, &s->have_tables, ch,
                               mt == SL_EVAL_METHOD_XU, segments, n, fin, fout, e);
    } else if (b == SL_EVAL_C) {
        switch (q) {
        case SL_EVAL_SCATTER:
            slc_scatter_rows(&fp, n, fin, fw, fout);
            break;
        case SL_EVAL_DEON_MP:
            slc_deon_mp_batch(n, fin, fout);
            break;
        case SL_EVAL_FURNACE:
            slc_furnace_batch(&fp, n, fin, fout);
            break;
        case SL_EVAL_MS_MATERIAL:
            if (!s->dual[ch]) { /* slc_ms_material_batch, its table kept for the next chunks */
                s->dual[ch] = sl_malloc(SL_DUAL_TABLE_FLOATS * sizeof(float));
                slc_dual_table(&fp, s->dual[ch]);
            }
            slc_ms_material_lookup(s->dual[ch], n, fin, fout);
            break;
        default:
            rc = sl_fail(e, "eval: %s is not implemented yet", d->name);
        }
    } else {
        switch (q) {
        case SL_EVAL_SCATTER:
            rc = slcl_scatter_rows(cl, &fp, n, fin, fw, fout, &s->rows, e);
            break;
        case SL_EVAL_DEON_MP:
            rc = slcl_deon_mp_rows(cl, n, fin, fout, &s->rows, e);
            break;
        case SL_EVAL_FURNACE:
            rc = slcl_furnace_rows(cl, &fp, n, fin, fout, &s->rows, e);
            break;
        case SL_EVAL_MS_MATERIAL:
            if (!s->dual[ch]) { /* slcl_ms_material_batch, its table kept for the next chunks */
                s->dual[ch] = sl_malloc(SL_DUAL_TABLE_FLOATS * sizeof(float));
                rc = slcl_dual_table(cl, &fp, s->dual[ch], e);
                if (rc) {
                    free(s->dual[ch]);
                    s->dual[ch] = NULL;
                }
            }
            if (!rc) rc = slcl_ms_material_lookup(cl, s->dual[ch], n, fin, fout, e);
            break;
        default:
            rc = sl_fail(e, "eval: %s is not implemented yet", d->name);
        }
        if (rc) rc = -1; /* SL_CL_EKERNEL too: an explicit --backend opencl never falls back */
    }
    if (!rc)
        for (size_t i = 0; i < n * nout; i++)
            out[i] = (double)fout[i];
    free(fin);
    free(fout);
    return rc;
}

int sl_eval_method_from_name(const char *name, sl_eval_method *mt) {
    static const char *const names[] = {"exact", "xu", "fast", "table"};
    for (int i = 0; i < 4; i++)
        if (strcmp(name, names[i]) == 0) {
            *mt = (sl_eval_method)(i + 1);
            return 0;
        }
    return -1;
}

const char *sl_eval_method_unsupported(sl_eval_quantity q, sl_eval_backend b, sl_eval_method mt) {
    if (q != SL_EVAL_SRBF || mt == SL_EVAL_METHOD_DEFAULT) return NULL;
    if (b == SL_EVAL_REFERENCE && mt != SL_EVAL_METHOD_EXACT)
        return "--backend reference has --method exact only (xu, fast and table run on c and "
               "opencl)";
    if (b != SL_EVAL_REFERENCE && mt == SL_EVAL_METHOD_EXACT)
        return "--method exact needs --backend reference";
    return NULL;
}

int sl_eval_run(sl_eval_quantity q, sl_eval_backend b, sl_cl *cl, const sl_material *m, int ch,
                size_t n, const double *in, double *out, sl_err *e) {
    return sl_eval_run_method(q, b, SL_EVAL_METHOD_DEFAULT, 0, cl, m, ch, n, in, out, e);
}

int sl_eval_run_method(sl_eval_quantity q, sl_eval_backend b, sl_eval_method mt, int srbf_segments,
                       sl_cl *cl, const sl_material *m, int ch, size_t n, const double *in,
                       double *out, sl_err *e) {
    sl_eval_session *s = sl_eval_session_new();
    int rc = sl_eval_run_session(s, q, b, mt, srbf_segments, cl, m, ch, n, in, out, e);
    sl_eval_session_free(s);
    return rc;
}

int sl_eval_run_session(sl_eval_session *s, sl_eval_quantity q, sl_eval_backend b,
                        sl_eval_method mt, int srbf_segments, sl_cl *cl, const sl_material *m,
                        int ch, size_t n, const double *in, double *out, sl_err *e) {
    const char *why = sl_eval_method_unsupported(q, b, mt);
    if (why) return sl_fail(e, "eval: %s", why);
    if (!quantities[q].implemented)
        return sl_fail(e, "eval: %s is not implemented yet", quantities[q].name);
    if (quantities[q].uses_material && !m)
        return sl_fail(e, "eval: %s needs a material", quantities[q].name);
    if (sl_eval_check_backend(q, b, m, NULL, e)) return -1;
    if (n == 0) return 0;
    if (b == SL_EVAL_REFERENCE) return run_reference(q, m, ch, n, in, out, e);
    return run_float(s, q, b, mt, srbf_segments, cl, quantities[q].uses_material ? m : NULL, ch, n,
                     in, out, e);
}
