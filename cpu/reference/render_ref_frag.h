/* render_ref_frag.h: the reference's fragment mode (issue 10, docs/reference.md "Fragment
 * mode"): the reference shades exactly the K-buffer entries of the fast path's view pass
 * (host/passes/view/frame_view.c) instead of tracing camera rays, and composites them with the fast path's
 * own front-to-back weights (kernels/kbuffer.h sl_kbuffer_weights). Coverage, alpha and depth
 * are therefore identical to the fast path's, and the only error of the image left to the
 * reference is its light cut (N directional lights), which N vs 2N lights measures.
 *
 * Each entry (segment `seg` = global index of its first point, parameter t) is shaded where the
 * fast path shades it at fragment rate (host/plan/frame.c build_points): x = pos[seg] + t (pos[seg+1]
 * - pos[seg]) in double, wo = unit(eye - x), with slref_shade (every light, exact fiber function,
 * shadow rays through the real fibers; the Embree primitive is seg - strand(seg), and the
 * self-hit rule of raytrace_ref.h ignores the entry's own segment and its neighbours).
 * Deterministic: no random numbers; every pixel is computed alone, whatever the thread count. */
#ifndef SL_RENDER_REF_FRAG_H
#define SL_RENDER_REF_FRAG_H

#include "io/hair/hair.h"
#include "kbuffer.h"
#include "render_ref.h"

#include <stdint.h>

/* The fast path's K-buffer of one frame: w * h pixels, K slots each (row 0 at the top);
 * kcount[px] entries of pixel px are kbuf[px K .. px K + kcount[px] - 1], nearest first. */
typedef struct slref_kbuf {
    int w, h, K;
    const sl_kfrag *kbuf;
    const uint8_t *kcount;
} slref_kbuf;

/* The Embree primitive (global segment index of raytrace_ref.c: segments numbered strand by
 * strand) of the segment that starts at hair point `seg`, and its strand; SLREF_RT_NONE when
 * seg is not the first point of a segment. strand_of: per point (slref_frag_strand_of). */
uint32_t slref_frag_prim(const sl_hair *h, const uint32_t *strand_of, uint32_t seg);
/* Per point strand index (num_points entries; free()). */
uint32_t *slref_frag_strand_of(const sl_hair *h);

/* Shades every entry of kb with sh (h: the hair the view pass drew and rt was built from; eye:
 * the camera position) and composites: out rgba = sum_i w_i (ss_i + ms_i), alpha = sum w_i,
 * depth = nearest entry's z (+inf when empty), ms_rgb / mode_rgb likewise weighted. o->threads,
 * o->progress are used (aa, jitter and seed are not). Returns 0 or -1 with e set. */
int slref_render_frags(const slref_shading *sh, const sl_hair *h, const slref_kbuf *kb,
                       const double eye[3], const slref_render_opts *o, slref_image *out,
                       sl_err *e);

#endif
