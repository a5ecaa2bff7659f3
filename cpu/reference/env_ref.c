/* env_ref.c: see env_ref.h. */
#include "env_ref.h"

#include "io/envmap/envmap.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

static double lum(const float *p) {
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

void slref_env_build(slref_env *env, const float *rgb, int w, int h, double rotation_deg,
                     double intensity) {
    memset(env, 0, sizeof *env);
    env->w = w, env->h = h, env->rgb = rgb, env->intensity = intensity;
    double r = rotation_deg * PI / 180.0;
    env->c = cos(r), env->s = sin(r);
    env->row_cdf = sl_malloc((size_t)(h + 1) * sizeof(double));
    env->col_cdf = sl_malloc((size_t)h * (w + 1) * sizeof(double));
    env->row_cdf[0] = 0;
    for (int y = 0; y < h; y++) {
        double om = sl_envmap_pixel_solid_angle(w, h, y), *cc = env->col_cdf + (size_t)y * (w + 1);
        cc[0] = 0;
        for (int x = 0; x < w; x++)
            cc[x + 1] = cc[x] + lum(rgb + 3 * ((size_t)y * w + x)) * om;
        env->row_cdf[y + 1] = env->row_cdf[y] + cc[w];
    }
    env->total = env->row_cdf[h];
}

void slref_env_free(slref_env *env) {
    free(env->row_cdf);
    free(env->col_cdf);
    memset(env, 0, sizeof *env);
}

/* The map pixel a world direction falls in (the inverse rotation, then envmap.h's mapping). */
static void pixel_of(const slref_env *env, const double d[3], int *px, int *py) {
    /* world = R map with R (x, z) = (c x + s z, -s x + c z): map = R^T world */
    double m[3] = {env->c * d[0] - env->s * d[2], d[1], env->s * d[0] + env->c * d[2]};
    double x, y;
    sl_envmap_dir_to_pixel(env->w, env->h, m, &x, &y);
    int ix = (int)floor(x + 0.5), iy = (int)floor(y + 0.5);
    ix = ((ix % env->w) + env->w) % env->w;
    *px = ix, *py = iy < 0 ? 0 : (iy >= env->h ? env->h - 1 : iy);
}

void slref_env_radiance(const slref_env *env, const double dir[3], double rgb[3]) {
    int x, y;
    pixel_of(env, dir, &x, &y);
    const float *p = env->rgb + 3 * ((size_t)y * env->w + x);
    for (int k = 0; k < 3; k++)
        rgb[k] = p[k] * env->intensity;
}

double slref_env_pdf(const slref_env *env, const double dir[3]) {
    if (!(env->total > 0)) return 0;
    int x, y;
    pixel_of(env, dir, &x, &y);
    const double *cc = env->col_cdf + (size_t)y * (env->w + 1);
    return (cc[x + 1] - cc[x]) / env->total / sl_envmap_pixel_solid_angle(env->w, env->h, y);
}

/* The interval i of a non-decreasing cdf[0..n] with cdf[i] <= t < cdf[i + 1] (never an empty
 * one: t < cdf[n] is assumed, and equal neighbours are skipped by taking the last i). */
static int find(const double *cdf, int n, double t) {
    int lo = 0, hi = n; /* cdf[lo] <= t < cdf[hi] */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (cdf[mid] <= t)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

double slref_env_sample(const slref_env *env, const double u[4], double dir[3], double rgb[3]) {
    dir[0] = dir[1] = dir[2] = rgb[0] = rgb[1] = rgb[2] = 0;
    if (!(env->total > 0)) return 0;
    int w = env->w, h = env->h;
    int y = find(env->row_cdf, h, u[0] * env->total);
    const double *cc = env->col_cdf + (size_t)y * (w + 1);
    int x = find(cc, w, u[1] * cc[w]);
    /* uniform in solid angle inside the pixel: phi and cos theta uniform over its cell */
    double c0 = cos(PI * y / h), c1 = cos(PI * (y + 1) / h);
    double ct = c0 - u[2] * (c0 - c1), st = sqrt(fmax(0.0, 1.0 - ct * ct));
    double ph = 2.0 * PI * (x + u[3]) / w - PI;
    double m[3] = {st * sin(ph), ct, -st * cos(ph)};
    dir[0] = env->c * m[0] + env->s * m[2];
    dir[1] = m[1];
    dir[2] = -env->s * m[0] + env->c * m[2];
    const float *p = env->rgb + 3 * ((size_t)y * w + x);
    for (int k = 0; k < 3; k++)
        rgb[k] = p[k] * env->intensity;
    return (cc[x + 1] - cc[x]) / env->total / sl_envmap_pixel_solid_angle(w, h, y);
}
