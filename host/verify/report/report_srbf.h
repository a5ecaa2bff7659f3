/* report_srbf.h: `strandlight report --kernel srbf` (issue 5): the SRBF closed forms (xu with
 * m = 1..8, fast) on every available float backend against the exact reference, on the fixed
 * seeded stiff sample of host/verify/report/srbf_sample.h: median / 95th percentile / maximum of the error
 * measure of numerics.md sec. 5 (total I and per mode), and lobe evaluations per second; printed
 * as a Markdown table, written as CSV and as an SVG error-vs-time plot. */
#ifndef SL_REPORT_SRBF_H
#define SL_REPORT_SRBF_H

#include "base/common.h"
#include "verify/report/srbf_sample.h"

typedef struct sl_report_srbf_opts {
    int n;                 /* sample size (0: 150) */
    const char *exact_in;  /* CSV of exact values of this sample (skips the slow reference) */
    const char *exact_out; /* write the exact values computed here as CSV */
    const char *csv;       /* results CSV (NULL: none) */
    const char *svg;       /* error-vs-time plot (NULL: none) */
    const char *device;    /* OpenCL device spec for the opencl rows; NULL: auto; "none": skip */
    double min_time_s;     /* timing: run each method at least this long (0: 0.3 s) */
} sl_report_srbf_opts;

/* One exact row: the configuration and I_R, I_TT, I_TRT, I (channel 0). */
typedef struct sl_srbf_exact {
    sl_srbf_config c;
    double v[4]; /* I_R, I_TT, I_TRT, I */
} sl_srbf_exact;

/* The exact values of cfg[0..n-1] (slref_srbf; seconds per eccentric row; progress bar when
 * progress != 0). */
void sl_srbf_exact_compute(const sl_srbf_config *cfg, int n, int progress, sl_srbf_exact *out);
/* Reads/writes the exact CSV (columns material,theta_o,phi_o,theta_j,phi_j,lambda,I_R,I_TT,
 * I_TRT,I, %.17g). Reading checks that the file holds the first n rows of the sample cfg
 * (else an error naming the file and line). */
int sl_srbf_exact_read(const char *path, const sl_srbf_config *cfg, int n, sl_srbf_exact *out,
                       sl_err *e);
/* The reading from memory (len bytes, no NUL needed; path names the file in messages). No I/O;
 * fuzzed by test/fuzz/fuzz_report_exact.c. */
int sl_srbf_exact_parse(const char *text, size_t len, const char *path, const sl_srbf_config *cfg,
                        int n, sl_srbf_exact *out, sl_err *e);
int sl_srbf_exact_write(const char *path, const sl_srbf_exact *x, int n, sl_err *e);

/* Error statistics of one method on the sample: err[t] of mode t (3: total I). */
typedef struct sl_srbf_stats {
    double median[4], p95[4], max[4];
    /* the total I over the rows whose exact I is above the error floor 0.03 int G (the others
     * are measured against the floor and are easy): how many, median, 95th percentile */
    int n_above;
    double median_above, p95_above;
} sl_srbf_stats;
/* out: 4 floats per row as slc_srbf_batch writes them. */
void sl_srbf_stats_of(const sl_srbf_exact *x, int n, const float *out, sl_srbf_stats *s);

int sl_report_srbf(const sl_report_srbf_opts *o, sl_err *e);

#endif
