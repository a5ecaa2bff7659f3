/* envfit.c: the fitting driver (see envfit.h): pyramid, greedy start, coarse-to-fine LM,
 * auto lobe count, final errors. */
#include "lighting/envfit_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void sl_envfit_default_settings(sl_envfit_settings *s) {
    memset(s, 0, sizeof *s);
    s->lobes = 40;
    s->target_error = 0.1;
    s->max_lobes = 256;
    s->lambda_min = 0;
    s->lambda_max = 1.0;
    s->effort = 1;
    s->threads = 2;
    s->conv_lambda = 10.0 * M_PI / 180.0;
    s->progress = 0;
}

/* LM iterations on the level `t` steps below the coarsest: most of the work happens where it is
 * cheap; the fine levels only polish (mainly the narrow lobes, whose bound relaxes there). */
#define EFL_FREEZE 16.0

static int level_budget(int t) {
    static const int b[] = {60, 40, 25, 15, 10, 8};
    return t < 6 ? b[t] : 6;
}

typedef struct fit_state {
    efl_level *L;
    int nlev;
    const sl_envfit_settings *s;
    double lam_min, lam_max;
    double *res; /* residual buffer, level 0 size */
    sl_progress prog;
    double work_total, work_done;
    int iters;
} fit_state;

static double level_work(const fit_state *st, int lv) {
    return (double)st->L[lv].w * st->L[lv].h * level_budget(st->nlev - 1 - lv);
}

static double lobe_power(const sl_lobe *l) {
    return (l->rgb[0] + l->rgb[1] + l->rgb[2]) * sl_lobe_integral(l->lambda);
}

/* Swap moves: a lobe is taken out and a new one put at the dictionary atom that best explains
 * the residual; the swap is kept if the refined objective drops. Two kinds: merging the two
 * lobes that overlap most (the greedy start may spend two lobes on one sun, which then settle on
 * either side of it, a local minimum no gradient step leaves), and dropping the weakest lobe. */
static double try_swap(efl_eval *ev, const efl_dict *d, sl_lobe *lobes, int n, const efl_lm_opts *o,
                       double F, int merge, int *iters) {
    if (n < 2) return -1;
    sl_lobe *save = sl_malloc(sizeof *save * (size_t)n);
    memcpy(save, lobes, sizeof *save * (size_t)n);
    int k = 0;
    if (merge) {
        /* The pair with the smallest angle relative to their widths (and the pixel size). */
        double h = M_PI / ev->lv->h, best = 1e300;
        int bj = -1, bk = -1;
        for (int j = 0; j < n; j++)
            for (int q = j + 1; q < n; q++) {
                const double *a = lobes[j].dir, *b = lobes[q].dir;
                double ang = acos(fmax(-1.0, fmin(1.0, a[0] * b[0] + a[1] * b[1] + a[2] * b[2])));
                double r = ang / (lobes[j].lambda + lobes[q].lambda + h);
                if (r < best) {
                    best = r;
                    bj = j;
                    bk = q;
                }
            }
        if (bj < 0 || best > 1.0) {
            free(save);
            return -1;
        }
        /* Merged lobe: power-weighted direction, the wider width, the summed power. */
        sl_lobe *A = &lobes[bj], *B = &lobes[bk];
        double pa = lobe_power(A), pb = lobe_power(B), m[3];
        for (int c = 0; c < 3; c++)
            m[c] = pa * A->dir[c] + pb * B->dir[c];
        double nm = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
        if (nm > 0)
            for (int c = 0; c < 3; c++)
                A->dir[c] = m[c] / nm;
        double lam = fmax(A->lambda, B->lambda), ia = sl_lobe_integral(A->lambda),
               ib = sl_lobe_integral(B->lambda), im = sl_lobe_integral(lam);
        for (int c = 0; c < 3; c++)
            A->rgb[c] = (A->rgb[c] * ia + B->rgb[c] * ib) / im;
        A->lambda = lam;
        k = bk;
    } else {
        for (int j = 1; j < n; j++)
            if (lobe_power(&lobes[j]) < lobe_power(&lobes[k])) k = j;
    }
    lobes[k] = lobes[n - 1];
    efl_greedy(d, lobes, n - 1, n);
    int it = 0;
    /* A short refinement decides; the level's next pass (or level) polishes the winner. */
    efl_lm_opts os = *o;
    if (os.max_iter > 15) os.max_iter = 15;
    double F2 = efl_lm(ev, lobes, n, &os, &it, NULL, 0, 0);
    *iters += it;
    if (F2 < F * (1 - 1e-6)) {
        free(save);
        return F2;
    }
    memcpy(lobes, save, sizeof *save * (size_t)n);
    free(save);
    efl_objective(ev, lobes, n); /* restore the residual buffer */
    return -1;
}

static void fit_levels(fit_state *st, const efl_dict *d, sl_lobe *lobes, int n) {
    const sl_envfit_settings *s = st->s;
    int top = st->nlev - 1;
    for (int lv = top; lv >= 0; lv--) {
        const efl_level *L = &st->L[lv];
        efl_lm_opts o;
        /* Coarse levels may not resolve what they cannot see: lobes there are at least a pixel
         * wide (a lobe tuned to a coarse pixel's footprint transfers badly to the next level);
         * the bound relaxes level by level down to lambda_min on the map itself. */
        o.lam_lo = lv > 0 ? fmin(fmax(st->lam_min, M_PI / L->h), st->lam_max) : st->lam_min;
        o.lam_hi = st->lam_max;
        o.max_iter = (int)ceil(level_budget(top - lv) * s->effort);
        o.rel_tol = 1e-5 / s->effort;
        efl_eval ev = {L, s->threads, EFL_CUT, st->res, NULL};
        double w = level_work(st, lv) / st->work_total;
        double p0 = st->work_done, p1 = p0 + w;
        int it = 0;
        double tl = sl_now();
        /* On the big levels, lobes broader than EFL_FREEZE pixels were resolved on the coarser
         * levels: there they only contribute a fixed background, which saves most of the
         * fine-level work (effort scales the threshold, so long runs refine everything). */
        double freeze =
            (double)L->w * L->h >= (1 << 17) ? EFL_FREEZE * s->effort * M_PI / L->h : INFINITY;
        int na = 0;
        for (int j = 0; j < n; j++)
            if (lobes[j].lambda < freeze) na++;
        double *bg = NULL;
        sl_lobe *act = lobes, *fro = NULL;
        if (na < n) {
            act = sl_malloc(sizeof *act * (size_t)(na ? na : 1));
            fro = sl_malloc(sizeof *fro * (size_t)(n - na));
            int ia = 0, ib = 0;
            for (int j = 0; j < n; j++) {
                if (lobes[j].lambda < freeze)
                    act[ia++] = lobes[j];
                else
                    fro[ib++] = lobes[j];
            }
            size_t np = (size_t)L->w * L->h * 3;
            bg = sl_malloc(sizeof(double) * np);
            efl_objective(&ev, fro, n - na);
            for (size_t i = 0; i < np; i++)
                bg[i] = st->res[i] + L->rgb[i];
            ev.bg = bg;
        }
        double F = na ? efl_lm(&ev, act, na, &o, &it, s->progress ? &st->prog : NULL, p0, p1)
                      : efl_objective(&ev, act, 0);
        st->iters += it;
        if (act != lobes) {
            int ia = 0, ib = 0;
            for (int j = 0; j < n; j++)
                lobes[j] = lobes[j].lambda < freeze ? act[ia++] : fro[ib++];
            free(act);
            free(fro);
            free(bg);
            ev.bg = NULL;
        }
        if (s->verbose)
            fprintf(
                stderr,
                "fit: level %d (%dx%d): %d of %d lobes free, %d iterations, rel_l2 %.5g, %.3f s\n",
                lv, L->w, L->h, na, n, it, L->energy > 0 ? sqrt(2 * F / L->energy) : 0.0,
                sl_now() - tl);
        /* Swaps are worth trying while the level is cheap; effort buys more of them. */
        if (lv >= top - 1) {
            int rounds = (int)ceil(2 * s->effort);
            for (int merge = 1; merge >= 0; merge--)
                for (int r = 0; r < rounds; r++) {
                    double F2 = try_swap(&ev, d, lobes, n, &o, F, merge, &st->iters);
                    if (F2 < 0) break;
                    F = F2;
                }
        }
        st->work_done = p1;
        if (s->progress) sl_progress_update(&st->prog, p1);
    }
}

static int cmp_power(const void *a, const void *b) {
    double pa = lobe_power(a), pb = lobe_power(b);
    return pa > pb ? -1 : pa < pb ? 1 : 0;
}

int sl_envfit(const sl_envmap *map, const sl_envfit_settings *s, sl_lobes *out,
              sl_envfit_report *rep, sl_err *e) {
    memset(out, 0, sizeof *out);
    memset(rep, 0, sizeof *rep);
    out->rel_l2 = out->lobe_conv_rel_l2 = -1;
    if (!map || map->width < 2 || map->height < 1 || !map->rgb)
        return sl_fail(e, "fit: the environment map is empty");
    if (s->lobes < 0 || s->lobes > SL_FIT_LOBES_MAX)
        return sl_fail(e, "fit: bad lobe count %d", s->lobes);
    if (s->lobes == 0 &&
        (s->max_lobes < 1 || s->max_lobes > SL_FIT_LOBES_MAX || !(s->target_error > 0)))
        return sl_fail(e, "fit: auto mode needs max_lobes >= 1 and target_error > 0");
    if (!(s->lambda_max > 0) || !(s->lambda_min >= 0) || !(s->effort > 0) || !(s->conv_lambda > 0))
        return sl_fail(e, "fit: lambda bounds, effort and conv_lambda must be positive");
    size_t np = (size_t)map->width * map->height * 3;
    for (size_t i = 0; i < np; i++)
        if (!isfinite(map->rgb[i]) || map->rgb[i] < 0)
            return sl_fail(e, "fit: the environment map has a negative or non-finite value");
    double t0 = sl_now();
    fit_state st;
    memset(&st, 0, sizeof st);
    st.s = s;
    st.lam_max = s->lambda_max;
    st.lam_min = s->lambda_min > 0 ? s->lambda_min : 0.25 * M_PI / map->height;
    if (st.lam_min > st.lam_max)
        return sl_fail(e, "fit: lambda_min %.4g exceeds lambda_max %.4g", st.lam_min, st.lam_max);
    int cap_all = s->lobes > 0 ? s->lobes : s->max_lobes;
    sl_lobe *all = sl_calloc((size_t)cap_all, sizeof *all);
    /* Suns first, each with a lobe of its own (envfit_sun.c); at most a quarter of the lobes. */
    float *sky = sl_malloc(sizeof(float) * np);
    int ns = efl_split_suns(map, cap_all / 4 < 4 ? cap_all / 4 : 4, st.lam_min, st.lam_max,
                            s->threads, sky, all);
    sl_envmap skymap = *map;
    skymap.rgb = sky;
    if (s->verbose) fprintf(stderr, "fit: %d sun lobe(s), %.3f s\n", ns, sl_now() - t0);
    st.nlev = efl_pyramid(&skymap, 32, &st.L);
    free(sky);
    st.res = sl_malloc(sizeof(double) * np);
    int top = st.nlev - 1;
    for (int k = 0; k < st.nlev; k++)
        st.work_total += level_work(&st, k);
    efl_dict d;
    double dlo = fmin(fmax(st.lam_min, M_PI / st.L[top].h), st.lam_max);
    efl_dict_build(&d, &st.L[top], dlo, st.lam_max, s->threads);
    if (s->verbose) fprintf(stderr, "fit: pyramid + dictionary %.3f s\n", sl_now() - t0);

    /* The sky's lobes; the suns stay as fitted. */
    sl_lobe *lobes = all + ns;
    int cap = cap_all - ns;
    int n = s->lobes > 0 ? cap : (cap < 8 ? cap : 8);
    if (s->progress) sl_progress_begin(&st.prog, "fit");
    /* Continuation in the number of lobes on the coarsest level: 10, 20, 40, ... lobes, each
     * round refined before the next adds lobes on its residual. Large N then starts from the
     * solution for N/2 instead of one long greedy pass (with 80 lobes at once LM stalled above
     * the 40-lobe error on blender_exr/studio.exr). */
    {
        efl_eval ev = {&st.L[top], s->threads, EFL_CUT, st.res, NULL};
        efl_lm_opts o = {(int)ceil(level_budget(0) * s->effort), 1e-5 / s->effort,
                         top > 0 ? fmin(fmax(st.lam_min, M_PI / st.L[top].h), st.lam_max)
                                 : st.lam_min,
                         st.lam_max};
        int m = n < 10 ? n : 10;
        efl_greedy(&d, lobes, 0, m);
        while (m < n) {
            int it = 0;
            efl_lm(&ev, lobes, m, &o, &it, NULL, 0, 0);
            st.iters += it;
            int m2 = 2 * m < n ? 2 * m : n;
            efl_greedy(&d, lobes, m, m2);
            m = m2;
        }
    }
    fit_levels(&st, &d, lobes, n);
    double rel = sl_envfit_rel_l2(map, all, ns + n, s->threads);
    while (s->lobes == 0 && rel > s->target_error && n < cap) {
        /* Ren 2010 Sec. 7: insert lobes where the error is largest and refit. */
        int n2 = n + (n / 4 > 4 ? n / 4 : 4);
        if (n2 > cap) n2 = cap;
        efl_greedy(&d, lobes, n, n2);
        n = n2;
        st.work_done = 0;
        fit_levels(&st, &d, lobes, n);
        rel = sl_envfit_rel_l2(map, all, ns + n, s->threads);
    }
    if (s->progress) sl_progress_end(&st.prog);
    n += ns;
    qsort(all, (size_t)n, sizeof *all, cmp_power);
    rep->rel_l2 = rel;
    double tc = sl_now();
    rep->lobe_conv_rel_l2 = sl_envfit_conv_rel_l2(map, all, n, s->conv_lambda, s->threads);
    if (s->verbose) fprintf(stderr, "fit: convolved error %.3f s\n", sl_now() - tc);
    rep->iterations = st.iters;
    rep->levels = st.nlev;
    rep->suns = ns;
    rep->time_s = sl_now() - t0;
    out->count = n;
    out->lobe = all;
    out->rel_l2 = rep->rel_l2;
    out->lobe_conv_rel_l2 = rep->lobe_conv_rel_l2;
    efl_dict_free(&d);
    free(st.res);
    for (int k = 0; k < st.nlev; k++)
        efl_level_free(&st.L[k]);
    free(st.L);
    return 0;
}
