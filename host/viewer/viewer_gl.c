/* viewer_gl.c: window, shaders, frame upload (PBO, or cl_khr_gl_sharing through viewer_gl_cl.c)
 * and screenshots of the viewer; see viewer_gl.h. Measured on Mesa llvmpipe under Xvfb
 * (docs/viewer.md). */
#include "viewer/viewer_gl.h"

#include <stb/stb_image_write.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *vs_src =
    "#version 330 core\n"
    "out vec2 uv;\n"
    "void main() {\n"
    "  vec2 p = vec2(float((gl_VertexID & 1) << 1), float(gl_VertexID & 2));\n"
    "  uv = p * 0.5;\n"
    "  gl_Position = vec4(p - 1.0, 0.0, 1.0);\n"
    "}\n";

/* The display transform of sl_png_write (host/io/image/image_write.h): un-premultiply, ACES filmic
 * fit of Narkowicz 2015 clamped to [0, 1], exact sRGB OETF; alpha stays linear. The frame's row 0
 * is the top, uploaded first, so v is flipped. */
static const char *fs_display =
    "#version 330 core\n"
    "in vec2 uv;\n"
    "out vec4 o;\n"
    "uniform sampler2D frame;\n"
    "float tm(float x) {\n"
    "  if (!(x > 0.0)) return 0.0;\n"
    "  float t = min(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 1.0);\n"
    "  return t <= 0.0031308 ? 12.92 * t : 1.055 * pow(t, 1.0 / 2.4) - 0.055;\n"
    "}\n"
    "void main() {\n"
    "  vec4 c = texture(frame, vec2(uv.x, 1.0 - uv.y));\n"
    "  vec3 s = c.a > 0.0 ? c.rgb / c.a : c.rgb;\n"
    "  o = vec4(tm(s.r), tm(s.g), tm(s.b), clamp(c.a, 0.0, 1.0));\n"
    "}\n";

static const char *fs_blit = "#version 330 core\n"
                             "in vec2 uv;\n"
                             "out vec4 o;\n"
                             "uniform sampler2D img;\n"
                             "void main() { o = texture(img, uv); }\n";

static GLuint shader(GLenum type, const char *src, sl_err *e) {
    GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[512] = "";
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        for (char *p = log; *p; p++)
            if (*p == '\n') *p = ' ';
        sl_fail(e, "view: shader: %s", log);
        glDeleteShader(s);
        return 0;
    }
    return s;
}

static GLuint program(const char *fs, sl_err *e) {
    GLuint v = shader(GL_VERTEX_SHADER, vs_src, e), f = v ? shader(GL_FRAGMENT_SHADER, fs, e) : 0;
    if (!f) {
        if (v) glDeleteShader(v);
        return 0;
    }
    GLuint p = glCreateProgram();
    glAttachShader(p, v);
    glAttachShader(p, f);
    glLinkProgram(p);
    glDeleteShader(v);
    glDeleteShader(f);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        glDeleteProgram(p);
        sl_fail(e, "view: shader program does not link");
        return 0;
    }
    return p;
}

int sl_vgl_open(sl_viewer_gl *g, int w, int h, sl_err *e) {
    memset(g, 0, sizeof *g);
    snprintf(g->upload_path, sizeof g->upload_path, "PBO upload");
    if (!glfwInit())
        return sl_fail(e, "view: no display (DISPLAY unset or X unreachable); use `strandlight "
                          "render` for offline frames");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    int ww = w + SL_VIEWER_PANEL_W, wh = h < 560 ? 560 : h;
    g->win = glfwCreateWindow(ww, wh, "strandlight view", NULL, NULL);
    if (!g->win) {
        glfwTerminate();
        return sl_fail(e, "view: cannot create an OpenGL 3.3 core window on this display");
    }
    glfwMakeContextCurrent(g->win);
    glfwSwapInterval(0); /* never block on vsync: rendering shares the main thread */
    snprintf(g->gl_version, sizeof g->gl_version, "%s", (const char *)glGetString(GL_VERSION));
    if (!(g->prog_display = program(fs_display, e)) || !(g->prog_blit = program(fs_blit, e))) {
        sl_vgl_close(g);
        return -1;
    }
    glGenVertexArrays(1, &g->vao);
    glGenTextures(1, &g->frame_tex);
    glGenBuffers(1, &g->pbo);
    glGenFramebuffers(1, &g->fbo);
    glGenTextures(1, &g->fbo_tex);
    return 0;
}

int sl_vgl_upload(sl_viewer_gl *g, const sl_fbuf *f, sl_err *e) {
    double t0 = sl_now();
    size_t bytes = (size_t)f->width * f->height * 4 * sizeof(float);
    glBindTexture(GL_TEXTURE_2D, g->frame_tex);
    if (f->width != g->tex_w || f->height != g->tex_h) {
        sl_vgl_drop_cl_image(g); /* the CL image is bound to the old storage */
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, f->width, f->height, 0, GL_RGBA, GL_FLOAT, NULL);
        g->tex_w = f->width;
        g->tex_h = f->height;
    }
    if (!(g->cl_shared && sl_vgl_upload_shared(g, f) == 0)) {
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, g->pbo);
        glBufferData(GL_PIXEL_UNPACK_BUFFER, (GLsizeiptr)bytes, NULL, GL_STREAM_DRAW);
        void *p = glMapBufferRange(GL_PIXEL_UNPACK_BUFFER, 0, (GLsizeiptr)bytes,
                                   GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT);
        if (!p) {
            glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
            return sl_fail(e, "view: cannot map the pixel buffer object");
        }
        memcpy(p, f->rgba, bytes);
        glUnmapBuffer(GL_PIXEL_UNPACK_BUFFER);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, f->width, f->height, GL_RGBA, GL_FLOAT, NULL);
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    }
    g->t_upload = sl_now() - t0;
    return 0;
}

void sl_vgl_draw(sl_viewer_gl *g, int img_w, int img_h) {
    double t0 = sl_now();
    /* 1. display transform into the image-size framebuffer; a frame of the image's size maps
     * texel to pixel (nearest), a half-size preview is stretched (linear) */
    if (img_w != g->fbo_w || img_h != g->fbo_h) {
        glBindTexture(GL_TEXTURE_2D, g->fbo_tex);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, img_w, img_h, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, g->fbo_tex, 0);
        g->fbo_w = img_w;
        g->fbo_h = img_h;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    glViewport(0, 0, img_w, img_h);
    glDisable(GL_BLEND);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    if (g->tex_w > 0) {
        glUseProgram(g->prog_display);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, g->frame_tex);
        GLint filt = (g->tex_w == img_w && g->tex_h == img_h) ? GL_NEAREST : GL_LINEAR;
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filt);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filt);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glUniform1i(glGetUniformLocation(g->prog_display, "frame"), 0);
        glBindVertexArray(g->vao);
        glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    }
    /* 2. into the window left of the panel, aspect kept, over a dark background */
    int fw, fh;
    glfwGetFramebufferSize(g->win, &fw, &fh);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, fw, fh);
    glClearColor(0.12f, 0.12f, 0.13f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    int aw = fw - SL_VIEWER_PANEL_W, ah = fh;
    if (aw < 1) aw = 1;
    double sc = (double)aw / img_w < (double)ah / img_h ? (double)aw / img_w : (double)ah / img_h;
    if (sc > 1.0) sc = 1.0; /* never magnify: 1:1 pixels when the window is big enough */
    g->img_w = (int)(img_w * sc + 0.5);
    g->img_h = (int)(img_h * sc + 0.5);
    g->img_x = 0;
    g->img_y = 0;
    glViewport(g->img_x, fh - g->img_y - g->img_h, g->img_w, g->img_h);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glUseProgram(g->prog_blit);
    glBindTexture(GL_TEXTURE_2D, g->fbo_tex);
    glUniform1i(glGetUniformLocation(g->prog_blit, "img"), 0);
    glBindVertexArray(g->vao);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glDisable(GL_BLEND);
    glViewport(0, 0, fw, fh);
    g->t_draw = sl_now() - t0;
}

int sl_vgl_to_image(const sl_viewer_gl *g, double wx, double wy, double *ix, double *iy) {
    int ww, wh, fw, fh;
    glfwGetWindowSize(g->win, &ww, &wh);
    glfwGetFramebufferSize(g->win, &fw, &fh);
    double sx = ww > 0 ? (double)fw / ww : 1.0, sy = wh > 0 ? (double)fh / wh : 1.0;
    double px = wx * sx - g->img_x, py = wy * sy - g->img_y;
    if (g->img_w <= 0 || px < 0 || py < 0 || px >= g->img_w || py >= g->img_h) return 0;
    *ix = px * g->fbo_w / g->img_w;
    *iy = py * g->fbo_h / g->img_h;
    return 1;
}

/* stb_image_write's sink: the bytes go to the atomic file's stream. */
static void shot_write(void *ctx, void *data, int size) {
    fwrite(data, 1, (size_t)size, (FILE *)ctx);
}

int sl_vgl_screenshot(sl_viewer_gl *g, const char *path, int whole_window, sl_err *e) {
    int w = g->fbo_w, h = g->fbo_h;
    if (whole_window) {
        glfwGetFramebufferSize(g->win, &w, &h);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
        glReadBuffer(GL_BACK);
    } else {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, g->fbo);
        glReadBuffer(GL_COLOR_ATTACHMENT0);
    }
    if (w < 1 || h < 1) return sl_fail(e, "%s: nothing displayed yet", path);
    unsigned char *px = sl_malloc((size_t)w * h * 4), *row = sl_malloc((size_t)w * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, px);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    /* GL rows start at the bottom; PNG rows at the top */
    for (int y = 0; y < h / 2; y++) {
        unsigned char *a = px + (size_t)y * w * 4, *b = px + (size_t)(h - 1 - y) * w * 4;
        memcpy(row, a, (size_t)w * 4);
        memcpy(a, b, (size_t)w * 4);
        memcpy(b, row, (size_t)w * 4);
    }
    if (whole_window) /* the window has no meaningful alpha */
        for (size_t i = 0; i < (size_t)w * h; i++)
            px[4 * i + 3] = 255;
    free(row);
    int rc = -1;
    sl_atomic_file af; /* a temporary of our own (O_EXCL | O_NOFOLLOW), renamed into place */
    if (sl_atomic_open(&af, path, e)) goto done;
    if (!stbi_write_png_to_func(shot_write, af.fp, w, h, 4, px, w * 4)) {
        sl_atomic_abort(&af);
        sl_fail(e, "%s: cannot write the screenshot", path);
        goto done;
    }
    if (sl_atomic_commit(&af, e)) goto done;
    rc = 0;
done:
    free(px);
    return rc;
}

void sl_vgl_close(sl_viewer_gl *g) {
    if (!g->win) return;
    sl_vgl_drop_cl_image(g);
    glDeleteTextures(1, &g->frame_tex);
    glDeleteTextures(1, &g->fbo_tex);
    glDeleteFramebuffers(1, &g->fbo);
    glDeleteBuffers(1, &g->pbo);
    glDeleteVertexArrays(1, &g->vao);
    if (g->prog_display) glDeleteProgram(g->prog_display);
    if (g->prog_blit) glDeleteProgram(g->prog_blit);
    glfwDestroyWindow(g->win);
    glfwTerminate();
    g->win = NULL;
}
