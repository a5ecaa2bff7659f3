/* envfit_sun.c: suns get lobes of their own.
 *
 * In the L2 norm of the radiance a sun thousands of times brighter than the sky outweighs the
 * whole sky: fitted jointly, broad sky lobes bend to absorb the sun's residual (measured on
 * blender_exr/sunrise.exr: a sky lobe of 3x the map's total power, convolved error 0.60). So a
 * compact, very bright region is split off first: its pixels above the surrounding sky level
 * (the mean of a ring around it) form a sun image, fitted by one narrow lobe with the pixel model
 * of envfit_eval.c, its rgb then set to the sun's exact power; the sky image (the sun's
 * pixels set to the ring level) is fitted by the other lobes. Sun + sky = the map.
 * A sun: connected pixels of luminance > EFL_SUN_RATIO x the map's mean (solid-angle weighted)
 * luminance, within EFL_SUN_MAX_SR steradians, carrying >= EFL_SUN_MIN_SHARE of the power. */
#include "lighting/envfit_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define EFL_SUN_RATIO 100.0
#define EFL_SUN_MAX_SR 0.005
#define EFL_SUN_MIN_SHARE 0.02

static double lum3(const float *p) {
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

int efl_split_suns(const sl_envmap *map, int max_suns, double lam_min, double lam_max, int threads,
                   float *sky, sl_lobe *suns) {
    int w = map->width, h = map->height, ns = 0;
    size_t np = (size_t)w * h;
    memcpy(sky, map->rgb, sizeof(float) * 3 * np);
    if (max_suns < 1 || h < 8) return 0;
    efl_level lv = {0};
    efl_level_geometry(&lv, w, h);
    double total = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            total += lv.om[y] * lum3(map->rgb + ((size_t)y * w + x) * 3);
    double thr = EFL_SUN_RATIO * total / (4 * M_PI);
    unsigned char *mask = sl_calloc(np, 1); /* 1: in a sun, 2: in the current one */
    int *stack = sl_malloc(sizeof(int) * np);
    float *sunimg = sl_calloc(3 * np, sizeof(float));
    double *res = sl_malloc(sizeof(double) * 3 * np);
    while (total > 0 && ns < max_suns) {
        long best = -1;
        double by = thr;
        for (size_t i = 0; i < np; i++) {
            double Y = lum3(sky + 3 * i);
            if (!mask[i] && Y > by) {
                by = Y;
                best = (long)i;
            }
        }
        if (best < 0) break;
        /* Flood fill (4-neighbours, wrapping in x) over pixels above the threshold. */
        int top = 0, count = 0;
        double sr = 0;
        stack[top++] = (int)best;
        mask[best] = 2;
        int *members = sl_malloc(sizeof(int) * np);
        while (top) {
            int i = stack[--top], x = i % w, y = i / w;
            members[count++] = i;
            sr += lv.om[y];
            int nb[4] = {y * w + (x + 1) % w, y * w + (x + w - 1) % w, y > 0 ? i - w : -1,
                         y < h - 1 ? i + w : -1};
            for (int k = 0; k < 4; k++)
                if (nb[k] >= 0 && !mask[nb[k]] && lum3(sky + 3 * (size_t)nb[k]) > thr) {
                    mask[nb[k]] = 2;
                    stack[top++] = nb[k];
                }
        }
        /* Ring: pixels within 2 of the region and outside every sun. */
        double ring[3] = {0, 0, 0}, rw = 0;
        for (int m = 0; m < count; m++) {
            int x = members[m] % w, y = members[m] / w;
            for (int dy = -2; dy <= 2; dy++)
                for (int dx = -2; dx <= 2; dx++) {
                    int yy = y + dy, xx = (x + dx + w) % w;
                    if (yy < 0 || yy >= h) continue;
                    size_t j = (size_t)yy * w + xx;
                    if (mask[j]) continue;
                    for (int c = 0; c < 3; c++)
                        ring[c] += lv.om[yy] * sky[3 * j + c];
                    rw += lv.om[yy];
                }
        }
        for (int c = 0; c < 3; c++)
            ring[c] = rw > 0 ? ring[c] / rw : 0;
        double power = 0;
        for (int m = 0; m < count; m++) {
            const float *p = sky + 3 * (size_t)members[m];
            for (int c = 0; c < 3; c++) {
                double v = p[c] - ring[c];
                power += (v > 0 ? v : 0) * lv.om[members[m] / w] *
                         (c == 1   ? 0.7152
                          : c == 0 ? 0.2126
                                   : 0.0722);
            }
        }
        int ok = sr <= EFL_SUN_MAX_SR && power >= EFL_SUN_MIN_SHARE * total;
        for (int m = 0; m < count; m++)
            mask[members[m]] = ok ? 1 : 3; /* 3: bright, not a sun */
        if (!ok) {
            free(members);
            continue;
        }
        /* Sun image (alone) and the sky with the sun's pixels at the ring level. */
        memset(sunimg, 0, sizeof(float) * 3 * np);
        double cen[3] = {0, 0, 0}, P[3] = {0, 0, 0};
        for (int m = 0; m < count; m++) {
            size_t i = (size_t)members[m];
            int x = members[m] % w, y = members[m] / w;
            double d[3], wl = 0;
            efl_pixel_dir(&lv, x, y, d);
            for (int c = 0; c < 3; c++) {
                double v = sky[3 * i + c] - ring[c];
                v = v > 0 ? v : 0;
                sunimg[3 * i + c] = (float)v;
                P[c] += v * lv.om[y];
                wl += v;
                sky[3 * i + c] = (float)(sky[3 * i + c] - v);
            }
            for (int k = 0; k < 3; k++)
                cen[k] += wl * lv.om[y] * d[k];
        }
        free(members);
        double nc = sqrt(cen[0] * cen[0] + cen[1] * cen[1] + cen[2] * cen[2]);
        sl_lobe *S = &suns[ns];
        for (int k = 0; k < 3; k++)
            S->dir[k] = cen[k] / nc;
        S->lambda = fmin(lam_max, fmax(lam_min, sqrt(sr / M_PI)));
        for (int c = 0; c < 3; c++)
            S->rgb[c] = P[c] / sl_lobe_integral(S->lambda);
        /* Refine direction, width and colour on the sun image alone. */
        lv.rgb = sunimg;
        efl_eval ev = {&lv, threads, EFL_CUT, res, NULL};
        efl_lm_opts o = {80, 1e-9, lam_min, lam_max};
        efl_lm(&ev, S, 1, &o, NULL, NULL, 0, 0);
        lv.rgb = NULL;
        /* The least-squares fit of a disc by a Gaussian does not keep its power (a sun disc
         * of 2 deg radius: +13 %), and a fiber, far broader than the sun, sees only the power:
         * the refined direction and width keep the sun image's exact power. */
        for (int c = 0; c < 3; c++)
            S->rgb[c] = P[c] / sl_lobe_integral(S->lambda);
        ns++;
    }
    free(mask);
    free(stack);
    free(sunimg);
    free(res);
    efl_level_free(&lv);
    return ns;
}
