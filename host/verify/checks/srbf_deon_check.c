/* srbf_deon_check.c: the `strandlight kernels` check of the d'Eon fast path's SRBF response
 * (models deon and chiang): kernels/srbf_deon.cl (host/passes/shade/srbf_deon_cl.c) against its
 * C twin (cpu/srbf_deon_c.c), both kernels (per-row outputs and the renderer's RGB rows). */
#include "verify/checks/kernel_checks.h"

#include "passes/shade/srbf_deon_cl.h"
#include "srbf_deon.h"
#include "srbf_deon_c.h"
#include "verify/report/srbf_sample.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Typical: d'Eon with 3 and 8 orders, chiang typical, narrow (roughness and radial roughness
 * 0.1) and maximally rough. Extreme: d'Eon's needle (beta 0.5 deg) and 32 orders, chiang with
 * radial roughness 1e-3 and sigma_a 50, eta 1.0001. */
static const char *const typical_mats[] = {
    "{\"model\": \"deon\", \"orders\": 3}",
    "{\"model\": \"deon\", \"orders\": 8, \"sigma_a\": 0.08, \"beta_R_deg\": 2.5}",
    "{\"model\": \"chiang\"}",
    "{\"model\": \"chiang\", \"melanin\": 0.5, \"roughness\": 0.1, \"radial_roughness\": 0.1}",
    "{\"model\": \"chiang\", \"sigma_a\": 0, \"roughness\": 1, \"radial_roughness\": 1}",
};
static const char *const extreme_mats[] = {
    "{\"model\": \"deon\", \"orders\": 5, \"beta_R_deg\": 0.5}",
    "{\"model\": \"deon\", \"orders\": 32, \"beta_R_deg\": 60, \"sigma_a\": 0}",
    "{\"model\": \"chiang\", \"roughness\": 0.001, \"radial_roughness\": 0.001}",
    "{\"model\": \"chiang\", \"sigma_a\": 50, \"eta\": 1.0001, \"coat\": 0.99, \"offset_deg\": 45}",
};

/* Extreme rows: views and lobes at and next to the poles, lambda 0.005..10, phi 0 and pi. */
static size_t extreme_rows(float *in, size_t cap) {
    static const float th[] = {-1.5707963f, -1.5707f, 0.0f, 0.7f, 1.5707f, 1.5707963f};
    static const float ph[] = {0.0f, 3.1415925f, -2.0f};
    static const float lam[] = {0.005f, 0.02f, 0.3f, 3.0f, 10.0f};
    size_t n = 0;
    for (int a = 0; a < 6; a++)
        for (int b = 0; b < 6; b++)
            for (int c = 0; c < 3; c++)
                for (int l = 0; l < 5 && n < cap; l++, n++) {
                    float *x = in + 5 * n;
                    x[0] = th[a], x[1] = 0.3f, x[2] = th[b], x[3] = 0.3f - ph[c], x[4] = lam[l];
                }
    return n;
}

int slchk_srbf_deon(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                    sl_err *e) {
    size_t n = o->size > 0 ? (size_t)o->size : 1024;
    int reps = o->reps > 0 ? o->reps : 3;
    const char *const *mats = o->extreme ? extreme_mats : typical_mats;
    size_t nm = o->extreme ? sizeof extreme_mats / sizeof *extreme_mats
                           : sizeof typical_mats / sizeof *typical_mats;
    float *in = sl_malloc(n * 5 * sizeof *in), *sig = sl_malloc(n * 3 * sizeof *sig);
    if (o->extreme) {
        n = extreme_rows(in, n);
    } else {
        sl_srbf_config *cfg = sl_malloc(n * sizeof *cfg);
        sl_srbf_sample(SL_SRBF_SAMPLE_SEED, (int)n, cfg);
        for (size_t i = 0; i < n; i++)
            sl_srbf_config_row(cfg + i, in + 5 * i);
        free(cfg);
    }
    sl_kernel_check_fill(sig, n * 3, 0x5eed5u, 0.0f, o->extreme ? 60.0f : 3.0f);
    snprintf(r->problem, sizeof r->problem, "%zu lobes x %zu materials (rows + rgb)", n, nm);
    /* Same float code and tables; only the device's exp/log/sqrt/trig differ by ulps, which the
     * sums carry through: relative 1e-3, or 1e-6 absolute near 0 (as the Marschner SRBF check). */
    r->tol_abs = 1e-6;
    r->tol_rel = 1e-3;
    snprintf(r->note, sizeof r->note,
             "same float code and tables; device exp/log/trig differ by ulps");
    size_t per = (size_t)SL_SRBF_DEON_NOUT + 9; /* row outputs (at most) + rgb outputs */
    float *a = sl_calloc(nm * n * per, sizeof *a), *b = sl_calloc(nm * n * per, sizeof *b);
    sl_srbf_tables t;
    int rc = sl_srbf_tables_get(&t, 0, e);
    r->c_s = r->cl_s = r->cl_wall_s = INFINITY;
    sl_fiber_params *fps = sl_malloc(nm * sizeof *fps);
    for (size_t k = 0; k < nm && !rc; k++) {
        sl_material m;
        rc = sl_material_parse(mats[k], strlen(mats[k]), "srbf_deon check", &m, e);
        if (!rc) sl_material_to_fiber(&m, 0, &fps[k]);
    }
    /* untimed first run: program build */
    if (!rc) rc = slcl_srbf_deon_batch(cl, &fps[0], &t, n, in, a, e);
    size_t used = 0;
    for (int rep = 0; rep < reps && !rc; rep++) {
        double t0 = sl_now();
        used = 0;
        for (size_t k = 0; k < nm && !rc; k++) {
            size_t no = (size_t)sl_srbf_deon_orders(&fps[k]) + 3;
            rc = slcl_srbf_deon_batch(cl, &fps[k], &t, n, in, a + used, e);
            if (!rc)
                rc = slcl_srbf_deon_rgb_batch(cl, &fps[k], &t, n, in, sig, a + used + n * no, e);
            used += n * (no + 9);
        }
        double wall = sl_now() - t0;
        if (wall < r->cl_wall_s) r->cl_wall_s = r->cl_s = wall;
        t0 = sl_now();
        used = 0;
        for (size_t k = 0; k < nm; k++) {
            size_t no = (size_t)sl_srbf_deon_orders(&fps[k]) + 3;
            slc_srbf_deon_batch(&fps[k], t.C, t.H, t.D, n, in, b + used);
            slc_srbf_deon_rgb_batch(&fps[k], t.C, t.H, t.D, n, in, sig, b + used + n * no);
            used += n * (no + 9);
        }
        double c = sl_now() - t0;
        if (c < r->c_s) r->c_s = c;
    }
    r->cl_s_is_device = 0;
    if (!rc) sl_kernel_compare(a, b, used, r);
    if (t.C) sl_srbf_tables_free(&t);
    free(fps);
    free(in);
    free(sig);
    free(a);
    free(b);
    return rc;
}
