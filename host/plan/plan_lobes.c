/* plan_lobes.c: the planning passes before any rendering: the SRBF tables, the lobes worth
 * shading (quality.lobe_threshold) and the broad lobes' sub-lobes (quality.broad_lobes). */
#include "plan/frame_internal.h"
#include "lighting/lobe_subdivide.h"
#include "passes/light/shadow_split.h"

#include <stdlib.h>

double sl_frame_lobe_power(const sl_lobe *lb) {
    static const double lum[3] = {0.2126, 0.7152, 0.0722};
    return (lum[0] * lb->rgb[0] + lum[1] * lb->rgb[1] + lum[2] * lb->rgb[2]) *
           sl_lobe_integral(lb->lambda);
}

int sl_pass_tables(sl_renderer *r, const sl_frame_inputs *in, sl_err *e) {
    (void)in;
    if (r->have_tables) sl_srbf_tables_free(&r->tables);
    r->have_tables = 0;
    if (sl_srbf_tables_get(&r->tables, 0, e)) return -1;
    r->have_tables = 1;
    sl_frame_why(r, "SRBF C_k/H_k tables %s",
                 r->tables.from_cache ? "loaded from the disk cache" : "built");
    return 0;
}

/* lobes: skip those whose share of the total power is negligible */
int sl_pass_lobes(sl_renderer *r, const sl_frame_inputs *in, sl_err *e) {
    (void)e;
    const sl_lobes *lobes = in->lobes;
    sl_frame_work *w = &r->fw;
    const double lobe_thr = r->o.lobe_threshold >= 0 ? r->o.lobe_threshold : in->s->lobe_threshold;
    double *power = sl_malloc(lobes->count * sizeof *power), total = 0;
    for (int j = 0; j < lobes->count; j++) {
        power[j] = sl_frame_lobe_power(&lobes->lobe[j]);
        total += power[j];
    }
    w->used = sl_malloc(lobes->count * sizeof *w->used);
    w->share = sl_malloc(lobes->count * sizeof *w->share);
    w->nused = 0;
    w->total = total;
    double skipped_share = 0;
    for (int j = 0; j < lobes->count; j++) {
        double sh = total > 0 ? power[j] / total : 0;
        if (sh >= lobe_thr) {
            w->share[w->nused] = sh;
            w->used[w->nused++] = j;
        } else {
            skipped_share += sh;
        }
    }
    free(power);
    w->fl = lobes;
    r->lobes_used = w->nused;
    if (w->nused < lobes->count) {
        r->rec_state = SL_PASS_SKIPPED;
        sl_frame_why(r,
                     "%d of %d lobes below %.3g of the total power (quality.lobe_threshold; "
                     "together %.2g %%) left out",
                     lobes->count - w->nused, lobes->count, lobe_thr, 100 * skipped_share);
    } else {
        sl_frame_why(r, "all %d lobes above %.3g of the total power (quality.lobe_threshold)",
                     w->nused, lobe_thr);
    }
    return 0;
}

/* The hashes of the shaded lobes that the keyed passes read: directions and lambdas (light),
 * directions alone (volume), the map budget (light). */
static void hash_lobes(sl_renderer *r) {
    const sl_frame_work *w = &r->fw;
    uint64_t k = 0x55, d = 0x66;
    for (int j = 0; j < w->nused; j++) {
        const sl_lobe *lb = &w->fl->lobe[w->used[j]];
        k = sl_hash64(lb->dir, sizeof lb->dir, k);
        k = sl_hash64(&lb->lambda, sizeof(double), k);
    }
    double *dirs = sl_malloc(3 * (w->nused ? w->nused : 1) * sizeof *dirs);
    for (int j = 0; j < w->nused; j++)
        for (int q = 0; q < 3; q++)
            dirs[3 * j + q] = w->fl->lobe[w->used[j]].dir[q];
    d = sl_hash64(dirs, 3 * w->nused * sizeof *dirs, d);
    free(dirs);
    r->data_hash[SL_DATA_LOBES] = k;
    r->data_hash[SL_DATA_LOBE_DIRS] = d;
    r->data_hash[SL_DATA_MAP_BUDGET] = sl_hash64(&w->extra_maps, sizeof w->extra_maps, 0x77);
}

/* broad lobes (docs/shadow.md, "Broad lobes"): with quality.broad_lobes subdivide, every used
 * lobe with lambda > SL_SUBDIV_LAMBDA_MIN becomes narrower sub-lobes that sum to it
 * (host/lighting/lobe_subdivide.h), so every pass below (light, march, lookup, shade) sees narrow
 * lobes, each with its own transmittance and response. The budget: the narrow lobes plus the
 * sub-lobes of quality.sublobe_width over the whole sphere (sl_subdiv_set_size). The fit is redone
 * each frame; the sub-lobes are deterministic, so an orbit's light pass still finds its maps by
 * key. */
int sl_pass_subdivide(sl_renderer *r, const sl_frame_inputs *in, sl_err *e) {
    (void)e;
    sl_frame_work *w = &r->fw;
    w->extra_maps = (SL_SHADOW_SPLIT_MAPS_PER_LOBE - 1) * w->nused;
    if (in->s->broad_lobes != SL_BROAD_SUBDIVIDE) {
        r->rec_state = SL_PASS_SKIPPED;
        sl_frame_why(r, "quality.broad_lobes split: a broad lobe keeps one lobe, its "
                        "transmittance split over several maps");
        hash_lobes(r);
        return 0;
    }
    /* the broad light is one function (lobe_subdivide.h): its sub-lobes' count is set by their
     * width (SL_SUBDIV_WIDTH), whatever the number of lobes it was cut into, so the budget (and
     * the image) does not change with the cut */
    int nnarrow = 0, nbroad = 0, nsub = 0;
    for (int j = 0; j < w->nused; j++)
        nnarrow += !(in->lobes->lobe[w->used[j]].lambda > SL_SUBDIV_LAMBDA_MIN);
    sl_subdiv_params sp;
    sl_subdiv_params_default(&sp);
    sp.width = in->s->sublobe_width;
    int budget = sl_subdiv_budget(nnarrow, in->s->sublobe_width);
    double fit_l2 = 0;
    sl_lobes_subdivide(in->lobes, w->used, w->nused, budget, &sp, &w->sub, &nbroad, &nsub, &fit_l2);
    if (nbroad > 0) {
        w->fl = &w->sub;
        free(w->used);
        free(w->share);
        w->nused = w->sub.count;
        w->used = sl_malloc(w->nused * sizeof *w->used);
        w->share = sl_malloc(w->nused * sizeof *w->share);
        for (int j = 0; j < w->nused; j++) {
            w->used[j] = j;
            w->share[j] = w->total > 0 ? sl_frame_lobe_power(&w->sub.lobe[j]) / w->total : 0;
        }
        w->extra_maps = budget - w->nused > 0 ? budget - w->nused : 0;
        sl_frame_why(r,
                     "%d broad lobes (lambda > %.2g) fitted together by %d sub-lobes (rel. L2 "
                     "%.2f): %d lobes shaded, at most %d deep opacity maps (quality.broad_lobes "
                     "subdivide)",
                     nbroad, SL_SUBDIV_LAMBDA_MIN, nsub, fit_l2, w->nused,
                     w->nused + w->extra_maps);
    } else {
        r->rec_state = SL_PASS_SKIPPED;
        sl_frame_why(r, "no used lobe broader than lambda %.2g (quality.broad_lobes subdivide)",
                     SL_SUBDIV_LAMBDA_MIN);
    }
    hash_lobes(r);
    return 0;
}
