/* volume_ms.c: see volume_ms.h (kernels/ms_response.h evaluated per channel). */
#include "volume_ms.h"

#include "ms_response.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int sl_volume_ms_init(const sl_material *m, sl_volume_ms *ms, sl_err *e) {
    memset(ms, 0, sizeof *ms);
    double t0 = sl_now();
    if (sl_dual_tables_build(m, &ms->dt, e)) return -1;
    for (int c = 0; c < 3; c++)
        sl_material_to_fiber(m, m->sigma_a_rgb ? c : 0, &ms->fp[c]);
    float rho[SL_DUAL_MAXJ];
    int nj = sl_dual_vm_coefs(ms->fp[0].caustic_width, rho);
    ms->ng = sl_malloc(3 * SL_MSR_TABLE_FLOATS * sizeof *ms->ng);
    for (int c = 0; c < 3; c++) {
        float *ng = ms->ng + (size_t)c * SL_MSR_TABLE_FLOATS;
        if (c >= ms->dt.nch) { /* grey: the same table */
            memcpy(ng, ms->ng, SL_MSR_TABLE_FLOATS * sizeof *ng);
            continue;
        }
        const sl_fiber_params *fp = &ms->fp[c];
        float eta_trt = fp->eccentricity == 1.0f
                            ? fp->eta
                            : 0.5f * (sl_eta_star(fp->eta, fp->eccentricity, 0.0f) +
                                      sl_eta_star(fp->eta, fp->eccentricity, SL_PI_F));
        for (int t = 0; t < 3; t++)
            for (int i = 0; i < SL_MSR_NT; i++)
                sl_msr_NG_row(fp, t, t == 2 ? eta_trt : fp->eta, i, rho, nj,
                              ng + ((size_t)t * SL_MSR_NT + i) * SL_MSR_ND);
    }
    ms->build_s = sl_now() - t0;
    return 0;
}

void sl_volume_ms_free(sl_volume_ms *ms) {
    free(ms->ng);
    ms->ng = NULL;
}

void sl_volume_ms_terms(const sl_volume_ms *ms, float theta_o, float phi_o, float theta_j,
                        float phi_j, float lambda, const float sigma_f[3], float MG[3],
                        float ML[3]) {
    for (int c = 0; c < 3; c++) {
        if (c > 0 && ms->dt.nch == 1 && sigma_f[c] == sigma_f[0]) { /* grey: same numbers */
            MG[c] = MG[0];
            ML[c] = ML[0];
            continue;
        }
        sl_ms_response_1(&ms->fp[c], ms->dt.tab[c], ms->ng + (size_t)c * SL_MSR_TABLE_FLOATS,
                         theta_o, phi_o, theta_j, phi_j, lambda, sigma_f[c], &MG[c], &ML[c]);
    }
}

void sl_volume_ms_response(const sl_volume_ms *ms, float theta_o, float phi_o, float theta_j,
                           float phi_j, float lambda, const float Tf[3], const float sigma_f[3],
                           float Tj, float out[3]) {
    float MG[3], ML[3];
    sl_volume_ms_terms(ms, theta_o, phi_o, theta_j, phi_j, lambda, sigma_f, MG, ML);
    double l2 = (double)lambda * lambda, P = 3.14159265358979 * l2 * (1 - exp(-4 / l2));
    for (int c = 0; c < 3; c++) {
        float g = Tf[c] - Tj > 0.0f ? Tf[c] - Tj : 0.0f;
        float v = (float)P * (g * MG[c] + SL_DUAL_DB * Tf[c] * ML[c]);
        out[c] = isfinite(v) && v > 0.0f ? v : 0.0f;
    }
}
