/* run_view.c: the view pass of the frame (frame_view.c fills the K-buffer), cached while
 * geometry, transparency, camera and K are unchanged (plan/passes.h). */
#include "plan/frame_internal.h"

int sl_frame_hair_transparent(const sl_hair *h) {
    if (!h->transparency) return h->default_transparency > 0;
    for (uint32_t i = 0; i < h->num_points; i++)
        if (h->transparency[i] > 0) return 1;
    return 0;
}

uint64_t sl_view_settings(const sl_renderer *r, const sl_frame_inputs *in) {
    (void)r;
    int K = sl_frame_oit_k(in->s);
    return sl_hash64(&K, sizeof K, 0x33);
}

/* The view pass on the renderer's K-buffer (the reference's fragment mode calls sl_view_pass
 * the same way). */
int sl_frame_view(sl_renderer *r, const sl_hair *h, const sl_camera *cam, int K, sl_err *e) {
    /* the K-buffer fill follows the same device rule as the SRBF response */
    return sl_view_pass(r->dev, sl_frame_threads(r), sl_frame_srbf_on_device(r), h, cam, K,
                        &r->view, e);
}

int sl_pass_view(sl_renderer *r, const sl_frame_inputs *in, sl_err *e) {
    int K = r->fw.K;
    if (sl_frame_view(r, in->h, in->cam, K, e)) return -1;
    size_t npx = (size_t)r->view.w * r->view.h;
    int maxc = 0;
    for (size_t i = 0; i < npx; i++)
        if (r->view.kcount[i] > maxc) maxc = r->view.kcount[i];
    sl_frame_why(r,
                 "%zu fragments, K=%d (deepest pixel %d), %zu merged on overflow or hidden "
                 "behind full coverage, "
                 "K-buffer on %s; %s",
                 r->view.frags, K, maxc, r->view.merges, r->view.on_device ? "OpenCL" : "C",
                 r->fw.transparent ? "per-point transparency applied"
                                   : "opaque hair: coverage only (transparency channel skipped)");
    return 0;
}
