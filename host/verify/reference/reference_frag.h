/* reference_frag.h: the fast path's K-buffer for the reference's fragment mode
 * (host/verify/reference/reference.h sl_reference_settings.fragments, cpu/reference/render_ref_frag.h): the view
 * pass of `strandlight render` (host/passes/view/frame_view.c, sl_frame_view) run on the C device with the
 * scene's K (sl_frame_oit_k), so the reference shades exactly the entries the fast path shades. */
#ifndef SL_REFERENCE_FRAG_H
#define SL_REFERENCE_FRAG_H

#include "scene/camera.h"
#include "base/common.h"
#include "io/hair/hair.h"
#include "kbuffer.h"
#include "scene/scene.h"

#include <stdint.h>

typedef struct sl_ref_kbuffer {
    int w, h, K;
    sl_kfrag *kbuf;  /* w * h * K */
    uint8_t *kcount; /* w * h */
    size_t entries;  /* sum of kcount */
} sl_ref_kbuffer;

/* Runs the view pass of hair h under cam with K = sl_frame_oit_k(s), on the C twin with
 * `threads` threads (0: every CPU; the result does not depend on it). Returns 0 or -1 with e. */
int sl_ref_kbuffer_build(const sl_scene *s, const sl_hair *h, const sl_camera *cam, int threads,
                         sl_ref_kbuffer *out, sl_err *e);
void sl_ref_kbuffer_free(sl_ref_kbuffer *k);

#endif
