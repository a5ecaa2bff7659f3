/* shadow_eval.c: `eval transmittance`: loads the scene's hair and SRBF lobes and evaluates the
 * effective transmittance per row: the ray-traced reference (cpu/reference/transmittance_ref.h)
 * or the light pass (shadow.h) on the C twin or the OpenCL kernels: one batched light pass for
 * all the lobes the rows use (sl_shadow_build_batch). */
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

int sl_shadow_eval_transmittance(const char *scene_path, sl_eval_backend b, sl_cl *cl, size_t n,
                                 const double *in, const long *line_no, double *out, sl_err *e) {
    sl_eval_scene_data d;
    if (sl_eval_scene_load(scene_path, NULL, n, in, line_no, &d, e)) return -1;
    const sl_scene *s = d.scene;
    const sl_hair *h = &d.hair;
    const sl_lobes *lobes = &d.lobes;
    int rc = -1;
    if (n == 0) {
        rc = 0;
        goto done;
    }
    if (b == SL_EVAL_REFERENCE) {
        slref_fibers *f;
        if (slref_fibers_build(h, &f, e)) goto done;
        for (size_t i = 0; i < n; i++) {
            const sl_lobe *l = &lobes->lobe[(int)in[4 * i + 3]];
            out[i] = slref_transmittance(f, in + 4 * i, l->dir, l->lambda, SL_SHADOW_REF_SAMPLES,
                                         (uint64_t)i + 1, NULL);
        }
        slref_fibers_free(f);
        rc = 0;
        goto done;
    }
    sl_device dev;
    if (sl_eval_scene_device(b, cl, &dev, e)) goto done;
    sl_shadow_opts o;
    sl_shadow_opts_default(&o);
    if (s->shadow_size > 0) o.size = s->shadow_size;
    if (s->layers > 0) o.layers = s->layers;
    if (s->kappa > 0 && s->kappa <= 1) o.kappa = s->kappa;
    /* one batched light pass for the lobes the rows use (maps stay on the device), a broad lobe
     * split into its shadow directions (shadow_split.h), then lookups of every row toward its
     * lobe's directions, combined with their weights */
    /* the lobes the rows use, in order of first use; pos[j]: lobe j's place among them */
    int *pos = sl_malloc((size_t)lobes->count * sizeof *pos),
        *idx = sl_malloc((size_t)lobes->count * sizeof *idx), nlobes = 0;
    for (int j = 0; j < lobes->count; j++)
        pos[j] = -1;
    for (size_t i = 0; i < n; i++) {
        int j = (int)in[4 * i + 3];
        if (pos[j] < 0) idx[nlobes] = j, pos[j] = nlobes++;
    }
    sl_shadow_maps mp;
    sl_shadow_maps_plan(lobes, idx, nlobes, NULL, &mp);
    int nused = mp.n;
    size_t nx = 0;
    for (size_t i = 0; i < n; i++) {
        int q = pos[(int)in[4 * i + 3]];
        nx += (size_t)(mp.first[q + 1] - mp.first[q]);
    }
    double *xyz = sl_malloc(3 * nx * sizeof *xyz), *Tx = sl_malloc(nx * sizeof *Tx);
    int *lb = sl_malloc(nx * sizeof *lb);
    for (size_t i = 0, r = 0; i < n; i++) {
        int q = pos[(int)in[4 * i + 3]];
        for (int m = mp.first[q]; m < mp.first[q + 1]; m++, r++) {
            memcpy(xyz + 3 * r, in + 4 * i, 3 * sizeof *xyz);
            lb[r] = m;
        }
    }
    sl_shadow_batch sb;
    double t0 = sl_now();
    rc = sl_shadow_build_batch(&dev, h, nused, mp.dir, mp.lambda, &o, &sb, e);
    if (!rc) {
        double t1 = sl_now();
        rc = sl_shadow_batch_lookup(&sb, nx, xyz, lb, Tx, e);
        for (size_t i = 0, r = 0; i < n && !rc; i++) {
            int q = pos[(int)in[4 * i + 3]];
            double t = 0;
            for (int m = mp.first[q]; m < mp.first[q + 1]; m++, r++)
                t += mp.w[m] * Tx[r];
            out[i] = t;
        }
        double t2 = sl_now();
        /* SL_SHADOW_TIMES=1 (test/bench/bench_shadow.sh): one line of light-pass times on stderr */
        const char *tv = getenv("SL_SHADOW_TIMES");
        if (!rc && tv && tv[0] == '1')
            fprintf(stderr,
                    "shadow-times lobes=%d size=%d K=%d segments=%zu device=%d wall_build=%.4f "
                    "upload=%.4f project=%.4f raster=%.4f tables=%.4f wall_lookup=%.4f\n",
                    nused, o.size, o.layers, sb.map[0].segments, sb.on_device, t1 - t0, sb.upload_s,
                    sb.project_s, sb.raster_s, sb.tables_s, t2 - t1);
        sl_shadow_batch_free(&sb);
    }
    free(pos);
    free(idx);
    sl_shadow_maps_free(&mp);
    free(lb);
    free(xyz);
    free(Tx);
done:
    sl_eval_scene_free(&d);
    return rc;
}
