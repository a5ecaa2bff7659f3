/* view.cl: the K-buffer fill of the view pass on the device (C twin: slc_kbuffer_build in
 * cpu/view.c; math: kernels/kbuffer.h). The host sorts the fragments by pixel, stably (segment
 * order kept within a pixel), so one work-item per pixel inserts its fragments in the same order
 * as the C twin: the buffers are bit-identical. Built with -DSL_KB_K=K (specialised: the
 * pixel's private buffer has exactly K entries and every loop bound is a constant), or without
 * it (generic: K is the kernel argument k, the buffer SL_KBUFFER_MAX entries); `kernels --bench`
 * times both (docs/frame.md). */
/* No fused multiply-add: "over" must round like the C twin's a + (1 - a) b. */
#pragma OPENCL FP_CONTRACT OFF
#include "kbuffer.h"

#ifdef SL_KB_K
#define KB_CAP SL_KB_K
#define KB_K SL_KB_K
#else
#define KB_CAP SL_KBUFFER_MAX
#define KB_K k
#endif

__kernel void sl_kbuffer_fill(__global const sl_kfrag *frags, __global const uint *start,
                              const uint npx, __global sl_kfrag *kbuf, __global uchar *count,
                              const int k) {
    uint p = get_global_id(0);
    if (p >= npx) return;
    sl_kfrag buf[KB_CAP];
    int n = 0;
    for (uint i = start[p]; i < start[p + 1]; i++)
        n = sl_kbuffer_insert(buf, n, KB_K, frags[i]);
    for (int i = 0; i < n; i++)
        kbuf[(size_t)p * KB_K + i] = buf[i];
    count[p] = (uchar)n;
}
