/* srbf_ren_c.c: the C twin's batch lookup in the Ren 2010 table (see srbf_ren_c.h).
 *
 * Two costs, measured on the 2-core Xeon (docs/srbf_ren.md, "Speed"): the coordinates of a row
 * (two divisions, five square roots, a log and an exp polynomial, six warped h cells: about 60 %
 * of the time with the table in cache) and the 16-corner reads of a 16.6 MB table that rows in
 * no useful order mostly miss. So the batch
 *  - computes the coordinates of 4 rows at once in SSE (GCC vector extensions; the same IEEE
 *    float operations in the same order as the scalar sl_srbf_ren_coords, so the results are
 *    bit-identical to it and to the OpenCL kernel's arithmetic up to the kernel compiler's own
 *    contractions), and
 *  - runs a pipeline: the corners of the next block of 4 rows are computed and their cache
 *    lines prefetched while the current block is blended (sl_srbf_ren_blend), so the misses of
 *    several rows overlap. */
#include "srbf_ren_c.h"

#include <string.h>

#if defined(__GNUC__) && defined(__SSE2__)
#include <emmintrin.h>
#define SL_REN_SIMD 1
#else
#define SL_REN_SIMD 0
#endif

static void prefetch_row(const sl_srbf_ren *t, const sl_srbf_ren_pt *q) {
#if defined(__GNUC__)
    const float *R = t->T + t->dims.off[0], *TT = t->T + t->dims.off[1],
                *TRT = t->T + t->dims.off[2];
    for (int c = 0; c < 8; c++) {
        int s = c >> 2;
        __builtin_prefetch(R + q->o8[c] + q->ih[s]);
        __builtin_prefetch(TT + 4 * (q->o8[c] + q->ih[2 + s]));
        __builtin_prefetch(TRT + 4 * (q->o8[c] + q->ih[4 + s]));
    }
#else
    (void)t, (void)q;
#endif
}

#if SL_REN_SIMD
typedef float v4f __attribute__((vector_size(16)));
typedef int v4i __attribute__((vector_size(16)));

static inline v4f splat(float x) {
    return (v4f){x, x, x, x};
}
/* a where m (all ones), else b */
static inline v4f sel(v4i m, v4f a, v4f b) {
    return (v4f)(((v4i)a & m) | ((v4i)b & ~m));
}
static inline v4f vabs(v4f x) {
    return (v4f)((v4i)x & (v4i){0x7fffffff, 0x7fffffff, 0x7fffffff, 0x7fffffff});
}
/* sl_clampf of C: x < lo ? lo : (x > hi ? hi : x) */
static inline v4f clampv(v4f x, float lo, float hi) {
    v4f l = splat(lo), h = splat(hi);
    return sel(x < l, l, sel(x > h, h, x));
}
static inline v4f maxv(v4f a, v4f b) { /* a > b ? a : b */
    return sel(a > b, a, b);
}
static inline v4f minv(v4f a, v4f b) { /* a < b ? a : b */
    return sel(a < b, a, b);
}
static inline v4f sqrtv(v4f x) {
    return (v4f)_mm_sqrt_ps((__m128)x);
}
static inline v4i truncv(v4f x) { /* (int)x, round toward zero */
    return __builtin_convertvector(x, v4i);
}
static inline v4f tofv(v4i x) {
    return __builtin_convertvector(x, v4f);
}
/* sl_srbf_ren_cell: cell index and fraction of f clamped to [0, n - 1] */
static inline v4i cellv(v4f f, int n, v4f *frac) {
    f = sel(f >= splat(0.0f), f, splat(0.0f));
    v4i i = truncv(f), lim = (v4i){n - 2, n - 2, n - 2, n - 2};
    v4i over = i > lim;
    i = (lim & over) | (i & ~over);
    *frac = f - tofv(i);
    return i;
}
/* sl_srbf_ren_log */
static inline v4f logv(v4f x) {
    v4i u = (v4i)x;
    v4i e = ((u >> 23) & 255) - 127;
    v4f m = (v4f)((u & 0x007fffff) | 0x3f800000);
    v4i big = m > splat(1.41421356f);
    m = sel(big, splat(0.5f) * m, m);
    e = e - big; /* big is -1 where true */
    v4f s = (m - 1.0f) / (m + 1.0f), s2 = s * s;
    v4f p = 2.0f * s *
            (1.0f + s2 * (1.0f / 3.0f + s2 * (1.0f / 5.0f + s2 * (1.0f / 7.0f + s2 / 9.0f))));
    return p + tofv(e) * 0.693147180559945f;
}
/* sl_srbf_ren_exp_neg */
static inline v4f exp_negv(v4f x) {
    v4f y = maxv(x, splat(-87.0f)) * 1.44269504088896f;
    v4f fy = tofv(truncv(y));
    fy = sel(fy > y, fy - 1.0f, fy);
    v4f f = (y - fy) * 0.693147180559945f;
    v4f q = 1.0f +
            f * (1.0f +
                 f * (0.5f + f * (1.0f / 6.0f +
                                  f * (1.0f / 24.0f + f * (1.0f / 120.0f + f * (1.0f / 720.0f))))));
    v4f r = q * (v4f)((truncv(fy) + 127) << 23);
    return sel(x < splat(-87.0f), splat(0.0f), r);
}

/* sl_srbf_ren_blend with the TT and TRT blocks in SSE: per corner the same operations, lane by
 * lane, as the scalar sl_srbf_ren_blend3 (bit-identical), which GCC -O2 leaves scalar. */
static inline void blend3v(const float *B, const sl_srbf_ren_pt *q, const int *ih, const float *wh,
                           float *out) {
    v4f a = splat(0.0f);
    for (int c = 0; c < 8; c++) {
        const float *p = B + 4 * (q->o8[c] + ih[c >> 2]);
        v4f q0, q1;
        memcpy(&q0, p, sizeof q0);
        memcpy(&q1, p + 4, sizeof q1);
        a += q->w8[c] * (q0 + wh[c >> 2] * (q1 - q0));
    }
    out[0] = a[0] * q->norm;
    out[1] = a[1] * q->norm;
    out[2] = a[2] * q->norm;
}

static void blendv(const float *T, const sl_srbf_ren_dims *d, const sl_srbf_ren_pt *q,
                   float out[9]) {
    float vr = sl_srbf_ren_blend_r(T, d, q) * q->norm;
    out[0] = out[1] = out[2] = vr;
    blend3v(T + d->off[1], q, q->ih + 2, q->wh + 2, out + 3);
    blend3v(T + d->off[2], q, q->ih + 4, q->wh + 4, out + 6);
}

/* sl_srbf_ren_coords for rows in[0..3] (5 floats each, stride 5) into q[0..3]. */
static void coords4(const float *T, const sl_srbf_ren_dims *d, const float *in, sl_srbf_ren_pt *q) {
    v4f to, po, tj, pj, la;
    for (int k = 0; k < 4; k++) {
        const float *x = in + 5 * k;
        to[k] = x[0], po[k] = x[1], tj[k] = x[2], pj[k] = x[3], la[k] = x[4];
    }
    const float half_pi = 0.5f * SL_PI_F;
    v4f h = clampv(0.5f * (to + tj), -half_pi, half_pi);
    v4f r = maxv(half_pi - vabs(h), splat(1e-30f));
    v4f tt = clampv(0.5f * (tj - to) / r, -1.0f, 1.0f);
    /* sl_srbf_ren_twarp: copysign(1 - sqrt(max(1 - |t|, 0)), t) */
    v4f tw = 1.0f - sqrtv(maxv(1.0f - vabs(tt), splat(0.0f)));
    tw = (v4f)(((v4i)tw & 0x7fffffff) | ((v4i)tt & (int)0x80000000));
    v4f wt, wp, wl;
    v4i it = cellv((tw + 1.0f) * d->t_scale, d->n_t, &wt);
    v4f x = (pj - po) * (0.5f * SL_INV_PI_F) + 0.5f;
    x = sel(x > splat(-7.0f), x, splat(-7.0f));
    x = sel(x < splat(9.0f), x, splat(9.0f));
    x = vabs(x - tofv(truncv(x + 8.0f) - 8) - 0.5f) * (2.0f * SL_PI_F);
    v4i ip = cellv(minv(x * d->p_scale, splat((float)(d->n_p - 1))), d->n_p, &wp);
    v4f lam = clampv(la, 1e-18f, 1e18f);
    v4f fl = clampv((logv(lam) - d->log_lmin) * d->l_scale, 0.0f, (float)(d->n_l - 1));
    v4i il = cellv(fl, d->n_l, &wl);
    v4f l2 = lam * lam;
    v4f norm = SL_PI_F * l2 * (1.0f - exp_negv(-4.0f / l2));
    int st = d->n_h, sp = d->n_h * d->n_t, sl = sp * d->n_p;
    v4i base = il * sl + ip * sp + it * st;
    for (int k = 0; k < 4; k++) {
        q[k].norm = norm[k];
        for (int c = 0; c < 8; c++) {
            int bl = c >> 2, bp = (c >> 1) & 1, bt = c & 1;
            q[k].w8[c] = (bl ? wl[k] : 1.0f - wl[k]) * (bp ? wp[k] : 1.0f - wp[k]) *
                         (bt ? wt[k] : 1.0f - wt[k]);
            q[k].o8[c] = base[k] + bl * sl + bp * sp + bt * st;
        }
    }
    v4f lc = clampv(lam, d->lmin, d->lmax);
    v4f ah = vabs(h);
    for (int m = 0; m < 3; m++) {
        v4f w = sqrtv(d->beta2[m] + 0.25f * lc * lc), dh = h - d->alpha[m], y = dh / w;
        v4f g = clampv((ah + 2.0f * w - half_pi) / w, 0.0f, 1.0f);
        for (int s = 0; s < 2; s++) {
            /* sl_srbf_ren_hcell in slices il and il + 1: the warp constants per row */
            v4f c0, c1, c2;
            for (int k = 0; k < 4; k++) {
                const float *qq = T + 4 * (m * d->n_l + il[k] + s);
                c0[k] = qq[0], c1[k] = qq[1], c2[k] = qq[2];
            }
            v4f yy = y + g * (dh * c0 - y);
            v4f sw = yy / (1.0f + vabs(yy) * (1.0f / SL_SRBF_REN_K));
            v4f fh = minv((sw - c1) * c2, splat((float)(d->n_h - 1)));
            v4f wh;
            v4i ih = cellv(fh, d->n_h, &wh);
            for (int k = 0; k < 4; k++) {
                q[k].ih[2 * m + s] = ih[k];
                q[k].wh[2 * m + s] = wh[k];
            }
        }
    }
}
#endif

void slc_srbf_ren_batch(const sl_srbf_ren *t, size_t n, const float *in, float *out) {
    sl_srbf_ren_dims d = t->dims;
    const float *T = t->T;
    size_t r = 0;
#if SL_REN_SIMD
    /* blocks of 4: coordinates of block b + 1 (and their prefetches) before the blend of b */
    sl_srbf_ren_pt q[2][4];
    size_t nb = n / 4;
    if (nb) {
        coords4(T, &d, in, q[0]);
        for (int k = 0; k < 4; k++)
            prefetch_row(t, &q[0][k]);
    }
    for (size_t b = 0; b < nb; b++) {
        sl_srbf_ren_pt *cur = q[b & 1], *nx = q[(b + 1) & 1];
        if (b + 1 < nb) {
            coords4(T, &d, in + 20 * (b + 1), nx);
            for (int k = 0; k < 4; k++)
                prefetch_row(t, &nx[k]);
        }
        for (int k = 0; k < 4; k++)
            blendv(T, &d, &cur[k], out + 9 * (4 * b + (size_t)k));
    }
    r = 4 * nb;
#endif
    for (; r < n; r++) {
        const float *x = in + 5 * r;
        sl_srbf_ren_lookup(T, &d, x[0], x[1], x[2], x[3], x[4], out + 9 * r);
    }
}
