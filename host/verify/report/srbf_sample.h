/* srbf_sample.h: the fixed, seeded "stiff" sample of SRBF configurations (issue 5) on which the
 * closed forms are measured against the exact reference: `strandlight report --kernel srbf`,
 * test/passes/shade/test_srbf.c and docs/srbf.md all use this one generator, so their figures agree.
 *
 * Each configuration: a material (one of SL_SRBF_SAMPLE_MATERIALS variants of the defaults:
 * default, dark, blond with sharp beta, sharp beta, eccentric), a view and a lobe in the fiber
 * frame: lambda log-uniform in [0.05, 1]; theta_o up to +-80 deg with a third grazing (|theta_o|
 * in 60..80 deg); 15 % of the lobes at a pole (theta_j = +-pi/2); the rest placed on one of the
 * modes' specular cones (theta_j near 2 alpha_t - theta_o, within a few lambda and beta) so the
 * response is above the error floor of numerics.md sec. 5 -- that is what makes it stiff. */
#ifndef SL_SRBF_SAMPLE_H
#define SL_SRBF_SAMPLE_H

#include "scene/material.h"

#define SL_SRBF_SAMPLE_MATERIALS 5
#define SL_SRBF_SAMPLE_SEED                                                                        \
    20110805u /* fixed: the sample is part of the contract of the report                           \
               */

typedef struct sl_srbf_config {
    int material; /* 0 default, 1 dark, 2 blond sharp, 3 sharp, 4 eccentric */
    double theta_o, phi_o, theta_j, phi_j, lambda;
} sl_srbf_config;

/* Name ("default", "dark", ...) and material of variant i (0..SL_SRBF_SAMPLE_MATERIALS-1). */
const char *sl_srbf_sample_material_name(int i);
void sl_srbf_sample_material(int i, sl_material *m);

/* Fills cfg[0..n-1] with the first n configurations of the sequence of seed `seed` (the same n
 * prefix for any larger n). Materials cycle 0,1,2,3,4,... so any prefix of 5k rows is balanced. */
void sl_srbf_sample(unsigned seed, int n, sl_srbf_config *cfg);

/* A configuration as the 5-float input row of the SRBF batches (theta_o, phi_o, theta_j, phi_j,
 * lambda; host/passes/shade/srbf_cl.h, cpu/srbf_c.h). */
void sl_srbf_config_row(const sl_srbf_config *c, float row[5]);

#endif
