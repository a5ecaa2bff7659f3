/* viewer_input.c: mouse, keyboard and drag-and-drop of the viewer window, turned into the
 * viewer's operations (host/viewer/viewer.h). Left drag orbits (or paints in paint mode), right or
 * middle drag pans, the wheel zooms; keys: R reset, arrows orbit, +/- zoom, [ ] rotate the
 * environment, Ctrl+Z undo, P paint mode, Esc quit. Events the ImGui panel takes are ignored. */
#include "viewer/viewer_input.h"

#include "viewer/viewer_ui.h"

#include <math.h>
#include <string.h>

static sl_vinput *from(GLFWwindow *w) {
    return (sl_vinput *)glfwGetWindowUserPointer(w);
}

static void status_err(sl_viewer *v, const sl_err *e) {
    snprintf(v->status, sizeof v->status, "%.250s", e->msg);
}

static void on_scroll(GLFWwindow *w, double dx, double dy) {
    (void)dx;
    sl_vinput *in = from(w);
    if (in->ui && sl_ui_wants_mouse()) return;
    sl_viewer_zoom(in->v, pow(1.1, dy));
}

static void on_key(GLFWwindow *w, int key, int scancode, int action, int mods) {
    (void)scancode;
    sl_vinput *in = from(w);
    sl_viewer *v = in->v;
    if (action == GLFW_RELEASE || (in->ui && sl_ui_wants_keyboard())) return;
    sl_err e = {{0}};
    switch (key) {
    case GLFW_KEY_R:
        sl_viewer_reset(v);
        break;
    case GLFW_KEY_LEFT:
        sl_viewer_orbit(v, -5, 0);
        break;
    case GLFW_KEY_RIGHT:
        sl_viewer_orbit(v, 5, 0);
        break;
    case GLFW_KEY_UP:
        sl_viewer_orbit(v, 0, 5);
        break;
    case GLFW_KEY_DOWN:
        sl_viewer_orbit(v, 0, -5);
        break;
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD:
        sl_viewer_zoom(v, 1.1);
        break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT:
        sl_viewer_zoom(v, 1.0 / 1.1);
        break;
    case GLFW_KEY_LEFT_BRACKET:
        if (sl_viewer_env_rotate(v, -5, &e)) status_err(v, &e);
        break;
    case GLFW_KEY_RIGHT_BRACKET:
        if (sl_viewer_env_rotate(v, 5, &e)) status_err(v, &e);
        break;
    case GLFW_KEY_Z:
        if (mods & GLFW_MOD_CONTROL) sl_viewer_undo(v);
        break;
    case GLFW_KEY_P:
        v->paint_mode = !v->paint_mode;
        break;
    case GLFW_KEY_ESCAPE:
        v->quit = 1;
        break;
    default:
        break;
    }
}

static void on_drop(GLFWwindow *w, int n, const char **paths) {
    sl_vinput *in = from(w);
    for (int i = 0; i < n; i++) {
        sl_err e = {{0}};
        if (sl_viewer_drop(in->v, paths[i], &e))
            status_err(in->v, &e);
        else
            snprintf(in->v->status, sizeof in->v->status, "loaded %s", paths[i]);
    }
}

void sl_vinput_install(sl_vinput *in, sl_viewer *v, sl_viewer_gl *g) {
    memset(in, 0, sizeof *in);
    in->v = v;
    in->g = g;
    glfwSetWindowUserPointer(g->win, in);
    glfwSetScrollCallback(g->win, on_scroll);
    glfwSetKeyCallback(g->win, on_key);
    glfwSetDropCallback(g->win, on_drop);
}

void sl_vinput_poll(sl_vinput *in) {
    sl_viewer *v = in->v;
    GLFWwindow *w = in->g->win;
    double x, y;
    glfwGetCursorPos(w, &x, &y);
    int left = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    int pan = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
              glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS;
    int down = left || pan;
    if (down && !in->dragging) {
        /* a drag belongs to whoever it started on: the panel or the image */
        in->dragging = 1;
        in->drag_ui = in->ui && sl_ui_wants_mouse();
        in->stroke_open = 0;
        in->lx = x;
        in->ly = y;
    }
    if (!down) {
        in->dragging = 0;
        return;
    }
    if (in->drag_ui) return;
    double dx = x - in->lx, dy = y - in->ly;
    in->lx = x;
    in->ly = y;
    if (left && v->paint_mode) {
        double ix, iy;
        if (!sl_vgl_to_image(in->g, x, y, &ix, &iy)) return;
        sl_err e = {{0}};
        long hits =
            sl_viewer_paint_at(v, ix, iy, v->brush_radius, v->brush_sigma, in->stroke_open, &e);
        if (hits < 0) status_err(v, &e);
        if (hits > 0) in->stroke_open = 1;
        return;
    }
    if (dx == 0 && dy == 0) return;
    if (left)
        sl_viewer_orbit(v, -0.4 * dx, 0.4 * dy);
    else
        sl_viewer_pan(v, dx, dy);
}
