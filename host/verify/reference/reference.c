/* reference.c: see reference.h. Loads what the reference needs (hair, map, N lights, camera
 * framed as `render` frames it), derives the cache key from the content (not the file names),
 * and drives cpu/reference/render_ref.c (pixel mode) or cpu/reference/render_ref_frag.c on the
 * fast path's K-buffer (fragment mode, host/verify/reference/reference_frag.h). */
#include "verify/reference/reference.h"
#include "base/parallel.h"

#include "base/disk_cache.h"
#include "scene/camera.h"
#include "io/envmap/envmap.h"
#include "lighting/envsample.h"
#include "io/envmap/exr_cxx_shim.h"
#include "io/hair/hair.h"
#include "verify/reference/reference_frag.h"
#include "verify/reference/ref_record.h"
#include "render_ref.h"
#include "render_ref_frag.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Bump when the reference's output changes for the same inputs (invalidates caches). */
#define SL_REFERENCE_VERSION "reference-5" /* 5: material.strand_sigma_a honoured */
/* Fragment mode's own version (mixed into its keys only: pixel-mode caches stay valid). */
#define SL_REFERENCE_FRAG_VERSION "fragments-1"

void sl_reference_settings_default(sl_reference_settings *s) {
    memset(s, 0, sizeof *s);
    s->lights = 256;
    s->aa = 2;
    s->seed = 1;
    s->threads = 0;
    s->ms = -1;
    s->progress = 1;
    s->light_split = 1;
}

typedef struct prep {
    sl_hair hair;
    sl_envmap map;
    sl_camera cam;
    float *strand_sa; /* material.strand_sigma_a: 3 per strand, or NULL */
    int ms;
    slref_rt *rt;
    slref_ms_tables *mst;
    int threads;
    sl_ref_kbuffer kb; /* fragment mode: the fast path's K-buffer */
} prep;

static void prep_free(prep *p) {
    sl_ref_kbuffer_free(&p->kb);
    slref_ms_tables_free(p->mst);
    slref_rt_free(p->rt);
    sl_envmap_free(&p->map);
    sl_hair_free(&p->hair);
    free(p->strand_sa);
    memset(p, 0, sizeof *p);
}

static int prepare(const sl_scene *s, const sl_reference_settings *set, prep *p, sl_err *e) {
    memset(p, 0, sizeof *p);
    if (set->lights < 1) return sl_fail(e, "reference: --lights must be >= 1");
    if (set->aa < 1 || set->aa > 64) return sl_fail(e, "reference: --aa must be in 1..64");
    if (!s->env_file[0])
        return sl_fail(e,
                       "%s: environment.file: the reference needs an environment map (it cuts "
                       "the map into directional lights; lobes alone are not enough)",
                       s->path);
    /* hair and camera through the loader `render` uses: the same framing, the same size
     * overrides */
    if (sl_ref_scene_load(s, set->width, set->height, &p->hair, &p->cam, &p->strand_sa, e))
        return -1;
    if (sl_envmap_load(s->env_file, set->clamp_nonfinite, &p->map, e)) {
        prep_free(p);
        return -1;
    }
    if (set->ms >= 0)
        p->ms = set->ms;
    else if (s->multiple_scattering == SL_MS_ON)
        p->ms = 1;
    else if (s->multiple_scattering == SL_MS_OFF)
        p->ms = 0;
    else if (s->material.model == SL_MODEL_MARSCHNER)
        p->ms = 1;
    else
        sl_note("reference: material.model %s: single scattering only (this reference's "
                "ray-shot dual scattering is Marschner's; the path tracer, --path, has every "
                "order)",
                sl_material_model_name(s->material.model));
    if (p->ms && s->material.model != SL_MODEL_MARSCHNER) {
        sl_fail(e,
                "%s: multiple scattering in the direct reference needs material.model "
                "\"marschner\" (use --ms off, or --path for every order)",
                s->path);
        prep_free(p);
        return -1;
    }
    if (p->ms && p->strand_sa)
        sl_note("reference: material.strand_sigma_a: single scattering per strand; this "
                "reference's multiple scattering keeps the material's sigma_a (the path "
                "tracer, --path, follows every strand's own)");
    p->threads = set->threads > 0 ? set->threads : sl_parallel_cpus();
    if (set->fragments && sl_ref_kbuffer_build(s, &p->hair, &p->cam, p->threads, &p->kb, e)) {
        prep_free(p);
        return -1;
    }
    return 0;
}

static uint64_t hash_doubles(const double *v, size_t n, uint64_t h) {
    return sl_ref_hash_doubles(h, v, n);
}

static uint64_t compute_key(const sl_scene *s, const sl_reference_settings *set, const prep *p) {
    uint64_t h =
        sl_hash64(SL_REFERENCE_VERSION, strlen(SL_REFERENCE_VERSION), 1469598103934665603ull);
    const sl_hair *hr = &p->hair;
    h = sl_ref_content_hash(h, hr, p->map.hash, &s->material, &p->cam);
    h = sl_ref_strand_hash(h, p->strand_sa, hr->num_strands);
    if (set->fragments) {
        /* "fragments", K and what the view pass reads besides the geometry (transparency);
         * aa, seed and the light split do not enter (no camera rays) */
        h = sl_hash64(SL_REFERENCE_FRAG_VERSION, strlen(SL_REFERENCE_FRAG_VERSION), h);
        if (hr->transparency)
            h = sl_hash64(hr->transparency, (size_t)hr->num_points * sizeof(float), h);
        else
            h = sl_hash64(&hr->default_transparency, sizeof(float), h);
        double fv[] = {p->kb.K,          set->lights, p->ms,      s->env_rotation_deg,
                       s->env_intensity, SLREF_MS_DF, SLREF_MS_DB};
        return hash_doubles(fv, sizeof fv / sizeof fv[0], h);
    }
    double sv[] = {set->lights,         set->aa,          (double)set->seed, p->ms,
                   s->env_rotation_deg, s->env_intensity, SLREF_MS_DF,       SLREF_MS_DB,
                   set->light_split};
    return hash_doubles(sv, sizeof sv / sizeof sv[0], h);
}

/* N lights from the map, rotated about +Y and scaled as the scene says (sl_lobes_transform). */
static int make_lights(const sl_scene *s, const prep *p, int n, slref_light **out, int *count,
                       sl_err *e) {
    sl_envlights L;
    if (sl_envsample(&p->map, n, 0.0, p->threads, &L, NULL, NULL, e)) return -1;
    double r = s->env_rotation_deg * M_PI / 180.0, c = cos(r), sn = sin(r);
    slref_light *l = sl_malloc((size_t)L.count * sizeof *l);
    for (int i = 0; i < L.count; i++) {
        const double *d = L.light[i].dir;
        l[i].dir[0] = c * d[0] + sn * d[2];
        l[i].dir[1] = d[1];
        l[i].dir[2] = -sn * d[0] + c * d[2];
        for (int k = 0; k < 3; k++)
            l[i].rgb[k] = L.light[i].rgb[k] * s->env_intensity;
    }
    *count = L.count;
    *out = l;
    sl_envlights_free(&L);
    return 0;
}

static void progress_cb(void *user, double f) {
    sl_progress_update(user, f);
}

/* Renders p's scene with n lights into out. */
static int render_prepared(const sl_scene *s, const sl_reference_settings *set, prep *p, int n,
                           uint64_t seed, const char *label, sl_reference_frame *out, sl_err *e) {
    memset(out, 0, sizeof *out);
    if (!p->rt && slref_rt_build(&p->hair, &p->rt, e)) return -1;
    if (p->ms && !p->mst && slref_ms_tables_build(&s->material, p->threads, &p->mst, e)) return -1;
    slref_light *L = NULL;
    int nl = 0;
    if (make_lights(s, p, n, &L, &nl, e)) return -1;
    slref_shading sh = {p->rt, &s->material, L, nl, p->ms ? p->mst : NULL, p->strand_sa};
    sl_progress pr;
    slref_render_opts o = {set->aa, 0, seed, p->threads, NULL, NULL};
    if (set->progress) {
        sl_progress_begin(&pr, label);
        o.progress = progress_cb;
        o.progress_user = &pr;
    }
    double t0 = sl_now();
    slref_image img;
    int rc;
    if (set->fragments) {
        slref_kbuf kb = {p->kb.w, p->kb.h, p->kb.K, p->kb.kbuf, p->kb.kcount};
        rc = slref_render_frags(&sh, &p->hair, &kb, p->cam.eye, &o, &img, e);
    } else {
        rc = slref_render_split(&sh, &p->cam, &o, set->light_split, &img, e);
    }
    if (set->progress) sl_progress_end(&pr);
    free(L);
    if (rc) return -1;
    out->width = img.w, out->height = img.h;
    out->rgba = img.rgba, out->depth = img.depth, out->ms_rgb = img.ms_rgb;
    out->mode_rgb = img.mode_rgb;
    out->lights = nl;
    out->ms = p->ms;
    out->fragments = set->fragments;
    out->time_s = sl_now() - t0;
    return 0;
}

int sl_reference_render(const sl_scene *s, const sl_reference_settings *set,
                        sl_reference_frame *out, sl_err *e) {
    memset(out, 0, sizeof *out);
    prep p;
    if (prepare(s, set, &p, e)) return -1;
    uint64_t key = compute_key(s, set, &p);
    int rc = render_prepared(s, set, &p, set->lights, set->seed,
                             set->fragments ? "reference (fragments)" : "reference", out, e);
    out->key = key;
    prep_free(&p);
    return rc;
}

void sl_reference_frame_free(sl_reference_frame *f) {
    free(f->rgba);
    free(f->depth);
    free(f->ms_rgb);
    free(f->mode_rgb);
    memset(f, 0, sizeof *f);
}

/* The EXR channels, in plane order: rgba, depth, MS, modes. */
enum { NPLANES = 17 };
static const char *const PLANE_NAMES[NPLANES] = {
    "R",        "G",        "B",    "A",    "Z",    "MS.R",  "MS.G",  "MS.B", "R_mode.R",
    "R_mode.G", "R_mode.B", "TT.R", "TT.G", "TT.B", "TRT.R", "TRT.G", "TRT.B"};

int sl_reference_write_exr(const char *path, const sl_reference_frame *f, sl_err *e) {
    size_t n = (size_t)f->width * f->height;
    float *pl = sl_malloc(NPLANES * n * sizeof(float));
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 4; c++)
            pl[c * n + i] = f->rgba[4 * i + c];
        pl[4 * n + i] = f->depth[i];
        for (int c = 0; c < 3; c++)
            pl[(5 + c) * n + i] = f->ms_rgb[3 * i + c];
        for (int c = 0; c < 9; c++)
            pl[(8 + c) * n + i] = f->mode_rgb[9 * i + c];
    }
    return sl_ref_exr_write_planes(path, f->width, f->height, PLANE_NAMES, NPLANES, pl, e);
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

void sl_image_error(const float *x, const float *ref, int w, int h, double *rel_rmse,
                    double rgb3[3], double *p99) {
    size_t n = (size_t)w * h, nh = 0;
    double num[3] = {0, 0, 0}, den[3] = {0, 0, 0}, ref2 = 0;
    for (size_t i = 0; i < n; i++) {
        if (!(x[4 * i + 3] > 0) && !(ref[4 * i + 3] > 0)) continue;
        nh++;
        for (int c = 0; c < 3; c++) {
            double d = (double)x[4 * i + c] - ref[4 * i + c];
            num[c] += d * d;
            den[c] += (double)ref[4 * i + c] * ref[4 * i + c];
            ref2 += (double)ref[4 * i + c] * ref[4 * i + c];
        }
    }
    double mean = 0;
    for (int c = 0; c < 3; c++) {
        double r = den[c] > 0 ? sqrt(num[c] / den[c]) : (num[c] > 0 ? INFINITY : 0);
        if (rgb3) rgb3[c] = r;
        mean += r / 3;
    }
    if (rel_rmse) *rel_rmse = mean;
    if (!p99) return;
    *p99 = 0;
    if (nh == 0) return;
    double floor_ = 0.01 * sqrt(ref2 / nh), *err = sl_malloc(nh * sizeof(double));
    size_t k = 0;
    for (size_t i = 0; i < n; i++) {
        if (!(x[4 * i + 3] > 0) && !(ref[4 * i + 3] > 0)) continue;
        double d2 = 0, r2 = 0;
        for (int c = 0; c < 3; c++) {
            double d = (double)x[4 * i + c] - ref[4 * i + c];
            d2 += d * d;
            r2 += (double)ref[4 * i + c] * ref[4 * i + c];
        }
        double r = sqrt(r2) > floor_ ? sqrt(r2) : floor_;
        err[k++] = r > 0 ? sqrt(d2) / r : (d2 > 0 ? INFINITY : 0);
    }
    qsort(err, nh, sizeof(double), cmp_double);
    size_t idx = (size_t)ceil(0.99 * nh);
    *p99 = err[idx > 0 ? idx - 1 : 0];
    free(err);
}

void sl_image_error_blocks(const float *x, const float *ref, int w, int h, int b, double *rel_rmse,
                           double *p99) {
    if (b < 1) b = 1;
    int bw = (w + b - 1) / b, bh = (h + b - 1) / b;
    size_t nb = (size_t)bw * bh;
    float *xs = sl_calloc(4 * nb, sizeof(float)), *rs = sl_calloc(4 * nb, sizeof(float));
    int *cnt = sl_calloc(nb, sizeof(int));
    for (int y = 0; y < h; y++)
        for (int xx = 0; xx < w; xx++) {
            size_t i = (size_t)y * w + xx, k = (size_t)(y / b) * bw + xx / b;
            cnt[k]++;
            for (int c = 0; c < 4; c++)
                xs[4 * k + c] += x[4 * i + c], rs[4 * k + c] += ref[4 * i + c];
        }
    for (size_t k = 0; k < nb; k++)
        for (int c = 0; c < 4; c++)
            xs[4 * k + c] /= (float)cnt[k], rs[4 * k + c] /= (float)cnt[k];
    sl_image_error(xs, rs, bw, bh, rel_rmse, NULL, p99);
    free(xs);
    free(rs);
    free(cnt);
}

/* The JSON beside the EXR: the key, settings, time, convergence and the EXR's digest. */
static int write_json(const char *path, const sl_scene *s, const sl_reference_settings *set,
                      const sl_reference_result *r, int w, int h, sl_ref_digest d, sl_err *e) {
    cJSON *ref, *root = sl_ref_record_begin(r->key, s->path, w, h, &ref);
    cJSON_AddNumberToObject(ref, "lights", r->lights);
    cJSON_AddNumberToObject(ref, "lights_asked", set->lights);
    cJSON_AddNumberToObject(ref, "aa", set->aa);
    cJSON_AddNumberToObject(ref, "seed", (double)set->seed);
    cJSON_AddBoolToObject(ref, "light_split", set->light_split);
    cJSON_AddBoolToObject(ref, "multiple_scattering", r->ms);
    cJSON_AddBoolToObject(ref, "fragments", set->fragments);
    if (set->fragments) {
        cJSON_AddNumberToObject(ref, "oit_k", r->oit_k);
        cJSON_AddNumberToObject(ref, "entries", r->entries);
    }
    cJSON_AddNumberToObject(ref, "time_s", r->time_s);
    sl_ref_add_mean(ref, r->mean_rgb, r->coverage);
    if (r->has_convergence) {
        cJSON *c = cJSON_AddObjectToObject(ref, "convergence");
        cJSON_AddNumberToObject(c, "lights_2n", 2 * set->lights);
        if (!set->fragments) cJSON_AddNumberToObject(c, "seed_2n", (double)(set->seed + 1));
        cJSON_AddNumberToObject(c, "rel_rmse", r->conv_rel_rmse);
        cJSON_AddNumberToObject(c, "p99_rel_err", r->conv_p99);
        cJSON_AddNumberToObject(c, "rel_rmse_4x4", r->conv_rel_rmse_4x4);
        cJSON_AddNumberToObject(c, "time_2n_s", r->time_2n_s);
    }
    sl_ref_integrity_add(ref, d);
    return sl_ref_json_write(path, root, e);
}

/* 1 when path.json records this key (and a convergence when asked) and the EXR's digest; fills
 * r. */
static int read_cached(const char *json_path, const char *exr_path, uint64_t key, int conv,
                       sl_reference_result *r) {
    if (access(exr_path, R_OK) != 0) return 0;
    cJSON *root = sl_ref_json_read(json_path);
    if (!root) return 0;
    int ok = 0;
    const cJSON *ref = cJSON_GetObjectItemCaseSensitive(root, "reference");
    if (sl_ref_key_matches(ref, key)) {
        const cJSON *c = cJSON_GetObjectItemCaseSensitive(ref, "convergence");
        int usable = !conv || cJSON_IsObject(c);
        sl_ref_digest d;
        if (usable && (sl_cache_file_hash(exr_path, &d.hash, &d.bytes, NULL) != 0 ||
                       !sl_ref_integrity_matches(ref, d))) {
            sl_warn("reference: %s does not match the digest in %s (corrupt, truncated or "
                    "written before digests); rendering it again",
                    exr_path, json_path);
            usable = 0;
        }
        if (usable) {
            ok = 1;
            r->cached = 1;
            r->key = key;
            const cJSON *v;
            if ((v = cJSON_GetObjectItemCaseSensitive(ref, "lights")) && cJSON_IsNumber(v))
                r->lights = v->valueint;
            if ((v = cJSON_GetObjectItemCaseSensitive(ref, "time_s")) && cJSON_IsNumber(v))
                r->time_s = v->valuedouble;
            if ((v = cJSON_GetObjectItemCaseSensitive(ref, "coverage")) && cJSON_IsNumber(v))
                r->coverage = v->valuedouble;
            const cJSON *mv = cJSON_GetObjectItemCaseSensitive(ref, "mean_rgb");
            for (int c = 0; c < 3 && cJSON_GetArraySize(mv) == 3; c++)
                if (cJSON_IsNumber(cJSON_GetArrayItem(mv, c)))
                    r->mean_rgb[c] = cJSON_GetArrayItem(mv, c)->valuedouble;
            r->ms = cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(ref, "multiple_scattering"));
            r->fragments = cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(ref, "fragments"));
            if ((v = cJSON_GetObjectItemCaseSensitive(ref, "oit_k")) && cJSON_IsNumber(v))
                r->oit_k = v->valueint;
            if ((v = cJSON_GetObjectItemCaseSensitive(ref, "entries")) && cJSON_IsNumber(v))
                r->entries = v->valuedouble;
            if (cJSON_IsObject(c)) {
                r->has_convergence = 1;
                if ((v = cJSON_GetObjectItemCaseSensitive(c, "rel_rmse")) && cJSON_IsNumber(v))
                    r->conv_rel_rmse = v->valuedouble;
                if ((v = cJSON_GetObjectItemCaseSensitive(c, "p99_rel_err")) && cJSON_IsNumber(v))
                    r->conv_p99 = v->valuedouble;
                if ((v = cJSON_GetObjectItemCaseSensitive(c, "rel_rmse_4x4")) && cJSON_IsNumber(v))
                    r->conv_rel_rmse_4x4 = v->valuedouble;
                if ((v = cJSON_GetObjectItemCaseSensitive(c, "time_2n_s")) && cJSON_IsNumber(v))
                    r->time_2n_s = v->valuedouble;
            }
        }
    }
    cJSON_Delete(root);
    return ok;
}

int sl_reference_run(const sl_scene *s, const sl_reference_settings *set, const char *exr_path,
                     int convergence, sl_reference_result *res, sl_err *e) {
    memset(res, 0, sizeof *res);
    prep p;
    if (prepare(s, set, &p, e)) return -1;
    res->key = compute_key(s, set, &p);
    char json_path[4200];
    snprintf(json_path, sizeof json_path, "%s.json", exr_path);
    if (read_cached(json_path, exr_path, res->key, convergence, res)) {
        prep_free(&p);
        return 0;
    }
    sl_reference_frame f = {0}, f2 = {0};
    int rc = -1;
    res->fragments = set->fragments;
    res->oit_k = set->fragments ? p.kb.K : 0;
    res->entries = (double)p.kb.entries;
    if (set->fragments)
        sl_note("reference: fragment mode: %.0f K-buffer entries (K %d) x %d lights", res->entries,
                p.kb.K, set->lights);
    if (render_prepared(s, set, &p, set->lights, set->seed,
                        set->fragments ? "reference (fragments)" : "reference", &f, e))
        goto done;
    res->lights = f.lights;
    res->ms = f.ms;
    res->time_s = f.time_s;
    {
        size_t np = (size_t)f.width * f.height;
        for (size_t i = 0; i < np; i++) {
            for (int c = 0; c < 3; c++)
                res->mean_rgb[c] += f.rgba[4 * i + c] / (double)np;
            res->coverage += f.rgba[4 * i + 3] / (double)np;
        }
    }
    if (convergence) {
        /* Another jitter seed for the 2N image: with the same camera rays the comparison would
         * see the light cut's error only, not the camera-ray sampling's, which dominates at
         * low resolution (two seeds at aa 2 differ by 0.71 rel. RMSE on the default scene at
         * 64 x 48; N vs 2N with one seed by 0.15: docs/results.md). */
        /* Fragment mode: the same fragments at 2N lights (no camera rays: the light cut's
         * error alone, sample's median cut being deterministic). */
        if (render_prepared(s, set, &p, 2 * set->lights, set->seed + 1,
                            set->fragments ? "reference (fragments, 2N lights)"
                                           : "reference (2N lights)",
                            &f2, e))
            goto done;
        sl_image_error(f.rgba, f2.rgba, f.width, f.height, &res->conv_rel_rmse, NULL,
                       &res->conv_p99);
        sl_image_error_blocks(f.rgba, f2.rgba, f.width, f.height, 4, &res->conv_rel_rmse_4x4, NULL);
        res->time_2n_s = f2.time_s;
        res->has_convergence = 1;
    }
    if (sl_reference_write_exr(exr_path, &f, e)) goto done;
    sl_ref_digest d;
    if (sl_cache_file_hash(exr_path, &d.hash, &d.bytes, e)) goto done;
    if (write_json(json_path, s, set, res, f.width, f.height, d, e)) goto done;
    rc = 0;
done:
    sl_reference_frame_free(&f);
    sl_reference_frame_free(&f2);
    prep_free(&p);
    return rc;
}

int sl_reference_load(const char *exr_path, sl_reference_frame *out, sl_err *e) {
    memset(out, 0, sizeof *out);
    char json_path[4200];
    snprintf(json_path, sizeof json_path, "%s.json", exr_path);
    unsigned char *data = NULL;
    size_t size = 0;
    if (sl_read_file(json_path, &data, &size, 1 << 20, e)) return -1;
    cJSON *root = cJSON_ParseWithLength((const char *)data, size);
    free(data);
    const cJSON *ref = cJSON_GetObjectItemCaseSensitive(root, "reference");
    const cJSON *w = cJSON_GetObjectItemCaseSensitive(ref, "width");
    const cJSON *h = cJSON_GetObjectItemCaseSensitive(ref, "height");
    const cJSON *k = cJSON_GetObjectItemCaseSensitive(ref, "key");
    if (!cJSON_IsNumber(w) || !cJSON_IsNumber(h) || w->valueint < 1 || h->valueint < 1 ||
        w->valueint > 16384 || h->valueint > 16384 || !cJSON_IsString(k)) {
        cJSON_Delete(root);
        return sl_fail(e, "%s: not a reference record (reference.width/height/key)", json_path);
    }
    int W = w->valueint, H = h->valueint;
    const cJSON *v;
    if ((v = cJSON_GetObjectItemCaseSensitive(ref, "lights")) && cJSON_IsNumber(v))
        out->lights = v->valueint;
    if ((v = cJSON_GetObjectItemCaseSensitive(ref, "time_s")) && cJSON_IsNumber(v))
        out->time_s = v->valuedouble;
    out->ms = cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(ref, "multiple_scattering"));
    out->fragments = cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(ref, "fragments"));
    out->key = strtoull(k->valuestring, NULL, 16);
    if (sl_read_file(exr_path, &data, &size, (size_t)1 << 34, e)) {
        cJSON_Delete(root);
        return -1;
    }
    /* a record without a digest predates them and is taken as it is; one with a digest must
     * match the EXR (a reference read back is what every error of a report is measured against) */
    sl_ref_digest d = {size, sl_cache_hash(data, size)};
    int has_digest = cJSON_GetObjectItemCaseSensitive(ref, "integrity") != NULL;
    int digest_ok = !has_digest || sl_ref_integrity_matches(ref, d);
    cJSON_Delete(root);
    if (!digest_ok) {
        free(data);
        return sl_fail(e, "%s: does not match the digest in %s (corrupt, truncated or replaced)",
                       exr_path, json_path);
    }
    size_t n = (size_t)W * H;
    float *pl = sl_malloc(NPLANES * n * sizeof(float));
    float *planes[NPLANES];
    for (int c = 0; c < NPLANES; c++)
        planes[c] = pl + c * n;
    char msg[512];
    int rc = sl_exrcxx_read_planes(data, size, W, H, NPLANES, PLANE_NAMES, planes, msg, sizeof msg);
    free(data);
    if (rc) {
        free(pl);
        return sl_fail(e, "%s: %s", exr_path, msg);
    }
    out->width = W, out->height = H;
    out->rgba = sl_malloc(4 * n * sizeof(float));
    out->depth = sl_malloc(n * sizeof(float));
    out->ms_rgb = sl_malloc(3 * n * sizeof(float));
    out->mode_rgb = sl_malloc(9 * n * sizeof(float));
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 4; c++)
            out->rgba[4 * i + c] = pl[c * n + i];
        out->depth[i] = pl[4 * n + i];
        for (int c = 0; c < 3; c++)
            out->ms_rgb[3 * i + c] = pl[(5 + c) * n + i];
        for (int c = 0; c < 9; c++)
            out->mode_rgb[9 * i + c] = pl[(8 + c) * n + i];
    }
    free(pl);
    return 0;
}
