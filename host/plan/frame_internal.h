/* frame_internal.h: what the files of the frame (frame.c, the passes' runs, frame_view.c,
 * frame_shade.c) share. */
#ifndef SL_FRAME_INTERNAL_H
#define SL_FRAME_INTERNAL_H

#include "plan/frame.h"
#include "plan/renderer.h"

int sl_frame_threads(const sl_renderer *r);

/* The view pass: fills r->kbuf, r->kcount (w x h x K) and r->frags, r->merges, seg_px_median. */
int sl_frame_view(sl_renderer *r, const sl_hair *h, const sl_camera *cam, int K, sl_err *e);

typedef struct sl_shade_ctx {
    const sl_material *mat;
    const sl_lobes *lobes;
    const int *used; /* lobe indices */
    int nused;
    const double *share; /* per used lobe: share of the total power */
    const sl_camera *cam;
    int ms_on;
    const sl_ftex *ftex; /* T_f, sigma_f per lobe (used index) */
    const sl_volume_ms *vms;
    /* per point: skip lobe j when T_j x share_j < point_threshold x the used shares' sum
     * (quality.point_threshold, default SL_FRAME_POINT_THRESHOLD) */
    double point_threshold;
    /* per-strand sigma_a (3 per strand, indexed by sl_shade_points.strand), or NULL: the
     * material's sigma_a everywhere (the same as r->strand_sigma_a, checked against the hair) */
    const float *strand_sigma_a;
} sl_shade_ctx;

/* 1 when the SRBF response and the K-buffer fill run on the OpenCL device, 0 on the C twins. */
int sl_frame_srbf_on_device(const sl_renderer *r);
/* SRBF + MS per point (C twin in threads, or the OpenCL srbf kernel). */
int sl_frame_shade(sl_renderer *r, const sl_shade_ctx *c, sl_shade_points *p, sl_err *e);

#endif
