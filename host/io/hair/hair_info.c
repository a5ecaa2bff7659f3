/* hair_info.c: `strandlight info` for hair files: format, counts, bounds, strand lengths,
 * thickness, and which per-point arrays are present. One `key: value` line each, so scripts
 * can grep them. Lengths are summed in double. */
#include "io/hair/hair.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* min/max of n*k values at stride k, component c. */
static void range(const float *a, size_t n, int k, float *lo, float *hi) {
    *lo = FLT_MAX, *hi = -FLT_MAX;
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < k; c++) {
            float v = a[i * k + c];
            if (v < *lo) *lo = v;
            if (v > *hi) *hi = v;
        }
    }
}

static void print_info(const sl_hair *h, const char *path, FILE *out) {
    uint32_t S = h->num_strands, P = h->num_points;
    uint32_t pmin = UINT32_MAX, pmax = 0, unusable = 0;
    double lmin = DBL_MAX, lmax = 0, ltot = 0, seg_min = DBL_MAX;
    for (uint32_t s = 0; s < S; s++) {
        uint32_t a = h->strand_first[s], n = h->strand_first[s + 1] - a;
        if (n < pmin) pmin = n;
        if (n > pmax) pmax = n;
        double len = 0;
        for (uint32_t k = 0; k + 1 < n; k++) {
            const float *p = h->pos + 3 * ((size_t)a + k);
            double dx = (double)p[3] - p[0], dy = (double)p[4] - p[1], dz = (double)p[5] - p[2];
            double l = sqrt(dx * dx + dy * dy + dz * dz);
            len += l;
            if (l < seg_min) seg_min = l;
            if (!sl_hair_segment_usable(h, s, k)) unusable++;
        }
        ltot += len;
        if (len < lmin) lmin = len;
        if (len > lmax) lmax = len;
    }
    float lo[3], hi[3];
    sl_hair_bounds(h, lo, hi);
    int cy = strncmp(h->format, "cyHair", 6) == 0;
    fprintf(out, "file: %s\n", path);
    fprintf(out, "format: %s\n", h->format);
    if (h->notes[0]) fprintf(out, "details: %s\n", h->notes);
    fprintf(out, "strands: %u\n", S);
    if (h->follow_added)
        fprintf(out, "guide strands: %u (+ %u follow strands)\n", h->guide_strands,
                S - h->guide_strands);
    if (h->dropped_strands)
        fprintf(out, "dropped strands: %u (single point)\n", h->dropped_strands);
    fprintf(out, "points: %u\n", P);
    fprintf(out, "segments: %u\n", P - S);
    fprintf(out, "points per strand: min %u, mean %.2f, max %u\n", pmin, (double)P / S, pmax);
    fprintf(out, "bounding box: (%g, %g, %g) -> (%g, %g, %g)\n", (double)lo[0], (double)lo[1],
            (double)lo[2], (double)hi[0], (double)hi[1], (double)hi[2]);
    fprintf(out, "strand length: min %.6g, mean %.6g, max %.6g\n", lmin, ltot / S, lmax);
    fprintf(out, "total length: %.3f\n", ltot);
    fprintf(out, "shortest segment: %.3g (%u segment%s too short for a tangent of their own)\n",
            seg_min, unusable, unusable == 1 ? "" : "s");
    if (h->radius) {
        float rlo, rhi;
        range(h->radius, P, 1, &rlo, &rhi);
        if (cy)
            fprintf(out, "thickness: per point, min %g, max %g (diameter)\n", 2 * (double)rlo,
                    2 * (double)rhi);
        else
            fprintf(out, "thickness: per point\n");
        fprintf(out, "radius: per point, min %g, max %g\n", (double)rlo, (double)rhi);
    } else {
        if (h->radius_source == SL_RADIUS_HEADER)
            fprintf(out, "thickness: default %g (diameter, from the header)\n",
                    2 * (double)h->default_radius);
        else if (h->radius_source == SL_RADIUS_ESTIMATED)
            fprintf(out, "thickness: none in the file\n");
        else
            fprintf(out, "thickness: default %g (diameter)\n", 2 * (double)h->default_radius);
        fprintf(out, "radius: %g%s\n", (double)h->default_radius,
                h->radius_source == SL_RADIUS_ESTIMATED ? " (estimated: 5e-4 x bounding-box "
                                                          "diagonal; the scene's hair.radius "
                                                          "overrides it)"
                                                        : "");
    }
    fprintf(out, "per-point thickness: %s\n", h->radius ? "yes" : "no");
    if (h->transparency) {
        float tlo, thi;
        range(h->transparency, P, 1, &tlo, &thi);
        fprintf(out, "per-point transparency: yes (min %g, max %g)\n", (double)tlo, (double)thi);
    } else {
        fprintf(out, "per-point transparency: no (default %g)\n", (double)h->default_transparency);
    }
    if (h->color) {
        float clo, chi;
        range(h->color, P, 3, &clo, &chi);
        fprintf(out, "per-point color: yes (components in [%g, %g])\n", (double)clo, (double)chi);
    } else {
        fprintf(out, "per-point color: no (default %g %g %g)\n", (double)h->default_color[0],
                (double)h->default_color[1], (double)h->default_color[2]);
    }
}

int sl_hair_info(const char *path, FILE *out, sl_err *e) {
    sl_hair h;
    if (sl_hair_load(path, &h, e)) return -1;
    print_info(&h, path, out);
    sl_hair_free(&h);
    return 0;
}
