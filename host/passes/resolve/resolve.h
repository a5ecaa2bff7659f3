/* resolve.h: the resolve pass: front-to-back compositing of each pixel's K-buffer entries, each
 * with its shading (sl_shade_entry: the fragment's own point, or the strand vertices around it
 * interpolated), into the beauty and the AOVs of an sl_fbuf. It reads the view pass's K-buffer
 * and the shade pass's points and results; the planner's run is plan/run_resolve.c. */
#ifndef SL_RESOLVE_H
#define SL_RESOLVE_H

#include "io/hair/hair.h"
#include "passes/shade/shade_points.h"

/* Beauty and AOVs of one frame, planar, row 0 top, w * h pixels. */
typedef struct sl_fbuf {
    int width, height;
    float *rgba;    /* 4 per pixel, linear, premultiplied */
    float *depth;   /* view depth of the nearest fragment, +inf where empty */
    float *mode[4]; /* R, TT, TRT, MS: 3 per pixel, premultiplied (they sum to rgb) */
    float *shadow;  /* power-weighted mean transmittance toward the lobes, coverage-weighted */
    float *lobes;   /* lobes evaluated per shading point, coverage-weighted mean */
} sl_fbuf;
void sl_fbuf_free(sl_fbuf *f);

/* Floats per pixel of an sl_fbuf: rgba 4 + depth 1 + 4 modes x 3 + shadow 1 + lobes 1. */
#define SL_FBUF_FLOATS 19

/* Allocates out at kb's size and composites it: K-buffer kb, hair h, shading rate k (0 fragment,
 * else every k-th vertex), the entry -> shading map sm and the shaded points pts. */
void sl_resolve(const sl_kbuf_view *kb, const sl_hair *h, int k, const sl_shade_map *sm,
                const sl_shade_points *pts, sl_fbuf *out);

#endif
