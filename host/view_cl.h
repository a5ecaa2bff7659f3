/* view_cl.h: the OpenCL driver of the K-buffer fill (kernels/kbuffer.cl; C twin
 * slc_kbuffer_build of cpu/view.h). Results equal the C twin's bit for bit. */
#ifndef SL_VIEW_CL_H
#define SL_VIEW_CL_H

#include "clrt.h"
#include "view.h"

/* Fills kbuf (K per pixel) and count from the fragment list l (list order kept per pixel);
 * *merges gets the number of overflowing insertions. Returns 0, -1 (e set) or SL_CL_EKERNEL. */
int slcl_kbuffer_build(sl_cl *cl, const slc_frag_list *l, int w, int h, int K, sl_kfrag *kbuf,
                       uint8_t *count, size_t *merges, sl_err *e);

#endif
