/* camera.c: see camera.h. */
#include "scene/camera.h"

#include <math.h>

static void normalize(double v[3]) {
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0) v[0] /= l, v[1] /= l, v[2] /= l;
}

static void cross(const double a[3], const double b[3], double o[3]) {
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

void sl_camera_setup(sl_camera *c, const double *eye, const double target[3], const double up[3],
                     double fov_deg, int width, int height, const float lo[3], const float hi[3]) {
    double half = 0.5 * fov_deg * 3.14159265358979323846 / 180.0;
    c->width = width;
    c->height = height;
    c->focal = 0.5 * height / tan(half);
    if (eye) {
        for (int i = 0; i < 3; i++) c->eye[i] = eye[i];
    } else {
        /* Bounding sphere of the box around its centre, seen from target + d Z so that it fits the
         * narrower of the two fields of view with a 5 % margin. */
        double r = 0, ctr[3];
        for (int i = 0; i < 3; i++) {
            ctr[i] = 0.5 * (lo[i] + hi[i]);
            r += 0.25 * (hi[i] - lo[i]) * (hi[i] - lo[i]);
        }
        r = sqrt(r);
        double half_w = atan(tan(half) * width / height);
        double h = half < half_w ? half : half_w;
        double dist = 1.05 * r / sin(h);
        double dz = fabs(ctr[2] - target[2]);
        c->eye[0] = target[0];
        c->eye[1] = target[1];
        c->eye[2] = target[2] + dist + dz;
    }
    for (int i = 0; i < 3; i++) c->fwd[i] = target[i] - c->eye[i];
    normalize(c->fwd);
    cross(c->fwd, up, c->right);
    normalize(c->right);
    cross(c->right, c->fwd, c->up);
}

int sl_camera_project(const sl_camera *c, const double p[3], double *px, double *py, double *z) {
    double d[3] = {p[0] - c->eye[0], p[1] - c->eye[1], p[2] - c->eye[2]};
    double zz = d[0] * c->fwd[0] + d[1] * c->fwd[1] + d[2] * c->fwd[2];
    if (zz <= 1e-6) return 0;
    double x = d[0] * c->right[0] + d[1] * c->right[1] + d[2] * c->right[2];
    double y = d[0] * c->up[0] + d[1] * c->up[1] + d[2] * c->up[2];
    *px = 0.5 * c->width + c->focal * x / zz;
    *py = 0.5 * c->height - c->focal * y / zz;
    *z = zz;
    return 1;
}
