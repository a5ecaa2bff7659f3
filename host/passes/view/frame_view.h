/* frame_view.h: the view pass: every segment of the hair projected into the camera, turned into
 * fragments with coverage antialiasing (cpu/view.c, the shared splat of kernels/splat.h) and
 * inserted in segment order into a K-buffer of K entries per pixel (kernels/kbuffer.h; the C twin
 * or kernels/view.cl), bit-identical for any thread count and either backend. The planner's
 * run is plan/run_view.c; the fragment reference (verify/reference/reference_frag.c) calls it
 * too, to shade exactly these fragments. */
#ifndef SL_FRAME_VIEW_H
#define SL_FRAME_VIEW_H

#include "base/common.h"
#include "cl/clrt.h"
#include "io/hair/hair.h"
#include "kbuffer.h"
#include "scene/camera.h"

#include <stddef.h>
#include <stdint.h>

typedef struct sl_view_result {
    int w, h, K;       /* pixels and entries per pixel */
    sl_kfrag *kbuf;    /* w x h x K entries */
    uint8_t *kcount;   /* w x h: entries filled */
    size_t frags;      /* fragments generated */
    size_t merges;     /* fragments without an entry of their own (merged or hidden) */
    int on_device;     /* the K-buffer fill ran on OpenCL */
    float seg_px_median; /* median projected segment length, pixels (shading_rate auto) */
} sl_view_result;

/* Renders the K-buffer of h seen by cam into r (its kbuf and kcount are freed and allocated
 * anew; the other fields are set). threads: C threads; on_device: fill the K-buffer with the
 * OpenCL kernel of dev (falls back to C where dev allows). Returns 0, or -1 with e set. */
int sl_view_pass(sl_device *dev, int threads, int on_device, const sl_hair *h,
                 const sl_camera *cam, int K, sl_view_result *r, sl_err *e);

#endif
