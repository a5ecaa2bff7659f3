/* volume_ms_nodes.h: the multiple-scattering response of strands with their own sigma_a
 * (material.strand_sigma_a: painted, or the hair file's colours). The response tables of
 * volume_ms.h are built for one sigma_a per channel; here they are built at a set of sigma_a
 * nodes, and a strand's channel reads the two nodes around its value, blended linearly in
 * u = ln(sigma_a + SL_MSN_U0). When the strands hold at most SL_MSN_MAX distinct channel values
 * (a file colour, a few paint colours) the nodes are those values and the lookup is exact;
 * otherwise they are spaced evenly in u over the strands' range (docs/volume.md, "Per-strand
 * sigma_a"; the interpolation error is measured by test ms_nodes_grid_vs_exact).
 *
 *   sl_volume_ms_nodes nd;
 *   if (sl_volume_ms_nodes_init(&material, sa, nstrands, &nd, &e)) ...;  (sl_volume_ms_nodes_free)
 *   sl_volume_ms_nodes_response(&nd, sa + 3 * strand, theta_o, ..., out);  (as volume_ms.h)
 */
#ifndef SL_VOLUME_MS_NODES_H
#define SL_VOLUME_MS_NODES_H

#include "passes/volume/volume_ms.h"

#include <stddef.h>
#include <stdint.h>

#define SL_MSN_MAX 18   /* nodes at most (a multiple of 3: three nodes share one table set) */
#define SL_MSN_U0 0.02f /* u = ln(sigma_a + U0): finite at sigma_a = 0 (white fibers) */

typedef struct sl_volume_ms_nodes {
    int n;                /* nodes, increasing sigma_a (n <= SL_MSN_MAX) */
    int exact;            /* 1: the nodes are the strands' own values */
    float sa[SL_MSN_MAX]; /* the nodes' sigma_a */
    float u[SL_MSN_MAX];  /* ln(sa + SL_MSN_U0) */
    int nsets;            /* ceil(n / 3) */
    sl_volume_ms *set;    /* node k is channel k % 3 of set[k / 3] */
    uint64_t key;         /* hash of the material-independent part: the node values */
    double build_s;
} sl_volume_ms_nodes;

/* The node values for the strands' sigma_a (3 per strand, n strands) and their key, without
 * building anything (the planner keys its pass on it). */
void sl_volume_ms_nodes_place(const float *sa, size_t nstrands, sl_volume_ms_nodes *nd);
/* Places the nodes and builds the tables of material m at each (m's other parameters).
 * threads: C threads for the table builds. 0 or -1 with e set (nothing to free then). */
int sl_volume_ms_nodes_init(const sl_material *m, const float *sa, size_t nstrands, int threads,
                            sl_volume_ms_nodes *nd, sl_err *e);
void sl_volume_ms_nodes_free(sl_volume_ms_nodes *nd);

/* MG, ML (volume_ms.h) of channel values sa[3], each blended from its two nodes. */
void sl_volume_ms_nodes_terms(const sl_volume_ms_nodes *nd, const float sa[3], float theta_o,
                              float phi_o, float theta_j, float phi_j, float lambda,
                              const float sigma_f[3], float MG[3], float ML[3]);
/* The radiance per unit lobe rgb, as sl_volume_ms_response. */
void sl_volume_ms_nodes_response(const sl_volume_ms_nodes *nd, const float sa[3], float theta_o,
                                 float phi_o, float theta_j, float phi_j, float lambda,
                                 const float Tf[3], const float sigma_f[3], float Tj, float out[3]);

#endif
