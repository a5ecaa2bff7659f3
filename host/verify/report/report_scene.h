/* report_scene.h: `strandlight report SCENE.json` (issue 10, second half): the brute-force
 * reference of the scene (host/verify/reference/reference.h, cached by its own key) against the
 * fast pipeline (host/plan/frame.h) over a sweep of settings, written to a report directory. Two
 * references: the pixel reference (camera rays, its own coverage) and the fragment reference (the
 * fast path's own K-buffer entries shaded by the reference, host/verify/reference/reference.h
 * fragments: only the shading is compared); every run is measured against both (columns rel_rmse...
 * and rel_rmse_frag...). results.csv        one row per run (the references are the rows with
 * backend "reference" and "reference_fragments") report.md          table, Pareto front, the
 * reference's settings and time, speed-ups error_vs_time.svg  rel. RMSE against run time, log-log,
 * front highlighted Errors are numerics.md sec. 6 (sl_image_error). The directory appears complete
 * or not at all (written under a temporary name, then renamed). */
#ifndef SL_REPORT_SCENE_H
#define SL_REPORT_SCENE_H

#include "base/common.h"

typedef struct sl_report_scene_opts {
    const char *scene;   /* scene file */
    const char *out_dir; /* NULL: report/<scene name> */
    int quick;           /* small sweep, smaller reference (a few minutes) */
    int tiny;            /* small image for CI (seconds) */
    const char *opencl;  /* device spec for the opencl rows (NULL: "opencl"), "none": C only */
    int lights, aa;      /* pixel reference settings, 0: by mode */
    int frag_lights;     /* fragment reference lights, 0: by mode */
    int width;           /* image width, 0: by mode (height keeps the scene's aspect) */
    int threads;         /* 0: every CPU */
    int reference;       /* pixel reference: 0 auto (path tracer for deon/chiang, the direct-light
                            reference for marschner, whose albedo above 1 makes every bounce
                            grow), 1 path tracer, 2 direct-light reference */
    int spp;             /* path tracer samples per pixel, 0: by mode */
} sl_report_scene_opts;

/* Runs the report. Returns 0, or -1 with e set (nothing written but the reference cache). */
int sl_report_scene(const sl_report_scene_opts *o, sl_err *e);

#endif
