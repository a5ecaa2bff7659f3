/* dodm.c: the C twin of kernels/dodm.cl (see kernels/dodm.h). Integer scans are exact, so any
 * order gives the kernel's tables; the lookup runs the same float code from kernels/dodm.h. */
#include "../cpu/dodm.h"
#include "../kernels/dodm.h"

void slc_dodm_cumulate(uint64_t *bins, size_t plane, unsigned K) {
    for (unsigned k = 1; k < K; k++)
        for (size_t t = 0; t < plane; t++)
            bins[k * plane + t] += bins[(k - 1) * plane + t];
}

void slc_dodm_cumulate_texel(const uint64_t *bins, size_t plane, unsigned K, uint64_t *planes) {
    for (size_t t = 0; t < plane; t++) {
        uint64_t s = 0;
        for (unsigned k = 0; k < K; k++)
            planes[k * plane + t] = s += bins[t * K + k];
    }
}

void slc_dodm_sat(uint64_t *a, int w, int h, unsigned K) {
    for (unsigned k = 0; k < K; k++) {
        uint64_t *p = a + (size_t)k * w * h;
        for (int y = 0; y < h; y++) {
            uint64_t *row = p + (size_t)y * w, s = 0;
            for (int x = 0; x < w; x++)
                row[x] = s += row[x];
            if (y > 0) /* add the row above: columns scanned with the rows, cache-friendly */
                for (int x = 0; x < w; x++)
                    row[x] += row[x - w];
        }
    }
}

void slc_dodm_lookup(const uint32_t *z0bits, const uint64_t *sat, int w, int h, unsigned K, float d,
                     float rfac, float inv_scale, const float *pts, size_t n, float *T) {
    for (size_t i = 0; i < n; i++)
        T[i] = expf(-sl_dodm_tau(z0bits, sat, w, h, K, d, rfac, inv_scale, pts[3 * i],
                                 pts[3 * i + 1], pts[3 * i + 2]));
}

void slc_dodm_lookup_both(const uint32_t *z0bits, const uint64_t *sat, int w, int h, unsigned K,
                          float d, float rfac, float inv_scale, const float *pts, size_t n,
                          float *T, float *B) {
    for (size_t i = 0; i < n; i++)
        T[i] = expf(-sl_dodm_tau_split(z0bits, sat, w, h, K, d, rfac, inv_scale, pts[3 * i],
                                       pts[3 * i + 1], pts[3 * i + 2], &B[i]));
}

void slc_dodm_lookup_lobes(const uint32_t *z0bits, const uint64_t *sat, int w, int h, unsigned K,
                           const float *params, const float *views, const float *pts,
                           const uint32_t *lobe, size_t n, unsigned nl, unsigned lobe0,
                           size_t stride, float *T) {
    for (size_t i = 0; i < n; i++) {
        if (lobe) {
            if (lobe[i] < lobe0 || lobe[i] - lobe0 >= nl) continue;
            T[i] = expf(-sl_dodm_tau_lobe(z0bits, sat, w, h, K, params, views, lobe[i] - lobe0,
                                          pts + 3 * i));
        } else
            for (unsigned l = 0; l < nl; l++)
                T[i * stride + lobe0 + l] =
                    expf(-sl_dodm_tau_lobe(z0bits, sat, w, h, K, params, views, l, pts + 3 * i));
    }
}
