/* viewer_input.h: the viewer window's mouse, keyboard and drag-and-drop (viewer_input.c). */
#ifndef SL_VIEWER_INPUT_H
#define SL_VIEWER_INPUT_H

#include "viewer/viewer.h"
#include "viewer/viewer_gl.h"

typedef struct sl_vinput {
    sl_viewer *v;
    sl_viewer_gl *g;
    int ui; /* the ImGui panel is up (its capture flags apply) */
    int dragging, drag_ui, stroke_open;
    double lx, ly;
} sl_vinput;

/* Installs the scroll, key and drop callbacks (before sl_ui_init, which chains them). */
void sl_vinput_install(sl_vinput *in, sl_viewer *v, sl_viewer_gl *g);
/* Mouse drags since the last call: orbit, pan or paint. */
void sl_vinput_poll(sl_vinput *in);

#endif
