/* test_path_env.c: the path tracer's environment (cpu/reference/env_ref.h): radiance by
 * direction in numerics.md sec. 4's frame, rotated as the lobes are (sl_lobes_transform), and
 * importance sampling whose density is what it reports, integrates to 1 and matches the
 * samples (chi-square over the pixels). */
#include "test.h"

#include "env_ref.h"
#include "io/envmap/envmap.h"
#include "path_rng.h"
#include "scene/env_lighting.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { W = 16, H = 8 };

static void test_map(float *rgb) {
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            float *p = rgb + 3 * (y * W + x);
            p[0] = (float)(1 + x), p[1] = (float)(1 + y), p[2] = (x + y) % 3 == 0 ? 0.0f : 2.0f;
        }
    for (int c = 0; c < 3; c++)
        rgb[3 * (2 * W + 5) + c] = 0; /* one black pixel: never sampled */
}

TEST(path_env_radiance_and_rotation) {
    float rgb[W * H * 3];
    test_map(rgb);
    slref_env env;
    slref_env_build(&env, rgb, W, H, 0, 2.0);
    int bad = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double d[3], l[3];
            sl_envmap_dir(W, H, x, y, d); /* the pixel's centre */
            slref_env_radiance(&env, d, l);
            for (int c = 0; c < 3; c++)
                bad += l[c] != 2.0 * rgb[3 * (y * W + x) + c];
        }
    CHECK_MSG(bad == 0, "%d radiance values differ from the pixel's x intensity", bad);
    slref_env_free(&env);
    /* rotation 70 deg: a lobe placed at a pixel's centre moves where the radiance moves */
    slref_env_build(&env, rgb, W, H, 70.0, 1.0);
    sl_lobe lobe;
    memset(&lobe, 0, sizeof lobe);
    sl_lobes lobes = {.count = 1, .lobe = &lobe};
    sl_envmap_dir(W, H, 3, 2, lobe.dir);
    sl_lobes_transform(&lobes, 70.0, 1.0);
    double l[3];
    slref_env_radiance(&env, lobe.dir, l);
    CHECK(l[0] == rgb[3 * (2 * W + 3)] && l[1] == rgb[3 * (2 * W + 3) + 1]);
    slref_env_free(&env);
}

TEST(path_env_sampling_density) {
    float rgb[W * H * 3];
    test_map(rgb);
    slref_env env;
    slref_env_build(&env, rgb, W, H, 25.0, 3.0);
    /* the density per solid angle integrates to 1 over the pixels */
    double tot = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double d[3], m[3];
            sl_envmap_dir(W, H, x, y, m);
            double c = cos(25.0 * M_PI / 180), s = sin(25.0 * M_PI / 180);
            d[0] = c * m[0] + s * m[2], d[1] = m[1], d[2] = -s * m[0] + c * m[2];
            tot += slref_env_pdf(&env, d) * sl_envmap_pixel_solid_angle(W, H, y);
        }
    CHECK_NEAR(tot, 1.0, 1e-12);
    enum { NS = 200000 };
    static int cnt[W * H];
    memset(cnt, 0, sizeof cnt);
    slref_rng g;
    slref_rng_seed(&g, 4, 5, 6);
    double worst = 0;
    int off_map = 0;
    for (int k = 0; k < NS; k++) {
        double u[4], d[3], l[3], l2[3];
        for (int i = 0; i < 4; i++)
            u[i] = slref_rng_unit(&g);
        double p = slref_env_sample(&env, u, d, l);
        worst = fmax(worst, fabs(p - slref_env_pdf(&env, d)) / p);
        slref_env_radiance(&env, d, l2);
        off_map += l[0] != l2[0] || l[1] != l2[1] || l[2] != l2[2];
        /* which pixel: undo the rotation, envmap.h's inverse mapping */
        double c = cos(25.0 * M_PI / 180), s = sin(25.0 * M_PI / 180), m[3], x, y;
        m[0] = c * d[0] - s * d[2], m[1] = d[1], m[2] = s * d[0] + c * d[2];
        sl_envmap_dir_to_pixel(W, H, m, &x, &y);
        int ix = ((int)floor(x + 0.5) + W) % W, iy = (int)floor(y + 0.5);
        cnt[(iy < 0 ? 0 : (iy >= H ? H - 1 : iy)) * W + ix]++;
    }
    CHECK_MSG(worst < 1e-12, "sampled density differs from slref_env_pdf by %g", worst);
    CHECK_MSG(off_map == 0, "%d samples' radiance differs from the lookup", off_map);
    CHECK(cnt[2 * W + 5] == 0);
    double chi = 0;
    int dof = -1;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double d[3];
            sl_envmap_dir(W, H, x, y, d);
            double lum = 0.2126 * rgb[3 * (y * W + x)] + 0.7152 * rgb[3 * (y * W + x) + 1] +
                         0.0722 * rgb[3 * (y * W + x) + 2];
            double ex = lum * sl_envmap_pixel_solid_angle(W, H, y) / env.total * NS;
            if (ex <= 0) continue;
            chi += (cnt[y * W + x] - ex) * (cnt[y * W + x] - ex) / ex, dof++;
        }
    /* dof + 5 sqrt(2 dof): a normal approximation's 3e-7 tail; fixed seed */
    CHECK_MSG(chi < dof + 5 * sqrt(2.0 * dof), "chi2 %.1f, dof %d", chi, dof);
    slref_env_free(&env);
    /* a black map: nothing to sample, density 0 */
    float black[W * H * 3] = {0};
    slref_env_build(&env, black, W, H, 0, 1);
    double u[4] = {0.5, 0.5, 0.5, 0.5}, d[3], l[3];
    CHECK(slref_env_sample(&env, u, d, l) == 0 && slref_env_pdf(&env, u) == 0);
    slref_env_free(&env);
}
