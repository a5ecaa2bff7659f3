/* viewer_camera.c: the viewer's camera controls (orbit, pan, zoom, reset) and environment
 * rotation. The camera is eye / target / up, turned into an sl_camera per frame size, so a
 * preview at half resolution sees exactly what the refined frame sees. */
#include "viewer/viewer.h"

#include <math.h>
#include <stdio.h>

#define DEG (3.14159265358979323846 / 180.0)

/* Rotates p about the unit axis a by angle t (Rodrigues). */
static void rotate(double p[3], const double a[3], double t) {
    double c = cos(t), s = sin(t), d = a[0] * p[0] + a[1] * p[1] + a[2] * p[2];
    double x[3] = {a[1] * p[2] - a[2] * p[1], a[2] * p[0] - a[0] * p[2], a[0] * p[1] - a[1] * p[0]};
    for (int k = 0; k < 3; k++)
        p[k] = p[k] * c + x[k] * s + a[k] * d * (1.0 - c);
}

static void changed(sl_viewer *v) {
    v->dirty = 1;
    v->refined = 0;
}

void sl_viewer_camera(const sl_viewer *v, int w, int h, sl_camera *cam) {
    sl_camera_setup(cam, v->eye, v->target, v->up, v->scene.fov_deg, w, h, v->lo, v->hi);
}

void sl_viewer_orbit(sl_viewer *v, double yaw_deg, double pitch_deg) {
    double d[3] = {v->eye[0] - v->target[0], v->eye[1] - v->target[1], v->eye[2] - v->target[2]};
    /* yaw about +Y: the same rotation as `render --orbit` (eye' = R_y(angle) (eye - target)) */
    static const double y_axis[3] = {0, 1, 0};
    rotate(d, y_axis, yaw_deg * DEG);
    rotate(v->up, y_axis, yaw_deg * DEG);
    if (pitch_deg != 0.0) {
        sl_camera c;
        sl_viewer_camera(v, v->scene.width, v->scene.height, &c);
        /* about the right axis; stop short of the poles so up stays usable */
        double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        double el = asin(fmax(-1.0, fmin(1.0, d[1] / len)));
        double lim = 85.0 * DEG, t = pitch_deg * DEG;
        if (el + t > lim) t = lim - el;
        if (el + t < -lim) t = -lim - el;
        rotate(d, c.right, -t);
    }
    for (int k = 0; k < 3; k++)
        v->eye[k] = v->target[k] + d[k];
    changed(v);
}

void sl_viewer_pan(sl_viewer *v, double dx, double dy) {
    sl_camera c;
    sl_viewer_camera(v, v->scene.width, v->scene.height, &c);
    double dist = 0;
    for (int k = 0; k < 3; k++)
        dist += (v->eye[k] - v->target[k]) * (v->eye[k] - v->target[k]);
    /* one pixel at the target's depth is dist / focal world units; content moves with the mouse,
     * so the camera moves the other way */
    double s = sqrt(dist) / c.focal;
    for (int k = 0; k < 3; k++) {
        double m = (-dx * c.right[k] + dy * c.up[k]) * s;
        v->eye[k] += m;
        v->target[k] += m;
    }
    changed(v);
}

void sl_viewer_zoom(sl_viewer *v, double f) {
    if (!(f > 0) || !isfinite(f)) return;
    for (int k = 0; k < 3; k++)
        v->eye[k] = v->target[k] + (v->eye[k] - v->target[k]) / f;
    changed(v);
}

void sl_viewer_reset(sl_viewer *v) {
    for (int k = 0; k < 3; k++) {
        v->eye[k] = v->home_eye[k];
        v->target[k] = v->home_target[k];
        v->up[k] = v->home_up[k];
    }
    changed(v);
}

int sl_viewer_env_rotate(sl_viewer *v, double deg, sl_err *e) {
    double r = fmod(v->scene.env_rotation_deg + deg, 360.0);
    char buf[64];
    snprintf(buf, sizeof buf, "%.17g", r);
    return sl_viewer_set(v, "environment.rotation_deg", buf, e);
}
