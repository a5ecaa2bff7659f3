/* env_ref.h: the environment map as the path tracer's light (docs/reference.md, "Path tracer"):
 * radiance by direction at the map's full resolution (each pixel a constant over its lat-long
 * cell, numerics.md sec. 4's directions, host/io/envmap/envmap.h), rotated about +Y by
 * environment.rotation_deg and scaled by environment.intensity as sl_lobes_transform does, and
 * importance sampling by a 2-D CDF over the pixels (rows by their sums, then a pixel within the
 * row) of weight luminance x solid angle, the solid angle of a row being proportional to
 * sin theta at its centre. Inside the pixel the direction is uniform in solid angle (phi and
 * cos theta uniform), so the density is exactly weight / total / pixel solid angle. */
#ifndef SL_ENV_REF_H
#define SL_ENV_REF_H

#include "base/common.h"

typedef struct slref_env {
    int w, h;
    const float *rgb; /* w * h * 3, row 0 at the top (not owned: the caller's map) */
    double c, s;      /* cos, sin of the rotation about +Y */
    double intensity; /* environment.intensity */
    double *row_cdf;  /* h + 1: cumulative row weights, row_cdf[h] = total */
    double *col_cdf;  /* h * (w + 1): cumulative pixel weights within each row */
    double total;     /* sum of the weights; 0: a black map, nothing to sample */
} slref_env;

/* Builds the tables of a w x h map (>= 1 x 1). rgb must outlive env. */
void slref_env_build(slref_env *env, const float *rgb, int w, int h, double rotation_deg,
                     double intensity);
void slref_env_free(slref_env *env);

/* Radiance arriving from the world direction dir (unit; toward the light), x intensity. */
void slref_env_radiance(const slref_env *env, const double dir[3], double rgb[3]);

/* The density (per solid angle) of slref_env_sample at dir (0 on black pixels). */
double slref_env_pdf(const slref_env *env, const double dir[3]);

/* Draws a world direction from four uniforms; returns its density (0 when the map is black:
 * then dir and rgb are zeros) and its radiance in rgb. */
double slref_env_sample(const slref_env *env, const double u[4], double dir[3], double rgb[3]);

#endif
