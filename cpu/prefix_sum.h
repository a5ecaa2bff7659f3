/* prefix_sum.h (cpu): the C twin of kernels/prefix_sum.cl: inclusive row scans and the 2-D
 * inclusive prefix sum (summed-area table) of a W x H float image, adding in exactly the kernel's
 * order (tiles of SL_SCAN_TILE, Blelloch up/down-sweep, recursive tile totals), so the OpenCL
 * results match bit for bit. Images are row-major: a[y * w + x]. */
#ifndef SL_CPU_PREFIX_SUM_H
#define SL_CPU_PREFIX_SUM_H

#include <stddef.h>

/* out[y][x] = sum of in[y][0..x], for every row. in == out is allowed. */
void slc_scan_rows(const float *in, float *out, size_t w, size_t h);

/* out[y][x] = sum of in[j][i] over j <= y, i <= x. in == out is allowed. w, h >= 1 and
 * w * h * sizeof(float) must fit in memory (the caller checks). */
void slc_prefix_sum_2d(const float *in, float *out, size_t w, size_t h);

#endif
