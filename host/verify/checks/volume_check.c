/* volume_check.c: `strandlight kernels` checks of the volume kernel pairs (kernels/voxel.cl,
 * kernels/march.cl, kernels/ms.cl, kernels/dual.cl) against their C twins, with timings
 * (docs/volume.md). voxel/march problem: procedural wavy hair (size = strands, default 2000 x 16
 * points), 64 voxels; the march: 4 lobes, 16 paths. */
#include "verify/checks/kernel_checks.h"
#include "dual_c.h"
#include "passes/volume/dual_cl.h"
#include "march.h"
#include "march_c.h"
#include "passes/volume/march_cl.h"
#include "passes/volume/volume.h"
#include "voxel.h"
#include "voxel_c.h"
#include "passes/volume/voxel_cl.h"
#include "passes/volume/volume_ms.h"
#include "passes/volume/ms_cl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int make_hair(const sl_kernel_check_opts *o, sl_hair *h, sl_err *e) {
    sl_hair_procedural p = {SL_PROC_WAVY, o->size > 0 ? (uint32_t)o->size : 2000u, 16, 1};
    return sl_hair_generate(&p, h, e);
}

/* Keeps the best (smallest) of each time over the repetitions (r's times start at INFINITY):
 * the C twin's, the kernel's (device time, or the wall time when there is none) and the wall
 * time of the OpenCL call. */
static void best_times(sl_kernel_check_result *r, double tc, double tk, double tw) {
    if (tc < r->c_s) r->c_s = tc;
    if (tk < r->cl_s) r->cl_s = tk;
    if (tw < r->cl_wall_s) r->cl_wall_s = tw;
}

/* Sets the tolerance and why it is what it is, then compares the n kernel outputs a against the
 * C twin's b. */
static void compare_within(sl_kernel_check_result *r, double tol_abs, double tol_rel,
                           const char *note, const float *a, const float *b, size_t n) {
    r->tol_abs = tol_abs;
    r->tol_rel = tol_rel;
    snprintf(r->note, sizeof r->note, "%s", note);
    sl_kernel_compare(a, b, n, r);
}

int slchk_voxel(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r, sl_err *e) {
    sl_hair h;
    if (make_hair(o, &h, e)) return -1;
    sl_voxel_grid g;
    sl_voxel_grid_layout(&h, 64, &g);
    size_t nseg, nvox = (size_t)g.n[0] * g.n[1] * g.n[2];
    float *segs = sl_voxel_segments(&h, &nseg), scale = sl_voxel_scale(segs, nseg);
    float *a = sl_malloc(nvox * SL_VOX_FIELDS * sizeof *a),
          *b = sl_malloc(nvox * SL_VOX_FIELDS * sizeof *b);
    uint64_t *acc = sl_malloc(nvox * SL_VOX_ACC * sizeof *acc);
    snprintf(r->problem, sizeof r->problem, "%zu segments, %dx%dx%d voxels", nseg, g.n[0], g.n[1],
             g.n[2]);
    int rc = 0;
    r->c_s = r->cl_s = r->cl_wall_s = INFINITY;
    for (int rep = 0; rep < o->reps && !rc; rep++) {
        double t0 = sl_now();
        memset(acc, 0, nvox * SL_VOX_ACC * sizeof *acc);
        slc_voxel_accumulate(segs, nseg, g.n, g.lo, g.h, scale, acc);
        slc_voxel_finalize(acc, nvox, g.h, 1.0f / scale, b);
        double tc = sl_now() - t0, tk;
        t0 = sl_now();
        rc = slcl_voxelize(cl, segs, nseg, g.n, g.lo, g.h, scale, a, &tk, e);
        double tw = sl_now() - t0;
        best_times(r, tc, tk, tw);
    }
    r->cl_s_is_device = sl_cl_profiling(cl);
    if (!rc) {
        /* Exact fixed-point sums of float pieces; the device's sqrt/division may move a piece by
         * an ulp, and the finalize's power iteration rounds differently: 1e-5 relative, 1e-5
         * absolute (directions and deviations are O(1)). */
        compare_within(r, 1e-5, 1e-5, "fixed-point sums; float finalize within 1e-5", a, b,
                       nvox * SL_VOX_FIELDS);
    }
    free(a);
    free(b);
    free(acc);
    free(segs);
    sl_hair_free(&h);
    return rc;
}

int slchk_march(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r, sl_err *e) {
    sl_hair h;
    if (make_hair(o, &h, e)) return -1;
    sl_voxel_grid g;
    if (sl_voxelize(NULL, &h, 64, &g, e)) {
        sl_hair_free(&h);
        return -1;
    }
    sl_material m;
    sl_material_default(&m);
    sl_dual_tables dt;
    sl_dual_tables_build(&m, &dt, e);
    /* The active vertex set of sl_march_build, rebuilt here through it on the C path once. */
    sl_march_opts mo;
    sl_march_opts_default(&mo);
    double dirs[12] = {0, 1, 0, 0.6, 0.8, 0, -0.48, 0.6, 0.64, 0, -0.6, -0.8};
    float fd[12];
    for (int i = 0; i < 12; i++)
        fd[i] = (float)dirs[i];
    int c = mo.coarse, mm[3];
    for (int a = 0; a < 3; a++)
        mm[a] = (g.n[a] + c - 1) / c + 1;
    size_t nvert = (size_t)mm[0] * mm[1] * mm[2];
    /* Every vertex (not only the active ones): a superset, same per-vertex work. */
    float *verts = sl_malloc(nvert * 3 * sizeof *verts);
    uint32_t *ids = sl_malloc(nvert * sizeof *ids);
    for (size_t v = 0; v < nvert; v++) {
        ids[v] = (uint32_t)v;
        int idx[3] = {(int)(v % mm[0]), (int)(v / mm[0] % mm[1]),
                      (int)(v / ((size_t)mm[0] * mm[1]))};
        for (int a = 0; a < 3; a++)
            verts[3 * v + a] = g.lo[a] + (float)idx[a] * (float)c * g.h;
    }
    size_t nout = nvert * 4 * SL_MARCH_CH;
    float *aT = sl_malloc(nout * sizeof *aT), *aS = sl_malloc(nout * sizeof *aS);
    float *bT = sl_malloc(nout * sizeof *bT), *bS = sl_malloc(nout * sizeof *bS);
    float *aG = sl_malloc(nout * sizeof *aG), *bG = sl_malloc(nout * sizeof *bG);
    snprintf(r->problem, sizeof r->problem, "%zu vertices x 4 lobes x %d paths", nvert, mo.paths);
    int rc = 0;
    r->c_s = r->cl_s = r->cl_wall_s = INFINITY;
    for (int rep = 0; rep < o->reps && !rc; rep++) {
        double t0 = sl_now();
        slc_march(g.vox, g.n, g.lo, g.h, &dt.tab[0][0], verts, ids, nvert, fd, 4, mo.paths, mo.seed,
                  bT, bS, bG);
        double tc = sl_now() - t0, tk;
        t0 = sl_now();
        rc = slcl_march(cl, g.vox, g.n, g.lo, g.h, &dt.tab[0][0], verts, ids, nvert, fd, 4,
                        mo.paths, mo.seed, aT, aS, aG, &tk, e);
        double tw = sl_now() - t0;
        best_times(r, tc, tk, tw);
    }
    r->cl_s_is_device = sl_cl_profiling(cl);
    if (!rc) {
        /* Same random numbers and float steps; exp/log/asin of the device within a few ulp. An
         * event decision flipped by such an ulp changes one path of 16 (up to ~0.05): the check
         * allows 1e-4 absolute, so a flip shows up as a FAIL to look at. */
        float *ka = sl_malloc(3 * nout * sizeof *ka), *kb = sl_malloc(3 * nout * sizeof *kb);
        memcpy(ka, aT, nout * sizeof *ka);
        memcpy(ka + nout, aS, nout * sizeof *ka);
        memcpy(ka + 2 * nout, aG, nout * sizeof *ka);
        memcpy(kb, bT, nout * sizeof *kb);
        memcpy(kb + nout, bS, nout * sizeof *kb);
        memcpy(kb + 2 * nout, bG, nout * sizeof *kb);
        compare_within(r, 1e-4, 1e-4, "same random streams; ulp-level exp/asin: 1e-4", ka, kb,
                       3 * nout);
        free(ka);
        free(kb);
    }
    free(verts);
    free(ids);
    free(aT);
    free(aS);
    free(bT);
    free(bS);
    free(aG);
    free(bG);
    sl_voxel_grid_free(&g);
    sl_hair_free(&h);
    return rc;
}

/* kernels/ms.cl (the multiple-scattering response rows) against the C side: size = rows
 * (default 20000), default material; same float math, the device's exp/cos/asin within a few
 * ulp, which move the table interpolation weights (the node position goes through asin):
 * measured 3.7e-7 relative on PoCL with the response table (9.7e-5 before it), checked 5e-4
 * relative or 1e-7 absolute. */
int slchk_ms_response(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                      sl_err *e) {
    size_t n = o->size > 0 ? (size_t)o->size : 20000;
    sl_material m;
    sl_material_default(&m);
    sl_volume_ms ms;
    if (sl_volume_ms_init(&m, &ms, e)) return -1;
    float *in = sl_malloc(6 * n * sizeof *in), *a = sl_malloc(2 * n * sizeof *a),
          *b = sl_malloc(2 * n * sizeof *b);
    sl_kernel_check_fill(in, 6 * n, 11, 0.0f, 1.0f);
    for (size_t i = 0; i < n; i++) {
        float *q = in + 6 * i;
        q[0] = (q[0] - 0.5f) * 2.8f;
        q[1] = (q[1] - 0.5f) * 6.2f;
        q[2] = (q[2] - 0.5f) * 2.8f;
        q[3] = (q[3] - 0.5f) * 6.2f;
        q[4] = 0.05f + 0.5f * q[4];
        q[5] = 0.4f * q[5];
    }
    snprintf(r->problem, sizeof r->problem, "%zu rows", n);
    int rc = 0;
    r->c_s = r->cl_s = r->cl_wall_s = INFINITY;
    for (int rep = 0; rep < o->reps && !rc; rep++) {
        double t0 = sl_now();
        for (size_t i = 0; i < n; i++) {
            const float *q = in + 6 * i;
            float sf[3] = {q[5], q[5], q[5]}, MG[3], ML[3];
            sl_volume_ms_terms(&ms, q[0], q[1], q[2], q[3], q[4], sf, MG, ML);
            b[2 * i] = MG[0];
            b[2 * i + 1] = ML[0];
        }
        double tc = sl_now() - t0;
        t0 = sl_now();
        rc = slcl_ms_response_rows(cl, &ms, 0, n, in, a, e);
        double tw = sl_now() - t0;
        best_times(r, tc, tw, tw);
    }
    r->cl_s_is_device = 0;
    if (!rc) {
        compare_within(r, 1e-7, 5e-4,
                       "device exp/cos ulps move table weights; PoCL 3.7e-7 measured: 5e-4", a, b,
                       2 * n);
    }
    free(in);
    free(a);
    free(b);
    sl_volume_ms_free(&ms);
    return rc;
}

/* kernels/dual.cl (the dual-scattering table's nodes on the device) against slc_dual_table, for
 * the three models' defaults (marschner; deon and chiang through kernels/dual_ec.h) and the
 * energy-conserving models' extremes (a sharp kernel, the roughest, heavy absorption): 2e-5
 * relative, 1e-7 absolute (docs/volume.md). */
int slchk_dual_table(sl_cl *cl, const sl_kernel_check_opts *o, sl_kernel_check_result *r,
                     sl_err *e) {
    enum { NM = 7 };
    sl_fiber_params fp[NM];
    for (int k = 0; k < NM; k++) {
        sl_material m;
        sl_material_default(&m);
        m.model = k == 0 ? SL_MODEL_MARSCHNER : (k % 2 ? SL_MODEL_DEON : SL_MODEL_CHIANG);
        if (k == 3) /* deon: a sharp detector (0.5 deg) and heavy absorption */
            for (int p = 0; p < 3; p++)
                m.beta[p] = 0.5 * M_PI / 180.0, m.sigma_a[p] = 50.0;
        if (k == 5) /* deon: 60 deg, 8 orders */
            for (int p = 0; p < 3; p++)
                m.beta[p] = 60.0 * M_PI / 180.0, m.orders = 8;
        if (k == 4) m.chiang.roughness = m.chiang.radial_roughness = 0.001; /* sharp */
        if (k == 6) m.chiang.roughness = m.chiang.radial_roughness = 1.0;
        if (m.model == SL_MODEL_CHIANG) sl_chiang_derive(&m);
        sl_material_to_fiber(&m, 0, &fp[k]);
    }
    float *a = sl_malloc(NM * SL_DUAL_TABLE_FLOATS * sizeof *a),
          *b = sl_malloc(NM * SL_DUAL_TABLE_FLOATS * sizeof *b);
    snprintf(r->problem, sizeof r->problem, "%d materials x %d nodes x %d rows", NM, SL_DUAL_N,
             SL_DUAL_ROWS);
    int rc = 0;
    r->c_s = r->cl_s = r->cl_wall_s = INFINITY;
    for (int rep = 0; rep < o->reps && !rc; rep++) {
        double t0 = sl_now();
        for (int k = 0; k < NM; k++)
            slc_dual_table(&fp[k], b + (size_t)k * SL_DUAL_TABLE_FLOATS);
        double tc = sl_now() - t0;
        t0 = sl_now();
        for (int k = 0; k < NM && !rc; k++)
            rc = slcl_dual_table(cl, &fp[k], a + (size_t)k * SL_DUAL_TABLE_FLOATS, e);
        double tw = sl_now() - t0;
        best_times(r, tc, tw, tw);
    }
    r->cl_s_is_device = 0;
    if (!rc) {
        compare_within(r, 1e-7, 2e-5, "same float math per node; device ulps", a, b,
                       NM * SL_DUAL_TABLE_FLOATS);
    }
    free(a);
    free(b);
    return rc;
}
