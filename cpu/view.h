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

struct slc_run_px; /* private to cpu/view.c */

/* A growing list of fragments and their pixel index (y * w + x). Zero-initialise it ({0}); the
 * fields after `cap` are the strand-continuity state of slc_view_segment (docs/coverage.md): the
 * pixels the previous segment touched, so that the next segment of the same strand adds its
 * coverage to theirs instead of compositing over them. Only f, pix, n and cap are the list. */
typedef struct slc_frag_list {
    sl_kfrag *f;
    uint32_t *pix;
    size_t n, cap;
    struct slc_run_px *run, *run_next;
    size_t run_n, run_cap, run_next_cap;
    double last_p1[3];
    uint32_t last_seg;
    int has_last;
} slc_frag_list;

void slc_frag_list_free(slc_frag_list *l);

/* Appends the fragments of the ribbon p0 -> p1 (x, y pixels with centres at i + 0.5, z the view
 * depth) of half-width hw pixels: one fragment per pixel it touches, with coverage min(1, sum of
 * the tent shares) times the opacity interpolated between a0 and a1, and the share-weighted mean
 * depth and parameter t along the segment. Fragments with coverage below 1e-4 are dropped (they
 * change no 16-bit half output). seg: the index of the segment's first point.
 *
 * Strands (docs/coverage.md): when this call continues the previous call on the same list (seg is
 * the previous seg + 1 and p0 equals the previous p1 bit for bit: the next segment of the same
 * strand), a pixel that the previous segment also touched gets no second fragment: the two
 * segments' shares add in ONE fragment, coverage min(1, M1 + M2) (one ribbon, as if the strand
 * were drawn in one piece), instead of two fragments that the K-buffer would composite with
 * "over" as if they were independent (losing M1 M2 at every joint). The merged fragment's depth
 * is the share-weighted mean, its opacity the share-weighted mean of the members', and it is
 * shaded at the (seg, t) of the member with the larger share (the earlier on a tie). Call the
 * segments of a strand in order on one list to get this; any other order gives the per-segment
 * fragments of before. */
void slc_view_segment(const double p0[3], const double p1[3], double hw, float a0, float a1,
                      uint32_t seg, int w, int h, slc_frag_list *out);

/* Fills the K-buffer: kbuf (K per pixel, w * h pixels) and count (entries per pixel) from the
 * fragments in list order, which fixes the result (merges depend on order). nthreads > 1 splits
 * the image into row bands; each band sees the fragments in the same order, so the result does
 * not depend on nthreads. Returns the number of fragments that are no entry of their own
 * (merged on overflow or hidden behind full coverage): all of them less the entries kept. */
size_t slc_kbuffer_build(const slc_frag_list *l, int w, int h, int K, sl_kfrag *kbuf,
                         uint8_t *count, int nthreads);
/* The same from several lists taken one after another (parts[0] first), as if concatenated:
 * the view pass's per-thread lists without the copy (a frame's fragments are ~120 MB on the goal
 * scene; docs/performance.md, session 15). */
size_t slc_kbuffer_build_parts(const slc_frag_list *parts, int nparts, int w, int h, int K,
                               sl_kfrag *kbuf, uint8_t *count, int nthreads);

#endif
