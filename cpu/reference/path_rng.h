/* path_rng.h: the path tracer's random numbers. Every (seed, pixel, sample) starts its own
 * stream from a hash of the three (counter-based), so a sample draws the same numbers whatever
 * thread renders it and in whatever order: the image is byte-identical for any thread count.
 * Within a stream, splitmix64 (Steele et al. 2014), whose output function is a strong 64-bit
 * mixer; 53-bit uniforms in [0, 1). */
#ifndef SL_PATH_RNG_H
#define SL_PATH_RNG_H

#include <stdint.h>

typedef struct slref_rng {
    uint64_t state;
} slref_rng;

static inline uint64_t slref_mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* The stream of sample `sample` of pixel `pixel` (any ids: tests use their own). Each input is
 * mixed before the next is folded in, so nearby pixels and samples start far apart. */
static inline void slref_rng_seed(slref_rng *r, uint64_t seed, uint64_t pixel, uint64_t sample) {
    uint64_t z = slref_mix64(seed + 0x9e3779b97f4a7c15ull);
    z = slref_mix64(z ^ (pixel * 0xd1b54a32d192ed03ull + 1));
    r->state = slref_mix64(z ^ (sample * 0x8cb92ba72f3d8dd7ull + 2));
}

static inline uint64_t slref_rng_next(slref_rng *r) {
    return slref_mix64(r->state += 0x9e3779b97f4a7c15ull);
}

/* Uniform in [0, 1). */
static inline double slref_rng_unit(slref_rng *r) {
    return (double)(slref_rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
}

#endif
