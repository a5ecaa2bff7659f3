/* march.h: shadow-path marching for dual scattering (Ren 2010 Sec. 6, Zinke 2008), shared by the
 * OpenCL kernel (kernels/march.cl) and the C twin (cpu/march_c.c). Definitions: docs/volume.md.
 *
 * From a coarse-grid vertex x, `paths` shadow paths run toward the lobe centre w (unit, toward
 * the light) through the voxel grid (kernels/voxel.h) in steps of h/2 (start jittered per path)
 * to the grid exit, or until every channel's T is below SL_MARCH_T_MIN.
 * In a step of length delta a scattering event happens with probability
 *     P = 1 - exp(-sigma_perp alpha(w) delta)                                    (Ren Sec. 6)
 * (alpha: sl_vox_alpha). At an event a fiber direction t is drawn around the voxel's direction
 * (Gaussian perturbation of rms sine ~ dev), the incident inclination is theta = asin(|w.t|) and
 * per colour channel the path's transmittance and variance update as
 *     T *= a_f(theta),   s2 += beta_f(theta)^2      (Zinke 2008; a_f, beta_f: dual tables)
 * A vertex stores, per channel, the mean over its paths and the energy-weighted spread:
 *     T_f = mean_p T_p,   sigma_f = sqrt(sum_p T_p s2_p / sum_p T_p)
 * (sigma_f in the material's width convention, exp(-x^2 / sigma_f^2); it excludes the lobe's own
 * width lambda, which the response adds: Xu Eq. 5), and the energy-weighted tilt of the fibers the
 * light crossed against the fiber at the vertex,
 *     tilt2 = sum_p T_p g2_p / sum_p T_p,   g2_p = sum_events |t_k - d_x|^2 + dev_x^2
 * (t_k the event's unit fiber, signed toward d_x; d_x, dev_x the mean direction and spread of the
 * vertex's voxel, or of the first event's voxel when the vertex's is empty): an event on a fiber
 * at angle delta to the shading fiber turns the light's inclination to it by delta times the
 * sine of half the azimuthal deflection, so the response widens sigma_f^2 by the material's
 * 2 E[1 + cos phi] per unit tilt2 (docs/volume.md "Where the scattered light goes"). Random
 * numbers are a counter-based hash of (seed, vertex, lobe, path, step), so both backends draw the
 * same numbers. */
#ifndef SL_MARCH_H
#define SL_MARCH_H

#include "dual_material.h"
#include "voxel.h"

#define SL_MARCH_CH 3 /* colour channels carried per path */
/* A path stops once every channel's T is below this (its light no longer matters: 1e-5 of the
 * lobe's, below a float image's visible range after exposure). */
#define SL_MARCH_T_MIN 1e-5f

/* lowbias32 (C. Wellons' integer hash). */
SL_INLINE sl_uint sl_march_hash(sl_uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

/* The random number of the counter (seed, a, b, c, d) is uniform in [0, 1) (24 bits):
 *     sl_march_rand_at(sl_march_rand_key(seed, a, b, c), d)
 * a chain of five hashes, of which the key holds the first four: they depend on (seed, a, b, c)
 * only, so a path (a vertex, b lobe, c path) computes them once, not at every step and event. */
SL_INLINE sl_uint sl_march_rand_key(sl_uint seed, sl_uint a, sl_uint b, sl_uint c) {
    sl_uint x = sl_march_hash(seed ^ 0x9e3779b9u);
    x = sl_march_hash(x ^ a);
    x = sl_march_hash(x ^ (b * 0x85ebca6bu));
    return sl_march_hash(x ^ (c * 0xc2b2ae35u));
}

/* The last link: the number of counter d under key (sl_march_rand_key). */
SL_INLINE float sl_march_rand_at(sl_uint key, sl_uint d) {
    return (float)(sl_march_hash(key ^ d) >> 8) * (1.0f / 16777216.0f);
}

/* Distance from x along unit w to the exit of the box [lo, lo + n h] (0 if outside). */
SL_INLINE float sl_march_exit(const float *x, const float *w, int nx, int ny, int nz,
                              const float *lo, float h) {
    float t = SL_FLT_MAX;
    float hi[3] = {lo[0] + (float)nx * h, lo[1] + (float)ny * h, lo[2] + (float)nz * h};
    for (int a = 0; a < 3; a++) {
        if (w[a] > 0.0f) t = sl_minf(t, (hi[a] - x[a]) / w[a]);
        if (w[a] < 0.0f) t = sl_minf(t, (lo[a] - x[a]) / w[a]);
    }
    return t < SL_FLT_MAX ? sl_maxf(t, 0.0f) : 0.0f;
}

/* Row `row` of one channel's dual table at the interval i and fraction t sl_dual_locate found:
 * sl_dual_lookup's interpolation, term for term (so the same float). */
SL_INLINE float sl_march_dual_at(SL_GLOBAL const float *tab, int row, int i, float t) {
    SL_GLOBAL const float *f = tab + row * SL_DUAL_N;
    return f[i] + t * (f[i + 1] - f[i]);
}

/* Probability of an event in one step of length delta through voxel vx (density > 0) toward w. */
SL_INLINE float sl_march_event_p(SL_GLOBAL const float *vx, const float *w, float delta) {
    return 1.0f - exp(-vx[SL_VOX_SIGMA] * sl_vox_alpha(vx, w[0], w[1], w[2]) * delta);
}

/* The reference fiber of a vertex's tilt (the top of the file): ref[0..2] the mean direction of
 * the voxel holding x and ref[3] its spread dev, or ref[3] = -1 when that voxel is empty (each
 * path then takes its first event's voxel). */
SL_INLINE void sl_march_tilt_ref(SL_GLOBAL const float *vox, int nx, int ny, int nz,
                                 const float *lo, float h, const float *x, float *ref) {
    int v = sl_vox_index(x[0], x[1], x[2], nx, ny, nz, lo[0], lo[1], lo[2], 1.0f / h);
    ref[0] = ref[1] = ref[2] = 0.0f;
    ref[3] = -1.0f;
    if (v < 0) return;
    SL_GLOBAL const float *vx = vox + (size_t)v * SL_VOX_FIELDS;
    if (!(vx[SL_VOX_SIGMA] > 0.0f)) return;
    ref[0] = vx[SL_VOX_DIRX], ref[1] = vx[SL_VOX_DIRY], ref[2] = vx[SL_VOX_DIRZ];
    ref[3] = vx[SL_VOX_DEV];
}

/* |t - d|^2 + dev^2 for unit d and t of length tn, t's sign turned toward d (fibers have no
 * direction). */
SL_INLINE float sl_march_tilt2(const float *t, float tn, const float *d, float dev) {
    float inv = tn > 0.0f ? 1.0f / tn : 0.0f;
    float dp = t[0] * d[0] + t[1] * d[1] + t[2] * d[2];
    float sg = dp < 0.0f ? -inv : inv, g = dev * dev;
    for (int q = 0; q < 3; q++) {
        float z = t[q] * sg - d[q];
        g += z * z;
    }
    return g;
}

/* One shadow path from x toward w; T and s2 (SL_MARCH_CH each) start at 1 and 0, *tilt (g2_p at
 * the top of the file: the sum of the events' sl_march_tilt2) at 0. ref: the vertex's reference
 * fiber (sl_march_tilt_ref). tabs: SL_MARCH_CH dual tables (SL_DUAL_TABLE_FLOATS each). ptab: 0, or
 * this lobe's sl_march_event_p of every voxel (0 where sigma is 0) precomputed with delta = 0.5 h
 * (the C twin: one exp per voxel instead of one per step; the same floats, so the same events).
 * Returns the number of events. */
SL_INLINE int sl_march_path(SL_GLOBAL const float *vox, int nx, int ny, int nz, const float *lo,
                            float h, SL_GLOBAL const float *tabs, const float *x, const float *w,
                            sl_uint seed, sl_uint vert, sl_uint lobe, sl_uint path,
                            SL_GLOBAL const float *ptab, const float *ref, float *T, float *s2,
                            float *tilt) {
    const float delta = 0.5f * h, inv_h = 1.0f / h;
    const float tex = sl_march_exit(x, w, nx, ny, nz, lo, h);
    const sl_uint key = sl_march_rand_key(seed, vert, lobe, path);
    const float j = sl_march_rand_at(key, 0xffffffffu);
    int events = 0;
    float d0[3] = {ref[0], ref[1], ref[2]}, dev0 = ref[3];
    *tilt = 0.0f;
    for (int c = 0; c < SL_MARCH_CH; c++) {
        T[c] = 1.0f;
        s2[c] = 0.0f;
    }
    for (sl_uint k = 0;; k++) {
        float s = ((float)k + j) * delta;
        if (!(s < tex)) break;
        int v = sl_vox_index(x[0] + s * w[0], x[1] + s * w[1], x[2] + s * w[2], nx, ny, nz, lo[0],
                             lo[1], lo[2], inv_h);
        if (v < 0) continue;
        SL_GLOBAL const float *vx = vox + (size_t)v * SL_VOX_FIELDS;
        float P;
        if (ptab) {
            /* P = 0 (empty voxel, or no chance) can never beat a uniform in [0, 1): no event,
             * as when the density test below skips the voxel */
            P = ptab[v];
            if (!(P > 0.0f)) continue;
        } else {
            if (!(vx[SL_VOX_SIGMA] > 0.0f)) continue;
            P = sl_march_event_p(vx, w, delta);
        }
        if (!(sl_march_rand_at(key, 4u * k) < P)) continue;
        /* The event's fiber: dir + g (n1 e1 + n2 e2), g = dev / sqrt(2), n Gaussian. */
        float d[3] = {vx[SL_VOX_DIRX], vx[SL_VOX_DIRY], vx[SL_VOX_DIRZ]};
        float t[3] = {d[0], d[1], d[2]};
        float dev = vx[SL_VOX_DEV];
        if (dev > 0.0f) {
            float a[3] = {0.0f, 0.0f, 0.0f};
            a[fabs(d[0]) < 0.6f ? 0 : (fabs(d[1]) < 0.6f ? 1 : 2)] = 1.0f;
            float e1[3] = {d[1] * a[2] - d[2] * a[1], d[2] * a[0] - d[0] * a[2],
                           d[0] * a[1] - d[1] * a[0]};
            float n1 = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
            for (int q = 0; q < 3; q++)
                e1[q] /= n1;
            float e2[3] = {d[1] * e1[2] - d[2] * e1[1], d[2] * e1[0] - d[0] * e1[2],
                           d[0] * e1[1] - d[1] * e1[0]};
            float u1 = sl_maxf(sl_march_rand_at(key, 4u * k + 1u), 1e-7f);
            float u2 = sl_march_rand_at(key, 4u * k + 2u);
            float r = sqrt(-2.0f * log(u1)) * dev * 0.70710678f;
            float g1 = r * cos(2.0f * SL_PI_F * u2), g2 = r * sin(2.0f * SL_PI_F * u2);
            for (int q = 0; q < 3; q++)
                t[q] = d[q] + g1 * e1[q] + g2 * e2[q];
        }
        float tn = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
        if (dev0 < 0.0f) { /* no fiber at the vertex: the first event's voxel stands for it */
            d0[0] = d[0], d0[1] = d[1], d0[2] = d[2];
            dev0 = dev;
        }
        *tilt += sl_march_tilt2(t, tn, d0, dev0);
        float cw = tn > 0.0f ? fabs(w[0] * t[0] + w[1] * t[1] + w[2] * t[2]) / tn : 0.0f;
        float theta = asin(sl_minf(cw, 1.0f));
        /* Every row of every channel's table has the same nodes: the interval and fraction of
         * theta once for the event (sl_dual_lookup would find them again for each of the six
         * lookups), then the same interpolation as sl_dual_lookup's. */
        float ft;
        const int it = sl_dual_locate(theta, &ft);
        for (int c = 0; c < SL_MARCH_CH; c++) {
            SL_GLOBAL const float *tab = tabs + (size_t)c * SL_DUAL_TABLE_FLOATS;
            float b = sl_march_dual_at(tab, SL_DUAL_BETA_F, it, ft);
            T[c] *= sl_march_dual_at(tab, SL_DUAL_AF, it, ft);
            s2[c] += b * b;
        }
        events++;
        /* Nothing left to carry: further events only lower T (and add spread weighted by it). */
        float tmax = T[0];
        for (int c = 1; c < SL_MARCH_CH; c++)
            tmax = sl_maxf(tmax, T[c]);
        if (tmax < SL_MARCH_T_MIN) break;
    }
    return events;
}

/* All paths of one (vertex, lobe): T_f, sigma_f and tilt2 per channel (the top of the file). */
SL_INLINE void sl_march_vertex(SL_GLOBAL const float *vox, int nx, int ny, int nz, const float *lo,
                               float h, SL_GLOBAL const float *tabs, const float *x, const float *w,
                               sl_uint seed, sl_uint vert, sl_uint lobe, int paths,
                               SL_GLOBAL const float *ptab, float *Tf, float *sf, float *tilt2) {
    float sT[SL_MARCH_CH], sTs[SL_MARCH_CH], ss[SL_MARCH_CH], sTg[SL_MARCH_CH], sg = 0.0f;
    float ref[4];
    sl_march_tilt_ref(vox, nx, ny, nz, lo, h, x, ref);
    for (int c = 0; c < SL_MARCH_CH; c++)
        sT[c] = sTs[c] = ss[c] = sTg[c] = 0.0f;
    for (int p = 0; p < paths; p++) {
        float T[SL_MARCH_CH], s2[SL_MARCH_CH], g2;
        sl_march_path(vox, nx, ny, nz, lo, h, tabs, x, w, seed, vert, lobe, (sl_uint)p, ptab, ref,
                      T, s2, &g2);
        for (int c = 0; c < SL_MARCH_CH; c++) {
            sT[c] += T[c];
            sTs[c] += T[c] * s2[c];
            ss[c] += s2[c];
            sTg[c] += T[c] * g2;
        }
        sg += g2;
    }
    for (int c = 0; c < SL_MARCH_CH; c++) {
        Tf[c] = sT[c] / (float)paths;
        sf[c] = sqrt(sT[c] > 0.0f ? sTs[c] / sT[c] : ss[c] / (float)paths);
        tilt2[c] = sT[c] > 0.0f ? sTg[c] / sT[c] : sg / (float)paths;
    }
}

/* ln(max(v, 1e-30)): a texel of the log-space T_f texture (sl_ftex_sample, logspace 1 and 2). */
SL_INLINE float sl_ftex_log_texel(float v) {
    return log(sl_maxf(v, 1e-30f));
}

/* Where a trilinear lookup in a per-vertex texture reads (SL_MARCH_CH floats per vertex;
 * vertices m[0] x m[1] x m[2] at lo + k H, x fastest; p clamped onto the grid): the n corners
 * with a non-zero weight, in corner order, as texel offsets and weights. They depend on p only,
 * so every texture of the same grid (one per lobe) reuses them. */
typedef struct sl_ftex_corners {
    int n;
    int off[8]; /* vertex index x SL_MARCH_CH */
    float w[8];
} sl_ftex_corners;

SL_INLINE void sl_ftex_corners_init(int mx, int my, int mz, const float *lo, float H,
                                    const float *p, sl_ftex_corners *cn) {
    int m[3] = {mx, my, mz}, i0[3];
    float f[3];
    for (int a = 0; a < 3; a++) {
        float u = sl_clampf((p[a] - lo[a]) / H, 0.0f, (float)(m[a] - 1));
        int i = (int)u;
        if (i > m[a] - 2) i = m[a] - 2;
        if (i < 0) i = 0;
        i0[a] = i;
        f[a] = m[a] > 1 ? u - (float)i : 0.0f;
    }
    cn->n = 0;
    for (int corner = 0; corner < 8; corner++) {
        int ix = i0[0] + (corner & 1), iy = i0[1] + ((corner >> 1) & 1),
            iz = i0[2] + ((corner >> 2) & 1);
        float wt = ((corner & 1) ? f[0] : 1.0f - f[0]) *
                   (((corner >> 1) & 1) ? f[1] : 1.0f - f[1]) *
                   (((corner >> 2) & 1) ? f[2] : 1.0f - f[2]);
        if (wt == 0.0f || ix >= mx || iy >= my || iz >= mz) continue;
        cn->off[cn->n] = ((iz * my + iy) * mx + ix) * SL_MARCH_CH;
        cn->w[cn->n++] = wt;
    }
}

/* The trilinear lookup at cn (sl_ftex_corners_init). logspace: interpolate ln(max(v, 1e-30))
 * and return exp of it (for T_f, which falls exponentially with depth: linear weights between
 * vertices 4 voxels apart overestimate it, 0.32 instead of 0.23 against the reference's 0.21 on
 * procedural hair, docs/volume.md). logspace = 2: tex already holds ln(max(v, 1e-30))
 * (sl_ftex_log_texel, computed once per march by the C host): the same sums without the logs. */
SL_INLINE void sl_ftex_sample_at(SL_GLOBAL const float *tex, const sl_ftex_corners *cn,
                                 int logspace, float *out) {
    for (int c = 0; c < SL_MARCH_CH; c++)
        out[c] = 0.0f;
    for (int k = 0; k < cn->n; k++) {
        SL_GLOBAL const float *t = tex + cn->off[k];
        for (int c = 0; c < SL_MARCH_CH; c++)
            out[c] += cn->w[k] * (logspace == 1 ? sl_ftex_log_texel(t[c]) : t[c]);
    }
    if (logspace)
        for (int c = 0; c < SL_MARCH_CH; c++)
            out[c] = exp(out[c]);
}

/* Trilinear lookup at p (sl_ftex_corners_init, then sl_ftex_sample_at). */
SL_INLINE void sl_ftex_sample(SL_GLOBAL const float *tex, int mx, int my, int mz, const float *lo,
                              float H, const float *p, int logspace, float *out) {
    sl_ftex_corners cn;
    sl_ftex_corners_init(mx, my, mz, lo, H, p, &cn);
    sl_ftex_sample_at(tex, &cn, logspace, out);
}

#endif
