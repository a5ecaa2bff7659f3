/* test_auto_device.c: the pieces of `--device auto` on a CPU OpenCL device that do not depend on
 * timing (host/plan/auto_device.h): the proxy hair is every k-th strand of the scene's, point for
 * point (checked against the strands picked by index here), and the cache key separates every
 * input the choice depends on. Which path wins a trial is a measurement, never asserted; the
 * CLI test (test/cli/test_devices.sh) checks the trial's plumbing: explain row, notice, cache. */
#include "test.h"

#include "base/parallel.h"
#include "plan/auto_device.h"

#include <string.h>

static void make_hair(sl_hair *h, uint32_t strands) {
    sl_hair_procedural p = {.style = 1, .strands = strands, .points = 5, .seed = 3};
    sl_err e;
    CHECK(sl_hair_generate(&p, h, &e) == 0);
}

TEST(auto_proxy_hair_every_kth_strand) {
    sl_hair h;
    make_hair(&h, 1003);
    /* per-point colours present: they must follow their points */
    h.color = sl_malloc((size_t)h.num_points * 3 * sizeof *h.color);
    for (uint32_t i = 0; i < 3 * h.num_points; i++)
        h.color[i] = (float)i;
    sl_hair p;
    sl_auto_proxy_hair(&h, 400, &p);
    /* k = ceil(1003 / 400) = 3: strands 0, 3, ..., 1002 -> 335 strands */
    CHECK(p.num_strands == 335);
    uint32_t np = 0;
    for (uint32_t j = 0; j < p.num_strands; j++) {
        uint32_t i = 3 * j, a = h.strand_first[i], n = h.strand_first[i + 1] - a;
        CHECK(p.strand_first[j] == np);
        CHECK(p.strand_first[j + 1] - p.strand_first[j] == n);
        CHECK(memcmp(p.pos + 3 * (size_t)np, h.pos + 3 * (size_t)a, 3 * n * sizeof(float)) == 0);
        CHECK(memcmp(p.color + 3 * (size_t)np, h.color + 3 * (size_t)a, 3 * n * sizeof(float)) ==
              0);
        np += n;
    }
    CHECK(p.num_points == np && p.strand_first[p.num_strands] == np);
    CHECK(p.radius == NULL && p.transparency == NULL);
    CHECK(p.default_radius == h.default_radius);
    sl_hair_free(&p);
    /* at most max strands: a hair already small is copied whole */
    sl_auto_proxy_hair(&h, 5000, &p);
    CHECK(p.num_strands == h.num_strands && p.num_points == h.num_points);
    CHECK(memcmp(p.pos, h.pos, 3 * (size_t)h.num_points * sizeof(float)) == 0);
    sl_hair_free(&p);
    sl_hair_free(&h);
}

TEST(auto_key_separates_its_inputs) {
    static sl_scene s, t;
    sl_scene_default(&s);
    sl_hair h, h2;
    make_hair(&h, 100);
    make_hair(&h2, 101);
    static sl_lobe lb[3];
    sl_lobes l = {.count = 2, .lobe = lb}, l3 = {.count = 3, .lobe = lb};
    sl_render_opts ro, ro2;
    sl_render_opts_default(&ro);
    const char *dev = "PoCL|3.1|cpu|3.1";
    sl_cache_key k0 = sl_auto_device_key(dev, &s, &h, &l, &ro);
    sl_cache_key k;
#define DIFFERS(expr)                                                                              \
    do {                                                                                           \
        k = (expr);                                                                                \
        CHECK(k.a != k0.a);                                                                        \
    } while (0)
    /* the same inputs: the same key (a later run finds the entry) */
    k = sl_auto_device_key(dev, &s, &h, &l, &ro);
    CHECK(k.a == k0.a && k.b == k0.b);
    DIFFERS(sl_auto_device_key("PoCL|3.1|cpu|3.2", &s, &h, &l, &ro)); /* driver update */
    DIFFERS(sl_auto_device_key(dev, &s, &h2, &l, &ro));               /* strands */
    DIFFERS(sl_auto_device_key(dev, &s, &h, &l3, &ro));               /* lobes */
    t = s;
    t.width++;
    DIFFERS(sl_auto_device_key(dev, &t, &h, &l, &ro));
    t = s;
    t.multiple_scattering = !s.multiple_scattering;
    DIFFERS(sl_auto_device_key(dev, &t, &h, &l, &ro));
    t = s;
    snprintf(t.shading_rate, sizeof t.shading_rate, "fragment");
    DIFFERS(sl_auto_device_key(dev, &t, &h, &l, &ro));
    t = s;
    t.material.model = s.material.model + 1;
    DIFFERS(sl_auto_device_key(dev, &t, &h, &l, &ro));
    ro2 = ro;
    ro2.srbf_method = ro.srbf_method + 1;
    DIFFERS(sl_auto_device_key(dev, &s, &h, &l, &ro2));
    ro2 = ro;
    ro2.threads = sl_parallel_threads(0) == 1 ? 2 : 1;
    DIFFERS(sl_auto_device_key(dev, &s, &h, &l, &ro2));
#undef DIFFERS
    sl_hair_free(&h);
    sl_hair_free(&h2);
}

TEST(auto_settle_leaves_c_and_explicit_devices) {
    /* no trial where there is no choice: the C path, and a device opened by name (not auto) */
    static sl_scene s;
    sl_scene_default(&s);
    sl_hair h;
    make_hair(&h, 10);
    static sl_lobe lb[1];
    sl_lobes l = {.count = 1, .lobe = lb};
    sl_render_opts ro;
    sl_render_opts_default(&ro);
    float lo[3] = {-1, -1, -1}, hi[3] = {1, 1, 1};
    double tg[3] = {0, 0, 0};
    sl_device dev;
    sl_err e;
    sl_auto_choice ch;
    CHECK(sl_device_open("c", &dev, &e) == 0);
    sl_auto_device_settle(&dev, &s, &h, &l, lo, hi, tg, &ro, &ch);
    CHECK(ch.state == SL_AUTO_NONE && ch.why[0] == 0 && !dev.is_opencl);
    if (sl_device_open("opencl", &dev, &e) == 0) {
        sl_auto_device_settle(&dev, &s, &h, &l, lo, hi, tg, &ro, &ch);
        CHECK(ch.state == SL_AUTO_NONE && dev.is_opencl); /* explicit: kept, no trial */
        sl_device_close(&dev);
    }
    sl_hair_free(&h);
}
