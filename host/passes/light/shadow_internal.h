/* shadow_internal.h: what the light pass (shadow.c) and its OpenCL side (shadow_cl.c) share;
 * private to host/passes/light/. */
#ifndef SL_SHADOW_INTERNAL_H
#define SL_SHADOW_INTERNAL_H

#include "passes/light/shadow.h"

#include <stdint.h>

/* What every lobe of a build shares: the kept segments (stochastic simplification) with their
 * half-widths in texels (all lobes' views have the same texel: the same bounding sphere), the
 * fixed-point scale, and the z0 window. */
typedef struct prep {
    uint32_t *seg; /* first point of each kept segment */
    float *hw;     /* half-width, texels, widened by 1 / kappa (Ren 2010 Sec. 7) */
    size_t nseg;
    double scale, texel;
    int z0_radius;
    float z0_frac; /* the window's fractional half-size beyond z0_radius (automatic window) */
    float lo[3], hi[3];
    double margin;
    int threads; /* C path */
} prep;

/* One launch's lobes l0 .. l0 + nl - 1 and where their maps live. */
struct sl_shadow_group {
    unsigned l0, nl;
    float *views, *params; /* nl * SL_RASTER_VIEW, nl * SL_DODM_PARAMS */
    uint32_t *z0;          /* C path: nl planes */
    uint64_t *sat;         /* C path: nl * K planes */
    cl_mem bz, bs, bviews, bparams;
};

/* ---- shadow_cl.c: the light pass on the device ---- */

/* The hair uploaded once, then per group of up to SL_SHADOW_BATCH lobes one launch of each
 * kernel (projection, z0, window, layers, tables); the maps stay on the device (b->group[i].bz,
 * bs, bviews, bparams). Returns 0, -1 or SL_CL_EKERNEL. */
int slcl_shadow_build(sl_cl *cl, const sl_hair *h, const prep *p, sl_shadow_batch *b, sl_err *e);
/* Releases g's device maps (those made) and clears them. */
void slcl_shadow_group_release(struct sl_shadow_group *g);
/* T of the n points pts (3 n floats) toward lobe lb[i] (lb NULL: toward every lobe) into t
 * (nout floats), from the maps on b->cl. */
int slcl_shadow_lookup(const sl_shadow_batch *b, size_t n, const float *pts, const uint32_t *lb,
                       size_t nout, float *t, sl_err *e);
/* Copies lobe g->l0 + l's maps from the device: z0bits (w * h), sat (K * w * h). */
int slcl_shadow_read(const sl_shadow_batch *b, const struct sl_shadow_group *g, unsigned l,
                     uint32_t *z0bits, uint64_t *sat, sl_err *e);

#endif
