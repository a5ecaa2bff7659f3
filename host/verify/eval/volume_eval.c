/* volume_eval.c: `eval forward-transmittance`: loads the scene's hair, material and SRBF lobes
 * once (sl_eval_scene_load, as host/verify/eval/shadow_eval.c does for `transmittance`) and
 * evaluates T_f and sigma_f per row, chunk by chunk: the fiber-exact reference or the volume
 * passes (host/passes/volume/volume.h) on the C twin or OpenCL. */
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

struct sl_volume_eval {
    sl_eval_scene_data d;
    sl_eval_backend b;
    sl_cl *cl;
    int nch;
    /* reference */
    double *theta; /* MAX_EVENTS */
    slref_dual_cache cache[3];
    /* c / opencl: built at the first row; slot[j]: lobe j's place among the lobes used so far
     * (-1: not yet), dirs: theirs in that order; f: the march of the first `built` of them */
    int ready;
    sl_device dev;
    sl_dual_tables dt;
    sl_voxel_grid g;
    int *slot, nl, built;
    double *dirs;
    sl_ftex f;
};

/* The dual-scattering terms exist for the Marschner model only (host/passes/volume/dual.h). */
static int needs_marschner(const sl_scene *s, const char *path, sl_err *e) {
    if (s->material.model == SL_MODEL_MARSCHNER) return 0;
    return sl_fail(e,
                   "%s: material.model: forward-transmittance needs the dual-scattering terms, "
                   "which support model marschner only",
                   path);
}

int sl_volume_eval_open(const char *scene_path, sl_eval_backend b, sl_cl *cl, size_t n,
                        const double *in, const long *line_no, sl_volume_eval **out, sl_err *e) {
    sl_volume_eval *v = sl_calloc(1, sizeof *v);
    if (sl_eval_scene_load(scene_path, needs_marschner, n, in, line_no, &v->d, e)) {
        free(v);
        return -1;
    }
    v->b = b;
    v->cl = cl;
    v->nch = sl_eval_num_channels(SL_EVAL_FORWARD_TRANSMITTANCE, &v->d.scene->material);
    *out = v;
    return 0;
}

static void rows_reference(sl_volume_eval *v, size_t n, const double *in, double *out) {
    const sl_material *m = &v->d.scene->material;
    if (!v->theta) v->theta = sl_malloc(MAX_EVENTS * sizeof *v->theta);
    for (size_t i = 0; i < n; i++) {
        const double *w = v->d.lobes.lobe[(int)in[4 * i + 3]].dir;
        size_t k = slref_march_events(&v->d.hair, in + 4 * i, w, v->theta, MAX_EVENTS);
        if (k > MAX_EVENTS) k = MAX_EVENTS; /* T_f is 0 to double precision long before */
        for (int c = 0; c < v->nch; c++) {
            double *y = out + ((size_t)c * n + i) * 2;
            slref_forward_from_events(m, c, v->theta, k, &v->cache[c], &y[0], &y[1]);
        }
    }
}

/* The device, the dual-scattering tables and the voxel grid: once, at the first row. */
static int prepare(sl_volume_eval *v, sl_err *e) {
    if (sl_eval_scene_device(v->b, v->cl, &v->dev, e)) return -1;
    if (sl_dual_tables_build(&v->d.scene->material, &v->dt, e)) return -1;
    int count = v->d.lobes.count;
    v->slot = sl_malloc((size_t)(count ? count : 1) * sizeof *v->slot);
    v->dirs = sl_malloc((size_t)(count ? count : 1) * 3 * sizeof *v->dirs);
    for (int j = 0; j < count; j++)
        v->slot[j] = -1;
    if (sl_voxelize(&v->dev, &v->d.hair, v->d.scene->voxels, &v->g, e)) return -1;
    v->ready = 1;
    return 0;
}

static int rows_march(sl_volume_eval *v, size_t n, const double *in, double *out, sl_err *e) {
    if (!v->ready && prepare(v, e)) return -1;
    /* March only the lobes the rows ask for. */
    for (size_t i = 0; i < n; i++) {
        int j = (int)in[4 * i + 3];
        if (v->slot[j] < 0) {
            v->slot[j] = v->nl;
            memcpy(v->dirs + 3 * v->nl++, v->d.lobes.lobe[j].dir, 3 * sizeof *v->dirs);
        }
    }
    if (v->built != v->nl) {
        if (v->built) sl_ftex_free(&v->f);
        v->built = 0;
        sl_march_opts o;
        sl_march_opts_default(&o);
        if (sl_march_build(&v->dev, &v->g, &v->dt, v->nl, v->dirs, &o, &v->f, e)) return -1;
        v->built = v->nl;
    }
    for (size_t i = 0; i < n; i++) {
        float T[3], sg[3];
        sl_ftex_lookup(&v->f, v->slot[(int)in[4 * i + 3]], in + 4 * i, T, sg);
        for (int c = 0; c < v->nch; c++) {
            double *y = out + ((size_t)c * n + i) * 2;
            y[0] = T[c];
            y[1] = sg[c];
        }
    }
    return 0;
}

int sl_volume_eval_rows(sl_volume_eval *v, size_t n, const double *in, const long *line_no,
                        double *out, sl_err *e) {
    if (sl_eval_scene_check_rows(&v->d.lobes, n, in, line_no, e)) return -1;
    if (n == 0) return 0;
    if (v->b == SL_EVAL_REFERENCE) {
        rows_reference(v, n, in, out);
        return 0;
    }
    return rows_march(v, n, in, out, e);
}

void sl_volume_eval_close(sl_volume_eval *v) {
    if (!v) return;
    if (v->built) sl_ftex_free(&v->f);
    if (v->ready) sl_voxel_grid_free(&v->g);
    free(v->slot);
    free(v->dirs);
    free(v->theta);
    sl_eval_scene_free(&v->d);
    free(v);
}
