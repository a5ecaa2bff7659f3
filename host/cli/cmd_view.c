/* cmd_view.c: `strandlight view SCENE.json` (issue 11, docs/viewer.md): the interactive viewer.
 * Opens the window (viewer_gl.c), the scene and its renderers (viewer_render.c), the ImGui panel
 * (viewer_ui.cpp) and runs the event loop, or a --script. Rendering runs in the main thread
 * between events: a cheap preview while anything changes, the refined frame once it stops. */
#include "cli/cli.h"
#include "scene/scene_inputs.h"
#include "viewer/viewer.h"
#include "viewer/viewer_gl.h"
#include "viewer/viewer_input.h"
#include "viewer/viewer_ui.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *usage_text =
    "usage: strandlight view SCENE.json [options]\n"
    "\n"
    "Interactive viewer (docs/viewer.md): orbit (left drag, arrows), pan (right/middle drag),\n"
    "zoom (wheel, +/-), reset (R), environment rotation ([ ]), drop a hair file or an\n"
    "environment map on the window, edit every material and quality setting in the panel, paint\n"
    "sigma_a on strands (P toggles the brush on left drag; Ctrl+Z undoes), save the scene.\n"
    "Options:\n"
    "  --script FILE   run the commands of FILE (set, orbit, pan, zoom, reset, env_rotate,\n"
    "                  paint, brush_depth, device, undo, drop, wait, screenshot,\n"
    "                  screenshot_window, save, explain, stats, quit; docs/viewer.md)\n"
    "                  and exit at its end\n"
    "  --size WxH      image size (default: image.width/height of the scene)\n"
    "  --device SPEC   auto|gpu|pocl|c|opencl|P:D (default auto)\n"
    "Needs an X display (DISPLAY); without one, use `strandlight render`.\n";

typedef struct view_app {
    sl_viewer v;
    sl_viewer_gl g;
    sl_vinput in;
    sl_ui_model m;
    int ui;
} view_app;

static void fill_model(const view_app *a, sl_ui_model *m) {
    const sl_viewer *v = &a->v;
    const sl_scene *s = &v->scene;
    const sl_material *mt = &s->material;
    const double deg = 180.0 / 3.14159265358979323846;
    char save[sizeof m->save_path];
    memcpy(save, m->save_path, sizeof save);
    memset(m, 0, sizeof *m);
    memcpy(m->save_path, save, sizeof save);
    m->model = mt->model;
    m->fresnel = mt->fresnel;
    m->orders = mt->orders;
    m->eta = mt->eta;
    for (int t = 0; t < 3; t++) {
        m->alpha_deg[t] = mt->alpha[t] * deg;
        m->beta_deg[t] = mt->beta[t] * deg;
        m->sigma_a[t] = mt->sigma_a[t];
    }
    const cJSON *mat = cJSON_GetObjectItemCaseSensitive(v->doc, "material");
    const cJSON *mel = mat ? cJSON_GetObjectItemCaseSensitive(mat, "melanin") : NULL;
    if (cJSON_IsObject(mel)) {
        m->has_melanin = 1;
        const cJSON *eu = cJSON_GetObjectItemCaseSensitive(mel, "eumelanin");
        const cJSON *ph = cJSON_GetObjectItemCaseSensitive(mel, "pheomelanin");
        m->eumelanin = cJSON_IsNumber(eu) ? eu->valuedouble : 0.0;
        m->pheomelanin = cJSON_IsNumber(ph) ? ph->valuedouble : 0.0;
    }
    const sl_chiang *ch = &mt->chiang;
    m->chiang_sigma = ch->sigma_a_given;
    m->melanin = ch->melanin;
    m->melanin_redness = ch->melanin_redness;
    for (int t = 0; t < 3; t++)
        m->tint[t] = ch->tint[t];
    m->roughness = ch->roughness;
    m->radial_roughness = ch->radial_roughness;
    m->coat = ch->coat;
    m->offset_deg = ch->offset * deg;
    m->eccentricity = mt->eccentricity;
    m->caustic_width_deg = mt->caustic_width * deg;
    m->lobes = s->lobes;
    m->layers = s->layers;
    m->segments_m = s->segments_m;
    m->voxels = s->voxels;
    m->oit_layers = s->oit_layers;
    m->ms = s->multiple_scattering;
    m->kappa = s->kappa;
    snprintf(m->shading_rate, sizeof m->shading_rate, "%s", s->shading_rate);
    m->env_rotation_deg = s->env_rotation_deg;
    m->env_intensity = s->env_intensity;
    m->fov_deg = s->fov_deg;
    m->paint_mode = v->paint_mode;
    m->depth_test = v->brush_depth_test;
    m->undo_steps = v->paint.nundo;
    m->painted = v->paint.nset;
    m->brush_radius = v->brush_radius;
    memcpy(m->brush_sigma, v->brush_sigma, sizeof m->brush_sigma);
    snprintf(m->device, sizeof m->device, "device: %.240s", v->dev.name);
    snprintf(m->upload_path, sizeof m->upload_path, "display: %.230s", a->g.upload_path);
    snprintf(m->gl_version, sizeof m->gl_version, "%s", a->g.gl_version);
    snprintf(m->status, sizeof m->status, "%s", v->status);
    m->frame_w = v->shown.width;
    m->frame_h = v->shown.height;
    m->refined = !v->shown_preview;
    m->strands = (int)v->hair.num_strands;
    const sl_renderer *r = sl_viewer_shown_renderer(v);
    m->lobes_used = sl_renderer_lobes_used(r);
    m->t_full = v->t_full;
    m->t_preview = v->t_preview;
    m->t_upload = a->g.t_upload;
    m->t_draw = a->g.t_draw;
    int npass = sl_renderer_npass(r);
    m->npass = npass < SL_UI_MAX_PASSES ? npass : SL_UI_MAX_PASSES;
    for (int i = 0; i < m->npass; i++) {
        const sl_pass_rec *p = sl_renderer_pass_at(r, i);
        snprintf(m->pass[i].name, sizeof m->pass[i].name, "%s", p->name);
        snprintf(m->pass[i].why, sizeof m->pass[i].why, "%s", p->why);
        m->pass[i].state = p->state;
        m->pass[i].seconds = p->seconds;
    }
}

static void apply_actions(view_app *a, const sl_ui_model *m, const sl_ui_actions *act) {
    sl_viewer *v = &a->v;
    v->paint_mode = m->paint_mode;
    v->brush_depth_test = m->depth_test;
    v->brush_radius = m->brush_radius > 1.0f ? m->brush_radius : 1.0f;
    memcpy(v->brush_sigma, m->brush_sigma, sizeof v->brush_sigma);
    snprintf(v->save_path, sizeof v->save_path, "%s", m->save_path);
    for (int i = 0; i < act->nedit; i++) {
        sl_err e = {{0}};
        if (sl_viewer_set(v, act->edit[i].key, act->edit[i].value, &e))
            snprintf(v->status, sizeof v->status, "%.250s", e.msg);
        else
            v->status[0] = 0;
    }
    if (act->device[0]) {
        sl_err e = {{0}};
        if (sl_viewer_set_device(v, act->device, &e))
            snprintf(v->status, sizeof v->status, "%.250s", e.msg);
    }
    if (act->reset_camera) sl_viewer_reset(v);
    if (act->undo) sl_viewer_undo(v);
    if (act->save) {
        sl_err e = {{0}};
        if (sl_viewer_save(v, v->save_path, &e))
            snprintf(v->status, sizeof v->status, "%.250s", e.msg);
        else
            snprintf(v->status, sizeof v->status, "saved %.240s", v->save_path);
    }
    if (act->quit) v->quit = 1;
}

/* Draws image + panel into the back buffer, optionally reads it back, and swaps. */
static int present(view_app *a, const char *shot, sl_err *e) {
    double t0 = sl_now();
    sl_vgl_draw(&a->g, a->v.scene.width, a->v.scene.height);
    if (a->ui) {
        int fw, fh;
        glfwGetFramebufferSize(a->g.win, &fw, &fh);
        sl_ui_actions act;
        fill_model(a, &a->m);
        sl_ui_frame(&a->m, &act, fw - SL_VIEWER_PANEL_W);
        apply_actions(a, &a->m, &act);
    }
    int rc = shot ? sl_vgl_screenshot(&a->g, shot, 1, e) : 0;
    glfwSwapBuffers(a->g.win);
    a->v.t_present = sl_now() - t0;
    return rc;
}

static view_app *app_of(sl_viewer *v) {
    return (view_app *)((char *)v - offsetof(view_app, v));
}

/* Polls events, renders what is due, uploads and repaints; with until_refined, repeats until
 * the refined frame of the current inputs is on screen. */
static int step(sl_viewer *v, int until_refined, sl_err *e) {
    view_app *a = app_of(v);
    for (;;) {
        glfwPollEvents();
        sl_vinput_poll(&a->in);
        if (glfwWindowShouldClose(a->g.win)) v->quit = 1;
        int r = sl_viewer_render(v, e);
        if (r < 0) return -1;
        if (r > 0 && sl_vgl_upload(&a->g, &v->shown, e)) return -1;
        if (present(a, NULL, e)) return -1;
        if (!until_refined || v->quit || (v->refined && !v->dirty)) return 0;
    }
}

static int screenshot(sl_viewer *v, const char *path, int whole_window, sl_err *e) {
    view_app *a = app_of(v);
    if (whole_window) return present(a, path, e);
    return sl_vgl_screenshot(&a->g, path, 0, e);
}

static int parse_size(const char *s, long *w, long *h) {
    char *end;
    *w = strtol(s, &end, 10);
    if (end == s || (*end != 'x' && *end != 'X')) return -1;
    const char *p = end + 1;
    *h = strtol(p, &end, 10);
    if (end == p || *end || *w < 1 || *h < 1 || *w > 16384 || *h > 16384) return -1;
    return 0;
}

int cmd_view(int argc, char **argv) {
    const char *scene_path = NULL, *script = NULL, *device = "auto", *size = NULL;
    int missing = 0;
    long w = 0, h = 0;
    for (int i = 1; i < argc; i++) {
        if (cli_is_help(argv[i])) {
            fputs(usage_text, stdout);
            return 0;
        } else if (cli_opt(argc, argv, &i, "--script", &script, &missing) ||
                   cli_opt(argc, argv, &i, "--device", &device, &missing) ||
                   cli_opt(argc, argv, &i, "--size", &size, &missing)) {
            if (missing) return 2;
        } else if (argv[i][0] == '-') {
            return cli_usage_error("view", "unknown option %s", argv[i]);
        } else if (!scene_path) {
            scene_path = argv[i];
        } else {
            return cli_usage_error("view", "more than one scene given");
        }
    }
    if (!scene_path) return cli_usage_error("view", "no scene file given");
    if (size && parse_size(size, &w, &h))
        return cli_usage_error("view", "--size: expected WxH (1..16384), got \"%s\"", size);

    sl_err e = {{0}};
    view_app *a = sl_calloc(1, sizeof *a);
    int rc = 1, have_gl = 0, have_v = 0;
    /* the scene first (its errors beat a missing display), then the window, then the inputs */
    sl_scene_inputs in;
    sl_scene_inputs_opts io = {.width = (int)w, .height = (int)h};
    int src = sl_scene_inputs_open(scene_path, &io, &in, &e);
    int iw = src ? 0 : in.scene->width, ih = src ? 0 : in.scene->height;
    sl_scene_inputs_free(&in);
    if (src) goto done;
    if (sl_vgl_open(&a->g, iw, ih, &e)) goto done;
    have_gl = 1;
    have_v = 1;
    if (sl_viewer_open(&a->v, scene_path, device, (int)w, (int)h, &e)) goto done;
    a->v.gl = &a->g;
    snprintf(a->m.save_path, sizeof a->m.save_path, "%s", "out/view_scene.json");
    sl_vgl_interop(&a->g, &a->v.dev);
    sl_vinput_install(&a->in, &a->v, &a->g);
    if (sl_ui_init(a->g.win)) {
        sl_fail(&e, "view: cannot start the ImGui panel");
        goto done;
    }
    a->ui = a->in.ui = 1;
    sl_viewer_host host = {step, screenshot};
    if (script) {
        if (sl_viewer_run_script(&a->v, script, &host, &e)) goto done;
    } else {
        while (!a->v.quit && !glfwWindowShouldClose(a->g.win)) {
            /* idle with the refined frame on screen: sleep until an event (or 250 ms) */
            if (a->v.refined && !a->v.dirty) glfwWaitEventsTimeout(0.25);
            if (step(&a->v, 0, &e)) {
                /* a frame the renderer refuses (e.g. a setting it does not support) is shown
                 * in the panel; the viewer stays up so the setting can be changed back */
                snprintf(a->v.status, sizeof a->v.status, "%.250s", e.msg);
                a->v.dirty = 0;
                a->v.refined = 1;
            }
        }
    }
    rc = 0;
done:
    if (rc) fprintf(stderr, "strandlight: %s\n", e.msg);
    if (a->ui) sl_ui_shutdown();
    if (have_v) sl_viewer_close(&a->v);
    if (have_gl) sl_vgl_close(&a->g);
    free(a);
    return rc;
}
