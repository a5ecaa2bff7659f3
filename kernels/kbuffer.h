/* kbuffer.h: the per-pixel K-buffer of the view pass (order-independent transparency), shared
 * by the C twin (cpu/view.c) and any OpenCL port: insertion of one fragment into a pixel's K
 * depth-sorted entries, overflow MERGED (never dropped), and front-to-back compositing.
 *
 * An entry is a fragment of one hair segment: view depth z, opacity a (coverage x (1 -
 * transparency)), the segment (index of its first point) and the parameter t along it, so the
 * entry can be shaded after visibility is known (deferred shading: only kept entries are shaded).
 *
 * Overflow: when a fragment arrives at a full pixel, the K + 1 candidates (sorted by depth) keep
 * their K - 1 nearest entries and the two farthest are merged into one: the merged opacity is
 * exactly "over" of the two, a = a_n + (1 - a_n) a_f, so the pixel's total coverage is conserved
 * whatever K is; the merged entry keeps the depth, segment and t of its nearer member (it is
 * shaded there: the only approximation, confined to the K-th layer and beyond).
 *
 * Occlusion (exact): an entry with a >= 1 (a fully covered pixel of an opaque strand) gets weight
 * a prod (1 - a_k) and leaves every entry behind it a weight of exactly 0 in sl_kbuffer_weights,
 * so fragments behind it are dropped and a new fully opaque fragment removes the entries behind
 * it: the pixel's beauty, alpha and depth are unchanged, there are just fewer entries to merge
 * and shade (for opaque hair most of the layers behind the first full coverage). */
#ifndef SL_KBUFFER_H
#define SL_KBUFFER_H

#include "sl_compat.h"

#define SL_KBUFFER_MAX 64

typedef struct sl_kfrag {
    float z, a;
    sl_uint seg;
    float t;
} sl_kfrag;

/* Strict depth order with a deterministic tie-break (segment, then t), so the result does not
 * depend on anything but the set and the insertion order of the fragments. */
SL_INLINE int sl_kfrag_before(const sl_kfrag *p, const sl_kfrag *q) {
    if (p->z != q->z) return p->z < q->z;
    if (p->seg != q->seg) return p->seg < q->seg;
    return p->t < q->t;
}

/* "over" of a nearer opacity an and a farther af. */
SL_INLINE float sl_kbuffer_over(float an, float af) {
    return an + (1.0f - an) * af;
}

/* Inserts f into the n (<= K) entries of buf (sorted nearest first); returns the new count.
 * Returns n + 1 while n < K; at n == K the two farthest of the K + 1 are merged. */
SL_INLINE int sl_kbuffer_insert(sl_kfrag *buf, int n, int K, sl_kfrag f) {
    /* occluded: behind a fully opaque entry (only the last can be one, see below) */
    if (n > 0 && buf[n - 1].a >= 1.0f && !sl_kfrag_before(&f, &buf[n - 1])) return n;
    int i = n;
    if (n < K) {
        while (i > 0 && sl_kfrag_before(&f, &buf[i - 1])) {
            buf[i] = buf[i - 1];
            i--;
        }
        buf[i] = f;
        return f.a >= 1.0f ? i + 1 : n + 1; /* fully opaque: what lies behind is hidden */
    }
    /* full: the farthest candidate is either f or buf[K-1] */
    if (!sl_kfrag_before(&f, &buf[K - 1])) {
        buf[K - 1].a = sl_kbuffer_over(buf[K - 1].a, f.a);
        return n;
    }
    sl_kfrag last = buf[K - 1]; /* leaves the K nearest; merges into the new K-th */
    i = K - 1;
    while (i > 0 && sl_kfrag_before(&f, &buf[i - 1])) {
        buf[i] = buf[i - 1];
        i--;
    }
    buf[i] = f;
    if (f.a >= 1.0f) return i + 1;
    buf[K - 1].a = sl_kbuffer_over(buf[K - 1].a, last.a);
    return n;
}

/* Front-to-back weights of n sorted entries: w[i] = a_i prod_{k<i} (1 - a_k) (each entry's share
 * of the pixel); returns the pixel's alpha 1 - prod (1 - a_k), computed as sum w (the same
 * number, without the cancellation of 1 - prod for faint pixels). */
SL_INLINE float sl_kbuffer_weights(const sl_kfrag *buf, int n, float *w) {
    float trans = 1.0f, sum = 0.0f;
    for (int i = 0; i < n; i++) {
        w[i] = trans * buf[i].a;
        sum += w[i];
        trans *= 1.0f - buf[i].a;
    }
    return sum;
}

#endif
