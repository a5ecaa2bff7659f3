/* passes.h: the frame's passes as data (docs/frame.md, "Passes"). One descriptor per pass, in
 * the order sl_renderer_frame runs them: what it reads and writes (bit sets of sl_frame_data),
 * whether it is needed this frame, and how it runs. The planner (frame.c) is a loop over this
 * table; --explain prints from it.
 *
 * The cache rule, the same for every keyed pass: key = hash(pass name, the hash of each input
 * it declares, its own settings). A frame input's hash is taken once per frame
 * (sl_frame_hash_inputs); an earlier pass's output carries the key of the pass that made it
 * (or, for the unkeyed lobe passes, the hash they give it). A keyed pass is cached when its
 * key equals the one stored after its last successful run. Unkeyed passes run every frame, or
 * decide inside their run (srbf: the Ren table is kept while sl_srbf_ren_matches). */
#ifndef SL_PASSES_H
#define SL_PASSES_H

#include "plan/frame.h"

#include <stdint.h>

/* What passes read and write: the frame's inputs, then the passes' outputs. */
typedef enum sl_frame_data {
    SL_DATA_GEOMETRY,     /* hair points, radii, strands */
    SL_DATA_TRANSPARENCY, /* per-point transparency */
    SL_DATA_MATERIAL,     /* the scene's material (field by field) */
    SL_DATA_STRAND_SIGMA, /* per-strand sigma_a overrides (sl_renderer_set_strand_sigma_a) */
    SL_DATA_ENVIRONMENT,  /* the environment's lobes */
    SL_DATA_CAMERA,       /* the camera and image size */
    SL_DATA_QUALITY,      /* the scene's quality keys (a keyed pass hashes its own: settings) */
    SL_DATA_SRBF_TABLES,  /* tables: the SRBF C_k/H_k tables */
    SL_DATA_USED_LOBES,   /* lobes: the lobes above quality.lobe_threshold, their shares */
    SL_DATA_LOBES,        /* subdivide: the shaded lobes (hash: directions and lambdas) */
    SL_DATA_LOBE_DIRS,    /* subdivide: the shaded lobes' directions */
    SL_DATA_MAP_BUDGET,   /* subdivide: deep opacity maps beyond one per shaded lobe */
    SL_DATA_MAPS,         /* light: deep opacity maps */
    SL_DATA_MS_ON,        /* ms: whether multiple scattering is shaded */
    SL_DATA_DUAL,         /* dual: dual-scattering tables */
    SL_DATA_VOLUME,       /* volume: voxel grid and march textures */
    SL_DATA_MS_TABLE,     /* ms table: multiple-scattering response tables */
    SL_DATA_KBUFFER,      /* view: K-buffer */
    SL_DATA_POINTS,       /* lookup: shading points and their transmittance */
    SL_DATA_SRBF,         /* srbf: the SRBF method (and Ren's table) */
    SL_DATA_SHADED,       /* shade: per-point results */
    SL_DATA_FRAME,        /* resolve: beauty + AOVs */
    SL_DATA_COUNT
} sl_frame_data;
#define SL_IN(d) (1u << (d))
/* "geometry", "lobe dirs", ... */
const char *sl_frame_data_name(int d);

/* The pass ids (index into sl_passes and sl_renderer.key), the table's order; the states are
 * SL_PASS_RUN, _CACHED, _SKIPPED (plan/frame.h). */
enum {
    SL_PASSID_TABLES,
    SL_PASSID_LOBES,
    SL_PASSID_SUBDIVIDE,
    SL_PASSID_LIGHT,
    SL_PASSID_MS,
    SL_PASSID_DUAL,
    SL_PASSID_VOLUME,
    SL_PASSID_MS_TABLE,
    SL_PASSID_VIEW,
    SL_PASSID_LOOKUP,
    SL_PASSID_SRBF,
    SL_PASSID_SHADE,
    SL_PASSID_RESOLVE,
    SL_PASSID_COUNT
};

/* The frame's inputs, as every pass's run receives them. */
typedef struct sl_frame_inputs {
    const sl_scene *s;
    const sl_hair *h;
    const sl_lobes *lobes; /* the environment's */
    const sl_camera *cam;
    sl_fbuf *out;
} sl_frame_inputs;

typedef struct sl_pass_desc {
    const char *name; /* as --explain prints it */
    uint32_t inputs;  /* SL_IN(...) bits read */
    uint32_t outputs; /* SL_IN(...) bits written */
    /* keyed: cached while the key (the rule above) is unchanged; settings: the pass's own
     * quality settings hashed into its key (NULL: none), named by settings_name */
    int keyed;
    uint64_t (*settings)(const sl_renderer *r, const sl_frame_inputs *in);
    const char *settings_name;
    /* needed: 0 skips the pass this frame with skip_why (NULL: always needed) */
    int (*needed)(const sl_renderer *r, const sl_frame_inputs *in);
    const char *skip_why;
    /* the why of a cached pass: cached_why, or on_cached when it has numbers to say */
    const char *cached_why;
    void (*on_cached)(sl_renderer *r, const sl_frame_inputs *in);
    /* runs the pass: writes its outputs into r and its why with sl_frame_why (the state stays
     * run unless it sets r->rec_state). Returns 0 or -1 with e set. */
    int (*run)(sl_renderer *r, const sl_frame_inputs *in, sl_err *e);
} sl_pass_desc;

extern const sl_pass_desc sl_passes[SL_PASSID_COUNT];

/* The key of pass d by the one rule, from this frame's data hashes (SL_DATA_COUNT) and the
 * pass's settings. Never 0 (0 marks "nothing cached"). */
uint64_t sl_pass_key(const sl_pass_desc *d, const uint64_t *data_hash, uint64_t settings);
/* The hashes of the frame inputs that keyed passes read: geometry, transparency, material,
 * camera (the others stay 0). */
void sl_frame_hash_inputs(const sl_frame_inputs *in, uint64_t *data_hash);
/* "geometry, lobes, map budget + quality.shadow_size, layers, kappa": what a keyed pass's key
 * covers; "-" for an unkeyed pass. */
void sl_pass_keyed_on(const sl_pass_desc *d, char *buf, size_t n);

/* The runs, by stage (host/plan/plan_lobes.c, run_light.c, run_volume.c, run_view.c,
 * run_srbf.c, run_shade.c, run_resolve.c): each takes what its descriptor declares from the
 * renderer and calls its pass (host/passes/...), which knows nothing of the renderer. */
int sl_pass_tables(sl_renderer *r, const sl_frame_inputs *in, sl_err *e);
int sl_pass_lobes(sl_renderer *r, const sl_frame_inputs *in, sl_err *e);
int sl_pass_subdivide(sl_renderer *r, const sl_frame_inputs *in, sl_err *e);
uint64_t sl_light_settings(const sl_renderer *r, const sl_frame_inputs *in);
void sl_light_on_cached(sl_renderer *r, const sl_frame_inputs *in);
int sl_pass_light(sl_renderer *r, const sl_frame_inputs *in, sl_err *e);
int sl_pass_ms(sl_renderer *r, const sl_frame_inputs *in, sl_err *e);
int sl_ms_needed(const sl_renderer *r, const sl_frame_inputs *in);
int sl_pass_dual(sl_renderer *r, const sl_frame_inputs *in, sl_err *e);
/* The material multiple scattering's volume passes use: the scene's, with sigma_a replaced by
 * the strands' mean where per-strand sigma_a is set (run_volume.c says how). */
void sl_frame_ms_material(const sl_renderer *r, const sl_frame_inputs *in, sl_material *m);
uint64_t sl_dual_settings(const sl_renderer *r, const sl_frame_inputs *in);
uint64_t sl_ms_table_settings(const sl_renderer *r, const sl_frame_inputs *in);
uint64_t sl_volume_settings(const sl_renderer *r, const sl_frame_inputs *in);
int sl_pass_volume(sl_renderer *r, const sl_frame_inputs *in, sl_err *e);
int sl_pass_ms_table(sl_renderer *r, const sl_frame_inputs *in, sl_err *e);
uint64_t sl_view_settings(const sl_renderer *r, const sl_frame_inputs *in);
int sl_pass_view(sl_renderer *r, const sl_frame_inputs *in, sl_err *e);
int sl_pass_lookup(sl_renderer *r, const sl_frame_inputs *in, sl_err *e);
int sl_pass_srbf(sl_renderer *r, const sl_frame_inputs *in, sl_err *e);
int sl_pass_shade(sl_renderer *r, const sl_frame_inputs *in, sl_err *e);
int sl_pass_resolve(sl_renderer *r, const sl_frame_inputs *in, sl_err *e);

#endif
