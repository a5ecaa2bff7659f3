/* reference_frag.c: see reference_frag.h. Borrows the fast path's view pass through a renderer
 * on the C device and takes its K-buffer (the renderer's kbuf/kcount are handed over, not
 * copied). frame*.c are not changed: sl_frame_view (frame_internal.h) is called as the frame
 * itself calls it. */
#include "verify/reference/reference_frag.h"

#include "cl/clrt.h"
#include "plan/frame.h"
#include "plan/frame_internal.h"

#include <stdlib.h>
#include <string.h>

int sl_ref_kbuffer_build(const sl_scene *s, const sl_hair *h, const sl_camera *cam, int threads,
                         sl_ref_kbuffer *out, sl_err *e) {
    memset(out, 0, sizeof *out);
    sl_device dev = {0};
    if (sl_device_open("c", &dev, e)) return -1;
    sl_render_opts ro;
    sl_render_opts_default(&ro);
    ro.threads = threads, ro.quiet = 1;
    sl_renderer *r = sl_renderer_create(&dev, &ro);
    int K = sl_frame_oit_k(s), rc = sl_frame_view(r, h, cam, K, e);
    if (rc == 0) {
        sl_renderer_take_kbuffer(r, &out->w, &out->h, &out->K, &out->kbuf, &out->kcount);
        size_t npx = (size_t)out->w * out->h;
        for (size_t p = 0; p < npx; p++)
            out->entries += out->kcount[p];
    }
    sl_renderer_free(r);
    sl_device_close(&dev);
    return rc;
}

void sl_ref_kbuffer_free(sl_ref_kbuffer *k) {
    free(k->kbuf);
    free(k->kcount);
    memset(k, 0, sizeof *k);
}
