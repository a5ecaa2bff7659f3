/* dual.h: the dual-scattering material tables of a material (all colour channels) for the
 * renderer, rebuilt when a material parameter changes (about 2 ms for the default material,
 * docs/dual.md), and the multiple-scattering share estimate behind
 * `quality.multiple_scattering: auto`.
 *
 *   sl_dual_tables t;
 *   if (sl_dual_tables_build(&material, &t, &e)) ...   (model deon: error)
 *   float a_f = sl_dual_lookup(t.tab[ch], SL_DUAL_AF, theta_d);          (kernels/dual_material.h)
 *   float mean = sl_dual_mean(t.tab[ch], SL_DUAL_DELTA_B, td0, td1);    (Xu Eq. 31)
 *
 * The table layout (kernels/dual_material.h, SL_DUAL_TABLE_FLOATS floats per channel) is what the
 * OpenCL kernels receive as a __global const float buffer. */
#ifndef SL_DUAL_HOST_H
#define SL_DUAL_HOST_H

#include "base/common.h"
#include "dual_material.h"
#include "scene/material.h"

typedef struct sl_dual_tables {
    int nch;                            /* 1, or 3 for an [r,g,b] sigma_a */
    float tab[3][SL_DUAL_TABLE_FLOATS]; /* per channel; tab[c] for c >= nch copies tab[0] */
} sl_dual_tables;

/* Builds the tables of m, any model (marschner: kernels/dual_material.h; deon, chiang: their own
 * A_p and N_p, kernels/dual_ec.h). Returns 0 (-1 with e set is kept for a model without terms;
 * every model has them now). */
int sl_dual_tables_build(const sl_material *m, sl_dual_tables *t, sl_err *e);

/* Estimated share of multiple scattering in the light a dense hair volume returns, in [0, 1)
 * (docs/dual.md): per channel, r = <a_b> and t = <a_f> (means over the sphere of incident
 * directions, weight cos theta_d) are the reflectance and transmittance of one fiber layer; an
 * infinite stack of such layers reflects R = ((1 + r^2 - t^2) - sqrt((1 + r^2 - t^2)^2 - 4 r^2))
 * / (2 r) (adding equations), of which r is single scattering; the share is
 * sum_c w_c (R_c - r_c) / sum_c w_c R_c with Rec. 709 luminance weights w. 0 when R = 0.
 * Returns -1 if the tables cannot be built (no model today). */
double sl_dual_ms_share(const sl_material *m);

/* The infinite-stack reflectance R(r, t) above (r, t >= 0, r + t <= 1). */
double sl_dual_stack_reflectance(double r, double t);
/* A stack of fiber layers of reflectance r and transmittance t (one channel's means, sl_dual_means)
 * and the local backscattering A_b the dual-scattering tables assume (Zinke's semi-infinite medium
 * behind the point): what the frame needs to weight A_b by the hair actually behind a point
 * (docs/volume.md, "The stack behind"). */
typedef struct sl_dual_stack {
    double r, t, Ab, R_inf;
    double a, b, kappa; /* the adding equations in Kubelka-Munk form (dual.c) */
    int lossless;       /* r + t = 1 (or r = 0): the closed forms' b -> 0 limit */
} sl_dual_stack;
void sl_dual_stack_init(double r, double t, double Ab, sl_dual_stack *s);
/* The reflectance of N layers (N real >= 0): 0 at N = 0, r at N = 1, R_inf as N -> inf. */
double sl_dual_stack_reflectance_n(const sl_dual_stack *s, double N);
/* The transmittance of N layers (the light through them by every path, interreflections
 * included): 1 at N = 0, t at N = 1. */
double sl_dual_stack_transmittance_n(const sl_dual_stack *s, double N);
/* The light arriving at a fiber with m layers in front of it (toward the light) and n behind,
 * relative to t^m (what a forward-scattering-only march, T_f = prod a_f, delivers there): the
 * front stack's transmittance, with the light the two stacks reflect between them,
 * T_m / (1 - R_m R_n) / t^m; 1 at m = 0 and n = 0. Capped at SL_DUAL_STACK_MAX_FACTOR. */
#define SL_DUAL_STACK_MAX_FACTOR 1e4
double sl_dual_stack_incident_factor(const sl_dual_stack *s, double m, double n);
/* (R_{n+1} - r) / A_b: the light a point's own fiber gets back from the n layers behind it
 * (and their interreflections with it), relative to A_b; 0 at n = 0, 1 when A_b is 0. */
double sl_dual_stack_local_factor(const sl_dual_stack *s, double n);
/* Channel c's means over incident directions (weight cos theta_d) of a_b (*r), a_f (*tr) and
 * Zinke's local backscattering A_b (*Ab; may be NULL). */
void sl_dual_means(const sl_dual_tables *t, int c, double *r, double *tr, double *Ab);

#endif
