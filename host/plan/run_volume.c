/* run_volume.c: the frame's multiple-scattering passes: the decision (ms: off, on, or auto by
 * the estimated share), the dual-scattering tables (dual), the voxel grid and shadow-path march
 * (volume) and the response tables (ms table). The last three run only when ms is on and are
 * cached by their keys (plan/passes.h). With per-strand sigma_a, the decision, the dual tables
 * and the march use the strands' mean sigma_a (the hair volume's average fiber), and the ms
 * table pass builds the response at the strands' sigma_a nodes besides the material's
 * (docs/frame.md, "Per-strand sigma_a"). */
#include "plan/frame_internal.h"

#include <math.h>
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

/* Steps of the strands' mean sigma_a in u = ln(sigma_a + SL_MSN_U0): a paint stroke that moves
 * the mean by less than about 1 % of sigma_a + 0.02 keeps the march (a 2 % change of every
 * fiber's absorption moves T_f by well under 1 % at the default scene's depths). */
#define MS_MEAN_STEP 0.02

void sl_frame_ms_material(const sl_renderer *r, const sl_frame_inputs *in, sl_material *m) {
    *m = in->s->material;
    const float *sa = r->strand_sigma_a;
    size_t n = r->strand_sigma_a_n;
    if (!sa || !n) return;
    int differs = 0;
    for (int c = 0; c < 3; c++) {
        float own = (float)in->s->material.sigma_a[c];
        int same = 1, uniform = 1;
        double sum = 0;
        for (size_t i = 0; i < n; i++) {
            float v = sa[3 * i + c];
            sum += v;
            same &= v == own;
            uniform &= v == sa[c];
        }
        if (same) continue; /* the material's own value, bit for bit */
        double mean = uniform ? (double)sa[c] : sum / (double)n;
        if (!uniform) { /* quantized: nearby paint states share the march */
            double u = log(mean + SL_MSN_U0);
            mean = exp(MS_MEAN_STEP * floor(u / MS_MEAN_STEP + 0.5)) - SL_MSN_U0;
            mean = mean > 0 ? mean : 0;
        }
        m->sigma_a[c] = mean;
        differs = 1;
    }
    if (differs && (m->sigma_a[0] != m->sigma_a[1] || m->sigma_a[1] != m->sigma_a[2]))
        m->sigma_a_rgb = 1;
}

uint64_t sl_dual_settings(const sl_renderer *r, const sl_frame_inputs *in) {
    sl_material m;
    sl_frame_ms_material(r, in, &m);
    return sl_hash64(m.sigma_a, sizeof m.sigma_a, 0x4455414c ^ (uint64_t)m.sigma_a_rgb);
}

uint64_t sl_ms_table_settings(const sl_renderer *r, const sl_frame_inputs *in) {
    (void)in;
    return r->strand_sigma_a ? r->strand_nodes_key : 0x4d53;
}

int sl_ms_needed(const sl_renderer *r, const sl_frame_inputs *in) {
    (void)in;
    return r->ms_on;
}

int sl_pass_ms(sl_renderer *r, const sl_frame_inputs *in, sl_err *e) {
    (void)e;
    const sl_scene *s = in->s;
    sl_material msmat;
    sl_frame_ms_material(r, in, &msmat);
    const sl_material *mat = &msmat;
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
                     r->strand_sigma_a ? "; of the strands' mean sigma_a" : "");
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
    sl_material m;
    sl_frame_ms_material(r, in, &m);
    if (sl_dual_tables_build(&m, &r->dual, e)) return -1;
    sl_dual_deflect_build(&m, &r->dual, &r->deflect);
    r->dual_ok = 1;
    if (r->strand_sigma_a)
        sl_frame_why(r, "dual-scattering tables of the strands' mean sigma_a %.4g %.4g %.4g",
                     m.sigma_a[0], m.sigma_a[1], m.sigma_a[2]);
    else
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
    if (r->have_msn) sl_volume_ms_nodes_free(&r->msn);
    r->have_vms = r->have_msn = 0;
    if (sl_volume_ms_init(&in->s->material, &r->vms, e)) return -1;
    r->have_vms = 1;
    if (r->strand_sigma_a) {
        if (sl_volume_ms_nodes_init(&in->s->material, r->strand_sigma_a, r->strand_sigma_a_n,
                                    sl_frame_threads(r), &r->msn, e))
            return -1;
        r->have_msn = 1;
        sl_frame_why(r,
                     "multiple-scattering response tables of the material and of %d per-strand "
                     "sigma_a nodes (%s; %.2f s)",
                     r->msn.n, r->msn.exact ? "the strands' own values" : "spaced in ln sigma_a",
                     r->msn.build_s);
        return 0;
    }
    sl_frame_why(r,
                 "multiple-scattering response tables of the material (%.2f s of it "
                 "the response table, docs/volume.md)",
                 r->vms.table_s);
    return 0;
}
