/* march_ref.c: see march_ref.h. Ray-capsule distances by the closest points of a ray and a segment
 * in double (Ericson, Real-Time Collision Detection 5.1.9, with the ray parameter bounded below
 * only). */
#include "march_ref.h"

#include "dual_ref.h"

#include <math.h>
#include <string.h>

/* Squared distance between the ray x + s w (s >= 0) and segment p0 + u d (u in [0, 1]); *s_at
 * gets the ray parameter of the closest point. */
static double ray_seg_dist2(const double x[3], const double w[3], const double p0[3],
                            const double d[3], double *s_at) {
    double r[3] = {x[0] - p0[0], x[1] - p0[1], x[2] - p0[2]};
    double e = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    double b = w[0] * d[0] + w[1] * d[1] + w[2] * d[2];
    double c = w[0] * r[0] + w[1] * r[1] + w[2] * r[2];
    double f = d[0] * r[0] + d[1] * r[1] + d[2] * r[2];
    double den = e - b * b, u = 0;
    if (den > 1e-14 * e) u = (f - b * c) / den;
    u = u < 0 ? 0 : (u > 1 ? 1 : u);
    double s = u * b - c;
    if (s < 0) {
        s = 0;
        u = e > 0 ? f / e : 0;
        u = u < 0 ? 0 : (u > 1 ? 1 : u);
    }
    double q = 0;
    for (int a = 0; a < 3; a++) {
        double v = r[a] + s * w[a] - u * d[a];
        q += v * v;
    }
    *s_at = s;
    return q;
}

/* Squared distance from x to the segment. */
static double point_seg_dist2(const double x[3], const double p0[3], const double d[3]) {
    double e = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], f = 0, q = 0;
    for (int a = 0; a < 3; a++)
        f += d[a] * (x[a] - p0[a]);
    double u = e > 0 ? f / e : 0;
    u = u < 0 ? 0 : (u > 1 ? 1 : u);
    for (int a = 0; a < 3; a++) {
        double v = x[a] - p0[a] - u * d[a];
        q += v * v;
    }
    return q;
}

size_t slref_march_events(const sl_hair *h, const double x[3], const double w[3], double *theta,
                          size_t max) {
    size_t n = 0;
    for (uint32_t st = 0; st < h->num_strands; st++) {
        int in_run = 0, run_has_x = 0;
        double best = INFINITY, best_t = 0;
        for (uint32_t p = h->strand_first[st]; p + 1 < h->strand_first[st + 1] + 1; p++) {
            int hit = 0, contains = 0;
            double dist2 = INFINITY, tcos = 0;
            if (p + 1 < h->strand_first[st + 1]) {
                double p0[3], d[3], r0, r1;
                for (int a = 0; a < 3; a++) {
                    p0[a] = h->pos[3 * (size_t)p + a];
                    d[a] = h->pos[3 * (size_t)(p + 1) + a] - p0[a];
                }
                r0 = h->radius ? h->radius[p] : h->default_radius;
                r1 = h->radius ? h->radius[p + 1] : h->default_radius;
                double r = r0 > r1 ? r0 : r1, s;
                double L = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                if (L > 0) {
                    dist2 = ray_seg_dist2(x, w, p0, d, &s);
                    hit = dist2 < r * r;
                    contains = point_seg_dist2(x, p0, d) < r * r;
                    tcos = fabs(w[0] * d[0] + w[1] * d[1] + w[2] * d[2]) / L;
                }
            }
            if (hit) {
                in_run = 1;
                run_has_x |= contains;
                if (dist2 < best) {
                    best = dist2;
                    best_t = tcos;
                }
            } else if (in_run) { /* a run ended: one event, unless the strand holds x there */
                if (!run_has_x) {
                    if (n < max) theta[n] = asin(best_t > 1 ? 1 : best_t);
                    n++;
                }
                in_run = run_has_x = 0;
                best = INFINITY;
            }
        }
    }
    return n;
}

void slref_forward_from_events(const sl_material *m, int ch, const double *theta, size_t n,
                               slref_dual_cache *cache, double *Tf, double *sigma_f) {
    slref_dual_cache local = {0, 0, 0, {0}};
    if (!cache) cache = &local;
    double T = 1, s2 = 0;
    for (size_t k = 0; k < n; k++) {
        if (!cache->valid || cache->ch != ch || cache->theta != theta[k]) {
            slref_dual_terms(m, ch, theta[k], cache->terms);
            cache->valid = 1;
            cache->ch = ch;
            cache->theta = theta[k];
        }
        T *= cache->terms[SLREF_DUAL_AF];
        s2 += cache->terms[SLREF_DUAL_BETA_F] * cache->terms[SLREF_DUAL_BETA_F];
    }
    *Tf = T;
    *sigma_f = sqrt(s2);
}
