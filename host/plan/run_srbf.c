/* run_srbf.c: the srbf pass of the frame: the SRBF method of this frame (docs/frame.md,
 * "SRBF method") and Ren 2010's table, built, loaded from the disk cache or kept in memory
 * while the material matches (sl_srbf_ren_matches: the pass decides its own reuse, it is not
 * keyed by plan/passes.h's rule). */
#include "plan/frame_internal.h"

#include <stdio.h>

void sl_frame_free_ren(sl_renderer *r) {
    slcl_srbf_ren_table_release(&r->ren_mem);
    if (r->have_ren) sl_srbf_ren_free(&r->ren);
    r->have_ren = 0;
}

/* 1 when shading point i's strand has a per-strand sigma_a other than the material's: its rows
 * use `fast` even when the table is on (the table is baked for one sigma_a). */
static int painted(const sl_renderer *r, const sl_material *m, const sl_shade_points *p, size_t i) {
    if (!r->strand_sigma_a || !p->strand) return 0;
    const float *q = r->strand_sigma_a + 3 * (size_t)p->strand[i];
    return q[0] != (float)m->sigma_a[0] || q[1] != (float)m->sigma_a[1] ||
           q[2] != (float)m->sigma_a[2];
}

static void table_params(const sl_renderer *r, sl_srbf_ren_params *p) {
    if (r->o.table_params) {
        *p = *r->o.table_params;
    } else {
        sl_srbf_ren_params_default(p);
        p->threads = r->o.threads;
    }
}

/* Loads or builds the table for mat (kept while the material matches). */
static int ensure_table(sl_renderer *r, const sl_material *mat, int *state, sl_err *e) {
    if (r->have_ren && sl_srbf_ren_matches(&r->ren, mat)) {
        *state = SL_PASS_CACHED;
        return 0;
    }
    sl_frame_free_ren(r);
    sl_srbf_ren_params p;
    table_params(r, &p);
    if (sl_srbf_ren_get(r->dev, mat, &p, &r->ren, e)) return -1;
    r->have_ren = 1;
    *state = SL_PASS_RUN;
    return 0;
}

/* The SRBF method of this frame (docs/frame.md, "SRBF method"): records pass "srbf" and sets
 * r->srbf_used. rows: (point, lobe) rows of unpainted strands this frame shades. */
static int plan_srbf(sl_renderer *r, const sl_material *mat, double rows, double rows_painted,
                     sl_err *e) {
    int m = r->o.srbf_method, state = SL_PASS_SKIPPED;
    double t0 = sl_now();
    const char *paint_note = rows_painted > 0 ? "; rows of painted strands (per-strand sigma_a "
                                                "other than the material's) use fast"
                                              : "";
    if (m == SL_SRBF_METHOD_XU || m == SL_SRBF_METHOD_FAST) {
        r->srbf_used = m;
        snprintf(r->srbf_why, sizeof r->srbf_why, "%s chosen (render --method %s)",
                 sl_render_method_name(m), sl_render_method_name(m));
        r->rec_state = SL_PASS_SKIPPED;
        sl_frame_why(r, "no table: %s", r->srbf_why);
        return 0;
    }
    const char *why = NULL;
    char buf[200];
    int use = 0;
    if (m == SL_RENDER_SRBF_TABLE) {
        use = 1;
        why = "table chosen (render --method table)";
    } else if (r->editing) {
        why = "auto: the material is being edited (sl_renderer_set_editing): fast, no table built";
    } else if (mat->eccentricity != 1.0) {
        /* the table averages an eccentric fiber over its rotation: p95 0.18 against the exact
         * value at one orientation where fast has 0.04 (docs/srbf_ren.md) */
        why = "auto: eccentric fiber (the table averages over the fiber's rotation, p95 error "
              "0.18 vs fast's 0.04): fast";
    } else if (r->have_ren && sl_srbf_ren_matches(&r->ren, mat)) {
        use = 1;
        why = "auto: the table for this material is in memory";
    } else if (rows <= 0) {
        why = "auto: no rows to shade from a table: fast";
    } else {
        sl_srbf_ren_params p;
        table_params(r, &p);
        long left = (r->o.frames > 0 ? r->o.frames : 1) - r->frames_done;
        if (left < 1) left = 1;
        double build = sl_srbf_ren_build_rows(mat, &p), saved = SL_FRAME_TABLE_SAVING * rows * left;
        if (sl_srbf_ren_cached(mat, &p, r->have_tables ? &r->tables : NULL)) {
            use = 1;
            why = "auto: the table for this material is in the disk cache";
        } else if (saved > build) {
            use = 1;
            snprintf(buf, sizeof buf,
                     "auto: building pays off: %ld frame%s x %.0f rows x %.1f saved > %.0f fast "
                     "evaluations to build",
                     left, left == 1 ? "" : "s", rows, SL_FRAME_TABLE_SAVING, build);
            why = buf;
        } else {
            snprintf(buf, sizeof buf,
                     "auto: fast: a build (%.0f fast evaluations) would not pay off over %ld "
                     "frame%s x %.0f rows x %.1f saved",
                     build, left, left == 1 ? "" : "s", rows, SL_FRAME_TABLE_SAVING);
            why = buf;
        }
    }
    if (use) {
        if (ensure_table(r, mat, &state, e)) return -1;
        r->srbf_used = SL_RENDER_SRBF_TABLE;
    } else {
        r->srbf_used = SL_SRBF_METHOD_FAST;
    }
    snprintf(r->srbf_why, sizeof r->srbf_why, "%s%s", why, use ? paint_note : "");
    r->rec_state = state;
    if (use && state == SL_PASS_RUN)
        sl_frame_why(r,
                     "Ren table %s in %.2f s (built on %s; self-check vs fast: median %.2g, p95 "
                     "%.2g); %s",
                     r->ren.from_cache ? "loaded from the disk cache" : "built",
                     r->ren.from_cache ? sl_now() - t0 : r->ren.build_s, r->ren.built_on,
                     r->ren.err_median, r->ren.err_p95, r->srbf_why);
    else if (use)
        sl_frame_why(r, "Ren table kept in memory; %s", r->srbf_why);
    else
        sl_frame_why(r, "no table: %s", r->srbf_why);
    return 0;
}

/* rows this frame shades (the same cut as sl_frame_shade's), split by whether the strand's
 * sigma_a is the material's: only those can come from a table */
int sl_pass_srbf(sl_renderer *r, const sl_frame_inputs *in, sl_err *e) {
    const sl_scene *s = in->s;
    const sl_frame_work *w = &r->fw;
    const sl_shade_points *p = &w->pts;
    double share_sum = 0, rows = 0, rows_p = 0;
    for (int j = 0; j < w->nused; j++)
        share_sum += w->share[j];
    for (size_t i = 0; i < p->n; i++) {
        int c = 0;
        for (int j = 0; j < w->nused; j++)
            c += p->T[(size_t)j * p->n + i] * w->share[j] >= s->point_threshold * share_sum;
        if (painted(r, &s->material, p, i))
            rows_p += c;
        else
            rows += c;
    }
    return plan_srbf(r, &s->material, rows, rows_p, e);
}
