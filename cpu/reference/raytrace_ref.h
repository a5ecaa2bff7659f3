/* raytrace_ref.h: the hair as Intel Embree 3 geometry for the reference renderer
 * (docs/reference.md): every strand segment is a RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE primitive
 * (a cone with spherical joints) of the fiber radius, so rays meet the actual fibers, not a
 * density. Three queries: the closest hit (camera rays), any hit (shadow rays: fibers are opaque
 * for single scattering, numerics.md sec. 7) and the list of fibers a ray crosses (dual
 * scattering's forward path, Zinke 2008). The closest-hit and any-hit queries count only hits
 * where the ray enters a fiber (geometric normal against the ray): a ray starting inside an
 * interpenetrating fiber leaves it without a hit, as in Cycles; the crossings list is unchanged.
 * Queries are thread-safe after build. */
#ifndef SL_RAYTRACE_REF_H
#define SL_RAYTRACE_REF_H

#include "io/hair/hair.h"

#include <stdint.h>

typedef struct slref_rt slref_rt;

#define SLREF_RT_NONE 0xffffffffu

typedef struct slref_hit {
    double t;        /* distance along the (unit) ray direction */
    uint32_t prim;   /* Embree primitive = global segment index */
    uint32_t strand; /* strand of the segment */
    uint32_t seg;    /* segment within the strand (points seg -> seg+1) */
    double u;        /* curve parameter along the segment in [0, 1] */
} slref_hit;

/* Builds the scene (positions and radii copied; h may be freed afterwards). */
int slref_rt_build(const sl_hair *h, slref_rt **out, sl_err *e);
void slref_rt_free(slref_rt *rt);
uint32_t slref_rt_num_prims(const slref_rt *rt);

/* Closest hit along o + t d, t in (0, tmax). Returns 1 and fills hit, or 0. */
int slref_rt_intersect(const slref_rt *rt, const double o[3], const double d[3], double tmax,
                       slref_hit *hit);

/* The closest hit along o + t d, t in (0, tmax), ignoring the segments of strand own_strand
 * within 1 of own_seg (as slref_rt_occluded): a path's continuation ray leaves the surface of
 * the fiber it scattered on, whose scattering (TT, TRT) the fiber function already holds. */
int slref_rt_intersect_excl(const slref_rt *rt, const double o[3], const double d[3], double tmax,
                            uint32_t own_strand, uint32_t own_seg, slref_hit *hit);

/* 1 when o + t d (t > 0) meets a fiber. Hits on the segments of strand `own_strand` whose index
 * is within 1 of `own_seg` are ignored (a point on a fiber's surface is not shadowed by that
 * fiber: numerics.md sec. 7); own_strand = SLREF_RT_NONE ignores nothing. */
int slref_rt_occluded(const slref_rt *rt, const double o[3], const double d[3], uint32_t own_strand,
                      uint32_t own_seg);

/* The fibers o + t d (t > 0) crosses, with the same exclusion as slref_rt_occluded: hits on one
 * strand on consecutive segments (a ray passing a joint, or entering and leaving one cone) count
 * as one crossing. Writes up to max crossings (the segment of the first hit of each, sorted by
 * t) into seg_prim and returns the number of crossings found (may exceed max). */
int slref_rt_crossings(const slref_rt *rt, const double o[3], const double d[3],
                       uint32_t own_strand, uint32_t own_seg, uint32_t *seg_prim, int max);

/* The strand/segment of a primitive and the unit tangent of that segment (sl_hair_tangent). */
void slref_rt_prim_info(const slref_rt *rt, uint32_t prim, uint32_t *strand, uint32_t *seg,
                        double tangent[3]);

/* The axis of a primitive: its first point p0 (the segment runs p0 -> p0 + len tangent) and
 * the fiber radius at curve parameter t in [0, 1] (linear between the two points' radii). */
void slref_rt_prim_axis(const slref_rt *rt, uint32_t prim, double t, double p0[3], double *radius);

#endif
