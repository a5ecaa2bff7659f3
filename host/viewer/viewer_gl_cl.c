/* viewer_gl_cl.c: the OpenCL side of the viewer's frame upload (cl_khr_gl_sharing): whether the
 * device can share, the CL image made on the frame texture, and the shared write; see
 * viewer_gl.h. */
#include "viewer/viewer_gl.h"

#include <CL/cl_gl.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int has_ext(cl_device_id d, const char *name) {
    size_t n = 0;
    if (clGetDeviceInfo(d, CL_DEVICE_EXTENSIONS, 0, NULL, &n) != CL_SUCCESS || n == 0) return 0;
    char *s = sl_malloc(n + 1);
    int found = 0;
    if (clGetDeviceInfo(d, CL_DEVICE_EXTENSIONS, n, s, NULL) == CL_SUCCESS) {
        s[n] = 0;
        found = strstr(s, name) != NULL;
    }
    free(s);
    return found;
}

void sl_vgl_interop(sl_viewer_gl *g, sl_device *dev) {
    g->dev = dev;
    g->cl_shared = 0;
    if (!dev->is_opencl) {
        snprintf(g->upload_path, sizeof g->upload_path, "PBO upload (C path: no OpenCL device)");
        return;
    }
    if (!has_ext(sl_cl_device_id(dev->cl), "cl_khr_gl_sharing")) {
        snprintf(g->upload_path, sizeof g->upload_path,
                 "PBO upload (%.200s has no cl_khr_gl_sharing)", dev->name);
        return;
    }
    /* The device can share: the texture is made a CL image at its first upload (it needs its
     * size); a context created without the GL properties refuses it there and we fall back. */
    g->cl_shared = 1;
    snprintf(g->upload_path, sizeof g->upload_path, "shared GL texture (cl_khr_gl_sharing)");
}

void sl_vgl_release_cl(sl_viewer_gl *g) {
    if (g->cl_tex) clReleaseMemObject((cl_mem)g->cl_tex);
    g->cl_tex = NULL;
    g->cl_shared = 0;
}

/* Not testable here: PoCL has no cl_khr_gl_sharing. */
int sl_vgl_upload_shared(sl_viewer_gl *g, const sl_fbuf *f) {
    cl_int err = CL_SUCCESS;
    cl_command_queue q = sl_cl_queue(g->dev->cl);
    if (!g->cl_tex) {
        g->cl_tex = clCreateFromGLTexture(sl_cl_context(g->dev->cl), CL_MEM_WRITE_ONLY,
                                          GL_TEXTURE_2D, 0, g->frame_tex, &err);
        if (err != CL_SUCCESS) {
            g->cl_tex = NULL;
            snprintf(g->upload_path, sizeof g->upload_path,
                     "PBO upload (cl_khr_gl_sharing present, but the OpenCL context is not "
                     "GL-shared: error %d)",
                     (int)err);
            g->cl_shared = 0;
            return -1;
        }
    }
    cl_mem m = (cl_mem)g->cl_tex;
    size_t origin[3] = {0, 0, 0}, region[3] = {(size_t)f->width, (size_t)f->height, 1};
    glFinish();
    err = clEnqueueAcquireGLObjects(q, 1, &m, 0, NULL, NULL);
    if (err == CL_SUCCESS)
        err = clEnqueueWriteImage(q, m, CL_TRUE, origin, region, 0, 0, f->rgba, 0, NULL, NULL);
    cl_int err2 = clEnqueueReleaseGLObjects(q, 1, &m, 0, NULL, NULL);
    clFinish(q);
    if (err != CL_SUCCESS || err2 != CL_SUCCESS) {
        clReleaseMemObject(m);
        g->cl_tex = NULL;
        g->cl_shared = 0;
        snprintf(g->upload_path, sizeof g->upload_path,
                 "PBO upload (shared texture write failed: error %d)", (int)err);
        return -1;
    }
    return 0;
}

void sl_vgl_drop_cl_image(sl_viewer_gl *g) {
    if (g->cl_tex) clReleaseMemObject((cl_mem)g->cl_tex);
    g->cl_tex = NULL;
}
