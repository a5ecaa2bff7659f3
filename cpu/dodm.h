/* dodm.h (cpu): the C twin of kernels/dodm.cl: cumulative layers, exact 64-bit summed-area
 * tables and the convolution-optical-depth lookup (kernels/dodm.h). */
#ifndef SL_CPU_DODM_H
#define SL_CPU_DODM_H

#include <stddef.h>
#include <stdint.h>

/* Plane k of the K planes of w * h values becomes the sum of planes 0..k. */
void slc_dodm_cumulate(uint64_t *bins, size_t plane, unsigned K);
/* The same from texel-major bins (bins[t K + k], cpu/raster.h: slc_raster_layers_texel) into
 * planes (planes[k plane + t] = the sum of bins[t K + 0 .. k]). */
void slc_dodm_cumulate_texel(const uint64_t *bins, size_t plane, unsigned K, uint64_t *planes);
/* Every plane becomes its inclusive summed-area table (exact, modulo 2^64). */
void slc_dodm_sat(uint64_t *a, int w, int h, unsigned K);
/* T[i] = exp(-tau) at n points (u, v, z) (kernels/dodm.h: sl_dodm_tau). */
void slc_dodm_lookup(const uint32_t *z0bits, const uint64_t *sat, int w, int h, unsigned K, float d,
                     float rfac, float inv_scale, const float *pts, size_t n, float *T);
/* The same T[i], and B[i] = the optical depth behind each point, from one box per point
 * (kernels/dodm.h: sl_dodm_tau_split). */
void slc_dodm_lookup_both(const uint32_t *z0bits, const uint64_t *sat, int w, int h, unsigned K,
                          float d, float rfac, float inv_scale, const float *pts, size_t n,
                          float *T, float *B);
/* Batch lookup (kernels/dodm.cl: sl_dodm_lookup_lobes): maps of nl lobes stacked (z0 one plane,
 * tables K planes per lobe), params SL_DODM_PARAMS and views SL_RASTER_VIEW floats per lobe, pts
 * 3 n world floats. lobe == NULL: every lobe at every point, T[i stride + lobe0 + l]; else point
 * i for lobe[i] if it is in lobe0 .. lobe0 + nl - 1, T[i]. */
void slc_dodm_lookup_lobes(const uint32_t *z0bits, const uint64_t *sat, int w, int h, unsigned K,
                           const float *params, const float *views, const float *pts,
                           const uint32_t *lobe, size_t n, unsigned nl, unsigned lobe0,
                           size_t stride, float *T);

#endif
