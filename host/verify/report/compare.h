/* compare.h: one image of ours against an outside reference (Blender Cycles, docs/validation.md):
 * mean colour per channel and relative RMSE per pixel and on K x K block means, corrected for
 * the Monte Carlo noise of both sides, so that a reference with a few percent of noise of its
 * own can still measure a systematic difference of a few percent.
 *
 * Pixels: "hair" where alpha > 0 in any of the images (numerics.md sec. 6: "in either").
 * Blocks: the mean over each K x K block of premultiplied rgb (edge blocks: over the pixels they
 * have); a block counts when it holds a hair pixel. Per channel c, over the counted pixels or
 * blocks, with x ours and r the reference:
 *   raw       = sqrt(sum (x - r)^2 / sum r^2)                     (numerics.md sec. 6)
 *   corrected = sqrt(max(0, sum (x - r)^2 - sum var_r - sum var_x) / sum r^2)
 * Two reference images A, B (two seeds): r = (A + B) / 2 and var_r = (A - B)^2 / 4 per block, an
 * unbiased estimate of the variance of their mean (E (A - B)^2 = 2 var of one). The same for
 * ours with a second image: SL_OURS_INDEPENDENT (same settings, another seed) x = (X + X2) / 2,
 * var_x = (X - X2)^2 / 4; SL_OURS_HALF (X2 is the image of the first half of X's own samples)
 * x = X, var_x = (X - X2)^2 (X - X2 is half the difference of the two halves, whose variance
 * is var_x). E (x - r)^2 = bias^2 + var_x + var_r, so the corrected figure estimates the
 * noise-free difference. The "avg" column is the mean over r, g, b (as sec. 6 averages). */
#ifndef SL_COMPARE_H
#define SL_COMPARE_H

#include "io/image/image_read.h"

#include <stdio.h>

enum { SL_OURS_INDEPENDENT = 0, SL_OURS_HALF = 1 };

typedef struct sl_compare_in {
    const sl_image *ours;  /* X */
    const sl_image *ours2; /* NULL, or X2 (see ours2_mode) */
    int ours2_mode;        /* SL_OURS_* */
    const sl_image *ref_a; /* A */
    const sl_image *ref_b; /* NULL, or B: another seed of A */
    int block;             /* K >= 1 */
    const char *names[4];  /* file names for messages and the table: ours, ours2, A, B */
} sl_compare_in;

/* One error measure, per channel r, g, b and their mean (index 3). */
typedef struct sl_compare_err {
    double raw[4], corrected[4];
    double ref_noise[4];  /* sqrt(sum var_r / sum r^2): the reference's own noise; 0 without B */
    double ours_noise[4]; /* sqrt(sum var_x / sum r^2); 0 without ours2 */
    long count;           /* hair pixels or blocks counted */
} sl_compare_err;

typedef struct sl_compare_result {
    int width, height, block;
    long pixels, blocks; /* all of them */
    /* mean premultiplied rgb over hair pixels: X, X2, A, B, and x and r as compared */
    double mean_ours[3], mean_ours2[3], mean_a[3], mean_b[3], mean_x[3], mean_ref[3];
    double ratio[3]; /* mean_x / mean_ref (NAN where mean_ref is 0) */
    /* mean alpha over hair pixels of x and r: coverage, which tells geometry or camera
     * differences from shading ones */
    double alpha_x, alpha_ref;
    sl_compare_err px, blk;
    double ab_blocks[4]; /* raw rel. RMSE of A against B on blocks (NAN without B) */
} sl_compare_result;

/* Returns 0, or -1 with e set: sizes differ (naming both files), block < 1, no hair pixel. */
int sl_compare(const sl_compare_in *in, sl_compare_result *r, sl_err *e);

/* The human-readable table, and the machine form: a header `quantity,r,g,b,avg` and one row per
 * figure (names as in the table, snake_case); the counts hair_pixels / hair_blocks repeat in
 * every column, the coverage rows mean_alpha_ours / mean_alpha_ref fill only avg. */
void sl_compare_print(FILE *f, const sl_compare_in *in, const sl_compare_result *r);
void sl_compare_csv(FILE *f, const sl_compare_in *in, const sl_compare_result *r);

#endif
