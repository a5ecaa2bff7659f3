/* frame_internal.h: what the files of the frame (frame.c, the passes' runs, frame_view.c,
 * frame_shade.c) share. */
#ifndef SL_FRAME_INTERNAL_H
#define SL_FRAME_INTERNAL_H

#include "plan/frame.h"
#include "plan/renderer.h"
#include "passes/shade/frame_shade.h"
#include "passes/view/frame_view.h"

int sl_frame_threads(const sl_renderer *r);

/* The view pass (passes/view/frame_view.h) into the renderer's r->view. */
int sl_frame_view(sl_renderer *r, const sl_hair *h, const sl_camera *cam, int K, sl_err *e);


/* 1 when the SRBF response and the K-buffer fill run on the OpenCL device, 0 on the C twins. */
int sl_frame_srbf_on_device(const sl_renderer *r);
/* SRBF + MS per point with the renderer's device, threads, method and tables
 * (passes/shade/frame_shade.h: sl_shade_run). */
int sl_frame_shade(sl_renderer *r, const sl_shade_ctx *c, sl_shade_points *p, sl_err *e);

#endif
