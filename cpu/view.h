/* view.h (cpu): the C twin of the view pass: hair segments already projected into the camera
 * (pixel coordinates, view depth) become per-pixel fragments with coverage antialiasing through
 * the shared segment rasterizer (kernels/raster.h: a ribbon sampled at most 1/2 pixel apart,
 * each sample tent-splatted onto 4 pixels, so a strand's area is conserved even when it is far
 * thinner than a pixel), and the fragments go into the per-pixel K-buffer (kernels/kbuffer.h). */
#ifndef SL_CPU_VIEW_H
#define SL_CPU_VIEW_H

#include "kbuffer.h"

#include <stddef.h>
#include <stdint.h>

/* A growing list of fragments and their pixel index (y * w + x). */
typedef struct slc_frag_list {
    sl_kfrag *f;
    uint32_t *pix;
    size_t n, cap;
} slc_frag_list;

void slc_frag_list_free(slc_frag_list *l);

/* Appends the fragments of the ribbon p0 -> p1 (x, y pixels with centres at i + 0.5, z the view
 * depth) of half-width hw pixels: one fragment per pixel it touches, with coverage min(1, sum of
 * the tent shares) times the opacity interpolated between a0 and a1, and the share-weighted mean
 * depth and parameter t along the segment. Fragments with coverage below 1e-4 are dropped (they
 * change no 16-bit half output). seg: the index of the segment's first point. */
void slc_view_segment(const double p0[3], const double p1[3], double hw, float a0, float a1,
                      uint32_t seg, int w, int h, slc_frag_list *out);

/* Fills the K-buffer: kbuf (K per pixel, w * h pixels) and count (entries per pixel) from the
 * fragments in list order, which fixes the result (merges depend on order). nthreads > 1 splits
 * the image into row bands; each band sees the fragments in the same order, so the result does
 * not depend on nthreads. Returns the number of merges (overflowing insertions). */
size_t slc_kbuffer_build(const slc_frag_list *l, int w, int h, int K, sl_kfrag *kbuf,
                         uint8_t *count, int nthreads);

#endif
