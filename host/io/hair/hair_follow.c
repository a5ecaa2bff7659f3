/* hair_follow.c: TressFX "follow" strands, the run-time densification of AMD's TressFX viewer
 * (TressFXAssetLoader::GenerateFollowHairs, TressFX 3.1): each guide strand gets per_guide
 * copies shifted by a random offset in the plane normal to the guide's root segment, the
 * offset growing linearly from the root to the tip so the follow strands fan out.
 *
 * Differences from AMD, on purpose: the offset is uniform in the disc of radius root_radius
 * (AMD draws each of two in-plane coordinates in [-r, r], a square whose corners reach r*sqrt 2),
 * and the scale at point k of n is 1 + tip_spread * k / (n - 1), so the tip gets exactly
 * 1 + tip_spread (AMD divides by n). Randomness is our splitmix64 stream, not rand(). */
#include "io/hair/hair.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Two unit vectors spanning the plane normal to unit t. */
static void normal_plane(const float t[3], float t0[3], float t1[3]) {
    /* cross with the axis least aligned with t (never parallel) */
    float ax[3] = {0, 0, 0};
    int m = 0;
    for (int c = 1; c < 3; c++)
        if (fabsf(t[c]) < fabsf(t[m])) m = c;
    ax[m] = 1;
    t0[0] = t[1] * ax[2] - t[2] * ax[1];
    t0[1] = t[2] * ax[0] - t[0] * ax[2];
    t0[2] = t[0] * ax[1] - t[1] * ax[0];
    float l = sqrtf(t0[0] * t0[0] + t0[1] * t0[1] + t0[2] * t0[2]);
    for (int c = 0; c < 3; c++)
        t0[c] /= l;
    t1[0] = t[1] * t0[2] - t[2] * t0[1];
    t1[1] = t[2] * t0[0] - t[0] * t0[2];
    t1[2] = t[0] * t0[1] - t[1] * t0[0];
}

int sl_hair_add_follow(sl_hair *h, const sl_hair_follow *f, sl_err *e) {
    if (f->per_guide < 0 || f->per_guide > SL_FOLLOW_MAX_PER_GUIDE)
        return sl_fail(e, "tfx_follow: per_guide %d is not in [0, %d]", f->per_guide,
                       SL_FOLLOW_MAX_PER_GUIDE);
    if (!(f->root_radius >= 0 && isfinite(f->root_radius)))
        return sl_fail(e, "tfx_follow: root_radius %g is not a finite number >= 0",
                       (double)f->root_radius);
    if (!(f->tip_spread >= 0 && isfinite(f->tip_spread)))
        return sl_fail(e, "tfx_follow: tip_spread %g is not a finite number >= 0",
                       (double)f->tip_spread);
    if (f->per_guide == 0) return 0;
    const uint64_t F1 = (uint64_t)f->per_guide + 1;
    if ((uint64_t)h->num_points * F1 > SL_HAIR_MAX_POINTS)
        return sl_fail(
            e, "tfx_follow: %d follow strands per guide would make %llu points (limit %u)",
            f->per_guide, (unsigned long long)((uint64_t)h->num_points * F1), SL_HAIR_MAX_POINTS);
    const uint32_t S = h->num_strands, S2 = (uint32_t)(S * F1), P2 = (uint32_t)(h->num_points * F1);
    uint32_t *first = sl_malloc(((size_t)S2 + 1) * sizeof *first);
    float *pos = sl_malloc((size_t)P2 * 3 * sizeof *pos);
    float *rad = h->radius ? sl_malloc((size_t)P2 * sizeof *rad) : NULL;
    float *tr = h->transparency ? sl_malloc((size_t)P2 * sizeof *tr) : NULL;
    float *col = h->color ? sl_malloc((size_t)P2 * 3 * sizeof *col) : NULL;
    sl_hair_rng rng = {0xf0110000ull ^ ((uint64_t)f->seed * 0x9e3779b97f4a7c15ull)};
    uint32_t so = 0, po = 0;
    for (uint32_t s = 0; s < S; s++) {
        uint32_t a = h->strand_first[s], n = h->strand_first[s + 1] - a;
        float t[3], t0[3], t1[3];
        sl_hair_tangent(h, s, 0, t); /* root segment, finite even when degenerate */
        normal_plane(t, t0, t1);
        for (uint64_t j = 0; j < F1; j++) {
            float off[3] = {0, 0, 0};
            if (j > 0) { /* uniform in the disc: r = R sqrt(u) */
                float r = f->root_radius * sqrtf(sl_hair_rng_float(&rng));
                float ph = 6.28318530718f * sl_hair_rng_float(&rng);
                float c = r * cosf(ph), sn = r * sinf(ph);
                for (int k = 0; k < 3; k++)
                    off[k] = c * t0[k] + sn * t1[k];
            }
            first[so++] = po;
            for (uint32_t k = 0; k < n; k++) {
                float scale = 1.0f + f->tip_spread * (float)k / (float)(n - 1);
                for (int c = 0; c < 3; c++)
                    pos[3 * (size_t)(po + k) + c] =
                        h->pos[3 * (size_t)(a + k) + c] + off[c] * scale;
            }
            if (rad) memcpy(rad + po, h->radius + a, n * sizeof *rad);
            if (tr) memcpy(tr + po, h->transparency + a, n * sizeof *tr);
            if (col)
                memcpy(col + 3 * (size_t)po, h->color + 3 * (size_t)a, 3 * (size_t)n * sizeof *col);
            po += n;
        }
    }
    first[S2] = po;
    for (size_t i = 0; i < 3 * (size_t)P2; i++)
        if (!isfinite(pos[i])) {
            free(first), free(pos), free(rad), free(tr), free(col);
            return sl_fail(e,
                           "tfx_follow: root_radius %g x (1 + tip_spread %g) overflows the "
                           "coordinates",
                           (double)f->root_radius, (double)f->tip_spread);
        }
    free(h->strand_first);
    free(h->pos);
    free(h->radius);
    free(h->transparency);
    free(h->color);
    h->strand_first = first, h->pos = pos, h->radius = rad, h->transparency = tr, h->color = col;
    if (!h->follow_added) h->guide_strands = S;
    h->num_strands = S2, h->num_points = P2;
    h->follow_added = 1;
    return 0;
}
