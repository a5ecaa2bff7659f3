/* prefix_sum.h: constants and the scan steps shared by kernels/prefix_sum.cl and its C twin
 * cpu/prefix_sum.c, so both add the same numbers in the same order (bit-identical results).
 *
 * The 2-D inclusive prefix sum (summed-area table, Crow 1984) is done as: scan every row,
 * transpose, scan every row again, transpose back. A row is scanned in tiles of SL_SCAN_TILE
 * elements with Blelloch's work-efficient exclusive scan (Blelloch 1990, "Prefix sums and their
 * applications": up-sweep/reduce then down-sweep), the tile totals of a row are scanned the same
 * way (recursively) and added back to the tiles after the first. */
#ifndef SL_PREFIX_SUM_H
#define SL_PREFIX_SUM_H

#include "sl_compat.h"

#define SL_SCAN_TILE 256u    /* elements per tile (a power of two) */
#define SL_SCAN_LOG2_TILE 8u /* log2(SL_SCAN_TILE) */
#define SL_SCAN_WG 128u      /* work-items per tile: each handles two elements */
#define SL_TRANSPOSE_TILE 16u

/* Number of tiles covering n elements. */
SL_INLINE sl_uint sl_scan_num_tiles(sl_uint n) {
    return (n + SL_SCAN_TILE - 1u) / SL_SCAN_TILE;
}

/* The tree node that pair k updates at stride d (both sweeps): i = (k+1)*2d - 1. */
SL_INLINE sl_uint sl_scan_node(sl_uint d, sl_uint k) {
    return (k + 1u) * 2u * d - 1u;
}

/* The two scan steps are macros so they work on local memory (the work-group kernel) and on
 * private memory (C, the serial kernel) alike: OpenCL 1.2 has no generic address space.
 *
 * Up-sweep step at stride d for pair k (k < SL_SCAN_TILE / (2d)): the node ending at
 * i = (k+1)*2d - 1 becomes the sum of its two children. After the strides 1, 2, ...,
 * SL_SCAN_TILE/2, s[SL_SCAN_TILE-1] holds the tile total. */
#define SL_SCAN_UP_STEP(s, d, k)                                                                   \
    do {                                                                                           \
        const sl_uint i_ = sl_scan_node((d), (k));                                                 \
        (s)[i_] = (s)[i_ - (d)] + (s)[i_];                                                         \
    } while (0)

/* Down-sweep step at stride d for pair k (strides SL_SCAN_TILE/2, ..., 1 after the root was set
 * to 0): the left child gets the parent's prefix, the right child parent prefix + left sum.
 * At the end s[j] holds the exclusive prefix sum of elements 0..j-1. */
#define SL_SCAN_DOWN_STEP(s, d, k)                                                                 \
    do {                                                                                           \
        const sl_uint i_ = sl_scan_node((d), (k));                                                 \
        const float left_ = (s)[i_ - (d)];                                                         \
        (s)[i_ - (d)] = (s)[i_];                                                                   \
        (s)[i_] = (s)[i_] + left_;                                                                 \
    } while (0)

/* The whole tile scan of sl_scan_tiles run by one thread on s[SL_SCAN_TILE] (private memory in
 * OpenCL): afterwards s[j] is the exclusive prefix of elements 0..j-1; returns the tile total.
 * Used by the C twin and by the barrier-free kernel variant (same additions, same order). */
SL_INLINE float sl_scan_tile_serial(float *s) {
    for (sl_uint d = 1u; d < SL_SCAN_TILE; d <<= 1)
        for (sl_uint k = 0u; k < SL_SCAN_TILE / (2u * d); k++)
            SL_SCAN_UP_STEP(s, d, k);
    float total = s[SL_SCAN_TILE - 1u];
    s[SL_SCAN_TILE - 1u] = 0.0f;
    for (sl_uint d = SL_SCAN_TILE / 2u; d >= 1u; d >>= 1)
        for (sl_uint k = 0u; k < SL_SCAN_TILE / (2u * d); k++)
            SL_SCAN_DOWN_STEP(s, d, k);
    return total;
}

/* Sum of a[y][x] over x0 <= x <= x1, y0 <= y <= y1 from an inclusive summed-area table of width
 * w (Crow 1984): S(x1,y1) - S(x0-1,y1) - S(x1,y0-1) + S(x0-1,y0-1), missing terms are 0. */
SL_INLINE float sl_sat_box_sum(SL_GLOBAL const float *sat, sl_uint w, sl_uint x0, sl_uint y0,
                               sl_uint x1, sl_uint y1) {
    float s = sat[(sl_ulong)y1 * w + x1];
    if (x0 > 0u) s -= sat[(sl_ulong)y1 * w + (x0 - 1u)];
    if (y0 > 0u) s -= sat[(sl_ulong)(y0 - 1u) * w + x1];
    if (x0 > 0u && y0 > 0u) s += sat[(sl_ulong)(y0 - 1u) * w + (x0 - 1u)];
    return s;
}

#endif
