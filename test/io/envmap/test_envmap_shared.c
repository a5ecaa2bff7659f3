/* test_envmap_shared.c: every environment map in ../shared/data/envmaps (SKIP when absent) and
 * the shipped default map. Expected numbers are copied from ../shared/data/README.md ("measured
 * statistics" table, computed there by tools/verify_data.py, an independent Python decoder). */
#include "io/envmap/envmap.h"
#include "test.h"

#include <string.h>

typedef struct map_case {
    const char *rel;
    int w, h;
    long negatives;      /* README "Negative values" */
    double y_mean_pixel; /* README "Y mean (pixel)"; 0 = not compared (see below) */
    int max_x, max_y;    /* README "Brightest px" */
} map_case;

/* npm_exr maps: the README mean is of the raw values; their large negative ringing (down to
 * -3394 around the sun of sky.exr) is clamped to 0 by the loader, which raises the mean, so the
 * means are not compared there. */
static const map_case cases[] = {
    {"envmaps/blender_exr/city.exr", 1024, 512, 506, 1.0545, 614, 120},
    {"envmaps/blender_exr/courtyard.exr", 1024, 512, 1818, 0.5387, 956, 214},
    {"envmaps/blender_exr/forest.exr", 1024, 512, 784, 0.5446, 613, 199},
    {"envmaps/blender_exr/interior.exr", 1024, 512, 8980, 0.9725, 465, 108},
    {"envmaps/blender_exr/night.exr", 1024, 512, 829, 0.1407, 289, 237},
    {"envmaps/blender_exr/studio.exr", 1024, 512, 3, 0.2549, 709, 234},
    {"envmaps/blender_exr/sunrise.exr", 1024, 512, 596, 0.4861, 614, 233},
    {"envmaps/blender_exr/sunset.exr", 1024, 512, 5, 0.4248, 614, 246},
    {"envmaps/blender_rgbe/city.hdr", 1024, 512, 0, 1.0513, 614, 120},
    {"envmaps/blender_rgbe/courtyard.hdr", 1024, 512, 0, 0.5365, 956, 214},
    {"envmaps/blender_rgbe/forest.hdr", 1024, 512, 0, 0.5427, 613, 199},
    {"envmaps/blender_rgbe/interior.hdr", 1024, 512, 0, 0.9691, 465, 108},
    {"envmaps/blender_rgbe/night.hdr", 1024, 512, 0, 0.1402, 289, 237},
    {"envmaps/blender_rgbe/studio.hdr", 1024, 512, 0, 0.2543, 709, 234},
    {"envmaps/blender_rgbe/sunrise.hdr", 1024, 512, 0, 0.4846, 614, 233},
    {"envmaps/blender_rgbe/sunset.hdr", 1024, 512, 0, 0.4231, 614, 246},
    {"envmaps/pmndrs/sky.hdr", 1024, 512, 0, 0.6740, 609, 119},
    {"envmaps/pmndrs/venice.hdr", 1024, 512, 0, 0.5955, 439, 224},
    {"envmaps/pmndrs/dawn.hdr", 1024, 512, 0, 0.6974, 646, 245},
    {"envmaps/pmndrs/npm_exr/sky.exr", 512, 256, 33, 0, 304, 59},
    {"envmaps/pmndrs/npm_exr/venice.exr", 512, 256, 446, 0, 219, 112},
    {"envmaps/pmndrs/npm_exr/dawn.exr", 512, 256, 406, 0, 320, 122},
};

TEST(envdata_every_shared_map) {
    const char *dir = sl_test_shared_data();
    if (!dir) SKIP("../shared/data not present");
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const map_case *c = &cases[i];
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", dir, c->rel);
        sl_envmap m;
        sl_err e;
        /* clamp_nonfinite = 0: a NaN/Inf would make the load fail. */
        if (sl_envmap_load(path, 0, &m, &e)) {
            CHECK_MSG(0, "%s", e.msg);
            continue;
        }
        CHECK_MSG(m.width == c->w && m.height == c->h, "%s: %d x %d", c->rel, m.width, m.height);
        CHECK_MSG(m.nonfinite == 0, "%s", c->rel);
        CHECK_MSG(m.negatives == c->negatives, "%s: %ld negatives, README %ld", c->rel, m.negatives,
                  c->negatives);
        CHECK(strstr(m.format, sl_ext_is(path, "exr") ? "(DWAB)" : "Radiance") != NULL);
        sl_envmap_stats s;
        sl_envmap_stats_compute(&m, &s);
        /* README rounds to 4-5 significant digits: 1e-3 relative covers the rounding. */
        if (c->y_mean_pixel > 0) CHECK_REL(s.lum_mean_pixel, c->y_mean_pixel, 1e-3);
        /* The brightest pixel pins orientation (no flip or shift of rows/columns). */
        CHECK_MSG(s.max_x == c->max_x && s.max_y == c->max_y, "%s: brightest (%d, %d)", c->rel,
                  s.max_x, s.max_y);
        sl_envmap_free(&m);
    }
}

TEST(envdata_exr_and_hdr_copies_agree) {
    const char *dir = sl_test_shared_data();
    if (!dir) SKIP("../shared/data not present");
    static const char *names[] = {"city",  "courtyard", "forest",  "interior",
                                  "night", "studio",    "sunrise", "sunset"};
    for (int i = 0; i < 8; i++) {
        char pe[1024], ph[1024];
        snprintf(pe, sizeof pe, "%s/envmaps/blender_exr/%s.exr", dir, names[i]);
        snprintf(ph, sizeof ph, "%s/envmaps/blender_rgbe/%s.hdr", dir, names[i]);
        sl_envmap a, b;
        sl_err e;
        if (sl_envmap_load(pe, 0, &a, &e) || sl_envmap_load(ph, 0, &b, &e)) {
            CHECK_MSG(0, "%s", e.msg);
            continue;
        }
        sl_envmap_stats sa, sb;
        sl_envmap_stats_compute(&a, &sa);
        sl_envmap_stats_compute(&b, &sb);
        /* Per-channel means over the sphere: the RGBE copy truncates mantissas (README: about
         * 0.3 % low) and drops channels below 1/256 of the pixel maximum; 2 % covers both. */
        for (int c = 0; c < 3; c++)
            CHECK_REL(sb.rgb_mean_solid_angle[c], sa.rgb_mean_solid_angle[c], 0.02);
        /* ... and the copy is below, never above, by more than rounding. */
        CHECK_MSG(sb.lum_mean_solid_angle <= sa.lum_mean_solid_angle * 1.0005, "%s", names[i]);
        sl_envmap_free(&a);
        sl_envmap_free(&b);
    }
}

TEST(envdata_default_map) {
    sl_envmap m;
    sl_err e;
    CHECK_MSG(sl_envmap_load("data/env/city_256.hdr", 0, &m, &e) == 0, "%s", e.msg);
    if (!m.rgb) return;
    CHECK(m.width == 256 && m.height == 128);
    CHECK(m.nonfinite == 0 && m.negatives == 0);
    sl_envmap_stats s;
    sl_envmap_stats_compute(&m, &s);
    /* Energy-preserving downsample of city: the mean radiance over the sphere equals the source
     * EXR's, README "Y mean (solid angle)" 0.9600, to within RGBE rounding and the README's
     * midpoint weights (0.1 %). */
    CHECK_REL(s.lum_mean_solid_angle, 0.9600, 1e-3);
    /* The sun: README (614, 120) at 1024x512 lands in 4x4 block (153, 30). */
    CHECK(s.max_x == 153 && s.max_y == 30);
    CHECK(s.max_elev_deg > 40 && s.max_elev_deg < 55);
    sl_envmap_free(&m);
}
