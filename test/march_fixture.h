/* march_fixture.h: the small march problem test_march.c and test_shadow_threads.c share: 300 wavy
 * strands of 12 points (seed 3) voxelized at 24, the default material (optionally with an
 * [r,g,b] sigma_a), its dual-scattering tables and the two lobe directions the march tests use.
 * Static inline: every test file includes it into the one unit_tests binary. */
#ifndef SL_TEST_MARCH_FIXTURE_H
#define SL_TEST_MARCH_FIXTURE_H

#include "test.h"

#include "passes/volume/dual.h"
#include "io/hair/hair.h"
#include "passes/volume/volume.h"

#include <string.h>

typedef struct march_wavy {
    sl_hair h;
    sl_voxel_grid g;
    sl_material m;
    sl_dual_tables dt;
    double dirs[6]; /* two unit directions: +y and (0.6, -0.48, 0.64) */
} march_wavy;

/* sigma_a_rgb: NULL keeps the default material's grey sigma_a. */
static inline void march_wavy_setup(march_wavy *w, const double sigma_a_rgb[3]) {
    sl_err e = {{0}};
    memset(w, 0, sizeof *w);
    sl_hair_procedural p = {SL_PROC_WAVY, 300, 12, 3};
    CHECK(sl_hair_generate(&p, &w->h, &e) == 0);
    CHECK(sl_voxelize(NULL, &w->h, 24, &w->g, &e) == 0);
    sl_material_default(&w->m);
    if (sigma_a_rgb) {
        w->m.sigma_a_rgb = 1;
        memcpy(w->m.sigma_a, sigma_a_rgb, 3 * sizeof *sigma_a_rgb);
    }
    CHECK(sl_dual_tables_build(&w->m, &w->dt, &e) == 0);
    static const double dirs[6] = {0, 1, 0, 0.6, -0.48, 0.64};
    memcpy(w->dirs, dirs, sizeof dirs);
}

static inline void march_wavy_free(march_wavy *w) {
    sl_voxel_grid_free(&w->g);
    sl_hair_free(&w->h);
}

#endif
