/* fiber_check.c: the `strandlight kernels` check of the fiber function of model chiang:
 * kernels/fiber.cl's sl_scatter_eval and sl_furnace_eval (host/passes/shade/fiber_cl.c) against
 * the C twin (cpu/fiber_c.c), both running kernels/fiber_chiang.h. */
#include "verify/checks/kernel_checks.h"

#include "fiber_c.h"
#include "passes/shade/fiber_cl.h"
#include "scene/material.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Typical: the defaults, a narrow logistic (s = 0.010) and a 0.2 deg R lobe. Extreme: radial
 * roughness 0.02 (s = 0.0036, 166 panels; smaller s costs the float furnace ~1/s^2: panels and
 * n_phi both grow as 1/s) with a 0.004 deg R lobe, every lobe at its widest, eta near 1 and a
 * huge sigma_a. */
static const char *const typical[] = {
    "{\"model\": \"chiang\"}",
    "{\"model\": \"chiang\", \"radial_roughness\": 0.05, \"melanin\": 0.2}",
    "{\"model\": \"chiang\", \"roughness\": 0.05, \"coat\": 0.9, \"offset_deg\": -5}",
};
static const char *const extreme[] = {
    "{\"model\": \"chiang\", \"radial_roughness\": 0.02, \"roughness\": 0.01, \"coat\": 0.99}",
    "{\"model\": \"chiang\", \"radial_roughness\": 1, \"roughness\": 1, \"sigma_a\": 0, "
    "\"offset_deg\": 45}",
    "{\"model\": \"chiang\", \"eta\": 1.0001, \"sigma_a\": 1000}",
};
#define FIBER_CHECK_MATS 3
#define FIBER_CHECK_NFURN 4

/* `strandlight kernels --only fiber_chiang`: o->size scatter rows (default 2048) per material,
 * random directions, a quarter of them within 1e-6 of a pole, then the furnace at 4 theta_o. */
int slchk_fiber_chiang(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                       sl_err *e) {
    size_t n = o->size > 0 ? (size_t)o->size : 2048;
    int reps = o->reps > 0 ? o->reps : 3;
    const char *const *mats = o->extreme ? extreme : typical;
    snprintf(r->problem, sizeof r->problem, "%d materials x (%zu scatter, %d furnace)",
             FIBER_CHECK_MATS, n, FIBER_CHECK_NFURN);
    /* The same float code; only the device's sin/asin/exp (within OpenCL's ulp bounds) differ,
     * and a phase error d moves the logistic by d/s relative: 1e-4 at s = 0.01 leaves 100x
     * margin (test_fiber_chiang.c measures 4e-6), or 1e-7 absolute where f is near 0 (f, the
     * albedo are O(1e-3..10)). */
    r->tol_abs = 1e-7;
    r->tol_rel = 1e-4;
    snprintf(r->note, sizeof r->note,
             "same float code; device sin/asin/exp differ by ulps, phases amplified by 1/s");
    size_t per = n * 5 + FIBER_CHECK_NFURN, total = per * FIBER_CHECK_MATS;
    float *in = sl_malloc(n * 4 * sizeof *in), *a = sl_malloc(total * sizeof *a),
          *b = sl_malloc(total * sizeof *b);
    float fin[2 * FIBER_CHECK_NFURN];
    sl_kernel_check_fill(in, n * 4, 7, -1.0f, 1.0f);
    for (size_t i = 0; i < n; i++) {
        float *x = in + 4 * i;
        x[0] *= 1.5707953f; /* the float 1e-6 below pi/2 */
        x[2] *= 1.5707953f;
        x[1] *= 3.14159265f;
        x[3] *= 3.14159265f;
        if (i % 8 == 1) x[0] = x[0] < 0 ? -1.5707953f : 1.5707953f;
        if (i % 8 == 2) x[2] = x[2] < 0 ? -1.5707953f : 1.5707953f;
    }
    for (int t = 0; t < FIBER_CHECK_NFURN; t++) {
        fin[2 * t] = -1.5707953f + 3.1415906f * (float)t / (float)(FIBER_CHECK_NFURN - 1);
        fin[2 * t + 1] = 0.3f;
    }
    int rc = 0;
    r->c_s = r->cl_s = r->cl_wall_s = INFINITY;
    for (int k = 0; k <= reps && !rc; k++) { /* k = 0: untimed (program build) */
        double cl_t = 0.0, c_t = 0.0;
        for (int mi = 0; mi < FIBER_CHECK_MATS && !rc; mi++) {
            sl_material m;
            if ((rc = sl_material_parse(mats[mi], strlen(mats[mi]), "fiber_chiang check", &m, e)))
                break;
            sl_fiber_params fp;
            sl_material_to_fiber(&m, 0, &fp);
            float *ao = a + per * (size_t)mi, *bo = b + per * (size_t)mi;
            double t0 = sl_now();
            rc = slcl_scatter_batch(cl, &fp, n, in, ao, e);
            if (!rc) rc = slcl_furnace_batch(cl, &fp, FIBER_CHECK_NFURN, fin, ao + 5 * n, e);
            cl_t += sl_now() - t0;
            t0 = sl_now();
            slc_scatter_batch(&fp, n, in, bo);
            slc_furnace_batch(&fp, FIBER_CHECK_NFURN, fin, bo + 5 * n);
            c_t += sl_now() - t0;
        }
        if (k > 0 && !rc) {
            if (cl_t < r->cl_wall_s) r->cl_wall_s = r->cl_s = cl_t;
            if (c_t < r->c_s) r->c_s = c_t;
        }
    }
    r->cl_s_is_device = 0;
    if (!rc) sl_kernel_compare(a, b, total, r);
    free(in);
    free(a);
    free(b);
    return rc;
}
