/* frame.c: the frame's pass planner (see frame.h, docs/frame.md). The passes are data
 * (plan/passes.h: what each reads and writes, whether it is needed, how it runs); the planner
 * walks the table: a pass not needed is skipped with its reason, a keyed pass whose key (the
 * hashes of the inputs it declares + its own settings) is unchanged is cached, any other runs;
 * each leaves a record (state, why, time) for --explain. So a per-strand sigma_a edit (paint)
 * re-runs only lookup + shade + resolve (the multiple-scattering tables and volume use the
 * material's sigma_a, docs/frame.md), and a camera orbit re-runs only the view pass and what
 * follows it. The passes also leave out what the scene does not need: lobes below
 * quality.lobe_threshold of the total power (no map, no shading), multiple scattering for dark
 * hair (quality.multiple_scattering auto, quality.ms_auto_threshold), (point, lobe) pairs below
 * quality.point_threshold, the K-buffer layers no pixel reached and, for opaque hair, the
 * transparency channel. */
#include "plan/frame_internal.h"
#include "base/parallel.h"
#include "base/text_wrap.h"
#include "lighting/lobe_subdivide.h"
#include "passes/light/shadow_split.h"
#include "srbf_c.h"
#include "march.h"
#include "voxel.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

void sl_render_opts_default(sl_render_opts *o) {
    memset(o, 0, sizeof *o);
    o->srbf_method = SL_RENDER_SRBF_AUTO;
    o->segments = 0;        /* the scene's quality.segments_m */
    o->lobe_threshold = -1; /* the scene's quality.lobe_threshold */
}

int sl_render_method_parse(const char *s, int *method, sl_err *e) {
    if (strcmp(s, "auto") == 0)
        *method = SL_RENDER_SRBF_AUTO;
    else if (strcmp(s, "fast") == 0)
        *method = SL_SRBF_METHOD_FAST;
    else if (strcmp(s, "xu") == 0)
        *method = SL_SRBF_METHOD_XU;
    else if (strcmp(s, "table") == 0)
        *method = SL_RENDER_SRBF_TABLE;
    else
        return sl_fail(e, "SRBF method \"%s\": expected auto, fast, xu or table", s);
    return 0;
}

const char *sl_render_method_name(int method) {
    switch (method) {
    case SL_SRBF_METHOD_XU:
        return "xu";
    case SL_SRBF_METHOD_FAST:
        return "fast";
    case SL_RENDER_SRBF_TABLE:
        return "table";
    default:
        return "auto";
    }
}

void sl_renderer_set_editing(sl_renderer *r, int editing) {
    r->editing = editing != 0;
}

sl_renderer *sl_renderer_create(sl_device *dev, const sl_render_opts *o) {
    sl_renderer *r = sl_calloc(1, sizeof *r);
    r->dev = dev;
    if (o)
        r->o = *o;
    else
        sl_render_opts_default(&r->o);
    return r;
}

void sl_renderer_free(sl_renderer *r) {
    if (!r) return;
    sl_frame_free_lights(r);
    sl_frame_free_volume(r);
    if (r->have_vms) sl_volume_ms_free(&r->vms);
    if (r->have_msn) sl_volume_ms_nodes_free(&r->msn);
    if (r->have_tables) sl_srbf_tables_free(&r->tables);
    sl_frame_free_ren(r);
    free(r->view.kbuf);
    free(r->view.kcount);
    free(r->strand_sigma_a);
    free(r);
}

int sl_renderer_set_strand_sigma_a(sl_renderer *r, const float *sigma_a, uint32_t n, sl_err *e) {
    free(r->strand_sigma_a);
    r->strand_sigma_a = NULL;
    r->strand_sigma_a_n = 0;
    r->strand_key = r->strand_nodes_key = 0;
    if (!sigma_a) return 0;
    for (size_t i = 0; i < 3 * (size_t)n; i++)
        if (!(sigma_a[i] >= 0.0f) || !isfinite(sigma_a[i]))
            return sl_fail(e, "per-strand sigma_a: strand %zu: expected a finite value >= 0",
                           i / 3);
    r->strand_sigma_a = sl_malloc(3 * (size_t)(n ? n : 1) * sizeof *r->strand_sigma_a);
    memcpy(r->strand_sigma_a, sigma_a, 3 * (size_t)n * sizeof *sigma_a);
    r->strand_sigma_a_n = n;
    r->strand_key = sl_hash64(sigma_a, 3 * (size_t)n * sizeof *sigma_a, 0x5354524e) | 1;
    sl_volume_ms_nodes nd;
    sl_volume_ms_nodes_place(sigma_a, n, &nd);
    r->strand_nodes_key = nd.key;
    return 0;
}

int sl_frame_threads(const sl_renderer *r) {
    return sl_parallel_threads(r->o.threads);
}

void sl_frame_why(sl_renderer *r, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->rec_why, sizeof r->rec_why, fmt, ap);
    va_end(ap);
}

sl_kbuf_view sl_frame_kbuf(const sl_renderer *r) {
    return (sl_kbuf_view){r->view.w, r->view.h, r->view.K, r->view.kbuf, r->view.kcount};
}

/* Appends the record of pass d to the plan. */
static void record(sl_renderer *r, const sl_pass_desc *d, int state, double seconds,
                   const char *why) {
    if (r->npass >= SL_FRAME_MAX_PASSES) return;
    sl_pass_rec *p = &r->pass[r->npass++];
    snprintf(p->name, sizeof p->name, "%s", d->name);
    p->state = state;
    p->seconds = seconds;
    snprintf(p->why, sizeof p->why, "%s", why);
}

const sl_pass_rec *sl_renderer_pass(const sl_renderer *r, const char *name) {
    for (int i = 0; i < r->npass; i++)
        if (strcmp(r->pass[i].name, name) == 0) return &r->pass[i];
    return NULL;
}

int sl_renderer_npass(const sl_renderer *r) {
    return r->npass;
}

const sl_pass_rec *sl_renderer_pass_at(const sl_renderer *r, int i) {
    return i >= 0 && i < r->npass ? &r->pass[i] : NULL;
}

void sl_renderer_set_status(sl_renderer *r, const char *label) {
    snprintf(r->status_label, sizeof r->status_label, "%s", label ? label : "");
}

int sl_renderer_lobes_used(const sl_renderer *r) {
    return r->lobes_used;
}

int sl_renderer_ms_on(const sl_renderer *r) {
    return r->ms_on;
}

int sl_renderer_shading_rate(const sl_renderer *r) {
    return r->rate_k;
}

int sl_renderer_srbf_used(const sl_renderer *r) {
    return r->srbf_used;
}

double sl_renderer_frame_seconds(const sl_renderer *r) {
    return r->total_s;
}

int sl_renderer_kbuffer(const sl_renderer *r, int *w, int *h, int *K, const sl_kfrag **kbuf,
                        const uint8_t **kcount) {
    if (!r->view.kbuf) return -1;
    *w = r->view.w, *h = r->view.h, *K = r->view.K;
    *kbuf = r->view.kbuf, *kcount = r->view.kcount;
    return 0;
}

int sl_renderer_take_kbuffer(sl_renderer *r, int *w, int *h, int *K, sl_kfrag **kbuf,
                             uint8_t **kcount) {
    if (!r->view.kbuf) return -1;
    *w = r->view.w, *h = r->view.h, *K = r->view.K;
    *kbuf = r->view.kbuf, *kcount = r->view.kcount;
    r->view.kbuf = NULL, r->view.kcount = NULL;
    r->key[SL_PASSID_VIEW] = 0; /* handed over: the next frame fills a new one */
    return 0;
}

/* The descriptor of the record named name (every record's name is a descriptor's). */
static const sl_pass_desc *desc_of(const char *name) {
    for (int i = 0; i < SL_PASSID_COUNT; i++)
        if (strcmp(sl_passes[i].name, name) == 0) return &sl_passes[i];
    return NULL;
}

void sl_renderer_explain(const sl_renderer *r, FILE *f) {
    static const char *st[] = {"run", "cached", "skipped"};
    int width = sl_term_width(f); /* a file or a pipe gets whole rows, for grep */
    fprintf(f, "%-10s %-8s %9s  %s  [keyed on]\n", "pass", "state", "time", "why");
    for (int i = 0; i < r->npass; i++) {
        const sl_pass_desc *d = desc_of(r->pass[i].name);
        char keyed[160] = "-", rest[800];
        if (d) sl_pass_keyed_on(d, keyed, sizeof keyed);
        fprintf(f, "%-10s %-8s %8.3fs  ", r->pass[i].name, st[r->pass[i].state],
                r->pass[i].seconds);
        snprintf(rest, sizeof rest, "%s  [%s]", r->pass[i].why, keyed);
        sl_put_wrapped(f, rest, 31, 31, width);
        fputc('\n', f);
    }
    fprintf(f, "%-10s %-8s %8.3fs\n", "total", "", r->total_s);
}

int sl_shading_rate_parse(const char *s, int *k, sl_err *e) {
    if (strcmp(s, "auto") == 0) {
        *k = -1;
    } else if (strcmp(s, "fragment") == 0) {
        *k = 0;
    } else if (strcmp(s, "vertex") == 0) {
        *k = 1;
    } else if (strncmp(s, "vertex:", 7) == 0) {
        char *end;
        long v = strtol(s + 7, &end, 10);
        if (*end || end == s + 7 || v < 1 || v > 64)
            return sl_fail(e, "shading rate \"%s\": vertex:K needs an integer K in 1..64", s);
        *k = (int)v;
    } else {
        return sl_fail(e, "shading rate \"%s\": expected auto, fragment, vertex or vertex:K", s);
    }
    return 0;
}

int sl_frame_oit_k(const sl_scene *s) {
    int K = s->oit_layers > 0 ? s->oit_layers : 8;
    return K > SL_KBUFFER_MAX ? SL_KBUFFER_MAX : K;
}

int sl_frame_shadow_size(const sl_scene *s, int opt) {
    if (opt > 0) return opt;
    if (s->shadow_size > 0) return s->shadow_size;
    return (size_t)s->width * s->height > 1000000 ? 512 : 256;
}

int sl_frame_shadow_layers(const sl_scene *s) {
    int L = s->layers > 0 ? s->layers : SL_SHADOW_DEFAULT_LAYERS;
    return L > SL_SHADOW_MAX_LAYERS ? SL_SHADOW_MAX_LAYERS : L;
}

/* Per pixel: the frame buffer (SL_FBUF_FLOATS, alloc_fbuf), the K-buffer (K sl_kfrag + a uint8
 * count, frame_view.c), the fragment-rate shade map (K uint32, build_points) and ~16 B for the
 * outputs (cmd_render's EXR planes). Per lobe map: z0 (uint32) + K layers of 64-bit summed-area
 * tables (host/passes/light/shadow.h). The voxel grid: SL_VOX_FIELDS floats per voxel, and the
 * march's per-lobe textures on its coarse vertices. The shading points (at most one per K-buffer
 * entry: pos 24 B, tan 12 B, strand 4 B, T and the optical depth behind B 4 B each per lobe, out
 * 56 B) are counted at fragment rate, their largest case; at vertex rate the sharp lobes'
 * per-entry lookups (quality.sharp_shadows: 24 B of position while looked up, 4 B of T per
 * sharp lobe, 4 B per pixel) stay below it. */
void sl_frame_estimate(const sl_scene *s, int shadow_size_opt, sl_frame_need *n) {
    double npx = (double)s->width * (double)s->height;
    int K = sl_frame_oit_k(s);
    double fbuf = SL_FBUF_FLOATS * sizeof(float) * npx, kbuf = npx * K * (double)sizeof(sl_kfrag);
    double view = kbuf + npx * (1.0 + 4.0 * K), outs = 16.0 * npx;
    int size = sl_frame_shadow_size(s, shadow_size_opt), layers = sl_frame_shadow_layers(s);
    int nl = s->lobes > 0 ? s->lobes : 1;
    /* maps: SL_SHADOW_SPLIT_MAPS_PER_LOBE per lobe (broad lobes split), or with broad lobes
     * subdivided at most the lobes plus the sub-lobes of the scene's quality.sublobe_width (the
     * budget of plan_lobes.c); the frame shades as many lobes at most, each a T per point */
    int nmaps = SL_SHADOW_SPLIT_MAPS_PER_LOBE * nl;
    if (s->broad_lobes == SL_BROAD_SUBDIVIDE) nmaps = sl_subdiv_budget(nl, s->sublobe_width);
    int nshade = s->broad_lobes == SL_BROAD_SUBDIVIDE ? nmaps : nl;
    double points = npx * K * (24.0 + 12.0 + 4.0 + 8.0 * nshade + 4.0 * SL_SHADE_BASE_FLOATS);
    double shadow_one = (double)size * size * (4.0 + 8.0 * layers),
           shadow = (double)nmaps * shadow_one;
    double vox =
        s->voxels > 0 ? (double)s->voxels * s->voxels * s->voxels * 4.0 * SL_VOX_FIELDS : 0.0;
    /* the march's textures (sl_ftex): per shaded lobe and coarse vertex (every 4 voxels)
     * SL_MARCH_CH floats each of T_f, ln T_f, sigma_f and tilt2 and one of the maps' depth tau,
     * and the per-vertex dev^2 */
    double mv = s->voxels > 0 ? s->voxels / 4.0 + 2.0 : 0.0;
    vox += mv * mv * mv * 4.0 * ((4.0 * SL_MARCH_CH + 1.0) * nshade + SL_MARCH_CH);
    n->host = fbuf + view + outs + points + shadow + vox;
    n->largest = kbuf, n->largest_what = "K-buffer",
    n->setting = "image.width/height or quality.oit_layers";
    if (npx * 16.0 > n->largest)
        n->largest = npx * 16.0, n->largest_what = "frame buffer",
        n->setting = "image.width/height";
    if (shadow_one > n->largest)
        n->largest = shadow_one, n->largest_what = "deep opacity map",
        n->setting = "quality.shadow_size or quality.layers";
    if (vox > n->largest)
        n->largest = vox, n->largest_what = "voxel grid", n->setting = "quality.voxels";
    /* the setting to name for the total: the biggest contributor */
    double parts[4] = {fbuf + outs, view + points, shadow, vox};
    const char *names[4] = {"image.width/height", "image.width/height or quality.oit_layers",
                            "quality.shadow_size, quality.layers or quality.lobes",
                            "quality.voxels"};
    int big = 0;
    for (int i = 1; i < 4; i++)
        if (parts[i] > parts[big]) big = i;
    n->host_setting = names[big];
}

size_t sl_frame_estimate_bytes(const sl_scene *s, int shadow_size_opt) {
    sl_frame_need n;
    sl_frame_estimate(s, shadow_size_opt, &n);
    return n.host >= (double)SIZE_MAX ? SIZE_MAX : (size_t)n.host;
}

/* Runs, reuses or skips each pass of the table in order (the rule of plan/passes.h). */
static int run_passes(sl_renderer *r, const sl_frame_inputs *in, sl_err *e) {
    for (int i = 0; i < SL_PASSID_COUNT; i++) {
        const sl_pass_desc *d = &sl_passes[i];
        if (d->needed && !d->needed(r, in)) {
            record(r, d, SL_PASS_SKIPPED, 0, d->skip_why);
            continue;
        }
        uint64_t key = 0;
        int cached = 0;
        r->rec_state = SL_PASS_RUN;
        r->rec_why[0] = 0;
        if (d->keyed) {
            key = sl_pass_key(d, r->data_hash, d->settings ? d->settings(r, in) : 0);
            cached = key == r->key[i];
            if (!cached) r->key[i] = 0; /* a failed run leaves nothing valid behind */
        }
        if (cached) {
            if (d->on_cached)
                d->on_cached(r, in);
            else
                sl_frame_why(r, "%s", d->cached_why);
            record(r, d, SL_PASS_CACHED, 0, r->rec_why);
        } else {
            double t0 = sl_now();
            /* which pass a long frame is in, on a terminal (passes with a bar draw their own) */
            if (!r->o.quiet) /* the viewer and report render quietly, many frames */
                sl_status("%s%s%s pass (%d of %d), %.1f s", r->status_label,
                          r->status_label[0] ? ": " : "frame: ", d->name, i + 1, SL_PASSID_COUNT,
                          t0 - r->frame_t0);
            if (d->run(r, in, e)) return -1;
            if (d->keyed) r->key[i] = key;
            record(r, d, r->rec_state, r->rec_state == SL_PASS_CACHED ? 0 : sl_now() - t0,
                   r->rec_why);
        }
        /* a keyed pass's outputs carry its key to the passes keyed on them */
        if (d->keyed)
            for (int o = 0; o < SL_DATA_COUNT; o++)
                if (d->outputs & SL_IN(o)) r->data_hash[o] = key;
    }
    return 0;
}

static void free_work(sl_frame_work *w) {
    sl_lobes_free(&w->sub);
    free(w->used);
    free(w->share);
    sl_shade_points_free(&w->pts);
    sl_shade_map_free(&w->sm);
    memset(w, 0, sizeof *w);
}

int sl_renderer_frame(sl_renderer *r, const sl_scene *s, const sl_hair *h, const sl_lobes *lobes,
                      const sl_camera *cam, sl_fbuf *out, sl_err *e) {
    double t_start = sl_now();
    r->npass = 0;
    memset(out, 0, sizeof *out);
    const sl_material *mat = &s->material;
    /* models deon and chiang: the d'Eon fast path (kernels/srbf_deon.h, srbf_chiang.h) or Ren's
     * table baked from it shades; Xu's form exists for the Marschner model only */
    const char *model = sl_material_model_name(mat->model);
    if (mat->model != SL_MODEL_MARSCHNER && r->o.srbf_method == SL_SRBF_METHOD_XU)
        return sl_fail(e,
                       "render: material model %s: --method xu exists for the Marschner model "
                       "only (%s shades with --method fast; docs/srbf.md)",
                       model, model);
    if (lobes->count < 1) return sl_fail(e, "render: the environment has no lobes");
    if (r->strand_sigma_a && r->strand_sigma_a_n != h->num_strands)
        return sl_fail(e,
                       "render: per-strand sigma_a has %u strands but the hair has %u (the "
                       "overrides belong to another hair)",
                       r->strand_sigma_a_n, h->num_strands);
    sl_frame_work *w = &r->fw;
    memset(w, 0, sizeof *w);
    if (sl_shading_rate_parse(s->shading_rate, &w->rate, e)) return -1;
    w->K = sl_frame_oit_k(s);
    w->segments = r->o.segments > 0 ? r->o.segments : s->segments_m;
    w->transparent = sl_frame_hair_transparent(h);
    sl_frame_inputs in = {s, h, lobes, cam, out};
    sl_frame_hash_inputs(&in, r->data_hash);
    r->data_hash[SL_DATA_STRAND_SIGMA] = r->strand_key;
    r->frame_t0 = t_start;
    int rc = run_passes(r, &in, e);
    sl_status_clear();
    if (rc == 0) r->frames_done++;
    free_work(w);
    if (rc) sl_fbuf_free(out);
    r->total_s = sl_now() - t_start;
    return rc;
}
