/* voxel.h: hair voxelization for multiple scattering (Ren 2010 Sec. 6), shared by the OpenCL
 * kernels (kernels/voxel.cl) and the C twin (cpu/voxel_c.c). Definitions: docs/volume.md.
 *
 * Grid: n[0] x n[1] x n[2] cubic voxels of edge h from corner lo; voxel (i, j, k) has index
 * (k * n[1] + j) * n[0] + i. Pass 1 (accumulate, one work-item per segment) samples each segment at
 * ns = ceil(4 L / h) equal pieces (midpoints; at most SL_VOX_MAX_SAMPLES) and adds, to the voxel
 * containing each midpoint, the piece's
 *     2 r l,  l,  l t t^T (6 entries)           (l = L / ns, t = unit tangent, r = radius there)
 * as 64-bit fixed point (value * scale rounded to nearest, two's complement: order-independent
 * exact sums with 64-bit atomics). Pass 2 (finalize, one work-item per voxel) turns the sums
 * into the SL_VOX_FIELDS floats of a voxel:
 *     sigma_perp = sum 2 r l / h^3   perpendicular attenuation: expected fibers crossed per unit
 *                                    length by a ray perpendicular to them (numerics.md sec. 7:
 *                                    a fiber adds 2 r l / A of projected area per unit area)
 *     density    = sum l / h^3       fiber length per unit volume
 *     dir        = principal eigenvector of M = sum l t t^T / sum l (the average direction of
 *                                    unsigned tangents; sign: largest component positive)
 *     dev        = sqrt(1 - dir^T M dir), the rms sine of the angle between a fiber and dir
 *                                    (0: all parallel; sqrt(2/3): isotropic)
 * An empty voxel is all zeros. */
#ifndef SL_VOXEL_H
#define SL_VOXEL_H

#include "sl_compat.h"

#define SL_VOX_ACC 8 /* fixed-point sums per voxel */
#define SL_VOX_FIELDS 6
enum { SL_VOX_SIGMA = 0, SL_VOX_DENSITY, SL_VOX_DIRX, SL_VOX_DIRY, SL_VOX_DIRZ, SL_VOX_DEV };
#define SL_VOX_SEG 8 /* segment record: p0 xyz, r0, p1 xyz, r1 */
#define SL_VOX_MAX_SAMPLES 4096
#define SL_VOX_POWER_ITERS 24

/* Number of pieces of a segment of length L in voxels of edge h (at most a quarter voxel). */
SL_INLINE int sl_vox_pieces(float L, float h) {
    float f = ceil(4.0f * L / h);
    if (!(f >= 1.0f)) return 1;
    return f > (float)SL_VOX_MAX_SAMPLES ? SL_VOX_MAX_SAMPLES : (int)f;
}

/* Voxel index of point p, or -1 outside the grid. */
SL_INLINE int sl_vox_index(float px, float py, float pz, int nx, int ny, int nz, float lox,
                           float loy, float loz, float inv_h) {
    float fx = (px - lox) * inv_h, fy = (py - loy) * inv_h, fz = (pz - loz) * inv_h;
    if (!(fx >= 0.0f && fy >= 0.0f && fz >= 0.0f)) return -1;
    if (fx >= (float)nx || fy >= (float)ny || fz >= (float)nz) return -1;
    int i = (int)fx, j = (int)fy, k = (int)fz;
    return (k * ny + j) * nx + i;
}

/* The 8 quantities of piece `s` of segment `seg` (SL_VOX_SEG floats), already multiplied by
 * scale; *vox gets its voxel (-1: outside, or a zero-length segment). */
SL_INLINE void sl_vox_piece(SL_GLOBAL const float *seg, int s, int ns, int nx, int ny, int nz,
                            float lox, float loy, float loz, float h, float scale, int *vox,
                            float q[SL_VOX_ACC]) {
    float dx = seg[4] - seg[0], dy = seg[5] - seg[1], dz = seg[6] - seg[2];
    float L = sqrt(dx * dx + dy * dy + dz * dz);
    *vox = -1;
    if (!(L > 0.0f)) return;
    float f = ((float)s + 0.5f) / (float)ns;
    float px = seg[0] + f * dx, py = seg[1] + f * dy, pz = seg[2] + f * dz;
    *vox = sl_vox_index(px, py, pz, nx, ny, nz, lox, loy, loz, 1.0f / h);
    float tx = dx / L, ty = dy / L, tz = dz / L;
    float l = L / (float)ns, r = seg[3] + f * (seg[7] - seg[3]);
    float ls = l * scale;
    q[0] = 2.0f * r * ls;
    q[1] = ls;
    q[2] = ls * tx * tx;
    q[3] = ls * ty * ty;
    q[4] = ls * tz * tz;
    q[5] = ls * tx * ty;
    q[6] = ls * tx * tz;
    q[7] = ls * ty * tz;
}

/* M v for the symmetric matrix m = (xx, yy, zz, xy, xz, yz). */
SL_INLINE void sl_vox_mulv(const float *m, const float *v, float *o) {
    o[0] = m[0] * v[0] + m[3] * v[1] + m[4] * v[2];
    o[1] = m[3] * v[0] + m[1] * v[1] + m[5] * v[2];
    o[2] = m[4] * v[0] + m[5] * v[1] + m[2] * v[2];
}

/* Finalizes one voxel from its sums (already divided by scale: s[0] = sum 2 r l, s[1] = sum l,
 * s[2..7] = sum l t t^T) into out[SL_VOX_FIELDS]. Power iteration for the principal axis, started
 * from the axis with the largest diagonal entry (M is positive semi-definite with trace 1). */
SL_INLINE void sl_vox_finalize(const float *s, float h, float *out) {
    for (int k = 0; k < SL_VOX_FIELDS; k++)
        out[k] = 0.0f;
    if (!(s[1] > 0.0f)) return;
    float inv_v = 1.0f / (h * h * h);
    out[SL_VOX_SIGMA] = s[0] * inv_v;
    out[SL_VOX_DENSITY] = s[1] * inv_v;
    float m[6];
    for (int k = 0; k < 6; k++)
        m[k] = s[2 + k] / s[1];
    float v[3] = {0.0f, 0.0f, 0.0f};
    int a = m[1] > m[0] ? 1 : 0;
    if (m[2] > m[a]) a = 2;
    v[a] = 1.0f;
    for (int it = 0; it < SL_VOX_POWER_ITERS; it++) {
        float w[3];
        sl_vox_mulv(m, v, w);
        float n = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        if (!(n > 0.0f)) break;
        v[0] = w[0] / n;
        v[1] = w[1] / n;
        v[2] = w[2] / n;
    }
    int b = fabs(v[1]) > fabs(v[0]) ? 1 : 0;
    if (fabs(v[2]) > fabs(v[b])) b = 2;
    float sg = v[b] < 0.0f ? -1.0f : 1.0f;
    float w[3];
    sl_vox_mulv(m, v, w);
    float lam = v[0] * w[0] + v[1] * w[1] + v[2] * w[2];
    out[SL_VOX_DIRX] = sg * v[0];
    out[SL_VOX_DIRY] = sg * v[1];
    out[SL_VOX_DIRZ] = sg * v[2];
    out[SL_VOX_DEV] = sqrt(sl_clampf(1.0f - lam, 0.0f, 1.0f));
}

/* Ratio alpha of the attenuation of a ray along unit w to sigma_perp (Ren's alpha(v, theta)):
 * the rms sine between w and the voxel's fibers for an axially symmetric spread of rms sine dev
 * around dir: E[(w.t)^2] = (1 - dev^2) c^2 + dev^2 (1 - c^2) / 2, c = w.dir; alpha =
 * sqrt(1 - E[(w.t)^2]). Exact for parallel fibers (|sin|); sqrt(2/3) for an isotropic cloud
 * where E|sin| = pi/4 (+3.9 %, docs/volume.md). */
SL_INLINE float sl_vox_alpha(SL_GLOBAL const float *vox, float wx, float wy, float wz) {
    float c = wx * vox[SL_VOX_DIRX] + wy * vox[SL_VOX_DIRY] + wz * vox[SL_VOX_DIRZ];
    float d2 = vox[SL_VOX_DEV] * vox[SL_VOX_DEV];
    float e = (1.0f - d2) * c * c + 0.5f * d2 * (1.0f - c * c);
    return sqrt(sl_clampf(1.0f - e, 0.0f, 1.0f));
}

#endif
