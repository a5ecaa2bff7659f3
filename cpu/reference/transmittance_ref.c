/* transmittance_ref.c: ray-traced fibers and the Monte Carlo effective transmittance of
 * transmittance_ref.h. Brute force by design (double precision, exact capsule distances); a
 * uniform grid with a 3-D DDA (Amanatides & Woo 1987) only skips segments far from the ray. */
#include "transmittance_ref.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct slref_fibers {
    size_t nseg;
    double *seg; /* 7 per segment: a, b, radius */
    double lo[3], cell[3];
    int dim[3];
    uint32_t *start, *items; /* CSR: cell c holds items[start[c] .. start[c+1]) */
};

static double dot3(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void seg_cells(const slref_fibers *f, const double *s, int c0[3], int c1[3]) {
    for (int k = 0; k < 3; k++) {
        double lo = fmin(s[k], s[3 + k]) - s[6], hi = fmax(s[k], s[3 + k]) + s[6];
        c0[k] = (int)floor((lo - f->lo[k]) / f->cell[k]);
        c1[k] = (int)floor((hi - f->lo[k]) / f->cell[k]);
        if (c0[k] < 0) c0[k] = 0;
        if (c1[k] > f->dim[k] - 1) c1[k] = f->dim[k] - 1;
    }
}

int slref_fibers_build(const sl_hair *h, slref_fibers **out, sl_err *e) {
    slref_fibers *f = sl_calloc(1, sizeof *f);
    f->nseg = h->num_points - h->num_strands;
    f->seg = sl_malloc((f->nseg ? f->nseg : 1) * 7 * sizeof *f->seg);
    double hi[3] = {-INFINITY, -INFINITY, -INFINITY}, rmax = 0;
    for (int k = 0; k < 3; k++)
        f->lo[k] = INFINITY;
    size_t n = 0;
    for (uint32_t s = 0; s < h->num_strands; s++)
        for (uint32_t i = h->strand_first[s]; i + 1 < h->strand_first[s + 1]; i++, n++) {
            double *g = f->seg + 7 * n;
            for (int k = 0; k < 6; k++)
                g[k] = h->pos[3 * i + k];
            g[6] = h->radius ? 0.5 * ((double)h->radius[i] + h->radius[i + 1]) : h->default_radius;
            rmax = fmax(rmax, g[6]);
            for (int k = 0; k < 3; k++) {
                f->lo[k] = fmin(f->lo[k], fmin(g[k], g[3 + k]));
                hi[k] = fmax(hi[k], fmax(g[k], g[3 + k]));
            }
        }
    if (n == 0) {
        for (int k = 0; k < 3; k++)
            f->lo[k] = hi[k] = 0;
    }
    double ext[3], vol = 1;
    for (int k = 0; k < 3; k++) {
        f->lo[k] -= rmax + 1e-9;
        hi[k] += rmax + 1e-9;
        ext[k] = fmax(hi[k] - f->lo[k], 1e-9);
        vol *= ext[k];
    }
    double side = cbrt(vol / fmax(1.0, 2.0 * (double)n));
    for (int k = 0; k < 3; k++) {
        double d = ceil(ext[k] / side);
        f->dim[k] = d < 1 ? 1 : d > 256 ? 256 : (int)d;
        f->cell[k] = ext[k] / f->dim[k];
    }
    size_t ncell = (size_t)f->dim[0] * f->dim[1] * f->dim[2];
    f->start = sl_calloc(ncell + 1, sizeof *f->start);
    size_t total = 0;
    for (int pass = 0; pass < 2; pass++) {
        if (pass == 1) {
            for (size_t c = 0; c < ncell; c++)
                f->start[c + 1] += f->start[c];
            total = f->start[ncell];
            if (total > 0xffffffffu) {
                slref_fibers_free(f);
                return sl_fail(e, "transmittance reference: grid too large");
            }
            f->items = sl_malloc((total ? total : 1) * sizeof *f->items);
        }
        uint32_t *fill = pass ? sl_calloc(ncell, sizeof *fill) : NULL;
        for (size_t s = 0; s < n; s++) {
            int c0[3], c1[3];
            seg_cells(f, f->seg + 7 * s, c0, c1);
            for (int z = c0[2]; z <= c1[2]; z++)
                for (int y = c0[1]; y <= c1[1]; y++)
                    for (int x = c0[0]; x <= c1[0]; x++) {
                        size_t c = ((size_t)z * f->dim[1] + y) * f->dim[0] + x;
                        if (pass == 0)
                            f->start[c + 1]++;
                        else
                            f->items[f->start[c] + fill[c]++] = (uint32_t)s;
                    }
        }
        free(fill);
    }
    *out = f;
    return 0;
}

void slref_fibers_free(slref_fibers *f) {
    if (!f) return;
    free(f->seg);
    free(f->start);
    free(f->items);
    free(f);
}

/* Squared distance between the point p and segment [a, b]. */
static double point_seg2(const double p[3], const double *a, const double *b) {
    double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    double l2 = dot3(ab, ab), t = l2 > 0 ? fmin(1, fmax(0, dot3(ap, ab) / l2)) : 0, d2 = 0;
    for (int k = 0; k < 3; k++) {
        double q = ap[k] - t * ab[k];
        d2 += q * q;
    }
    return d2;
}

/* Squared distance between the ray o + t dir (0 <= t <= tmax) and segment [a, b]: the closest
 * points of two segments (Ericson, Real-Time Collision Detection, 5.1.9). */
static double ray_seg2(const double o[3], const double dir[3], double tmax, const double *a,
                       const double *b) {
    double d2[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double r[3] = {o[0] - a[0], o[1] - a[1], o[2] - a[2]};
    double A = tmax * tmax, E = dot3(d2, d2), F = dot3(d2, r);
    double C = tmax * dot3(dir, r), B = tmax * dot3(dir, d2);
    double s, t; /* s along the ray (in units of tmax), t along the segment */
    if (E <= 0) {
        t = 0;
        s = fmin(1, fmax(0, -C / A));
    } else {
        double den = A * E - B * B;
        s = den > 0 ? fmin(1, fmax(0, (B * F - C * E) / den)) : 0;
        t = (B * s + F) / E;
        if (t < 0) {
            t = 0;
            s = fmin(1, fmax(0, -C / A));
        } else if (t > 1) {
            t = 1;
            s = fmin(1, fmax(0, (B - C) / A));
        }
    }
    double q = 0;
    for (int k = 0; k < 3; k++) {
        double v = (o[k] + s * tmax * dir[k]) - (a[k] + t * d2[k]);
        q += v * v;
    }
    return q;
}

static int cell_hit(const slref_fibers *f, size_t c, const double o[3], const double dir[3],
                    double tmax) {
    for (uint32_t i = f->start[c]; i < f->start[c + 1]; i++) {
        const double *g = f->seg + 7 * f->items[i];
        double r2 = g[6] * g[6];
        if (point_seg2(o, g, g + 3) < r2) continue; /* x inside this fiber: ignored */
        if (ray_seg2(o, dir, tmax, g, g + 3) <= r2) return 1;
    }
    return 0;
}

int slref_fibers_occluded(const slref_fibers *f, const double o[3], const double dir[3]) {
    if (f->nseg == 0) return 0;
    /* clip the ray to the grid box */
    double t0 = 0, t1 = INFINITY, hi[3];
    for (int k = 0; k < 3; k++) {
        hi[k] = f->lo[k] + f->cell[k] * f->dim[k];
        if (dir[k] == 0) {
            if (o[k] < f->lo[k] || o[k] > hi[k]) return 0;
            continue;
        }
        double a = (f->lo[k] - o[k]) / dir[k], b = (hi[k] - o[k]) / dir[k];
        if (a > b) {
            double t = a;
            a = b;
            b = t;
        }
        t0 = fmax(t0, a);
        t1 = fmin(t1, b);
    }
    if (t0 > t1) return 0;
    double tmax = t1 + 1e-9; /* the ray cannot meet a fiber beyond the grid */
    int c[3], step[3];
    double tnext[3], tdelta[3];
    for (int k = 0; k < 3; k++) {
        double p = o[k] + t0 * dir[k];
        c[k] = (int)floor((p - f->lo[k]) / f->cell[k]);
        if (c[k] < 0) c[k] = 0;
        if (c[k] > f->dim[k] - 1) c[k] = f->dim[k] - 1;
        if (dir[k] > 0) {
            step[k] = 1;
            tnext[k] = (f->lo[k] + (c[k] + 1) * f->cell[k] - o[k]) / dir[k];
            tdelta[k] = f->cell[k] / dir[k];
        } else if (dir[k] < 0) {
            step[k] = -1;
            tnext[k] = (f->lo[k] + c[k] * f->cell[k] - o[k]) / dir[k];
            tdelta[k] = -f->cell[k] / dir[k];
        } else {
            step[k] = 0;
            tnext[k] = tdelta[k] = INFINITY;
        }
    }
    for (;;) {
        size_t cell = ((size_t)c[2] * f->dim[1] + c[1]) * f->dim[0] + c[0];
        if (cell_hit(f, cell, o, dir, tmax)) return 1;
        int k = tnext[0] < tnext[1] ? (tnext[0] < tnext[2] ? 0 : 2) : (tnext[1] < tnext[2] ? 1 : 2);
        if (tnext[k] > t1) return 0;
        c[k] += step[k];
        if (c[k] < 0 || c[k] >= f->dim[k]) return 0;
        tnext[k] += tdelta[k];
    }
}

static uint64_t rng_next(uint64_t *s) {
    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}
static double rng_u(uint64_t *s) {
    return (double)(rng_next(s) >> 11) * 0x1.0p-53;
}

double slref_transmittance(const slref_fibers *f, const double x[3], const double dir[3],
                           double lambda, int n, uint64_t seed, double *std_err) {
    /* frame around the lobe centre */
    double z[3], l = sqrt(dot3(dir, dir));
    for (int k = 0; k < 3; k++)
        z[k] = dir[k] / l;
    double a[3] = {fabs(z[0]) < 0.9 ? 1 : 0, fabs(z[0]) < 0.9 ? 0 : 1, 0}, u[3], v[3];
    double p = dot3(a, z);
    for (int k = 0; k < 3; k++)
        u[k] = a[k] - p * z[k];
    l = sqrt(dot3(u, u));
    for (int k = 0; k < 3; k++)
        u[k] /= l;
    v[0] = z[1] * u[2] - z[2] * u[1];
    v[1] = z[2] * u[0] - z[0] * u[2];
    v[2] = z[0] * u[1] - z[1] * u[0];
    double kap = 2.0 / (lambda * lambda); /* G = exp(kap (cos - 1)) */
    uint64_t s = seed * 0x2545f4914f6cdd1dull + 1;
    int vis = 0;
    for (int i = 0; i < n; i++) {
        /* exact inversion of the vMF cosine: pdf ~ exp(kap (c - 1)) on [-1, 1] */
        double xi = rng_u(&s), ph = 2 * M_PI * rng_u(&s);
        double c = 1 + log1p(xi * expm1(-2 * kap)) / kap;
        if (c < -1) c = -1;
        double sn = sqrt(fmax(0, 1 - c * c)), w[3];
        for (int k = 0; k < 3; k++)
            w[k] = c * z[k] + sn * (cos(ph) * u[k] + sin(ph) * v[k]);
        vis += !slref_fibers_occluded(f, x, w);
    }
    double T = (double)vis / n;
    if (std_err) *std_err = sqrt(T * (1 - T) / n);
    return T;
}
