/* frame_view.c: the view pass of the frame (frame_view.h): every segment projected into the camera
 * (perspective, per endpoint, in double), turned into fragments by the shared rasterizer
 * (cpu/view.c) in threads over contiguous segment ranges, then inserted in segment order into
 * the K-buffer (C twin in threads over row bands, or kernels/view.cl through
 * host/passes/view/view_cl.h, bit-identical), so the result is independent of the thread count and
 * the backend. */
#include "passes/view/frame_view.h"

#include "base/parallel.h"
#include "view.h"
#include "passes/view/view_cl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct vjob {
    const sl_hair *h;
    const sl_camera *cam;
    slc_frag_list *out; /* one list per part, concatenated in part order */
    float *seglen;      /* projected length per segment (NAN when not drawn), indexed by point */
} vjob;

/* Strands begin .. end - 1 into part's own fragment list. */
static void view_part(void *arg, size_t begin, size_t end, int part) {
    const vjob *j = arg;
    const sl_hair *h = j->h;
    const sl_camera *cam = j->cam;
    slc_frag_list *out = &j->out[part];
    for (uint32_t s = (uint32_t)begin; s < (uint32_t)end; s++) {
        uint32_t a = h->strand_first[s], b = h->strand_first[s + 1];
        for (uint32_t i = a; i + 1 < b; i++) {
            double q0[3], q1[3], p0[3], p1[3];
            for (int k = 0; k < 3; k++)
                q0[k] = h->pos[3 * i + k], q1[k] = h->pos[3 * i + 3 + k];
            if (!sl_camera_project(cam, q0, &p0[0], &p0[1], &p0[2]) ||
                !sl_camera_project(cam, q1, &p1[0], &p1[1], &p1[2]))
                continue;
            double r0 = h->radius ? h->radius[i] : h->default_radius;
            double r1 = h->radius ? h->radius[i + 1] : h->default_radius;
            double hw = 0.5 * (r0 * cam->focal / p0[2] + r1 * cam->focal / p1[2]);
            float a0 = 1.0f - (h->transparency ? h->transparency[i] : h->default_transparency);
            float a1 = 1.0f - (h->transparency ? h->transparency[i + 1] : h->default_transparency);
            a0 = a0 < 0 ? 0 : (a0 > 1 ? 1 : a0);
            a1 = a1 < 0 ? 0 : (a1 > 1 ? 1 : a1);
            j->seglen[i] = (float)hypot(p1[0] - p0[0], p1[1] - p0[1]);
            slc_view_segment(p0, p1, hw, a0, a1, i, cam->width, cam->height, out);
        }
    }
}

static int cmp_float(const void *a, const void *b) {
    float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : x > y;
}

int sl_view_pass(sl_device *dev, int threads, int on_device, const sl_hair *h, const sl_camera *cam,
                 int K, sl_view_result *r, sl_err *e) {
    enum { MAXT = 16 };
    int nt = threads;
    if (nt > MAXT) nt = MAXT;
    if (h->num_strands < 64) nt = 1;
    int w = cam->width, hh = cam->height;
    float *seglen = sl_malloc((h->num_points ? h->num_points : 1) * sizeof *seglen);
    for (uint32_t i = 0; i < h->num_points; i++)
        seglen[i] = NAN;
    slc_frag_list out[MAXT] = {{0}};
    vjob job = {h, cam, out, seglen};
    /* parts are whole strands, and a run of fragments (cpu/view.c) never continues across a
     * strand, so the part lists concatenated in part order are the one-thread list */
    sl_parallel_parts(nt, h->num_strands, view_part, &job);
    int nt_lists = nt;
    size_t total = 0;
    for (int t = 0; t < nt; t++)
        total += out[t].n;
    free(r->kbuf);
    free(r->kcount);
    size_t npx = (size_t)w * hh;
    r->kbuf = sl_malloc(npx * K * sizeof *r->kbuf);
    r->kcount = sl_malloc(npx);
    r->w = w, r->h = hh, r->K = K;
    int done = 0;
    if (on_device) {
        /* the device takes one list: the parts appended to the first in segment order (its
         * size is known: one reallocation), each freed once copied */
        slc_frag_list all = out[0];
        if (total > all.cap) {
            all.cap = total;
            all.f = sl_realloc(all.f, all.cap * sizeof *all.f);
            all.pix = sl_realloc(all.pix, all.cap * sizeof *all.pix);
        }
        for (int t = 1; t < nt; t++) {
            if (out[t].n) { /* (an empty part may have no buffers: no memcpy from NULL) */
                memcpy(all.f + all.n, out[t].f, out[t].n * sizeof *all.f);
                memcpy(all.pix + all.n, out[t].pix, out[t].n * sizeof *all.pix);
                all.n += out[t].n;
            }
            slc_frag_list_free(&out[t]);
        }
        out[0] = all;
        nt_lists = 1;
        int rc = slcl_kbuffer_build(dev->cl, &all, w, hh, K, r->kbuf, r->kcount, &r->merges, e);
        if (rc == 0)
            done = 1;
        else if (!sl_device_try_fallback(dev, rc, e)) {
            slc_frag_list_free(&out[0]);
            free(seglen);
            return -1;
        }
    }
    /* C: the per-thread lists in part order are the one-thread list; no copy */
    if (!done) slc_kbuffer_build_parts(out, nt_lists, w, hh, K, r->kbuf, r->kcount, nt);
    r->on_device = done;
    r->frags = total;
    /* fragments without an entry of their own (merged on overflow, or hidden behind a fully
     * opaque entry, kernels/kbuffer.h): the same count on both backends */
    size_t entries = 0;
    for (size_t p = 0; p < npx; p++)
        entries += r->kcount[p];
    r->merges = total - entries;
    for (int t = 0; t < nt_lists; t++)
        slc_frag_list_free(&out[t]);
    /* median projected segment length (for shading_rate auto) */
    size_t m = 0;
    for (uint32_t i = 0; i < h->num_points; i++)
        if (!isnan(seglen[i])) seglen[m++] = seglen[i];
    if (m) {
        qsort(seglen, m, sizeof *seglen, cmp_float);
        r->seg_px_median = seglen[m / 2];
    } else {
        r->seg_px_median = 0;
    }
    free(seglen);
    return 0;
}
