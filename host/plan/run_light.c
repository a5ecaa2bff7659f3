/* run_light.c: the light pass of the frame: one deep opacity map per shaded lobe, several
 * for a broad lobe (shadow_split.h), cached while geometry, lobes, the map budget and the
 * shadow quality are unchanged (plan/passes.h: a camera orbit reuses every one). */
#include "plan/frame_internal.h"
#include "passes/light/shadow_split.h"

#include <stdlib.h>
#include <string.h>

void sl_frame_free_lights(sl_renderer *r) {
    for (int i = 0; i < r->nlights; i++)
        sl_dodm_free(&r->light[i]);
    free(r->light);
    free(r->light_lobe);
    free(r->light_w);
    r->light_w = NULL;
    r->light = NULL;
    r->light_lobe = NULL;
    r->nlights = 0;
    r->key[SL_PASSID_LIGHT] = 0;
}

/* A broad lobe of the light pass: its position in the used list, its split directions and its
 * power (the budget's extra maps go to the most powerful first). */
typedef struct split_order {
    int lobe, dirs;
    double power;
} split_order;

static int split_order_cmp(const void *a, const void *b) {
    const split_order *x = a, *y = b;
    if (x->power != y->power) return x->power > y->power ? -1 : 1;
    return x->lobe - y->lobe; /* ties: the used order, so the plan is deterministic */
}

/* The deep opacity maps' options: the part of the scene the key covers, then the threads
 * (the maps do not depend on them). */
static void shadow_opts(const sl_renderer *r, const sl_scene *s, sl_shadow_opts *so) {
    memset(so, 0, sizeof *so); /* padding too: the struct is hashed */
    sl_shadow_opts_default(so);
    so->layers = sl_frame_shadow_layers(s);
    so->kappa = s->kappa > 0 ? s->kappa : 1.0;
    so->size = sl_frame_shadow_size(s, r->o.shadow_size);
    so->z0_fibers = SL_SHADOW_Z0_FIBERS_SHADING; /* shading points lie on fibers */
}

uint64_t sl_light_settings(const sl_renderer *r, const sl_frame_inputs *in) {
    sl_shadow_opts so;
    shadow_opts(r, in->s, &so);
    return sl_hash64(&so, sizeof so, 0x11);
}

void sl_light_on_cached(sl_renderer *r, const sl_frame_inputs *in) {
    (void)in;
    sl_frame_why(r, "%d deep opacity maps reused (geometry, lobes and shadow quality unchanged)",
                 r->nlights);
}

int sl_pass_light(sl_renderer *r, const sl_frame_inputs *in, sl_err *e) {
    const sl_hair *h = in->h;
    const sl_lobes *lobes = r->fw.fl;
    const int *used = r->fw.used;
    int nused = r->fw.nused, extra_maps = r->fw.extra_maps;
    sl_shadow_opts so;
    shadow_opts(r, in->s, &so);
    so.threads = sl_frame_threads(r);
    sl_frame_free_lights(r);
    /* broad lobes get several maps (shadow_split.h), within a budget of extra_maps beyond one
     * per lobe (SL_SHADOW_SPLIT_MAPS_PER_LOBE per lobe; with sub-lobes, what they left): the
     * extra maps go to the broad lobes of largest power first (a lobe left without extras keeps
     * its single capped map) */
    int nmaps = 0, nsplit = 0;
    double sd[3 * SL_SHADOW_SPLIT_N], sw[SL_SHADOW_SPLIT_N];
    int *want = sl_malloc((nused ? nused : 1) * sizeof *want);
    split_order *order = sl_malloc((nused ? nused : 1) * sizeof *order);
    int nbroad = 0;
    for (int j = 0; j < nused; j++) {
        const sl_lobe *lb = &lobes->lobe[used[j]];
        int c = sl_shadow_split(lb->dir, lb->lambda, sd, sw);
        want[j] = 1;
        if (c > 1)
            order[nbroad++] = (split_order){
                j, c, (lb->rgb[0] + lb->rgb[1] + lb->rgb[2]) * sl_lobe_integral(lb->lambda)};
    }
    qsort(order, (size_t)nbroad, sizeof *order, split_order_cmp);
    for (int b = 0, extra = extra_maps; b < nbroad; b++) {
        int give = order[b].dirs - 1 < extra ? order[b].dirs - 1 : extra;
        want[order[b].lobe] = 1 + give;
        extra -= give;
    }
    free(order);
    for (int j = 0; j < nused; j++)
        nsplit += want[j] > 1;
    sl_shadow_maps sm;
    sl_shadow_maps_plan(lobes, used, nused, want, &sm);
    nmaps = sm.n;
    r->light = sl_calloc(nmaps ? nmaps : 1, sizeof *r->light);
    r->light_lobe = sl_malloc((nmaps ? nmaps : 1) * sizeof *r->light_lobe);
    r->light_w = sl_malloc((nmaps ? nmaps : 1) * sizeof *r->light_w);
    /* one batch for every map: the segments prepared once, whole maps per thread on C */
    if (nmaps && sl_shadow_build_maps(r->dev, h, nmaps, sm.dir, sm.lambda, &so, r->light, e)) {
        r->nlights = 0;
        sl_frame_free_lights(r);
        free(want);
        sl_shadow_maps_free(&sm);
        return -1;
    }
    for (int m = 0; m < nmaps; m++) {
        r->light_lobe[m] = sm.lobe[m];
        r->light_w[m] = sm.w[m];
    }
    r->nlights = nmaps;
    sl_shadow_maps_free(&sm);
    free(want);
    sl_frame_why(r,
                 "%d deep opacity maps %dx%d for %d lobes (%d broad, split), K=%d, kappa %.3g (%s)",
                 nmaps, so.size, so.size, nused, nsplit, so.layers, so.kappa,
                 r->dev->is_opencl ? "OpenCL" : "C");
    return 0;
}
