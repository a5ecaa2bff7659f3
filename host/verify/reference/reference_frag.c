/* reference_frag.c: see reference_frag.h. Takes the fast path's K-buffer from its own view
 * pass (passes/view/frame_view.h, on the C device, as the frame runs it there), so the
 * reference shades exactly the fast path's fragments. */
#include "verify/reference/reference_frag.h"

#include "base/parallel.h"
#include "cl/clrt.h"
#include "passes/view/frame_view.h"
#include "plan/frame.h"

#include <stdlib.h>
#include <string.h>

int sl_ref_kbuffer_build(const sl_scene *s, const sl_hair *h, const sl_camera *cam, int threads,
                         sl_ref_kbuffer *out, sl_err *e) {
    memset(out, 0, sizeof *out);
    sl_device dev = {0};
    if (sl_device_open("c", &dev, e)) return -1;
    sl_view_result v = {0}; /* the K-buffer is the same for any thread count */
    int rc = sl_view_pass(&dev, sl_parallel_threads(threads), 0, h, cam, sl_frame_oit_k(s), &v, e);
    if (rc == 0) {
        out->w = v.w, out->h = v.h, out->K = v.K, out->kbuf = v.kbuf, out->kcount = v.kcount;
        size_t npx = (size_t)out->w * out->h;
        for (size_t p = 0; p < npx; p++)
            out->entries += out->kcount[p];
    } else {
        free(v.kbuf);
        free(v.kcount);
    }
    sl_device_close(&dev);
    return rc;
}

void sl_ref_kbuffer_free(sl_ref_kbuffer *k) {
    free(k->kbuf);
    free(k->kcount);
    memset(k, 0, sizeof *k);
}
