/* hair_procedural.c: a deterministic head of hair for scenes without a hair file.
 *
 * Roots lie on a scalp-like cap of a sphere of radius R = SL_PROC_HEAD_RADIUS centred at the
 * origin (+Y up; the face, towards +Z below the hairline, and everything below the ears stay
 * bare). Each strand leaves the scalp at a shallow angle, combed down and back, and bends under
 * "gravity": a small integration of a direction pulled towards -Y, with the head as a collision
 * sphere (strands rest on a shell slightly outside it, a different shell per strand so they layer).
 * Length is SL_PROC_LENGTH +-15 %. Wavy and curly styles add a planar sine or a helix around that
 * base curve, ramped in over the first units so the roots stay on the scalp. Wave phases vary
 * smoothly over the scalp so that neighbouring strands clump as real hair does. All randomness
 * comes from a splitmix64 stream seeded by `seed`: the same parameters give the same hair bit for
 * bit. */
#include "io/hair/hair.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI_F 3.14159265358979f

static const char *style_names[] = {"straight", "wavy", "curly"};

int sl_hair_style_from_name(const char *name) {
    for (int i = 0; i < 3; i++)
        if (strcmp(name, style_names[i]) == 0) return i;
    return -1;
}

const char *sl_hair_style_name(int style) {
    return style >= 0 && style < 3 ? style_names[style] : "unknown";
}

static float len3(const float v[3]) {
    return sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

static void normalize3(float v[3]) {
    float l = len3(v);
    if (l > 0) v[0] /= l, v[1] /= l, v[2] /= l;
}

static void cross3(const float a[3], const float b[3], float o[3]) {
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

/* A unit root direction on the scalp cap: uniform on the sphere, rejected below the ears
 * (y < -0.3) and on the face (front, below the hairline). */
static void scalp_direction(sl_hair_rng *rng, float n[3]) {
    for (int tries = 0; tries < 1000; tries++) {
        float y = 1 - 2 * sl_hair_rng_float(rng), ph = 2 * PI_F * sl_hair_rng_float(rng);
        float r = sqrtf(fmaxf(0, 1 - y * y));
        n[0] = r * sinf(ph), n[1] = y, n[2] = r * cosf(ph);
        if (y < -0.3f) continue;
        if (n[2] > 0.35f && y < 0.55f) continue; /* face and forehead */
        return;
    }
    n[0] = 0, n[1] = 1, n[2] = 0;
}

/* Base curve of one strand at K+1 evenly spaced steps of length ds: grows along n, pulled
 * down, kept outside the shell of radius shell. */
static void drape(const float n[3], float R, float shell, float ds, int K, float *base) {
    const float gravity = 0.35f; /* direction change towards -Y per unit length */
    /* Hair leaves the scalp at a shallow angle, combed down and a little back: the start
     * direction is mostly the "downhill" tangent of -Y - 0.3 Z, plus some of the normal. */
    float comb[3] = {0, -1, -0.3f}, dn = comb[0] * n[0] + comb[1] * n[1] + comb[2] * n[2];
    float p[3] = {R * n[0], R * n[1], R * n[2]}, d[3];
    for (int c = 0; c < 3; c++)
        comb[c] -= dn * n[c];
    normalize3(comb);
    for (int c = 0; c < 3; c++)
        d[c] = 0.4f * n[c] + comb[c];
    normalize3(d);
    memcpy(base, p, sizeof p);
    for (int k = 1; k <= K; k++) {
        d[1] -= gravity * ds;
        normalize3(d);
        float q[3] = {p[0] + ds * d[0], p[1] + ds * d[1], p[2] + ds * d[2]};
        float r = len3(q);
        if (r < shell) { /* slide along the head */
            for (int c = 0; c < 3; c++)
                q[c] *= shell / r;
            float nd[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
            if (len3(nd) > 0) {
                normalize3(nd);
                memcpy(d, nd, sizeof d);
            }
        }
        memcpy(p, q, sizeof p);
        memcpy(base + 3 * k, p, sizeof p);
    }
}

int sl_hair_generate(const sl_hair_procedural *pp, sl_hair *out, sl_err *e) {
    memset(out, 0, sizeof *out);
    if (pp->style < 0 || pp->style > 2)
        return sl_fail(e, "procedural: style %d is not 0 (straight), 1 (wavy) or 2 (curly)",
                       pp->style);
    if (pp->strands < 1 || pp->strands > SL_PROC_MAX_STRANDS)
        return sl_fail(e, "procedural: strands %u is not in [1, %u]", pp->strands,
                       SL_PROC_MAX_STRANDS);
    if (pp->points < 2 || pp->points > SL_PROC_MAX_POINTS)
        return sl_fail(e, "procedural: points %u is not in [2, %u]", pp->points,
                       SL_PROC_MAX_POINTS);
    const uint32_t S = pp->strands, P = pp->points;
    const float R = SL_PROC_HEAD_RADIUS;
    const int K = P - 1 > 64 ? (int)(P - 1) : 64; /* base-curve steps (fine for any P) */
    float *base = sl_malloc((size_t)(K + 1) * 3 * sizeof *base);
    sl_hair_alloc(out, S, S * P);
    sl_hair_rng rng = {0x5eed0000ull ^ ((uint64_t)pp->seed * 0x9e3779b97f4a7c15ull)};
    for (uint32_t s = 0; s < S; s++) {
        out->strand_first[s] = s * P;
        float n[3];
        scalp_direction(&rng, n);
        float L = SL_PROC_LENGTH * (0.85f + 0.3f * sl_hair_rng_float(&rng));
        float shell = R * (1.02f + 0.08f * sl_hair_rng_float(&rng));
        float jitter = sl_hair_rng_float(&rng);
        /* Style parameters; the phase is smooth over the scalp (clumps) plus a little noise. */
        float phase = 2 * PI_F * (0.8f * n[0] + 0.5f * n[2]) + 0.6f * jitter;
        float amp = 0, wavelength = 1;
        if (pp->style == SL_PROC_WAVY) amp = 0.7f, wavelength = 7.0f;
        if (pp->style == SL_PROC_CURLY) amp = 0.6f, wavelength = 3.5f;
        amp *= 0.8f + 0.4f * sl_hair_rng_float(&rng);
        /* The fiber keeps length L: the base curve is shorter by the arc-length factor of the
         * sine (1 + k^2/4 to second order) or the helix (sqrt(1 + k^2)), k = 2 pi amp / wavelength;
         * curly hair springs up shorter, as it should. */
        float k = 2 * PI_F * amp / wavelength;
        float stretch = pp->style == SL_PROC_CURLY ? sqrtf(1 + k * k) : 1 + 0.25f * k * k;
        float ds = L / stretch / (float)K;
        drape(n, R, shell, ds, K, base);
        float *o = out->pos + 3 * (size_t)s * P;
        for (uint32_t k = 0; k < P; k++) {
            float u = (float)k * (float)K / (float)(P - 1); /* position in base steps */
            int i = (int)u;
            if (i >= K) i = K - 1;
            float f = u - (float)i, *a = base + 3 * i, *b = a + 3;
            float p[3], t[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            for (int c = 0; c < 3; c++)
                p[c] = a[c] + f * (b[c] - a[c]);
            if (k == 0) memcpy(p, base, sizeof p); /* the root exactly on the scalp */
            if (amp > 0 && k > 0) {
                float sarc = u * ds, w = sarc / 3.0f; /* ramp in over 3 units */
                float ramp = w >= 1 ? 1 : w * w * (3 - 2 * w);
                float radial[3] = {p[0], p[1], p[2]}, n1[3], n2[3];
                normalize3(t);
                normalize3(radial);
                cross3(t, radial, n1);
                if (len3(n1) < 1e-3f) {
                    float x[3] = {1, 0, 0};
                    cross3(t, x, n1);
                }
                normalize3(n1);
                cross3(t, n1, n2);
                float ang = 2 * PI_F * sarc / wavelength + phase;
                float c1 = amp * ramp * sinf(ang);
                float c2 = pp->style == SL_PROC_CURLY ? amp * ramp * (cosf(ang) - 1) : 0;
                for (int c = 0; c < 3; c++)
                    p[c] += c1 * n1[c] + c2 * n2[c];
                float r = len3(p);
                if (r < R * 1.01f)
                    for (int c = 0; c < 3; c++)
                        p[c] *= R * 1.01f / r;
            }
            memcpy(o + 3 * k, p, sizeof p);
        }
    }
    out->strand_first[S] = S * P;
    free(base);
    snprintf(out->format, sizeof out->format, "procedural (%s)", sl_hair_style_name(pp->style));
    snprintf(out->notes, sizeof out->notes,
             "seed %u, head radius %g, length %g +-15%%, %u points per strand", pp->seed, (double)R,
             (double)SL_PROC_LENGTH, P);
    out->default_radius = SL_PROC_RADIUS;
    out->radius_source = SL_RADIUS_PROCEDURAL;
    out->default_transparency = 0;
    for (int c = 0; c < 3; c++)
        out->default_color[c] = 1;
    if (sl_hair_validate(out, "procedural", e)) {
        sl_hair_free(out);
        return -1;
    }
    return 0;
}
