/* view_cl.h: the OpenCL driver of the K-buffer fill (kernels/view.cl; C twin
 * slc_kbuffer_build of cpu/view.h). Results equal the C twin's bit for bit. */
#ifndef SL_VIEW_CL_H
#define SL_VIEW_CL_H

#include "cl/clrt.h"
#include "view.h"

/* Fills kbuf (K per pixel) and count from the fragment list l (list order kept per pixel);
 * *merges gets the number of fragments that are no entry of their own (merged or hidden), as
 * slc_kbuffer_build counts them. Returns 0, -1 (e set) or SL_CL_EKERNEL. */
int slcl_kbuffer_build(sl_cl *cl, const slc_frag_list *l, int w, int h, int K, sl_kfrag *kbuf,
                       uint8_t *count, size_t *merges, sl_err *e);
/* The same with the build chosen: specialised = 1 builds view.cl with -DSL_KB_K=K (what
 * slcl_kbuffer_build uses), 0 the generic program (K a kernel argument). *kernel_s (may be NULL)
 * gets the kernel's time (profiling events when the queue has them, else the wall clock of
 * launch + finish). */
int slcl_kbuffer_build_ex(sl_cl *cl, const slc_frag_list *l, int w, int h, int K, int specialised,
                          sl_kfrag *kbuf, uint8_t *count, size_t *merges, double *kernel_s,
                          sl_err *e);

#endif
