/* test_dual_deflect.c: the material's azimuthal deflection moments and the energy of a widened
 * psi_f (host/passes/volume/dual_deflect.c; docs/volume.md "Where the scattered light goes"). */
#include "test.h"

#include "passes/volume/dual.h"
#include "passes/volume/dual_deflect.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void material(const char *json, sl_material *m) {
    sl_err e = {{0}};
    CHECK(sl_material_parse(json, strlen(json), "test", m, &e) == 0);
}

/* N(mu, s) by the composite Simpson rule on 20000 intervals, in double: the brute-force
 * reference of sl_dual_deflect_norm's table. */
static double norm_simpson(double mu, double s) {
    const int n = 20000;
    double h = M_PI / n, sum = 0.0;
    for (int k = 0; k <= n; k++) {
        double x = -0.5 * M_PI + k * h, z = (x - mu) / s;
        double w = (k == 0 || k == n) ? 1.0 : (k % 2 ? 4.0 : 2.0);
        sum += w * exp(-z * z) * cos(x);
    }
    return sum * h / 3.0 / (sqrt(M_PI) * s);
}

/* The coarse rule the renderer uses (8 x 24 x 48) against a rule twice as fine on every axis
 * (16 x 48 x 96), on the default chiang, a dark rough chiang, a d'Eon and the Marschner default:
 * within 2 % (measured: 0.2-1.5 %). Also the bounds the definition implies: 0 <= 2 E[1 + cos phi]
 * <= 4, forward light turned less than backward light (kf < kb), and TT's forward deflection
 * well below the isotropic 2 (kf < 1). */
TEST(dual_deflect_resolution) {
    const char *mats[4] = {
        "{\"model\": \"chiang\", \"melanin\": 0.3, \"roughness\": 0.3, \"radial_roughness\": 0.3}",
        "{\"model\": \"chiang\", \"melanin\": 0.8, \"roughness\": 0.6, \"radial_roughness\": 0.8}",
        "{\"model\": \"deon\", \"sigma_a\": [0.2, 0.3, 0.5]}", "{}"};
    for (int i = 0; i < 4; i++) {
        sl_material m;
        material(mats[i], &m);
        sl_fiber_params fp;
        sl_material_to_fiber(&m, 0, &fp);
        float kf, kb, kf2, kb2;
        sl_dual_deflect_moments(&fp, 8, 24, 48, &kf, &kb);
        sl_dual_deflect_moments(&fp, 16, 48, 96, &kf2, &kb2);
        if (getenv("SL_TEST_VERBOSE"))
            fprintf(stderr, "  %s: kf %.4f (fine %.4f), kb %.4f (fine %.4f)\n", mats[i], kf, kf2,
                    kb, kb2);
        CHECK_MSG(fabsf(kf - kf2) <= 0.02f * kf2, "%s: kf %g vs %g", mats[i], kf, kf2);
        CHECK_MSG(fabsf(kb - kb2) <= 0.02f * kb2, "%s: kb %g vs %g", mats[i], kb, kb2);
        CHECK(kf > 0.0f && kf < 1.0f && kb > kf && kb <= 4.0f);
    }
}

/* sl_dual_deflect_build fills every channel and the mean backscattering width from the dual
 * tables: a grey material gives three equal channels, sb2 > 0; an absorbing rgb material's blue
 * (shortest paths inside the fiber survive) keeps less of TT's straight-through light, so it is
 * turned more on average (kf rises with absorption: measured 0.46 / 0.48 / 0.55). */
TEST(dual_deflect_build_channels) {
    sl_err e = {{0}};
    sl_material m;
    material("{\"model\": \"chiang\", \"sigma_a\": [0, 0, 0]}", &m);
    sl_dual_tables *t = malloc(sizeof *t);
    CHECK(sl_dual_tables_build(&m, t, &e) == 0);
    sl_dual_deflect d;
    sl_dual_deflect_build(&m, t, &d);
    CHECK(d.kf[0] == d.kf[1] && d.kf[1] == d.kf[2] && d.kb[0] == d.kb[2]);
    CHECK(d.sb2[0] > 0.0f && d.sb2[0] < 1.0f);
    material("{\"model\": \"chiang\", \"melanin\": 0.3}", &m);
    CHECK(sl_dual_tables_build(&m, t, &e) == 0);
    sl_dual_deflect_build(&m, t, &d);
    CHECK_MSG(d.kf[0] < d.kf[1] && d.kf[1] < d.kf[2], "kf %g %g %g", d.kf[0], d.kf[1], d.kf[2]);
    free(t);
}

/* The energy of psi_f on the sphere, N(mu, s): against Simpson's rule in double (above) within
 * 1e-3 absolute (the table's bilinear interpolation, measured 4.6e-4; N <= 1) at narrow, middle and
 * wide spreads and at grazing mu; for a narrow spread far from the poles the untruncated closed
 * form cos(mu) exp(-s^2 / 4) holds (the mean of cos over a Gaussian of variance s^2 / 2); and s ->
 * 0 gives Xu's cos(mu). */
TEST(dual_deflect_norm_closed_form) {
    const double mus[5] = {0.0, 0.3, -0.9, 1.3, -1.55};
    const double ss[5] = {0.05, 0.2, 0.6, 1.5, 3.0};
    double worst = 0.0;
    for (int a = 0; a < 5; a++)
        for (int b = 0; b < 5; b++) {
            double ref = norm_simpson(mus[a], ss[b]);
            double got = sl_dual_deflect_norm((float)mus[a], (float)ss[b]);
            worst = fmax(worst, fabs(got - ref));
            CHECK_MSG(fabs(got - ref) <= 1e-3, "N(%g, %g) = %g, Simpson %g", mus[a], ss[b], got,
                      ref);
        }
    if (getenv("SL_TEST_VERBOSE")) fprintf(stderr, "  N table vs Simpson: max %.2e\n", worst);
    CHECK_NEAR(sl_dual_deflect_norm(0.3f, 0.2f), cos(0.3) * exp(-0.01), 2e-3);
    CHECK_NEAR(sl_dual_deflect_norm(0.3f, 0.0f), cos(0.3), 2e-3);
}
