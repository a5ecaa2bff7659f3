/* raster.c: the C twin of kernels/raster.cl: the same splat loop (kernels/splat.h) and per-sample
 * operations (kernels/raster.h) run one segment after another with plain adds instead of atomics;
 * the fixed-point adds are exact, so the maps equal the kernel's bit for bit. Also builds the
 * segment records. */
#include "../cpu/raster.h"
#include "../kernels/raster.h"
#include "../kernels/splat.h"

#include <math.h>
#include <string.h>

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
 * even), without the libm call: below 2^23 adding and subtracting 2^23 rounds s to an integer in
 * that mode (the sum's ulp is 1) and both operations are exact otherwise; from 2^23 on a float
 * is already an integer. Bit-identical to llrintf (and to the kernel's convert_ulong_rte). */
static inline uint64_t round_share(float s) {
    if (s < 8388608.0f) return (uint64_t)((s + 8388608.0f) - 8388608.0f);
    return (uint64_t)s;
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

void slc_raster_z0(const float *recs, size_t nseg, int w, int h, uint32_t *z0bits) {
    for (size_t t = 0; t < (size_t)w * h; t++)
        z0bits[t] = SL_RASTER_Z_EMPTY;
    for (size_t s = 0; s < nseg; s++) {
        const float *rec = recs + s * SL_RASTER_REC;
        sl_splat it;
        sl_splat_begin(&it, rec, w, h, !rec_inside(rec, w, h));
        /* a sample at a time: the corner-by-corner walk costs more than this compare */
        while (sl_splat_next_sample(&it)) {
            const uint32_t b = bits_of(it.z);
            for (int c = 0; c < 4; c++) {
                /* llrintf(share) == 0 <=> share <= 0.5 (share >= 0; rint(0.5) = 0 by
                 * ties-to-even) */
                if (!(it.left >> c & 1u) || !(it.sh[c] > 0.5f)) continue;
                uint32_t *p = &z0bits[(size_t)(it.iy + (c >> 1)) * w + (it.ix + (c & 1))];
                if (b < *p) *p = b;
            }
        }
    }
}

/* sl_raster_layer with the boundaries precomputed: bnd[k] = (float)((k + 1)(k + 2) / 2) d, the
 * same float the kernel compares against. */
static inline unsigned layer_of(float dz, const float *bnd, unsigned K) {
    unsigned k = 0;
    while (k + 1u < K && dz > bnd[k])
        k++;
    return k;
}

static inline float z0_of(const uint32_t *z0bits, size_t t) {
    float z0;
    memcpy(&z0, &z0bits[t], sizeof z0);
    return z0;
}

void slc_raster_layers(const float *recs, size_t nseg, int w, int h, unsigned K, float d,
                       const uint32_t *z0bits, uint64_t *bins) {
    const size_t plane = (size_t)w * h;
    memset(bins, 0, K * plane * sizeof *bins);
    float bnd[SL_RASTER_MAX_LAYERS];
    if (K > SL_RASTER_MAX_LAYERS) K = SL_RASTER_MAX_LAYERS;
    for (unsigned k = 0; k + 1u < K; k++)
        bnd[k] = (float)((k + 1u) * (k + 2u) / 2u) * d;
    for (size_t s = 0; s < nseg; s++) {
        const float *rec = recs + s * SL_RASTER_REC;
        sl_splat it;
        sl_splat_begin(&it, rec, w, h, !rec_inside(rec, w, h));
        sl_int tx, ty;
        float share, z;
        while (sl_splat_next(&it, &tx, &ty, &share, &z)) {
            const uint64_t q = round_share(share);
            if (q == 0) continue;
            const size_t t = (size_t)ty * w + tx;
            bins[layer_of(z - z0_of(z0bits, t), bnd, K) * plane + t] += q;
        }
    }
}

void slc_raster_z0_dilate(uint32_t *z0bits, int w, int h, int m, uint32_t *tmp) {
    if (m <= 0) return;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            tmp[(size_t)y * w + x] = sl_raster_z0_window(z0bits, w, h, x, y, m, 1);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            z0bits[(size_t)y * w + x] = sl_raster_z0_window(tmp, w, h, x, y, m, 0);
}

void slc_raster_project(const float *pos, const uint32_t *seg, const float *hw, const float *views,
                        size_t nseg, unsigned nl, float mscale, float *recs) {
    for (unsigned l = 0; l < nl; l++)
        for (size_t s = 0; s < nseg; s++)
            sl_raster_project_seg(pos, seg, hw, views, (sl_uint)nseg, l, (sl_uint)s, mscale, recs);
}
