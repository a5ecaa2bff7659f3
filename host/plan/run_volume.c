/* run_volume.c: the frame's multiple-scattering passes: the decision (ms: off, on, or auto by
 * the estimated share), the dual-scattering tables (dual), the voxel grid and shadow-path march
 * (volume) and the response tables (ms table). The last three run only when ms is on and are
 * cached by their keys (plan/passes.h). They use the material's sigma_a, never the per-strand
 * overrides (docs/frame.md). */
#include "plan/frame_internal.h"

#include <stdlib.h>

void sl_frame_free_march(sl_renderer *r) {
    if (r->have_vol) sl_ftex_free(&r->ftex);
    r->have_vol = 0;
    r->key[SL_PASSID_VOLUME] = 0;
}

void sl_frame_free_volume(sl_renderer *r) {
    sl_frame_free_march(r);
    if (r->have_vgrid) sl_voxel_grid_free(&r->vgrid);
    r->have_vgrid = 0;
    r->vox_key = 0;
}

int sl_ms_needed(const sl_renderer *r, const sl_frame_inputs *in) {
    (void)in;
    return r->ms_on;
}

int sl_pass_ms(sl_renderer *r, const sl_frame_inputs *in, sl_err *e) {
    (void)e;
    const sl_scene *s = in->s;
    const sl_material *mat = &s->material;
    r->ms_on = 0;
    r->rec_state = SL_PASS_SKIPPED;
    if (s->multiple_scattering == SL_MS_OFF) {
        sl_frame_why(r, "quality.multiple_scattering is off");
        return 0;
    }
    double ms_share = sl_dual_ms_share(mat);
    r->ms_on = s->multiple_scattering == SL_MS_ON || ms_share >= s->ms_auto_threshold;
    if (r->ms_on) {
        r->rec_state = SL_PASS_RUN;
        sl_frame_why(r,
                     "%s: estimated multiple-scattering share %.3f (quality.ms_auto_threshold "
                     "%.3g)%s",
                     s->multiple_scattering == SL_MS_ON ? "on" : "auto", ms_share,
                     s->ms_auto_threshold,
                     r->strand_sigma_a ? "; uses the material's sigma_a, not per strand" : "");
    } else {
        sl_frame_why(r,
                     "auto: dark hair, estimated multiple-scattering share %.4f < %.3g "
                     "(quality.ms_auto_threshold)",
                     ms_share, s->ms_auto_threshold);
    }
    return 0;
}

int sl_pass_dual(sl_renderer *r, const sl_frame_inputs *in, sl_err *e) {
    r->dual_ok = 0;
    if (sl_dual_tables_build(&in->s->material, &r->dual, e)) return -1;
    r->dual_ok = 1;
    sl_frame_why(r, "dual-scattering material tables (material changed)");
    return 0;
}

uint64_t sl_volume_settings(const sl_renderer *r, const sl_frame_inputs *in) {
    (void)r;
    return sl_hash64(&in->s->voxels, sizeof in->s->voxels, 0x44);
}

/* The voxel grid's own key: geometry and quality.voxels (a material or lobe edit keeps it). */
static uint64_t grid_key(const sl_renderer *r, const sl_frame_inputs *in) {
    uint64_t k = sl_hash64(&r->data_hash[SL_DATA_GEOMETRY], sizeof(uint64_t), 0x47);
    return sl_hash64(&in->s->voxels, sizeof in->s->voxels, k) | 1;
}

int sl_pass_volume(sl_renderer *r, const sl_frame_inputs *in, sl_err *e) {
    const sl_frame_work *w = &r->fw;
    int nused = w->nused;
    double *dirs = sl_malloc(3 * (nused ? nused : 1) * sizeof *dirs);
    for (int j = 0; j < nused; j++)
        for (int k = 0; k < 3; k++)
            dirs[3 * j + k] = w->fl->lobe[w->used[j]].dir[k];
    uint64_t gk = grid_key(r, in);
    int grid_cached = r->have_vgrid && gk == r->vox_key;
    sl_frame_free_march(r);
    sl_march_opts mo;
    sl_march_opts_default(&mo);
    mo.threads = sl_frame_threads(r);
    if (!grid_cached) {
        sl_frame_free_volume(r);
        if (sl_voxelize(r->dev, in->h, in->s->voxels, &r->vgrid, e)) {
            free(dirs);
            return -1;
        }
        r->have_vgrid = 1;
        r->vox_key = gk;
    }
    if (sl_march_build(r->dev, &r->vgrid, &r->dual, nused, dirs, &mo, &r->ftex, e)) {
        free(dirs);
        return -1;
    }
    free(dirs);
    r->have_vol = 1;
    sl_frame_why(r,
                 "voxels %dx%dx%d (%s), march %d paths toward %d lobes (%zu active "
                 "vertices)",
                 r->vgrid.n[0], r->vgrid.n[1], r->vgrid.n[2],
                 grid_cached ? "grid reused: geometry unchanged" : "voxelized", mo.paths, nused,
                 r->ftex.active);
    return 0;
}

int sl_pass_ms_table(sl_renderer *r, const sl_frame_inputs *in, sl_err *e) {
    if (r->have_vms) sl_volume_ms_free(&r->vms);
    r->have_vms = 0;
    if (sl_volume_ms_init(&in->s->material, &r->vms, e)) return -1;
    r->have_vms = 1;
    sl_frame_why(r,
                 "multiple-scattering response tables of the material (%.2f s of it "
                 "the response table, docs/volume.md)",
                 r->vms.table_s);
    return 0;
}
