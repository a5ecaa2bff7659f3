/* auto_device.c: the auto choice between a CPU OpenCL device and the C path (auto_device.h). */
#include "plan/auto_device.h"

#include "base/parallel.h"
#include "scene/scene_inputs.h"

#include <stdlib.h>
#include <string.h>

void sl_auto_proxy_hair(const sl_hair *h, uint32_t max_strands, sl_hair *out) {
    *out = *h;
    uint32_t k = max_strands ? (h->num_strands + max_strands - 1) / max_strands : 1;
    if (k < 1) k = 1;
    uint32_t ns = (h->num_strands + k - 1) / k, np = 0;
    for (uint32_t i = 0; i < h->num_strands; i += k)
        np += h->strand_first[i + 1] - h->strand_first[i];
    sl_hair_alloc(out, ns, np);
    out->radius = h->radius ? sl_malloc((size_t)np * sizeof *out->radius) : NULL;
    out->transparency = h->transparency ? sl_malloc((size_t)np * sizeof *out->transparency) : NULL;
    out->color = h->color ? sl_malloc((size_t)np * 3 * sizeof *out->color) : NULL;
    uint32_t o = 0, j = 0;
    for (uint32_t i = 0; i < h->num_strands; i += k, j++) {
        uint32_t a = h->strand_first[i], n = h->strand_first[i + 1] - a;
        out->strand_first[j] = o;
        memcpy(out->pos + 3 * (size_t)o, h->pos + 3 * (size_t)a, 3 * (size_t)n * sizeof *h->pos);
        if (h->radius) memcpy(out->radius + o, h->radius + a, n * sizeof *h->radius);
        if (h->transparency)
            memcpy(out->transparency + o, h->transparency + a, n * sizeof *h->transparency);
        if (h->color)
            memcpy(out->color + 3 * (size_t)o, h->color + 3 * (size_t)a, 3 * n * sizeof *h->color);
        o += n;
    }
    out->strand_first[ns] = o;
    out->guide_strands = ns;
}

sl_cache_key sl_auto_device_key(const char *device_identity, const sl_scene *s, const sl_hair *h,
                                const sl_lobes *lobes, const sl_render_opts *ro) {
    char shape[1400];
    /* everything the relative speed of the two paths depends on; the values exactly, so a
     * different scene size is measured afresh (a trial costs two small frames) */
    snprintf(shape, sizeof shape,
             "auto-device 1|%s|strands %u|points %u|lobes %d|%dx%d|model %d|ms %d|rate %s|broad %d|"
             "method %d|threads %d|layers %d|voxels %d|oit %d|shadow %d/%d|refine %g|sharp %d",
             device_identity, h->num_strands, h->num_points, lobes->count, s->width, s->height,
             (int)s->material.model, s->multiple_scattering, s->shading_rate, s->broad_lobes,
             ro->srbf_method, sl_parallel_threads(ro->threads), s->layers, s->voxels, s->oit_layers,
             s->shadow_size, ro->shadow_size, s->shading_refine, s->sharp_shadows);
    sl_cache_key k = {sl_cache_hash(shape, strlen(shape)), 0};
    return k;
}

typedef struct choice_rec {
    uint32_t picked_c;
    uint32_t pad;
    double t_c, t_cl;
} choice_rec;

/* One frame of (s, h) at w x h pixels on dev with a fresh renderer; its seconds, or -1 when it
 * failed (dev may then have fallen back to the C path). */
static double proxy_frame(sl_device *dev, const sl_scene *s0, const sl_hair *h,
                          const sl_lobes *lobes, const float lo[3], const float hi[3],
                          const double target[3], const sl_render_opts *ro0, int w, int hgt) {
    sl_scene *s = sl_malloc(sizeof *s);
    *s = *s0;
    s->width = w;
    s->height = hgt;
    sl_render_opts ro = *ro0;
    ro.quiet = 1;
    ro.frames = 1;
    /* no table build inside a trial: it would be paid by whichever side runs first */
    if (ro.srbf_method == SL_RENDER_SRBF_AUTO) ro.srbf_method = SL_SRBF_METHOD_FAST;
    double t[3] = {target[0], target[1], target[2]};
    sl_camera cam;
    sl_scene_camera(s, lo, hi, w, hgt, t, &cam);
    sl_renderer *r = sl_renderer_create(dev, &ro);
    sl_fbuf fb;
    sl_err e;
    double t0 = sl_now();
    int rc = sl_renderer_frame(r, s, h, lobes, &cam, &fb, &e);
    double dt = sl_now() - t0;
    if (rc == 0) sl_fbuf_free(&fb);
    sl_renderer_free(r);
    free(s);
    return rc == 0 ? dt : -1.0;
}

static void cache_entry(const sl_device *dev, const sl_scene *s, const sl_hair *h,
                        const sl_lobes *lobes, const sl_render_opts *ro, char *path, size_t n) {
    char dir[4096], id[1200];
    path[0] = 0;
    if (!sl_cache_dir_find(dir, sizeof dir)) return;
    sl_cl_identity(dev->cl, id, sizeof id);
    if (!sl_cache_path(path, n, dir, "auto-device", sl_auto_device_key(id, s, h, lobes, ro),
                       SL_AUTO_CACHE_FORMAT))
        path[0] = 0;
}

void sl_auto_device_settle(sl_device *dev, const sl_scene *s, const sl_hair *h,
                           const sl_lobes *lobes, const float lo[3], const float hi[3],
                           const double target[3], const sl_render_opts *ro, sl_auto_choice *out) {
    memset(out, 0, sizeof *out);
    if (!dev->is_opencl || !sl_device_may_fallback(dev)) return;
    char label[256];
    snprintf(label, sizeof label, "%s", dev->name);
    if (sl_cl_is_gpu(dev->cl)) {
        snprintf(out->why, sizeof out->why, "auto: %s, a GPU device: used without a trial", label);
        return;
    }
    double t0 = sl_now();
    int faults = sl_cl_fault() != SL_CL_FAULT_NONE; /* simulated faults must reach the device */
    char path[4600] = "";
    char id[1200];
    sl_cl_identity(dev->cl, id, sizeof id);
    sl_cache_key key = sl_auto_device_key(id, s, h, lobes, ro);
    if (!faults) cache_entry(dev, s, h, lobes, ro, path, sizeof path);
    void *data = NULL;
    size_t size = 0;
    if (path[0] &&
        sl_cache_read(path, SL_AUTO_CACHE_FORMAT, key, sizeof(choice_rec), &data, &size, NULL) ==
            0 &&
        size == sizeof(choice_rec)) {
        choice_rec c;
        memcpy(&c, data, sizeof c);
        free(data);
        out->state = SL_AUTO_CACHED;
        out->picked_c = c.picked_c != 0;
        out->t_c = c.t_c;
        out->t_cl = c.t_cl;
    } else {
        free(data);
        /* the warm-up: a tiny frame builds (or loads) the device's programs and lets PoCL
         * generate each kernel's code, once per process, outside the timed frames */
        sl_hair tiny, proxy;
        sl_auto_proxy_hair(h, 50, &tiny);
        sl_auto_proxy_hair(h, SL_AUTO_PROXY_STRANDS, &proxy);
        int pw = s->width > 16 ? s->width / 2 : s->width,
            ph = s->height > 16 ? s->height / 2 : s->height;
        double warm = proxy_frame(dev, s, &tiny, lobes, lo, hi, target, ro, 32, 24);
        double tcl = warm >= 0 && dev->is_opencl
                         ? proxy_frame(dev, s, &proxy, lobes, lo, hi, target, ro, pw, ph)
                         : -1.0;
        sl_hair_free(&tiny);
        if (tcl < 0 || !dev->is_opencl) {
            sl_hair_free(&proxy);
            out->state = SL_AUTO_FAILED;
            out->seconds = sl_now() - t0;
            snprintf(out->why, sizeof out->why, "auto: the trial frame failed on %s: %s (%.3f s)",
                     label,
                     dev->is_opencl ? "kept, the render will report the error"
                                    : "fell back to the C path",
                     out->seconds);
            return;
        }
        sl_device cdev;
        sl_err ce;
        sl_device_open("c", &cdev, &ce); /* "c" cannot fail */
        double tc = proxy_frame(&cdev, s, &proxy, lobes, lo, hi, target, ro, pw, ph);
        sl_device_close(&cdev);
        sl_hair_free(&proxy);
        out->state = SL_AUTO_MEASURED;
        out->t_c = tc;
        out->t_cl = tcl;
        out->picked_c = tc >= 0 && tc < tcl;
        if (path[0] && tc >= 0) {
            choice_rec c = {(uint32_t)out->picked_c, 0, tc, tcl};
            sl_cache_part part = {&c, sizeof c};
            sl_err we; /* a cache that cannot be written only costs the next run a trial */
            sl_cache_write(path, SL_AUTO_CACHE_FORMAT, key, &part, 1, 0, &we);
        }
    }
    out->seconds = sl_now() - t0;
    int nstr =
        h->num_strands < SL_AUTO_PROXY_STRANDS ? (int)h->num_strands : (int)SL_AUTO_PROXY_STRANDS;
    snprintf(out->why, sizeof out->why,
             "auto on a CPU OpenCL device: %s (%s %.3f s, C path %.3f s per frame of a proxy: ~%d "
             "strands, half the image%s)",
             out->picked_c ? "C path, faster here" : "kept the device, faster here", label,
             out->t_cl, out->t_c, nstr,
             out->state == SL_AUTO_CACHED ? "; measured before, from the disk cache"
             : path[0]                    ? "; measured now, cached"
                                          : "; measured now, no disk cache");
    if (out->picked_c) sl_device_close(dev);
    sl_note("device: %s", out->why);
}
