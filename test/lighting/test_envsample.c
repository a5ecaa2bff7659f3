/* test_envsample.c: median-cut directional lights (envsample.h). */
#include "lighting/envfit.h"
#include "lighting/envsample.h"
#include "test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void map_fill(sl_envmap *m, int w, int h) {
    memset(m, 0, sizeof *m);
    m->width = w;
    m->height = h;
    m->rgb = calloc((size_t)w * h * 3, sizeof(float));
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 3; c++)
                m->rgb[((size_t)y * w + x) * 3 + c] =
                    (float)(1 + 0.5 * sin(0.1 * x * (c + 1)) + (y < h / 3 ? 2 : 0));
}

/* Independent: sum of radiance x exact pixel solid angle. */
static void map_power(const sl_envmap *m, double P[3]) {
    P[0] = P[1] = P[2] = 0;
    for (int y = 0; y < m->height; y++) {
        double om =
            2 * M_PI / m->width * (cos(M_PI * y / m->height) - cos(M_PI * (y + 1) / m->height));
        for (int x = 0; x < m->width; x++)
            for (int c = 0; c < 3; c++)
                P[c] += om * m->rgb[((size_t)y * m->width + x) * 3 + c];
    }
}

TEST(envsample_conserves_power_and_stratifies) {
    sl_envmap m;
    map_fill(&m, 128, 64);
    double P[3];
    map_power(&m, P);
    sl_envlights L;
    double rel, conv;
    sl_err e;
    CHECK(sl_envsample(&m, 100, 10 * M_PI / 180, 2, &L, &rel, &conv, &e) == 0);
    CHECK(L.count == 100);
    double S[3] = {0, 0, 0}, pmin = 1e300, pmax = 0, sa = 0;
    for (int i = 0; i < L.count; i++) {
        const sl_envlight *l = &L.light[i];
        CHECK_NEAR(l->dir[0] * l->dir[0] + l->dir[1] * l->dir[1] + l->dir[2] * l->dir[2], 1, 1e-12);
        double p = l->rgb[0] + l->rgb[1] + l->rgb[2];
        for (int c = 0; c < 3; c++)
            S[c] += l->rgb[c];
        pmin = fmin(pmin, p);
        pmax = fmax(pmax, p);
        sa += l->solid_angle;
        if (i) CHECK(p <= L.light[i - 1].rgb[0] + L.light[i - 1].rgb[1] + L.light[i - 1].rgb[2]);
    }
    /* The regions partition the sphere and the map's power: exact up to round-off. */
    for (int c = 0; c < 3; c++)
        CHECK_REL(S[c], P[c], 1e-9);
    CHECK_REL(sa, 4 * M_PI, 1e-9);
    /* Median cut with N not a power of two: regions one split apart differ by 2x, and each
     * split is at the median only to within one pixel column or row (~1.5x at 128x64). */
    CHECK_MSG(pmax < 4.5 * pmin, "powers %.4g .. %.4g", pmin, pmax);
    CHECK_MSG(rel > 0 && rel < 0.3, "rel %.5g", rel);
    /* 100 lights are ~20 degrees apart, coarser than the 10-degree lobe: ripples of ~30 %. */
    CHECK_MSG(conv > 0 && conv < 0.5, "conv %.5g", conv);
    sl_envlights_free(&L);
    free(m.rgb);
}

TEST(envsample_errors_fall_with_more_lights_and_find_the_sun) {
    sl_envmap m;
    map_fill(&m, 128, 64);
    /* A sun: one pixel 10^4 x the sky. */
    int sx = 40, sy = 20;
    for (int c = 0; c < 3; c++)
        m.rgb[((size_t)sy * 128 + sx) * 3 + c] = 2e4f;
    double prev = INFINITY;
    int ns[] = {16, 64, 256};
    for (int k = 0; k < 3; k++) {
        sl_envlights L;
        double rel, conv;
        sl_err e;
        CHECK(sl_envsample(&m, ns[k], 10 * M_PI / 180, 2, &L, &rel, &conv, &e) == 0);
        CHECK_MSG(conv < prev, "N=%d: conv %.5g after %.5g", ns[k], conv, prev);
        prev = conv;
        /* The most powerful light is the sun pixel, at its centre's direction. */
        double d[3];
        sl_envmap_dir(128, 64, sx, sy, d);
        CHECK_NEAR(L.light[0].dir[0] * d[0] + L.light[0].dir[1] * d[1] + L.light[0].dir[2] * d[2],
                   1, 1e-9);
        sl_envlights_free(&L);
    }
    free(m.rgb);
}

TEST(envsample_file_round_trip_and_errors) {
    sl_envmap m;
    map_fill(&m, 32, 16);
    sl_envlights L, R;
    sl_err e;
    CHECK(sl_envsample(&m, 7, 0.2, 1, &L, NULL, NULL, &e) == 0);
    L.record_json = strdup("{\"map_hash\":\"ab\"}");
    char path[4096];
    snprintf(path, sizeof path, "%s/lights_rt.json", sl_test_tmpdir());
    CHECK(sl_envlights_save(path, &L, &e) == 0);
    CHECK(sl_envlights_load(path, &R, &e) == 0);
    CHECK(R.count == 7);
    for (int i = 0; i < 7 && R.count == 7; i++)
        for (int c = 0; c < 3; c++)
            CHECK_REL(R.light[i].rgb[c], L.light[i].rgb[c], 1e-8);
    CHECK(R.record_json && strstr(R.record_json, "map_hash"));
    sl_envlights_free(&R);
    sl_envlights_free(&L);
    FILE *f = fopen(path, "w");
    fputs("{\"lights\": [{\"dir\": [0,1,0], \"rgb\": [1,-2,0]}]}", f);
    fclose(f);
    CHECK(sl_envlights_load(path, &R, &e) == -1);
    CHECK(strstr(e.msg, "lights[0].rgb[1]") != NULL);
    free(m.rgb);
}
