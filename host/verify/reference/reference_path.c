/* reference_path.c: see reference_path.h. Loads what the path tracer needs (hair and camera as
 * `render` frames them, the map), runs cpu/reference/path_ref.c in whole passes under the time
 * budget and the cancel flag with a progress line, and makes the frame; the EXR, the JSON and
 * the cache are reference_path_record.c's. */
#include "verify/reference/reference_path.h"

#include "base/parallel.h"
#include "io/envmap/envmap.h"
#include "path_ref.h"
#include "verify/reference/path_noise.h"
#include "verify/reference/ref_record.h"
#include "verify/reference/reference_path_parts.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

void sl_path_settings_default(sl_path_settings *s) {
    memset(s, 0, sizeof *s);
    s->spp = 16;
    s->seed = 1;
    s->progress = 1;
}

void sl_path_prep_free(sl_path_prep *p) {
    slref_env_free(&p->env);
    slref_rt_free(p->rt);
    sl_envmap_free(&p->map);
    sl_hair_free(&p->hair);
    free(p->strand_sa);
    memset(p, 0, sizeof *p);
}

int sl_path_prepare(const sl_scene *s, const sl_path_settings *set, sl_path_prep *p, sl_err *e) {
    memset(p, 0, sizeof *p);
    if (set->spp < 0 || (set->spp == 0 && !(set->time_s > 0)))
        return sl_fail(e, "reference: --spp must be >= 1");
    if (!s->env_file[0])
        return sl_fail(e,
                       "%s: environment.file: the path tracer needs an environment map (lobes "
                       "alone are not enough)",
                       s->path);
    if (sl_ref_scene_load(s, set->width, set->height, &p->hair, &p->cam, &p->strand_sa, e))
        return -1;
    if (sl_envmap_load(s->env_file, set->clamp_nonfinite, &p->map, e)) {
        sl_path_prep_free(p);
        return -1;
    }
    p->threads = set->threads > 0 ? set->threads : sl_parallel_cpus();
    if (s->material.model == SL_MODEL_MARSCHNER)
        sl_note("reference: --path with model marschner: its albedo exceeds 1 where absorption "
                "is low (Xu 2011's form does not conserve energy: 1.05 at sigma_a 0.36, ~1.4 at "
                "0.18), so light scattered many times grows; models deon and chiang conserve it");
    return 0;
}

static double cpu_now(void) {
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The progress line (stderr a terminal only): passes done of the most, wall time, ETA and the
 * running noise estimate (path_noise.h, recomputed at most twice a second: O(pixels)). */
typedef struct progress {
    int active;
    double start, last;
} progress;

static void progress_show(progress *pg, const slref_path_accum *a, int done, int most,
                          double budget, int final) {
    if (!pg->active) return;
    double t = sl_now(), el = t - pg->start;
    if (!final && t - pg->last < 0.5) return;
    pg->last = t;
    double frac = most > 0 ? (double)done / most : 0;
    if (budget > 0 && el / budget > frac) frac = el / budget;
    if (frac > 1) frac = 1;
    char bar[31];
    for (int i = 0; i < 30; i++)
        bar[i] = i < (int)(frac * 30 + 0.5) ? '#' : '.';
    bar[30] = 0;
    double eta = frac > 0 ? el * (1 - frac) / frac : 0, nz = sl_path_noise(a, 1);
    char most_s[32];
    if (most > 0)
        snprintf(most_s, sizeof most_s, "%d", most);
    else
        snprintf(most_s, sizeof most_s, "-");
    fprintf(stderr, "\rpath [%s] %d/%s spp %.1fs eta %.1fs noise %s%.3g ", bar, done, most_s, el,
            eta, isfinite(nz) ? "" : "n/a ", isfinite(nz) ? nz : 0.0);
    if (final) fputc('\n', stderr);
    fflush(stderr);
}

static void frame_from(const slref_path_accum *a, sl_path_frame *f) {
    size_t n = (size_t)a->w * a->h;
    double ns = (double)a->n[0] + a->n[1];
    f->width = a->w, f->height = a->h;
    f->rgba = sl_malloc(4 * n * sizeof(float));
    f->depth = sl_malloc(n * sizeof(float));
    f->direct = sl_malloc(3 * n * sizeof(float));
    f->indirect = sl_malloc(3 * n * sizeof(float));
    f->lobes = sl_malloc(12 * n * sizeof(float));
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 4; c++)
            f->rgba[4 * i + c] = (float)((a->half[0][4 * i + c] + a->half[1][4 * i + c]) / ns);
        f->depth[i] = a->depth[i];
        const double *v = a->aov + SLREF_PATH_AOV * i;
        for (int c = 0; c < 3; c++)
            f->direct[3 * i + c] = (float)(v[c] / ns),
                              f->indirect[3 * i + c] = (float)(v[3 + c] / ns);
        for (int c = 0; c < 12; c++)
            f->lobes[12 * i + c] = (float)(v[6 + c] / ns);
    }
}

int sl_path_render_prepared(const sl_scene *s, const sl_path_settings *set, sl_path_prep *p,
                            sl_path_frame *out, sl_path_result *r, sl_err *e) {
    memset(out, 0, sizeof *out);
    if (!p->rt && slref_rt_build(&p->hair, &p->rt, e)) return -1;
    if (!p->env.row_cdf)
        slref_env_build(&p->env, p->map.rgb, p->map.width, p->map.height, s->env_rotation_deg,
                        s->env_intensity);
    slref_path_ctx ctx = {p->rt,   &s->material, p->strand_sa,          &p->env,
                          &p->cam, set->seed,    SLREF_PATH_MAX_EVENTS, SLREF_PATH_RR_EVENTS};
    slref_path_accum acc;
    slref_path_accum_init(&acc, p->cam.width, p->cam.height);
    int most = set->spp; /* 0 with a time budget: no sample limit */
    progress pg = {set->progress && isatty(2) && !sl_is_quiet(), sl_now(), 0};
    double t0 = sl_now(), c0 = cpu_now();
    int done = 0, stopped = 0;
    for (uint32_t k = 0; most == 0 || (int)k < most; k++) {
        if ((set->cancel && *set->cancel) ||
            slref_path_pass(&ctx, &acc, k, p->threads, set->cancel)) {
            stopped = 1;
            break;
        }
        done = (int)k + 1;
        double el = sl_now() - t0;
        progress_show(&pg, &acc, done, most, set->time_s, 0);
        /* whole passes: stop when the next one (at the mean pass time) would pass the budget */
        if (set->time_s > 0 && el + el / done > set->time_s) break;
        if (done == 0x7fffffff) break;
    }
    if (stopped) {
        if (pg.active) fputc('\n', stderr);
        slref_path_accum_free(&acc);
        r->interrupted = 1;
        return sl_fail(e, "reference: interrupted (SIGINT) after %d spp: nothing written", done);
    }
    progress_show(&pg, &acc, done, most, set->time_s, 1);
    r->wall_s = sl_now() - t0;
    r->cpu_s = cpu_now() - c0;
    r->spp = done;
    r->spp_asked = set->spp;
    r->threads = p->threads;
    long long ev;
    slref_path_stats(&acc, &r->paths, &ev, &r->capped);
    r->paths_per_s = r->wall_s > 0 ? (double)r->paths / r->wall_s : 0;
    r->events_per_path = r->paths > 0 ? (double)ev / (double)r->paths : 0;
    r->noise = sl_path_noise(&acc, 1);
    r->noise_4x4 = sl_path_noise(&acc, 4);
    r->noise_8x8 = sl_path_noise(&acc, 8);
    frame_from(&acc, out);
    size_t n = (size_t)out->width * out->height;
    memset(r->mean_rgb, 0, sizeof r->mean_rgb);
    r->coverage = 0;
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 3; c++)
            r->mean_rgb[c] += out->rgba[4 * i + c] / (double)n;
        r->coverage += out->rgba[4 * i + 3] / (double)n;
    }
    slref_path_accum_free(&acc);
    if (r->capped > 0)
        sl_warn("reference: %lld of %lld paths reached the cap of %d scattering events and were "
                "cut (their remaining light is missing)",
                r->capped, r->paths, SLREF_PATH_MAX_EVENTS);
    return 0;
}

int sl_path_render(const sl_scene *s, const sl_path_settings *set, sl_path_frame *out,
                   sl_path_result *r, sl_err *e) {
    memset(r, 0, sizeof *r);
    memset(out, 0, sizeof *out);
    sl_path_prep p;
    if (sl_path_prepare(s, set, &p, e)) return -1;
    int rc = sl_path_render_prepared(s, set, &p, out, r, e);
    if (rc == 0) r->key = sl_path_key(s, &p, r->spp, set->seed);
    sl_path_prep_free(&p);
    return rc;
}

void sl_path_frame_free(sl_path_frame *f) {
    free(f->rgba);
    free(f->depth);
    free(f->direct);
    free(f->indirect);
    free(f->lobes);
    memset(f, 0, sizeof *f);
}
