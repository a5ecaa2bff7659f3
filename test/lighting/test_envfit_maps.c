/* test_envfit_maps.c: fitting the shared environment maps (reduced to 256 x 128 to keep the
 * test fast; the full sweep over every map at full size is test/bench/bench_fit.sh). */
#include "lighting/envfit.h"
#include "test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* 4 x 4 box reduction weighted by the exact pixel solid angle (power preserving). */
static void reduce4(sl_envmap *m) {
    int w = m->width / 4, h = m->height / 4;
    float *o = calloc((size_t)w * h * 3, sizeof(float));
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double acc[3] = {0, 0, 0}, ws = 0;
            for (int sy = 0; sy < 4; sy++) {
                int yy = 4 * y + sy;
                double om = cos(M_PI * yy / m->height) - cos(M_PI * (yy + 1) / m->height);
                for (int sx = 0; sx < 4; sx++) {
                    const float *p = m->rgb + ((size_t)yy * m->width + 4 * x + sx) * 3;
                    for (int c = 0; c < 3; c++)
                        acc[c] += om * p[c];
                    ws += om;
                }
            }
            for (int c = 0; c < 3; c++)
                o[((size_t)y * w + x) * 3 + c] = (float)(acc[c] / ws);
        }
    free(m->rgb);
    m->rgb = o;
    m->width = w;
    m->height = h;
}

static void sweep(const char *rel) {
    const char *dir = sl_test_shared_data();
    char path[4096];
    snprintf(path, sizeof path, "%s/envmaps/%s", dir, rel);
    sl_envmap m;
    sl_err e;
    if (sl_envmap_load(path, 0, &m, &e)) {
        CHECK_MSG(0, "%s", e.msg);
        return;
    }
    reduce4(&m);
    int ns[] = {10, 20, 40};
    double prev = INFINITY, prev_conv = INFINITY;
    for (int k = 0; k < 3; k++) {
        sl_envfit_settings s;
        sl_envfit_default_settings(&s);
        s.lobes = ns[k];
        sl_lobes out;
        sl_envfit_report rep;
        CHECK(sl_envfit(&m, &s, &out, &rep, &e) == 0);
        CHECK(out.count == ns[k]);
        for (int j = 0; j < out.count; j++) {
            const sl_lobe *l = &out.lobe[j];
            CHECK(isfinite(l->lambda) && l->lambda > 0);
            for (int c = 0; c < 3; c++)
                CHECK(isfinite(l->dir[c]) && isfinite(l->rgb[c]) && l->rgb[c] >= 0);
        }
        CHECK(isfinite(rep.rel_l2) && isfinite(rep.lobe_conv_rel_l2));
        /* More lobes never fit worse (each fit is independent, so this is a real check). */
        CHECK_MSG(rep.rel_l2 <= prev, "%s: N=%d rel_l2 %.5g after %.5g", rel, ns[k], rep.rel_l2,
                  prev);
        /* The convolved error follows, with 10 % slack: it is not what the fit minimises. */
        CHECK_MSG(rep.lobe_conv_rel_l2 <= 1.1 * prev_conv, "%s: N=%d conv %.5g after %.5g", rel,
                  ns[k], rep.lobe_conv_rel_l2, prev_conv);
        prev = rep.rel_l2;
        prev_conv = rep.lobe_conv_rel_l2;
        sl_lobes_free(&out);
    }
    sl_envmap_free(&m);
}

TEST(envfit_shared_sun_map_error_falls_with_lobes) {
    if (!sl_test_shared_data()) SKIP("no ../shared/data");
    sweep("blender_rgbe/sunrise.hdr");
}

TEST(envfit_shared_sky_map_error_falls_with_lobes) {
    if (!sl_test_shared_data()) SKIP("no ../shared/data");
    sweep("pmndrs/venice.hdr");
}
