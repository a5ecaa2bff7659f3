/* raster.c: the C twin of kernels/raster.cl: the same splat loop (kernels/splat.h) and per-sample
 * operations (kernels/raster.h) run one segment after another with plain adds instead of atomics;
 * the fixed-point adds are exact, so the maps equal the kernel's bit for bit. Also builds the
 * segment records. */
#include "../cpu/raster.h"
#include "../kernels/raster.h"
#include "../kernels/splat.h"

#include <math.h>
#include <string.h>
#if defined(__x86_64__) && defined(__SSE2__)
#include <immintrin.h>
/* x86-64's baseline (no dispatch needed): the one-sample-wide in-map walks take four samples'
 * positions, tents and shares in one vector (quad_load). */
#define SL_RASTER_SSE2 1
#else
#define SL_RASTER_SSE2 0
#endif

/* The double-precision twin of sl_raster_record_f (kernels/raster.h: spacing and caps), for
 * callers that project on the host (tests, a future view pass). */
#define SAMPLE_SPACING 0.5
#define MAX_ALONG ((double)SL_RASTER_MAX_ALONG)
#define MAX_ACROSS ((double)SL_RASTER_MAX_ACROSS)
#define SL_RASTER_MAX_LAYERS 64 /* host/passes/light/shadow.h: SL_SHADOW_MAX_LAYERS */

void slc_raster_record(const double p0[3], const double p1[3], double hw, double scale,
                       float *rec) {
    memset(rec, 0, SL_RASTER_REC * sizeof *rec);
    double dx = p1[0] - p0[0], dy = p1[1] - p0[1], dz = p1[2] - p0[2];
    double len = sqrt(dx * dx + dy * dy);
    double area = 2.0 * hw * len; /* numerics.md sec. 7: 2 r l */
    if (!(area > 0) || !isfinite(area)) return;
    double na = fmin(fmax(1.0, ceil(len / SAMPLE_SPACING)), MAX_ALONG);
    double nw = fmin(fmax(1.0, ceil(2.0 * hw / SAMPLE_SPACING)), MAX_ACROSS);
    double ax = dx / na, ay = dy / na, az = dz / na;
    double nx = -dy / len, ny = dx / len; /* unit normal of the ribbon in the raster */
    double wx = nx * 2.0 * hw / nw, wy = ny * 2.0 * hw / nw;
    double off = -(nw - 1.0) / 2.0;
    rec[0] = (float)(p0[0] + 0.5 * ax + off * wx);
    rec[1] = (float)(p0[1] + 0.5 * ay + off * wy);
    rec[2] = (float)(p0[2] + 0.5 * az);
    rec[3] = (float)ax;
    rec[4] = (float)ay;
    rec[5] = (float)az;
    rec[6] = (float)wx;
    rec[7] = (float)wy;
    rec[8] = (float)(area * scale / (na * nw));
    rec[9] = (float)na;
    rec[10] = (float)nw;
}

/* (uint64_t)llrintf(s) for 0 <= s < 2^63 in the default rounding mode (to nearest, ties to
 * even), without the libm call. On x86-64 that is one cvtss2si (it rounds in the MXCSR's mode,
 * to nearest by default, and nothing here changes it). Elsewhere: below 2^23 adding and
 * subtracting 2^23 rounds s to an integer in that mode (the sum's ulp is 1) and both operations
 * are exact otherwise; from 2^23 on a float is already an integer. Bit-identical to llrintf (and
 * to the kernel's convert_ulong_rte) either way; the map total stays below 2^60
 * (host/passes/light/shadow.c: prep_make), so s < 2^63. */
static inline uint64_t round_share(float s) {
#if SL_RASTER_SSE2
    return (uint64_t)_mm_cvtss_si64(_mm_set_ss(s));
#else
    if (s < 8388608.0f) return (uint64_t)((s + 8388608.0f) - 8388608.0f);
    return (uint64_t)s;
#endif
}

static uint32_t bits_of(float f) {
    uint32_t b;
    memcpy(&b, &f, sizeof b);
    return b;
}

/* Whether every tent corner of every sample of rec lies inside the w x h map, with a texel of
 * slack for the rounding of the per-sample float positions: the splat loop then skips its
 * bounds checks (sl_splat_begin's clip = 0; which texels get what is unchanged). (Either
 * answer is right for a record without samples: it yields nothing.) */
static int rec_inside(const float *rec, int w, int h) {
    const double na = rec[9] - 1.0, nw = rec[10] - 1.0;
    double x0 = rec[0], y0 = rec[1], xl = x0, xh = x0, yl = y0, yh = y0;
    for (int c = 1; c < 4; c++) {
        const double x = x0 + ((c & 1) ? na * rec[3] : 0.0) + ((c & 2) ? nw * rec[6] : 0.0);
        const double y = y0 + ((c & 1) ? na * rec[4] : 0.0) + ((c & 2) ? nw * rec[7] : 0.0);
        xl = x < xl ? x : xl, xh = x > xh ? x : xh;
        yl = y < yl ? y : yl, yh = y > yh ? y : yh;
    }
    /* corners: floor(x - 0.5) - 1 .. floor(x - 0.5) + 2 with one texel of slack */
    return xl - 2.5 >= 0.0 && yl - 2.5 >= 0.0 && xh + 2.5 < (double)w && yh + 2.5 < (double)h;
}

/* sl_raster_tent (kernels/raster.h) for a sample of an in-map record (rec_inside holds: every
 * tent corner is at least a texel inside, so x - 0.5 and y - 0.5 are positive): floor is
 * truncation there, so one conversion per coordinate gives both the texel index and the floor.
 * The same ix, iy, fx, fy bit for bit; why: without SSE4.1 the compiler's floorf is a range test,
 * a branch and two conversions per coordinate, the largest part of the per-sample work
 * (docs/performance.md, "Light pass (session 8)"). The map is at most SL_SHADOW_MAX_SIZE texels
 * wide, far below 2^31. */
static inline void tent_inside(float x, float y, sl_int *ix, sl_int *iy, float *fx, float *fy) {
    const float gx = x - 0.5f, gy = y - 0.5f;
    const sl_int jx = (sl_int)gx, jy = (sl_int)gy;
    *ix = jx;
    *iy = jy;
    *fx = gx - (float)jx;
    *fy = gy - (float)jy;
}

/* *p = min(*p, b) where the share rounds to a non-zero integer (llrintf(share) == 0 <=>
 * share <= 0.5: share >= 0, and rint(0.5) = 0 by ties-to-even); written as selects, so the
 * compiler emits conditional moves instead of two unpredictable branches a corner. */
static inline void z0_min(uint32_t *p, uint32_t b, float share) {
    const uint32_t v = *p;
    *p = (share > 0.5f) & (b < v) ? b : v;
}

/* One in-map record's first depths (rec_inside holds): the walk of sl_splat_next_sample
 * (kernels/splat.h) written out for the C path, with the same float operations from
 * kernels/raster.h in the same order (sl_raster_sample, sl_raster_tent as tent_inside,
 * sl_raster_share), so the same texels get the same depths; only the iterator's state is kept in
 * registers instead of a struct, and the four corners are written directly (no bounds test is
 * needed). Why: the light pass walks ~2.7 M samples per 256^2 map on the goal scene, and the
 * generic walk cost ~16 ns a sample in this pass (docs/performance.md, "Light pass and march
 * (session 7)"). */
static void z0_inside(const float *rec, int w, uint32_t *z0bits) {
    const float m = rec[8];
    const sl_uint na = (sl_uint)rec[9], nw = (sl_uint)rec[10];
    for (sl_uint i = 0; i < na; i++)
        for (sl_uint j = 0; j < nw; j++) {
            float x, y, z, fx, fy;
            sl_int ix, iy;
            sl_raster_sample(rec, i, j, &x, &y, &z);
            tent_inside(x, y, &ix, &iy, &fx, &fy);
            const float gx = 1.0f - fx, gy = 1.0f - fy;
            const uint32_t b = bits_of(z);
            uint32_t *p = z0bits + (size_t)iy * w + ix;
            z0_min(p, b, sl_raster_share(m, gx, gy));
            z0_min(p + 1, b, sl_raster_share(m, fx, gy));
            z0_min(p + w, b, sl_raster_share(m, gx, fy));
            z0_min(p + w + 1, b, sl_raster_share(m, fx, fy));
        }
}

#if SL_RASTER_SSE2
/* Samples i0 .. i0 + 3 (j = 0) of a one-sample-wide in-map record (nw = 1, the common case for
 * hair: widths are far below a texel), lane l being sample i0 + l: the operations of
 * sl_raster_sample, tent_inside and sl_raster_share, in the same order on the same operands
 * lane by lane (cvttps2dq truncates as the scalar (int) does; fi counts up by 1.0f, exact below
 * 2^24 = SL_RASTER_MAX_SAMPLES), so every texel gets the scalar walk's share and depth. Why:
 * the per-sample arithmetic is ~1/3 of the walks' instructions; four lanes take ~15 % off the
 * map (docs/performance.md, "Light pass (session 8)"). Lanes past the record's end are computed
 * and not used. */
typedef struct quad4 {
    int32_t ix[4], iy[4];
    float z[4], s[4][4]; /* s[corner][lane] */
} quad4;

static inline void quad_load(const float *rec, __m128 fi, quad4 *q) {
    const __m128 fj = _mm_setzero_ps(), half = _mm_set1_ps(0.5f), one = _mm_set1_ps(1.0f);
    const __m128 x =
        _mm_add_ps(_mm_add_ps(_mm_set1_ps(rec[0]), _mm_mul_ps(fi, _mm_set1_ps(rec[3]))),
                   _mm_mul_ps(fj, _mm_set1_ps(rec[6])));
    const __m128 y =
        _mm_add_ps(_mm_add_ps(_mm_set1_ps(rec[1]), _mm_mul_ps(fi, _mm_set1_ps(rec[4]))),
                   _mm_mul_ps(fj, _mm_set1_ps(rec[7])));
    const __m128 z = _mm_add_ps(_mm_set1_ps(rec[2]), _mm_mul_ps(fi, _mm_set1_ps(rec[5])));
    const __m128 gx = _mm_sub_ps(x, half), gy = _mm_sub_ps(y, half);
    const __m128i ix = _mm_cvttps_epi32(gx), iy = _mm_cvttps_epi32(gy);
    const __m128 fx = _mm_sub_ps(gx, _mm_cvtepi32_ps(ix)), fy = _mm_sub_ps(gy, _mm_cvtepi32_ps(iy));
    const __m128 ux = _mm_sub_ps(one, fx), uy = _mm_sub_ps(one, fy), m = _mm_set1_ps(rec[8]);
    _mm_storeu_si128((__m128i *)q->ix, ix);
    _mm_storeu_si128((__m128i *)q->iy, iy);
    _mm_storeu_ps(q->z, z);
    _mm_storeu_ps(q->s[0], _mm_mul_ps(_mm_mul_ps(m, ux), uy));
    _mm_storeu_ps(q->s[1], _mm_mul_ps(_mm_mul_ps(m, fx), uy));
    _mm_storeu_ps(q->s[2], _mm_mul_ps(_mm_mul_ps(m, ux), fy));
    _mm_storeu_ps(q->s[3], _mm_mul_ps(_mm_mul_ps(m, fx), fy));
}

/* z0_inside for nw = 1, four samples a step. */
static void z0_quads(const float *rec, int w, uint32_t *z0bits) {
    const sl_uint na = (sl_uint)rec[9];
    __m128 fi = _mm_setr_ps(0.0f, 1.0f, 2.0f, 3.0f);
    const __m128 four = _mm_set1_ps(4.0f);
    quad4 q;
    for (sl_uint i = 0; i < na; i += 4, fi = _mm_add_ps(fi, four)) {
        quad_load(rec, fi, &q);
        const sl_uint n = na - i < 4 ? na - i : 4;
        for (sl_uint l = 0; l < n; l++) {
            const uint32_t b = bits_of(q.z[l]);
            uint32_t *p = z0bits + (size_t)q.iy[l] * w + q.ix[l];
            z0_min(p, b, q.s[0][l]);
            z0_min(p + 1, b, q.s[1][l]);
            z0_min(p + w, b, q.s[2][l]);
            z0_min(p + w + 1, b, q.s[3][l]);
        }
    }
}
#endif

void slc_raster_z0(const float *recs, size_t nseg, int w, int h, uint32_t *z0bits) {
    for (size_t t = 0; t < (size_t)w * h; t++)
        z0bits[t] = SL_RASTER_Z_EMPTY;
    for (size_t s = 0; s < nseg; s++) {
        const float *rec = recs + s * SL_RASTER_REC;
        if (rec_inside(rec, w, h)) {
#if SL_RASTER_SSE2
            if (rec[10] == 1.0f) {
                z0_quads(rec, w, z0bits);
                continue;
            }
#endif
            z0_inside(rec, w, z0bits);
            continue;
        }
        sl_splat it;
        sl_splat_begin(&it, rec, w, h, 1);
        /* a sample at a time: the corner-by-corner walk costs more than this compare */
        while (sl_splat_next_sample(&it)) {
            const uint32_t b = bits_of(it.z);
            for (int c = 0; c < 4; c++) {
                if (!(it.left >> c & 1u) || !(it.sh[c] > 0.5f)) continue;
                uint32_t *p = &z0bits[(size_t)(it.iy + (c >> 1)) * w + (it.ix + (c & 1))];
                if (b < *p) *p = b;
            }
        }
    }
}

/* sl_raster_layer with the boundaries precomputed: bnd[k] = (float)((k + 1)(k + 2) / 2) d, the
 * same float the kernel compares against. The boundaries do not decrease (d > 0; rounding is
 * monotonic), so the loop's k, the first boundary dz does not pass, is the number of boundaries
 * it passes: a count without branches (NaN passes none: 0 either way). */
static inline unsigned layer_of(float dz, const float *bnd, unsigned K) {
    unsigned k = 0;
    for (unsigned b = 0; b + 1u < K; b++)
        k += dz > bnd[b];
    return k;
}

static inline float z0_of(const uint32_t *z0bits, size_t t) {
    return sl_raster_z_of(z0bits[t]);
}

/* Where layer k of texel t lives: bins[k * ks + t * ts] (planes: ks = w h, ts = 1; texel-major:
 * ks = 1, ts = K, a texel's K layers in one cache line). */
typedef struct layer_out {
    uint64_t *bins;
    size_t ks, ts;
    const float *bnd;
    unsigned K;
    const uint32_t *z0bits;
} layer_out;

static inline void layer_add(const layer_out *o, size_t t, float share, float z) {
    const uint64_t q = round_share(share);
    if (q == 0) return;
    o->bins[layer_of(z - z0_of(o->z0bits, t), o->bnd, o->K) * o->ks + t * o->ts] += q;
}

/* Corner t of an in-map sample with K layers side by side (texel-major): the share is added
 * whether or not it rounds to 0 (adding 0 changes no sum), so there is no branch; a zero share's
 * texel may have no first depth (dz = -inf: layer 0), harmless for the same reason. */
static inline __attribute__((always_inline)) void layer_add_tk(uint64_t *bins, const float *bnd,
                                                               const uint32_t *z0bits, unsigned K,
                                                               size_t t, float share, float z) {
    bins[t * K + layer_of(z - z0_of(z0bits, t), bnd, K)] += round_share(share);
}

/* One in-map record's layers: the walk of sl_splat_next written out as z0_inside is (same
 * operations, same texels and shares). texel-major with K a constant after inlining (the
 * renderer's K = 4 gets its own copy: the layer count and the index unrolled). */
static inline __attribute__((always_inline)) void layers_inside_tk(const float *rec, int w,
                                                                   const layer_out *o, unsigned K) {
    const float m = rec[8];
    const sl_uint na = (sl_uint)rec[9], nw = (sl_uint)rec[10];
    uint64_t *bins = o->bins;
    const float *bnd = o->bnd;
    const uint32_t *z0 = o->z0bits;
    for (sl_uint i = 0; i < na; i++)
        for (sl_uint j = 0; j < nw; j++) {
            float x, y, z, fx, fy;
            sl_int ix, iy;
            sl_raster_sample(rec, i, j, &x, &y, &z);
            tent_inside(x, y, &ix, &iy, &fx, &fy);
            const float gx = 1.0f - fx, gy = 1.0f - fy;
            const size_t t = (size_t)iy * w + ix;
            layer_add_tk(bins, bnd, z0, K, t, sl_raster_share(m, gx, gy), z);
            layer_add_tk(bins, bnd, z0, K, t + 1, sl_raster_share(m, fx, gy), z);
            layer_add_tk(bins, bnd, z0, K, t + w, sl_raster_share(m, gx, fy), z);
            layer_add_tk(bins, bnd, z0, K, t + w + 1, sl_raster_share(m, fx, fy), z);
        }
}

#if SL_RASTER_SSE2
/* layers_inside_tk for K = 4 and nw = 1, four samples a step (quad_load). */
static void layers4_quads(const float *rec, int w, const layer_out *o) {
    const sl_uint na = (sl_uint)rec[9];
    uint64_t *bins = o->bins;
    const float *bnd = o->bnd;
    const uint32_t *z0 = o->z0bits;
    __m128 fi = _mm_setr_ps(0.0f, 1.0f, 2.0f, 3.0f);
    const __m128 four = _mm_set1_ps(4.0f);
    quad4 q;
    for (sl_uint i = 0; i < na; i += 4, fi = _mm_add_ps(fi, four)) {
        quad_load(rec, fi, &q);
        const sl_uint n = na - i < 4 ? na - i : 4;
        for (sl_uint l = 0; l < n; l++) {
            const size_t t = (size_t)q.iy[l] * w + q.ix[l];
            const float z = q.z[l];
            layer_add_tk(bins, bnd, z0, 4, t, q.s[0][l], z);
            layer_add_tk(bins, bnd, z0, 4, t + 1, q.s[1][l], z);
            layer_add_tk(bins, bnd, z0, 4, t + w, q.s[2][l], z);
            layer_add_tk(bins, bnd, z0, 4, t + w + 1, q.s[3][l], z);
        }
    }
}
#endif

/* The same for any layout (planes, or texel-major with an uncommon K). */
static void layers_inside(const float *rec, int w, const layer_out *o) {
    if (o->ks == 1 && o->K == 4) {
#if SL_RASTER_SSE2
        if (rec[10] == 1.0f) {
            layers4_quads(rec, w, o);
            return;
        }
#endif
        layers_inside_tk(rec, w, o, 4);
        return;
    }
    if (o->ks == 1) {
        layers_inside_tk(rec, w, o, o->K);
        return;
    }
    const float m = rec[8];
    const sl_uint na = (sl_uint)rec[9], nw = (sl_uint)rec[10];
    for (sl_uint i = 0; i < na; i++)
        for (sl_uint j = 0; j < nw; j++) {
            float x, y, z, fx, fy;
            sl_int ix, iy;
            sl_raster_sample(rec, i, j, &x, &y, &z);
            tent_inside(x, y, &ix, &iy, &fx, &fy);
            const float gx = 1.0f - fx, gy = 1.0f - fy;
            const size_t t = (size_t)iy * w + ix;
            layer_add(o, t, sl_raster_share(m, gx, gy), z);
            layer_add(o, t + 1, sl_raster_share(m, fx, gy), z);
            layer_add(o, t + w, sl_raster_share(m, gx, fy), z);
            layer_add(o, t + w + 1, sl_raster_share(m, fx, fy), z);
        }
}

static void layers_run(const float *recs, size_t nseg, int w, int h, unsigned K, float d,
                       const uint32_t *z0bits, uint64_t *bins, int texel_major) {
    const size_t plane = (size_t)w * h;
    if (K > SL_RASTER_MAX_LAYERS) K = SL_RASTER_MAX_LAYERS;
    memset(bins, 0, K * plane * sizeof *bins);
    float bnd[SL_RASTER_MAX_LAYERS];
    for (unsigned k = 0; k + 1u < K; k++)
        bnd[k] = (float)((k + 1u) * (k + 2u) / 2u) * d;
    const layer_out o = {bins, texel_major ? 1 : plane, texel_major ? K : 1, bnd, K, z0bits};
    for (size_t s = 0; s < nseg; s++) {
        const float *rec = recs + s * SL_RASTER_REC;
        if (rec_inside(rec, w, h)) {
            layers_inside(rec, w, &o);
            continue;
        }
        sl_splat it;
        sl_splat_begin(&it, rec, w, h, 1);
        sl_int tx, ty;
        float share, z;
        while (sl_splat_next(&it, &tx, &ty, &share, &z))
            layer_add(&o, (size_t)ty * w + tx, share, z);
    }
}

void slc_raster_layers(const float *recs, size_t nseg, int w, int h, unsigned K, float d,
                       const uint32_t *z0bits, uint64_t *bins) {
    layers_run(recs, nseg, w, h, K, d, z0bits, bins, 0);
}

void slc_raster_layers_texel(const float *recs, size_t nseg, int w, int h, unsigned K, float d,
                             const uint32_t *z0bits, uint64_t *bins) {
    layers_run(recs, nseg, w, h, K, d, z0bits, bins, 1);
}

void slc_raster_z0_dilate(uint32_t *z0bits, int w, int h, int m, float frac, uint32_t *tmp,
                          uint32_t *tmp2) {
    if (m < 0) m = 0;
    const int blend = frac > 0.0f;
    if (m == 0 && !blend) return;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            tmp[(size_t)y * w + x] = sl_raster_z0_window(z0bits, w, h, x, y, m, 1);
            if (blend) tmp2[(size_t)y * w + x] = sl_raster_z0_window(z0bits, w, h, x, y, m + 1, 1);
        }
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const sl_uint a = sl_raster_z0_window(tmp, w, h, x, y, m, 0);
            z0bits[(size_t)y * w + x] =
                blend ? sl_raster_z0_blend(a, sl_raster_z0_window(tmp2, w, h, x, y, m + 1, 0), frac)
                      : a;
        }
}

void slc_raster_project(const float *pos, const uint32_t *seg, const float *hw, const float *views,
                        size_t nseg, unsigned nl, float mscale, float *recs) {
    for (unsigned l = 0; l < nl; l++)
        for (size_t s = 0; s < nseg; s++)
            sl_raster_project_seg(pos, seg, hw, views, (sl_uint)nseg, l, (sl_uint)s, mscale, recs);
}
