/* volume_eval.c: `eval forward-transmittance`: loads the scene's hair, material and SRBF lobes
 * (sl_eval_scene_load, as host/verify/eval/shadow_eval.c does for `transmittance`) and evaluates T_f and
 * sigma_f per row: the fiber-exact reference or the volume passes (host/passes/volume/volume.h) on the C twin
 * or OpenCL. */
#include "verify/eval/volume_eval.h"

#include "passes/volume/dual.h"
#include "march_ref.h"
#include "verify/eval/eval_scene.h"
#include "scene/scene.h"
#include "passes/volume/volume.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_EVENTS 100000

/* The dual-scattering terms exist for the Marschner model only (host/passes/volume/dual.h). */
static int needs_marschner(const sl_scene *s, const char *path, sl_err *e) {
    if (s->material.model == SL_MODEL_MARSCHNER) return 0;
    return sl_fail(e,
                   "%s: material.model: forward-transmittance needs the dual-scattering terms, "
                   "which support model marschner only",
                   path);
}

int sl_volume_eval_forward(const char *scene_path, sl_eval_backend b, sl_cl *cl, size_t n,
                           const double *in, const long *line_no, double *out, sl_err *e) {
    sl_eval_scene_data d;
    if (sl_eval_scene_load(scene_path, needs_marschner, n, in, line_no, &d, e)) return -1;
    const sl_scene *s = d.scene;
    const sl_hair *h = &d.hair;
    const sl_lobes *lobes = &d.lobes;
    const sl_material *m = &s->material;
    int nch = sl_eval_num_channels(SL_EVAL_FORWARD_TRANSMITTANCE, m);
    int rc = -1;
    if (n == 0) {
        rc = 0;
        goto done;
    }
    if (b == SL_EVAL_REFERENCE) {
        double *theta = sl_malloc(MAX_EVENTS * sizeof *theta);
        slref_dual_cache cache[3];
        memset(cache, 0, sizeof cache);
        for (size_t i = 0; i < n; i++) {
            const double *w = lobes->lobe[(int)in[4 * i + 3]].dir;
            size_t k = slref_march_events(h, in + 4 * i, w, theta, MAX_EVENTS);
            if (k > MAX_EVENTS) k = MAX_EVENTS; /* T_f is 0 to double precision long before */
            for (int c = 0; c < nch; c++) {
                double *y = out + ((size_t)c * n + i) * 2;
                slref_forward_from_events(m, c, theta, k, &cache[c], &y[0], &y[1]);
            }
        }
        rc = 0;
        free(theta);
        goto done;
    }
    sl_device dev;
    if (sl_eval_scene_device(b, cl, &dev, e)) goto done;
    sl_dual_tables dt;
    if (sl_dual_tables_build(m, &dt, e)) goto done;
    /* March only the lobes the rows ask for. */
    int *slot = sl_malloc((size_t)lobes->count * sizeof *slot);
    double *dirs = sl_malloc((size_t)lobes->count * 3 * sizeof *dirs);
    int nl = 0;
    for (int j = 0; j < lobes->count; j++)
        slot[j] = -1;
    for (size_t i = 0; i < n; i++) {
        int j = (int)in[4 * i + 3];
        if (slot[j] < 0) {
            slot[j] = nl;
            memcpy(dirs + 3 * nl++, lobes->lobe[j].dir, 3 * sizeof *dirs);
        }
    }
    sl_voxel_grid g;
    sl_ftex f;
    sl_march_opts o;
    sl_march_opts_default(&o);
    if (!sl_voxelize(&dev, h, s->voxels, &g, e)) {
        if (!sl_march_build(&dev, &g, &dt, nl, dirs, &o, &f, e)) {
            for (size_t i = 0; i < n; i++) {
                float T[3], sg[3];
                sl_ftex_lookup(&f, slot[(int)in[4 * i + 3]], in + 4 * i, T, sg);
                for (int c = 0; c < nch; c++) {
                    double *y = out + ((size_t)c * n + i) * 2;
                    y[0] = T[c];
                    y[1] = sg[c];
                }
            }
            sl_ftex_free(&f);
            rc = 0;
        }
        sl_voxel_grid_free(&g);
    }
    free(slot);
    free(dirs);
done:
    sl_eval_scene_free(&d);
    return rc;
}
