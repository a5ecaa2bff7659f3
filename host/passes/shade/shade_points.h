/* shade_points.h: the shading points of a frame (fragment rate: one per K-buffer entry; vertex
 * rate k: every k-th strand vertex, interpolated along the strand) and the map from each
 * K-buffer entry back to its shading, which the resolve reads. */
#ifndef SL_SHADE_POINTS_H
#define SL_SHADE_POINTS_H

#include "io/hair/hair.h"
#include "kbuffer.h"

#include <stddef.h>
#include <stdint.h>

/* Most lobes whose shadow a vertex-rate frame looks up per K-buffer entry instead of
 * interpolating it between shading points (quality.sharp_shadows, docs/frame.md "Sharp
 * shadows per entry"). */
#define SL_SHADE_SHARP_MAX 2
/* Floats of one shading point's result: R, TT, TRT, MS (rgb each), shadow, lobe count, then per
 * sharp lobe its R, TT, TRT rgb without its transmittance (sl_shade_stride: only as many as
 * there are sharp lobes); SL_SHADE_FLOATS is the most, the length of a shade vector. */
#define SL_SHADE_BASE_FLOATS 14
#define SL_SHADE_FLOATS (SL_SHADE_BASE_FLOATS + 9 * SL_SHADE_SHARP_MAX)

/* Shading points and what they need. */
typedef struct sl_shade_points {
    size_t n;
    double *pos;      /* 3 n */
    float *tan;       /* 3 n, unit */
    uint32_t *strand; /* n: the strand of each point (for per-strand sigma_a, r->strand_sigma_a) */
    float *T;         /* nlobes x n: transmittance toward each used lobe (1 without a map) */
    /* nlobes x n: the optical depth of the hair behind the point seen from each used lobe
     * (sl_shadow_lookup_both, the lobe's maps weighted as T), or NULL (MS off) */
    float *B;
    float *out; /* sl_shade_stride(p) n */
    /* Vertex rate with sharp lobes (nsharp > 0): used-lobe indices sharp[l] whose single
     * scattering each point stores without its T (out slot SL_SHADE_BASE_FLOATS + 9 l) and its
     * shadow share (sharp_share[l], of the used shares' sum) left out of the shadow AOV; per
     * K-buffer entry their T, entry_T[l nentries + entry_first[px] + i], which sl_shade_entry
     * applies. */
    int nsharp;
    int sharp[SL_SHADE_SHARP_MAX];
    float sharp_share[SL_SHADE_SHARP_MAX];
    size_t nentries;
    uint32_t *entry_first; /* per pixel: its first entry's index (the kcount prefix sum) */
    float *entry_T;        /* nsharp x nentries */
} sl_shade_points;

/* From each K-buffer entry to its shading (point index, or anchor pair + weight). */
typedef struct sl_shade_map {
    uint32_t *strand_of; /* per hair point */
    uint32_t *anchor;    /* per hair point: shading point index, UINT32_MAX if not shaded */
    /* rate 1: per hair point, the shading point where a pair ends there (the same as anchor[i]
     * unless the vertex is bent: then each segment's end has its own point and tangent); NULL
     * at rates k > 1 (anchor serves both) */
    uint32_t *anchor_end;
    uint32_t *entry; /* fragment rate: per K-buffer slot */
    /* vertex rate, refined (sl_shade_points_refine), per hair point that starts an anchor pair:
     * the pair's interval cut into sub_m[lo] >= 1 equal parts in the strand's parameter, whose
     * inner ends are the shading points sub_first[lo] .. sub_first[lo] + sub_m[lo] - 2; NULL when
     * nothing was refined */
    uint32_t *sub_first;
    uint8_t *sub_m;
} sl_shade_map;

/* The K-buffer of a view pass: w x h pixels, K entries each, kcount[px] filled. */
typedef struct sl_kbuf_view {
    int w, h, K;
    const sl_kfrag *kbuf;
    const uint8_t *kcount;
} sl_kbuf_view;

/* The shading points of kb at rate k (0 fragment, >= 1 every k-th vertex) into p (pos, tan,
 * strand, n) and the map m (strand_of, anchor or entry). */
void sl_shade_points_build(const sl_hair *h, const sl_kbuf_view *kb, int k, sl_shade_map *m,
                           sl_shade_points *p);
/* Vertex rate 1: a vertex whose two segments bend by more than this (degrees) is shaded once
 * per segment, with that segment's tangent, instead of once with their mean (docs/frame.md,
 * "Bent vertices"). */
#define SL_SHADE_SPLIT_DEG 10.0f
/* Most parts an anchor pair's interval is cut into by the refinement. */
#define SL_SHADE_REFINE_MAX 8
/* Floor of a transmittance in the refinement's log ratios (a lobe that is dark at both ends
 * carries nothing, and its weight below is its larger T). */
#define SL_SHADE_REFINE_TFLOOR 1e-4f

/* Pairs whose share-weighted larger T (the lobes' light reaching either end, as a share of all
 * of it) is below this are not refined: deep in the hair the chord's error is a few % of a lit
 * fiber's radiance at most. On the goal scene's orbit frame it keeps 20 % of the inner points;
 * the report scenes' figures do not move (docs/frame.md, "Refined vertex rate"). */
#define SL_SHADE_REFINE_GATE 0.05

/* Refinement of vertex-rate shading (rate k >= 1) where the transmittance changes along a
 * strand faster than linear interpolation follows (docs/frame.md, "Refined vertex rate"): for
 * every anchor pair the view pass uses, with T (nlobes x p->n, index j p->n + i) and the lobes'
 * power shares, the share- and T-weighted mean |ln T_j(lo) - ln T_j(hi)| = D (pairs under
 * SL_SHADE_REFINE_GATE excepted); the pair is cut
 * into m = ceil(D / ln ratio) parts (<= SL_SHADE_REFINE_MAX) and its m - 1 inner points are
 * appended to p (pos, tan, strand; p->T and p->B are left to the caller). Fills m->sub_first
 * and m->sub_m. Returns the number of points added. */
size_t sl_shade_points_refine(const sl_hair *h, const sl_kbuf_view *kb, int k, sl_shade_map *m,
                              sl_shade_points *p, const float *T, int nlobes, const double *share,
                              double ratio);
/* The index of every pixel's first K-buffer entry when they are numbered pixel by pixel, entry
 * by entry (the kcount prefix sum; npx + 1 values, the last the count), allocated. */
uint32_t *sl_shade_entry_first(const sl_kbuf_view *kb);
/* The positions (3 doubles each) of the entries of pixels [px0, px1) into pos, in that order. */
void sl_shade_entry_positions(const sl_hair *h, const sl_kbuf_view *kb, size_t px0, size_t px1,
                              double *pos);
/* Floats per point in p->out: SL_SHADE_BASE_FLOATS, and 9 per sharp lobe. */
static inline size_t sl_shade_stride(const sl_shade_points *p) {
    return SL_SHADE_BASE_FLOATS + 9 * (size_t)p->nsharp;
}
/* The sharp slot of used lobe j in p (0 .. nsharp - 1), or -1. */
static inline int sl_shade_sharp_slot(const sl_shade_points *p, int j) {
    for (int l = 0; l < p->nsharp; l++)
        if (p->sharp[l] == j) return l;
    return -1;
}
/* The shade vector of K-buffer entry i of pixel px into v[0 .. SL_SHADE_BASE_FLOATS - 1]: the
 * point's, or the interpolation along the strand; with sharp lobes, their single scattering
 * times the entry's own T added to R, TT, TRT and their share of it to the shadow. v holds
 * SL_SHADE_FLOATS (the rest is scratch: the sharp lobes' interpolated slots). */
void sl_shade_entry(const sl_hair *h, const sl_kbuf_view *kb, int k, const sl_shade_map *m,
                    const sl_shade_points *p, size_t px, int i, float *v);
void sl_shade_points_free(sl_shade_points *p);
void sl_shade_map_free(sl_shade_map *m);

#endif
