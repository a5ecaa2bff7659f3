/* viewer_script.c: `strandlight view --script FILE`: plain-text commands, one per line, `#`
 * starts a comment. Each command calls the same function as the matching mouse, key or panel
 * control, then the window repaints (a preview frame when something changed), so a script test
 * exercises the interactive viewer. Commands (docs/viewer.md):
 *   set KEY VALUE        a scene key (material.*, quality.*, camera.*, environment.*, image.*,
 *                        hair.*), VALUE as JSON or a bare word
 *   orbit DEG [PITCH]    yaw about +Y through the target (as render --orbit), optional pitch
 *   pan DX DY            move the hair by DX, DY pixels
 *   zoom F               distance / F
 *   reset                camera back to the scene's
 *   env_rotate DEG       environment.rotation_deg += DEG
 *   paint X Y R SR SG SB brush at image pixel (X, Y), radius R pixels, sigma_a (SR, SG, SB)
 *   brush_depth on|off   the brush's depth test (default on)
 *   device SPEC          switch the backend (as --device)
 *   undo                 undo the last paint stroke
 *   drop PATH            as dropping a hair file or environment map on the window
 *   wait                 render until the refined frame is on screen
 *   screenshot PATH      PNG of the displayed image (glReadPixels of the image framebuffer)
 *   screenshot_window PATH   PNG of the whole window, panel included
 *   save PATH            scene JSON (+ PATH stem .strands.csv when painted)
 *   explain              print the plan of the frame on screen to stdout
 *   stats                print frame, preview, upload and draw times to stdout
 *   quit                 close the viewer */
#include "viewer/viewer.h"

#include "viewer/viewer_gl.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Splits off the next whitespace-separated word of *s (NULL at the end). */
static char *word(char **s) {
    char *p = *s;
    while (*p && isspace((unsigned char)*p))
        p++;
    if (!*p) return NULL;
    char *w = p;
    while (*p && !isspace((unsigned char)*p))
        p++;
    if (*p) *p++ = 0;
    *s = p;
    return w;
}

static char *rest(char **s) {
    char *p = *s;
    while (*p && isspace((unsigned char)*p))
        p++;
    size_t n = strlen(p);
    while (n > 0 && isspace((unsigned char)p[n - 1]))
        p[--n] = 0;
    return *p ? p : NULL;
}

static int num(const char *where, const char *cmd, const char *w, double *out, sl_err *e) {
    if (!w) return sl_fail(e, "%s: %s: missing a number", where, cmd);
    char *end;
    errno = 0;
    *out = strtod(w, &end);
    if (end == w || *end || errno || !isfinite(*out))
        return sl_fail(e, "%s: %s: expected a number, got \"%s\"", where, cmd, w);
    return 0;
}

/* Reads n numbers and insists nothing follows. */
static int nums(const char *where, const char *cmd, char **s, int n, int optional_from, double *out,
                sl_err *e) {
    for (int i = 0; i < n; i++) {
        char *w = word(s);
        if (!w && i >= optional_from) return i;
        if (num(where, cmd, w, &out[i], e)) return -1;
    }
    if (word(s)) return sl_fail(e, "%s: %s: too many arguments", where, cmd);
    return n;
}

static int with_where(const char *where, sl_err *e) {
    char msg[sizeof e->msg];
    snprintf(msg, sizeof msg, "%s", e->msg);
    return sl_fail(e, "%s: %s", where, msg);
}

int sl_viewer_command(sl_viewer *v, char *line, const char *where, const sl_viewer_host *host,
                      sl_err *e) {
    char *s = line, *cmd = word(&s);
    if (!cmd) return 0;
    double a[6];
    int rc = 0;
    if (strcmp(cmd, "set") == 0) {
        char *key = word(&s), *val = rest(&s);
        if (!key || !val) return sl_fail(e, "%s: set: expected KEY VALUE", where);
        if (sl_viewer_set(v, key, val, e)) return with_where(where, e);
    } else if (strcmp(cmd, "orbit") == 0) {
        int n = nums(where, cmd, &s, 2, 1, a, e);
        if (n < 0) return -1;
        sl_viewer_orbit(v, a[0], n > 1 ? a[1] : 0.0);
    } else if (strcmp(cmd, "pan") == 0) {
        if (nums(where, cmd, &s, 2, 2, a, e) < 0) return -1;
        sl_viewer_pan(v, a[0], a[1]);
    } else if (strcmp(cmd, "zoom") == 0) {
        if (nums(where, cmd, &s, 1, 1, a, e) < 0) return -1;
        if (!(a[0] > 0)) return sl_fail(e, "%s: zoom: the factor must be > 0", where);
        sl_viewer_zoom(v, a[0]);
    } else if (strcmp(cmd, "reset") == 0) {
        if (nums(where, cmd, &s, 0, 0, a, e) < 0) return -1;
        sl_viewer_reset(v);
    } else if (strcmp(cmd, "env_rotate") == 0) {
        if (nums(where, cmd, &s, 1, 1, a, e) < 0) return -1;
        if (sl_viewer_env_rotate(v, a[0], e)) return with_where(where, e);
    } else if (strcmp(cmd, "paint") == 0) {
        if (nums(where, cmd, &s, 6, 6, a, e) < 0) return -1;
        float sa[3] = {(float)a[3], (float)a[4], (float)a[5]};
        /* the depth test needs the refined frame of this view */
        if (v->brush_depth_test && host->step(v, 1, e)) return with_where(where, e);
        long hits = sl_viewer_paint_at(v, a[0], a[1], a[2], sa, 0, e);
        if (hits < 0) return with_where(where, e);
        snprintf(v->status, sizeof v->status, "paint: %ld strands", hits);
        printf("paint: %ld strands\n", hits);
        fflush(stdout);
    } else if (strcmp(cmd, "brush_depth") == 0) {
        char *w = word(&s);
        if (!w || (strcmp(w, "on") && strcmp(w, "off")) || word(&s))
            return sl_fail(e, "%s: brush_depth: expected on or off", where);
        v->brush_depth_test = strcmp(w, "on") == 0;
    } else if (strcmp(cmd, "undo") == 0) {
        if (nums(where, cmd, &s, 0, 0, a, e) < 0) return -1;
        if (!sl_viewer_undo(v)) return sl_fail(e, "%s: undo: nothing to undo", where);
    } else if (strcmp(cmd, "drop") == 0) {
        char *p = rest(&s);
        if (!p) return sl_fail(e, "%s: drop: expected a file", where);
        if (sl_viewer_drop(v, p, e)) return with_where(where, e);
    } else if (strcmp(cmd, "device") == 0) {
        char *d = word(&s);
        if (!d || word(&s))
            return sl_fail(e, "%s: device: expected auto|gpu|pocl|c|opencl|P:D", where);
        if (sl_viewer_set_device(v, d, e)) return with_where(where, e);
    } else if (strcmp(cmd, "wait") == 0) {
        if (nums(where, cmd, &s, 0, 0, a, e) < 0) return -1;
        if (host->step(v, 1, e)) return with_where(where, e);
        return 0;
    } else if (strcmp(cmd, "screenshot") == 0 || strcmp(cmd, "screenshot_window") == 0) {
        char *p = rest(&s);
        if (!p) return sl_fail(e, "%s: %s: expected a PNG path", where, cmd);
        if (host->step(v, 0, e) || host->screenshot(v, p, cmd[10] == '_', e))
            return with_where(where, e);
        return 0;
    } else if (strcmp(cmd, "save") == 0) {
        char *p = rest(&s);
        if (!p) return sl_fail(e, "%s: save: expected a JSON path", where);
        if (sl_viewer_save(v, p, e)) return with_where(where, e);
        return 0;
    } else if (strcmp(cmd, "explain") == 0) {
        printf("%s frame %dx%d\n", v->shown_preview ? "preview" : "refined", v->shown.width,
               v->shown.height);
        sl_renderer_explain(sl_viewer_shown_renderer(v), stdout);
        fflush(stdout);
        return 0;
    } else if (strcmp(cmd, "stats") == 0) {
        const sl_viewer_gl *g = v->gl;
        printf("view: %dx%d on %s: refined frame %.3f s, preview %.3f s, upload %.2f ms, draw "
               "%.2f ms, present %.2f ms (%s)\n",
               v->scene.width, v->scene.height, v->dev.name, v->t_full, v->t_preview,
               g ? 1e3 * g->t_upload : 0.0, g ? 1e3 * g->t_draw : 0.0, 1e3 * v->t_present,
               g ? g->upload_path : "");
        fflush(stdout);
        return 0;
    } else if (strcmp(cmd, "quit") == 0) {
        v->quit = 1;
        return 0;
    } else {
        return sl_fail(e, "%s: unknown command \"%s\"", where, cmd);
    }
    rc = host->step(v, 0, e);
    return rc ? with_where(where, e) : 0;
}

int sl_viewer_run_script(sl_viewer *v, const char *path, const sl_viewer_host *host, sl_err *e) {
    unsigned char *text = NULL;
    size_t len = 0;
    if (sl_read_file(path, &text, &len, 16u << 20, e)) return -1;
    int rc = sl_viewer_run_script_text(v, (const char *)text, len, path, host, e);
    free(text);
    return rc;
}

int sl_viewer_run_script_text(sl_viewer *v, const char *text, size_t len, const char *path,
                              const sl_viewer_host *host, sl_err *e) {
    int rc = 0, lineno = 0;
    const char *p = text, *end = p + len;
    while (p < end && !v->quit && rc == 0) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        size_t n = nl ? (size_t)(nl - p) : (size_t)(end - p);
        char line[4096];
        lineno++;
        char where[4200];
        snprintf(where, sizeof where, "%s:%d", path, lineno);
        if (n >= sizeof line) {
            rc = sl_fail(e, "%s: line too long", where);
            break;
        }
        if (memchr(p, 0, n)) {
            rc = sl_fail(e, "%s: NUL byte in the script", where);
            break;
        }
        memcpy(line, p, n);
        line[n] = 0;
        char *hash = strchr(line, '#');
        if (hash) *hash = 0;
        rc = sl_viewer_command(v, line, where, host, e);
        p += n + 1;
    }
    return rc;
}
