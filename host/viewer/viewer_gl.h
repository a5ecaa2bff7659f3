/* viewer_gl.h: the viewer's window and OpenGL side: a GLFW window with a 3.3 core context, the
 * frame uploaded to a float texture (through a pixel buffer object, or straight from OpenCL
 * into a shared texture when the device has cl_khr_gl_sharing and a GL-shared context), shown
 * through the display transform of `render`'s PNG (un-premultiply, ACES fit, sRGB) into an
 * image-sized RGBA8 framebuffer object that screenshots read back with glReadPixels. */
#ifndef SL_VIEWER_GL_H
#define SL_VIEWER_GL_H

#define GLFW_INCLUDE_NONE
#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GL/glext.h>
#include <GLFW/glfw3.h>

#include "cl/clrt.h"
#include "base/common.h"
#include "plan/frame.h"

#define SL_VIEWER_PANEL_W 340 /* pixels right of the image for the ImGui panel */

typedef struct sl_viewer_gl {
    GLFWwindow *win;
    GLuint prog_display, prog_blit, vao;
    GLuint
        frame_tex; /* RGBA32F, the renderer's frame (row 0 at the bottom: flipped in the shader) */
    int tex_w, tex_h;
    GLuint pbo;
    GLuint fbo, fbo_tex; /* RGBA8, image size: what the screen shows, straight alpha */
    int fbo_w, fbo_h;
    int img_x, img_y, img_w, img_h; /* where the image sits in the window (pixels, top-left) */
    /* cl_khr_gl_sharing path */
    int cl_shared;
    void *cl_tex; /* cl_mem on frame_tex when shared */
    sl_device *dev;
    char upload_path[256]; /* shown in the panel */
    char gl_version[128];
    double t_upload, t_draw;
} sl_viewer_gl;

/* Opens the window (image w x h plus the panel). Fails with the "no display" message when
 * GLFW cannot reach an X server. */
int sl_vgl_open(sl_viewer_gl *g, int w, int h, sl_err *e);
/* ---- viewer_gl_cl.c: the OpenCL side of the upload ---- */
/* Decides the upload path for this device (shared texture or PBO) and says why. */
void sl_vgl_interop(sl_viewer_gl *g, sl_device *dev);
/* Releases the shared CL image (before the device it belongs to is closed). */
void sl_vgl_release_cl(sl_viewer_gl *g);
/* cl_khr_gl_sharing: writes the frame into frame_tex through OpenCL (acquire, write, release),
 * making the CL image at the first call. Returns 0, or -1 to fall back to the PBO (sharing is
 * then off, upload_path says why). */
int sl_vgl_upload_shared(sl_viewer_gl *g, const sl_fbuf *f);
/* Releases the CL image made on frame_tex, if any (the texture's storage is about to change);
 * sharing stays on. */
void sl_vgl_drop_cl_image(sl_viewer_gl *g);
/* ---- */
/* Uploads a frame (any size: a preview is stretched) to frame_tex. */
int sl_vgl_upload(sl_viewer_gl *g, const sl_fbuf *f, sl_err *e);
/* Runs the display transform into the image-size framebuffer, then draws it into the window's
 * back buffer beside the panel area (not swapped). */
void sl_vgl_draw(sl_viewer_gl *g, int img_w, int img_h);
/* Window pixel (from GLFW cursor coordinates) -> image pixel. Returns 0 outside the image. */
int sl_vgl_to_image(const sl_viewer_gl *g, double wx, double wy, double *ix, double *iy);
/* PNG of the image framebuffer (whole_window = 0) or of the back buffer (1). */
int sl_vgl_screenshot(sl_viewer_gl *g, const char *path, int whole_window, sl_err *e);
void sl_vgl_close(sl_viewer_gl *g);

#endif
