/* shadow_eval.c: `eval transmittance`: loads the scene's hair and SRBF lobes and evaluates the
 * effective transmittance per row: the ray-traced reference (cpu/reference/transmittance_ref.h)
 * or the light pass (shadow.h) on the C twin or the OpenCL kernels, one light pass per lobe. */
#include "shadow_eval.h"

#include "scene_hair.h"

#include "env_lighting.h"
#include "scene.h"
#include "shadow.h"
#include "transmittance_ref.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int sl_shadow_eval_transmittance(const char *scene_path, sl_eval_backend b, sl_cl *cl, size_t n,
                                 const double *in, const long *line_no, double *out, sl_err *e) {
    sl_scene *s = sl_malloc(sizeof *s);
    sl_hair h;
    sl_lobes lobes;
    memset(&h, 0, sizeof h);
    memset(&lobes, 0, sizeof lobes);
    int rc = -1;
    if (sl_scene_load(scene_path, s, e)) goto done;
    /* environment.lobes, or quality.lobes lobes fitted to environment.file (cached); the lobe
     * directions turned by environment.rotation_deg as the renderer turns them. */
    if (sl_scene_lobes(s, 0, &lobes, e)) goto done;
    sl_lobes_transform(&lobes, s->env_rotation_deg, 1.0);
    for (size_t i = 0; i < n; i++)
        if (in[4 * i + 3] >= lobes.count) {
            sl_fail(e, "<stdin>:%ld: lobe: %.0f is out of range (the scene has %d lobes, 0..%d)",
                    line_no ? line_no[i] : (long)i + 2, in[4 * i + 3], lobes.count,
                    lobes.count - 1);
            goto done;
        }
    if (sl_scene_load_hair(s, &h, e)) goto done;
    if (n == 0) {
        rc = 0;
        goto done;
    }
    if (b == SL_EVAL_REFERENCE) {
        slref_fibers *f;
        if (slref_fibers_build(&h, &f, e)) goto done;
        for (size_t i = 0; i < n; i++) {
            const sl_lobe *l = &lobes.lobe[(int)in[4 * i + 3]];
            out[i] = slref_transmittance(f, in + 4 * i, l->dir, l->lambda, SL_SHADOW_REF_SAMPLES,
                                         (uint64_t)i + 1, NULL);
        }
        slref_fibers_free(f);
        rc = 0;
        goto done;
    }
    sl_device dev;
    memset(&dev, 0, sizeof dev);
    if (b == SL_EVAL_OPENCL) {
        if (!cl) {
            sl_fail(e, "eval: --backend opencl needs a device");
            goto done;
        }
        dev.is_opencl = 1;
        dev.cl = cl; /* explicit device: never falls back */
    }
    sl_shadow_opts o;
    sl_shadow_opts_default(&o);
    if (s->layers > 0) o.layers = s->layers;
    if (s->kappa > 0 && s->kappa <= 1) o.kappa = s->kappa;
    double *xyz = sl_malloc(3 * n * sizeof *xyz), *T = sl_malloc(n * sizeof *T);
    size_t *idx = sl_malloc(n * sizeof *idx);
    rc = 0;
    for (int j = 0; j < lobes.count && !rc; j++) {
        size_t m = 0;
        for (size_t i = 0; i < n; i++)
            if ((int)in[4 * i + 3] == j) {
                memcpy(xyz + 3 * m, in + 4 * i, 3 * sizeof *xyz);
                idx[m++] = i;
            }
        if (!m) continue;
        sl_dodm map;
        if (sl_shadow_build(&dev, &h, lobes.lobe[j].dir, lobes.lobe[j].lambda, &o, &map, e)) {
            rc = -1;
            break;
        }
        rc = sl_shadow_lookup(&dev, &map, m, xyz, T, e);
        sl_dodm_free(&map);
        for (size_t k = 0; k < m && !rc; k++)
            out[idx[k]] = T[k];
    }
    free(xyz);
    free(T);
    free(idx);
done:
    sl_lobes_free(&lobes);
    sl_hair_free(&h);
    free(s);
    return rc;
}
