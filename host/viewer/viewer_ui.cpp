// viewer_ui.cpp: the viewer's Dear ImGui panel (libimgui-dev 1.86, GLFW + OpenGL3 backends),
// behind the C interface of viewer_ui.h. It only shows an sl_ui_model and turns widget changes
// into `set KEY VALUE` edits, so every panel control has a script equivalent (docs/viewer.md).
#include "viewer/viewer_ui.h"

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <cstdio>
#include <cstring>

namespace {

void add_edit(sl_ui_actions *a, const char *key, const char *fmt, double v) {
    if (a->nedit >= SL_UI_MAX_EDITS) return;
    sl_ui_edit *e = &a->edit[a->nedit++];
    std::snprintf(e->key, sizeof e->key, "%s", key);
    std::snprintf(e->value, sizeof e->value, fmt, v);
}

void add_edit_str(sl_ui_actions *a, const char *key, const char *value) {
    if (a->nedit >= SL_UI_MAX_EDITS) return;
    sl_ui_edit *e = &a->edit[a->nedit++];
    std::snprintf(e->key, sizeof e->key, "%s", key);
    std::snprintf(e->value, sizeof e->value, "%s", value);
}

// A double drag widget bound to a scene key.
void dbl(sl_ui_actions *a, const char *label, const char *key, double *v, float speed, double lo,
         double hi) {
    if (ImGui::DragScalar(label, ImGuiDataType_Double, v, speed, &lo, &hi, "%.4g"))
        add_edit(a, key, "%.9g", *v);
}

void integer(sl_ui_actions *a, const char *label, const char *key, int *v, int lo, int hi) {
    if (ImGui::DragInt(label, v, 0.2f, lo, hi)) add_edit(a, key, "%.0f", *v);
}

void rgb(sl_ui_actions *a, const char *label, const char *key, double *v) {
    double lo = 0.0, hi = 50.0;
    if (ImGui::DragScalarN(label, ImGuiDataType_Double, v, 3, 0.01f, &lo, &hi, "%.3f")) {
        if (a->nedit >= SL_UI_MAX_EDITS) return;
        sl_ui_edit *e = &a->edit[a->nedit++];
        std::snprintf(e->key, sizeof e->key, "%s", key);
        std::snprintf(e->value, sizeof e->value, "[%.9g, %.9g, %.9g]", v[0], v[1], v[2]);
    }
}

// The marschner / deon keys: Fresnel, eta, the lobes' shifts and widths, absorption.
void lobe_panel(sl_ui_model *m, sl_ui_actions *a) {
    const char *fres[] = {"exact", "schlick"};
    if (ImGui::Combo("fresnel", &m->fresnel, fres, 2))
        add_edit_str(a, "material.fresnel", fres[m->fresnel]);
    dbl(a, "eta", "material.eta", &m->eta, 0.005f, 1.0001, 4.0);
    static const char *const ak[3] = {"material.alpha_R_deg", "material.alpha_TT_deg",
                                      "material.alpha_TRT_deg"};
    static const char *const bk[3] = {"material.beta_R_deg", "material.beta_TT_deg",
                                      "material.beta_TRT_deg"};
    static const char *const an[3] = {"alpha R", "alpha TT", "alpha TRT"};
    static const char *const bn[3] = {"beta R", "beta TT", "beta TRT"};
    for (int t = 0; t < 3; t++)
        dbl(a, an[t], ak[t], &m->alpha_deg[t], 0.1f, -45.0, 45.0);
    for (int t = 0; t < 3; t++)
        dbl(a, bn[t], bk[t], &m->beta_deg[t], 0.1f, 0.05, 60.0);
    if (m->has_melanin) {
        dbl(a, "eumelanin", "material.melanin.eumelanin", &m->eumelanin, 0.01f, 0.0, 20.0);
        dbl(a, "pheomelanin", "material.melanin.pheomelanin", &m->pheomelanin, 0.01f, 0.0, 20.0);
    } else {
        rgb(a, "sigma_a", "material.sigma_a", m->sigma_a);
    }
    dbl(a, "eccentricity", "material.eccentricity", &m->eccentricity, 0.005f, 0.5, 2.0);
    dbl(a, "w_c (deg)", "material.caustic_width_deg", &m->caustic_width_deg, 0.1f, 0.5, 60.0);
    if (m->model == 1) integer(a, "orders", "material.orders", &m->orders, 2, 32);
}

// Model chiang's keys (numerics.md sec. 2); sigma_a when the material gives it, else the
// pigments (editing either switches the document to it: viewer_doc.c keeps one of the two).
void chiang_panel(sl_ui_model *m, sl_ui_actions *a) {
    dbl(a, "eta", "material.eta", &m->eta, 0.005f, 1.0001, 4.0);
    if (m->chiang_sigma) {
        rgb(a, "sigma_a", "material.sigma_a", m->sigma_a);
    } else {
        dbl(a, "melanin", "material.melanin", &m->melanin, 0.005f, 0.0, 1.0);
        dbl(a, "redness", "material.melanin_redness", &m->melanin_redness, 0.005f, 0.0, 1.0);
        double lo = 0.001, hi = 1.0;
        if (ImGui::DragScalarN("tint", ImGuiDataType_Double, m->tint, 3, 0.005f, &lo, &hi,
                               "%.3f") &&
            a->nedit < SL_UI_MAX_EDITS) {
            sl_ui_edit *e = &a->edit[a->nedit++];
            std::snprintf(e->key, sizeof e->key, "material.tint");
            std::snprintf(e->value, sizeof e->value, "[%.9g, %.9g, %.9g]", m->tint[0], m->tint[1],
                          m->tint[2]);
        }
    }
    dbl(a, "roughness", "material.roughness", &m->roughness, 0.005f, 0.001, 1.0);
    dbl(a, "radial roughness", "material.radial_roughness", &m->radial_roughness, 0.005f, 0.001,
        1.0);
    dbl(a, "coat", "material.coat", &m->coat, 0.005f, 0.0, 0.999);
    dbl(a, "offset (deg)", "material.offset_deg", &m->offset_deg, 0.05f, -45.0, 45.0);
}

const char *state_name(int s) {
    return s == 0 ? "run" : s == 1 ? "cached" : "skipped";
}

} // namespace

extern "C" int sl_ui_init(struct GLFWwindow *win) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr; // no imgui.ini written into the working directory
    ImGui::StyleColorsDark();
    if (!ImGui_ImplGlfw_InitForOpenGL(win, true)) return -1;
    if (!ImGui_ImplOpenGL3_Init("#version 330 core")) return -1;
    return 0;
}

extern "C" void sl_ui_frame(sl_ui_model *m, sl_ui_actions *a, int panel_x) {
    std::memset(a, 0, sizeof *a);
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    ImGuiIO &io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2((float)panel_x, 0.0f));
    ImGui::SetNextWindowSize(ImVec2(io.DisplaySize.x - (float)panel_x, io.DisplaySize.y));
    ImGui::Begin("strandlight", nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
    ImGui::PushItemWidth(150.0f);

    ImGui::TextWrapped("%s", m->device);
    static const char *const backends[] = {"auto", "pocl", "c"};
    for (int i = 0; i < 3; i++) {
        if (i) ImGui::SameLine();
        if (ImGui::SmallButton(backends[i]))
            std::snprintf(a->device, sizeof a->device, "%s", backends[i]);
    }
    ImGui::TextWrapped("%s", m->upload_path);
    ImGui::Text("%dx%d %s  %d strands  %d lobes", m->frame_w, m->frame_h,
                m->refined ? "refined" : "preview", m->strands, m->lobes_used);
    ImGui::Text("frame %.0f ms  preview %.0f ms", 1e3 * m->t_full, 1e3 * m->t_preview);
    ImGui::Text("upload %.1f ms  draw %.1f ms", 1e3 * m->t_upload, 1e3 * m->t_draw);
    if (m->status[0]) ImGui::TextWrapped("%s", m->status);

    if (ImGui::CollapsingHeader("Material", ImGuiTreeNodeFlags_DefaultOpen)) {
        const char *models[] = {"marschner", "deon", "chiang"};
        if (ImGui::Combo("model", &m->model, models, 3))
            add_edit_str(a, "material.model", models[m->model]);
        if (m->model == 2) /* chiang: Blender's Principled Hair parameters */
            chiang_panel(m, a);
        else
            lobe_panel(m, a);
    }
    if (ImGui::CollapsingHeader("Quality", ImGuiTreeNodeFlags_DefaultOpen)) {
        integer(a, "lobes", "quality.lobes", &m->lobes, 1, 200);
        integer(a, "layers", "quality.layers", &m->layers, 1, 16);
        integer(a, "m (segments)", "quality.segments_m", &m->segments_m, 1, 16);
        dbl(a, "kappa", "quality.kappa", &m->kappa, 0.01f, 0.05, 8.0);
        integer(a, "voxels", "quality.voxels", &m->voxels, 8, 256);
        integer(a, "oit layers", "quality.oit_layers", &m->oit_layers, 1, 32);
        const char *ms[] = {"auto", "on", "off"};
        if (ImGui::Combo("multiple scattering", &m->ms, ms, 3))
            add_edit_str(a, "quality.multiple_scattering", ms[m->ms]);
        const char *rates[] = {"auto", "fragment", "vertex"};
        int rate = std::strcmp(m->shading_rate, "fragment") == 0     ? 1
                   : std::strncmp(m->shading_rate, "vertex", 6) == 0 ? 2
                                                                     : 0;
        if (ImGui::Combo("shading rate", &rate, rates, 3))
            add_edit_str(a, "quality.shading_rate", rates[rate]);
    }
    if (ImGui::CollapsingHeader("Camera and environment", ImGuiTreeNodeFlags_DefaultOpen)) {
        dbl(a, "env rotation", "environment.rotation_deg", &m->env_rotation_deg, 0.5f, -360.0,
            360.0);
        dbl(a, "env intensity", "environment.intensity", &m->env_intensity, 0.01f, 0.0, 100.0);
        dbl(a, "fov (deg)", "camera.fov_deg", &m->fov_deg, 0.2f, 1.0, 120.0);
        if (ImGui::Button("reset camera (R)")) a->reset_camera = 1;
        ImGui::TextDisabled("drag: orbit  right/middle: pan  wheel: zoom");
    }
    if (ImGui::CollapsingHeader("Paint", ImGuiTreeNodeFlags_DefaultOpen)) {
        bool pm = m->paint_mode != 0, dt = m->depth_test != 0;
        if (ImGui::Checkbox("brush on left drag (P)", &pm)) m->paint_mode = pm;
        if (ImGui::Checkbox("depth test", &dt)) m->depth_test = dt;
        ImGui::DragFloat("radius (px)", &m->brush_radius, 0.2f, 1.0f, 200.0f);
        ImGui::DragFloat3("brush sigma_a", m->brush_sigma, 0.01f, 0.0f, 50.0f);
        ImGui::Text("%u strands painted, %d undo steps", m->painted, m->undo_steps);
        if (ImGui::Button("undo (Ctrl+Z)")) a->undo = 1;
    }
    if (ImGui::CollapsingHeader("Plan", ImGuiTreeNodeFlags_DefaultOpen)) {
        for (int i = 0; i < m->npass && i < SL_UI_MAX_PASSES; i++) {
            const sl_ui_pass *p = &m->pass[i];
            ImGui::Text("%-8s %-7s %7.1f ms", p->name, state_name(p->state), 1e3 * p->seconds);
            ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
            ImGui::TextWrapped("  %s", p->why);
            ImGui::PopStyleColor();
        }
    }
    ImGui::InputText("##save", m->save_path, sizeof m->save_path);
    ImGui::SameLine();
    if (ImGui::Button("save")) a->save = 1;
    ImGui::PopItemWidth();
    ImGui::End();
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

extern "C" int sl_ui_wants_mouse(void) {
    return ImGui::GetIO().WantCaptureMouse;
}
extern "C" int sl_ui_wants_keyboard(void) {
    return ImGui::GetIO().WantCaptureKeyboard;
}

extern "C" void sl_ui_shutdown(void) {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
}
