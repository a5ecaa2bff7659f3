/* volume_ms.h: the multiple-scattering response per fragment and SRBF lobe (Xu 2011 Eq. 27-31
 * with the dual-scattering tables of host/passes/volume/dual.h and T_f, sigma_f of the volume
 * march, host/passes/volume/volume.h). The math is kernels/ms_response.h (also OpenCL C); the
 * renderer reads it from a per-material table (kernels/ms_table.h, built by sl_volume_ms_init);
 * definitions, the table and the combination with single scattering: docs/volume.md.
 *
 *   sl_volume_ms ms;
 *   if (sl_volume_ms_init(&material, &ms, &e)) ...;      (per material edit; sl_volume_ms_free)
 *   for each fragment (fiber frame: theta_o, phi_o) and lobe j (theta_j, phi_j, lambda_j, rgb_j):
 *       float Tf[3], sf[3], r[3];
 *       sl_ftex_lookup(&ftex, j, p, Tf, sf); (host/passes/volume/volume.h)
 *       sl_volume_ms_response(&ms, theta_o, phi_o, theta_j, phi_j, lambda_j, Tf, sf, Tj, r);
 *       L[c] += rgb_j[c] * r[c];        (Tj: the single-scattering transmittance toward j)
 */
#ifndef SL_VOLUME_MS_H
#define SL_VOLUME_MS_H

#include "passes/volume/dual.h"
#include "fiber_params.h"
#include "scene/material.h"

typedef struct sl_volume_ms {
    sl_dual_tables dt;     /* host/passes/volume/dual.h */
    sl_fiber_params fp[3]; /* per channel */
    float *ng;             /* 3 channels x SL_MSR_TABLE_FLOATS: the N^G tables (ms_response.h) */
    float *mt;             /* 3 channels x SL_MST_FLOATS: the response tables (ms_table.h) */
    double build_s;        /* time of the last init (all tables) */
    double table_s;        /* of which the response tables */
} sl_volume_ms;

/* Tables and per-channel fiber parameters of m (marschner; deon: -1 with e set, nothing to free).
 * Rebuild (free + init) when the material changes. Builds the response table too (~5 MB for
 * rgb, docs/volume.md). */
int sl_volume_ms_init(const sl_material *m, sl_volume_ms *ms, sl_err *e);
void sl_volume_ms_free(sl_volume_ms *ms);

/* The two parts for one lobe, per channel: MG = int psi_f f d w_i (global, Xu Eq. 27) and
 * ML = int psi_f S_back cos theta_i d w_i (local, Xu Eq. 29; without d_b). Both per unit lobe
 * power; sigma_f excludes lambda (it is added here: Xu Eq. 5). Read from the response table
 * (kernels/ms_table.h: within ~1 % of the direct evaluation where the terms matter, test
 * ms_table_*). */
void sl_volume_ms_terms(const sl_volume_ms *ms, float theta_o, float phi_o, float theta_j,
                        float phi_j, float lambda, const float sigma_f[3], float MG[3],
                        float ML[3]);
/* The same row at three spreads per channel: M^G at sg and at si, M^L at sl (each as
 * sl_volume_ms_terms at that spread; the row's table cells found once); need: the
 * SL_MST_NEED_* (kernels/ms_table.h) of the values wanted, the others are 0. */
void sl_volume_ms_terms_spread(const sl_volume_ms *ms, float theta_o, float phi_o, float theta_j,
                               float phi_j, float lambda, const float sg[3], const float si[3],
                               const float sl[3], int need, float MG[3], float MGi[3], float ML[3]);

/* The same two parts by the direct evaluation (kernels/ms_response.h, no response table): the
 * reference of the table, ~4x slower. */
void sl_volume_ms_terms_exact(const sl_volume_ms *ms, float theta_o, float phi_o, float theta_j,
                              float phi_j, float lambda, const float sigma_f[3], float MG[3],
                              float ML[3]);

/* Radiance per unit lobe rgb (out[c]): P(lambda) [max(T_f - Tj, 0) MG + d_b T_f ML], P = pi
 * lambda^2 (1 - exp(-4 / lambda^2)) the lobe's power, d_b = SL_DUAL_DB. T_f - Tj keeps only light
 * that scattered at least once on the way (the unscattered part is single scattering, T_j S);
 * pass Tj = 0 for Xu's Eq. 3 as printed. */
void sl_volume_ms_response(const sl_volume_ms *ms, float theta_o, float phi_o, float theta_j,
                           float phi_j, float lambda, const float Tf[3], const float sigma_f[3],
                           float Tj, float out[3]);
/* The same radiance from the two parts MG, ML (sl_volume_ms_terms, or per-strand nodes:
 * volume_ms_nodes.h). */
void sl_volume_ms_combine(float lambda, const float Tf[3], float Tj, const float MG[3],
                          const float ML[3], float out[3]);
/* sl_volume_ms_combine with the light arriving split in two (docs/volume.md, "Where the scattered
 * light goes"): of the light that scattered on the way, max(Tf f - Tj, 0), the part the stacks
 * around the point add by interreflection, Tf (f - 1) (clamped to [0, that]), is spread by its
 * backscattering and shaded with MGi, the rest with MG; the local term takes all of Tf f. Tf: the
 * march's T_f, f: the stack's incident factor (1 without one). MGi = MG and f = 1 give
 * sl_volume_ms_combine exactly. */
void sl_volume_ms_combine_split(float lambda, const float Tf[3], const float f[3], float Tj,
                                const float MG[3], const float MGi[3], const float ML[3],
                                float out[3]);
/* Which of sl_volume_ms_combine_split's terms get any light (SL_MST_NEED_* of kernels/ms_table.h,
 * for sl_volume_ms_terms_spread): M^L always, M^G where some scattered light is not
 * interreflected, M^Gi where some is. */
int sl_volume_ms_split_need(const float Tf[3], const float f[3], float Tj);

#endif
