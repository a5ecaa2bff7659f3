/* scene_hair.c: see scene_hair.h. */
#include "scene/scene_hair.h"

#include <stdlib.h>
#include <string.h>

int sl_scene_load_hair(const sl_scene *s, sl_hair *h, sl_err *e) {
    if (s->hair_procedural) {
        sl_hair_procedural p = {s->proc_style, s->proc_strands, s->proc_points, s->proc_seed};
        if (sl_hair_generate(&p, h, e)) return -1;
    } else {
        if (sl_hair_load(s->hair_file, h, e)) return -1;
        if (s->up_z) sl_hair_z_up_to_y_up(h);
        /* tfx_follow densifies TressFX guides; a .tfxproj already brought its own followers.
         * Where it cannot apply it is an error, not a setting silently dropped (issue 22). */
        if (s->has_follow && strncmp(h->format, "TressFX", 7) != 0) {
            sl_fail(e, "%s: hair.tfx_follow: applies to TressFX guides only (%s is %s)", s->path,
                    s->hair_file, h->format);
            sl_hair_free(h);
            return -1;
        }
        if (s->has_follow && h->follow_added) {
            sl_fail(e,
                    "%s: hair.tfx_follow: %s sets its own followers (followPerGuide in the "
                    ".tfxproj); remove tfx_follow",
                    s->path, s->hair_file);
            sl_hair_free(h);
            return -1;
        }
        if (s->has_follow && s->follow_per_guide > 0) {
            sl_hair_follow f = {s->follow_per_guide, (float)s->follow_root_radius,
                                (float)s->follow_tip_spread, 1};
            if (sl_hair_add_follow(h, &f, e)) {
                sl_hair_free(h);
                return -1;
            }
        }
    }
    if (!s->file_transparency) {
        /* fibers are opaque (numerics.md sec. 7): the file's transparency is an alpha for
         * line rasterizers, which would let the camera see through fibers that cast full
         * shadows and that the path tracer hits (docs/formats.md "Transparency") */
        free(h->transparency);
        h->transparency = NULL;
        h->default_transparency = 0.0f;
    }
    if (s->radius > 0) {
        free(h->radius);
        h->radius = NULL;
        h->default_radius = (float)s->radius;
    }
    return 0;
}
