/* raytrace_ref.c: see raytrace_ref.h. Embree 3 C API: one round-linear-curve geometry, geometry
 * filter functions that skip the shading fiber and, for crossings, record every hit and reject
 * it so that traversal visits all of them. */
#include "raytrace_ref.h"

#include <embree3/rtcore.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

struct slref_rt {
    RTCDevice dev;
    RTCScene scene;
    uint32_t nprims;
    uint32_t *prim_strand, *prim_seg;
    float *prim_tan; /* 3 per prim */
    float *prim_pr;  /* 5 per prim: first point, its radius, the second point's radius */
};

enum { RT_MAX_HITS = 1024 };

/* The C API has no RTCHitN/RTCRayN accessors (C++ only): SOA layout of rtcore_ray.h. */

/* Our context extends Embree's (Embree passes the pointer we give it back to the filters). */
typedef struct rt_ctx {
    struct RTCIntersectContext ctx; /* must be first */
    const slref_rt *rt;
    uint32_t own_strand, own_seg;
    int collect; /* 1: record and reject every hit (crossings) */
    int n;
    float t[RT_MAX_HITS];
    uint32_t prim[RT_MAX_HITS];
} rt_ctx;

static int is_own(const rt_ctx *c, uint32_t prim) {
    if (c->own_strand == SLREF_RT_NONE || c->rt->prim_strand[prim] != c->own_strand) return 0;
    uint32_t s = c->rt->prim_seg[prim];
    return s + 1 >= c->own_seg && s <= c->own_seg + 1;
}

static void filter(const struct RTCFilterFunctionNArguments *args) {
    rt_ctx *c = (rt_ctx *)args->context;
    for (unsigned i = 0; i < args->N; i++) {
        if (args->valid[i] != -1) continue;
        uint32_t prim = ((const unsigned *)args->hit)[5 * args->N + i]; /* RTCHitN_primID */
        if (is_own(c, prim)) {
            args->valid[i] = 0;
            continue;
        }
        /* A hit where the ray leaves a fiber (the geometric normal along the ray) is not a hit:
         * a ray that starts inside another, interpenetrating fiber passes out of it, as in
         * Cycles (docs/validation.md, "What the gap was"). Camera rays never start inside. */
        if (!c->collect) {
            const float *ng = (const float *)args->hit, *ry = (const float *)args->ray;
            unsigned n = args->N;
            double dn = (double)ng[i] * ry[4 * n + i] + (double)ng[n + i] * ry[5 * n + i] +
                        (double)ng[2 * n + i] * ry[6 * n + i];
            if (dn > 0) {
                args->valid[i] = 0;
                continue;
            }
        }
        if (c->collect) {
            if (c->n < RT_MAX_HITS) {
                c->t[c->n] = ((const float *)args->ray)[8 * args->N + i]; /* RTCRayN_tfar */
                c->prim[c->n] = prim;
                c->n++;
            }
            args->valid[i] = 0;
        }
    }
}

static void error_cb(void *user, enum RTCError code, const char *str) {
    (void)user;
    (void)code;
    (void)str; /* reported through rtcGetDeviceError where it matters */
}

int slref_rt_build(const sl_hair *h, slref_rt **out, sl_err *e) {
    *out = NULL;
    if (h->num_points < 2 || h->num_strands == 0) return sl_fail(e, "hair: no segments to trace");
    slref_rt *rt = sl_calloc(1, sizeof *rt);
    rt->dev = rtcNewDevice("verbose=0");
    if (!rt->dev) {
        free(rt);
        return sl_fail(e, "embree: cannot create a device (error %d)",
                       (int)rtcGetDeviceError(NULL));
    }
    rtcSetDeviceErrorFunction(rt->dev, error_cb, NULL);
    rt->nprims = h->num_points - h->num_strands;
    rt->prim_strand = sl_malloc((size_t)rt->nprims * sizeof(uint32_t));
    rt->prim_seg = sl_malloc((size_t)rt->nprims * sizeof(uint32_t));
    rt->prim_tan = sl_malloc((size_t)rt->nprims * 3 * sizeof(float));
    rt->prim_pr = sl_malloc((size_t)rt->nprims * 5 * sizeof(float));
    RTCGeometry g = rtcNewGeometry(rt->dev, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
    float *vb = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                        4 * sizeof(float), h->num_points);
    unsigned *ib = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT,
                                           sizeof(unsigned), rt->nprims);
    if (!vb || !ib) {
        rtcReleaseGeometry(g);
        slref_rt_free(rt);
        return sl_fail(e, "embree: cannot allocate the curve buffers (%u points)", h->num_points);
    }
    for (uint32_t i = 0; i < h->num_points; i++) {
        for (int k = 0; k < 3; k++)
            vb[4 * i + k] = h->pos[3 * i + k];
        vb[4 * i + 3] = h->radius ? h->radius[i] : h->default_radius;
    }
    uint32_t p = 0;
    for (uint32_t s = 0; s < h->num_strands; s++) {
        for (uint32_t i = h->strand_first[s]; i + 1 < h->strand_first[s + 1]; i++, p++) {
            ib[p] = i;
            rt->prim_strand[p] = s;
            rt->prim_seg[p] = i - h->strand_first[s];
            sl_hair_tangent(h, s, rt->prim_seg[p], rt->prim_tan + 3 * p);
            for (int k = 0; k < 3; k++)
                rt->prim_pr[5 * p + k] = h->pos[3 * i + k];
            rt->prim_pr[5 * p + 3] = h->radius ? h->radius[i] : h->default_radius;
            rt->prim_pr[5 * p + 4] = h->radius ? h->radius[i + 1] : h->default_radius;
        }
    }
    rtcSetGeometryIntersectFilterFunction(g, filter);
    rtcSetGeometryOccludedFilterFunction(g, filter);
    rtcCommitGeometry(g);
    rt->scene = rtcNewScene(rt->dev);
    rtcSetSceneFlags(rt->scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(rt->scene, RTC_BUILD_QUALITY_HIGH);
    rtcAttachGeometry(rt->scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(rt->scene);
    enum RTCError err = rtcGetDeviceError(rt->dev);
    if (err != RTC_ERROR_NONE) {
        slref_rt_free(rt);
        return sl_fail(e, "embree: scene build failed (error %d)", (int)err);
    }
    *out = rt;
    return 0;
}

void slref_rt_free(slref_rt *rt) {
    if (!rt) return;
    if (rt->scene) rtcReleaseScene(rt->scene);
    if (rt->dev) rtcReleaseDevice(rt->dev);
    free(rt->prim_strand);
    free(rt->prim_seg);
    free(rt->prim_tan);
    free(rt->prim_pr);
    free(rt);
}

uint32_t slref_rt_num_prims(const slref_rt *rt) {
    return rt->nprims;
}

static void ctx_init(rt_ctx *c, const slref_rt *rt, uint32_t own_strand, uint32_t own_seg,
                     int collect) {
    rtcInitIntersectContext(&c->ctx);
    c->rt = rt;
    c->own_strand = own_strand;
    c->own_seg = own_seg;
    c->collect = collect;
    c->n = 0;
}

static void ray_init(struct RTCRay *r, const double o[3], const double d[3], double tmax) {
    memset(r, 0, sizeof *r);
    r->org_x = (float)o[0], r->org_y = (float)o[1], r->org_z = (float)o[2];
    r->dir_x = (float)d[0], r->dir_y = (float)d[1], r->dir_z = (float)d[2];
    r->tnear = 0.0f;
    r->tfar = tmax < 3e38 ? (float)tmax : INFINITY;
    r->mask = 0xffffffffu;
}

int slref_rt_intersect(const slref_rt *rt, const double o[3], const double d[3], double tmax,
                       slref_hit *hit) {
    return slref_rt_intersect_excl(rt, o, d, tmax, SLREF_RT_NONE, 0, hit);
}

int slref_rt_intersect_excl(const slref_rt *rt, const double o[3], const double d[3], double tmax,
                            uint32_t own_strand, uint32_t own_seg, slref_hit *hit) {
    rt_ctx c;
    ctx_init(&c, rt, own_strand, own_seg, 0);
    struct RTCRayHit rh;
    ray_init(&rh.ray, o, d, tmax);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(rt->scene, &c.ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return 0;
    hit->t = rh.ray.tfar;
    hit->prim = rh.hit.primID;
    hit->strand = rt->prim_strand[hit->prim];
    hit->seg = rt->prim_seg[hit->prim];
    hit->u = rh.hit.u;
    return 1;
}

int slref_rt_occluded(const slref_rt *rt, const double o[3], const double d[3], uint32_t own_strand,
                      uint32_t own_seg) {
    rt_ctx c;
    ctx_init(&c, rt, own_strand, own_seg, 0);
    struct RTCRay r;
    ray_init(&r, o, d, INFINITY);
    rtcOccluded1(rt->scene, &c.ctx, &r);
    return r.tfar < 0; /* Embree sets tfar = -inf on occlusion */
}

int slref_rt_crossings(const slref_rt *rt, const double o[3], const double d[3],
                       uint32_t own_strand, uint32_t own_seg, uint32_t *seg_prim, int max) {
    rt_ctx *c = sl_malloc(sizeof *c);
    ctx_init(c, rt, own_strand, own_seg, 1);
    struct RTCRay r;
    ray_init(&r, o, d, INFINITY);
    rtcOccluded1(rt->scene, &c->ctx, &r);
    /* Sort the hits by t (insertion sort: a few dozen at most in practice), then merge hits on
     * one strand whose segments are within 1 of a crossing already found on that strand. */
    for (int i = 1; i < c->n; i++) {
        float t = c->t[i];
        uint32_t p = c->prim[i];
        int j = i - 1;
        while (j >= 0 && (c->t[j] > t || (c->t[j] == t && c->prim[j] > p))) {
            c->t[j + 1] = c->t[j];
            c->prim[j + 1] = c->prim[j];
            j--;
        }
        c->t[j + 1] = t;
        c->prim[j + 1] = p;
    }
    int nx = 0;
    uint32_t *lo = sl_malloc((size_t)(c->n + 1) * sizeof(uint32_t));
    uint32_t *hi = sl_malloc((size_t)(c->n + 1) * sizeof(uint32_t));
    uint32_t *st = sl_malloc((size_t)(c->n + 1) * sizeof(uint32_t));
    for (int i = 0; i < c->n; i++) {
        uint32_t p = c->prim[i], s = rt->prim_strand[p], g = rt->prim_seg[p];
        int merged = 0;
        for (int k = 0; k < nx && !merged; k++) {
            if (st[k] == s && g + 1 >= lo[k] && g <= hi[k] + 1) {
                if (g < lo[k]) lo[k] = g;
                if (g > hi[k]) hi[k] = g;
                merged = 1;
            }
        }
        if (merged) continue;
        st[nx] = s, lo[nx] = hi[nx] = g;
        if (nx < max) seg_prim[nx] = p;
        nx++;
    }
    free(lo);
    free(hi);
    free(st);
    free(c);
    return nx;
}

void slref_rt_prim_info(const slref_rt *rt, uint32_t prim, uint32_t *strand, uint32_t *seg,
                        double tangent[3]) {
    if (strand) *strand = rt->prim_strand[prim];
    if (seg) *seg = rt->prim_seg[prim];
    if (tangent)
        for (int k = 0; k < 3; k++)
            tangent[k] = rt->prim_tan[3 * prim + k];
}

void slref_rt_prim_axis(const slref_rt *rt, uint32_t prim, double t, double p0[3], double *radius) {
    const float *q = rt->prim_pr + 5 * (size_t)prim;
    for (int k = 0; k < 3; k++)
        p0[k] = q[k];
    if (t < 0) t = 0;
    if (t > 1) t = 1;
    *radius = q[3] + t * ((double)q[4] - q[3]);
}
