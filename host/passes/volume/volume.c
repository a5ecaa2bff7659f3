/* volume.c: the volume passes of multiple scattering (volume.h): grid layout, segment records,
 * voxelization and the shadow-path march on OpenCL or the C twins (with the `auto` fallback),
 * the coarse vertex set and the texture lookup. */
#include "passes/volume/volume.h"
#include "base/parallel.h"

#include "march.h"
#include "march_c.h"
#include "passes/volume/march_cl.h"
#include "voxel.h"
#include "voxel_c.h"
#include "passes/volume/voxel_cl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

void sl_voxel_grid_layout(const sl_hair *hair, int voxels, sl_voxel_grid *g) {
    memset(g, 0, sizeof *g);
    if (voxels < 1) voxels = 64;
    if (!hair || hair->num_points == 0) {
        g->n[0] = g->n[1] = g->n[2] = 1;
        g->h = 1.0f;
        return;
    }
    float lo[3], hi[3];
    sl_hair_bounds(hair, lo, hi);
    double rmax = hair->default_radius;
    if (hair->radius)
        for (size_t i = 0; i < hair->num_points; i++)
            if (hair->radius[i] > rmax) rmax = hair->radius[i];
    double ext = 0;
    for (int a = 0; a < 3; a++)
        if (hi[a] - lo[a] > ext) ext = hi[a] - lo[a];
    double grow = rmax + 1e-3 * ext + 1e-6;
    double emax = ext + 2 * grow, h = emax / voxels;
    for (int a = 0; a < 3; a++) {
        g->lo[a] = (float)(lo[a] - grow);
        int n = (int)ceil((hi[a] - lo[a] + 2 * grow) / h - 1e-9);
        g->n[a] = n < 1 ? 1 : (n > voxels ? voxels : n);
    }
    g->h = (float)h;
}

float *sl_voxel_segments(const sl_hair *hair, size_t *nseg) {
    size_t n = 0;
    for (uint32_t s = 0; s < hair->num_strands; s++)
        n += hair->strand_first[s + 1] - hair->strand_first[s] - 1;
    float *r = sl_malloc((n ? n : 1) * SL_VOX_SEG * sizeof *r);
    size_t k = 0;
    for (uint32_t s = 0; s < hair->num_strands; s++)
        for (uint32_t p = hair->strand_first[s]; p + 1 < hair->strand_first[s + 1]; p++, k++) {
            float *o = r + k * SL_VOX_SEG;
            for (int q = 0; q < 2; q++) {
                memcpy(o + 4 * q, hair->pos + 3 * (size_t)(p + q), 3 * sizeof *o);
                o[4 * q + 3] = hair->radius ? hair->radius[p + q] : hair->default_radius;
            }
        }
    *nseg = n;
    return r;
}

float sl_voxel_scale(const float *segs, size_t nseg) {
    double total = 0;
    for (size_t i = 0; i < nseg; i++) {
        const float *s = segs + i * SL_VOX_SEG;
        double d[3] = {s[4] - s[0], s[5] - s[1], s[6] - s[2]};
        double L = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        double r = s[3] > s[7] ? s[3] : s[7];
        total += L * (2 * r > 1 ? 2 * r : 1) * 1.001 + 1e-30;
    }
    if (!(total > 0)) return 1.0f;
    int ex = (int)floor(log2(ldexp(1.0, 61) / total));
    if (ex > 100) ex = 100;
    if (ex < -100) ex = -100;
    return (float)ldexp(1.0, ex);
}

int sl_voxelize_segments(sl_device *dev, const float *segs, size_t nseg, sl_voxel_grid *g,
                         sl_err *e) {
    size_t nvox = (size_t)g->n[0] * g->n[1] * g->n[2];
    g->vox = NULL;
    if (nvox > SL_VOXEL_MAX)
        return sl_fail(e,
                       "voxel grid %dx%dx%d is too large (%zu voxels, at most %d: 88 bytes each; "
                       "lower quality.voxels)",
                       g->n[0], g->n[1], g->n[2], nvox, SL_VOXEL_MAX);
    float scale = sl_voxel_scale(segs, nseg);
    g->segments = nseg;
    g->vox = sl_malloc(nvox * SL_VOX_FIELDS * sizeof *g->vox);
    if (dev && dev->is_opencl) {
        int rc =
            slcl_voxelize(dev->cl, segs, nseg, g->n, g->lo, g->h, scale, g->vox, &g->seconds, e);
        if (rc == 0) return 0;
        if (!sl_device_try_fallback(dev, rc, e)) {
            free(g->vox);
            g->vox = NULL;
            return -1;
        }
    }
    double t0 = sl_now();
    uint64_t *acc = sl_calloc(nvox * SL_VOX_ACC, sizeof *acc);
    slc_voxel_accumulate(segs, nseg, g->n, g->lo, g->h, scale, acc);
    slc_voxel_finalize(acc, nvox, g->h, 1.0f / scale, g->vox);
    free(acc);
    g->seconds = sl_now() - t0;
    return 0;
}

int sl_voxelize(sl_device *dev, const sl_hair *hair, int voxels, sl_voxel_grid *g, sl_err *e) {
    sl_voxel_grid_layout(hair, voxels, g);
    size_t nseg;
    float *segs = sl_voxel_segments(hair, &nseg);
    int rc = sl_voxelize_segments(dev, segs, nseg, g, e);
    free(segs);
    return rc;
}

void sl_voxel_grid_free(sl_voxel_grid *g) {
    free(g->vox);
    g->vox = NULL;
}

void sl_march_opts_default(sl_march_opts *o) {
    o->coarse = 4;
    o->paths = 16;
    o->seed = 1;
    o->threads = 0;
}

/* Coarse vertices with hair within one coarse cell (any voxel of density > 0 in one of the 8
 * cells around the vertex). */
static size_t active_vertices(const sl_voxel_grid *g, int c, const int m[3], uint32_t **ids) {
    int nc[3] = {m[0] - 1, m[1] - 1, m[2] - 1};
    size_t ncell = (size_t)nc[0] * nc[1] * nc[2], nvert = (size_t)m[0] * m[1] * m[2];
    unsigned char *occ = sl_calloc(ncell ? ncell : 1, 1);
    for (int k = 0; k < g->n[2]; k++)
        for (int j = 0; j < g->n[1]; j++)
            for (int i = 0; i < g->n[0]; i++) {
                size_t v = ((size_t)k * g->n[1] + j) * g->n[0] + i;
                if (g->vox[v * SL_VOX_FIELDS + SL_VOX_DENSITY] > 0)
                    occ[((size_t)(k / c) * nc[1] + j / c) * nc[0] + i / c] = 1;
            }
    *ids = sl_malloc((nvert ? nvert : 1) * sizeof **ids);
    size_t n = 0;
    for (int k = 0; k < m[2]; k++)
        for (int j = 0; j < m[1]; j++)
            for (int i = 0; i < m[0]; i++) {
                int hit = 0;
                for (int q = 0; q < 8 && !hit; q++) {
                    int a = i - 1 + (q & 1), b = j - 1 + ((q >> 1) & 1), d = k - 1 + (q >> 2);
                    if (a < 0 || b < 0 || d < 0 || a >= nc[0] || b >= nc[1] || d >= nc[2]) continue;
                    hit = occ[((size_t)d * nc[1] + b) * nc[0] + a];
                }
                if (hit) (*ids)[n++] = (uint32_t)(((size_t)k * m[1] + j) * m[0] + i);
            }
    free(occ);
    return n;
}

/* The fibers' spread around their mean direction near each coarse vertex (m vertices every c
 * voxels): the length-weighted mean of dev^2 over the c x c x c voxels centred on the vertex, 0
 * where they hold no hair; SL_MARCH_CH equal floats per vertex (so sl_ftex_sample_at reads it). */
static void vertex_dev2(const sl_voxel_grid *g, int c, const int m[3], float *out) {
    int lo = -(c / 2), hi = lo + c;
    for (int k = 0; k < m[2]; k++)
        for (int j = 0; j < m[1]; j++)
            for (int i = 0; i < m[0]; i++) {
                double sw = 0.0, sd = 0.0;
                for (int dz = lo; dz < hi; dz++)
                    for (int dy = lo; dy < hi; dy++)
                        for (int dx = lo; dx < hi; dx++) {
                            int x = i * c + dx, y = j * c + dy, z = k * c + dz;
                            if (x < 0 || y < 0 || z < 0 || x >= g->n[0] || y >= g->n[1] ||
                                z >= g->n[2])
                                continue;
                            const float *v =
                                g->vox + (((size_t)z * g->n[1] + y) * g->n[0] + x) * SL_VOX_FIELDS;
                            double w = v[SL_VOX_DENSITY];
                            sw += w;
                            sd += w * (double)v[SL_VOX_DEV] * v[SL_VOX_DEV];
                        }
                float d2 = sw > 0.0 ? (float)(sd / sw) : 0.0f;
                float *o = out + (((size_t)k * m[1] + j) * m[0] + i) * SL_MARCH_CH;
                for (int q = 0; q < SL_MARCH_CH; q++)
                    o[q] = d2;
            }
}

/* The world position of vertex id (x fastest): lo + k H, in double. */
static void vertex_pos(const sl_ftex *f, size_t id, double p[3]) {
    size_t idx[3] = {id % (size_t)f->m[0], id / (size_t)f->m[0] % (size_t)f->m[1],
                     id / ((size_t)f->m[0] * f->m[1])};
    for (int a = 0; a < 3; a++)
        p[a] = (double)f->lo[a] + (double)idx[a] * f->H;
}

int sl_march_build(sl_device *dev, const sl_voxel_grid *g, const sl_dual_tables *dt, int nlobes,
                   const double *dirs, const sl_march_opts *o, sl_ftex *f, sl_err *e) {
    memset(f, 0, sizeof *f);
    int c = o->coarse >= 1 ? o->coarse : 4, paths = o->paths >= 1 ? o->paths : 1;
    for (int a = 0; a < 3; a++) {
        f->m[a] = (g->n[a] + c - 1) / c + 1;
        f->lo[a] = g->lo[a];
    }
    f->H = (float)c * g->h;
    f->nlobes = nlobes;
    size_t nvert = (size_t)f->m[0] * f->m[1] * f->m[2];
    f->T = sl_malloc((nlobes ? nlobes : 1) * nvert * SL_MARCH_CH * sizeof *f->T);
    f->sigma = sl_calloc((nlobes ? nlobes : 1) * nvert * SL_MARCH_CH, sizeof *f->sigma);
    f->tilt2 = sl_calloc((nlobes ? nlobes : 1) * nvert * SL_MARCH_CH, sizeof *f->tilt2);
    f->dev2 = sl_calloc(nvert * SL_MARCH_CH, sizeof *f->dev2);
    vertex_dev2(g, c, f->m, f->dev2);
    for (size_t i = 0; i < (size_t)nlobes * nvert * SL_MARCH_CH; i++)
        f->T[i] = 1.0f;
    uint32_t *ids;
    size_t na = active_vertices(g, c, f->m, &ids);
    f->active = na;
    float *verts = sl_malloc((na ? na : 1) * 3 * sizeof *verts);
    for (size_t v = 0; v < na; v++) {
        double p[3];
        vertex_pos(f, ids[v], p);
        for (int a = 0; a < 3; a++)
            verts[3 * v + a] = (float)p[a];
    }
    float *fd = sl_malloc((nlobes ? nlobes : 1) * 3 * sizeof *fd);
    for (int l = 0; l < nlobes; l++) {
        double len = sqrt(dirs[3 * l] * dirs[3 * l] + dirs[3 * l + 1] * dirs[3 * l + 1] +
                          dirs[3 * l + 2] * dirs[3 * l + 2]);
        for (int a = 0; a < 3; a++)
            fd[3 * l + a] = (float)(len > 0 ? dirs[3 * l + a] / len : (a == 1));
    }
    size_t nout = na * (size_t)nlobes;
    float *oT = sl_malloc((nout ? nout : 1) * SL_MARCH_CH * sizeof *oT);
    float *oS = sl_malloc((nout ? nout : 1) * SL_MARCH_CH * sizeof *oS);
    float *oG = sl_malloc((nout ? nout : 1) * SL_MARCH_CH * sizeof *oG);
    const float *tabs = &dt->tab[0][0];
    int rc = -1, done = 0;
    if (dev && dev->is_opencl) {
        rc = slcl_march(dev->cl, g->vox, g->n, g->lo, g->h, tabs, verts, ids, na, fd,
                        (size_t)nlobes, paths, o->seed, oT, oS, oG, &f->seconds, e);
        if (rc == 0)
            done = 1;
        else if (!sl_device_try_fallback(dev, rc, e))
            goto out;
    }
    if (!done) {
        double t0 = sl_now();
        int nt = o->threads;
        if (nt <= 0) {
            nt = sl_parallel_cpus();
            if ((size_t)nt > nout / 64 + 1) nt = (int)(nout / 64 + 1); /* small jobs: fewer */
        }
        slc_march_threads(g->vox, g->n, g->lo, g->h, tabs, verts, ids, na, fd, (size_t)nlobes,
                          paths, o->seed, oT, oS, oG, nt);
        f->seconds = sl_now() - t0;
    }
    for (int l = 0; l < nlobes; l++)
        for (size_t v = 0; v < na; v++) {
            size_t src = ((size_t)l * na + v) * SL_MARCH_CH;
            size_t dst = ((size_t)l * nvert + ids[v]) * SL_MARCH_CH;
            memcpy(f->T + dst, oT + src, SL_MARCH_CH * sizeof *oT);
            memcpy(f->sigma + dst, oS + src, SL_MARCH_CH * sizeof *oS);
            memcpy(f->tilt2 + dst, oG + src, SL_MARCH_CH * sizeof *oG);
        }
    /* the logs sl_ftex_lookup would take of the 8 corners of every lookup, once per texel */
    f->logT = sl_malloc((nlobes ? nlobes : 1) * nvert * SL_MARCH_CH * sizeof *f->logT);
    for (size_t i = 0; i < (size_t)nlobes * nvert * SL_MARCH_CH; i++)
        f->logT[i] = sl_ftex_log_texel(f->T[i]);
    rc = 0;
out:
    free(ids);
    free(verts);
    free(fd);
    free(oT);
    free(oS);
    free(oG);
    if (rc) sl_ftex_free(f);
    return rc;
}

void sl_ftex_at(const sl_ftex *f, const double p[3], sl_ftex_corners *cn) {
    float pf[3] = {(float)p[0], (float)p[1], (float)p[2]};
    sl_ftex_corners_init(f->m[0], f->m[1], f->m[2], f->lo, f->H, pf, cn);
}

void sl_ftex_lookup_at(const sl_ftex *f, int lobe, const sl_ftex_corners *cn, float T[3],
                       float sigma[3]) {
    size_t nvert = (size_t)f->m[0] * f->m[1] * f->m[2];
    if (f->logT)
        sl_ftex_sample_at(f->logT + (size_t)lobe * nvert * SL_MARCH_CH, cn, 2, T);
    else
        sl_ftex_sample_at(f->T + (size_t)lobe * nvert * SL_MARCH_CH, cn, 1, T);
    sl_ftex_sample_at(f->sigma + (size_t)lobe * nvert * SL_MARCH_CH, cn, 0, sigma);
}

void sl_ftex_tilt_at(const sl_ftex *f, int lobe, const sl_ftex_corners *cn, float tilt2[3]) {
    size_t nvert = (size_t)f->m[0] * f->m[1] * f->m[2];
    sl_ftex_sample_at(f->tilt2 + (size_t)lobe * nvert * SL_MARCH_CH, cn, 0, tilt2);
}

void sl_ftex_dev2_at(const sl_ftex *f, const sl_ftex_corners *cn, float dev2[3]) {
    sl_ftex_sample_at(f->dev2, cn, 0, dev2);
}

void sl_ftex_lookup(const sl_ftex *f, int lobe, const double p[3], float T[3], float sigma[3]) {
    sl_ftex_corners cn;
    sl_ftex_at(f, p, &cn);
    sl_ftex_lookup_at(f, lobe, &cn, T, sigma);
}

void sl_ftex_lookup_guided(const sl_ftex *f, int lobe, const sl_ftex_corners *cn, float tau_p,
                           float T[3], float sigma[3]) {
    if (!f->tau || !f->logT) {
        sl_ftex_lookup_at(f, lobe, cn, T, sigma);
        return;
    }
    size_t nvert = (size_t)f->m[0] * f->m[1] * f->m[2];
    const float *tv = f->tau + (size_t)lobe * nvert;
    const float *lt = f->logT + (size_t)lobe * nvert * SL_MARCH_CH;
    sl_ftex_sample_at(f->sigma + (size_t)lobe * nvert * SL_MARCH_CH, cn, 0, sigma);
    /* num: sl_ftex_lookup_at's log-space sum (the same terms in the same order), den: the
     * corners' depth */
    float den = 0.0f, num[3] = {0.0f, 0.0f, 0.0f};
    for (int k = 0; k < cn->n; k++) {
        den += cn->w[k] * tv[cn->off[k] / SL_MARCH_CH];
        for (int c = 0; c < SL_MARCH_CH; c++)
            num[c] += cn->w[k] * lt[cn->off[k] + c];
    }
    int guided = den >= SL_FTEX_TAU_MIN;
    for (int c = 0; c < SL_MARCH_CH; c++)
        T[c] = (float)exp(guided ? (double)(sl_clampf(num[c] / den, -1.0f, 0.0f) * tau_p)
                                 : (double)num[c]);
}

void sl_ftex_set_tau(sl_ftex *f, const float *Tj) {
    size_t n = (size_t)f->nlobes * f->m[0] * f->m[1] * f->m[2];
    free(f->tau);
    f->tau = sl_malloc((n + 1) * sizeof *f->tau);
    for (size_t i = 0; i < n; i++)
        f->tau[i] = sl_ftex_tau_of(Tj[i]);
}

double *sl_ftex_vertex_positions(const sl_ftex *f) {
    size_t n = (size_t)f->m[0] * f->m[1] * f->m[2];
    double *p = sl_malloc((3 * n + 1) * sizeof *p);
    for (size_t i = 0; i < n; i++)
        vertex_pos(f, i, p + 3 * i);
    return p;
}

void sl_ftex_free(sl_ftex *f) {
    free(f->tau);
    free(f->T);
    free(f->sigma);
    free(f->logT);
    free(f->tilt2);
    free(f->dev2);
    f->T = f->sigma = f->logT = f->tilt2 = f->dev2 = f->tau = NULL;
}
