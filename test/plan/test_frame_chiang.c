/* test_frame_chiang.c: frames of a model chiang material (host/plan/frame.h, shaded by the d'Eon
 * fast path's Chiang azimuth, kernels/srbf_chiang.h): the C path against OpenCL, the invariants
 * of Chiang's lobes in the frame (R, A_0 = f, does not see sigma_a; more absorption only darkens
 * TT and TRT), the multiple-scattering pass skipped with its reason, and xu refused.
 * The SRBF values themselves are test/passes/shade/test_srbf_chiang.c's. */
#include "test.h"

#include "cl_fixture.h"

#include "frame_fixture.h"

#include <stdlib.h>
#include <string.h>

/* The tiny scene with a chiang material (parsed from JSON, as a scene file gives it). */
static int chiang_tiny(frame_tiny *t, int strands, const char *json) {
    if (frame_tiny_setup(t, strands)) return -1;
    sl_err e = {{0}};
    int rc = sl_material_parse(json, strlen(json), "test", &t->s.material, &e);
    CHECK_MSG(rc == 0, "%s", e.msg);
    return rc;
}

static sl_renderer *quiet_renderer(sl_device *dev) {
    sl_render_opts o;
    sl_render_opts_default(&o);
    o.quiet = 1;
    return sl_renderer_create(dev, &o);
}

/* The same chiang frame on the C path and on OpenCL (PoCL here): everything but the SRBF
 * kernel is shared or bit-identical (test_frame.c, frame_c_vs_opencl), and the kernel is the
 * C twin's float header, so only device math ulps differ: max |difference| <= 1e-3 x the
 * brightest pixel, as for Marschner (a missing lobe or a wrong argument is > 1e-2). */
TEST(frame_chiang_c_vs_opencl) {
    sl_device cl = {0};
    sl_err e;
    SL_TEST_OPEN_CL(&cl, &e);
    frame_tiny t;
    CHECK(chiang_tiny(&t, 150,
                      "{\"model\": \"chiang\", \"melanin\": 0.3, \"radial_roughness\": 0.35}") ==
          0);
    sl_device c = {0};
    CHECK(sl_device_open("c", &c, &e) == 0);
    sl_renderer *rc = quiet_renderer(&c), *ro = quiet_renderer(&cl);
    sl_fbuf a, b;
    CHECK(frame_tiny_render(rc, &t, &a) == 0);
    unsigned long k0 = sl_cl_kernels_enqueued();
    CHECK(frame_tiny_render(ro, &t, &b) == 0);
    CHECK_CL_RAN(k0);
    const sl_pass_rec *sh = sl_renderer_pass(ro, "shade");
    CHECK(sh && strstr(sh->why, "on OpenCL") != NULL);
    double mx, md = frame_max_diff(&a, &b, &mx);
    CHECK(mx > 0);
    CHECK_MSG(md <= 1e-3 * mx, "max diff %g of max %g", md, mx);
    sl_fbuf_free(&a);
    sl_fbuf_free(&b);
    sl_renderer_free(rc);
    sl_renderer_free(ro);
    sl_device_close(&c);
    sl_device_close(&cl);
    frame_tiny_free(&t);
}

/* Chiang's R is the Fresnel reflection alone (A_0 = f), so a frame with ten times the
 * absorption has the same R AOV to the bit (the shared RGB evaluation computes R once, with no
 * sigma_a in it), and TT and TRT never brighten; they darken on most covered pixels. The
 * multiple-scattering pass runs (chiang has its own dual-scattering terms; this test expected
 * it skipped before) and the SRBF pass names the path. The AOVs compared are R, TT and TRT,
 * which multiple scattering does not touch. */
TEST(frame_chiang_lobes_and_plan) {
    frame_tiny t;
    sl_device dev = {0};
    sl_err e;
    CHECK(chiang_tiny(&t, 150, "{\"model\": \"chiang\", \"sigma_a\": [0.1, 0.2, 0.4]}") == 0);
    CHECK(sl_device_open("c", &dev, &e) == 0);
    t.s.multiple_scattering = SL_MS_ON;
    sl_renderer *r = quiet_renderer(&dev);
    sl_fbuf a, b;
    CHECK(frame_tiny_render(r, &t, &a) == 0);
    const sl_pass_rec *ms = sl_renderer_pass(r, "ms"), *sr = sl_renderer_pass(r, "srbf");
    CHECK(ms && ms->state == SL_PASS_RUN);
    /* one frame: a table build would not pay off, so the d'Eon fast path shades */
    CHECK(sr && strstr(sr->why, "auto: fast") != NULL &&
          sl_renderer_srbf_used(r) == SL_SRBF_METHOD_FAST);
    for (int k = 0; k < 3; k++)
        t.s.material.sigma_a[k] *= 10.0;
    CHECK(frame_tiny_render(r, &t, &b) == 0);
    size_t n = (size_t)a.width * a.height, darker = 0, covered = 0;
    int r_same = 1, brighter = 0;
    for (size_t i = 0; i < n; i++) {
        r_same &= memcmp(a.mode[0] + 3 * i, b.mode[0] + 3 * i, 3 * sizeof(float)) == 0;
        if (a.rgba[4 * i + 3] <= 0.05f) continue;
        covered++;
        for (int m = 1; m <= 2; m++)
            for (int c = 0; c < 3; c++) {
                float x = a.mode[m][3 * i + c], y = b.mode[m][3 * i + c];
                brighter |= y > x * (1.0f + 1e-6f) + 1e-9f;
            }
        darker += b.mode[1][3 * i] + b.mode[2][3 * i] < a.mode[1][3 * i] + a.mode[2][3 * i];
    }
    CHECK(r_same);
    CHECK(!brighter);
    CHECK(covered > 50);
    CHECK_MSG(darker > covered / 2, "%zu of %zu covered pixels darker", darker, covered);
    sl_fbuf_free(&a);
    sl_fbuf_free(&b);
    sl_renderer_free(r);
    frame_tiny_close(&t, &dev);
}

/* Xu's closed form is the Marschner model's: a chiang frame with --method xu is an error that
 * names the model, not a silent switch of method. (Ren's table exists for chiang too, baked from
 * its own fast path: test_frame_table.c, frame_table_chiang_image_vs_fast.) */
TEST(frame_chiang_refuses_xu) {
    frame_tiny t;
    sl_device dev = {0};
    sl_err e;
    CHECK(chiang_tiny(&t, 40, "{\"model\": \"chiang\"}") == 0);
    CHECK(sl_device_open("c", &dev, &e) == 0);
    sl_render_opts o;
    sl_render_opts_default(&o);
    o.quiet = 1;
    o.srbf_method = SL_SRBF_METHOD_XU;
    sl_renderer *r = sl_renderer_create(&dev, &o);
    sl_fbuf fb;
    e.msg[0] = 0;
    CHECK(sl_renderer_frame(r, &t.s, &t.h, &t.l, &t.cam, &fb, &e) != 0);
    CHECK_MSG(strstr(e.msg, "model chiang") != NULL, "%s", e.msg);
    sl_renderer_free(r);
    frame_tiny_close(&t, &dev);
}
