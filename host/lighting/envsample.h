/* envsample.h: directional lights that stand for an environment map, for the brute-force
 * reference renderer (`strandlight sample`).
 *
 * Method: median cut (Debevec 2005, a structured importance sampling in the spirit of Agarwal
 * et al. 2003): the lat-long map is split recursively into rectangles of equal power
 * (solid-angle-weighted luminance), always splitting the most powerful region across its
 * angularly longer side at its power median. Each region becomes one light at its power-weighted
 * mean direction carrying the region's power per channel (sum of radiance x solid angle), so the
 * lights are stratified by power and their total equals the map's exactly.
 *
 * File: {"lights": [{"dir": [x, y, z], "rgb": [r, g, b], "solid_angle": s}, ...],
 *        "sample": {"map_hash": ..., "settings": {...}, "rel_l2": ..., "lobe_conv_rel_l2": ...}}
 * dir a unit vector in the world frame (numerics.md sec. 4) pointing toward the light, rgb the
 * power (W m^-2 per unit radiance: integral of L over the region), solid_angle the region's. */
#ifndef SL_ENVSAMPLE_H
#define SL_ENVSAMPLE_H

#include "io/envmap/envmap.h"
#include "lighting/lobes_json.h"

typedef struct sl_envlight {
    double dir[3];
    double rgb[3];      /* power: integral of radiance over the light's region */
    double solid_angle; /* of the region */
} sl_envlight;

typedef struct sl_envlights {
    int count;
    sl_envlight *light;
    char *record_json; /* the "sample" object as JSON text (NULL when absent) */
} sl_envlights;

/* Cuts the map into n regions (n >= 1; fewer when the map has fewer pixels) and returns one
 * light per region, sorted by decreasing power. Also reports the errors of the lights as a
 * stand-in for the map (envfit.h): *conv_rel_l2 treats them as directional sources seen through
 * G(.; ., conv_lambda); *rel_l2 is that of the piecewise-constant map that spreads each light's
 * power evenly over its region. Returns 0 or -1 with e set. */
int sl_envsample(const sl_envmap *map, int n, double conv_lambda, int threads, sl_envlights *out,
                 double *rel_l2, double *conv_rel_l2, sl_err *e);

int sl_envlights_save(const char *path, const sl_envlights *l, sl_err *e);
/* Reads and validates a lights file ("lights[3].rgb[1]: expected a finite number >= 0"). */
int sl_envlights_load(const char *path, sl_envlights *out, sl_err *e);
/* The same from memory (len bytes, no NUL needed; path names the file in messages): no I/O,
 * fuzzed by test/fuzz/fuzz_lights.c. On failure *out is zeroed. */
int sl_envlights_parse(const char *text, size_t len, const char *path, sl_envlights *out,
                       sl_err *e);
void sl_envlights_free(sl_envlights *l);

#endif
