/* scene_strands.c: per-strand sigma_a overrides (material.strand_sigma_a): the CSV reader and
 * writer and the colour -> sigma_a inversion for "colors"; see scene_strands.h. */
#include "scene/scene_strands.h"

#include "base/csv.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Chiang, Bitterli, Tappan, Burley 2016, "A Practical and Controllable Hair and Fur Model for
 * Production Path Tracing", Eq. 9: sigma_a = (ln c / (5.969 - 0.215 bn + 2.532 bn^2 -
 * 10.73 bn^3 + 5.574 bn^4 + 0.245 bn^5))^2, a fit that inverts the colour of multiply
 * scattered light. pbrt-v3 (HairBSDF::SigmaAFromReflectance) uses the same per unit radius. */
double sl_chiang_sigma_a(double c, double beta_n) {
    if (!(c > 1e-4)) c = 1e-4; /* also catches NaN: a black strand, not an infinite sigma_a */
    if (c > 1) c = 1;
    if (!(beta_n >= 0)) beta_n = 0;
    if (beta_n > 1) beta_n = 1;
    double b = beta_n, b2 = b * b, b3 = b2 * b, b4 = b3 * b, b5 = b4 * b;
    double d = 5.969 - 0.215 * b + 2.532 * b2 - 10.73 * b3 + 5.574 * b4 + 0.245 * b5;
    double r = log(c) / d;
    return r * r;
}

/* Chiang 2016 Eq. 7: the longitudinal standard deviation sqrt(v) = 0.726 b + 0.812 b^2 +
 * 3.7 b^20 of roughness b, increasing on [0, 1]; bisection (60 halvings reach double
 * resolution on [0, 1]). */
double sl_chiang_beta_m(double sd) {
    if (!(sd > 0)) return 0;
    double lo = 0, hi = 1;
    if (0.726 + 0.812 + 3.7 <= sd) return 1;
    for (int i = 0; i < 60; i++) {
        double b = 0.5 * (lo + hi);
        double f = 0.726 * b + 0.812 * b * b + 3.7 * pow(b, 20);
        if (f < sd)
            lo = b;
        else
            hi = b;
    }
    return 0.5 * (lo + hi);
}

int sl_strand_sigma_a_from_colors(const sl_hair *h, const sl_material *m, float **out, sl_err *e) {
    *out = NULL;
    if (!h->color && !h->color_from_file)
        return sl_fail(e,
                       "material.strand_sigma_a \"colors\": the hair (%s) has no per-point "
                       "colours (nor a .tfxproj hairColor)",
                       h->format);
    /* Chiang's beta_n is the azimuthal (radial) roughness: model chiang has it as a key; for
     * the others, whose beta_R is a longitudinal width (marschner: a Gaussian width, standard
     * deviation beta_R / sqrt(2); deon: the standard deviation, numerics.md sec. 2), it is taken
     * equal to the beta_m of that deviation. */
    double bn = m->model == SL_MODEL_CHIANG ? m->chiang.radial_roughness
                : m->model == SL_MODEL_DEON ? sl_chiang_beta_m(m->beta[0])
                                            : sl_chiang_beta_m(m->beta[0] / sqrt(2.0));
    float *sa = sl_malloc(3 * ((size_t)h->num_strands + 1) * sizeof *sa);
    for (uint32_t s = 0; s < h->num_strands; s++) {
        uint32_t a = h->strand_first[s], b = h->strand_first[s + 1];
        double c[3] = {0, 0, 0};
        for (uint32_t i = a; i < b; i++)
            for (int q = 0; q < 3; q++) /* no per-point colours: the file's one colour */
                c[q] += h->color ? h->color[3 * (size_t)i + q] : h->default_color[q];
        for (int q = 0; q < 3; q++) {
            double cq = c[q] / (double)(b - a);
            sa[3 * (size_t)s + q] = (float)sl_chiang_sigma_a(cq, bn);
        }
    }
    *out = sa;
    return 0;
}

/* A strand index field: a non-negative integer below n. */
static int strand_index(const sl_csv *csv, size_t row, int col, uint32_t n, uint32_t *out,
                        sl_err *e) {
    const char *f = csv->fields[row * csv->ncols + col];
    char *end;
    unsigned long long v = strtoull(f, &end, 10);
    if (!f[0] || *end || f[0] == '-' || f[0] == '+')
        return sl_fail(e, "%s:%ld: strand: '%s' is not a strand index", csv->src, csv->line_no[row],
                       f);
    if (v >= n)
        return sl_fail(e, "%s:%ld: strand %llu: out of range (the hair has %u strands)", csv->src,
                       csv->line_no[row], v, n);
    *out = (uint32_t)v;
    return 0;
}

int sl_strand_sigma_a_parse_csv(const char *text, size_t len, const char *name, uint32_t n,
                                const float base[3], float **out, sl_err *e) {
    *out = NULL;
    sl_csv csv;
    if (sl_csv_parse(text, len, name, &csv, e)) return -1;
    static const char *const cols[4] = {"strand", "sigma_a_r", "sigma_a_g", "sigma_a_b"};
    int ci[4];
    for (int k = 0; k < 4; k++) {
        ci[k] = sl_csv_find(&csv, cols[k]);
        if (ci[k] < 0) {
            sl_csv_free(&csv);
            return sl_fail(e,
                           "%s:1: missing column '%s' (expected strand,sigma_a_r,sigma_a_g,"
                           "sigma_a_b)",
                           name, cols[k]);
        }
    }
    if (csv.ncols != 4) {
        sl_csv_free(&csv);
        return sl_fail(e,
                       "%s:1: expected exactly the columns strand,sigma_a_r,sigma_a_g,"
                       "sigma_a_b",
                       name);
    }
    float *sa = sl_malloc(3 * ((size_t)n + 1) * sizeof *sa);
    uint8_t *seen = sl_calloc((size_t)n + 1, 1);
    for (uint32_t s = 0; s < n; s++)
        for (int q = 0; q < 3; q++)
            sa[3 * (size_t)s + q] = base[q];
    int rc = -1;
    for (size_t r = 0; r < csv.nrows; r++) {
        uint32_t s = 0;
        if (strand_index(&csv, r, ci[0], n, &s, e)) goto done;
        if (seen[s]) {
            sl_fail(e, "%s:%ld: strand %u: given twice", name, csv.line_no[r], s);
            goto done;
        }
        seen[s] = 1;
        for (int q = 0; q < 3; q++) {
            double v;
            if (sl_csv_number(&csv, r, ci[q + 1], &v, e)) goto done;
            if (!(v >= 0) || !(v <= 3.4e38)) {
                sl_fail(e, "%s:%ld: %s: %g: must be a finite value >= 0", name, csv.line_no[r],
                        cols[q + 1], v);
                goto done;
            }
            sa[3 * (size_t)s + q] = (float)v;
        }
    }
    rc = 0;
done:
    free(seen);
    sl_csv_free(&csv);
    if (rc)
        free(sa);
    else
        *out = sa;
    return rc;
}

int sl_strand_sigma_a_read_csv(const char *path, uint32_t n, const float base[3], float **out,
                               sl_err *e) {
    *out = NULL;
    unsigned char *data;
    size_t len;
    if (sl_read_file(path, &data, &len, (size_t)1 << 30, e)) return -1;
    int rc = sl_strand_sigma_a_parse_csv((const char *)data, len, path, n, base, out, e);
    free(data);
    return rc;
}

int sl_strand_sigma_a_write_csv(const char *path, const float *sa, uint32_t n, const float base[3],
                                sl_err *e) {
    sl_atomic_file af;
    if (sl_atomic_open(&af, path, e)) return -1;
    fprintf(af.fp, "strand,sigma_a_r,sigma_a_g,sigma_a_b\n");
    for (uint32_t s = 0; s < n; s++) {
        const float *v = sa + 3 * (size_t)s;
        if (v[0] == base[0] && v[1] == base[1] && v[2] == base[2]) continue;
        /* %.9g: 9 significant digits read back to the same float (IEEE 754 binary32) */
        fprintf(af.fp, "%u,%.9g,%.9g,%.9g\n", s, (double)v[0], (double)v[1], (double)v[2]);
    }
    if (ferror(af.fp)) {
        sl_atomic_abort(&af);
        return sl_fail(e, "%s: write error", path);
    }
    return sl_atomic_commit(&af, e);
}

int sl_scene_strand_sigma_a(const sl_scene *s, const sl_hair *h, float **out, sl_err *e) {
    *out = NULL;
    /* one mapping whatever the render settings: sigma_a is the fiber's, and the references
     * (which scatter every order) read it too (docs/formats.md) */
    if (s->strand_sigma_a_colors) return sl_strand_sigma_a_from_colors(h, &s->material, out, e);
    if (!s->strand_sigma_a[0]) return 0;
    float base[3];
    for (int q = 0; q < 3; q++)
        base[q] = (float)s->material.sigma_a[q];
    return sl_strand_sigma_a_read_csv(s->strand_sigma_a, h->num_strands, base, out, e);
}
