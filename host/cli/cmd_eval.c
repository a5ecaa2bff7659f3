/* cmd_eval.c: `strandlight eval QUANTITY`: reads CSV on stdin, evaluates a fiber quantity with
 * the chosen backend and writes CSV on stdout or to --output FILE (numerics.md sec. 5; user docs
 * in docs/eval.md).
 *
 * The rows stream through in chunks (EVAL_CHUNK_ROWS): each chunk is read, checked, evaluated
 * (one batch per channel: one kernel dispatch on opencl) and its output rows written, so memory
 * does not grow with the number of rows (issue 21; docs/robustness.md sec. 5). Nothing reaches
 * the output unless the whole input was valid and every row was evaluated: the chunks are
 * written to a temporary file (beside --output FILE, renamed over it at the end; for stdout an
 * unlinked one in $TMPDIR, copied to stdout at the end), so an error in any chunk leaves stdout
 * empty and no output file. */
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
#include <unistd.h>

/* Rows per chunk: large enough that a batch keeps a device busy and the per-chunk costs vanish,
 * small enough that a chunk's text, fields and values stay a few tens of MB. SL_EVAL_CHUNK_ROWS
 * (tests only: chunk boundaries on small inputs) overrides it. */
#define EVAL_CHUNK_ROWS 65536

static void help(void) {
    printf("usage: strandlight eval QUANTITY [--material FILE.json | --scene S.json]\n"
           "                        [--backend reference|c|opencl] [--method exact|xu|fast|table]\n"
           "                        [--device SPEC] [-o FILE] < in.csv > out.csv\n"
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
           "  -o, --output FILE     write the table to FILE (atomically: whole, or not at all)\n"
           "                        instead of standard output\n"
           "\n"
           "CSV: a header line naming the columns is required; columns in any order; other\n"
           "columns are copied through as text; one output row per input row, in order. Angles:\n"
           "theta in [-pi/2, pi/2], phi in [-pi, pi] (values within 1e-6 beyond a bound are\n"
           "clamped onto it). With an [r,g,b] sigma_a (or melanin) every output column is given\n"
           "per channel with a _r, _g, _b suffix (all _r columns, then _g, then _b). No quoting;\n"
           "LF or CRLF line endings. Errors: one line on stderr naming the line\n"
           "(\"<stdin>:3: theta_i: 'x' is not a number\", the header is line 1), exit 1, nothing\n"
           "on stdout and no --output file. Usage errors exit 2. The rows are read, evaluated\n"
           "and written in chunks, so memory does not grow with their number.\n");
}

typedef struct eval_opts {
    sl_eval_quantity q;
    sl_eval_backend backend;
    const char *material, *scene, *device, *output;
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
        else if (cli_opt(argc, argv, &i, "-o", &v, &missing) ||
                 cli_opt(argc, argv, &i, "--output", &v, &missing))
            o->output = v;
        else if (cli_opt(argc, argv, &i, "--segments", &v, &missing)) {
            char *end;
            long s = strtol(v, &end, 10);
            if (*end || end == v || s < 1 || s > 8)
                return cli_usage_error("eval", "--segments: expected an integer 1..8, got '%s'", v);
            o->segments = (int)s;
        } else if (argv[i][0] == '-' && argv[i][1])
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

/* The header's checks: every input column present, no output column among the inputs. */
static int check_columns(const eval_opts *o, const sl_csv *csv, const sl_material *m, int *col,
                         sl_err *e) {
    const sl_eval_input *in;
    size_t nin = sl_eval_inputs(o->q, &in);
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
    return 0;
}

/* Reads and validates the input columns of the chunk's rows into x (row-major, nin per row). */
static int read_inputs(const eval_opts *o, const sl_csv *csv, const int *col, double *x,
                       sl_err *e) {
    const sl_eval_input *in;
    size_t nin = sl_eval_inputs(o->q, &in);
    for (size_t r = 0; r < csv->nrows; r++)
        for (size_t k = 0; k < nin; k++) {
            double *v = &x[r * nin + k];
            if (sl_csv_number(csv, r, col[k], v, e)) return -1;
            const char *why = sl_eval_check_input(in[k].range, v);
            if (why)
                return sl_fail(e, "%s:%ld: %s: %s (got %.64s)", csv->src, csv->line_no[r],
                               in[k].name, why, csv->fields[r * csv->ncols + (size_t)col[k]]);
        }
    return 0;
}

/* What one run keeps across its chunks: the device, the scene quantities' loaded scene, srbf's
 * tables. */
typedef struct eval_run {
    sl_device dev;
    int have_dev;
    sl_cl *cl;
    sl_shadow_eval *shadow;   /* transmittance */
    sl_volume_eval *volume;   /* forward-transmittance */
    sl_eval_session *session; /* the others */
    size_t row0;              /* rows evaluated before this chunk */
} eval_run;

/* After the first chunk is read and checked (so its errors come first, as they did when the whole
 * input was read at once): the device and the scene. */
static int run_open(const eval_opts *o, const sl_csv *csv, const double *x, eval_run *run,
                    sl_err *e) {
    if (o->backend == SL_EVAL_OPENCL) {
        if (sl_device_open(o->device ? o->device : "opencl", &run->dev, e)) return -1;
        run->have_dev = 1;
        if (!run->dev.is_opencl)
            return sl_fail(e, "--device %s is not an OpenCL device (--backend opencl needs one)",
                           o->device ? o->device : "opencl");
        run->cl = run->dev.cl;
    }
    if (o->q == SL_EVAL_TRANSMITTANCE) { /* needs the scene's hair and lobes: shadow_eval.h */
        if (!o->scene) return sl_fail(e, "eval transmittance needs --scene S.json");
        return sl_shadow_eval_open(o->scene, o->backend, run->cl, csv->nrows, x, csv->line_no,
                                   &run->shadow, e);
    }
    if (o->q == SL_EVAL_FORWARD_TRANSMITTANCE) { /* hair, material, lobes: volume_eval.h */
        if (!o->scene) return sl_fail(e, "eval forward-transmittance needs --scene S.json");
        return sl_volume_eval_open(o->scene, o->backend, run->cl, csv->nrows, x, csv->line_no,
                                   &run->volume, e);
    }
    run->session = sl_eval_session_new();
    return 0;
}

static void run_close(eval_run *run) {
    sl_shadow_eval_close(run->shadow);
    sl_volume_eval_close(run->volume);
    sl_eval_session_free(run->session);
    if (run->have_dev) sl_device_close(&run->dev);
}

/* Evaluates every channel of the chunk's rows into y: nch blocks of n rows x nout values. */
static int evaluate(const eval_opts *o, eval_run *run, const sl_csv *csv, const sl_material *m,
                    const double *x, double *y, sl_err *e) {
    size_t n = csv->nrows, nout = sl_eval_num_outputs(o->q, m);
    int nch = sl_eval_num_channels(o->q, m);
    if (run->shadow) return sl_shadow_eval_rows(run->shadow, run->row0, n, x, csv->line_no, y, e);
    if (run->volume) return sl_volume_eval_rows(run->volume, n, x, csv->line_no, y, e);
    for (int ch = 0; ch < nch; ch++)
        if (sl_eval_run_session(run->session, o->q, o->backend, o->method, o->segments, run->cl, m,
                                ch, n, x, y + (size_t)ch * n * nout, e))
            return -1;
    return 0;
}

/* The output header line into out. */
static void format_header(const eval_opts *o, const sl_csv *csv, const sl_material *m,
                          sl_buf *out) {
    sl_buf_puts(out, csv->header);
    for (int ch = 0; ch < sl_eval_num_channels(o->q, m); ch++)
        for (size_t k = 0; k < sl_eval_num_outputs(o->q, m); k++) {
            char name[64];
            sl_eval_output_name(o->q, m, ch, k, name, sizeof name);
            sl_buf_printf(out, ",%s", name);
        }
    sl_buf_puts(out, "\n");
}

/* The chunk's output rows into out: each input row as given, then its values. */
static void format_rows(const eval_opts *o, const sl_csv *csv, const sl_material *m,
                        const double *y, sl_buf *out) {
    size_t n = csv->nrows, nout = sl_eval_num_outputs(o->q, m);
    int nch = sl_eval_num_channels(o->q, m);
    const char *fmt = sl_eval_format(o->backend);
    for (size_t r = 0; r < n; r++) {
        sl_buf_puts(out, csv->rows[r]);
        for (int ch = 0; ch < nch; ch++)
            for (size_t k = 0; k < nout; k++) {
                sl_buf_puts(out, ",");
                sl_buf_printf(out, fmt, y[(size_t)ch * n * nout + r * nout + k]);
            }
        sl_buf_puts(out, "\n");
    }
}

/* Where the output goes until it is complete: the atomic temporary of --output FILE, or for
 * stdout a temporary file in $TMPDIR (else /tmp), unlinked at once so nothing is left behind
 * whatever happens, copied to stdout at the end. */
typedef struct eval_sink {
    sl_atomic_file af;
    int atomic;
    FILE *fp;
} eval_sink;

static int sink_open(const eval_opts *o, eval_sink *k, sl_err *e) {
    memset(k, 0, sizeof *k);
    if (o->output) {
        if (sl_make_parent_dirs(o->output, e) || sl_atomic_open(&k->af, o->output, e)) return -1;
        k->atomic = 1;
        k->fp = k->af.fp;
        return 0;
    }
    const char *dir = getenv("TMPDIR");
    char path[4200];
    snprintf(path, sizeof path, "%s/strandlight-eval-XXXXXX", dir && dir[0] ? dir : "/tmp");
    int fd = mkstemp(path);
    if (fd < 0) return sl_fail(e, "%s: cannot create a temporary file for the output", path);
    unlink(path);
    k->fp = fdopen(fd, "w+b");
    if (!k->fp) {
        close(fd);
        return sl_fail(e, "%s: cannot open the temporary file for the output", path);
    }
    return 0;
}

static int sink_write(eval_sink *k, const sl_buf *b, sl_err *e) {
    if (b->len && fwrite(b->p, 1, b->len, k->fp) != b->len)
        return sl_fail(e, "%s: write error", k->atomic ? k->af.path : "temporary output file");
    return 0;
}

/* Makes the output appear: renames --output's temporary over FILE, or copies to stdout. */
static int sink_commit(eval_sink *k, sl_err *e) {
    if (k->atomic) {
        k->atomic = 0;
        k->fp = NULL;
        return sl_atomic_commit(&k->af, e);
    }
    if (fflush(k->fp) != 0 || ferror(k->fp) || fseek(k->fp, 0, SEEK_SET) != 0)
        return sl_fail(e, "temporary output file: write error");
    char buf[65536];
    size_t got;
    while ((got = fread(buf, 1, sizeof buf, k->fp)) > 0)
        if (fwrite(buf, 1, got, stdout) != got) return sl_fail(e, "write error on standard output");
    if (ferror(k->fp)) return sl_fail(e, "temporary output file: read error");
    if (fflush(stdout) != 0 || ferror(stdout)) return sl_fail(e, "write error on standard output");
    return 0;
}

static void sink_abort(eval_sink *k) {
    if (k->atomic)
        sl_atomic_abort(&k->af);
    else if (k->fp)
        fclose(k->fp);
    memset(k, 0, sizeof *k);
}

static size_t chunk_rows(void) {
    const char *v = getenv("SL_EVAL_CHUNK_ROWS");
    if (v && *v) {
        char *end;
        long n = strtol(v, &end, 10);
        if (!*end && n >= 1) return (size_t)n;
    }
    return EVAL_CHUNK_ROWS;
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
    if (o.output) { /* as render's and reference's outputs: before any work (robustness.md 5) */
        const char *inputs[2];
        int ni = 0;
        if (o.material) inputs[ni++] = o.material;
        if (o.scene) inputs[ni++] = o.scene;
        if (sl_output_precheck(o.output, "-o", &e) ||
            sl_output_not_input(o.output, "-o", inputs, ni, &e))
            return fail(&e);
    }

    sl_csv_reader rd;
    if (sl_csv_reader_open(&rd, stdin, "<stdin>", &e)) return fail(&e);
    const sl_csv *csv = &rd.csv;
    int col[8];
    eval_run run;
    memset(&run, 0, sizeof run);
    eval_sink sink = {0};
    int have_sink = 0;
    sl_buf out = {0};
    double *x = NULL, *y = NULL;
    const sl_eval_input *inputs;
    size_t cap = 0, nin = sl_eval_inputs(o.q, &inputs);
    size_t width = sl_eval_num_outputs(o.q, mp) * (size_t)sl_eval_num_channels(o.q, mp);
    size_t max_rows = chunk_rows();
    rc = 1;
    if (check_columns(&o, csv, mp, col, &e)) goto done;
    for (int first = 1;; first = 0) {
        if (sl_csv_reader_next(&rd, max_rows, &e)) goto done;
        size_t n = csv->nrows;
        if (!first && n == 0) break;
        if (n > cap) {
            cap = n;
            x = sl_realloc(x, cap * nin * sizeof *x);
            y = sl_realloc(y, cap * (width ? width : 1) * sizeof *y);
        }
        if (read_inputs(&o, csv, col, x, &e)) goto done;
        if (first) {
            if (run_open(&o, csv, x, &run, &e) || sink_open(&o, &sink, &e)) goto done;
            have_sink = 1;
            out.len = 0;
            format_header(&o, csv, mp, &out);
            if (sink_write(&sink, &out, &e)) goto done;
        }
        if (evaluate(&o, &run, csv, mp, x, y, &e)) goto done;
        out.len = 0;
        format_rows(&o, csv, mp, y, &out);
        if (sink_write(&sink, &out, &e)) goto done;
        run.row0 += n;
        if (n == 0) break;
    }
    if (sink_commit(&sink, &e)) goto done;
    rc = 0;
done:
    if (rc) fail(&e);
    if (have_sink) sink_abort(&sink);
    run_close(&run);
    sl_buf_free(&out);
    free(x);
    free(y);
    sl_csv_reader_close(&rd);
    return rc;
}
