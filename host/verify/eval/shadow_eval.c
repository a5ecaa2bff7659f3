/* shadow_eval.c: `eval transmittance`: loads the scene's hair and SRBF lobes once and evaluates
 * the effective transmittance per row, chunk by chunk: the ray-traced reference
 * (cpu/reference/transmittance_ref.h) or the light pass (shadow.h) on the C twin or the OpenCL
 * kernels: one batched light pass for all the lobes the rows use (sl_shadow_build_batch). */
#include "verify/eval/shadow_eval.h"

#include "verify/eval/eval_scene.h"
#include "scene/scene.h"
#include "passes/light/shadow.h"
#include "passes/light/shadow_split.h"
#include "transmittance_ref.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct sl_shadow_eval {
    sl_eval_scene_data d;
    sl_eval_backend b;
    sl_cl *cl;
    slref_fibers *fibers; /* reference: built at the first row */
    /* c / opencl: the lobes the rows used, in order of first use; pos[j]: lobe j's place among
     * them (-1: not used yet); the light pass of the first `built` of them */
    sl_device dev;
    int dev_ready;
    sl_shadow_opts o;
    int *pos, *idx, nlobes, built;
    sl_shadow_maps mp;
    sl_shadow_batch sb;
    double build_s, lookup_s; /* SL_SHADOW_TIMES */
};

int sl_shadow_eval_open(const char *scene_path, sl_eval_backend b, sl_cl *cl, size_t n,
                        const double *in, const long *line_no, sl_shadow_eval **out, sl_err *e) {
    sl_shadow_eval *t = sl_calloc(1, sizeof *t);
    if (sl_eval_scene_load(scene_path, NULL, n, in, line_no, &t->d, e)) {
        free(t);
        return -1;
    }
    t->b = b;
    t->cl = cl;
    int count = t->d.lobes.count;
    t->pos = sl_malloc((size_t)(count ? count : 1) * sizeof *t->pos);
    t->idx = sl_malloc((size_t)(count ? count : 1) * sizeof *t->idx);
    for (int j = 0; j < count; j++)
        t->pos[j] = -1;
    *out = t;
    return 0;
}

static int rows_reference(sl_shadow_eval *t, size_t row0, size_t n, const double *in, double *out,
                          sl_err *e) {
    if (!t->fibers && slref_fibers_build(&t->d.hair, &t->fibers, e)) return -1;
    for (size_t i = 0; i < n; i++) {
        const sl_lobe *l = &t->d.lobes.lobe[(int)in[4 * i + 3]];
        out[i] = slref_transmittance(t->fibers, in + 4 * i, l->dir, l->lambda,
                                     SL_SHADOW_REF_SAMPLES, (uint64_t)(row0 + i) + 1, NULL);
    }
    return 0;
}

/* (Re)builds the light pass when the rows have used lobes it lacks: the batch of all the used
 * lobes in order of first use, as one pass over the whole input would build it. */
static int ensure_built(sl_shadow_eval *t, sl_err *e) {
    if (t->built == t->nlobes) return 0;
    if (t->built) {
        sl_shadow_batch_free(&t->sb);
        sl_shadow_maps_free(&t->mp);
        t->built = 0;
    }
    /* a broad lobe split into its shadow directions (shadow_split.h); the maps stay on the
     * device */
    sl_shadow_maps_plan(&t->d.lobes, t->idx, t->nlobes, NULL, &t->mp);
    double t0 = sl_now();
    if (sl_shadow_build_batch(&t->dev, &t->d.hair, t->mp.n, t->mp.dir, t->mp.lambda, &t->o, &t->sb,
                              e)) {
        sl_shadow_maps_free(&t->mp);
        return -1;
    }
    t->build_s += sl_now() - t0;
    t->built = t->nlobes;
    return 0;
}

static int rows_light_pass(sl_shadow_eval *t, size_t n, const double *in, double *out, sl_err *e) {
    if (!t->dev_ready) {
        if (sl_eval_scene_device(t->b, t->cl, &t->dev, e)) return -1;
        t->dev_ready = 1;
        const sl_scene *s = t->d.scene;
        sl_shadow_opts_default(&t->o);
        if (s->shadow_size > 0) t->o.size = s->shadow_size;
        if (s->layers > 0) t->o.layers = s->layers;
        if (s->kappa > 0 && s->kappa <= 1) t->o.kappa = s->kappa;
    }
    for (size_t i = 0; i < n; i++) {
        int j = (int)in[4 * i + 3];
        if (t->pos[j] < 0) t->idx[t->nlobes] = j, t->pos[j] = t->nlobes++;
    }
    if (ensure_built(t, e)) return -1;
    /* lookups of every row toward its lobe's directions, combined with their weights */
    const sl_shadow_maps *mp = &t->mp;
    size_t nx = 0;
    for (size_t i = 0; i < n; i++) {
        int q = t->pos[(int)in[4 * i + 3]];
        nx += (size_t)(mp->first[q + 1] - mp->first[q]);
    }
    double *xyz = sl_malloc(3 * nx * sizeof *xyz), *Tx = sl_malloc(nx * sizeof *Tx);
    int *lb = sl_malloc(nx * sizeof *lb);
    for (size_t i = 0, r = 0; i < n; i++) {
        int q = t->pos[(int)in[4 * i + 3]];
        for (int m = mp->first[q]; m < mp->first[q + 1]; m++, r++) {
            memcpy(xyz + 3 * r, in + 4 * i, 3 * sizeof *xyz);
            lb[r] = m;
        }
    }
    double t1 = sl_now();
    int rc = sl_shadow_batch_lookup(&t->sb, nx, xyz, lb, Tx, e);
    for (size_t i = 0, r = 0; i < n && !rc; i++) {
        int q = t->pos[(int)in[4 * i + 3]];
        double sum = 0;
        for (int m = mp->first[q]; m < mp->first[q + 1]; m++, r++)
            sum += mp->w[m] * Tx[r];
        out[i] = sum;
    }
    t->lookup_s += sl_now() - t1;
    free(lb);
    free(xyz);
    free(Tx);
    return rc;
}

int sl_shadow_eval_rows(sl_shadow_eval *t, size_t row0, size_t n, const double *in,
                        const long *line_no, double *out, sl_err *e) {
    if (sl_eval_scene_check_rows(&t->d.lobes, n, in, line_no, e)) return -1;
    if (n == 0) return 0;
    if (t->b == SL_EVAL_REFERENCE) return rows_reference(t, row0, n, in, out, e);
    return rows_light_pass(t, n, in, out, e);
}

void sl_shadow_eval_close(sl_shadow_eval *t) {
    if (!t) return;
    if (t->built) {
        /* SL_SHADOW_TIMES=1 (test/bench/bench_shadow.sh): one line of light-pass times on
         * stderr (wall_build: every build of the input; wall_lookup: every chunk's lookups) */
        const char *tv = getenv("SL_SHADOW_TIMES");
        if (tv && tv[0] == '1')
            fprintf(stderr,
                    "shadow-times lobes=%d size=%d K=%d segments=%zu device=%d wall_build=%.4f "
                    "upload=%.4f project=%.4f raster=%.4f tables=%.4f wall_lookup=%.4f\n",
                    t->mp.n, t->o.size, t->o.layers, t->sb.map[0].segments, t->sb.on_device,
                    t->build_s, t->sb.upload_s, t->sb.project_s, t->sb.raster_s, t->sb.tables_s,
                    t->lookup_s);
        sl_shadow_batch_free(&t->sb);
        sl_shadow_maps_free(&t->mp);
    }
    if (t->fibers) slref_fibers_free(t->fibers);
    free(t->pos);
    free(t->idx);
    sl_eval_scene_free(&t->d);
    free(t);
}
