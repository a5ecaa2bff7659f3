/* eval_scene.c: see eval_scene.h. */
#include "verify/eval/eval_scene.h"

#include "scene/env_lighting.h"
#include "scene/scene_inputs.h"

#include <stdlib.h>
#include <string.h>

int sl_eval_scene_check_rows(const sl_lobes *lobes, size_t n, const double *rows,
                             const long *line_no, sl_err *e) {
    for (size_t i = 0; i < n; i++)
        if (rows[4 * i + 3] >= lobes->count)
            return sl_fail(
                e, "<stdin>:%ld: lobe: %.0f is out of range (the scene has %d lobes, 0..%d)",
                line_no ? line_no[i] : (long)i + 2, rows[4 * i + 3], lobes->count,
                lobes->count - 1);
    return 0;
}

int sl_eval_scene_lobes(const sl_scene *s, size_t n, const double *rows, const long *line_no,
                        sl_lobes *lobes, sl_err *e) {
    if (sl_scene_lobes(s, 0, lobes, e)) return -1;
    sl_lobes_transform(lobes, s->env_rotation_deg, 1.0);
    return sl_eval_scene_check_rows(lobes, n, rows, line_no, e);
}

int sl_eval_scene_load(const char *path, sl_eval_scene_check check, size_t n, const double *rows,
                       const long *line_no, sl_eval_scene_data *d, sl_err *e) {
    memset(d, 0, sizeof *d);
    /* the loader of render, with the quantity's check and the lobes (turned as eval turns them,
     * checked against the rows) between the scene and the hair */
    sl_scene_inputs in;
    sl_scene_inputs_opts io = {0};
    int rc = sl_scene_inputs_open(path, &io, &in, e) || (check && check(in.scene, path, e)) ||
             sl_eval_scene_lobes(in.scene, n, rows, line_no, &d->lobes, e) ||
             sl_scene_inputs_finish(&in, &io, e);
    d->scene = in.scene; /* in holds nothing else: its lobes and strand sigma_a were not asked */
    d->hair = in.hair;
    if (rc) {
        sl_eval_scene_free(d);
        return -1;
    }
    return 0;
}

void sl_eval_scene_free(sl_eval_scene_data *d) {
    sl_lobes_free(&d->lobes);
    sl_hair_free(&d->hair);
    free(d->scene);
    memset(d, 0, sizeof *d);
}

int sl_eval_scene_device(sl_eval_backend b, sl_cl *cl, sl_device *dev, sl_err *e) {
    memset(dev, 0, sizeof *dev);
    if (b != SL_EVAL_OPENCL) return 0;
    if (!cl) return sl_fail(e, "eval: --backend opencl needs a device");
    dev->is_opencl = 1;
    dev->cl = cl;
    return 0;
}
