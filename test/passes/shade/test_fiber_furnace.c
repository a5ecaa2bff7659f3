/* test_fiber_furnace.c: white-furnace integrals (cpu/reference/furnace_ref.c in double,
 * kernels/fiber_furnace.h in float). d'Eon with sigma_a = 0, every order sharing one alpha/beta,
 * explicit orders + rest: the albedo is exactly 1 for every theta_o (d'Eon Sec. 4.2: M_p
 * integrates to 1 against cos theta_i, and sum_p E_p + E_rest = 1/2 integral 1 dh = 1). */
#include "test.h"

#include "fiber_furnace.h"
#include "furnace_ref.h"

#include <string.h>

#define FPI 3.14159265358979323846
#define FDEG (FPI / 180.0)

static void furn_material(sl_material *m, int model, double beta, double alpha, double sigma_a) {
    sl_material_default(m);
    m->model = model;
    m->sigma_a[0] = m->sigma_a[1] = m->sigma_a[2] = sigma_a;
    if (model == SL_MODEL_DEON && beta > 0.0) /* beta 0: keep the default lobes */
        for (int q = 0; q < 3; q++) {
            m->alpha[q] = alpha;
            m->beta[q] = beta;
        }
}

static void furn_to_fiber(const sl_material *m, sl_fiber_params *fp) {
    memset(fp, 0, sizeof *fp);
    fp->model = m->model;
    fp->fresnel = m->fresnel;
    fp->orders = m->orders;
    fp->eta = (float)m->eta;
    fp->eccentricity = (float)m->eccentricity;
    fp->caustic_width = (float)m->caustic_width;
    fp->sigma_a = (float)m->sigma_a[0];
    for (int q = 0; q < 3; q++) {
        fp->alpha[q] = (float)m->alpha[q];
        fp->beta[q] = (float)m->beta[q];
    }
}

static const double furn_tos[] = {-(FPI / 2 - 1e-6), -1.4, -0.6, 0.0, 0.35, 1.1, 1.5,
                                  FPI / 2 - 1e-6};

TEST(furnace_ref_deon_white) {
    const double betas[] = {1.0, 5.0, 20.0, 60.0};
    for (int b = 0; b < 4; b++)
        for (int a = 0; a < 2; a++) {
            sl_material m;
            furn_material(&m, SL_MODEL_DEON, betas[b] * FDEG, a ? 4.0 * FDEG : 0.0, 0.0);
            for (int t = 0; t < 8; t++) {
                double alb = slref_furnace(&m, 0, furn_tos[t], 0.3);
                /* 1e-5: the integrals are asked for 1e-9..1e-11 */
                CHECK_MSG(fabs(alb - 1.0) <= 1e-5, "beta %g alpha %d theta_o %.9g: albedo %.9g",
                          betas[b], a, furn_tos[t], alb);
            }
        }
}

TEST(furnace_float_deon_white) {
    const double betas[] = {1.0, 5.0, 20.0, 60.0};
    for (int b = 0; b < 4; b++) {
        sl_material m;
        furn_material(&m, SL_MODEL_DEON, betas[b] * FDEG, b == 2 ? 4.0 * FDEG : 0.0, 0.0);
        sl_fiber_params fp;
        furn_to_fiber(&m, &fp);
        for (int t = 0; t < 8; t += (b == 0 ? 6 : 1)) { /* 1 deg costs 0.5 s per value */
            float alb = sl_furnace(&fp, (float)furn_tos[t], 0.3f);
            /* 1e-3 (the contract); measured <= 7e-6 */
            CHECK_MSG(fabs(alb - 1.0) <= 1e-3, "beta %g theta_o %.9g: albedo %.9g", betas[b],
                      furn_tos[t], alb);
        }
    }
}

/* With absorption and the default (unequal) lobes the albedo is < 1; float and reference must
 * still agree (1e-3 relative: the float furnace's rules, measured ~1e-5). */
TEST(furnace_deon_absorbing_float_vs_ref) {
    sl_material m;
    furn_material(&m, SL_MODEL_DEON, 0, 0, 0.36);
    sl_fiber_params fp;
    furn_to_fiber(&m, &fp);
    for (int t = 0; t < 8; t += 2) {
        double r = slref_furnace(&m, 0, furn_tos[t], 0.0);
        float f = sl_furnace(&fp, (float)furn_tos[t], 0.0f);
        CHECK(r > 0.0 && r < 1.0);
        CHECK_REL(f, r, 1e-3);
    }
}

/* Marschner does not conserve energy; only sanity: finite and positive (float, two directions). */
TEST(furnace_marschner_finite) {
    sl_material m;
    furn_material(&m, SL_MODEL_MARSCHNER, 0, 0, 0.2);
    sl_fiber_params fp;
    furn_to_fiber(&m, &fp);
    for (int t = 0; t < 8; t += 4) {
        float f = sl_furnace(&fp, (float)furn_tos[t], 0.4f);
        CHECK_MSG(isfinite(f) && f > 0.0f && f < 10.0f, "theta_o %g: albedo %g", furn_tos[t], f);
    }
}
