/* srbf_exact_csv.c: the exact-values CSV of `strandlight report --kernel srbf` (--exact,
 * --write-exact; see report_srbf.h). Apart from report_srbf.c so that the parser links alone
 * (test/fuzz/fuzz_report_exact.c). */
#include "verify/report/report_srbf.h"

#include "base/csv.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static const char *const exact_cols[10] = {"material", "theta_o", "phi_o", "theta_j", "phi_j",
                                           "lambda",   "I_R",     "I_TT",  "I_TRT",   "I"};

int sl_srbf_exact_read(const char *path, const sl_srbf_config *cfg, int n, sl_srbf_exact *out,
                       sl_err *e) {
    char *text = NULL;
    size_t len = 0;
    if (sl_read_file(path, (unsigned char **)&text, &len, 64u << 20, e)) return -1;
    int rc = sl_srbf_exact_parse(text, len, path, cfg, n, out, e);
    free(text);
    return rc;
}

int sl_srbf_exact_parse(const char *text, size_t len, const char *path, const sl_srbf_config *cfg,
                        int n, sl_srbf_exact *out, sl_err *e) {
    sl_csv csv;
    int rc = sl_csv_parse(text, len, path, &csv, e);
    if (rc) return -1;
    int col[10];
    for (int k = 0; k < 10 && !rc; k++) {
        col[k] = sl_csv_find(&csv, exact_cols[k]);
        if (col[k] < 0) rc = sl_fail(e, "%s: missing column '%s'", path, exact_cols[k]);
    }
    if (!rc && csv.nrows < (size_t)n)
        rc = sl_fail(e, "%s: %zu rows, the report needs %d (regenerate it with --write-exact)",
                     path, csv.nrows, n);
    for (int i = 0; i < n && !rc; i++) {
        double v[10];
        for (int k = 0; k < 10 && !rc; k++)
            rc = sl_csv_number(&csv, (size_t)i, col[k], &v[k], e);
        if (rc) break;
        const sl_srbf_config *c = cfg + i;
        double want[6] = {c->material, c->theta_o, c->phi_o, c->theta_j, c->phi_j, c->lambda};
        for (int k = 0; k < 6 && !rc; k++)
            if (fabs(v[k] - want[k]) > 1e-12 * (1.0 + fabs(want[k])))
                rc = sl_fail(e, "%s:%d: %s is %.17g, the sample has %.17g (stale file?)", path,
                             i + 2, exact_cols[k], v[k], want[k]);
        out[i].c = *c;
        for (int k = 0; k < 4; k++)
            out[i].v[k] = v[6 + k];
    }
    sl_csv_free(&csv);
    return rc ? -1 : 0;
}

int sl_srbf_exact_write(const char *path, const sl_srbf_exact *x, int n, sl_err *e) {
    sl_atomic_file af;
    if (sl_atomic_open(&af, path, e)) return -1;
    fprintf(af.fp, "material,theta_o,phi_o,theta_j,phi_j,lambda,I_R,I_TT,I_TRT,I\n");
    for (int i = 0; i < n; i++) {
        const sl_srbf_config *c = &x[i].c;
        fprintf(af.fp, "%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", c->material,
                c->theta_o, c->phi_o, c->theta_j, c->phi_j, c->lambda, x[i].v[0], x[i].v[1],
                x[i].v[2], x[i].v[3]);
    }
    if (ferror(af.fp)) {
        sl_atomic_abort(&af);
        return sl_fail(e, "%s: write error", path);
    }
    return sl_atomic_commit(&af, e);
}
