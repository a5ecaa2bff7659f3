/* lobes_json.h: SRBF lobe lists (numerics.md sec. 4) and their JSON files.
 *
 * An environment map is approximated by lobes (omega_j, lambda_j, rgb_j):
 *   L(omega) ~ sum_j rgb_j G(omega; omega_j, lambda_j),  G = exp(2 (omega . omega_j - 1) /
 * lambda^2) (Xu 2011 Eq. 1). The file is
 *   {"lobes": [{"dir": [x, y, z], "lambda": l, "rgb": [r, g, b]}, ...], "fit": {...}}
 * with dir a unit vector in the world frame, lambda > 0 and rgb >= 0. `strandlight fit` writes
 * the "fit" object (map hash, settings, achieved errors, time); readers keep it as text so a
 * load + save round trip preserves it. The same layout with "lights" and lambda = 0 is NOT a
 * lobe file: directional lights (envsample.h) have their own reader. */
#ifndef SL_LOBES_JSON_H
#define SL_LOBES_JSON_H

#include "base/common.h"

typedef struct sl_lobe {
    double dir[3]; /* unit vector, world frame */
    double lambda; /* bandwidth (Xu's convention), > 0 */
    double rgb[3]; /* weights, >= 0 */
} sl_lobe;

typedef struct sl_lobes {
    int count;
    sl_lobe *lobe;
    /* The "fit" object as JSON text (NULL when absent); written back verbatim by sl_lobes_save. */
    char *fit_json;
    /* Parsed from "fit" when present: the source map's hash ("" when absent) and the achieved
     * errors (-1 when absent). */
    char map_hash[40];
    double rel_l2, lobe_conv_rel_l2;
} sl_lobes;

#define SL_LOBES_MAX 100000

/* Reads and validates a lobes file. Errors name the file and the key, e.g.
 * "lobes.json: lobes[3].lambda: expected a positive number". A dir whose length differs from 1
 * by more than 1e-3 is an error; smaller deviations (printing round-off) are normalised. */
int sl_lobes_load(const char *path, sl_lobes *out, sl_err *e);
/* Parses a lobes document from memory; `name` is used in messages. */
int sl_lobes_parse(const char *text, size_t len, const char *name, sl_lobes *out, sl_err *e);
/* Writes atomically (temporary file + rename). Validates like the loader first. */
int sl_lobes_save(const char *path, const sl_lobes *l, sl_err *e);
/* The text sl_lobes_save writes, validated the same way (`name` for messages): allocated (free
 * it), its length in *len; NULL with e set. For callers that store it elsewhere (the disk cache
 * of fitted lobes). */
char *sl_lobes_format(const sl_lobes *l, const char *name, size_t *len, sl_err *e);
void sl_lobes_free(sl_lobes *l);

/* Integral of G over the sphere: pi lambda^2 (1 - exp(-4 / lambda^2)). */
double sl_lobe_integral(double lambda);

#endif
