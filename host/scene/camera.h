/* camera.h: a pinhole camera from the scene's eye/target/up/fov (vertical field of view), and
 * automatic framing of a bounding box along -Z when the scene omits camera.eye (scene.md). */
#ifndef SL_CAMERA_H
#define SL_CAMERA_H

typedef struct sl_camera {
    double eye[3];
    double right[3], up[3], fwd[3]; /* orthonormal; fwd points from the eye into the scene */
    double focal;                   /* pixels: height / (2 tan(fov/2)) */
    int width, height;
} sl_camera;

/* eye == NULL frames the box [lo, hi] from `target` looking along -Z. */
void sl_camera_setup(sl_camera *c, const double *eye, const double target[3], const double up[3],
                     double fov_deg, int width, int height, const float lo[3], const float hi[3]);

/* Projects a world point: pixel coordinates (x right, y down, pixel centres at +0.5) and the
 * view depth z along fwd. Returns 0 when the point is behind the near plane. */
int sl_camera_project(const sl_camera *c, const double p[3], double *px, double *py, double *z);

#endif
