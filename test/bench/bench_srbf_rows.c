/* bench_srbf_rows.c: rows per second per core of the renderer's RGB SRBF batches (the shade
 * pass's slc_srbf_deon_rgb_batch for models chiang / deon, slc_srbf_rgb_batch for marschner
 * fast), on rows shaped like the shade pass's: NPTS points, each with NLOBES consecutive lobe
 * rows (same theta_o, phi_o and sigma_a; the lobes' theta_j, phi_j, lambda spread like a
 * 40-lobe fit), 3 sigma_a per row. Prints the scalar reference (one row at a time) and the
 * batched driver on the same rows, and the largest difference between them. Built and run by
 * test/bench/bench_srbf.sh against build/libstrandlight.a (not part of the unit tests: it
 * prints timings). Usage: bench_srbf_rows MATERIAL_JSON [MIN_SECONDS [batched]] (batched: that
 * one only, for a profiler). */
#include "passes/shade/srbf_tables.h"
#include "scene/material.h"
#include "srbf_c.h"
#include "srbf_deon_c.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define NPTS 256
#define NLOBES 32

static double cpu_s(void) {
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static double urand(unsigned *s) {
    *s = *s * 1664525u + 1013904223u;
    return ((*s >> 8) + 0.5) / 16777216.0;
}

typedef void (*batch_fn)(const sl_fiber_params *fp, const sl_srbf_tables *t, size_t n,
                         const float *in, const float *sig, float *out);

static void deon_batch(const sl_fiber_params *fp, const sl_srbf_tables *t, size_t n,
                       const float *in, const float *sig, float *out) {
    slc_srbf_deon_rgb_batch(fp, t->C, t->H, t->D, n, in, sig, out);
}
static void deon_scalar(const sl_fiber_params *fp, const sl_srbf_tables *t, size_t n,
                        const float *in, const float *sig, float *out) {
    slc_srbf_deon_rgb_scalar(fp, t->C, t->H, t->D, n, in, sig, out);
}
static void fast_batch(const sl_fiber_params *fp, const sl_srbf_tables *t, size_t n,
                       const float *in, const float *sig, float *out) {
    slc_srbf_rgb_batch(fp, t->C, t->H, SL_SRBF_METHOD_FAST, 4, n, in, sig, out);
}
static void fast_scalar(const sl_fiber_params *fp, const sl_srbf_tables *t, size_t n,
                        const float *in, const float *sig, float *out) {
    slc_srbf_rgb_scalar(fp, t->C, t->H, SL_SRBF_METHOD_FAST, 4, n, in, sig, out);
}

/* Rows per CPU second of f on the n rows, repeated for at least min_s. */
static double rate(batch_fn f, const sl_fiber_params *fp, const sl_srbf_tables *t, size_t n,
                   const float *in, const float *sig, float *out, double min_s) {
    double t0 = cpu_s(), t1;
    size_t rows = 0;
    do {
        f(fp, t, n, in, sig, out);
        rows += n;
        t1 = cpu_s();
    } while (t1 - t0 < min_s);
    return (double)rows / (t1 - t0);
}

int main(int argc, char **argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: bench_srbf_rows MATERIAL_JSON [MIN_SECONDS]\n");
        return 2;
    }
    double min_s = argc > 2 ? atof(argv[2]) : 1.0;
    sl_material m;
    sl_err e;
    memset(&e, 0, sizeof e);
    if (sl_material_parse(argv[1], strlen(argv[1]), "bench_srbf_rows", &m, &e)) {
        fprintf(stderr, "bench_srbf_rows: %s\n", e.msg);
        return 1;
    }
    sl_srbf_tables t;
    if (sl_srbf_tables_get(&t, 0, &e)) {
        fprintf(stderr, "bench_srbf_rows: %s\n", e.msg);
        return 1;
    }
    sl_fiber_params fp;
    sl_material_to_fiber(&m, 0, &fp);
    size_t n = (size_t)NPTS * NLOBES;
    float *in = malloc(n * 5 * sizeof *in), *sig = malloc(n * 3 * sizeof *sig);
    float *o1 = malloc(n * 9 * sizeof *o1), *o2 = malloc(n * 9 * sizeof *o2);
    unsigned s = 12345u;
    float lt[NLOBES], lp[NLOBES], ll[NLOBES];
    for (int j = 0; j < NLOBES; j++) { /* a lobe fit: most narrow, a few broad */
        lt[j] = (float)(asin(2.0 * urand(&s) - 1.0));
        lp[j] = (float)(3.14159265 * (2.0 * urand(&s) - 1.0));
        ll[j] = (float)exp(log(0.05) + (log(1.2) - log(0.05)) * urand(&s));
    }
    for (size_t i = 0; i < NPTS; i++) {
        float to = (float)(1.5 * (2.0 * urand(&s) - 1.0)), po = (float)(3.14159 * urand(&s));
        for (int j = 0; j < NLOBES; j++) {
            size_t r = i * NLOBES + (size_t)j;
            float *x = in + 5 * r;
            x[0] = to, x[1] = po, x[2] = lt[j], x[3] = lp[j], x[4] = ll[j];
            for (int c = 0; c < 3; c++)
                sig[3 * r + c] = (float)m.sigma_a[c];
        }
    }
    const char *name = sl_material_model_name(m.model);
    int marschner = fp.model == SL_MODEL_MARSCHNER;
    batch_fn sc = marschner ? fast_scalar : deon_scalar, bt = marschner ? fast_batch : deon_batch;
    if (argc > 3 && !strcmp(argv[3], "batched")) {
        printf("batched %.3g rows/s per core\n", rate(bt, &fp, &t, n, in, sig, o2, min_s));
        return 0;
    }
    double rs = rate(sc, &fp, &t, n, in, sig, o1, min_s);
    double rb = rate(bt, &fp, &t, n, in, sig, o2, min_s);
    double dmax = 0.0, vmax = 0.0;
    for (size_t k = 0; k < n * 9; k++) {
        double d = fabs((double)o1[k] - (double)o2[k]);
        if (d > dmax) dmax = d;
        if (fabs(o1[k]) > vmax) vmax = fabs(o1[k]);
    }
    printf("%-9s %s rows (point, lobe, RGB) per core: scalar %.3g/s, batched %.3g/s (x%.2f); "
           "max |batched - scalar| %.3g (largest output %.3g)\n",
           name, marschner ? "fast" : "fast (d'Eon path)", rs, rb, rb / rs, dmax, vmax);
    free(in), free(sig), free(o1), free(o2);
    sl_srbf_tables_free(&t);
    return 0;
}
