/* render_ref_frag.c: see render_ref_frag.h. The fragment-mode reference: every K-buffer entry of
 * the fast path shaded with the reference's slref_shade, composited with sl_kbuffer_weights. */
#include "render_ref_frag.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

uint32_t *slref_frag_strand_of(const sl_hair *h) {
    uint32_t *s = sl_malloc((h->num_points ? h->num_points : 1) * sizeof *s);
    for (uint32_t k = 0; k < h->num_strands; k++)
        for (uint32_t i = h->strand_first[k]; i < h->strand_first[k + 1]; i++)
            s[i] = k;
    return s;
}

uint32_t slref_frag_prim(const sl_hair *h, const uint32_t *strand_of, uint32_t seg) {
    if (seg + 1 >= h->num_points) return SLREF_RT_NONE;
    uint32_t s = strand_of[seg];
    if (seg + 1 >= h->strand_first[s + 1]) return SLREF_RT_NONE; /* the strand's last point */
    /* raytrace_ref.c numbers the segments strand by strand: strand s has points
     * strand_first[s] .. strand_first[s+1]-1 and segments p = i - s for its points i but the
     * last (every earlier strand has one point more than segments). */
    return seg - s;
}

typedef struct frag_job {
    const slref_shading *sh;
    const sl_hair *h;
    const uint32_t *strand_of;
    const slref_kbuf *kb;
    const double *eye;
    slref_image *img;
} frag_job;

static void frag_pixel(const frag_job *j, size_t px) {
    const slref_kbuf *kb = j->kb;
    const sl_hair *h = j->h;
    int n = kb->kcount[px];
    double acc[3] = {0, 0, 0}, accm[3] = {0, 0, 0}, accd[9] = {0};
    float wt[SL_KBUFFER_MAX];
    const sl_kfrag *f = kb->kbuf + px * (size_t)kb->K;
    float alpha = n > 0 ? sl_kbuffer_weights(f, n, wt) : 0.0f;
    for (int i = 0; i < n; i++) {
        if (!(wt[i] > 0)) continue; /* weight 0 (behind an opaque entry): adds nothing */
        uint32_t seg = f[i].seg, prim = slref_frag_prim(h, j->strand_of, seg);
        if (prim == SLREF_RT_NONE) continue; /* not a segment: the view pass never emits it */
        double x[3], wo[3], l = 0, ss[3], ms[3], md[9];
        for (int q = 0; q < 3; q++) { /* host/plan/frame.c build_points, in double */
            x[q] = h->pos[3 * seg + q] +
                   (double)f[i].t * (h->pos[3 * seg + 3 + q] - h->pos[3 * seg + q]);
            wo[q] = j->eye[q] - x[q];
            l += wo[q] * wo[q];
        }
        l = sqrt(l);
        if (!(l > 0)) continue;
        for (int q = 0; q < 3; q++)
            wo[q] /= l;
        slref_shade(j->sh, x, wo, prim, ss, ms, md);
        double w = wt[i];
        for (int q = 0; q < 3; q++)
            acc[q] += w * (ss[q] + ms[q]), accm[q] += w * ms[q];
        for (int q = 0; q < 9; q++)
            accd[q] += w * md[q];
    }
    for (int q = 0; q < 3; q++) {
        j->img->rgba[4 * px + q] = (float)acc[q];
        j->img->ms_rgb[3 * px + q] = (float)accm[q];
    }
    for (int q = 0; q < 9; q++)
        j->img->mode_rgb[9 * px + q] = (float)accd[q];
    j->img->rgba[4 * px + 3] = alpha;
    j->img->depth[px] = n > 0 ? f[0].z : INFINITY;
}

static void frag_rows(void *arg, size_t y0, size_t y1, int worker) {
    (void)worker;
    const frag_job *j = arg;
    for (size_t y = y0; y < y1; y++)
        for (int x = 0; x < j->kb->w; x++)
            frag_pixel(j, y * j->kb->w + x);
}

int slref_render_frags(const slref_shading *sh, const sl_hair *h, const slref_kbuf *kb,
                       const double eye[3], const slref_render_opts *o, slref_image *out,
                       sl_err *e) {
    memset(out, 0, sizeof *out);
    if (kb->w < 1 || kb->h < 1 || kb->K < 1 || kb->K > SL_KBUFFER_MAX)
        return sl_fail(e, "reference: bad K-buffer (%dx%d, K %d)", kb->w, kb->h, kb->K);
    slref_image_alloc(out, kb->w, kb->h);
    uint32_t *strand_of = slref_frag_strand_of(h);
    frag_job j = {.sh = sh, .h = h, .strand_of = strand_of, .kb = kb, .eye = eye, .img = out};
    slref_run_rows(frag_rows, &j, kb->h, o);
    free(strand_of);
    return 0;
}
