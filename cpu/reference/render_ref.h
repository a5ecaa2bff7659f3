/* render_ref.h: the brute-force reference renderer's core (docs/reference.md), in double:
 * camera rays through jittered sub-pixel positions (host/scene/camera.h pixels), the closest fiber hit
 * (Embree, raytrace_ref.h), and at each hit the sum over N directional lights of
 *   single scattering: f(omega_i, omega_o) (the exact reference fiber function, marschner_ref.h /
 *     deon_ref.h, per colour channel) x light power x visibility (a shadow ray through the
 *     actual fibers; fibers are opaque, numerics.md sec. 7);
 *   multiple scattering (optional, Marschner only): dual scattering (Zinke 2008) with the
 *     forward attenuation T_f = prod a_f and spread sigma_f^2 = sum beta_f^2 / 2 gathered over
 *     the fibers the traced shadow ray crosses (ray-shooting form), material terms from
 *     dual_ref.h tabulated over theta_d.
 * Deterministic for a seed whatever the thread count (every pixel has its own random stream). */
#ifndef SL_RENDER_REF_H
#define SL_RENDER_REF_H

#include "scene/camera.h"
#include "scene/material.h"
#include "raytrace_ref.h"
#include "base/parallel.h"

#include <stdint.h>

/* Zinke 2008's density factors (forward d_f, backward d_b; "0.7 works well"). No material key
 * exists for them (numerics.md sec. 2 forbids unknown keys): docs/dual.md. */
#define SLREF_MS_DF 0.7
#define SLREF_MS_DB 0.7

typedef struct slref_light {
    double dir[3]; /* unit, toward the light */
    double rgb[3]; /* power: integral of the radiance over the light's region */
} slref_light;

/* Dual-scattering tables of a material (double; built from dual_ref.h / marschner_ref.h). */
typedef struct slref_ms_tables slref_ms_tables;
int slref_ms_tables_build(const sl_material *m, int threads, slref_ms_tables **out, sl_err *e);
void slref_ms_tables_free(slref_ms_tables *t);
/* Looks up dual term `term` (SLREF_DUAL_*) of channel ch at theta_d (linear interpolation). */
double slref_ms_term(const slref_ms_tables *t, int ch, int term, double theta_d);
/* N^G_t(theta_d, phi) = 1/pi int_{phi - pi/2}^{phi + pi/2} N_t(theta_d, x) dx (Xu 2011 Eq. 28):
 * the azimuthal response to light spread uniformly over the forward half circle. */
double slref_ms_ng(const slref_ms_tables *t, int ch, int mode, double theta_d, double phi);

/* The material of strand `strand`: m itself when sa is NULL, else a copy in *own with sigma_a
 * = the strand's three values of sa (material.strand_sigma_a, as the frame applies it). */
const sl_material *slref_strand_material(const sl_material *m, const float *sa, uint32_t strand,
                                         sl_material *own);

/* What one hit receives; lights, material and geometry are shared, read-only. */
typedef struct slref_shading {
    const slref_rt *rt;
    const sl_material *m;
    const slref_light *L;
    int nl;
    const slref_ms_tables *ms; /* NULL: single scattering only */
    /* per-strand sigma_a (3 per strand) for single scattering, or NULL; multiple scattering
     * keeps the tables of m (reference.c says so when both are on) */
    const float *strand_sa;
} slref_shading;

/* The fiber frame of a segment with unit tangent u (numerics.md sec. 1): v is the component of
 * +Y normal to u (of +X when |u_y| > 0.9), w = u x v; as the renderer builds it. */
void slref_fiber_frame(const double u[3], double v[3], double w[3]);

/* Radiance toward the viewer (wo: unit, toward the viewer) of point x on segment prim:
 * ss = single scattering, ms = multiple scattering (zeros without tables), modes (may be NULL)
 * = single scattering by mode: modes[3 t + c] for t = R, TT, TRT (d'Eon: orders 0, 1, 2). */
void slref_shade(const slref_shading *sh, const double x[3], const double wo[3], uint32_t prim,
                 double ss[3], double ms[3], double modes[9]);
/* The same over the lights l0, l0 + stride, l0 + 2 stride, ... only (stride >= 1; not scaled):
 * interleaved light subsets, one per camera ray of a pixel (slref_render_opts.light_split). */
void slref_shade_lights(const slref_shading *sh, const double x[3], const double wo[3],
                        uint32_t prim, int l0, int stride, double ss[3], double ms[3],
                        double modes[9]);

typedef struct slref_render_opts {
    int aa;        /* aa x aa camera rays per pixel (>= 1), one per sub-pixel stratum */
    int no_jitter; /* 1: rays through the strata centres (aa = 1: the pixel centre); for tests */
    uint64_t seed; /* jitter seed */
    int threads;   /* >= 1 */
    void (*progress)(void *user, double fraction); /* called from the calling thread, or NULL */
    void *progress_user;
} slref_render_opts;

/* Output planes (w * h each, row 0 at the top): rgb premultiplied by alpha (mean over the
 * camera rays, misses count 0), alpha = coverage, depth = nearest view depth (+inf: empty),
 * the multiple-scattering part of rgb (ms_rgb) and the single scattering by mode (mode_rgb:
 * R rgb, TT rgb, TRT rgb per pixel), all premultiplied. */
typedef struct slref_image {
    int w, h;
    float *rgba;     /* 4 * w * h interleaved */
    float *depth;    /* w * h */
    float *ms_rgb;   /* 3 * w * h interleaved */
    float *mode_rgb; /* 9 * w * h interleaved */
} slref_image;

int slref_render(const slref_shading *sh, const sl_camera *cam, const slref_render_opts *o,
                 slref_image *out, sl_err *e);
/* slref_render with light_split = 1: interleaved light subsets. The S = aa x aa camera rays of
 * a pixel share the N lights: ray r (after a random per-pixel rotation) shades lights
 * l = r, r + S, r + 2S, ... with weight S, so a pixel costs about N shadings whatever aa is.
 * Unbiased against the image with every light on every ray (each light is shaded once per
 * pixel, at a random one of the pixel's jittered rays); it trades the light cut's
 * stratification within one ray for many more camera rays, which is where the error of a hair
 * image at low resolution is (many fibers per pixel, each lit and shadowed differently:
 * docs/reference.md). light_split = 0 is slref_render. */
int slref_render_split(const slref_shading *sh, const sl_camera *cam, const slref_render_opts *o,
                       int light_split, slref_image *out, sl_err *e);
void slref_image_free(slref_image *img);
/* Allocates the planes of a w x h image (zeros; depth set by the renderer). */
void slref_image_alloc(slref_image *img, int w, int h);
/* Runs fn(job, y0, y1, worker) over rows 0 .. rows - 1, one row at a time, on o->threads threads
 * (on the calling thread when none starts), reporting the finished fraction through o->progress
 * every 0.1 s (sl_parallel_for_progress). */
void slref_run_rows(sl_parallel_fn fn, void *job, int rows, const slref_render_opts *o);

/* The camera ray through pixel position (px, py) (pixel centres at +0.5, camera.h): unit dir. */
void slref_camera_ray(const sl_camera *cam, double px, double py, double dir[3]);

#endif
