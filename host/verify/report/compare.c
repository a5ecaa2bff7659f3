/* compare.c: see compare.h. */
#include "verify/report/compare.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Indices of the four inputs (all the same size; NULL where absent). */
enum { IM_X = 0, IM_X2 = 1, IM_A = 2, IM_B = 3, IM_N = 4 };

typedef struct sums {
    double d[3], r[3], vr[3], vx[3], ab[3];
    long count;
} sums;

/* Block means (rgba) of image `im` for block (bx, by) of size k: over the pixels it has. */
static void block_mean(const sl_image *im, int k, int bx, int by, double out[4]) {
    int x0 = bx * k, y0 = by * k;
    int x1 = x0 + k < im->width ? x0 + k : im->width,
        y1 = y0 + k < im->height ? y0 + k : im->height;
    double s[4] = {0, 0, 0, 0};
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++)
            for (int c = 0; c < 4; c++)
                s[c] += im->rgba[4 * ((size_t)y * im->width + x) + c];
    double n = (double)(x1 - x0) * (y1 - y0);
    for (int c = 0; c < 4; c++)
        out[c] = s[c] / n;
}

/* 1 when any pixel of the block is hair in any image (alpha > 0). */
static int block_has_hair(const sl_image *const im[IM_N], int k, int bx, int by) {
    int x0 = bx * k, y0 = by * k;
    int x1 = x0 + k < im[IM_X]->width ? x0 + k : im[IM_X]->width;
    int y1 = y0 + k < im[IM_X]->height ? y0 + k : im[IM_X]->height;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++)
            for (int i = 0; i < IM_N; i++)
                if (im[i] && im[i]->rgba[4 * ((size_t)y * im[i]->width + x) + 3] > 0) return 1;
    return 0;
}

/* The sums of compare.h's formulas over the blocks of size k that hold hair. */
static void accumulate(const sl_image *const im[IM_N], int ours2_mode, int k, sums *s) {
    memset(s, 0, sizeof *s);
    int bw = (im[IM_X]->width + k - 1) / k, bh = (im[IM_X]->height + k - 1) / k;
    for (int by = 0; by < bh; by++)
        for (int bx = 0; bx < bw; bx++) {
            if (!block_has_hair(im, k, bx, by)) continue;
            double m[IM_N][4] = {{0}};
            for (int i = 0; i < IM_N; i++)
                if (im[i]) block_mean(im[i], k, bx, by, m[i]);
            for (int c = 0; c < 3; c++) {
                double x = m[IM_X][c], r = m[IM_A][c], vx = 0, vr = 0;
                if (im[IM_B]) {
                    double dab = m[IM_A][c] - m[IM_B][c];
                    r = 0.5 * (m[IM_A][c] + m[IM_B][c]);
                    vr = 0.25 * dab * dab;
                    s->ab[c] += dab * dab;
                }
                if (im[IM_X2]) {
                    double dx = m[IM_X][c] - m[IM_X2][c];
                    if (ours2_mode == SL_OURS_INDEPENDENT) {
                        x = 0.5 * (m[IM_X][c] + m[IM_X2][c]);
                        vx = 0.25 * dx * dx;
                    } else {
                        vx = dx * dx;
                    }
                }
                s->d[c] += (x - r) * (x - r);
                s->r[c] += r * r;
                s->vr[c] += vr;
                s->vx[c] += vx;
            }
            s->count++;
        }
}

static double ratio_sqrt(double num, double den) {
    return den > 0 ? sqrt(num / den) : NAN;
}

static void avg4(double v[4]) {
    v[3] = (v[0] + v[1] + v[2]) / 3.0;
}

static void finish(const sums *s, sl_compare_err *o) {
    for (int c = 0; c < 3; c++) {
        double left = s->d[c] - s->vr[c] - s->vx[c];
        o->raw[c] = ratio_sqrt(s->d[c], s->r[c]);
        o->corrected[c] = ratio_sqrt(left > 0 ? left : 0, s->r[c]);
        o->ref_noise[c] = ratio_sqrt(s->vr[c], s->r[c]);
        o->ours_noise[c] = ratio_sqrt(s->vx[c], s->r[c]);
    }
    avg4(o->raw);
    avg4(o->corrected);
    avg4(o->ref_noise);
    avg4(o->ours_noise);
    o->count = s->count;
}

int sl_compare(const sl_compare_in *in, sl_compare_result *r, sl_err *e) {
    memset(r, 0, sizeof *r);
    const sl_image *im[IM_N] = {in->ours, in->ours2, in->ref_a, in->ref_b};
    for (int i = 1; i < IM_N; i++)
        if (im[i] && (im[i]->width != im[0]->width || im[i]->height != im[0]->height))
            return sl_fail(e, "%s is %d x %d but %s is %d x %d", in->names[i], im[i]->width,
                           im[i]->height, in->names[0], im[0]->width, im[0]->height);
    if (in->block < 1) return sl_fail(e, "block size %d: must be >= 1", in->block);
    int w = im[0]->width, h = im[0]->height;
    r->width = w, r->height = h, r->block = in->block;
    r->pixels = (long)w * h;
    r->blocks = (long)((w + in->block - 1) / in->block) * ((h + in->block - 1) / in->block);

    /* means over hair pixels */
    double sum[IM_N][4] = {{0}};
    long nh = 0;
    for (size_t p = 0; p < (size_t)w * h; p++) {
        int hair = 0;
        for (int i = 0; i < IM_N; i++)
            if (im[i] && im[i]->rgba[4 * p + 3] > 0) hair = 1;
        if (!hair) continue;
        nh++;
        for (int i = 0; i < IM_N; i++)
            for (int c = 0; im[i] && c < 4; c++)
                sum[i][c] += im[i]->rgba[4 * p + c];
    }
    if (nh == 0)
        return sl_fail(e, "no hair pixel (alpha > 0) in %s or %s", in->names[0], in->names[2]);
    for (int c = 0; c < 3; c++) {
        r->mean_ours[c] = sum[IM_X][c] / nh;
        r->mean_ours2[c] = im[IM_X2] ? sum[IM_X2][c] / nh : NAN;
        r->mean_a[c] = sum[IM_A][c] / nh;
        r->mean_b[c] = im[IM_B] ? sum[IM_B][c] / nh : NAN;
        r->mean_x[c] = im[IM_X2] && in->ours2_mode == SL_OURS_INDEPENDENT
                           ? 0.5 * (r->mean_ours[c] + r->mean_ours2[c])
                           : r->mean_ours[c];
        r->mean_ref[c] = im[IM_B] ? 0.5 * (r->mean_a[c] + r->mean_b[c]) : r->mean_a[c];
        r->ratio[c] = r->mean_ref[c] != 0 ? r->mean_x[c] / r->mean_ref[c] : NAN;
    }

    int x_avg = im[IM_X2] && in->ours2_mode == SL_OURS_INDEPENDENT;
    r->alpha_x = (x_avg ? 0.5 * (sum[IM_X][3] + sum[IM_X2][3]) : sum[IM_X][3]) / nh;
    r->alpha_ref = (im[IM_B] ? 0.5 * (sum[IM_A][3] + sum[IM_B][3]) : sum[IM_A][3]) / nh;

    sums s;
    accumulate(im, in->ours2_mode, 1, &s);
    finish(&s, &r->px);
    accumulate(im, in->ours2_mode, in->block, &s);
    finish(&s, &r->blk);
    for (int c = 0; c < 3; c++)
        r->ab_blocks[c] = im[IM_B] ? ratio_sqrt(s.ab[c], s.r[c]) : NAN;
    avg4(r->ab_blocks);
    return 0;
}

/* ---- output ---- */

typedef struct row {
    const char *label, *key;
    const double *v;
    int n; /* 3 (r g b) or 4 (r g b avg) */
} row;

/* The rows of the table that apply to these inputs; returns how many. */
static int rows(const sl_compare_in *in, const sl_compare_result *r, row out[24]) {
    int n = 0, two = in->ref_b != NULL, o2 = in->ours2 != NULL;
    out[n++] = (row){"mean ours (X)", "mean_ours", r->mean_ours, 3};
    if (o2) out[n++] = (row){"mean ours (X2)", "mean_ours2", r->mean_ours2, 3};
    if (o2 && in->ours2_mode == SL_OURS_INDEPENDENT)
        out[n++] = (row){"mean ours (X+X2)/2", "mean_x", r->mean_x, 3};
    out[n++] = (row){"mean reference A", "mean_a", r->mean_a, 3};
    if (two) out[n++] = (row){"mean reference B", "mean_b", r->mean_b, 3};
    if (two) out[n++] = (row){"mean reference (A+B)/2", "mean_ref", r->mean_ref, 3};
    out[n++] = (row){"ratio ours / reference", "ratio", r->ratio, 3};
    out[n++] = (row){"rel RMSE pixels, raw", "rel_rmse_px_raw", r->px.raw, 4};
    if (two || o2)
        out[n++] = (row){"rel RMSE pixels, corrected", "rel_rmse_px_corrected", r->px.corrected, 4};
    out[n++] = (row){"rel RMSE blocks, raw", "rel_rmse_blocks_raw", r->blk.raw, 4};
    if (two || o2)
        out[n++] =
            (row){"rel RMSE blocks, corrected", "rel_rmse_blocks_corrected", r->blk.corrected, 4};
    if (two) {
        out[n++] = (row){"reference noise, pixels", "ref_noise_px", r->px.ref_noise, 4};
        out[n++] = (row){"reference noise, blocks", "ref_noise_blocks", r->blk.ref_noise, 4};
        out[n++] = (row){"A vs B, blocks (raw)", "a_vs_b_blocks", r->ab_blocks, 4};
    }
    if (o2) {
        out[n++] = (row){"ours noise, pixels", "ours_noise_px", r->px.ours_noise, 4};
        out[n++] = (row){"ours noise, blocks", "ours_noise_blocks", r->blk.ours_noise, 4};
    }
    return n;
}

void sl_compare_print(FILE *f, const sl_compare_in *in, const sl_compare_result *r) {
    fprintf(f, "ours       %s", in->names[0]);
    if (in->ours2)
        fprintf(f, "  + %s (%s)", in->names[1],
                in->ours2_mode == SL_OURS_HALF ? "its first half" : "independent");
    fprintf(f, "\nreference  %s", in->names[2]);
    if (in->ref_b) fprintf(f, "  + %s (another seed)", in->names[3]);
    fprintf(f, "\n%d x %d: %ld hair pixels of %ld; %d x %d blocks: %ld with hair of %ld\n",
            r->width, r->height, r->px.count, r->pixels, r->block, r->block, r->blk.count,
            r->blocks);
    fprintf(f, "mean alpha over hair pixels (coverage): ours %.6g, reference %.6g\n\n", r->alpha_x,
            r->alpha_ref);
    row rw[24];
    int n = rows(in, r, rw);
    fprintf(f, "%-28s %12s %12s %12s %12s\n", "", "R", "G", "B", "avg");
    for (int i = 0; i < n; i++) {
        fprintf(f, "%-28s", rw[i].label);
        for (int c = 0; c < rw[i].n; c++)
            fprintf(f, " %12.6g", rw[i].v[c]);
        fputc('\n', f);
    }
}

void sl_compare_csv(FILE *f, const sl_compare_in *in, const sl_compare_result *r) {
    row rw[24];
    int n = rows(in, r, rw);
    fprintf(f, "quantity,r,g,b,avg\n");
    fprintf(f, "hair_pixels,%ld,%ld,%ld,%ld\n", r->px.count, r->px.count, r->px.count, r->px.count);
    fprintf(f, "hair_blocks,%ld,%ld,%ld,%ld\n", r->blk.count, r->blk.count, r->blk.count,
            r->blk.count);
    fprintf(f, "mean_alpha_ours,,,,%.9g\nmean_alpha_ref,,,,%.9g\n", r->alpha_x, r->alpha_ref);
    for (int i = 0; i < n; i++) {
        fprintf(f, "%s", rw[i].key);
        for (int c = 0; c < 4; c++) {
            if (c < rw[i].n)
                fprintf(f, ",%.9g", rw[i].v[c]);
            else
                fprintf(f, ",");
        }
        fputc('\n', f);
    }
}
