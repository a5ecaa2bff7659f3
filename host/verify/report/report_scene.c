/* report_scene.c: `strandlight report SCENE.json` (see report_scene.h): reference once (cached),
 * the fast pipeline over a sweep of settings, error of each against the reference
 * (numerics.md sec. 6), results.csv + report.md + error_vs_time.svg written into a temporary
 * directory that is swapped in for the report directory at the end (report_dir.h). */
#include "verify/report/report_scene.h"

#include "scene/camera.h"
#include "cl/clrt.h"
#include "scene/env_lighting.h"
#include "plan/frame.h"
#include "io/hair/hair.h"
#include "io/image/image_write.h"
#include "verify/reference/reference.h"
#include "verify/reference/reference_path.h"
#include "verify/report/report_dir.h"
#include "scene/scene.h"
#include "scene/scene_inputs.h"
#include "srbf_c.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define MAX_RUNS 64
/* Full-mode defaults (docs/results.md "Settings and run times": measured so that a full report
 * of data/default.json takes about 10-15 min on 2 cores at low load). */
#define SL_REPORT_FULL_WIDTH 128
#define SL_REPORT_FULL_LIGHTS 512
#define SL_REPORT_FULL_AA 12
/* path-traced pixel reference: samples per pixel by mode (full, quick, tiny) */
#define SL_REPORT_FULL_SPP 256
#define SL_REPORT_QUICK_SPP 64
#define SL_REPORT_TINY_SPP 8
#define SL_REPORT_FULL_FRAG_LIGHTS 96
#define SL_REPORT_QUICK_FRAG_LIGHTS 32
#define MAX_LOBESETS 8

typedef struct run_cfg {
    int opencl; /* 0 c, 1 opencl */
    int method; /* SL_SRBF_METHOD_FAST or _XU */
    int lobes, layers, m, voxels;
    double kappa;
    int ms; /* SL_MS_ON / SL_MS_OFF / SL_MS_AUTO (asked) */
    /* diagnostics (full mode): frag_rate 1 = quality.shading_rate "fragment" (else the scene's),
     * split 1 = quality.broad_lobes "split" (else the scene's, default subdivide) */
    int frag_rate, split;
} run_cfg;

typedef struct run_res {
    run_cfg c;
    int ms_on; /* what the planner did */
    int lobes_used;
    double time_s, rel_rmse, p99, aov[4]; /* aov: R, TT, TRT, MS rel. RMSE, NAN when absent */
    double rel_rmse_4x4; /* rel. RMSE of 4 x 4 pixel block means (sl_image_error_blocks) */
    /* against the fragment reference (NAN when it was not rendered): rel. RMSE, p99, AOVs */
    double rel_rmse_frag, p99_frag, aov_frag[4];
    double rel_rmse_frag_4x4; /* the same on 4 x 4 block means */
    int pareto;
    int pareto_frag; /* on the Pareto front of (time, rel_rmse_frag) */
    int index;       /* run number, 1-based (heat_NN.png) */
    float *heat;     /* rgba heat map of the per-pixel relative error (heat_map) */
} run_res;

typedef struct lobeset {
    int count;
    sl_lobes l;
} lobeset;

/* ------------------------------------------------------------------------------ sweep */

static int cfg_equal(const run_cfg *a, const run_cfg *b) {
    return a->opencl == b->opencl && a->method == b->method && a->lobes == b->lobes &&
           a->layers == b->layers && a->m == b->m && a->voxels == b->voxels &&
           a->kappa == b->kappa && a->ms == b->ms && a->frag_rate == b->frag_rate &&
           a->split == b->split;
}

static int add_cfg(run_cfg *list, int n, run_cfg c) {
    for (int i = 0; i < n; i++)
        if (cfg_equal(&list[i], &c)) return n; /* no duplicates */
    if (n < MAX_RUNS) list[n++] = c;
    return n;
}

/* One-factor-at-a-time around the scene's own settings (the base), plus a cheap corner and
 * an expensive corner, on the C path; base and the cheap corner again on OpenCL. */
static int make_sweep(const sl_scene *s, int quick, int tiny, int have_cl, int lobes_fixed,
                      run_cfg *list) {
    run_cfg base = {0,        SL_SRBF_METHOD_FAST,    s->lobes, s->layers, s->segments_m, s->voxels,
                    s->kappa, s->multiple_scattering, 0,        0};
    int n = 0;
    run_cfg c;
    n = add_cfg(list, n, base);
    static const int lob_full[] = {10, 20, 40, 80}, lob_quick[] = {12, 48}, lob_tiny[] = {8};
    static const int lay_full[] = {1, 2, 4, 8}, lay_quick[] = {1, 8}, lay_tiny[] = {1};
    static const int m_full[] = {1, 2, 4, 8}, m_quick[] = {1, 4}, m_tiny[] = {1};
    static const double kap_full[] = {0.05, 0.25, 0.5, 1.0}, kap_quick[] = {0.1, 0.5};
    static const int vox_full[] = {16, 32, 64, 128}, vox_quick[] = {16, 32};
    const int *lob = tiny ? lob_tiny : quick ? lob_quick : lob_full;
    int nlob = tiny ? 1 : quick ? 2 : 4;
    const int *lay = tiny ? lay_tiny : quick ? lay_quick : lay_full;
    int nlay = tiny ? 1 : quick ? 2 : 4;
    const int *mm = tiny ? m_tiny : quick ? m_quick : m_full;
    int nm = tiny ? 1 : quick ? 2 : 4;
    const double *kap = quick || tiny ? kap_quick : kap_full;
    int nkap = tiny ? 0 : quick ? 2 : 4;
    const int *vox = quick || tiny ? vox_quick : vox_full;
    int nvox = tiny ? 0 : quick ? 2 : 4;
    for (int i = 0; i < nlob && !lobes_fixed; i++) {
        c = base, c.lobes = lob[i];
        n = add_cfg(list, n, c);
    }
    for (int i = 0; i < nlay; i++) {
        c = base, c.layers = lay[i];
        n = add_cfg(list, n, c);
    }
    /* Xu's form exists for the Marschner model only (deon and chiang shade with the fast path) */
    int xu_ok = s->material.model == SL_MODEL_MARSCHNER;
    for (int i = 0; i < nm && xu_ok; i++) {
        c = base, c.method = SL_SRBF_METHOD_XU, c.m = mm[i];
        n = add_cfg(list, n, c);
    }
    for (int i = 0; i < nkap; i++) {
        c = base, c.kappa = kap[i];
        n = add_cfg(list, n, c);
    }
    for (int i = 0; i < nvox; i++) {
        c = base, c.voxels = vox[i], c.ms = SL_MS_ON;
        n = add_cfg(list, n, c);
    }
    c = base, c.ms = SL_MS_OFF;
    n = add_cfg(list, n, c);
    c = base, c.ms = SL_MS_ON;
    n = add_cfg(list, n, c);
    /* cheap corner: fewest lobes, one layer, no MS */
    run_cfg cheap = base;
    if (!lobes_fixed) cheap.lobes = lob[0];
    cheap.layers = 1, cheap.ms = SL_MS_OFF;
    n = add_cfg(list, n, cheap);
    if (!tiny) {
        run_cfg rich = base;
        if (!lobes_fixed) rich.lobes = lob[nlob - 1];
        rich.layers = 8, rich.ms = SL_MS_ON;
        if (xu_ok) rich.method = SL_SRBF_METHOD_XU, rich.m = 8;
        n = add_cfg(list, n, rich);
    }
    if (!tiny && !quick) {
        /* what the fragment metric needs to tell apart: vertex-rate interpolation (auto picks
         * vertex shading when segments project short) and the broad-lobe subdivision */
        c = base, c.frag_rate = 1;
        n = add_cfg(list, n, c);
        c = base, c.split = 1;
        n = add_cfg(list, n, c);
    }
    if (have_cl) {
        c = base, c.opencl = 1;
        n = add_cfg(list, n, c);
        cheap.opencl = 1;
        n = add_cfg(list, n, cheap);
    }
    return n;
}

/* ------------------------------------------------------------------------------ errors */

/* Relative RMSE of one AOV (3 per pixel), masked by the beauty alphas of both images. */
static double aov_error(const float *x3, const float *xa, const float *r3, int rstride,
                        const float *ra, int w, int h) {
    size_t n = (size_t)w * h;
    float *x = sl_malloc(4 * n * sizeof(float)), *r = sl_malloc(4 * n * sizeof(float));
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 3; c++) {
            x[4 * i + c] = x3[3 * i + c];
            r[4 * i + c] = r3[(size_t)rstride * i + c];
        }
        x[4 * i + 3] = xa[4 * i + 3];
        r[4 * i + 3] = ra[4 * i + 3];
    }
    double rmse, rgb3[3], p99;
    sl_image_error(x, r, w, h, &rmse, rgb3, &p99);
    free(x);
    free(r);
    return rmse;
}

/* The per-pixel relative error of numerics.md sec. 6 (|x - ref|_2 / max(|ref|_2, 0.01 RMS of
 * |ref|_2 over hair pixels), as in sl_image_error) as an rgba image: log10 of the error from
 * -3 (black) over blue, red, yellow to 0 and above (white); pixels that are hair in neither
 * image are transparent. */
static float *heat_map(const sl_fbuf *f, const sl_reference_frame *ref) {
    size_t n = (size_t)f->width * f->height, nh = 0;
    double ref2 = 0;
    for (size_t i = 0; i < n; i++) {
        if (!(f->rgba[4 * i + 3] > 0) && !(ref->rgba[4 * i + 3] > 0)) continue;
        nh++;
        for (int c = 0; c < 3; c++)
            ref2 += (double)ref->rgba[4 * i + c] * ref->rgba[4 * i + c];
    }
    double fl = nh ? 0.01 * sqrt(ref2 / (double)nh) : 0;
    float *out = sl_malloc(4 * n * sizeof(float));
    for (size_t i = 0; i < n; i++) {
        float *o = out + 4 * i;
        o[0] = o[1] = o[2] = o[3] = 0;
        if (!(f->rgba[4 * i + 3] > 0) && !(ref->rgba[4 * i + 3] > 0)) continue;
        double d2 = 0, r2 = 0;
        for (int c = 0; c < 3; c++) {
            double d = (double)f->rgba[4 * i + c] - ref->rgba[4 * i + c];
            d2 += d * d, r2 += (double)ref->rgba[4 * i + c] * ref->rgba[4 * i + c];
        }
        double r = fmax(sqrt(r2), fl), err = r > 0 ? sqrt(d2) / r : (d2 > 0 ? 1.0 : 0.0);
        double u = err > 0 ? (log10(err) + 3.0) / 3.0 : 0.0; /* 1e-3 .. 1 -> 0 .. 1 */
        u = u < 0 ? 0 : u > 1 ? 1 : u;
        /* ramp: black -> blue -> red -> yellow -> white (values are linear; the PNG writer
         * applies the sRGB curve) */
        static const float ramp[5][3] = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {1, 1, 0}, {1, 1, 1}};
        double s = u * 4.0;
        int k = (int)s;
        if (k > 3) k = 3;
        double fr = s - k;
        for (int c = 0; c < 3; c++)
            o[c] = (float)(ramp[k][c] + fr * (ramp[k + 1][c] - ramp[k][c]));
        o[3] = 1;
    }
    return out;
}

/* rel. RMSE, p99 and per-AOV errors of frame f against one reference. */
static void measure_one(const sl_fbuf *f, const sl_reference_frame *ref, int model, int ms_on,
                        double *rmse, double *p99, double aov[4]) {
    double rgb3[3];
    sl_image_error(f->rgba, ref->rgba, f->width, f->height, rmse, rgb3, p99);
    for (int k = 0; k < 4; k++)
        aov[k] = NAN;
    /* per-mode AOVs name the same thing in both images only for Marschner (d'Eon: orders) */
    if (model == SL_MODEL_MARSCHNER)
        for (int k = 0; k < 3; k++)
            aov[k] = aov_error(f->mode[k], f->rgba, ref->mode_rgb + 3 * k, 9, ref->rgba, f->width,
                               f->height);
    if (ms_on && ref->ms)
        aov[3] = aov_error(f->mode[3], f->rgba, ref->ms_rgb, 3, ref->rgba, f->width, f->height);
}

/* Errors against the pixel reference (rel_rmse, p99, 4x4, aov) and, when given, the fragment
 * reference (rel_rmse_frag, p99_frag, aov_frag). */
static void measure(const sl_fbuf *f, const sl_reference_frame *ref,
                    const sl_reference_frame *ref_frag, int model, run_res *out) {
    measure_one(f, ref, model, out->ms_on, &out->rel_rmse, &out->p99, out->aov);
    sl_image_error_blocks(f->rgba, ref->rgba, f->width, f->height, 4, &out->rel_rmse_4x4, NULL);
    out->rel_rmse_frag = out->p99_frag = out->rel_rmse_frag_4x4 = NAN;
    for (int k = 0; k < 4; k++)
        out->aov_frag[k] = NAN;
    if (ref_frag) {
        measure_one(f, ref_frag, model, out->ms_on, &out->rel_rmse_frag, &out->p99_frag,
                    out->aov_frag);
        sl_image_error_blocks(f->rgba, ref_frag->rgba, f->width, f->height, 4,
                              &out->rel_rmse_frag_4x4, NULL);
    }
}

/* The error a front or a speed-up table is over: per pixel, 4x4 blocks (pixel reference) or
 * the fragment reference's. */
enum { MET_PIXEL = 0, MET_BLOCKS = 1, MET_FRAG = 2 };
static double metric(const run_res *r, int which) {
    return which == MET_FRAG     ? r->rel_rmse_frag
           : which == MET_BLOCKS ? r->rel_rmse_4x4
                                 : r->rel_rmse;
}

/* Pareto front over (time, error): no other run is at least as fast and as accurate and
 * strictly better in one. Writes pareto (MET_PIXEL) or pareto_frag (MET_FRAG). */
static void mark_pareto(run_res *r, int n, int which) {
    for (int i = 0; i < n; i++) {
        double ei = metric(&r[i], which);
        int front = isfinite(ei);
        for (int j = 0; j < n && front; j++) {
            double ej = metric(&r[j], which);
            if (j == i || !isfinite(ej)) continue;
            if (r[j].time_s <= r[i].time_s && ej <= ei && (r[j].time_s < r[i].time_s || ej < ei))
                front = 0;
        }
        if (which == MET_FRAG)
            r[i].pareto_frag = front;
        else
            r[i].pareto = front;
    }
}

/* ------------------------------------------------------------------------------ outputs */

static const char *method_name(int m) {
    return m == SL_SRBF_METHOD_XU ? "xu" : "fast";
}

static void fmt_num(char *b, size_t n, double v) {
    if (isfinite(v))
        snprintf(b, n, "%.6g", v);
    else
        b[0] = 0;
}

/* rr: the pixel reference, rf: the fragment reference (NULL when not rendered). */
static int write_csv(const char *path, const run_res *r, int n, const sl_reference_result *rr,
                     const sl_reference_result *rf, const sl_path_result *pr, int w, int h, int aa,
                     sl_err *e) {
    sl_atomic_file af;
    if (sl_atomic_open(&af, path, e)) return -1;
    FILE *f = af.fp;
    fprintf(f, "backend,method,lobes,layers,m,kappa,voxels,ms,time_s,rel_rmse,p99_rel_err,"
               "rel_rmse_4x4,rel_rmse_R,rel_rmse_TT,rel_rmse_TRT,rel_rmse_MS,lights,aa,width,"
               "height,pareto,rel_rmse_frag,p99_frag,rel_rmse_frag_R,rel_rmse_frag_TT,"
               "rel_rmse_frag_TRT,rel_rmse_frag_MS,pareto_frag,rel_rmse_frag_4x4,shading_rate,"
               "broad_lobes\n");
    if (pr) /* the path tracer: its own noise (even vs odd samples) in the error columns, spp as aa
             */
        fprintf(f, "reference_path,path,,,,,,on,%.6g,%.6g,,%.6g,,,,,,%d,%d,%d,0,,,,,,,0,,,\n",
                pr->wall_s, pr->noise, pr->noise_4x4, pr->spp, w, h);
    else
        fprintf(f, "reference,exact,,,,,,%s,%.6g,%.6g,%.6g,%.6g,,,,,%d,%d,%d,%d,0,,,,,,,0,,,\n",
                rr->ms ? "on" : "off", rr->time_s, rr->has_convergence ? rr->conv_rel_rmse : NAN,
                rr->has_convergence ? rr->conv_p99 : NAN,
                rr->has_convergence ? rr->conv_rel_rmse_4x4 : NAN, rr->lights, aa, w, h);
    if (rf) /* its own convergence (N vs 2N lights, same fragments) in both error columns */
        fprintf(
            f,
            "reference_fragments,exact,,,,,,%s,%.6g,%.6g,%.6g,%.6g,,,,,%d,,%d,%d,0,%.6g,%.6g,,,,"
            ",0,%.6g,,\n",
            rf->ms ? "on" : "off", rf->time_s, rf->has_convergence ? rf->conv_rel_rmse : NAN,
            rf->has_convergence ? rf->conv_p99 : NAN,
            rf->has_convergence ? rf->conv_rel_rmse_4x4 : NAN, rf->lights, w, h,
            rf->has_convergence ? rf->conv_rel_rmse : NAN, rf->has_convergence ? rf->conv_p99 : NAN,
            rf->has_convergence ? rf->conv_rel_rmse_4x4 : NAN);
    for (int i = 0; i < n; i++) {
        char a[4][32], fa[7][32];
        for (int k = 0; k < 4; k++) {
            fmt_num(a[k], sizeof a[k], r[i].aov[k]);
            fmt_num(fa[2 + k], sizeof fa[2 + k], r[i].aov_frag[k]);
        }
        fmt_num(fa[0], sizeof fa[0], r[i].rel_rmse_frag);
        fmt_num(fa[1], sizeof fa[1], r[i].p99_frag);
        fmt_num(fa[6], sizeof fa[6], r[i].rel_rmse_frag_4x4);
        fprintf(f,
                "%s,%s,%d,%d,%d,%.6g,%d,%s,%.6g,%.6g,%.6g,%.6g,%s,%s,%s,%s,,,%d,%d,%d,%s,%s,%s,%s,"
                "%s,%s,%d,%s,%s,%s\n",
                r[i].c.opencl ? "opencl" : "c", method_name(r[i].c.method), r[i].c.lobes,
                r[i].c.layers, r[i].c.method == SL_SRBF_METHOD_XU ? r[i].c.m : 0, r[i].c.kappa,
                r[i].c.voxels, r[i].ms_on ? "on" : "off", r[i].time_s, r[i].rel_rmse, r[i].p99,
                r[i].rel_rmse_4x4, a[0], a[1], a[2], a[3], w, h, r[i].pareto, fa[0], fa[1], fa[2],
                fa[3], fa[4], fa[5], r[i].pareto_frag, fa[6],
                r[i].c.frag_rate ? "fragment" : "scene", r[i].c.split ? "split" : "scene");
    }
    return sl_atomic_commit(&af, e);
}

static int cmp_time(const void *a, const void *b) {
    const run_res *x = a, *y = b;
    return (x->time_s > y->time_s) - (x->time_s < y->time_s);
}

static void run_settings(FILE *f, const run_res *r) {
    fprintf(f, "%s %s, %d lobes, K=%d, m=%d, kappa %g, voxels %d, MS %s%s%s",
            r->c.opencl ? "opencl" : "c", method_name(r->c.method), r->c.lobes, r->c.layers,
            r->c.method == SL_SRBF_METHOD_XU ? r->c.m : 0, r->c.kappa, r->c.voxels,
            r->ms_on ? "on" : "off", r->c.frag_rate ? ", shading_rate fragment" : "",
            r->c.split ? ", broad_lobes split" : "");
}

/* The fastest run (s sorted by time) with error <= level on metric `which`, -1 if none. */
static int fastest_within(const run_res *s, int n, int which, double level) {
    for (int i = 0; i < n; i++)
        if (metric(&s[i], which) <= level) return i;
    return -1;
}

/* Issue 10's target against one reference: its own convergence <= 1 %, and the fastest run at
 * <= 5 % rel. RMSE >= 1000 x faster than it. */
static void target_sentence(FILE *f, const char *what, const run_res *s, int n, int which,
                            const sl_reference_result *ref) {
    int b = fastest_within(s, n, which, 0.05);
    fprintf(f, "- Against the %s (own convergence %s): ", what,
            ref->has_convergence
                ? (ref->conv_rel_rmse <= 0.01 ? "<= 1 %, reached" : "above 1 %, not reached")
                : "not measured");
    if (ref->has_convergence) fprintf(f, "%.4g; ", ref->conv_rel_rmse);
    if (b < 0) {
        double best = INFINITY;
        for (int i = 0; i < n; i++)
            best = fmin(best, metric(&s[i], which));
        fprintf(f, "no run reaches <= 5 %% rel. RMSE (best %.4g): target **not met**.\n", best);
        return;
    }
    double sp = s[b].time_s > 0 ? ref->time_s / s[b].time_s : 0;
    int met = sp >= 1000 && ref->has_convergence && ref->conv_rel_rmse <= 0.01;
    fprintf(f,
            "fastest run at <= 5 %% rel. RMSE: %.3f s (%.4g), %.3g x faster than the "
            "reference's %.2f s: target **%s**.\n",
            s[b].time_s, metric(&s[b], which), sp, ref->time_s,
            met          ? "met"
            : sp >= 1000 ? "not met (the reference is not within 1 %)"
                         : "not met (speed-up below 1000 x)");
}

static int write_md(const char *path, const char *scene, const run_res *r, int n,
                    const sl_reference_result *rr, const sl_reference_result *rf,
                    const sl_path_result *pr, int w, int h, int aa, const char *mode,
                    const char *cl_name, sl_err *e) {
    sl_atomic_file af;
    if (sl_atomic_open(&af, path, e)) return -1;
    FILE *f = af.fp;
    fprintf(f, "# Report: %s\n\n", scene);
    fprintf(f,
            "Mode: %s, image %d x %d. Errors: numerics.md sec. 6 (relative RMSE over hair "
            "pixels, mean of R, G, B; p99 of the per-pixel relative error) against the "
            "references below; `4x4`: the same rel. RMSE on 4 x 4 pixel block means (systematic "
            "differences without pixel-level sampling noise, docs/results.md); `frag`: against "
            "the fragment reference (the fast path's own fragments, coverage and weights, "
            "shaded by the reference: shading error only). Times: wall "
            "seconds of one frame with a fresh renderer (every pass run, SRBF tables and fitted "
            "lobes from the disk cache).\n\n",
            mode, w, h);
    if (pr)
        fprintf(f,
                "## Reference\n\nPixel reference: the path tracer (`strandlight reference "
                "--path`: every bounce through the real fibers, the map sampled by importance, "
                "docs/reference.md \"Path tracer\"), %d samples per pixel, %.1f events per path, "
                "render time %.2f s wall, %.2f s CPU%s.\nIts own noise (even vs odd samples, the "
                "rel. RMSE of the full image's estimate): per pixel %.4g, 4x4 blocks %.4g, 8x8 "
                "blocks %.4g. Errors below these are not resolved by the reference.\n\n",
                pr->spp, pr->events_per_path, pr->wall_s, pr->cpu_s,
                pr->cached ? " (from the cache: the run that rendered it)" : "", pr->noise,
                pr->noise_4x4, pr->noise_8x8);
    else
        fprintf(f,
                "## Reference\n\nPixel reference: %d directional lights (median cut), %d x %d "
                "rays per pixel sharing the lights (light split), multiple scattering %s, render "
                "time %.2f s%s.\n",
                rr->lights, aa, aa, rr->ms ? "on" : "off", rr->time_s,
                rr->cached ? " (from the cache: time of the run that rendered it)" : "");
    if (!pr && rr->has_convergence)
        fprintf(f,
                "Own convergence (image at %d lights vs %d lights with another jitter seed: "
                "light cut and camera-ray sampling): rel. RMSE %.4g, p99 %.4g, 4x4 %.4g "
                "(render at 2N: %.2f s). Errors below this are not resolved by the "
                "reference.\n\n",
                rr->lights, 2 * rr->lights, rr->conv_rel_rmse, rr->conv_p99, rr->conv_rel_rmse_4x4,
                rr->time_2n_s);
    if (rf) {
        fprintf(f,
                "Fragment reference (row `reference_fragments`): the fast path's %.0f K-buffer "
                "entries (K %d) shaded with %d directional lights, exact fiber function, traced "
                "shadows%s, composited with the fast path's weights; render time %.2f s%s.\n",
                rf->entries, rf->oit_k, rf->lights,
                rf->ms ? ", dual scattering by ray shooting" : "", rf->time_s,
                rf->cached ? " (from the cache)" : "");
        if (rf->has_convergence)
            fprintf(f,
                    "Own convergence (the same fragments at %d vs %d lights: the light cut "
                    "alone): rel. RMSE %.4g, p99 %.4g, 4x4 %.4g (render at 2N: %.2f s).\n\n",
                    rf->lights, 2 * rf->lights, rf->conv_rel_rmse, rf->conv_p99,
                    rf->conv_rel_rmse_4x4, rf->time_2n_s);
    }
    fprintf(f, "OpenCL rows: %s.\n\n", cl_name);
    fprintf(f, "## Runs (sorted by time; * = Pareto front per pixel, f = front on frag)\n\n");
    fprintf(f, "| | backend | method | lobes | layers | m | kappa | voxels | MS | time s | rel. "
               "RMSE | p99 | 4x4 | R | TT | TRT | MS err | speed-up | frag | frag p99 | frag R | "
               "frag TT | frag TRT | frag MS | frag 4x4 | other |\n");
    fprintf(f, "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
               "---|---|---|---|---|---|\n");
    run_res *s = sl_malloc(sizeof(run_res) * (size_t)(n > 0 ? n : 1));
    memcpy(s, r, sizeof(run_res) * (size_t)n);
    qsort(s, (size_t)n, sizeof *s, cmp_time);
    for (int i = 0; i < n; i++) {
        char a[4][32], fa[7][32];
        for (int k = 0; k < 4; k++) {
            fmt_num(a[k], sizeof a[k], s[i].aov[k]);
            if (!a[k][0]) snprintf(a[k], sizeof a[k], "-");
            fmt_num(fa[2 + k], sizeof fa[2 + k], s[i].aov_frag[k]);
        }
        fmt_num(fa[0], sizeof fa[0], s[i].rel_rmse_frag);
        fmt_num(fa[1], sizeof fa[1], s[i].p99_frag);
        fmt_num(fa[6], sizeof fa[6], s[i].rel_rmse_frag_4x4);
        for (int k = 0; k < 7; k++)
            if (!fa[k][0]) snprintf(fa[k], sizeof fa[k], "-");
        char m[16];
        if (s[i].c.method == SL_SRBF_METHOD_XU)
            snprintf(m, sizeof m, "%d", s[i].c.m);
        else
            snprintf(m, sizeof m, "-");
        fprintf(f,
                "| %s%s | %s | %s | %d | %d | %s | %g | %d | %s | %.3f | %.4f | %.3f | %.4f | %s | "
                "%s | %s | %s | %.3g | %s | %s | %s | %s | %s | %s | %s | %s%s%s |\n",
                s[i].pareto ? "*" : "", s[i].pareto_frag ? "f" : "", s[i].c.opencl ? "opencl" : "c",
                method_name(s[i].c.method), s[i].c.lobes, s[i].c.layers, m, s[i].c.kappa,
                s[i].c.voxels, s[i].ms_on ? "on" : "off", s[i].time_s, s[i].rel_rmse, s[i].p99,
                s[i].rel_rmse_4x4, a[0], a[1], a[2], a[3],
                s[i].time_s > 0 ? rr->time_s / s[i].time_s : 0.0, fa[0], fa[1], fa[2], fa[3], fa[4],
                fa[5], fa[6], s[i].c.frag_rate ? "rate fragment" : "",
                s[i].c.frag_rate && s[i].c.split ? ", " : "", s[i].c.split ? "broad split" : "");
    }
    fprintf(f, "\n## Pareto front (time against rel. RMSE)\n\nPlot: error_vs_time.svg; "
               "reference images: reference.png (pixel), reference_fragments.png; error heat "
               "maps against the pixel reference (log10 of the per-pixel "
               "relative error, black 1e-3, blue, red, yellow, white >= 1): heat_NN.png.\n\n"
               "| time s | rel. RMSE | heat map | settings |\n|---|---|---|---|\n");
    for (int i = 0; i < n; i++)
        if (s[i].pareto) {
            fprintf(f, "| %.3f | %.4f | heat_%02d.png | ", s[i].time_s, s[i].rel_rmse, s[i].index);
            run_settings(f, &s[i]);
            fprintf(f, " |\n");
        }
    if (rf) {
        fprintf(f, "\n## Pareto front on the fragment metric (shading error only)\n\n"
                   "| time s | rel. RMSE (frag) | p99 (frag) | settings |\n|---|---|---|---|\n");
        for (int i = 0; i < n; i++)
            if (s[i].pareto_frag) {
                fprintf(f, "| %.3f | %.4f | %.3f | ", s[i].time_s, s[i].rel_rmse_frag,
                        s[i].p99_frag);
                run_settings(f, &s[i]);
                fprintf(f, " |\n");
            }
    }
    fprintf(f, "\n## Speed-up over the reference at each error level\n\n"
               "Per pixel and 4x4 blocks: against the pixel reference (speed-up over its time); "
               "frag: against the fragment reference (speed-up over its time).\n\n"
               "| error <= | per pixel: fastest run | its error | speed-up | 4x4 blocks: fastest "
               "run | its error | speed-up | frag: fastest run | its error | speed-up |\n"
               "|---|---|---|---|---|---|---|---|---|---|\n");
    static const double levels[] = {0.5, 0.2, 0.1, 0.05, 0.02, 0.01};
    for (int l = 0; l < 6; l++) {
        fprintf(f, "| %g |", levels[l]);
        for (int which = 0; which < 3; which++) {
            const sl_reference_result *ref = which == MET_FRAG ? rf : rr;
            int best = ref ? fastest_within(s, n, which, levels[l]) : -1;
            if (best < 0)
                fprintf(f, " none | - | - |");
            else
                fprintf(f, " %.3f s | %.4f | %.3g x |", s[best].time_s, metric(&s[best], which),
                        ref->time_s / s[best].time_s);
        }
        fprintf(f, "\n");
    }
    fprintf(f, "\n(pixel reference: %.2f s", rr->time_s);
    if (rf) fprintf(f, "; fragment reference: %.2f s", rf->time_s);
    fprintf(f, ")\n");
    fprintf(f,
            "\n## Target\n\nIssue 10: at <= 5 %% rel. RMSE >= 1000 x faster than a reference that "
            "reaches <= 1 %% on its own convergence.\n\n");
    target_sentence(f, "pixel reference", s, n, MET_PIXEL, rr);
    if (rf) target_sentence(f, "fragment reference", s, n, MET_FRAG, rf);
    free(s);
    return sl_atomic_commit(&af, e);
}

/* log-log plot of rel. RMSE against time: every run grey, the front red and joined, the
 * reference (its time, its own convergence error) as a blue square; the fragment metric as
 * purple diamonds (its front joined), the fragment reference as a purple diamond outline. */
static int write_svg(const char *path, const run_res *r, int n, const sl_reference_result *rr,
                     const sl_reference_result *rf, sl_err *e) {
    double tmin = INFINITY, tmax = -INFINITY, emin = INFINITY, emax = -INFINITY;
    for (int i = 0; i < n; i++) {
        if (!(r[i].time_s > 0) || !(r[i].rel_rmse > 0)) continue;
        tmin = fmin(tmin, r[i].time_s), tmax = fmax(tmax, r[i].time_s);
        emin = fmin(emin, r[i].rel_rmse), emax = fmax(emax, r[i].rel_rmse);
        if (r[i].rel_rmse_4x4 > 0)
            emin = fmin(emin, r[i].rel_rmse_4x4), emax = fmax(emax, r[i].rel_rmse_4x4);
        if (r[i].rel_rmse_frag > 0)
            emin = fmin(emin, r[i].rel_rmse_frag), emax = fmax(emax, r[i].rel_rmse_frag);
    }
    int fragp = rf && rf->time_s > 0 && rf->has_convergence && rf->conv_rel_rmse > 0;
    if (fragp) {
        tmin = fmin(tmin, rf->time_s), tmax = fmax(tmax, rf->time_s);
        emin = fmin(emin, rf->conv_rel_rmse), emax = fmax(emax, rf->conv_rel_rmse);
    }
    int refp = rr->time_s > 0 && rr->has_convergence && rr->conv_rel_rmse > 0;
    if (refp) {
        tmin = fmin(tmin, rr->time_s), tmax = fmax(tmax, rr->time_s);
        emin = fmin(emin, rr->conv_rel_rmse), emax = fmax(emax, rr->conv_rel_rmse);
        if (rr->conv_rel_rmse_4x4 > 0)
            emin = fmin(emin, rr->conv_rel_rmse_4x4), emax = fmax(emax, rr->conv_rel_rmse_4x4);
    }
    if (!isfinite(tmin)) tmin = 0.1, tmax = 1, emin = 0.01, emax = 1;
    double lt0 = floor(log10(tmin)), lt1 = ceil(log10(tmax));
    double le0 = floor(log10(emin)), le1 = ceil(log10(emax));
    if (lt1 <= lt0) lt1 = lt0 + 1;
    if (le1 <= le0) le1 = le0 + 1;
    const double W = 640, H = 440, x0 = 70, x1 = 620, y0 = 20, y1 = 390;
#define PX(t) (x0 + (log10(t) - lt0) / (lt1 - lt0) * (x1 - x0))
#define PY(v) (y1 - (log10(v) - le0) / (le1 - le0) * (y1 - y0))
    sl_atomic_file af;
    if (sl_atomic_open(&af, path, e)) return -1;
    FILE *f = af.fp;
    fprintf(f,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%g\" height=\"%g\" "
            "font-family=\"sans-serif\" font-size=\"12\">\n",
            W, H);
    fprintf(f, "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n");
    fprintf(f,
            "<rect x=\"%g\" y=\"%g\" width=\"%g\" height=\"%g\" fill=\"none\" "
            "stroke=\"black\"/>\n",
            x0, y0, x1 - x0, y1 - y0);
    for (double d = lt0; d <= lt1 + 0.5; d += 1) {
        double x = x0 + (d - lt0) / (lt1 - lt0) * (x1 - x0);
        fprintf(f,
                "<line x1=\"%.1f\" y1=\"%g\" x2=\"%.1f\" y2=\"%g\" stroke=\"#ddd\"/>"
                "<text x=\"%.1f\" y=\"%g\" text-anchor=\"middle\">%g</text>\n",
                x, y0, x, y1, x, y1 + 16, pow(10, d));
    }
    for (double d = le0; d <= le1 + 0.5; d += 1) {
        double y = y1 - (d - le0) / (le1 - le0) * (y1 - y0);
        fprintf(f,
                "<line x1=\"%g\" y1=\"%.1f\" x2=\"%g\" y2=\"%.1f\" stroke=\"#ddd\"/>"
                "<text x=\"%g\" y=\"%.1f\" text-anchor=\"end\">%g</text>\n",
                x0, y, x1, y, x0 - 4, y + 4, pow(10, d));
    }
    fprintf(f, "<text x=\"%g\" y=\"%g\" text-anchor=\"middle\">time per frame (s)</text>\n",
            0.5 * (x0 + x1), H - 12);
    fprintf(f,
            "<text x=\"16\" y=\"%g\" text-anchor=\"middle\" transform=\"rotate(-90 16 %g)\">"
            "relative RMSE</text>\n",
            0.5 * (y0 + y1), 0.5 * (y0 + y1));
    run_res *s = sl_malloc(sizeof(run_res) * (size_t)(n > 0 ? n : 1));
    memcpy(s, r, sizeof(run_res) * (size_t)n);
    qsort(s, (size_t)n, sizeof *s, cmp_time);
    fprintf(f, "<polyline fill=\"none\" stroke=\"#d62728\" stroke-width=\"1.5\" points=\"");
    for (int i = 0; i < n; i++)
        if (s[i].pareto && s[i].time_s > 0 && s[i].rel_rmse > 0)
            fprintf(f, "%.1f,%.1f ", PX(s[i].time_s), PY(s[i].rel_rmse));
    fprintf(f, "\"/>\n");
    for (int i = 0; i < n; i++) /* 4x4 block errors: hollow, under the per-pixel markers */
        if (s[i].time_s > 0 && s[i].rel_rmse_4x4 > 0)
            fprintf(f,
                    "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3\" fill=\"none\" stroke=\"%s\">"
                    "<title>4x4 blocks: %.4f</title></circle>\n",
                    PX(s[i].time_s), PY(s[i].rel_rmse_4x4),
                    s[i].pareto ? "#d62728" : (s[i].c.opencl ? "#2ca02c" : "#888"),
                    s[i].rel_rmse_4x4);
    for (int i = 0; i < n; i++) {
        if (!(s[i].time_s > 0) || !(s[i].rel_rmse > 0)) continue;
        fprintf(f,
                "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"%d\" fill=\"%s\"><title>%s %s lobes %d "
                "K %d m %d kappa %g voxels %d MS %s: %.3f s, %.4f</title></circle>\n",
                PX(s[i].time_s), PY(s[i].rel_rmse), s[i].pareto ? 5 : 3,
                s[i].pareto ? "#d62728" : (s[i].c.opencl ? "#2ca02c" : "#888"),
                s[i].c.opencl ? "opencl" : "c", method_name(s[i].c.method), s[i].c.lobes,
                s[i].c.layers, s[i].c.method == SL_SRBF_METHOD_XU ? s[i].c.m : 0, s[i].c.kappa,
                s[i].c.voxels, s[i].ms_on ? "on" : "off", s[i].time_s, s[i].rel_rmse);
    }
    if (refp)
        fprintf(f,
                "<rect x=\"%.1f\" y=\"%.1f\" width=\"10\" height=\"10\" fill=\"#1f77b4\">"
                "<title>reference: %d lights, %.2f s, own convergence %.4f</title></rect>\n"
                "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">reference</text>\n",
                PX(rr->time_s) - 5, PY(rr->conv_rel_rmse) - 5, rr->lights, rr->time_s,
                rr->conv_rel_rmse, PX(rr->time_s) - 8, PY(rr->conv_rel_rmse) - 8);
    /* fragment metric: purple diamonds, front joined */
    fprintf(f, "<polyline fill=\"none\" stroke=\"#9467bd\" stroke-width=\"1\" "
               "stroke-dasharray=\"4 3\" points=\"");
    for (int i = 0; i < n; i++)
        if (s[i].pareto_frag && s[i].time_s > 0 && s[i].rel_rmse_frag > 0)
            fprintf(f, "%.1f,%.1f ", PX(s[i].time_s), PY(s[i].rel_rmse_frag));
    fprintf(f, "\"/>\n");
    for (int i = 0; i < n; i++)
        if (s[i].time_s > 0 && s[i].rel_rmse_frag > 0) {
            double cx = PX(s[i].time_s), cy = PY(s[i].rel_rmse_frag),
                   d = s[i].pareto_frag ? 5 : 3.5;
            fprintf(f,
                    "<polygon points=\"%.1f,%.1f %.1f,%.1f %.1f,%.1f %.1f,%.1f\" fill=\"#9467bd\">"
                    "<title>fragment reference: %.4f</title></polygon>\n",
                    cx, cy - d, cx + d, cy, cx, cy + d, cx - d, cy, s[i].rel_rmse_frag);
        }
    if (fragp) {
        double cx = PX(rf->time_s), cy = PY(rf->conv_rel_rmse);
        fprintf(f,
                "<polygon points=\"%.1f,%.1f %.1f,%.1f %.1f,%.1f %.1f,%.1f\" fill=\"none\" "
                "stroke=\"#9467bd\" stroke-width=\"2\"><title>fragment reference: %d lights, %.2f "
                "s, own convergence %.4f</title></polygon>\n<text x=\"%.1f\" y=\"%.1f\" "
                "text-anchor=\"end\">fragment reference</text>\n",
                cx, cy - 7, cx + 7, cy, cx, cy + 7, cx - 7, cy, rf->lights, rf->time_s,
                rf->conv_rel_rmse, cx - 9, cy + 16);
    }
    if (refp && rr->conv_rel_rmse_4x4 > 0)
        fprintf(f,
                "<rect x=\"%.1f\" y=\"%.1f\" width=\"10\" height=\"10\" fill=\"none\" "
                "stroke=\"#1f77b4\"><title>reference own convergence, 4x4 blocks: %.4f</title>"
                "</rect>\n",
                PX(rr->time_s) - 5, PY(rr->conv_rel_rmse_4x4) - 5, rr->conv_rel_rmse_4x4);
    fprintf(f,
            "<text x=\"%g\" y=\"%g\">red: Pareto front; grey: C; green: OpenCL; blue: "
            "reference (own convergence); filled: per pixel, hollow: 4x4 blocks</text>\n",
            x0 + 8, y0 + 16);
    if (rf)
        fprintf(f,
                "<text x=\"%g\" y=\"%g\">purple diamonds: against the fragment reference "
                "(shading only; dashed: its front)</text>\n",
                x0 + 8, y0 + 32);
    fprintf(f, "</svg>\n");
#undef PX
#undef PY
    free(s);
    return sl_atomic_commit(&af, e);
}

/* ------------------------------------------------------------------------------ main */

static void scene_name(const char *path, char *out, size_t n) {
    const char *b = strrchr(path, '/');
    b = b ? b + 1 : path;
    const char *dot = strrchr(b, '.');
    int len = dot && dot > b ? (int)(dot - b) : (int)strlen(b);
    snprintf(out, n, "%.*s", len, b);
}

static int get_lobes(const sl_scene *s, int count, lobeset *sets, int *nsets, sl_lobes **out,
                     sl_err *e) {
    for (int i = 0; i < *nsets; i++)
        if (sets[i].count == count) {
            *out = &sets[i].l;
            return 0;
        }
    if (*nsets >= MAX_LOBESETS) return sl_fail(e, "report: too many lobe counts");
    sl_scene tmp = *s;
    tmp.lobes = count;
    lobeset *ls = &sets[*nsets];
    memset(ls, 0, sizeof *ls);
    if (sl_scene_lobes(&tmp, 0, &ls->l, e)) return -1;
    sl_lobes_transform(&ls->l, s->env_rotation_deg, s->env_intensity);
    ls->count = count;
    (*nsets)++;
    *out = &ls->l;
    return 0;
}

int sl_report_scene(const sl_report_scene_opts *o, sl_err *e) {
    int rc = -1;
    sl_scene_inputs in = {0};
    sl_scene_inputs_opts io = {0}; /* lobes: by count, below (get_lobes) */
    sl_device dev_c = {0}, dev_cl = {0};
    int have_cl = 0, nsets = 0, nruns = 0;
    lobeset sets[MAX_LOBESETS];
    run_cfg cfgs[MAX_RUNS];
    run_res *res = sl_malloc(sizeof(run_res) * MAX_RUNS);
    sl_reference_frame ref = {0}, ref_frag = {0};
    sl_reference_result rf;
    memset(&rf, 0, sizeof rf);
    char frag_path[4600];
    char cl_name[1200] = "not run (--device none)";
    sl_report_dir rd;
    int rd_open = 0;

    if (sl_scene_inputs_open(o->scene, &io, &in, e)) goto done;
    char out_dir[4096], name[256];
    scene_name(o->scene, name, sizeof name);
    if (o->out_dir)
        snprintf(out_dir, sizeof out_dir, "%s", o->out_dir);
    else
        snprintf(out_dir, sizeof out_dir, "report/%s", name);
    size_t odl = strlen(out_dir);
    while (odl > 1 && out_dir[odl - 1] == '/')
        out_dir[--odl] = 0;
    /* before any long work (the lobe fit, below) */
    if (sl_report_dir_check(out_dir, e)) goto done;
    sl_scene *s = in.scene;
    if (!s->env_file[0]) {
        sl_fail(e,
                "%s: the report needs environment.file (the reference cuts the map into "
                "lights)",
                o->scene);
        goto done;
    }
    /* image size: tiny / quick / full, height by the scene's aspect */
    /* full: 128 px wide (the scene's 640 px took hours for the pixel reference; the full
     * defaults are chosen so that a full report of data/default.json takes about 10-15 min on
     * 2 cores at low load: docs/results.md "Settings and run times") */
    int w = o->width ? o->width : o->tiny ? 48 : o->quick ? 80 : SL_REPORT_FULL_WIDTH;
    int hgt = (int)lround((double)w * s->height / s->width);
    if (hgt < 1) hgt = 1;
    s->width = w, s->height = hgt;
    /* The reference's error is mostly camera-ray sampling (sub-pixel fibers and glints), not the
     * light cut: two seeds at aa 2 differ by 0.71 rel. RMSE on the default scene at 64 x 48,
     * 128 vs 256 lights with one seed by 0.15 (docs/results.md). With the light split the
     * aa x aa rays of a pixel share the lights, so many rays cost about as much as one. */
    int lights = o->lights ? o->lights : o->tiny ? 8 : o->quick ? 256 : SL_REPORT_FULL_LIGHTS;
    int aa = o->aa ? o->aa : o->tiny ? 2 : o->quick ? 8 : SL_REPORT_FULL_AA;
    /* The fragment reference shades every K-buffer entry with every light (no light split):
     * it costs entries x N shadings, a few times the pixel reference per light, but its only
     * error is the light cut (docs/results.md). */
    int frag_lights = o->frag_lights ? o->frag_lights
                      : o->tiny      ? 8
                      : o->quick     ? SL_REPORT_QUICK_FRAG_LIGHTS
                                     : SL_REPORT_FULL_FRAG_LIGHTS;
    const char *mode = o->tiny ? (o->quick ? "quick + tiny" : "tiny") : o->quick ? "quick" : "full";

    if (sl_scene_inputs_finish(&in, &io, e)) goto done; /* hair, camera at w x hgt */
    const sl_hair *h = &in.hair;
    /* the scene's lobes first: a bad map or lobes file fails before anything is written */
    sl_lobes *base_lobes;
    if (get_lobes(s, s->lobes, sets, &nsets, &base_lobes, e)) goto done;
    int lobes_fixed = s->env_lobes[0] != 0; /* a lobes file: its count only */
    if (lobes_fixed) s->lobes = base_lobes->count;

    /* reference: cached beside the report directory (survives the directory's replacement) */
    char parent[4096], ref_path[4600];
    sl_dirname(out_dir, parent, sizeof parent);
    snprintf(ref_path, sizeof ref_path, "%s/.reference/%s_%dx%d_n%d_aa%d.exr", parent, name, w, hgt,
             lights, aa);
    /* The pixel reference is the path tracer (the ground truth) for the energy-conserving
     * models; the direct-light reference stays the fast one, and the only one for marschner,
     * whose albedo above 1 makes multiply scattered light grow with every bounce. */
    int use_path =
        o->reference == 1 || (o->reference == 0 && s->material.model != SL_MODEL_MARSCHNER);
    if (o->reference == 0 && !use_path)
        sl_note("report: model marschner: the direct-light pixel reference (its single scattering "
                "carries ~2x the energy, so the path tracer is no ground truth for it: "
                "docs/models.md)");
    int spp = o->spp     ? o->spp
              : o->tiny  ? SL_REPORT_TINY_SPP
              : o->quick ? SL_REPORT_QUICK_SPP
                         : SL_REPORT_FULL_SPP;
    if (use_path)
        snprintf(ref_path, sizeof ref_path, "%s/.reference/%s_%dx%d_path_spp%d.exr", parent, name,
                 w, hgt, spp);
    if (sl_make_parent_dirs(ref_path, e)) goto done;
    sl_reference_settings set;
    sl_reference_settings_default(&set);
    set.lights = lights, set.aa = aa, set.width = w, set.height = hgt;
    set.threads = o->threads, set.progress = 1;
    sl_reference_result rr;
    memset(&rr, 0, sizeof rr);
    sl_path_result pr;
    memset(&pr, 0, sizeof pr);
    if (use_path) {
        sl_path_settings ps;
        sl_path_settings_default(&ps);
        ps.spp = spp, ps.width = w, ps.height = hgt, ps.threads = o->threads;
        sl_note("report: path-traced reference %dx%d, %d spp -> %s", w, hgt, spp, ref_path);
        if (sl_path_run(s, &ps, ref_path, 0, &pr, e)) goto done;
        rr.cached = pr.cached, rr.key = pr.key, rr.ms = 1, rr.time_s = pr.wall_s;
        rr.has_convergence = isfinite(pr.noise);
        rr.conv_rel_rmse = pr.noise, rr.conv_rel_rmse_4x4 = pr.noise_4x4, rr.conv_p99 = NAN;
    } else {
        sl_note("report: reference %dx%d, %d lights, aa %d -> %s", w, hgt, lights, aa, ref_path);
        if (sl_reference_run(s, &set, ref_path, 1, &rr, e)) goto done;
    }
    if (sl_reference_load(ref_path, &ref, e)) goto done;
    if (ref.width != w || ref.height != hgt) {
        sl_fail(e, "%s: %dx%d, expected %dx%d", ref_path, ref.width, ref.height, w, hgt);
        goto done;
    }
    /* the fragment reference: the fast path's own K-buffer shaded by the reference */
    snprintf(frag_path, sizeof frag_path, "%s/.reference/%s_%dx%d_frag_n%d.exr", parent, name, w,
             hgt, frag_lights);
    set.fragments = 1, set.lights = frag_lights;
    sl_note("report: fragment reference %dx%d, %d lights -> %s", w, hgt, frag_lights, frag_path);
    if (sl_reference_run(s, &set, frag_path, 1, &rf, e)) goto done;
    if (sl_reference_load(frag_path, &ref_frag, e)) goto done;
    if (ref_frag.width != w || ref_frag.height != hgt) {
        sl_fail(e, "%s: %dx%d, expected %dx%d", frag_path, ref_frag.width, ref_frag.height, w, hgt);
        goto done;
    }

    /* devices */
    if (sl_device_open("c", &dev_c, e)) goto done;
    const char *cl_spec = o->opencl ? o->opencl : "opencl";
    if (strcmp(cl_spec, "none") != 0) {
        sl_err ce = {{0}};
        if (sl_device_open(cl_spec, &dev_cl, &ce) == 0 && dev_cl.is_opencl) {
            have_cl = 1;
            snprintf(cl_name, sizeof cl_name, "%s", dev_cl.name);
        } else {
            snprintf(cl_name, sizeof cl_name, "not run (%s)", ce.msg[0] ? ce.msg : "no device");
            sl_note("report: no OpenCL rows: %s", cl_name);
        }
    }

    /* camera as `strandlight render` frames it (the same loader) */
    const sl_camera cam = in.cam;

    int ncfg = make_sweep(s, o->quick, o->tiny, have_cl, lobes_fixed, cfgs);
    int warmed[2] = {0, 0};
    double sweep_t0 = sl_now();
    for (int i = 0; i < ncfg; i++) {
        run_cfg c = cfgs[i];
        sl_lobes *lobes;
        if (get_lobes(s, c.lobes, sets, &nsets, &lobes, e)) goto done;
        sl_scene sc = *s;
        sc.lobes = c.lobes, sc.layers = c.layers, sc.segments_m = c.m, sc.voxels = c.voxels;
        sc.kappa = c.kappa, sc.multiple_scattering = c.ms;
        if (c.frag_rate) snprintf(sc.shading_rate, sizeof sc.shading_rate, "fragment");
        if (c.split) sc.broad_lobes = SL_BROAD_SPLIT;
        sl_render_opts ro;
        sl_render_opts_default(&ro);
        ro.srbf_method = c.method, ro.segments = c.m, ro.threads = o->threads, ro.quiet = 1;
        sl_device *dev = c.opencl ? &dev_cl : &dev_c;
        sl_fbuf fb;
        if (!warmed[c.opencl]) {
            /* one untimed frame per backend: kernel builds and the SRBF/dual tables' first
             * load (disk-cached) and cold memory are not part of a frame's time */
            sl_renderer *wr = sl_renderer_create(dev, &ro);
            int wrc = sl_renderer_frame(wr, &sc, h, lobes, &cam, &fb, e);
            sl_renderer_free(wr);
            if (wrc) goto done;
            sl_fbuf_free(&fb);
        }
        warmed[c.opencl] = 1;
        sl_renderer *r = sl_renderer_create(dev, &ro);
        double t0 = sl_now();
        int frc = sl_renderer_frame(r, &sc, h, lobes, &cam, &fb, e);
        double dt = sl_now() - t0;
        run_res *rs = &res[nruns];
        memset(rs, 0, sizeof *rs);
        rs->index = nruns + 1;
        rs->c = c, rs->time_s = dt, rs->ms_on = sl_renderer_ms_on(r);
        rs->lobes_used = sl_renderer_lobes_used(r);
        sl_renderer_free(r);
        if (frc) goto done;
        measure(&fb, &ref, &ref_frag, s->material.model, rs);
        rs->heat = heat_map(&fb, &ref);
        sl_fbuf_free(&fb);
        /* ETA from the mean wall time per run so far (warm-ups and measurements included) */
        double per = (sl_now() - sweep_t0) / (double)(i + 1);
        sl_note("report: run %d/%d: %s %s lobes %d K %d m %d kappa %g voxels %d MS %s: %.3f s, "
                "rel RMSE %.4f, p99 %.3f, frag %.4f (sweep %.0f s, about %.0f s left)",
                i + 1, ncfg, c.opencl ? "opencl" : "c", method_name(c.method), c.lobes, c.layers,
                c.m, c.kappa, c.voxels, rs->ms_on ? "on" : "off", dt, rs->rel_rmse, rs->p99,
                rs->rel_rmse_frag, sl_now() - sweep_t0, per * (double)(ncfg - i - 1));
        nruns++;
    }
    mark_pareto(res, nruns, MET_PIXEL);
    mark_pareto(res, nruns, MET_FRAG);

    /* outputs into a temporary directory, swapped in at the end (report_dir.h) */
    if (sl_report_dir_begin(&rd, out_dir, e)) goto done;
    rd_open = 1;
    char p[4500];
    if (!sl_report_dir_file(&rd, "reference.png", p, sizeof p, e) ||
        sl_png_write(p, w, hgt, ref.rgba, 0.0f, e))
        goto done;
    if (!sl_report_dir_file(&rd, "reference_fragments.png", p, sizeof p, e) ||
        sl_png_write(p, w, hgt, ref_frag.rgba, 0.0f, e))
        goto done;
    for (int i = 0; i < nruns; i++)
        if (res[i].pareto) {
            char hn[32];
            snprintf(hn, sizeof hn, "heat_%02d.png", res[i].index);
            if (!sl_report_dir_file(&rd, hn, p, sizeof p, e) ||
                sl_png_write(p, w, hgt, res[i].heat, 0.0f, e))
                goto done;
        }
    if (!sl_report_dir_file(&rd, "results.csv", p, sizeof p, e) ||
        write_csv(p, res, nruns, &rr, &rf, use_path ? &pr : NULL, w, hgt, aa, e))
        goto done;
    if (!sl_report_dir_file(&rd, "report.md", p, sizeof p, e) ||
        write_md(p, o->scene, res, nruns, &rr, &rf, use_path ? &pr : NULL, w, hgt, aa, mode,
                 cl_name, e))
        goto done;
    if (!sl_report_dir_file(&rd, "error_vs_time.svg", p, sizeof p, e) ||
        write_svg(p, res, nruns, &rr, &rf, e))
        goto done;
    rd_open = 0;
    if (sl_report_dir_commit(&rd, e)) goto done;
    sl_note("report: %d runs -> %s/ (results.csv, report.md, error_vs_time.svg)", nruns, out_dir);
    rc = 0;
done:
    if (rd_open) sl_report_dir_abort(&rd);
    sl_reference_frame_free(&ref);
    sl_reference_frame_free(&ref_frag);
    for (int i = 0; i < nruns; i++)
        free(res[i].heat);
    for (int i = 0; i < nsets; i++)
        sl_lobes_free(&sets[i].l);
    sl_scene_inputs_free(&in);
    sl_device_close(&dev_cl);
    sl_device_close(&dev_c);
    free(res);
    return rc;
}
