/* viewer_render.c: opens the viewer's inputs and renders its frames with the frame pipeline
 * (host/plan/frame.h). Two renderers keep their own caches: "preview" (half size, the strongest
 * SL_VIEWER_PREVIEW_LOBES lobes, vertex shading, no multiple scattering) while something
 * changes, "full" (the scene's own settings, identical to `strandlight render`) once it stops. */
#include "viewer/viewer.h"

#include "base/json_util.h"
#include "viewer/viewer_gl.h"

#include <stdlib.h>
#include <string.h>

int sl_viewer_open(sl_viewer *v, const char *scene_path, const char *device, int size_w, int size_h,
                   sl_err *e) {
    memset(v, 0, sizeof *v);
    snprintf(v->scene_path, sizeof v->scene_path, "%s", scene_path);
    v->size_w = size_w;
    v->size_h = size_h;
    v->device_spec = device;
    v->brush_radius = 12.0f;
    v->brush_sigma[0] = 0.05f, v->brush_sigma[1] = 0.6f, v->brush_sigma[2] = 2.0f;
    v->brush_depth_test = 1;
    unsigned char *text = NULL;
    size_t len = 0;
    if (sl_read_file(scene_path, &text, &len, 64u << 20, e)) return -1;
    v->doc = sl_json_parse((const char *)text, len, scene_path, e);
    free(text);
    if (!v->doc) return -1;
    if (sl_viewer_parse_doc(v, e)) return -1;
    if (sl_device_open(device, &v->dev, e)) return -1;
    v->have_dev = 1;
    if (sl_viewer_load_hair(v, e) || sl_viewer_load_lobes(v, e)) return -1;
    sl_viewer_camera_from_scene(v);
    sl_render_opts o;
    sl_render_opts_default(&o);
    o.quiet = 1;
    v->full = sl_renderer_create(&v->dev, &o);
    v->preview = sl_renderer_create(&v->dev, &o);
    v->have_renderers = 1;
    v->dirty = 1;
    return 0;
}

void sl_viewer_close(sl_viewer *v) {
    if (v->have_renderers) {
        sl_renderer_free(v->full);
        sl_renderer_free(v->preview);
    }
    sl_fbuf_free(&v->shown);
    sl_fbuf_free(&v->last_full);
    sl_paint_free(&v->paint);
    sl_lobes_free(&v->lobes_raw);
    sl_lobes_free(&v->lobes);
    sl_lobes_free(&v->lobes_preview);
    sl_hair_free(&v->hair);
    if (v->have_dev) sl_device_close(&v->dev);
    cJSON_Delete(v->doc);
    v->doc = NULL;
}

int sl_viewer_set_device(sl_viewer *v, const char *spec, sl_err *e) {
    sl_device nd = {0};
    if (sl_device_open(spec, &nd, e)) return -1;
    if (v->gl) sl_vgl_release_cl(v->gl);
    sl_renderer_free(v->full);
    sl_renderer_free(v->preview);
    sl_device_close(&v->dev);
    v->dev = nd;
    sl_render_opts o;
    sl_render_opts_default(&o);
    o.quiet = 1;
    v->full = sl_renderer_create(&v->dev, &o);
    v->preview = sl_renderer_create(&v->dev, &o);
    if (v->gl) sl_vgl_interop(v->gl, &v->dev);
    v->paint.applied_key = 0; /* the new renderers hold no paint yet */
    v->dirty = 1;
    v->refined = 0;
    return 0;
}

/* Hands the paint layer to both renderers when it changed since they last got it. */
static int apply_paint(sl_viewer *v, sl_err *e) {
    float *sa = sl_viewer_paint_array(v);
    uint64_t key = 1;
    if (sa) {
        key = sl_hash64(sa, 3 * (size_t)v->hair.num_strands * sizeof *sa, 7);
        key |= 2; /* never 1 (= "none") and never 0 (= "not applied yet") */
    }
    int rc = 0;
    if (key != v->paint.applied_key) {
        uint32_t n = sa ? v->hair.num_strands : 0;
        rc = sl_renderer_set_strand_sigma_a(v->full, sa, n, e) ||
             sl_renderer_set_strand_sigma_a(v->preview, sa, n, e);
        if (!rc) v->paint.applied_key = key;
    }
    free(sa);
    return rc ? -1 : 0;
}

static void copy_fbuf(const sl_fbuf *src, sl_fbuf *dst) {
    sl_fbuf_free(dst);
    size_t n = (size_t)src->width * src->height;
    dst->width = src->width;
    dst->height = src->height;
    dst->rgba = sl_malloc(4 * n * sizeof(float));
    memcpy(dst->rgba, src->rgba, 4 * n * sizeof(float));
    dst->depth = sl_malloc(n * sizeof(float));
    memcpy(dst->depth, src->depth, n * sizeof(float));
}

int sl_viewer_render(sl_viewer *v, sl_err *e) {
    if (!v->dirty && v->refined) return 0;
    if (apply_paint(v, e)) return -1;
    int preview = v->dirty;
    sl_scene *s = sl_malloc(sizeof *s);
    *s = v->scene;
    const sl_lobes *lobes = &v->lobes;
    sl_renderer *r = v->full;
    if (preview) {
        s->width = s->width > 1 ? s->width / 2 : 1;
        s->height = s->height > 1 ? s->height / 2 : 1;
        s->multiple_scattering = SL_MS_OFF;
        snprintf(s->shading_rate, sizeof s->shading_rate, "vertex");
        lobes = &v->lobes_preview;
        r = v->preview;
    }
    sl_camera cam;
    sl_viewer_camera(v, s->width, s->height, &cam);
    sl_fbuf fb;
    double t0 = sl_now();
    sl_renderer_set_editing(r, preview); /* while dragging: fast, never a table build */
    int rc = sl_renderer_frame(r, s, &v->hair, lobes, &cam, &fb, e);
    free(s);
    if (rc) return -1;
    double dt = sl_now() - t0;
    sl_fbuf_free(&v->shown);
    v->shown = fb;
    v->shown_preview = preview;
    if (preview) {
        v->t_preview = dt;
        v->npreview++;
        v->dirty = 0;
        v->refined = 0;
    } else {
        v->t_full = dt;
        v->nfull++;
        v->refined = 1;
        copy_fbuf(&fb, &v->last_full);
        v->last_full_cam = cam;
    }
    return 1;
}

const sl_renderer *sl_viewer_shown_renderer(const sl_viewer *v) {
    return v->shown_preview ? v->preview : v->full;
}
