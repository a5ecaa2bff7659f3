/* volume_ms.c: see volume_ms.h (kernels/ms_response.h evaluated per channel, directly or through
 * the response table of kernels/ms_table.h built here). */
#include "passes/volume/volume_ms.h"

#include "ms_table.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#if (SL_MSR_ND - 1) % (SL_MST_ND - 1) != 0
#error "the response table's D nodes must be N^G table nodes"
#endif

/* Node values of the response table at (theta_o, theta_j, s_F) for one channel (layout:
 * kernels/ms_table.h): A_t at the D nodes from the same Gauss-Hermite nodes and N^G rows as the
 * direct evaluation, L from its local core. s_F = 0 (node 0) is taken as 1e-4: the limit. */
static void table_node(const sl_fiber_params *fp, const float *tab, const float *ng, float to,
                       float tj, float sF, float *v) {
    const int step = (SL_MSR_ND - 1) / (SL_MST_ND - 1);
    float td[6], wq[6], s = sF > 1e-4f ? sF : 1e-4f;
    for (int k = 0; k < 3 * SL_MST_ND; k++)
        v[k] = 0.0f;
    for (int t = 0; t < 3; t++) {
        float *out = v + t; /* D node k of mode t at out[3 k] */
        sl_msr_global_nodes(fp, t, to, tj, s, td, wq); /* its pref is G_t, applied at lookup */
        for (int q = 0; q < 6; q++) {
            if (!(wq[q] > 0.0f)) continue;
            float fi;
            int i = sl_msr_td_locate(td[q], &fi);
            const float *r0 = ng + (t * SL_MSR_NT + i) * SL_MSR_ND, *r1 = r0 + SL_MSR_ND;
            for (int k = 0; k < SL_MST_ND; k++) {
                int kk = k * step;
                out[3 * k] += wq[q] * (r0[kk] + fi * (r1[kk] - r0[kk]));
            }
        }
    }
    float pl; /* its pref is G_b, applied at lookup */
    v[3 * SL_MST_ND] = sl_msr_local_core(fp, tab, to, tj, s, &pl);
}

/* Channel c's response table (SL_MST_FLOATS at mt). */
static void table_build(const sl_volume_ms *ms, int c, float *mt) {
    const float *ng = ms->ng + (size_t)c * SL_MSR_TABLE_FLOATS;
    for (int o = 0; o < SL_MST_NO; o++)
        for (int j = 0; j < SL_MST_NJ; j++)
            for (int s = 0; s < SL_MST_NS; s++)
                table_node(&ms->fp[c], ms->dt.tab[c], ng, sl_mst_node_theta(o, SL_MST_NO),
                           sl_mst_node_theta(j, SL_MST_NJ), sl_mst_node_s(s, SL_MST_NS),
                           mt + ((size_t)(o * SL_MST_NJ + j) * SL_MST_NS + s) * SL_MST_STRIDE);
    for (int u = 0; u < SL_MST_NU; u++) /* (~Delta_b, ~sigma_b) at theta_j - theta_o = u */
        for (int s = 0; s < SL_MST_NSB; s++) {
            float *b = mt + SL_MST_MAIN + (size_t)(u * SL_MST_NSB + s) * 2;
            float sF = sl_mst_node_s(s, SL_MST_NSB);
            sl_msr_local_means(ms->dt.tab[c], 0.0f,
                               -SL_PI_F + 2.0f * SL_PI_F * (float)u / (float)(SL_MST_NU - 1),
                               sF > 1e-4f ? sF : 1e-4f, &b[0], &b[1]);
        }
}

int sl_volume_ms_init(const sl_material *m, sl_volume_ms *ms, sl_err *e) {
    memset(ms, 0, sizeof *ms);
    double t0 = sl_now();
    if (sl_dual_tables_build(m, &ms->dt, e)) return -1;
    for (int c = 0; c < 3; c++)
        sl_material_to_fiber(m, m->sigma_a_rgb ? c : 0, &ms->fp[c]);
    sl_dual_kern *kern = sl_malloc(sizeof *kern);
    ms->ng = sl_malloc(3 * SL_MSR_TABLE_FLOATS * sizeof *ms->ng);
    for (int c = 0; c < 3; c++) {
        float *ng = ms->ng + (size_t)c * SL_MSR_TABLE_FLOATS;
        if (c >= ms->dt.nch) { /* grey: the same table */
            memcpy(ng, ms->ng, SL_MSR_TABLE_FLOATS * sizeof *ng);
            continue;
        }
        const sl_fiber_params *fp = &ms->fp[c];
        sl_dual_kern_init(fp, kern);
        if (fp->model != 0) { /* deon, chiang: their own azimuthal (kernels/dual_ec.h) */
            for (int t = 0; t < 3; t++)
                for (int i = 0; i < SL_MSR_NT; i++)
                    sl_ec_NG_row(fp, t, sl_msr_node_td(i), kern->rho + t * SL_DUAL_MAXJ,
                                 kern->nj[t], SL_MSR_ND,
                                 ng + ((size_t)t * SL_MSR_NT + i) * SL_MSR_ND);
            continue;
        }
        float eta_trt = fp->eccentricity == 1.0f
                            ? fp->eta
                            : 0.5f * (sl_eta_star(fp->eta, fp->eccentricity, 0.0f) +
                                      sl_eta_star(fp->eta, fp->eccentricity, SL_PI_F));
        for (int t = 0; t < 3; t++)
            for (int i = 0; i < SL_MSR_NT; i++)
                sl_msr_NG_row(fp, t, t == 2 ? eta_trt : fp->eta, i, kern->rho + 2 * SL_DUAL_MAXJ,
                              kern->nj[2], ng + ((size_t)t * SL_MSR_NT + i) * SL_MSR_ND);
    }
    free(kern);
    double t1 = sl_now();
    ms->mt = sl_malloc(3 * SL_MST_FLOATS * sizeof *ms->mt);
    for (int c = 0; c < 3; c++) {
        float *mt = ms->mt + (size_t)c * SL_MST_FLOATS;
        if (c >= ms->dt.nch) /* grey: the same table */
            memcpy(mt, ms->mt, SL_MST_FLOATS * sizeof *mt);
        else
            table_build(ms, c, mt);
    }
    ms->table_s = sl_now() - t1;
    ms->build_s = sl_now() - t0;
    return 0;
}

void sl_volume_ms_free(sl_volume_ms *ms) {
    free(ms->ng);
    free(ms->mt);
    ms->ng = NULL;
    ms->mt = NULL;
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
        sl_ms_table_1(&ms->fp[c], ms->mt + (size_t)c * SL_MST_FLOATS, theta_o, phi_o, theta_j,
                      phi_j, lambda, sigma_f[c], &MG[c], &ML[c]);
    }
}

void sl_volume_ms_terms_spread(const sl_volume_ms *ms, float theta_o, float phi_o, float theta_j,
                               float phi_j, float lambda, const float sg[3], const float si[3],
                               const float sl[3], int need, float MG[3], float MGi[3],
                               float ML[3]) {
    for (int c = 0; c < 3; c++) {
        if (c > 0 && ms->dt.nch == 1 && sg[c] == sg[0] && si[c] == si[0] && sl[c] == sl[0]) {
            MG[c] = MG[0], MGi[c] = MGi[0], ML[c] = ML[0];
            continue;
        }
        sl_ms_table_spread(&ms->fp[c], ms->mt + (size_t)c * SL_MST_FLOATS, theta_o, phi_o, theta_j,
                           phi_j, lambda, sg[c], si[c], sl[c], need, &MG[c], &MGi[c], &ML[c]);
    }
}

void sl_volume_ms_terms_exact(const sl_volume_ms *ms, float theta_o, float phi_o, float theta_j,
                              float phi_j, float lambda, const float sigma_f[3], float MG[3],
                              float ML[3]) {
    for (int c = 0; c < 3; c++) {
        if (c > 0 && ms->dt.nch == 1 && sigma_f[c] == sigma_f[0]) {
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
    sl_volume_ms_combine(lambda, Tf, Tj, MG, ML, out);
}

void sl_volume_ms_combine(float lambda, const float Tf[3], float Tj, const float MG[3],
                          const float ML[3], float out[3]) {
    double l2 = (double)lambda * lambda, P = 3.14159265358979 * l2 * (1 - exp(-4 / l2));
    for (int c = 0; c < 3; c++) {
        float g = Tf[c] - Tj > 0.0f ? Tf[c] - Tj : 0.0f;
        float v = (float)P * (g * MG[c] + SL_DUAL_DB * Tf[c] * ML[c]);
        out[c] = isfinite(v) && v > 0.0f ? v : 0.0f;
    }
}

/* The light arriving a = Tf f, the part of it that scattered on the way g = max(a - Tj, 0) and
 * the part of that the stacks add by interreflection gi = Tf (f - 1) clamped to [0, g]. */
static float split_parts(float Tf, float f, float Tj, float *g, float *gi) {
    float a = Tf * f;
    *g = a - Tj > 0.0f ? a - Tj : 0.0f;
    float i = Tf * (f - 1.0f);
    *gi = i > 0.0f ? (i < *g ? i : *g) : 0.0f;
    return a;
}

int sl_volume_ms_split_need(const float Tf[3], const float f[3], float Tj) {
    int need = SL_MST_NEED_L;
    for (int c = 0; c < 3; c++) {
        float g, gi;
        split_parts(Tf[c], f[c], Tj, &g, &gi);
        if (g - gi > 0.0f) need |= SL_MST_NEED_G;
        if (gi > 0.0f) need |= SL_MST_NEED_GI;
    }
    return need;
}

void sl_volume_ms_combine_split(float lambda, const float Tf[3], const float f[3], float Tj,
                                const float MG[3], const float MGi[3], const float ML[3],
                                float out[3]) {
    double l2 = (double)lambda * lambda, P = 3.14159265358979 * l2 * (1 - exp(-4 / l2));
    for (int c = 0; c < 3; c++) {
        float g, gi, a = split_parts(Tf[c], f[c], Tj, &g, &gi);
        float v = (float)P * ((g - gi) * MG[c] + gi * MGi[c] + SL_DUAL_DB * a * ML[c]);
        out[c] = isfinite(v) && v > 0.0f ? v : 0.0f;
    }
}
