/* scene_inputs.c: see scene_inputs.h. */
#include "scene/scene_inputs.h"

#include "scene/env_lighting.h"
#include "scene/scene_hair.h"
#include "scene/scene_strands.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void sl_scene_camera(const sl_scene *s, const float lo[3], const float hi[3], int width, int height,
                     double target[3], sl_camera *cam) {
    for (int k = 0; k < 3; k++)
        target[k] = s->has_target ? s->target[k] : 0.5 * (lo[k] + hi[k]);
    sl_camera_setup(cam, s->has_eye ? s->eye : NULL, target, s->up, s->fov_deg, width, height, lo,
                    hi);
}

void sl_scene_set_size(sl_scene *s, int width, int height) {
    if (width > 0) s->width = width;
    if (height > 0) s->height = height;
}

int sl_scene_inputs_open(const char *scene_path, const sl_scene_inputs_opts *o, sl_scene_inputs *in,
                         sl_err *e) {
    memset(in, 0, sizeof *in);
    in->scene = sl_malloc(sizeof *in->scene);
    if (sl_scene_load(scene_path, in->scene, e)) return -1;
    sl_scene_set_size(in->scene, o->width, o->height);
    return 0;
}

/* An error in a file the scene refers to names the scene and the key too: "scene.json:
 * environment.file: maps/x.hdr: No such file or directory" (the file's own message follows). */
static int in_scene(const sl_scene *s, const char *key, sl_err *e) {
    size_t np = strlen(s->path);
    if (np && strncmp(e->msg, s->path, np) == 0 && e->msg[np] == ':') return -1; /* named already */
    char msg[sizeof e->msg];
    snprintf(msg, sizeof msg, "%s", e->msg);
    return sl_fail(e, "%s: %s: %s", s->path[0] ? s->path : "scene", key, msg);
}

/* Geometry the float pipeline can render (issue 21: hair at +-3e38, an extent of 1e-38 or a
 * radius of 1.5e38 rendered black with exit 0): coordinates and radii below SL_HAIR_MAX_COORD,
 * an extent above SL_HAIR_MIN_EXTENT of its distance from the origin (float keeps ~7 digits of a
 * coordinate: a smaller head has no resolvable shape) and a largest radius below the extent. */
#define SL_HAIR_MAX_COORD 1e18
#define SL_HAIR_MIN_EXTENT 1e-5
static int hair_representable(const sl_hair *h, const float lo[3], const float hi[3], sl_err *e) {
    double ext = 0, far = 0, rmax = h->radius ? 0 : h->default_radius;
    for (int k = 0; k < 3; k++) {
        ext = fmax(ext, (double)hi[k] - lo[k]);
        far = fmax(far, fmax(fabs((double)lo[k]), fabs((double)hi[k])));
    }
    for (uint32_t i = 0; h->radius && i < h->num_points; i++)
        rmax = fmax(rmax, h->radius[i]);
    if (!(far < SL_HAIR_MAX_COORD) || !isfinite(ext))
        return sl_fail(e, "coordinates up to %g: too large to render (the limit is %g)", far,
                       SL_HAIR_MAX_COORD);
    if (!(ext > SL_HAIR_MIN_EXTENT * fmax(far, 1e-30)) || !(ext > 1e-30))
        return sl_fail(e,
                       "extent %g at distance %g from the origin: too small to render (float "
                       "keeps about 7 digits; move or scale the hair)",
                       ext, far);
    if (!(rmax < SL_HAIR_MAX_COORD) || !(rmax <= ext))
        return sl_fail(e, "fiber radius up to %g for an extent of %g: cannot be rendered", rmax,
                       ext);
    return 0;
}

int sl_scene_inputs_finish(sl_scene_inputs *in, const sl_scene_inputs_opts *o, sl_err *e) {
    const sl_scene *s = in->scene;
    if (sl_scene_load_hair(s, &in->hair, e))
        return in_scene(s, s->hair_file[0] ? "hair.file" : "hair.procedural", e);
    if (o->lobes) {
        if (sl_scene_lobes(s, o->clamp_nonfinite, &in->lobes, e)) {
            size_t nl = strlen(s->env_lobes);
            int lobes = nl && strncmp(e->msg, s->env_lobes, nl) == 0;
            return in_scene(s, lobes ? "environment.lobes" : "environment.file", e);
        }
        sl_lobes_transform(&in->lobes, s->env_rotation_deg, s->env_intensity);
    }
    sl_hair_bounds(&in->hair, in->lo, in->hi);
    if (hair_representable(&in->hair, in->lo, in->hi, e))
        return in_scene(s, s->hair_file[0] ? "hair.file" : "hair.procedural", e);
    sl_scene_camera(s, in->lo, in->hi, s->width, s->height, in->target, &in->cam);
    if (o->strand_sigma_a && sl_scene_strand_sigma_a(s, &in->hair, &in->strand_sigma_a, e))
        return in_scene(s, "material.strand_sigma_a", e);
    return 0;
}

int sl_scene_inputs_load(const char *scene_path, const sl_scene_inputs_opts *o, sl_scene_inputs *in,
                         sl_err *e) {
    if (sl_scene_inputs_open(scene_path, o, in, e)) return -1;
    return sl_scene_inputs_finish(in, o, e);
}

int sl_scene_inputs_from_scene(const sl_scene *s, const sl_scene_inputs_opts *o,
                               sl_scene_inputs *in, sl_err *e) {
    memset(in, 0, sizeof *in);
    in->scene = sl_malloc(sizeof *in->scene);
    *in->scene = *s;
    sl_scene_set_size(in->scene, o->width, o->height);
    return sl_scene_inputs_finish(in, o, e);
}

void sl_scene_inputs_free(sl_scene_inputs *in) {
    free(in->strand_sigma_a);
    sl_lobes_free(&in->lobes);
    sl_hair_free(&in->hair);
    free(in->scene);
    memset(in, 0, sizeof *in);
}
