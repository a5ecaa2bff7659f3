/* volume_ms_nodes.c: see volume_ms_nodes.h. */
#include "passes/volume/volume_ms_nodes.h"

#include "base/parallel.h"
#include "ms_table.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static float node_u(float sa) {
    return logf(sa + SL_MSN_U0);
}

static int cmp_float(const void *a, const void *b) {
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

void sl_volume_ms_nodes_place(const float *sa, size_t nstrands, sl_volume_ms_nodes *nd) {
    memset(nd, 0, sizeof *nd);
    size_t nv = 3 * nstrands;
    float *v = sl_malloc((nv ? nv : 1) * sizeof *v);
    for (size_t i = 0; i < nv; i++)
        v[i] = sa[i] > 0.0f ? sa[i] : 0.0f; /* the scene refuses negatives; -0 is 0 */
    qsort(v, nv, sizeof *v, cmp_float);
    size_t nd_distinct = 0;
    for (size_t i = 0; i < nv; i++)
        if (i == 0 || v[i] != v[i - 1]) v[nd_distinct++] = v[i];
    if (nd_distinct <= SL_MSN_MAX) { /* the strands' own values: lookups are exact */
        nd->exact = 1;
        nd->n = (int)nd_distinct;
        for (int k = 0; k < nd->n; k++)
            nd->sa[k] = v[k];
    } else { /* evenly in u over the range: both ends are nodes */
        float u0 = node_u(v[0]), u1 = node_u(v[nd_distinct - 1]);
        nd->n = SL_MSN_MAX;
        for (int k = 0; k < nd->n; k++) {
            float u = u0 + (u1 - u0) * (float)k / (float)(nd->n - 1);
            nd->sa[k] = k == 0 ? v[0] : k == nd->n - 1 ? v[nd_distinct - 1] : expf(u) - SL_MSN_U0;
        }
    }
    free(v);
    for (int k = 0; k < nd->n; k++)
        nd->u[k] = node_u(nd->sa[k]);
    nd->nsets = (nd->n + 2) / 3;
    nd->key = sl_hash64(nd->sa, (size_t)nd->n * sizeof *nd->sa, 0x4d534e44) | 1;
}

typedef struct build_job {
    const sl_material *m;
    sl_volume_ms_nodes *nd;
    int *failed;
    sl_err *err; /* one per set */
} build_job;

static void build_sets(void *arg, size_t begin, size_t end, int worker) {
    (void)worker;
    build_job *j = arg;
    for (size_t s = begin; s < end; s++) {
        sl_material m = *j->m;
        m.sigma_a_rgb = 1;
        for (int c = 0; c < 3; c++) { /* a short last set repeats its last node */
            int k = 3 * (int)s + c;
            m.sigma_a[c] = j->nd->sa[k < j->nd->n ? k : j->nd->n - 1];
        }
        j->failed[s] = sl_volume_ms_init(&m, &j->nd->set[s], &j->err[s]) != 0;
    }
}

int sl_volume_ms_nodes_init(const sl_material *m, const float *sa, size_t nstrands, int threads,
                            sl_volume_ms_nodes *nd, sl_err *e) {
    double t0 = sl_now();
    sl_volume_ms_nodes_place(sa, nstrands, nd);
    if (nd->n == 0) {
        return sl_fail(e, "multiple scattering per strand: no strands");
    }
    nd->set = sl_calloc((size_t)nd->nsets, sizeof *nd->set);
    int *failed = sl_calloc((size_t)nd->nsets, sizeof *failed);
    sl_err *err = sl_calloc((size_t)nd->nsets, sizeof *err);
    build_job job = {m, nd, failed, err};
    sl_parallel_for(threads, (size_t)nd->nsets, 1, build_sets, &job);
    int rc = 0;
    for (int s = 0; s < nd->nsets; s++)
        if (failed[s] && !rc) {
            *e = err[s];
            rc = -1;
        }
    if (rc) {
        for (int s = 0; s < nd->nsets; s++)
            if (!failed[s]) sl_volume_ms_free(&nd->set[s]);
        free(nd->set);
        nd->set = NULL;
    }
    free(failed);
    free(err);
    nd->build_s = sl_now() - t0;
    return rc;
}

void sl_volume_ms_nodes_free(sl_volume_ms_nodes *nd) {
    for (int s = 0; nd->set && s < nd->nsets; s++)
        sl_volume_ms_free(&nd->set[s]);
    free(nd->set);
    nd->set = NULL;
}

/* The node at or below x (k) and the weight of node k + 1 (t in [0, 1]). */
static int locate(const sl_volume_ms_nodes *nd, float x, float *t) {
    *t = 0.0f;
    if (nd->n == 1 || !(x > nd->sa[0])) return 0;
    if (x >= nd->sa[nd->n - 1]) return nd->n - 1;
    int k = 0;
    while (k + 2 < nd->n && nd->sa[k + 1] <= x)
        k++;
    if (x == nd->sa[k]) return k;         /* exact nodes: no blend */
    float ds = nd->sa[k + 1] - nd->sa[k]; /* linear in sigma_a: see blend */
    *t = ds > 0.0f ? (x - nd->sa[k]) / ds : 0.0f;
    *t = *t < 0.0f ? 0.0f : *t > 1.0f ? 1.0f : *t;
    return k;
}

/* The blend of a term's values at two nodes, weight t of b: geometric where both are positive
 * (a term falls about exponentially with sigma_a, ln of it about linearly), else linear. */
static float blend(float a, float b, float t) {
    if (a > 0.0f && b > 0.0f) return a * powf(b / a, t);
    return a + t * (b - a);
}

static void node_terms(const sl_volume_ms_nodes *nd, int k, float theta_o, float phi_o,
                       float theta_j, float phi_j, float lambda, float sigma_f, float *MG,
                       float *ML) {
    const sl_volume_ms *s = &nd->set[k / 3];
    int c = k % 3;
    sl_ms_table_1(&s->fp[c], s->mt + (size_t)c * SL_MST_FLOATS, theta_o, phi_o, theta_j, phi_j,
                  lambda, sigma_f, MG, ML);
}

void sl_volume_ms_nodes_terms(const sl_volume_ms_nodes *nd, const float sa[3], float theta_o,
                              float phi_o, float theta_j, float phi_j, float lambda,
                              const float sigma_f[3], float MG[3], float ML[3]) {
    for (int c = 0; c < 3; c++) {
        float t;
        int k = locate(nd, sa[c], &t);
        node_terms(nd, k, theta_o, phi_o, theta_j, phi_j, lambda, sigma_f[c], &MG[c], &ML[c]);
        if (t > 0.0f) {
            float g, l;
            node_terms(nd, k + 1, theta_o, phi_o, theta_j, phi_j, lambda, sigma_f[c], &g, &l);
            MG[c] = blend(MG[c], g, t);
            ML[c] = blend(ML[c], l, t);
        }
    }
}

void sl_volume_ms_nodes_response(const sl_volume_ms_nodes *nd, const float sa[3], float theta_o,
                                 float phi_o, float theta_j, float phi_j, float lambda,
                                 const float Tf[3], const float sigma_f[3], float Tj,
                                 float out[3]) {
    float MG[3], ML[3];
    sl_volume_ms_nodes_terms(nd, sa, theta_o, phi_o, theta_j, phi_j, lambda, sigma_f, MG, ML);
    sl_volume_ms_combine(lambda, Tf, Tj, MG, ML, out);
}
