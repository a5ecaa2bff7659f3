/* viewer_ui.h: the C interface of the viewer's Dear ImGui panel (host/viewer/viewer_ui.cpp, the
 * only C++ of the viewer). The viewer fills an sl_ui_model with what the panel shows; the panel
 * returns what the user changed as `set KEY VALUE` edits and button presses, which the viewer
 * applies through the same functions as a script (host/viewer/viewer.h). Plain C types only, so the
 * C++ side never sees the renderer's headers. */
#ifndef SL_VIEWER_UI_H
#define SL_VIEWER_UI_H

#ifdef __cplusplus
extern "C" {
#endif

struct GLFWwindow;

#define SL_UI_MAX_PASSES 16
#define SL_UI_MAX_EDITS 24

typedef struct sl_ui_pass {
    char name[24];
    int state; /* 0 run, 1 cached, 2 skipped */
    char why[600];
    double seconds;
} sl_ui_pass;

typedef struct sl_ui_model {
    /* material (numerics.md sec. 2), degrees where the key says _deg */
    int model;   /* 0 marschner, 1 deon, 2 chiang */
    int fresnel; /* 0 exact, 1 schlick */
    int orders;
    double eta, alpha_deg[3], beta_deg[3], sigma_a[3];
    int has_melanin;
    double eumelanin, pheomelanin;
    double eccentricity, caustic_width_deg;
    /* model chiang: the Principled Hair parameters (sigma_a above when given instead) */
    int chiang_sigma; /* 1: the material gives sigma_a, not melanin / redness / tint */
    double melanin, melanin_redness, tint[3], roughness, radial_roughness, coat, offset_deg;
    /* quality */
    int lobes, layers, segments_m, voxels, oit_layers, ms; /* ms: 0 auto, 1 on, 2 off */
    double kappa;
    char shading_rate[32];
    /* environment, camera */
    double env_rotation_deg, env_intensity, fov_deg;
    /* brush */
    int paint_mode, depth_test, undo_steps;
    unsigned painted;
    float brush_radius, brush_sigma[3];
    /* read-only information */
    char device[256], upload_path[256], gl_version[128], status[256];
    int frame_w, frame_h, refined, strands, lobes_used;
    double t_full, t_preview, t_upload, t_draw;
    int npass;
    sl_ui_pass pass[SL_UI_MAX_PASSES];
    char save_path[1024]; /* edited in place */
} sl_ui_model;

typedef struct sl_ui_edit {
    char key[64];
    char value[96];
} sl_ui_edit;

typedef struct sl_ui_actions {
    int nedit;
    sl_ui_edit edit[SL_UI_MAX_EDITS];
    int reset_camera, undo, save, quit;
    char device[16]; /* a backend chosen in the panel ("auto", "pocl", "c"), "" if none */
} sl_ui_actions;

/* Sets up ImGui on the window (after the viewer's own GLFW callbacks, which ImGui chains). */
int sl_ui_init(struct GLFWwindow *win);
/* Builds the panel at x = panel_x (window pixels), fills `out` (zeroed first) and renders it
 * into the current back buffer. */
void sl_ui_frame(sl_ui_model *m, sl_ui_actions *out, int panel_x);
int sl_ui_wants_mouse(void);
int sl_ui_wants_keyboard(void);
void sl_ui_shutdown(void);

#ifdef __cplusplus
}
#endif

#endif
