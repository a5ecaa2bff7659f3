/* report_srbf.c: `strandlight report --kernel srbf` (see report_srbf.h, docs/srbf.md). */
#include "verify/report/report_srbf.h"

#include "cl/clrt.h"
#include "base/parallel.h"
#include "srbf_c.h"
#include "passes/shade/srbf_cl.h"
#include "srbf_ref.h"
#include "passes/shade/srbf_ren.h"
#include "passes/shade/srbf_tables.h"
#include "srbf_xu.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* CPU seconds of the whole process (every thread, PoCL's workers included): rates per CPU
 * second are rates per core, and unlike wall-clock rates they hold on a machine shared with
 * other jobs (docs/srbf.md, "Speed"). */
static double cpu_now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void sl_srbf_exact_compute(const sl_srbf_config *cfg, int n, int progress, sl_srbf_exact *out) {
    sl_progress p;
    if (progress) sl_progress_begin(&p, "exact SRBF reference");
    /* eccentric rows cost ~100x the others: weight the progress accordingly */
    double total = 0.0, done = 0.0;
    for (int i = 0; i < n; i++)
        total += cfg[i].material == 4 ? 100.0 : 1.0;
    for (int i = 0; i < n; i++) {
        sl_material m;
        sl_srbf_sample_material(cfg[i].material, &m);
        out[i].c = cfg[i];
        slref_srbf(&m, 0, cfg[i].theta_o, cfg[i].phi_o, cfg[i].theta_j, cfg[i].phi_j, cfg[i].lambda,
                   out[i].v);
        done += cfg[i].material == 4 ? 100.0 : 1.0;
        if (progress) sl_progress_update(&p, done / total);
    }
    if (progress) sl_progress_end(&p);
}

static int cmp_d(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Percentile q of sorted v[0..n-1] by linear interpolation between order statistics. */
static double pct(const double *v, int n, double q) {
    if (n <= 0) return 0.0;
    double r = q * (n - 1);
    int i = (int)r;
    if (i >= n - 1) return v[n - 1];
    return v[i] + (v[i + 1] - v[i]) * (r - i);
}

void sl_srbf_stats_of(const sl_srbf_exact *x, int n, const float *out, sl_srbf_stats *s) {
    double *v = sl_malloc((size_t)(n > 0 ? n : 1) * sizeof *v);
    for (int t = 0; t < 4; t++) {
        for (int i = 0; i < n; i++)
            v[i] = slref_srbf_error(out[4 * i + t], x[i].v[t], x[i].c.lambda);
        qsort(v, (size_t)n, sizeof *v, cmp_d);
        s->median[t] = pct(v, n, 0.5);
        s->p95[t] = pct(v, n, 0.95);
        s->max[t] = n ? v[n - 1] : 0.0;
    }
    int k = 0;
    for (int i = 0; i < n; i++)
        if (x[i].v[3] > 0.03 * slref_srbf_lobe_integral(x[i].c.lambda))
            v[k++] = slref_srbf_error(out[4 * i + 3], x[i].v[3], x[i].c.lambda);
    qsort(v, (size_t)k, sizeof *v, cmp_d);
    s->n_above = k;
    s->median_above = pct(v, k, 0.5);
    s->p95_above = pct(v, k, 0.95);
    free(v);
}

/* ---- running the methods ---- */

typedef struct run_ctx {
    const sl_srbf_exact *x;
    int n;
    float *in;  /* 5 per row, rows grouped by material */
    int *order; /* grouped row -> sample row */
    int start[SL_SRBF_SAMPLE_MATERIALS + 1];
    sl_fiber_params fp[SL_SRBF_SAMPLE_MATERIALS];
    sl_srbf_tables t;
    sl_cl *cl;
    int rep;       /* timing: each material's rows repeated rep times per batch */
    float *in_rep; /* the repeated rows (rep > 1) */
    float *out_rep;
    /* Ren 2010's table (method M_TABLE, docs/srbf_ren.md): one per sample material, resident on
     * the OpenCL device (ren_mem) for the opencl rows; out9: the lookups' 9 floats per row */
    sl_srbf_ren ren[SL_SRBF_SAMPLE_MATERIALS];
    cl_mem ren_mem[SL_SRBF_SAMPLE_MATERIALS];
    float *out9;
} run_ctx;

/* The method code of the table rows (the closed forms use SL_SRBF_METHOD_*). */
#define M_TABLE 100

/* n table rows of material g: out 4 floats per row (I_R, I_TT, I_TRT, I of channel 0, as
 * slc_srbf_batch writes them). OpenCL: the table stays resident, rows and results travel. */
static int table_rows(run_ctx *r, int g, size_t n, const float *in, float *out, sl_err *e) {
    if (r->cl) {
        if (slcl_srbf_ren_rows(r->cl, &r->ren[g], &r->ren_mem[g], "clCreateBuffer", n, in, r->out9,
                               e))
            return -1;
    } else {
        slc_srbf_ren_batch(&r->ren[g], n, in, r->out9);
    }
    for (size_t i = 0; i < n; i++) {
        const float *o = r->out9 + 9 * i;
        out[4 * i] = o[0];
        out[4 * i + 1] = o[3];
        out[4 * i + 2] = o[6];
        out[4 * i + 3] = o[0] + o[3] + o[6];
    }
    return 0;
}

/* One pass over the sample; out in sample order. */
static int run_once(run_ctx *r, int method, int seg, float *tmp, float *out, sl_err *e) {
    for (int g = 0; g < SL_SRBF_SAMPLE_MATERIALS; g++) {
        size_t a = (size_t)r->start[g], cnt = (size_t)(r->start[g + 1] - r->start[g]);
        if (!cnt) continue;
        if (method == M_TABLE) {
            if (table_rows(r, g, cnt, r->in + 5 * a, tmp + 4 * a, e)) return -1;
        } else if (r->cl) {
            if (slcl_srbf_batch(r->cl, &r->fp[g], &r->t, method, seg, cnt, r->in + 5 * a,
                                tmp + 4 * a, e))
                return -1;
        } else
            slc_srbf_batch(&r->fp[g], r->t.C, r->t.H, method, seg, cnt, r->in + 5 * a, tmp + 4 * a);
    }
    for (int i = 0; i < r->n; i++)
        memcpy(out + 4 * r->order[i], tmp + 4 * i, 4 * sizeof(float));
    return 0;
}

/* One timing pass with every material's rows repeated r->rep times (outputs discarded). */
static int run_rep(run_ctx *r, int method, int seg, sl_err *e) {
    for (int g = 0; g < SL_SRBF_SAMPLE_MATERIALS; g++) {
        size_t a = (size_t)r->start[g], cnt = (size_t)(r->start[g + 1] - r->start[g]);
        if (!cnt) continue;
        for (int k = 0; k < r->rep; k++)
            memcpy(r->in_rep + 5 * cnt * k, r->in + 5 * a, 5 * cnt * sizeof(float));
        size_t m = cnt * (size_t)r->rep;
        if (method == M_TABLE) {
            if (table_rows(r, g, m, r->in_rep, r->out_rep, e)) return -1;
        } else if (r->cl) {
            if (slcl_srbf_batch(r->cl, &r->fp[g], &r->t, method, seg, m, r->in_rep, r->out_rep, e))
                return -1;
        } else
            slc_srbf_batch(&r->fp[g], r->t.C, r->t.H, method, seg, m, r->in_rep, r->out_rep);
    }
    return 0;
}

typedef struct result {
    const char *method, *backend;
    int seg;
    sl_srbf_stats s;
    double evals_per_s;     /* wall clock */
    double evals_per_cpu_s; /* per CPU second of the process: per core */
    sl_srbf_stats vs_fast;  /* table rows: against the C fast closed form it was built from */
} result;

static int measure(run_ctx *r, int method, int seg, double min_time, result *res, sl_err *e) {
    float *tmp = sl_malloc((size_t)r->n * 4 * sizeof(float));
    float *out = sl_malloc((size_t)r->n * 4 * sizeof(float));
    int rc = run_once(r, method, seg, tmp, out, e); /* also warms up (kernel build) */
    if (!rc) sl_srbf_stats_of(r->x, r->n, out, &res->s);
    if (!rc && method == M_TABLE) {
        /* the table's own error: against the C fast closed form, as the "exact" values */
        sl_cl *cl = r->cl;
        float *fo = sl_malloc((size_t)r->n * 4 * sizeof(float));
        sl_srbf_exact *fx = sl_malloc((size_t)r->n * sizeof *fx);
        r->cl = NULL;
        rc = run_once(r, SL_SRBF_METHOD_FAST, 0, tmp, fo, e);
        r->cl = cl;
        for (int i = 0; i < r->n; i++) {
            fx[i] = r->x[i];
            for (int t = 0; t < 4; t++)
                fx[i].v[t] = fo[4 * i + t];
        }
        if (!rc) sl_srbf_stats_of(fx, r->n, out, &res->vs_fast);
        free(fo);
        free(fx);
    }
    double t0 = sl_now(), c0 = cpu_now(), el = 0.0;
    long evals = 0;
    while (!rc && el < min_time) {
        if (r->rep > 1)
            rc = run_rep(r, method, seg, e);
        else
            rc = run_once(r, method, seg, tmp, out, e);
        evals += (long)r->n * r->rep;
        el = sl_now() - t0;
    }
    double cpu = cpu_now() - c0;
    res->evals_per_s = el > 0.0 ? (double)evals / el : 0.0;
    res->evals_per_cpu_s = cpu > 0.0 ? (double)evals / cpu : 0.0;
    free(tmp);
    free(out);
    return rc;
}

/* ---- extra rates of the fast path: 2 C threads, the RGB batch, PoCL generic vs -D ---- */

typedef struct xjob {
    const run_ctx *r;
    int rgb;    /* 1: slc_srbf_rgb_batch with 3 distinct sigma_a per row */
    float *sig; /* 3 per sample row (rgb) */
    float *out; /* 9 per sample row */
    double min_time;
    long rows;
} xjob;

static void xjob_time(xjob *j) {
    const run_ctx *r = j->r;
    double t0 = sl_now();
    j->rows = 0;
    while (sl_now() - t0 < j->min_time) {
        for (int g = 0; g < SL_SRBF_SAMPLE_MATERIALS; g++) {
            size_t a = (size_t)r->start[g], cnt = (size_t)(r->start[g + 1] - r->start[g]);
            if (!cnt) continue;
            if (j->rgb)
                slc_srbf_rgb_batch(&r->fp[g], r->t.C, r->t.H, SL_SRBF_METHOD_FAST, 4, cnt,
                                   r->in + 5 * a, j->sig + 3 * a, j->out + 9 * a);
            else
                slc_srbf_batch(&r->fp[g], r->t.C, r->t.H, SL_SRBF_METHOD_FAST, 4, cnt,
                               r->in + 5 * a, j->out + 4 * a);
        }
        j->rows += r->n;
    }
}

/* Jobs begin .. end - 1 (one a part): each repeats the whole sample for min_time. */
static void xjob_run(void *arg, size_t begin, size_t end, int part) {
    (void)part;
    for (size_t k = begin; k < end; k++)
        xjob_time((xjob *)arg + k);
}

/* rows/s (wall) and rows per CPU second over nt threads. */
static void xrates(const run_ctx *r, int rgb, int nt, float *sig, double min_time, double *wall,
                   double *per_core) {
    enum { MAXT = 2 };
    xjob j[MAXT];
    double t0 = sl_now(), c0 = cpu_now();
    for (int k = 0; k < nt; k++)
        j[k] = (xjob){r, rgb, sig, sl_malloc((size_t)r->n * 9 * sizeof(float)), min_time, 0};
    sl_parallel_parts(nt, (size_t)nt, xjob_run, j);
    double el = sl_now() - t0, cpu = cpu_now() - c0;
    long rows = 0;
    for (int k = 0; k < nt; k++) {
        rows += j[k].rows;
        free(j[k].out);
    }
    *wall = el > 0 ? (double)rows / el : 0.0;
    *per_core = cpu > 0 ? (double)rows / cpu : 0.0;
}

/* PoCL: sl_srbf_eval_rgb generic vs specialised, 64 copies of the sample per material batch. */
static int cl_rgb_rates(run_ctx *r, float *sig, double min_time, double rate[2], sl_err *e) {
    int rep = 64;
    float *sig_rep = sl_malloc((size_t)r->n * rep * 3 * sizeof(float));
    float *out = sl_malloc((size_t)r->n * rep * 9 * sizeof(float));
    int rc = 0;
    rate[0] = rate[1] = 0.0;
    for (int round = 0; round < 2 && !rc; round++)
        for (int generic = 1; generic >= 0 && !rc; generic--) {
            double t0 = sl_now(), el = 0.0;
            long rows = 0;
            int first = 1;
            while (!rc && el < min_time) {
                for (int g = 0; g < SL_SRBF_SAMPLE_MATERIALS && !rc; g++) {
                    size_t a = (size_t)r->start[g], cnt = (size_t)(r->start[g + 1] - r->start[g]);
                    if (!cnt) continue;
                    for (int k = 0; k < rep; k++) {
                        memcpy(r->in_rep + 5 * cnt * k, r->in + 5 * a, 5 * cnt * sizeof(float));
                        memcpy(sig_rep + 3 * cnt * k, sig + 3 * a, 3 * cnt * sizeof(float));
                    }
                    rc = slcl_srbf_rgb_batch_ex(r->cl, &r->fp[g], &r->t, SL_SRBF_METHOD_FAST, 4,
                                                cnt * rep, r->in_rep, sig_rep, out, generic, e);
                }
                if (first) { /* the first pass builds the programs: untimed */
                    first = 0;
                    t0 = sl_now();
                    continue;
                }
                rows += (long)r->n * rep;
                el = sl_now() - t0;
            }
            double v = el > 0 ? (double)rows / el : 0.0;
            if (v > rate[1 - generic]) rate[1 - generic] = v;
        }
    free(sig_rep);
    free(out);
    return rc;
}

static int print_extra_rates(run_ctx *r, double min_time, sl_err *e) {
    /* 3 distinct sigma_a per row, in the ratios of data/default.json (0.18 : 0.32 : 0.62) */
    float *sig = sl_malloc((size_t)r->n * 3 * sizeof(float));
    for (int g = 0; g < SL_SRBF_SAMPLE_MATERIALS; g++)
        for (int i = r->start[g]; i < r->start[g + 1]; i++) {
            float s0 = r->fp[g].sigma_a;
            sig[3 * i] = s0, sig[3 * i + 1] = s0 * 1.78f, sig[3 * i + 2] = s0 * 3.44f;
        }
    double w1, c1, w2, c2, wr, cr;
    xrates(r, 0, 1, sig, min_time, &w1, &c1);
    xrates(r, 0, 2, sig, min_time, &w2, &c2);
    xrates(r, 1, 1, sig, min_time, &wr, &cr);
    printf("\nfast, c: 1 thread %.3g lobe evals/s (%.3g per core); 2 threads %.3g/s (%.3g per "
           "core); RGB batch (slc_srbf_rgb_batch, 3 sigma_a per row, 1 thread) %.3g rows/s = "
           "%.3g channel evals/s (%.3g per core)\n",
           w1, c1, w2, c2, wr, 3.0 * wr, 3.0 * cr);
    int rc = 0;
    if (r->cl) {
        double rate[2];
        rc = cl_rgb_rates(r, sig, min_time, rate, e);
        if (!rc)
            printf("fast, opencl RGB batch (sl_srbf_eval_rgb, 64 copies per batch, uploads "
                   "included): generic build %.3g rows/s, -D specialised %.3g rows/s (x%.2f)\n",
                   rate[0], rate[1], rate[0] > 0 ? rate[1] / rate[0] : 0.0);
    }
    free(sig);
    return rc;
}

/* ---- SVG: error (median and p95 of I) against nanoseconds per lobe evaluation ---- */

static double lx(double v, double lo, double hi, double a, double b) {
    return a + (log10(v) - log10(lo)) / (log10(hi) - log10(lo)) * (b - a);
}

static int write_svg(const char *path, const result *r, int nr, sl_err *e) {
    double tlo = 1e30, thi = 0.0, elo = 1e-4, ehi = 10.0;
    for (int i = 0; i < nr; i++)
        if (r[i].evals_per_s > 0.0) {
            double ns = 1e9 / r[i].evals_per_s;
            tlo = fmin(tlo, ns);
            thi = fmax(thi, ns);
        }
    if (!(thi > 0.0)) tlo = 1.0, thi = 10.0;
    tlo = pow(10.0, floor(log10(tlo)));
    thi = pow(10.0, ceil(log10(thi)));
    if (thi <= tlo) thi = tlo * 10.0;
    const double X0 = 70, X1 = 620, Y0 = 380, Y1 = 30;
    sl_atomic_file af;
    if (sl_atomic_open(&af, path, e)) return -1;
    FILE *f = af.fp;
    fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"760\" height=\"440\" "
               "font-family=\"sans-serif\" font-size=\"11\">\n"
               "<rect width=\"760\" height=\"440\" fill=\"white\"/>\n");
    for (double d = elo; d <= ehi * 1.001; d *= 10.0) {
        double y = lx(d, elo, ehi, Y0, Y1);
        fprintf(f,
                "<line x1=\"%g\" y1=\"%.1f\" x2=\"%g\" y2=\"%.1f\" stroke=\"#ddd\"/>"
                "<text x=\"%g\" y=\"%.1f\" text-anchor=\"end\">%g</text>\n",
                X0, y, X1, y, X0 - 4, y + 4, d);
    }
    for (double d = tlo; d <= thi * 1.001; d *= 10.0) {
        double x = lx(d, tlo, thi, X0, X1);
        fprintf(f,
                "<line x1=\"%.1f\" y1=\"%g\" x2=\"%.1f\" y2=\"%g\" stroke=\"#ddd\"/>"
                "<text x=\"%.1f\" y=\"%g\" text-anchor=\"middle\">%g</text>\n",
                x, Y0, x, Y1, x, Y0 + 14, d);
    }
    fprintf(f,
            "<text x=\"%g\" y=\"%g\" text-anchor=\"middle\">ns per lobe evaluation (log)</text>\n"
            "<text x=\"14\" y=\"%g\" transform=\"rotate(-90 14 %g)\" text-anchor=\"middle\">"
            "error of I, numerics.md sec. 5 (log)</text>\n"
            "<text x=\"%g\" y=\"18\" text-anchor=\"middle\">SRBF closed forms vs exact: "
            "filled = p95, open = median</text>\n",
            0.5 * (X0 + X1), Y0 + 32, 0.5 * (Y0 + Y1), 0.5 * (Y0 + Y1), 0.5 * (X0 + X1));
    for (int i = 0; i < nr; i++) {
        if (!(r[i].evals_per_s > 0.0)) continue;
        double x = lx(1e9 / r[i].evals_per_s, tlo, thi, X0, X1);
        int fast = strcmp(r[i].method, "fast") == 0, ocl = strcmp(r[i].backend, "opencl") == 0;
        int tab = strcmp(r[i].method, "table") == 0;
        const char *col = tab    ? (ocl ? "#7b4173" : "#e377c2")
                          : fast ? (ocl ? "#d62728" : "#ff7f0e")
                                 : (ocl ? "#1f77b4" : "#2ca02c");
        double p = fmax(fmin(r[i].s.p95[3], ehi), elo), m = fmax(fmin(r[i].s.median[3], ehi), elo);
        double yp = lx(p, elo, ehi, Y0, Y1), ym = lx(m, elo, ehi, Y0, Y1);
        fprintf(f,
                "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"%s\"/>"
                "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"none\" stroke=\"%s\"/>"
                "<text x=\"%.1f\" y=\"%.1f\" fill=\"%s\">%s%s%.0d</text>\n",
                x, yp, col, x, ym, col, x + 6, yp - 3, col,
                tab    ? "table"
                : fast ? "fast"
                       : "xu m=",
                "", fast || tab ? 0 : r[i].seg);
    }
    double ly = 60;
    const char *leg[6][2] = {{"#2ca02c", "xu, c"},    {"#1f77b4", "xu, opencl"},
                             {"#ff7f0e", "fast, c"},  {"#d62728", "fast, opencl"},
                             {"#e377c2", "table, c"}, {"#7b4173", "table, opencl"}};
    for (int k = 0; k < 6; k++, ly += 16)
        fprintf(f,
                "<circle cx=\"640\" cy=\"%g\" r=\"4\" fill=\"%s\"/><text x=\"650\" y=\"%g\">%s"
                "</text>\n",
                ly, leg[k][0], ly + 4, leg[k][1]);
    fprintf(f, "</svg>\n");
    if (ferror(f)) {
        sl_atomic_abort(&af);
        return sl_fail(e, "%s: write error", path);
    }
    return sl_atomic_commit(&af, e);
}

static int write_csv(const char *path, const result *r, int nr, int n, sl_err *e) {
    sl_atomic_file af;
    if (sl_atomic_open(&af, path, e)) return -1;
    fprintf(af.fp,
            "method,segments,backend,n,median,p95,max,median_R,p95_R,median_TT,p95_TT,"
            "median_TRT,p95_TRT,n_above_floor,median_above_floor,p95_above_floor,evals_per_s,"
            "evals_per_cpu_s\n");
    for (int i = 0; i < nr; i++) {
        const sl_srbf_stats *s = &r[i].s;
        fprintf(af.fp,
                "%s,%d,%s,%d,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%d,%.6g,%.6g,%.6g,%.6g\n",
                r[i].method, r[i].seg, r[i].backend, n, s->median[3], s->p95[3], s->max[3],
                s->median[0], s->p95[0], s->median[1], s->p95[1], s->median[2], s->p95[2],
                s->n_above, s->median_above, s->p95_above, r[i].evals_per_s, r[i].evals_per_cpu_s);
    }
    if (ferror(af.fp)) {
        sl_atomic_abort(&af);
        return sl_fail(e, "%s: write error", path);
    }
    return sl_atomic_commit(&af, e);
}

int sl_report_srbf(const sl_report_srbf_opts *o, sl_err *e) {
    int n = o->n > 0 ? o->n : 150;
    double min_time = o->min_time_s > 0.0 ? o->min_time_s : 0.3;
    sl_srbf_config *cfg = sl_malloc((size_t)n * sizeof *cfg);
    sl_srbf_exact *x = sl_malloc((size_t)n * sizeof *x);
    sl_srbf_sample(SL_SRBF_SAMPLE_SEED, n, cfg);
    int rc = 0;
    if (o->exact_in)
        rc = sl_srbf_exact_read(o->exact_in, cfg, n, x, e);
    else
        sl_srbf_exact_compute(cfg, n, 1, x);
    if (!rc && o->exact_out) rc = sl_srbf_exact_write(o->exact_out, x, n, e);
    run_ctx r;
    memset(&r, 0, sizeof r);
    r.x = x;
    r.n = n;
    r.in = sl_malloc((size_t)n * 5 * sizeof(float));
    r.order = sl_malloc((size_t)n * sizeof(int));
    int k = 0;
    for (int g = 0; g < SL_SRBF_SAMPLE_MATERIALS; g++) {
        r.start[g] = k;
        sl_material m;
        sl_srbf_sample_material(g, &m);
        sl_material_to_fiber(&m, 0, &r.fp[g]);
        for (int i = 0; i < n; i++)
            if (cfg[i].material == g) {
                float *p = r.in + 5 * k;
                p[0] = (float)cfg[i].theta_o;
                p[1] = (float)cfg[i].phi_o;
                p[2] = (float)cfg[i].theta_j;
                p[3] = (float)cfg[i].phi_j;
                p[4] = (float)cfg[i].lambda;
                r.order[k++] = i;
            }
    }
    r.start[SL_SRBF_SAMPLE_MATERIALS] = k;
    r.in_rep = sl_malloc((size_t)n * 64 * 5 * sizeof(float));
    r.out_rep = sl_malloc((size_t)n * 64 * 4 * sizeof(float));
    if (!rc) rc = sl_srbf_tables_get(&r.t, 1, e);
    /* one Ren table per sample material (built on the C path, or loaded from the disk cache) */
    r.out9 = sl_malloc((size_t)n * 64 * 9 * sizeof(float));
    int nren = 0;
    for (int g = 0; g < SL_SRBF_SAMPLE_MATERIALS && !rc; g++, nren++) {
        sl_material m;
        sl_srbf_sample_material(g, &m);
        sl_srbf_ren_params rp;
        sl_srbf_ren_params_default(&rp);
        rp.verbose = 1;
        rc = sl_srbf_ren_get(NULL, &m, &rp, &r.ren[g], e);
        if (rc) break;
    }
    result res[2 * (SL_SRBF_MAX_SEGMENTS + 2)];
    int nr = 0;
    sl_device dev;
    memset(&dev, 0, sizeof dev);
    int have_cl = 0;
    if (!rc && !(o->device && strcmp(o->device, "none") == 0)) {
        sl_err e2 = {{0}};
        if (sl_device_open(o->device ? o->device : "opencl", &dev, &e2) == 0 && dev.is_opencl)
            have_cl = 1;
        else
            sl_warn("report: no OpenCL rows: %s", e2.msg[0] ? e2.msg : "no OpenCL device");
    }
    /* Timing on a shared machine is noisy: three interleaved rounds over all methods, and each
     * method keeps its best rate (the least disturbed). */
    for (int round = 0; round < 3 && !rc; round++) {
        int k2 = 0;
        for (int b = 0; b < 1 + have_cl && !rc; b++) {
            r.cl = b ? dev.cl : NULL;
            r.rep = b ? 64 : 1; /* OpenCL: large batches, the per-call upload amortised */
            for (int mi = 0; mi <= SL_SRBF_MAX_SEGMENTS + 1 && !rc; mi++, k2++) {
                result q;
                memset(&q, 0, sizeof q);
                int tab = mi == SL_SRBF_MAX_SEGMENTS + 1;
                q.backend = b ? "opencl" : "c";
                q.method = tab ? "table" : mi == 0 ? "fast" : "xu";
                q.seg = tab ? 0 : mi;
                rc = measure(&r,
                             tab       ? M_TABLE
                             : mi == 0 ? SL_SRBF_METHOD_FAST
                                       : SL_SRBF_METHOD_XU,
                             tab ? 0 : mi, min_time / 3.0, &q, e);
                if (rc) break;
                if (round == 0)
                    res[nr++] = q;
                else {
                    if (q.evals_per_s > res[k2].evals_per_s) res[k2].evals_per_s = q.evals_per_s;
                    if (q.evals_per_cpu_s > res[k2].evals_per_cpu_s)
                        res[k2].evals_per_cpu_s = q.evals_per_cpu_s;
                }
            }
        }
    }
    if (!rc) {
        printf("SRBF closed forms against the exact reference: %d configurations of the stiff "
               "sample (seed %u, host/verify/report/srbf_sample.c); error of numerics.md sec. 5; "
               "%d rows have an "
               "exact I above the error floor\n\n",
               n, SL_SRBF_SAMPLE_SEED, nr ? res[0].s.n_above : 0);
        printf("| method | m | backend | I median | I p95 | I max | R p95 | TT p95 | TRT p95 | "
               "above floor: median | p95 | lobe evals/s | per core (CPU s) |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
        for (int i = 0; i < nr; i++) {
            const sl_srbf_stats *s = &res[i].s;
            printf("| %s | %s%.0d | %s | %.4f | %.4f | %.3f | %.4f | %.4f | %.4f | %.4f | %.4f | "
                   "%.3g | %.3g |\n",
                   res[i].method, res[i].seg ? "" : "-", res[i].seg, res[i].backend, s->median[3],
                   s->p95[3], s->max[3], s->p95[0], s->p95[1], s->p95[2], s->median_above,
                   s->p95_above, res[i].evals_per_s, res[i].evals_per_cpu_s);
        }
        printf("\nRen 2010's precomputed table (docs/srbf_ren.md; default size, one table per "
               "sample material, resident on the device for opencl): error against exact as "
               "above, and against the C fast closed form it is baked from\n\n"
               "| method | backend | I median | I p95 | I max | vs fast: median | p95 | max | "
               "lobe evals/s | per core (CPU s) |\n|---|---|---|---|---|---|---|---|---|---|\n");
        for (int i = 0; i < nr; i++) {
            if (strcmp(res[i].method, "table")) continue;
            const sl_srbf_stats *s = &res[i].s, *f = &res[i].vs_fast;
            printf("| table | %s | %.4f | %.4f | %.3f | %.4f | %.4f | %.3f | %.3g | %.3g |\n",
                   res[i].backend, s->median[3], s->p95[3], s->max[3], f->median[3], f->p95[3],
                   f->max[3], res[i].evals_per_s, res[i].evals_per_cpu_s);
        }
        if (have_cl)
            printf("\nopencl: %s (batches of 64 copies of the sample's rows per material; rates "
                   "include "
                   "the upload of rows and tables per batch)\n",
                   dev.name);
    }
    if (!rc) {
        r.cl = have_cl ? dev.cl : NULL;
        rc = print_extra_rates(&r, min_time / 3.0, e);
    }
    if (!rc && o->csv) rc = write_csv(o->csv, res, nr, n, e);
    if (!rc && o->svg) rc = write_svg(o->svg, res, nr, e);
    for (int g = 0; g < SL_SRBF_SAMPLE_MATERIALS; g++)
        slcl_srbf_ren_table_release(&r.ren_mem[g]);
    for (int g = 0; g < nren; g++)
        sl_srbf_ren_free(&r.ren[g]);
    free(r.out9);
    if (have_cl) sl_device_close(&dev);
    sl_srbf_tables_free(&r.t);
    free(r.in);
    free(r.in_rep);
    free(r.out_rep);
    free(r.order);
    free(cfg);
    free(x);
    return rc ? -1 : 0;
}
