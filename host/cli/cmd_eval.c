/* cmd_eval.c: `strandlight eval QUANTITY`: reads CSV on stdin, evaluates a fiber quantity with
 * the chosen backend and writes CSV on stdout (numerics.md sec. 5; user docs in docs/eval.md).
 *
 * Nothing reaches stdout unless the whole input was valid and every row was evaluated: the
 * output is built in memory and written at the end, so an error leaves stdout empty. */
#include "cli/cli.h"
#include "cl/clrt.h"
#include "base/csv.h"
#include "verify/eval/fiber_eval.h"
#include "scene/material.h"
#include "scene/scene.h"
#include "verify/eval/shadow_eval.h"
#include "verify/eval/volume_eval.h"

#include <stdlib.h>
#include <string.h>

static void help(void) {
    printf("usage: strandlight eval QUANTITY [--material FILE.json | --scene S.json]\n"
           "                        [--backend reference|c|opencl] [--method exact|xu|fast|table]\n"
           "                        [--device SPEC] < in.csv > out.csv\n"
           "\n"
           "Evaluates a fiber scattering quantity for every row of a CSV table read from standard\n"
           "input, and writes the table to standard output with the results appended as new\n"
           "columns (the numerical contract, ../shared/spec/numerics.md sec. 5; docs/eval.md).\n"
           "\n"
           "quantities (input columns -> output columns; angles in radians, fiber frame):\n"
           "  scatter     theta_i,phi_i,theta_o,phi_o -> f_R,f_TT,f_TRT,f\n"
           "              (model deon: f_0,...,f_<orders>,f_rest,f)\n"
           "  deon-mp     v,theta_i,theta_o -> M,log_M   (d'Eon Eq. 7; no material; v > 0)\n"
           "  furnace     theta_o,phi_o -> albedo         (integral of f over the sphere)\n"
           "  srbf        theta_o,phi_o,theta_j,phi_j,lambda -> I_R,I_TT,I_TRT,I\n"
           "              (response to one SRBF light; model deon: I_0,...,I_<orders>,I_rest,I;\n"
           "              docs/srbf.md)\n"
           "  ms-material theta_d -> a_f,a_b,alpha_f,alpha_b,beta_f,beta_b,A_b,Delta_b,sigma_b\n"
           "              (dual-scattering terms, Zinke 2008; marschner only; docs/dual.md)\n"
           "  transmittance x,y,z,lobe -> T   (with --scene: effective transmittance of the\n"
           "              scene's hair toward lobe `lobe` of environment.lobes at world point\n"
           "              x,y,z; reference: ray-traced fibers, Monte Carlo over the lobe;\n"
           "              c/opencl: deep opacity maps; docs/shadow.md)\n"
           "  forward-transmittance x,y,z,lobe -> T_f,sigma_f   (with --scene: forward-scattering\n"
           "              transmittance and spread (dual scattering, Zinke 2008) on the shadow\n"
           "              path toward lobe `lobe`; reference: the actual fibers; c/opencl: voxel\n"
           "              grid + shadow-path march; docs/volume.md)\n"
           "\n"
           "options:\n"
           "  --material FILE.json  material (numerics.md sec. 2); default: the defaults there\n"
           "  --scene S.json        use the material of a scene file instead\n"
           "  --backend B           reference: double precision, adaptive quadrature (relative\n"
           "                        error <= 1e-6), printed with %%.17g;\n"
           "                        c (default): the C twin, float, printed with %%.9g;\n"
           "                        opencl: the OpenCL kernels, float, %%.9g (error if no OpenCL\n"
           "                        device exists)\n"
           "  --device SPEC         OpenCL device for --backend opencl: opencl (default: any,\n"
           "                        GPU preferred), gpu, pocl, P:D or N; implies --backend opencl\n"
           "  --method M            exact|xu|fast|table, for srbf (accepted and ignored by the\n"
           "                        others): exact needs --backend reference (its default\n"
           "                        there); xu, fast (the default) and table (Ren 2010's\n"
           "                        precomputed table of the material, built once and cached;\n"
           "                        docs/srbf_ren.md) run on c and opencl\n"
           "  --segments M          srbf --method xu: segments of the piecewise-linear quadrature\n"
           "                        (1..8, default 4; Xu 2011 Sec. 4.2.2)\n"
           "\n"
           "CSV: a header line naming the columns is required; columns in any order; other\n"
           "columns are copied through as text; one output row per input row, in order. Angles:\n"
           "theta in [-pi/2, pi/2], phi in [-pi, pi] (values within 1e-6 beyond a bound are\n"
           "clamped onto it). With an [r,g,b] sigma_a (or melanin) every output column is given\n"
           "per channel with a _r, _g, _b suffix (all _r columns, then _g, then _b). No quoting;\n"
           "LF or CRLF line endings. Errors: one line on stderr naming the line\n"
           "(\"<stdin>:3: theta_i: 'x' is not a number\", the header is line 1), exit 1, nothing\n"
           "on stdout. Usage errors exit 2.\n");
}

typedef struct eval_opts {
    sl_eval_quantity q;
    sl_eval_backend backend;
    const char *material, *scene, *device;
    sl_eval_method method; /* srbf */
    int segments;          /* srbf --method xu; 0: default */
} eval_opts;

/* Parses the command line; returns -1 to continue, else the exit code. */
static int parse_args(int argc, char **argv, eval_opts *o) {
    const char *quantity = NULL, *backend = NULL, *method = NULL, *v;
    memset(o, 0, sizeof *o);
    for (int i = 1; i < argc; i++) {
        int missing = 0;
        if (cli_is_help(argv[i])) {
            help();
            return 0;
        }
        if (cli_opt(argc, argv, &i, "--material", &v, &missing))
            o->material = v;
        else if (cli_opt(argc, argv, &i, "--scene", &v, &missing))
            o->scene = v;
        else if (cli_opt(argc, argv, &i, "--backend", &v, &missing))
            backend = v;
        else if (cli_opt(argc, argv, &i, "--method", &v, &missing))
            method = v;
        else if (cli_opt(argc, argv, &i, "--device", &v, &missing))
            o->device = v;
        else if (cli_opt(argc, argv, &i, "--segments", &v, &missing)) {
            char *end;
            long s = strtol(v, &end, 10);
            if (*end || end == v || s < 1 || s > 8)
                return cli_usage_error("eval", "--segments: expected an integer 1..8, got '%s'", v);
            o->segments = (int)s;
        }
        else if (argv[i][0] == '-' && argv[i][1])
            return cli_usage_error("eval", "unknown option '%s'", argv[i]);
        else if (!quantity)
            quantity = argv[i];
        else
            return cli_usage_error("eval", "unexpected argument '%s'", argv[i]);
        if (missing) return 2;
    }
    if (!quantity) return cli_usage_error("eval", "missing QUANTITY");
    if (sl_eval_quantity_from_name(quantity, &o->q))
        return cli_usage_error("eval",
                               "unknown quantity '%s' (expected scatter, srbf, deon-mp, furnace, "
                               "transmittance, forward-transmittance or ms-material)",
                               quantity);
    if (backend && sl_eval_backend_from_name(backend, &o->backend))
        return cli_usage_error("eval", "unknown backend '%s' (expected reference, c or opencl)",
                               backend);
    if (!backend) o->backend = o->device ? SL_EVAL_OPENCL : SL_EVAL_C;
    if (o->device && o->backend != SL_EVAL_OPENCL)
        return cli_usage_error("eval", "--device applies to --backend opencl only");
    if (method && sl_eval_method_from_name(method, &o->method))
        return cli_usage_error("eval", "unknown method '%s' (expected exact, xu, fast or table)",
                               method);
    const char *why = sl_eval_method_unsupported(o->q, o->backend, o->method);
    if (why) return cli_usage_error("eval", "%s", why);
    if (o->material && o->scene)
        return cli_usage_error("eval", "give --material or --scene, not both");
    if (!sl_eval_quantity_uses_material(o->q) && !sl_eval_quantity_needs_scene(o->q) &&
        (o->material || o->scene))
        return cli_usage_error("eval", "%s takes no material", quantity);
    return -1;
}

static int fail(const sl_err *e) {
    fprintf(stderr, "strandlight: %s\n", e->msg);
    return 1;
}

/* Material from --material, --scene or the defaults. */
static int load_material(const eval_opts *o, sl_material *m, sl_err *e) {
    sl_material_default(m);
    if (o->material) return sl_material_load(o->material, m, e);
    if (o->scene) {
        sl_scene *s = sl_malloc(sizeof *s);
        int rc = sl_scene_load(o->scene, s, e);
        if (!rc) *m = s->material;
        free(s);
        return rc;
    }
    return 0;
}

/* Reads and validates the input columns of every row into a row-major array. */
static int read_inputs(const eval_opts *o, const sl_csv *csv, const sl_material *m, double **x,
                       sl_err *e) {
    const sl_eval_input *in;
    size_t nin = sl_eval_inputs(o->q, &in);
    int col[8];
    for (size_t k = 0; k < nin; k++) {
        col[k] = sl_csv_find(csv, in[k].name);
        if (col[k] < 0) {
            char need[256] = "";
            for (size_t j = 0; j < nin; j++)
                snprintf(need + strlen(need), sizeof need - strlen(need), "%s%s", j ? "," : "",
                         in[j].name);
            return sl_fail(e, "%s:1: missing column '%s' (%s needs %s)", csv->src, in[k].name,
                           sl_eval_quantity_name(o->q), need);
        }
    }
    /* An output column that is already an input column would make the output ambiguous. */
    size_t nout = sl_eval_num_outputs(o->q, m);
    for (int ch = 0; ch < sl_eval_num_channels(o->q, m); ch++)
        for (size_t k = 0; k < nout; k++) {
            char name[64];
            sl_eval_output_name(o->q, m, ch, k, name, sizeof name);
            if (sl_csv_find(csv, name) >= 0)
                return sl_fail(e, "%s:1: input column '%s' has the name of an output column",
                               csv->src, name);
        }
    *x = sl_malloc((csv->nrows ? csv->nrows : 1) * nin * sizeof **x);
    for (size_t r = 0; r < csv->nrows; r++)
        for (size_t k = 0; k < nin; k++) {
            double *v = &(*x)[r * nin + k];
            if (sl_csv_number(csv, r, col[k], v, e)) goto bad;
            const char *why = sl_eval_check_input(in[k].range, v);
            if (why) {
                sl_fail(e, "%s:%ld: %s: %s (got %.64s)", csv->src, csv->line_no[r], in[k].name, why,
                        csv->fields[r * csv->ncols + (size_t)col[k]]);
                goto bad;
            }
        }
    return 0;
bad:
    free(*x);
    *x = NULL;
    return -1;
}

/* Evaluates every channel and formats the whole output table into out. */
static int evaluate(const eval_opts *o, const sl_csv *csv, const sl_material *m, const double *x,
                    sl_cl *cl, sl_buf *out, sl_err *e) {
    size_t n = csv->nrows, nout = sl_eval_num_outputs(o->q, m);
    int nch = sl_eval_num_channels(o->q, m);
    double *y = sl_calloc((n ? n : 1) * nout * (size_t)nch, sizeof *y);
    if (o->q == SL_EVAL_TRANSMITTANCE) { /* needs the scene's hair and lobes: shadow_eval.h */
        if (!o->scene ||
            sl_shadow_eval_transmittance(o->scene, o->backend, cl, n, x, csv->line_no, y, e)) {
            if (!o->scene) sl_fail(e, "eval transmittance needs --scene S.json");
            free(y);
            return -1;
        }
    } else if (o->q == SL_EVAL_FORWARD_TRANSMITTANCE) { /* hair, material, lobes: volume_eval.h */
        if (!o->scene ||
            sl_volume_eval_forward(o->scene, o->backend, cl, n, x, csv->line_no, y, e)) {
            if (!o->scene) sl_fail(e, "eval forward-transmittance needs --scene S.json");
            free(y);
            return -1;
        }
    } else
    for (int ch = 0; ch < nch; ch++)
        if (sl_eval_run_method(o->q, o->backend, o->method, o->segments, cl, m, ch, n, x,
                               y + (size_t)ch * n * nout, e)) {
            free(y);
            return -1;
        }
    const char *fmt = sl_eval_format(o->backend);
    sl_buf_puts(out, csv->header);
    for (int ch = 0; ch < nch; ch++)
        for (size_t k = 0; k < nout; k++) {
            char name[64];
            sl_eval_output_name(o->q, m, ch, k, name, sizeof name);
            sl_buf_printf(out, ",%s", name);
        }
    sl_buf_puts(out, "\n");
    for (size_t r = 0; r < n; r++) {
        sl_buf_puts(out, csv->rows[r]);
        for (int ch = 0; ch < nch; ch++)
            for (size_t k = 0; k < nout; k++) {
                sl_buf_puts(out, ",");
                sl_buf_printf(out, fmt, y[(size_t)ch * n * nout + r * nout + k]);
            }
        sl_buf_puts(out, "\n");
    }
    free(y);
    return 0;
}

int cmd_eval(int argc, char **argv) {
    eval_opts o;
    int rc = parse_args(argc, argv, &o);
    if (rc >= 0) return rc;
    if (!sl_eval_quantity_implemented(o.q)) {
        fprintf(stderr, "strandlight eval: %s is not implemented yet\n",
                sl_eval_quantity_name(o.q));
        return 1;
    }
    sl_err e = {{0}};
    sl_material m;
    const sl_material *mp = sl_eval_quantity_uses_material(o.q) ? &m : NULL;
    if (load_material(&o, &m, &e)) return fail(&e);
    char where[4200];
    if (o.scene)
        snprintf(where, sizeof where, "%s: material.orders", o.scene);
    else
        snprintf(where, sizeof where, "%s: orders", o.material ? o.material : "material");
    if (mp && sl_eval_check_backend(o.q, o.backend, mp, where, &e)) return fail(&e);

    char *text = NULL;
    size_t len = 0;
    if (sl_read_stream(stdin, "<stdin>", &text, &len, &e)) return fail(&e);
    sl_csv csv;
    rc = sl_csv_parse(text, len, "<stdin>", &csv, &e);
    free(text);
    if (rc) return fail(&e);

    double *x = NULL;
    sl_device dev;
    int have_dev = 0;
    sl_buf out = {0};
    rc = 1;
    if (read_inputs(&o, &csv, mp, &x, &e)) goto done;
    if (o.backend == SL_EVAL_OPENCL) {
        if (sl_device_open(o.device ? o.device : "opencl", &dev, &e)) goto done;
        have_dev = 1;
        if (!dev.is_opencl) {
            sl_fail(&e, "--device %s is not an OpenCL device (--backend opencl needs one)",
                    o.device ? o.device : "opencl");
            goto done;
        }
    }
    if (evaluate(&o, &csv, mp, x, have_dev ? dev.cl : NULL, &out, &e)) goto done;
    if (out.len && fwrite(out.p, 1, out.len, stdout) != out.len) {
        sl_fail(&e, "write error on standard output");
        goto done;
    }
    if (fflush(stdout) != 0 || ferror(stdout)) {
        sl_fail(&e, "write error on standard output");
        goto done;
    }
    rc = 0;
done:
    if (rc) fail(&e);
    if (have_dev) sl_device_close(&dev);
    sl_buf_free(&out);
    free(x);
    sl_csv_free(&csv);
    return rc;
}
