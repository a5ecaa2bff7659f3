/* test_srbf_batch.c: the renderer's batched SRBF drivers (cpu/srbf_deon_c.c: model chiang's
 * point constants built once per shading point and reused over its lobes) against the row by row
 * reference (slc_srbf_deon_rgb_scalar: one sl_srbf_deon_rgb_row per row) on the same rows,
 * point by point as the shade pass builds them: typical rows and extreme ones (grazing and
 * polar views and lobes, lambda 0.005 and 4, phi 0 and pi), sigma_a NULL, per channel, and
 * changing within a point's rows (painted strands); the x86-64 baseline batch and, where the
 * CPU has them, the AVX2 + FMA one (cpu/srbf_deon_c_avx2.c). Tolerance: 0 (the batch does the
 * same float operations on the same values, and ISO C contracts nothing into an FMA;
 * docs/performance.md "SIMD shading (session 7)" and "AVX2 (session 15)"). */
#include "test.h"

#include "chiang_fixture.h"

#include "passes/shade/srbf_tables.h"
#include "srbf_deon.h"
#include "srbf_deon_c.h"

#include <stdlib.h>
#include <string.h>

#define NPT 40
#define NLB 24

static double brand(unsigned *s) {
    *s = *s * 1664525u + 1013904223u;
    return ((*s >> 8) + 0.5) / 16777216.0;
}

/* Rows of NPT points x NLB lobes; every 5th point extreme, every 7th point's sigma_a changes
 * half way through its lobes. */
static void batch_rows(unsigned seed, const sl_material *m, float *in, float *sig) {
    unsigned s = seed;
    const float hp = 1.5707963f, pi = 3.1415927f;
    for (int i = 0; i < NPT; i++) {
        int ext = i % 5 == 0;
        float to = ext ? (i % 10 == 0 ? hp : -hp * 0.9999f) : (float)(1.4 * (2 * brand(&s) - 1));
        float po = (float)(pi * (2 * brand(&s) - 1));
        for (int j = 0; j < NLB; j++) {
            float *x = in + 5 * (i * NLB + j), *sg = sig + 3 * (i * NLB + j);
            x[0] = to, x[1] = po;
            x[2] = ext && j % 3 == 0 ? (j % 2 ? hp : -hp) : (float)(hp * (2 * brand(&s) - 1));
            x[3] = ext && j % 4 == 0 ? po - (j % 8 ? pi : 0.0f) : (float)(pi * (2 * brand(&s) - 1));
            x[4] = ext && j % 2 ? (j % 4 == 1 ? 0.005f : 4.0f)
                                : (float)exp(log(0.02) + (log(1.5) - log(0.02)) * brand(&s));
            for (int c = 0; c < 3; c++)
                sg[c] = (float)m->sigma_a[c] * (i % 7 == 0 && j >= NLB / 2 ? 0.3f : 1.0f);
        }
    }
}

TEST(srbf_batch_chiang_vs_scalar) {
    sl_srbf_tables t;
    sl_err e;
    if (sl_srbf_tables_get(&t, 0, &e)) {
        CHECK_MSG(0, "%s", e.msg);
        return;
    }
    size_t n = (size_t)NPT * NLB;
    float *in = malloc(n * 5 * sizeof *in), *sig = malloc(n * 3 * sizeof *sig);
    float *a = malloc(n * 9 * sizeof *a), *b = malloc(n * 9 * sizeof *b);
    for (int mi = 0; mi < CHB_NMAT; mi++) {
        sl_material m;
        if (chb_material(mi, &m)) break;
        sl_fiber_params fp;
        sl_material_to_fiber(&m, 0, &fp);
        batch_rows(1000u + (unsigned)mi, &m, in, sig);
        for (int use_sig = 0; use_sig < 2; use_sig++) {
            const float *sg = use_sig ? sig : NULL;
            slc_srbf_deon_rgb_scalar(&fp, t.C, t.H, t.D, n, in, sg, a);
            /* the baseline batch, and the AVX2 one where the CPU has it */
            for (int avx2 = 0; avx2 <= slc_simd_avx2(); avx2++) {
                memset(b, 0xff, n * 9 * sizeof *b); /* NaN: a row the batch skipped shows */
                slc_srbf_chiang_rgb_batch(avx2, &fp, t.C, t.H, t.D, n, in, sg, b);
                size_t bad = 0, nonzero = 0;
                for (size_t k = 0; k < n * 9; k++) {
                    if (memcmp(a + k, b + k, sizeof *a)) bad++;
                    if (a[k] > 0.0f) nonzero++;
                }
                CHECK_MSG(bad == 0, "material %d sig %d avx2 %d: %zu of %zu outputs differ", mi,
                          use_sig, avx2, bad, n * 9);
                CHECK_MSG(nonzero > n, "material %d: only %zu positive outputs", mi, nonzero);
            }
        }
    }
    free(in), free(sig), free(a), free(b);
    sl_srbf_tables_free(&t);
}

/* The 12-lane von Mises harmonics (sl_srbf_chiang_vmx) lane by lane against one k alone. */
TEST(srbf_batch_chiang_vm_lanes) {
    float k[SL_SRBF_CH_VL], rho[SL_SRBF_CH_NHV][SL_SRBF_CH_VL];
    const float ks[SL_SRBF_CH_VL] = {0.0f, 1e-31f, 1e-6f,  0.01f, 0.5f, 1.0f,
                                     7.3f, 40.0f,  300.0f, 5e3f,  1e5f, 1e30f};
    for (int l = 0; l < SL_SRBF_CH_VL; l++)
        k[SL_SRBF_CH_VL - 1 - l] = ks[l];
    sl_srbf_chiang_vmx(k, rho);
    for (int l = 0; l < SL_SRBF_CH_VL; l++) {
        float one[SL_SRBF_CH_NHV];
        sl_srbf_chiang_vm(k[l], one);
        for (int nn = 0; nn < SL_SRBF_CH_NHV; nn++)
            CHECK_MSG(one[nn] == rho[nn][l], "k %g n %d: %g vs %g", (double)k[l], nn,
                      (double)rho[nn][l], (double)one[nn]);
        CHECK(rho[0][l] == 1.0f);
        if (!(k[l] > 1e-30f)) CHECK(rho[1][l] == 0.0f);
    }
}
