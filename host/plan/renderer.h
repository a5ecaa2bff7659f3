/* renderer.h: the renderer's state, private to the planner (host/plan) and the passes
 * (host/passes) and white-box tests; everyone else holds an opaque sl_renderer and uses the
 * functions of plan/frame.h. */
#ifndef SL_RENDERER_H
#define SL_RENDERER_H

#include "plan/frame.h"
#include "plan/passes.h"
#include "passes/shade/shade_points.h"
#include "passes/view/frame_view.h"
#include "passes/volume/dual_deflect.h"

/* One frame's working state, passed from pass to pass (freed at the end of the frame). */
typedef struct sl_frame_work {
    const sl_lobes *fl; /* the shaded lobes: the environment's, or sub */
    sl_lobes sub;       /* sub-lobes (quality.broad_lobes subdivide) */
    int *used;          /* lobe indices into fl */
    int nused;
    double *share;  /* per used lobe: share of the environment's total power */
    double total;   /* the environment's total power (lobe_power) */
    int extra_maps; /* deep opacity maps beyond one per used lobe */
    int rate;       /* quality.shading_rate parsed: -1 auto, 0 fragment, k vertex */
    int K;          /* K-buffer entries per pixel (sl_frame_oit_k) */
    int segments;   /* m of Xu's form: --segments, else quality.segments_m */
    int transparent;
    sl_shade_points pts;
    sl_shade_map sm;
} sl_frame_work;

struct sl_renderer {
    double frame_t0;        /* sl_now() at the start of the frame (status lines) */
    char status_label[128]; /* sl_renderer_set_status: before the pass on the status line */
    sl_device *dev;
    sl_render_opts o;
    /* the cache: each pass's key after its last successful run (0: nothing cached), and this
     * frame's hashes of the data passes read (passes.h, the key rule) */
    uint64_t key[SL_PASSID_COUNT];
    uint64_t data_hash[SL_DATA_COUNT];
    /* caches */
    int have_tables;
    sl_srbf_tables tables;
    int nlights;     /* shadow maps: one per used lobe, several for a broad lobe */
    int *light_lobe; /* each map's position in the frame's used-lobe list */
    double *light_w; /* each map's weight in its lobe's T (host/passes/light/shadow_split.h) */
    sl_dodm *light;
    sl_dual_tables dual;
    sl_dual_deflect deflect; /* the material's azimuthal deflections, with dual */
    int dual_ok;
    uint64_t vox_key; /* voxel grid (geometry, quality.voxels): a material edit keeps it */
    int have_vgrid;
    int have_vol; /* march textures (voxel grid, used lobes, material through dual) */
    sl_voxel_grid vgrid;
    sl_ftex ftex;
    /* the light pass's key when ftex.tau (the maps' depth at the march's vertices) was set:
     * ftex.tau follows the maps and the march, not the camera (run_shade.c) */
    uint64_t tau_light_key;
    int have_vms; /* multiple-scattering response tables (material) */
    sl_volume_ms vms;
    /* the same at the per-strand sigma_a nodes, built with vms when strand_sigma_a is set
     * (host/passes/volume/volume_ms_nodes.h) */
    int have_msn;
    sl_volume_ms_nodes msn;
    sl_view_result view; /* the last view pass: K-buffer, counts, median segment length */
    /* per-strand absorption overrides (painted, or from the file's colours; docs/frame.md):
     * 3 floats (sigma_a r, g, b) per strand, or NULL: every strand uses the material's sigma_a.
     * Set with sl_renderer_set_strand_sigma_a; the key is part of the shading pass's inputs
     * only (editing sigma_a re-runs shading, never the view or light passes). */
    float *strand_sigma_a;
    uint32_t strand_sigma_a_n;
    uint64_t strand_key;
    /* the key of the sigma_a nodes of strand_sigma_a (sl_volume_ms_nodes_place), taken when it
     * is set: the ms table pass's setting */
    uint64_t strand_nodes_key;
    /* Ren 2010's table (docs/frame.md, "SRBF method"): built or loaded by the planner, kept
     * while the material is unchanged (sl_srbf_ren_matches); ren_mem: the table resident on the
     * OpenCL device (uploaded once per table) when shading runs there */
    int have_ren;
    sl_srbf_ren ren;
    cl_mem ren_mem;
    int editing;      /* sl_renderer_set_editing: the material is being edited -> fast */
    long frames_done; /* frames rendered by this renderer (auto: frames left = o.frames - it) */
    int srbf_used;    /* the last frame's method: SL_SRBF_METHOD_XU, _FAST or SL_RENDER_SRBF_TABLE
                         (table: rows of strands with a per-strand sigma_a other than the
                         material's still use fast) */
    char srbf_why[300];
    /* the frame in progress */
    sl_frame_work fw;
    int rec_state;     /* the running pass's state (run unless its run says otherwise) */
    char rec_why[600]; /* the running pass's why (sl_frame_why) */
    /* last frame's plan */
    int npass;
    sl_pass_rec pass[SL_FRAME_MAX_PASSES];
    int rate_k;     /* 0: fragment, k >= 1: every k-th vertex */
    size_t refined; /* shading points the refinement added this frame (vertex rate) */
    int ms_on, lobes_used;
    double total_s;
};

/* The running pass's why (printf). */
void sl_frame_why(sl_renderer *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* The K-buffer of the last view pass. */
sl_kbuf_view sl_frame_kbuf(const sl_renderer *r);

/* Frees a pass's cache (and clears its key). */
void sl_frame_free_lights(sl_renderer *r);
void sl_frame_free_march(sl_renderer *r);
void sl_frame_free_volume(sl_renderer *r);
void sl_frame_free_ren(sl_renderer *r);

/* 1 when any point of h is transparent (else the view pass skips the transparency channel). */
int sl_frame_hair_transparent(const sl_hair *h);
/* A lobe's power for the planner: luminance of rgb x the lobe's integral of G. */
double sl_frame_lobe_power(const sl_lobe *lb);

#endif
