/* kernel_checks.c: the table of kernel-vs-C-twin checks (kernel_checks.h) and the prefix-sum
 * check. */
#include "verify/checks/kernel_checks.h"

#include "../cpu/prefix_sum.h"
#include "passes/light/prefix_sum_cl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const sl_kernel_check checks[] = {
    {"prefix_sum", "inclusive 2-D prefix sum (summed-area table), prefix_sum.cl, work-group scan",
     slchk_prefix_sum, 0},
    {"prefix_sum_serial", "the same, one work-item per tile (the variant CPU devices use)",
     slchk_prefix_sum_serial, 0},
    {"raster", "segment rasterizer + DODM tables, raster.cl + dodm.cl (bit-identical)",
     slchk_raster, 0},
    {"dodm_lookup", "convolution optical depth lookup T = exp(-tau), dodm.cl", slchk_dodm, 0},
    {"dodm_behind", "optical depth of the hair behind a point (multiple scattering), dodm.cl",
     slchk_dodm_behind, 0},
    {"voxel", "hair voxelization (density, direction, deviation), voxel.cl", slchk_voxel, 0},
    {"march", "shadow-path march T_f, sigma_f (dual scattering), march.cl", slchk_march, 0},
    {"ms", "multiple-scattering response per fragment and lobe (Xu Eq. 27-31), ms.cl",
     slchk_ms_response, 0},
    {"dual", "dual-scattering material table nodes, dual.cl", slchk_dual_table, 0},
    {"srbf", "SRBF response, --method fast and xu (m = 4), srbf.cl", slchk_srbf, 0},
    {"srbf_deon", "SRBF response of models deon and chiang (rows and RGB rows), srbf_deon.cl",
     slchk_srbf_deon, 1},
    {"fiber_chiang", "fiber function of model chiang (eval scatter, furnace), fiber.cl",
     slchk_fiber_chiang, 1},
    {"kbuffer", "view-pass K-buffer fill, view.cl built with -DSL_KB_K=K (bit-identical)",
     slchk_kbuffer, 1},
    {"kbuffer_generic", "the same, generic build (K a kernel argument), for the -D gain",
     slchk_kbuffer_generic, 1},
};

const sl_kernel_check *sl_kernel_checks(size_t *count) {
    *count = sizeof checks / sizeof checks[0];
    return checks;
}

const sl_kernel_check *sl_kernel_check_find(const char *name) {
    for (size_t i = 0; i < sizeof checks / sizeof checks[0]; i++)
        if (strcmp(checks[i].name, name) == 0) return &checks[i];
    return NULL;
}

void sl_kernel_compare(const float *kernel_out, const float *c_out, size_t n,
                       sl_kernel_check_result *r) {
    r->max_abs = r->max_rel = 0;
    r->compared = n;
    r->bad = 0;
    for (size_t i = 0; i < n; i++) {
        double a = kernel_out[i], b = c_out[i];
        if (isnan(a) && isnan(b)) continue;
        if (isinf(a) || isinf(b)) {
            if (a != b) {
                r->bad++;
                r->max_abs = r->max_rel = INFINITY;
            }
            continue;
        }
        double d = fabs(a - b);
        if (isnan(d)) d = INFINITY; /* one NaN */
        double rel = d == 0 ? 0 : (b != 0 ? d / fabs(b) : INFINITY);
        if (d > r->max_abs) r->max_abs = d;
        if (rel > r->max_rel) r->max_rel = rel;
        if (!(d <= r->tol_abs || d <= r->tol_rel * fabs(b))) r->bad++;
    }
    r->pass = r->bad == 0;
}

void sl_kernel_check_fill(float *x, size_t n, unsigned long long seed, float lo, float hi) {
    unsigned long long s = seed * 2654435761ull + 0x9e3779b97f4a7c15ull;
    for (size_t i = 0; i < n; i++) {
        s ^= s >> 12;
        s ^= s << 25;
        s ^= s >> 27;
        double u = (double)((s * 2685821657736338717ull) >> 11) * 0x1.0p-53; /* [0,1) */
        x[i] = (float)(lo + (hi - lo) * u);
        if (x[i] >= hi) x[i] = lo; /* rounding up to hi */
    }
}

/* ---------------------------------------------------------------- prefix sum */

static int check_prefix_sum(sl_cl *cl, const sl_kernel_check_opts *o, sl_ps_variant variant,
                            sl_kernel_check_result *r, sl_err *e) {
    /* Default: sizes that are not multiples of the 256 tile and need two scan levels. */
    size_t w = o->size > 0 ? (size_t)o->size : 1031, h = o->size > 0 ? (size_t)o->size : 517;
    int reps = o->reps > 0 ? o->reps : 3;
    snprintf(r->problem, sizeof r->problem, "%zux%zu image", w, h);
    /* Same additions in the same order (kernels/prefix_sum.h), IEEE single additions only:
     * the results must be bit-identical. */
    r->tol_abs = 0;
    r->tol_rel = 0;
    snprintf(r->note, sizeof r->note, "same summation order as the C twin: bit-identical");
    float *in = sl_malloc(w * h * sizeof *in), *a = sl_malloc(w * h * sizeof *a),
          *b = sl_malloc(w * h * sizeof *b);
    sl_kernel_check_fill(in, w * h, 1, 0.0f, 1.0f);
    int rc = 0;
    r->c_s = r->cl_s = r->cl_wall_s = INFINITY;
    /* One untimed OpenCL run first: the program build and PoCL's code generation at the first
     * enqueue are not kernel time. */
    double ks;
    if ((rc = slcl_prefix_sum_2d_variant(cl, in, a, w, h, variant, &ks, e))) goto done;
    for (int i = 0; i < reps; i++) {
        double t0 = sl_now();
        if ((rc = slcl_prefix_sum_2d_variant(cl, in, a, w, h, variant, &ks, e))) goto done;
        double wall = sl_now() - t0;
        if (ks < r->cl_s) r->cl_s = ks;
        if (wall < r->cl_wall_s) r->cl_wall_s = wall;
        t0 = sl_now();
        slc_prefix_sum_2d(in, b, w, h);
        double c = sl_now() - t0;
        if (c < r->c_s) r->c_s = c;
    }
    r->cl_s_is_device = sl_cl_profiling(cl);
    sl_kernel_compare(a, b, w * h, r);
done:
    free(in);
    free(a);
    free(b);
    return rc;
}

int slchk_prefix_sum(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                     sl_err *e) {
    return check_prefix_sum(cl, o, SL_PS_WORKGROUP, r, e);
}

int slchk_prefix_sum_serial(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                            sl_err *e) {
    return check_prefix_sum(cl, o, SL_PS_SERIAL, r, e);
}

/* ---------------------------------------------------------------- extreme sweep (--extreme)
 * Degenerate geometry and extreme materials through the C path and, when cl is given, the
 * OpenCL kernels (docs/robustness.md). The requirement is zero NaN/Inf in any output (and
 * T in [0, 1]); C-vs-kernel agreement is the business of the regular checks. Devices made
 * here around cl never fall back (sl_device.auto_chosen = 0). */
#include "verify/eval/fiber_eval.h"
#include "io/hair/hair.h"
#include "scene/material.h"
#include "passes/light/shadow.h"

/* Hair of `strands` strands of `pts` points: a fan of straight strands, then `kind` bends it:
 * 0 normal, 1 every other strand zero-length (all points equal), 2 all strands coincident,
 * 3 every point of the hair at one place, 4 far from the origin (1e6), 5 one strand of 2 points. */
static void extreme_hair(sl_hair *h, int kind) {
    uint32_t ns = kind == 5 ? 1 : 64, np = kind == 5 ? 2 : 8;
    memset(h, 0, sizeof *h);
    sl_hair_alloc(h, ns, ns * np);
    h->default_radius = 0.01f;
    h->default_transparency = 0;
    for (uint32_t s = 0; s <= ns; s++)
        h->strand_first[s] = s * np;
    for (uint32_t s = 0; s < ns; s++)
        for (uint32_t k = 0; k < np; k++) {
            float *p = h->pos + 3 * (s * np + k);
            float a = kind == 2 ? 0 : 0.1f * (float)s, t = (float)k / (float)(np - 1);
            p[0] = 0.3f * cosf(a) * t;
            p[1] = 1.0f - t;
            p[2] = 0.3f * sinf(a) * t;
            if ((kind == 1 && s % 2) || kind == 3) p[0] = p[1] = p[2] = 0.25f;
            if (kind == 4) p[0] += 1e6f, p[2] -= 1e6f;
        }
}

static int all_finite(const double *x, size_t n, int unit) {
    for (size_t i = 0; i < n; i++)
        if (!isfinite(x[i]) || (unit && (x[i] < 0 || x[i] > 1))) return 0;
    return 1;
}

/* Shadow map + lookups for one hair/lobe on dev; T gets n values. */
static int extreme_shadow(sl_device *dev, const sl_hair *h, const double dir[3], double lambda,
                          int size, size_t n, const double *xyz, double *T, sl_err *e) {
    sl_shadow_opts o;
    sl_shadow_opts_default(&o);
    o.size = size;
    sl_dodm m;
    if (sl_shadow_build(dev, h, dir, lambda, &o, &m, e)) return -1;
    int rc = sl_shadow_lookup(dev, &m, n, xyz, T, e);
    sl_dodm_free(&m);
    return rc;
}

static int extreme_geometry(sl_cl *cl, FILE *out) {
    static const char *const names[6] = {"normal",
                                         "zero-length segments",
                                         "coincident strands",
                                         "all points at one place",
                                         "far from the origin (1e6)",
                                         "one 2-point strand"};
    static const double dirs[3][3] = {{0, 1, 0}, {0, 0, -1}, {0.36, 0.8, 0.48}};
    static const double lambdas[3] = {1e-3, 0.3, 10};
    int failed = 0;
    for (int kind = 0; kind < 6; kind++) {
        sl_hair h;
        extreme_hair(&h, kind);
        float lo[3], hi[3];
        sl_hair_bounds(&h, lo, hi);
        /* Lookups at the hair's centre (inside it), at its bounds, far behind and far in front
         * along every axis. */
        enum { NP = 9 };
        double xyz[3 * NP];
        for (int k = 0; k < 3; k++) {
            double c = 0.5 * ((double)lo[k] + hi[k]);
            for (int i = 0; i < NP; i++)
                xyz[3 * i + k] = c;
            xyz[3 * 1 + k] = lo[k];
            xyz[3 * 2 + k] = hi[k];
            xyz[3 * (3 + k) + k] = c + 1e3;
            xyz[3 * (6 + k) + k] = c - 1e3;
        }
        size_t cases = 0, bad = 0;
        char why[512] = "";
        for (int d = 0; d < 3; d++)
            for (int l = 0; l < 3; l++)
                for (int size = 2; size <= 64; size *= 32) { /* 2 and 64 texels */
                    for (int use_cl = 0; use_cl <= (cl != NULL); use_cl++) {
                        sl_device dev = {0};
                        dev.is_opencl = use_cl;
                        dev.cl = use_cl ? cl : NULL;
                        double T[NP];
                        sl_err e = {{0}};
                        cases++;
                        if (extreme_shadow(&dev, &h, dirs[d], lambdas[l], size, NP, xyz, T, &e)) {
                            bad++;
                            snprintf(why, sizeof why, "%s: %.400s", use_cl ? "OpenCL" : "C", e.msg);
                        } else if (!all_finite(T, NP, 1)) {
                            bad++;
                            snprintf(why, sizeof why,
                                     "%s: T not finite or outside [0, 1] (dir %d, lambda %g, "
                                     "%d texels)",
                                     use_cl ? "OpenCL" : "C", d, lambdas[l], size);
                        }
                    }
                }
        fprintf(out, "extreme shadow %-28s %s (%zu maps x %d lookups%s)%s%s\n", names[kind],
                bad ? "FAIL" : "PASS", cases, NP, cl ? ", C and OpenCL" : ", C only",
                bad ? ": " : "", why);
        failed += bad > 0;
        sl_hair_free(&h);
    }
    return failed;
}

static int extreme_materials(sl_cl *cl, FILE *out) {
    static const char *const mats[] = {
        "{}",
        "{\"eta\": 1.0001}",
        "{\"eta\": 10, \"sigma_a\": 0}",
        "{\"beta_R_deg\": 0.5, \"sigma_a\": 50}",
        "{\"beta_R_deg\": 60, \"alpha_R_deg\": 20}",
        "{\"eccentricity\": 0.5, \"caustic_width_deg\": 0.5}",
        "{\"eccentricity\": 2, \"fresnel\": \"schlick\"}",
        "{\"model\": \"deon\", \"orders\": 2, \"beta_R_deg\": 0.5}",
        "{\"model\": \"deon\", \"orders\": 32, \"beta_R_deg\": 60, \"sigma_a\": 0}",
        "{\"model\": \"chiang\"}",
        "{\"model\": \"chiang\", \"radial_roughness\": 0.001, \"roughness\": 0.001, \"coat\": 0.99}",
        "{\"model\": \"chiang\", \"radial_roughness\": 1, \"roughness\": 1, \"offset_deg\": 45, "
        "\"eta\": 1.0001, \"sigma_a\": 0}",
        "{\"model\": \"chiang\", \"eta\": 10, \"sigma_a\": 1000, \"offset_deg\": -45}",
    };
    /* Grazing and axis-aligned directions; 1.5707963 is the float just below pi/2. */
    static const double th[] = {-1.5707963, -1, 0, 0.5, 1.5707963};
    static const double ph[] = {0, 1e-7, 1.5707963, 3.1415925, -3.1415925};
    enum { NT = 5, NPH = 5, N = NT * NPH * NT * NPH };
    double *in = sl_malloc(4 * N * sizeof *in), *res = NULL;
    size_t r = 0;
    for (int a = 0; a < NT; a++)
        for (int b = 0; b < NPH; b++)
            for (int c = 0; c < NT; c++)
                for (int d = 0; d < NPH; d++, r++) {
                    in[4 * r] = th[a];
                    in[4 * r + 1] = ph[b];
                    in[4 * r + 2] = th[c];
                    in[4 * r + 3] = ph[d];
                }
    int failed = 0;
    for (size_t i = 0; i < sizeof mats / sizeof mats[0]; i++) {
        sl_material m;
        sl_err e = {{0}};
        char why[512] = "";
        size_t bad = 0;
        if (sl_material_parse(mats[i], strlen(mats[i]), "extreme", &m, &e)) {
            bad = 1;
            snprintf(why, sizeof why, "%.400s", e.msg);
        }
        size_t nout = bad ? 0 : sl_eval_num_outputs(SL_EVAL_SCATTER, &m);
        res = sl_realloc(res, (nout ? nout : 1) * N * sizeof *res);
        for (int b = SL_EVAL_C; !bad && b <= (cl ? SL_EVAL_OPENCL : SL_EVAL_C); b++) {
            if (sl_eval_run(SL_EVAL_SCATTER, (sl_eval_backend)b, cl, &m, 0, N, in, res, &e)) {
                bad++;
                snprintf(why, sizeof why, "%s: %.400s", b == SL_EVAL_C ? "C" : "OpenCL", e.msg);
            } else if (!all_finite(res, nout * N, 0)) {
                bad++;
                snprintf(why, sizeof why, "%s: NaN or Inf in f", b == SL_EVAL_C ? "C" : "OpenCL");
            }
        }
        fprintf(out, "extreme scatter %-52s %s (%d directions%s)%s%s\n", mats[i],
                bad ? "FAIL" : "PASS", N, cl ? ", C and OpenCL" : ", C only", bad ? ": " : "", why);
        failed += bad > 0;
    }
    free(in);
    free(res);
    return failed;
}

int sl_kernel_extreme(sl_cl *cl, FILE *out) {
    return extreme_geometry(cl, out) + extreme_materials(cl, out);
}
