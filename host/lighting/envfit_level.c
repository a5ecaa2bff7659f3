/* envfit_level.c: the solid-angle-weighted pyramid, lobe supports on the lat-long grid, the
 * block fan-out (over base/parallel.h) and the tangent basis used by the fitter
 * (envfit_internal.h). */
#include "lighting/envfit_internal.h"

#include "base/parallel.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void efl_level_geometry(efl_level *lv, int w, int h) {
    lv->w = w;
    lv->h = h;
    lv->om = sl_malloc(sizeof(double) * (size_t)h);
    lv->ct = sl_malloc(sizeof(double) * (size_t)h);
    lv->st = sl_malloc(sizeof(double) * (size_t)h);
    lv->cp = sl_malloc(sizeof(double) * (size_t)w);
    lv->sp = sl_malloc(sizeof(double) * (size_t)w);
    for (int y = 0; y < h; y++) {
        double th = M_PI * (y + 0.5) / h;
        lv->ct[y] = cos(th);
        lv->st[y] = sin(th);
        /* Exact solid angle of the row's pixels: (2 pi / w) (cos th_top - cos th_bottom); the
         * rows sum to exactly 4 pi. */
        lv->om[y] = 2.0 * M_PI / w * (cos(M_PI * y / h) - cos(M_PI * (y + 1) / h));
    }
    for (int x = 0; x < w; x++) {
        double ph = 2.0 * M_PI * (x + 0.5) / w - M_PI;
        lv->cp[x] = cos(ph);
        lv->sp[x] = sin(ph);
    }
}

void efl_pixel_dir(const efl_level *lv, int x, int y, double d[3]) {
    d[0] = lv->st[y] * lv->sp[x];
    d[1] = lv->ct[y];
    d[2] = -lv->st[y] * lv->cp[x];
}

static void level_energy(efl_level *lv) {
    double e = 0;
    for (int y = 0; y < lv->h; y++) {
        double row = 0;
        const float *p = lv->rgb + (size_t)y * lv->w * 3;
        for (int i = 0; i < lv->w * 3; i++)
            row += (double)p[i] * p[i];
        e += row * lv->om[y];
    }
    lv->energy = e;
}

void efl_level_free(efl_level *lv) {
    if (!lv) return;
    free(lv->rgb);
    free(lv->om);
    free(lv->ct);
    free(lv->st);
    free(lv->cp);
    free(lv->sp);
    memset(lv, 0, sizeof *lv);
}

int efl_pyramid(const sl_envmap *map, int min_h, efl_level **levels) {
    int cap = 1, w = map->width, h = map->height;
    while (h > min_h && w >= 4) {
        w = (w + 1) / 2;
        h = (h + 1) / 2;
        cap++;
    }
    efl_level *L = sl_calloc((size_t)cap, sizeof *L);
    efl_level_geometry(&L[0], map->width, map->height);
    size_t np = (size_t)map->width * map->height * 3;
    L[0].rgb = sl_malloc(np * sizeof(float));
    memcpy(L[0].rgb, map->rgb, np * sizeof(float));
    level_energy(&L[0]);
    for (int k = 1; k < cap; k++) {
        const efl_level *f = &L[k - 1];
        efl_level *c = &L[k];
        efl_level_geometry(c, (f->w + 1) / 2, (f->h + 1) / 2);
        double *acc = sl_calloc((size_t)c->w * c->h * 4, sizeof(double));
        for (int y = 0; y < f->h; y++) {
            int cy = (int)((long)y * c->h / f->h);
            for (int x = 0; x < f->w; x++) {
                int cx = (int)((long)x * c->w / f->w);
                double *a = acc + ((size_t)cy * c->w + cx) * 4;
                const float *p = f->rgb + ((size_t)y * f->w + x) * 3;
                a[0] += f->om[y] * p[0];
                a[1] += f->om[y] * p[1];
                a[2] += f->om[y] * p[2];
                a[3] += f->om[y];
            }
        }
        c->rgb = sl_malloc((size_t)c->w * c->h * 3 * sizeof(float));
        for (size_t i = 0; i < (size_t)c->w * c->h; i++)
            for (int ch = 0; ch < 3; ch++)
                c->rgb[i * 3 + ch] =
                    (float)(acc[i * 4 + 3] > 0 ? acc[i * 4 + ch] / acc[i * 4 + 3] : 0);
        free(acc);
        level_energy(c);
    }
    *levels = L;
    return cap;
}

/* The fitter's block callbacks take one block at a time; its sums are per block and reduced in
 * block order by the callers, so any worker may take any block. */
typedef struct par_blocks {
    void (*fn)(void *, int);
    void *ctx;
} par_blocks;

static void par_run(void *arg, size_t begin, size_t end, int worker) {
    (void)worker;
    const par_blocks *pb = arg;
    for (size_t b = begin; b < end; b++)
        pb->fn(pb->ctx, (int)b);
}

void efl_parallel(int threads, int nblocks, void (*fn)(void *ctx, int block), void *ctx) {
    if (nblocks <= 0) return;
    if (threads > 16) threads = 16;
    par_blocks pb = {fn, ctx};
    sl_parallel_for(threads, (size_t)nblocks, 1, par_run, &pb);
}

void efl_row_span(const efl_level *lv, int y, const double mu[3], double a, double cut, int *x0,
                  int *nx) {
    int w = lv->w;
    double dmin = 1.0 - cut / a; /* G >= exp(-cut)  <=>  omega . mu >= dmin */
    double cth = mu[1];
    double sth = sqrt(fmax(0.0, mu[0] * mu[0] + mu[2] * mu[2]));
    double hi = lv->ct[y] * cth + lv->st[y] * sth, lo = lv->ct[y] * cth - lv->st[y] * sth;
    *x0 = 0;
    *nx = 0;
    if (hi < dmin) return;
    if (lo >= dmin || sth * lv->st[y] < 1e-300) {
        *nx = w;
        return;
    }
    double q = (dmin - lv->ct[y] * cth) / (lv->st[y] * sth);
    double dph = q <= -1 ? M_PI : acos(fmin(1.0, q));
    double phm = atan2(mu[0], -mu[2]);
    double xc = (phm + M_PI) * w / (2 * M_PI) - 0.5, half = dph * w / (2 * M_PI);
    long a0 = (long)ceil(xc - half), a1 = (long)floor(xc + half);
    if (a1 < a0) {
        /* The span lies between two pixel centres: the nearest pixel is still worth a look
         * (cheap, and it keeps very narrow lobes visible to the gradient). */
        a0 = a1 = (long)floor(xc + 0.5);
    }
    if (a1 - a0 + 1 >= w) {
        *nx = w;
        return;
    }
    long m = a0 % w;
    if (m < 0) m += w;
    *x0 = (int)m;
    *nx = (int)(a1 - a0 + 1);
}

void efl_tangent(const double mu[3], double t1[3], double t2[3]) {
    /* t1 = normalize(up x mu) with up = +Y unless mu is close to +-Y, then +X. */
    double up[3] = {0, 1, 0};
    if (fabs(mu[1]) > 0.9) {
        up[0] = 1;
        up[1] = 0;
    }
    t1[0] = up[1] * mu[2] - up[2] * mu[1];
    t1[1] = up[2] * mu[0] - up[0] * mu[2];
    t1[2] = up[0] * mu[1] - up[1] * mu[0];
    double n = sqrt(t1[0] * t1[0] + t1[1] * t1[1] + t1[2] * t1[2]);
    for (int k = 0; k < 3; k++)
        t1[k] /= n;
    t2[0] = mu[1] * t1[2] - mu[2] * t1[1];
    t2[1] = mu[2] * t1[0] - mu[0] * t1[2];
    t2[2] = mu[0] * t1[1] - mu[1] * t1[0];
}
