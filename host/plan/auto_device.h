/* auto_device.h: `--device auto` on a CPU OpenCL device (PoCL): C or the device, for this scene.
 *
 * On a CPU OpenCL device the same cores run both paths, and which is faster depends on the
 * scene (docs/performance.md: PoCL's light pass is slower than C's, its volume pass faster). So
 * `render` under auto, when the device it opened is a CPU one, times one frame of a cheap proxy
 * of the scene (at most SL_AUTO_PROXY_STRANDS strands, every k-th, at half the width and height) on
 * the device (as auto runs it: shading on C, sl_shade_on_device) and on the C path, after a tiny
 * warm-up frame on the device (program builds and PoCL's first-enqueue code generation are not the
 * frame's cost), keeps the faster, and caches the choice in the disk cache keyed by the device's
 * identity and the scene's shape. A GPU device is kept without a trial; an explicit --device
 * never triggers one. Under SL_CL_FAULT (simulated failures, tests) the cache is neither read nor
 * written: the simulated faults must reach the device.
 *
 *   sl_auto_choice ch;
 *   sl_auto_device_settle(&dev, s, h, lobes, lo, hi, target, &ro, &ch);   // may make dev C
 *   if (ch.state != SL_AUTO_NONE) ... ch.why for --explain ...
 */
#ifndef SL_AUTO_DEVICE_H
#define SL_AUTO_DEVICE_H

#include "plan/frame.h"

#define SL_AUTO_PROXY_STRANDS 400u
#define SL_AUTO_CACHE_FORMAT 1u

enum {
    SL_AUTO_NONE = 0, /* no choice to make: not auto, the C path, or a GPU device */
    SL_AUTO_MEASURED, /* a trial ran in this process */
    SL_AUTO_CACHED,   /* the choice came from the disk cache */
    SL_AUTO_FAILED    /* the trial could not finish on the device: the device is kept as it is */
};

typedef struct sl_auto_choice {
    int state;
    int picked_c;     /* 1: the C path was chosen (dev is now the C path) */
    double t_c, t_cl; /* seconds of one proxy frame on C and on the device */
    double seconds;   /* what the trial (or the cache lookup) cost in this process */
    char why[768];    /* one line for --explain and the notice */
} sl_auto_choice;

/* Settles dev (opened by sl_device_open) for this scene as described above; prints one notice
 * (sl_note) when it made or reused a choice. Never fails the render: a trial that fails on the
 * device leaves dev as it is (a fallback inside it has already made dev the C path). */
void sl_auto_device_settle(sl_device *dev, const sl_scene *s, const sl_hair *h,
                           const sl_lobes *lobes, const float lo[3], const float hi[3],
                           const double target[3], const sl_render_opts *ro, sl_auto_choice *out);

/* The cache key of a choice: the device identity (sl_cl_identity) and the scene's shape (strands,
 * points, lobes, width, height, material model, multiple scattering, shading rate, broad lobes,
 * method, threads). Exposed for the tests. */
sl_cache_key sl_auto_device_key(const char *device_identity, const sl_scene *s, const sl_hair *h,
                                const sl_lobes *lobes, const sl_render_opts *ro);

/* out = every k-th strand of h (k = ceil(strands / max_strands), so at most max_strands), with
 * its per-point radius, transparency and colour when h has them; the rest of h's fields copied.
 * Free with sl_hair_free. */
void sl_auto_proxy_hair(const sl_hair *h, uint32_t max_strands, sl_hair *out);

#endif
