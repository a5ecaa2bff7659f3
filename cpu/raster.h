/* raster.h (cpu): the C twin of kernels/raster.cl (segment rasterizer, kernels/raster.h) and the
 * builder of the segment records both consume. Maps are row-major w x h; bins are K planes. */
#ifndef SL_CPU_RASTER_H
#define SL_CPU_RASTER_H

#include <stddef.h>
#include <stdint.h>

/* Record of the ribbon from p0 to p1 (x, y in texels with centres at i + 0.5, z a depth >= 0) of
 * half-width hw texels: area 2 hw |p1 - p0|_xy texel^2, times `scale` (fixed-point units per
 * texel^2), spread over a grid of samples at most 1/2 texel apart. A ribbon with no area (a
 * segment seen end-on, or hw = 0) gets no samples. rec has SL_RASTER_REC (12) floats. */
void slc_raster_record(const double p0[3], const double p1[3], double hw, double scale, float *rec);

/* Records (SL_RASTER_REC floats each, lobe-major: recs[(l nseg + s) SL_RASTER_REC]) of nl lobes x
 * nseg segments: segment s runs from world point pos[3 seg[s]] to the next one, half-width hw[s]
 * texels; views: SL_RASTER_VIEW floats per lobe (kernels/raster.h: sl_raster_project_seg, float
 * arithmetic identical to raster.cl's sl_raster_project_k). */
void slc_raster_project(const float *pos, const uint32_t *seg, const float *hw, const float *views,
                        size_t nseg, unsigned nl, float mscale, float *recs);
/* Pass 1: z0bits[t] = the smallest depth (as uint bits) of any sample with a non-zero share in
 * texel t, SL_RASTER_Z_EMPTY (+inf) where none. Fills z0bits itself. */
void slc_raster_z0(const float *recs, size_t nseg, int w, int h, uint32_t *z0bits);
/* Between the passes: z0bits becomes its minimum over the (2m + 1)^2 window around every texel
 * (kernels/raster.h: sl_raster_z0_window), or with frac > 0 that minimum blended toward the one
 * over (2m + 3)^2 (sl_raster_z0_blend: a window of half-size m + frac). m <= 0 and frac 0:
 * unchanged. tmp: w * h scratch values; tmp2 too when frac > 0 (else unused, may be NULL). */
void slc_raster_z0_dilate(uint32_t *z0bits, int w, int h, int m, float frac, uint32_t *tmp,
                          uint32_t *tmp2);
/* Pass 2: bins[k * w * h + t] = the fixed-point shares landing in texel t at a depth offset
 * (z - z0) inside layer k (kernels/raster.h: sl_raster_layer). Zeroes bins (K planes) itself. */
void slc_raster_layers(const float *recs, size_t nseg, int w, int h, unsigned K, float d,
                       const uint32_t *z0bits, uint64_t *bins);
/* Pass 2 into texel-major bins: bins[t * K + k] (a texel's layers side by side, so the four tent
 * corners of a sample touch one or two cache lines instead of 4 K); the same sums as
 * slc_raster_layers. cpu/dodm.h: slc_dodm_cumulate_texel turns them into planes. */
void slc_raster_layers_texel(const float *recs, size_t nseg, int w, int h, unsigned K, float d,
                             const uint32_t *z0bits, uint64_t *bins);

#endif
