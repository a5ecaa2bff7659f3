/* view.c: the C twin of the view pass (see view.h). */
#include "view.h"

#include "raster.h"
#include "../kernels/raster.h"
#include "../kernels/splat.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/common.h"
#include "base/parallel.h"

/* A pixel the previous segment of the current strand touched: its running sums (coverage mass
 * M, opacity-weighted mass, depth-weighted mass) and the fragment they became (idx, or NO_FRAG
 * while the coverage is below the drop threshold), and the shading point of the member with the
 * largest share. */
struct slc_run_px {
    uint32_t pix, seg;
    float t;
    size_t idx;
    double m, ma, mz, best;
};
#define NO_FRAG ((size_t)-1)
#define DROP_ALPHA 1e-4f /* view.h: below this a fragment changes no 16-bit half output */

void slc_frag_list_free(slc_frag_list *l) {
    free(l->f);
    free(l->pix);
    free(l->run);
    free(l->run_next);
    memset(l, 0, sizeof *l);
}

static void run_push(slc_frag_list *l, struct slc_run_px e) {
    if (l->run_n == l->run_next_cap) { /* run_n counts run_next while a segment is being built */
        l->run_next_cap = l->run_next_cap ? 2 * l->run_next_cap : 64;
        l->run_next = sl_realloc(l->run_next, l->run_next_cap * sizeof *l->run_next);
    }
    l->run_next[l->run_n++] = e;
}

static void push(slc_frag_list *l, uint32_t pix, sl_kfrag f) {
    if (l->n == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 4096;
        l->f = sl_realloc(l->f, l->cap * sizeof *l->f);
        l->pix = sl_realloc(l->pix, l->cap * sizeof *l->pix);
    }
    l->f[l->n] = f;
    l->pix[l->n++] = pix;
}

typedef struct share {
    uint32_t pix;
    float m, mt, mz;
} share;

/* Stable sort by pixel (equal pixels keep their generation order, so the per-pixel double sums
 * below add in one fixed order on every platform). A stable sort's result is unique, so any
 * stable algorithm gives the same bits. Insertion sort on runs of RUN shares (a segment's
 * shares come along it, nearly sorted within a run), then bottom-up merges through tmp
 * (k entries): O(k log k) whatever the segment's direction. The insertion sort alone was
 * O(k^2) for segments drawn toward lower pixel indices (their shares arrive in descending
 * order), and k grows with the segment's length in pixels: the view pass's cost per fragment
 * grew with resolution (issue 20, slope 1.41). */
#define RUN 16
static void insertion_sort(share *s, size_t k) {
    for (size_t i = 1; i < k; i++) {
        share x = s[i];
        size_t j = i;
        for (; j > 0 && s[j - 1].pix > x.pix; j--)
            s[j] = s[j - 1];
        s[j] = x;
    }
}

/* Sorts s (k entries) stably by pixel; tmp: k entries of scratch. */
static void share_sort(share *s, size_t k, share *tmp) {
    for (size_t a = 0; a < k; a += RUN)
        insertion_sort(s + a, k - a < RUN ? k - a : RUN);
    if (k <= RUN) return;
    share *src = s, *dst = tmp;
    for (size_t wd = RUN; wd < k; wd *= 2) {
        for (size_t a = 0; a < k; a += 2 * wd) {
            size_t m = a + wd < k ? a + wd : k, b = a + 2 * wd < k ? a + 2 * wd : k;
            size_t i = a, j = m, o = a;
            if (m == b || src[m - 1].pix <= src[m].pix) { /* already in order: copy */
                memcpy(dst + a, src + a, (b - a) * sizeof *src);
                continue;
            }
            while (i < m && j < b) /* ties from the left run first: stable */
                dst[o++] = src[j].pix < src[i].pix ? src[j++] : src[i++];
            while (i < m)
                dst[o++] = src[i++];
            while (j < b)
                dst[o++] = src[j++];
        }
        share *t = src;
        src = dst, dst = t;
    }
    if (src != s) memcpy(s, src, k * sizeof *s);
}

void slc_view_segment(const double p0[3], const double p1[3], double hw, float a0, float a1,
                      uint32_t seg, int w, int h, slc_frag_list *out) {
    /* the next segment of the strand the previous call drew (view.h): same point, next index */
    const int cont = out->has_last && seg == out->last_seg + 1u && p0[0] == out->last_p1[0] &&
                     p0[1] == out->last_p1[1] && p0[2] == out->last_p1[2];
    out->has_last = 1;
    out->last_seg = seg;
    memcpy(out->last_p1, p1, sizeof out->last_p1);
    if (!cont) out->run_n = 0;
    float rec[SL_RASTER_REC];
    slc_raster_record(p0, p1, hw, 1.0, rec); /* mass in pixel^2 */
    const sl_uint na = (sl_uint)rec[9], nw = (sl_uint)rec[10];
    if (na == 0 || nw == 0) return; /* no area (end-on): the strand's run goes on past it */
    /* quick reject: the ribbon's bounding box misses the image (it touches no pixel) */
    double r = hw + 2.0;
    if (fmax(p0[0], p1[0]) + r < 0 || fmin(p0[0], p1[0]) - r > w || fmax(p0[1], p1[1]) + r < 0 ||
        fmin(p0[1], p1[1]) - r > h) {
        out->run_n = 0;
        return;
    }
    size_t ns = (size_t)na * nw * 4, k = 0;
    share stack[2 * 512];
    share *s = ns <= 512 ? stack : sl_malloc(2 * ns * sizeof *s);
    share *scratch = s + (ns <= 512 ? 512 : ns);
    sl_splat it;
    sl_splat_begin_box(&it, rec, w, h, 1);
    sl_int tx, ty;
    float sh, z, ts = 0.0f;
    sl_uint ti = ~0u; /* the row ts is of: none yet (na <= SL_RASTER_MAX_ALONG) */
    while (sl_splat_next(&it, &tx, &ty, &sh, &z)) {
        if (!(sh > 0.0f)) continue;
        /* the sample's parameter along the segment (the centre of its slice), once per row */
        if (it.i != ti) ti = it.i, ts = ((float)it.i + 0.5f) / (float)na;
        s[k++] = (share){(uint32_t)ty * (uint32_t)w + (uint32_t)tx, sh, sh * ts, sh * z};
    }
    share_sort(s, k, scratch);
    /* the previous segment's pixels (sorted by pixel, as the shares are): a merge join */
    struct slc_run_px *prev = out->run;
    const size_t nprev = out->run_n;
    size_t jp = 0;
    out->run_n = 0; /* now counts run_next: this segment's pixels */
    for (size_t a = 0; a < k;) {
        size_t b = a;
        double M = 0, Mt = 0, Mz = 0;
        for (; b < k && s[b].pix == s[a].pix; b++)
            M += s[b].m, Mt += s[b].mt, Mz += s[b].mz;
        const uint32_t pix = s[a].pix;
        a = b;
        double cov = M < 1.0 ? M : 1.0, t = Mt / M;
        double a_op = a0 + t * (a1 - a0);
        while (jp < nprev && prev[jp].pix < pix)
            jp++;
        if (jp < nprev && prev[jp].pix == pix) {
            /* one ribbon: the shares add (coverage min(1, M1 + M2)), no "over" */
            struct slc_run_px e = prev[jp];
            e.m += M, e.ma += M * a_op, e.mz += Mz;
            if (M > e.best) e.best = M, e.seg = seg, e.t = (float)t;
            const float alpha = (float)((e.m < 1.0 ? e.m : 1.0) * (e.ma / e.m));
            const sl_kfrag f = {(float)(e.mz / e.m), alpha, e.seg, e.t};
            if (e.idx != NO_FRAG) {
                out->f[e.idx] = f;
            } else if (alpha >= DROP_ALPHA) {
                e.idx = out->n;
                push(out, pix, f);
            }
            run_push(out, e);
            continue;
        }
        float alpha = (float)(cov * a_op);
        size_t idx = NO_FRAG;
        if (alpha >= DROP_ALPHA) {
            idx = out->n;
            push(out, pix, (sl_kfrag){(float)(Mz / M), alpha, seg, (float)t});
        }
        run_push(out, (struct slc_run_px){pix, seg, (float)t, idx, M, M * a_op, Mz, M});
    }
    /* this segment's pixels become the run the next segment continues */
    struct slc_run_px *tmp = out->run;
    size_t tcap = out->run_cap;
    out->run = out->run_next, out->run_cap = out->run_next_cap;
    out->run_next = tmp, out->run_next_cap = tcap;
    if (s != stack) free(s);
}

typedef struct kb_job {
    const slc_frag_list *parts;
    int nparts, w, K;
    sl_kfrag *kbuf;
    uint8_t *count;
    size_t *merges; /* one count per part */
} kb_job;

/* Rows begin .. end - 1: every fragment of those rows' pixels, in list order (the lists one after
 * another). */
static void kb_part(void *arg, size_t begin, size_t end, int part) {
    const kb_job *j = arg;
    const uint32_t pix_lo = (uint32_t)begin * (uint32_t)j->w;
    const uint32_t pix_hi = (uint32_t)end * (uint32_t)j->w;
    size_t arrived = 0, kept = 0;
    for (int q = 0; q < j->nparts; q++) {
        const slc_frag_list *l = &j->parts[q];
        for (size_t i = 0; i < l->n; i++) {
            uint32_t p = l->pix[i];
            if (p < pix_lo || p >= pix_hi) continue;
            arrived++;
            j->count[p] =
                (uint8_t)sl_kbuffer_insert(j->kbuf + (size_t)p * j->K, j->count[p], j->K, l->f[i]);
        }
    }
    for (uint32_t p = pix_lo; p < pix_hi; p++)
        kept += j->count[p];
    /* the fragments that are no entry of their own: merged on overflow or hidden behind full
     * coverage (the OpenCL fill counts the same from its counts: host/passes/view/view_cl.c) */
    j->merges[part] = arrived - kept;
}

size_t slc_kbuffer_build_parts(const slc_frag_list *parts, int nparts, int w, int h, int K,
                               sl_kfrag *kbuf, uint8_t *count, int nthreads) {
    enum { MAXT = 16 };
    if (nthreads < 1) nthreads = 1;
    if (nthreads > MAXT) nthreads = MAXT;
    memset(count, 0, (size_t)w * h);
    size_t part_merges[MAXT] = {0};
    kb_job job = {parts, nparts, w, K, kbuf, count, part_merges};
    sl_parallel_parts(nthreads, (size_t)h, kb_part, &job);
    size_t merges = 0;
    for (int t = 0; t < nthreads; t++)
        merges += part_merges[t];
    return merges;
}

size_t slc_kbuffer_build(const slc_frag_list *l, int w, int h, int K, sl_kfrag *kbuf,
                         uint8_t *count, int nthreads) {
    return slc_kbuffer_build_parts(l, 1, w, h, K, kbuf, count, nthreads);
}
