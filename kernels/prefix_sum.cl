/* prefix_sum.cl: inclusive row and column scans and a transpose, from which host/passes/light/prefix_sum_cl.c
 * builds the 2-D inclusive prefix sum (summed-area table) in two variants: work-group tile scans
 * of rows with transposes for the columns (GPUs), or one work-item per tile running the tile's
 * tree serially, rows then columns in place (CPU devices). The C twin is cpu/prefix_sum.c; the scan
 * steps come from prefix_sum.h so both add in the same order. */
#include "prefix_sum.h"

/* One work-group scans one tile of SL_SCAN_TILE elements of one row (global size
 * (ntiles * SL_SCAN_WG, rows)): out gets the inclusive scan within the tile, tile_sums[row *
 * ntiles + tile] the tile total. Elements past the row end count as 0. */
__kernel __attribute__((reqd_work_group_size(SL_SCAN_WG, 1, 1))) void
sl_scan_tiles(__global const float *in, __global float *out, __global float *tile_sums, uint width,
              uint ntiles) {
    __local float s[SL_SCAN_TILE];
    const uint lid = (uint)get_local_id(0);
    const uint tile = (uint)get_group_id(0);
    const size_t row = get_global_id(1);
    const size_t base = row * width;
    const uint x0 = tile * SL_SCAN_TILE;
    for (uint j = lid; j < SL_SCAN_TILE; j += SL_SCAN_WG)
        s[j] = x0 + j < width ? in[base + x0 + j] : 0.0f;
    barrier(CLK_LOCAL_MEM_FENCE);
    /* Up-sweep (Blelloch 1990): strides 1, 2, ..., TILE/2. */
    for (uint d = 1u; d < SL_SCAN_TILE; d <<= 1) {
        if (lid < SL_SCAN_TILE / (2u * d)) SL_SCAN_UP_STEP(s, d, lid);
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    const float total = s[SL_SCAN_TILE - 1u];
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid == 0u) s[SL_SCAN_TILE - 1u] = 0.0f;
    barrier(CLK_LOCAL_MEM_FENCE);
    /* Down-sweep: strides TILE/2, ..., 1. */
    for (uint d = SL_SCAN_TILE / 2u; d >= 1u; d >>= 1) {
        if (lid < SL_SCAN_TILE / (2u * d)) SL_SCAN_DOWN_STEP(s, d, lid);
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    /* Inclusive value j = exclusive value j+1; the last one is the total. */
    for (uint j = lid; j < SL_SCAN_TILE; j += SL_SCAN_WG)
        if (x0 + j < width) out[base + x0 + j] = j + 1u < SL_SCAN_TILE ? s[j + 1u] : total;
    if (lid == 0u) tile_sums[row * ntiles + tile] = total;
}

/* The same as sl_scan_tiles with one work-item per (tile, row) running the tile's tree serially
 * in private memory (sl_scan_tile_serial, also the C twin's code): no barriers, which suits CPU
 * devices (PoCL) and narrow rows. Global size (ntiles, >= rows), any local size. */
__kernel void sl_scan_tiles_serial(__global const float *in, __global float *out,
                                   __global float *tile_sums, uint width, uint ntiles,
                                   uint height) {
    const uint tile = (uint)get_global_id(0);
    const size_t row = get_global_id(1);
    if (tile >= ntiles || row >= height) return;
    const size_t base = row * width;
    const uint x0 = tile * SL_SCAN_TILE;
    float s[SL_SCAN_TILE];
    for (uint j = 0u; j < SL_SCAN_TILE; j++)
        s[j] = x0 + j < width ? in[base + x0 + j] : 0.0f;
    const float total = sl_scan_tile_serial(s);
    for (uint j = 0u; j < SL_SCAN_TILE && x0 + j < width; j++)
        out[base + x0 + j] = j + 1u < SL_SCAN_TILE ? s[j + 1u] : total;
    tile_sums[row * ntiles + tile] = total;
}

/* Column version of sl_scan_tiles_serial for the barrier-free variant (no transposes): work-item
 * (x, tile) scans rows tile*TILE.. of column x of a height x width image. tile_sums is ntiles
 * rows of width (so the totals are scanned by this same kernel, recursively). Neighbouring
 * work-items touch neighbouring addresses. Global size (>= width, ntiles). */
__kernel void sl_scan_col_tiles_serial(__global const float *in, __global float *out,
                                       __global float *tile_sums, uint width, uint height) {
    const size_t x = get_global_id(0);
    const uint tile = (uint)get_global_id(1);
    const uint y0 = tile * SL_SCAN_TILE;
    if (x >= width) return;
    float s[SL_SCAN_TILE];
    for (uint j = 0u; j < SL_SCAN_TILE; j++)
        s[j] = y0 + j < height ? in[(size_t)(y0 + j) * width + x] : 0.0f;
    const float total = sl_scan_tile_serial(s);
    for (uint j = 0u; j < SL_SCAN_TILE && y0 + j < height; j++)
        out[(size_t)(y0 + j) * width + x] = j + 1u < SL_SCAN_TILE ? s[j + 1u] : total;
    tile_sums[(size_t)tile * width + x] = total;
}

/* Column version of sl_scan_add_offsets (global size (>= width, height)). */
__kernel void sl_scan_col_add_offsets(__global float *out, __global const float *scanned_sums,
                                      uint width) {
    const size_t x = get_global_id(0);
    const uint y = (uint)get_global_id(1);
    if (x >= width) return;
    const uint tile = y / SL_SCAN_TILE;
    if (tile == 0u) return;
    const size_t i = (size_t)y * width + x;
    out[i] = out[i] + scanned_sums[(size_t)(tile - 1u) * width + x];
}

/* Adds the inclusive scan of the previous tiles' totals to every element of tiles 1.. of each
 * row (global size (>= width, rows)). */
__kernel void sl_scan_add_offsets(__global float *out, __global const float *scanned_sums,
                                  uint width, uint ntiles) {
    const uint x = (uint)get_global_id(0);
    const size_t row = get_global_id(1);
    if (x >= width) return;
    const uint tile = x / SL_SCAN_TILE;
    if (tile == 0u) return;
    const size_t i = row * width + x;
    out[i] = out[i] + scanned_sums[row * ntiles + (tile - 1u)];
}

/* out (width rows of height) = transpose of in (height rows of width), through local memory in
 * SL_TRANSPOSE_TILE^2 blocks (padded by one column against bank conflicts). Global size: width
 * and height rounded up to the tile. */
__kernel __attribute__((reqd_work_group_size(SL_TRANSPOSE_TILE, SL_TRANSPOSE_TILE, 1))) void
sl_transpose(__global const float *in, __global float *out, uint width, uint height) {
    __local float t[SL_TRANSPOSE_TILE][SL_TRANSPOSE_TILE + 1u];
    const uint lx = (uint)get_local_id(0), ly = (uint)get_local_id(1);
    const uint bx = (uint)get_group_id(0) * SL_TRANSPOSE_TILE;
    const uint by = (uint)get_group_id(1) * SL_TRANSPOSE_TILE;
    if (bx + lx < width && by + ly < height) t[ly][lx] = in[(size_t)(by + ly) * width + bx + lx];
    barrier(CLK_LOCAL_MEM_FENCE);
    /* Write row (bx + ly) of out, columns by + lx: consecutive work-items write consecutive
     * addresses. */
    if (by + lx < height && bx + ly < width) out[(size_t)(bx + ly) * height + by + lx] = t[lx][ly];
}
