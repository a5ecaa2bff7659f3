/* prefix_sum.c: the C twin of kernels/prefix_sum.cl (see cpu/prefix_sum.h). It runs the kernel's
 * work-items one after another; the scan steps themselves come from kernels/prefix_sum.h.
 * (Both headers are called prefix_sum.h, so they are included by relative path.) */
#include "../cpu/prefix_sum.h"
#include "../kernels/prefix_sum.h"

#include "base/common.h"

#include <stdlib.h>
#include <string.h>

/* Floats of scratch scan_row needs for a row of n: tile totals and their scan, per level. */
static size_t scratch_size(size_t n) {
    size_t nt = (n + SL_SCAN_TILE - 1) / SL_SCAN_TILE;
    return nt > 1 ? 2 * nt + scratch_size(nt) : 0;
}

/* Inclusive scan of in[0..n) into out (in == out allowed), as sl_scan_tiles + the recursive
 * scan of tile totals + sl_scan_add_offsets do it. */
static void scan_row(const float *in, float *out, size_t n, float *scratch) {
    size_t nt = (n + SL_SCAN_TILE - 1) / SL_SCAN_TILE;
    float *sums = scratch, *scanned = scratch + nt;
    float s[SL_SCAN_TILE];
    for (size_t t = 0; t < nt; t++) {
        size_t x0 = t * SL_SCAN_TILE;
        for (sl_uint j = 0; j < SL_SCAN_TILE; j++)
            s[j] = x0 + j < n ? in[x0 + j] : 0.0f;
        float total = sl_scan_tile_serial(s);
        for (sl_uint j = 0; j < SL_SCAN_TILE && x0 + j < n; j++)
            out[x0 + j] = j + 1 < SL_SCAN_TILE ? s[j + 1] : total;
        if (nt > 1) sums[t] = total;
    }
    if (nt > 1) {
        scan_row(sums, scanned, nt, scratch + 2 * nt);
        for (size_t x = SL_SCAN_TILE; x < n; x++)
            out[x] = out[x] + scanned[x / SL_SCAN_TILE - 1];
    }
}

void slc_scan_rows(const float *in, float *out, size_t w, size_t h) {
    size_t ns = scratch_size(w);
    float *scratch = ns ? sl_malloc(ns * sizeof *scratch) : NULL;
    for (size_t y = 0; y < h; y++)
        scan_row(in + y * w, out + y * w, w, scratch);
    free(scratch);
}

/* Columns are scanned CW at a time, each tree step applied to a row of CW floats: the same
 * additions, in the same order per column, as the kernel's transpose + row scan, without the
 * cache-hostile transposes (a 2048 x 2048 image: ~25 ms instead of ~250 ms). */
#define CW 64

/* Inclusive scan down every column of an h x w block with row stride `stride` (in == out
 * allowed); tile totals are scanned recursively the same way. */
static void scan_cols(const float *in, float *out, size_t w, size_t h, size_t stride) {
    const size_t T = SL_SCAN_TILE;
    size_t nt = (h + T - 1) / T;
    float *s = sl_malloc(T * CW * sizeof *s), total[CW];
    float *sums = nt > 1 ? sl_malloc(2 * nt * CW * sizeof *sums) : NULL;
    float *scanned = sums ? sums + nt * CW : NULL;
    for (size_t c0 = 0; c0 < w; c0 += CW) {
        size_t cw = w - c0 < CW ? w - c0 : CW;
        for (size_t t = 0; t < nt; t++) {
            size_t y0 = t * T;
            for (size_t j = 0; j < T; j++)
                for (size_t c = 0; c < cw; c++)
                    s[j * CW + c] = y0 + j < h ? in[(y0 + j) * stride + c0 + c] : 0.0f;
            /* sl_scan_tile_serial on CW columns at once (Blelloch up-sweep, down-sweep). */
            for (sl_uint d = 1; d < T; d <<= 1)
                for (sl_uint k = 0; k < T / (2u * d); k++) {
                    float *r = s + (size_t)sl_scan_node(d, k) * CW, *l = r - (size_t)d * CW;
                    for (size_t c = 0; c < cw; c++)
                        r[c] = l[c] + r[c];
                }
            for (size_t c = 0; c < cw; c++)
                total[c] = s[(T - 1) * CW + c], s[(T - 1) * CW + c] = 0;
            for (sl_uint d = T / 2; d >= 1; d >>= 1)
                for (sl_uint k = 0; k < T / (2u * d); k++) {
                    float *r = s + (size_t)sl_scan_node(d, k) * CW, *l = r - (size_t)d * CW;
                    for (size_t c = 0; c < cw; c++) {
                        float left = l[c];
                        l[c] = r[c];
                        r[c] = r[c] + left;
                    }
                }
            for (size_t j = 0; j < T && y0 + j < h; j++) {
                const float *src = j + 1 < T ? s + (j + 1) * CW : total;
                for (size_t c = 0; c < cw; c++)
                    out[(y0 + j) * stride + c0 + c] = src[c];
            }
            if (sums)
                for (size_t c = 0; c < cw; c++)
                    sums[t * CW + c] = total[c];
        }
        if (sums) {
            scan_cols(sums, scanned, cw, nt, CW);
            for (size_t y = T; y < h; y++) {
                const float *off = scanned + (y / T - 1) * CW;
                float *o = out + y * stride + c0;
                for (size_t c = 0; c < cw; c++)
                    o[c] = o[c] + off[c];
            }
        }
    }
    free(s);
    free(sums);
}

void slc_prefix_sum_2d(const float *in, float *out, size_t w, size_t h) {
    /* Rows, then columns: the kernel's rows, transpose, rows, transpose back. */
    slc_scan_rows(in, out, w, h);
    scan_cols(out, out, w, h, w);
}
