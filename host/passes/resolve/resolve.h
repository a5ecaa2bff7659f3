/* resolve.h: the resolve pass of the frame: front-to-back compositing of each pixel's K-buffer
 * entries, each with its shading (sl_shade_entry: the fragment's own point, or the strand
 * vertices around it interpolated), into the beauty and the AOVs of sl_fbuf (plan/frame.h). */
#ifndef SL_RESOLVE_H
#define SL_RESOLVE_H

#include "plan/passes.h"

/* Allocates in->out at the view pass's size and composites it from the K-buffer, the shading
 * points and their results of this frame (r->fw). Returns 0. */
int sl_resolve_run(sl_renderer *r, const sl_frame_inputs *in, sl_err *e);

#endif
