/* run_resolve.c: the planner's run of the resolve pass (passes/resolve/resolve.h) over this
 * frame's K-buffer and shading (r->fw), with the line --explain prints. */
#include "plan/frame_internal.h"

int sl_pass_resolve(sl_renderer *r, const sl_frame_inputs *in, sl_err *e) {
    (void)e;
    const sl_frame_work *w = &r->fw;
    sl_kbuf_view kb = sl_frame_kbuf(r);
    sl_resolve(&kb, in->h, r->rate_k, &w->sm, &w->pts, in->out);
    sl_frame_why(r, "front-to-back compositing of %dx%d pixels%s", kb.w, kb.h,
                 w->transparent ? "" : " (opaque hair: coverage alpha only)");
    return 0;
}
