/* test_fiber_chiang.c: model chiang (Chiang 2016 / pbrt-v4 HairBxDF, numerics.md sec. 3): the
 * double reference (cpu/reference/chiang_ref.c) against independent quadratures of the per-hit
 * model (cpu/reference/chiang_hit.c) and of the logistic's Fourier series, its energy, and the
 * float twin (kernels/fiber_chiang.h: the C backend directly, OpenCL through fiber.cl) against
 * the reference on typical and extreme rows. Tolerances are stated at each check; the measured
 * values are in docs/numerics-chiang.md. */
#include "cl_fixture.h"
#include "test.h"

#include "chiang_hit.h"
#include "chiang_ref.h"
#include "fiber_c.h"
#include "fiber_chiang.h"
#include "passes/shade/fiber_cl.h"
#include "marschner_ref.h"
#include "quad.h"
#include "srbf_ref.h"

#include <stdlib.h>
#include <string.h>

#define CPI 3.14159265358979323846
#define CGRAZE (CPI / 2 - 1e-6)

static void chiang_mat(const char *json, sl_material *m) {
    sl_err e = {{0}};
    int rc = sl_material_parse(json, strlen(json), "test", m, &e);
    CHECK_MSG(rc == 0, "%s: %s", json, e.msg);
}

/* The materials of the float-vs-reference checks: the defaults and each extreme the contract
 * allows (radial roughness 0.05 gives s = 0.010, 1 gives s = 4.28; coat 0.9 with roughness 0.05
 * gives an R lobe of 0.2 deg). */
static const char *const chiang_rows[] = {
    "{\"model\": \"chiang\"}",
    "{\"model\": \"chiang\", \"radial_roughness\": 0.05}",
    "{\"model\": \"chiang\", \"radial_roughness\": 1}",
    "{\"model\": \"chiang\", \"roughness\": 0.05}",
    "{\"model\": \"chiang\", \"roughness\": 1}",
    "{\"model\": \"chiang\", \"roughness\": 0.05, \"coat\": 0.9}",
    "{\"model\": \"chiang\", \"sigma_a\": 0}",
    "{\"model\": \"chiang\", \"sigma_a\": 20}",
    "{\"model\": \"chiang\", \"offset_deg\": 0}",
    "{\"model\": \"chiang\", \"offset_deg\": -5, \"roughness\": 0.1}",
    "{\"model\": \"chiang\", \"eta\": 1.3, \"radial_roughness\": 0.05, \"sigma_a\": 0}",
    "{\"model\": \"chiang\", \"eta\": 2.5, \"melanin\": 0.2}",
    "{\"model\": \"chiang\", \"roughness\": 0.05, \"radial_roughness\": 0.05, \"offset_deg\": -5}",
};
#define CHIANG_NROWS (sizeof chiang_rows / sizeof chiang_rows[0])

/* Directions: theta_o over the range including 1e-6 from the poles; theta_i on R's cone and off
 * it (and at a pole); phi forward, backward, sideways. */
static int chiang_dirs(const sl_material *m, float *in) {
    const double tos[7] = {-CGRAZE, -1.2, -0.3, 0.0, 0.5, 1.4, CGRAZE};
    const double phis[5] = {0.0, 0.3, 1.5, 2.6, CPI};
    int n = 0;
    for (int a = 0; a < 7; a++)
        for (int b = 0; b < 3; b++)
            for (int c = 0; c < 5; c++) {
                double ti = b == 0   ? 2.0 * m->alpha[0] - tos[a] /* R's cone */
                            : b == 1 ? 0.35 - 0.1 * a
                                     : (a % 2 ? CGRAZE : -CGRAZE);
                if (ti > CGRAZE) ti = CGRAZE;
                if (ti < -CGRAZE) ti = -CGRAZE;
                float *r = in + 4 * n++;
                r[0] = (float)ti;
                r[1] = (float)(0.2 * c - 0.4);
                r[2] = (float)tos[a];
                r[3] = (float)sl_wrap_pi((float)(r[1] + phis[c]));
                if (r[3] > (float)CPI) r[3] = (float)CPI;
            }
    return n;
}

/* Error of component p (f_0, f_1, f_2, f_rest) as docs/numerics-deon.md measures it: relative to
 * the value or to the level the same energy would have with a uniform azimuth (M_p E_p / 2pi),
 * whichever is larger, with floors of 1e-6 of the total S and 1e-30 (float underflow). Index 4
 * (f) is relative to S. */
static void chiang_errors(const sl_material *m, int ch, const float *r, const double *ref,
                          const float *got, double *err) {
    double lvl[4], S = 0.0;
    for (int p = 0; p < 4; p++) {
        double e = slref_chiang_energy(m, ch, p, r[2]);
        lvl[p] = p < 3 ? exp(slref_chiang_log_mp(m, p, r[0], r[2])) * e / (2 * CPI) : ref[3];
        S += ref[p] + lvl[p];
    }
    for (int p = 0; p < 5; p++) {
        double l = p < 4 ? lvl[p] : S;
        err[p] = fabs((double)got[p] - ref[p]) / (ref[p] + l + 1e-6 * S + 1e-30);
        if (!isfinite(got[p])) err[p] = INFINITY;
    }
}

/* ---- the reference ---- */

typedef struct hit_ctx {
    const sl_material *m;
    double ti, to, phi;
    int p;
} hit_ctx;

/* The per-hit model of chiang_hit.c (written separately from the width average) by a composite
 * 5-point Gauss-Legendre rule in h = sin(gamma) on n panels: no breakpoints, no adaptivity. */
static void hit_average(const sl_material *m, double ti, double to, double phi, int n,
                        double out[4]) {
    static const double x[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                0.9061798459386640};
    static const double w[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                0.4786286704993665, 0.2369268850561891};
    double H = CPI / n;
    for (int p = 0; p < 4; p++)
        out[p] = 0.0;
    for (int k = 0; k < n; k++)
        for (int j = 0; j < 5; j++) {
            double g = -CPI / 2 + (k + 0.5) * H + 0.5 * H * x[j], f[4];
            slref_chiang_hit hk;
            slref_chiang_hit_init(m, 0, to, sin(g), &hk);
            slref_chiang_hit_f(m, &hk, ti, to, phi, f);
            for (int p = 0; p < 4; p++)
                out[p] += 0.5 * 0.5 * H * w[j] * cos(g) * f[p];
        }
}

/* The reference f against the brute width average of the per-hit f: 3000 panels put >= 6 panels
 * in the narrowest logistic peak (s/2 = 0.005 rad in gamma for radial roughness 0.05), so the
 * brute rule is good to ~1e-10; the check is the contract's 1e-6 (measured 2e-10). */
TEST(chiang_ref_vs_hit_average) {
    const char *mats[3] = {chiang_rows[1], chiang_rows[2], chiang_rows[10]};
    const double rows[6][3] = {{0.3, -0.25, 0.0},    {-1.0, 0.9, 2.9},    {0.2, 1.4, 1.2},
                               {-1.3, CGRAZE, -0.4}, {CGRAZE, -0.5, CPI}, {0.0, -CGRAZE, 0.7}};
    double worst = 0.0;
    for (int i = 0; i < 3; i++) {
        sl_material m;
        chiang_mat(mats[i], &m);
        for (int r = 0; r < 6; r++) {
            double ref[5], brute[4];
            slref_chiang_scatter(&m, 0, rows[r][0], 0.0, rows[r][1], rows[r][2], ref);
            hit_average(&m, rows[r][0], rows[r][1], rows[r][2], 3000, brute);
            double tot = 0.0;
            for (int p = 0; p < 4; p++) {
                tot += brute[p];
                double e = fabs(ref[p] - brute[p]) / fmax(fabs(brute[p]), 1e-300);
                if (brute[p] > 1e-12 * ref[4] && e > worst) worst = e;
                CHECK_MSG(e <= 1e-6 || fabs(ref[p] - brute[p]) <= 1e-12 * ref[4],
                          "%s row %d p %d: ref %.12g brute %.12g", mats[i], r, p, ref[p], brute[p]);
            }
            CHECK_REL(ref[4], tot, 1e-6);
        }
    }
    printf("  reference vs brute width average: worst relative %.2e\n", worst);
}

typedef struct nbar_ctx {
    const sl_material *m;
    int p;
    double to;
} nbar_ctx;

static double nbar_fn(double phi, void *c) {
    const nbar_ctx *n = c;
    return slref_chiang_azimuthal(n->m, 0, n->p, n->to, phi);
}

/* Energy: with sigma_a = 0 the four A_p sum to 1 at every h, so E_0 + E_1 + E_2 + E_3 = 1; and
 * the azimuthal integral of Nbar_p (adaptive in phi over the reference's own Nbar) is E_p: the
 * trimmed logistic is normalised over a period and the width integral keeps every peak. */
TEST(chiang_ref_energy) {
    sl_material m;
    chiang_mat("{\"model\": \"chiang\", \"melanin\": 0, \"radial_roughness\": 0.2}", &m);
    for (double to = -1.5; to < 1.6; to += 0.75) {
        double sum = 0.0;
        for (int p = 0; p < 4; p++)
            sum += slref_chiang_energy(&m, 0, p, to);
        CHECK_NEAR(sum, 1.0, 1e-10); /* quadratures asked for 1e-12 */
    }
    chiang_mat("{\"model\": \"chiang\", \"sigma_a\": 0.3, \"radial_roughness\": 0.3}", &m);
    for (int p = 0; p < 3; p++) {
        nbar_ctx c = {&m, p, 0.6};
        double pts[3] = {-1.5, 0.0, 1.5};
        double ip = slq_integrate_pts(nbar_fn, &c, -CPI, CPI, pts, 3, 1e-9, 1e-300, 30, NULL);
        CHECK_REL(ip, slref_chiang_energy(&m, 0, p, 0.6), 1e-7);
    }
}

static double logistic_cos(double x, void *c) {
    const double *sn = c;
    return slref_trimmed_logistic(x, sn[0]) * cos(sn[1] * x);
}

/* The closed-form Fourier coefficients of the trimmed logistic (srbf_ref.c's detector) against
 * adaptive quadrature of L(x) cos(n x) over (-pi, pi): 1e-12 absolute (b_n <= 1). */
TEST(chiang_logistic_fourier) {
    const double ss[4] = {0.0101738, 0.11716, 1.0, 4.2807};
    const int ns[6] = {0, 1, 2, 5, 20, 100};
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 6; j++) {
            double sn[2] = {ss[i], ns[j]};
            double pts[3] = {-4 * ss[i], 0.0, 4 * ss[i]};
            double q = slq_integrate_pts(logistic_cos, sn, -CPI, CPI, pts, ss[i] < 0.5 ? 3 : 1,
                                         1e-13, 1e-15, 50, NULL);
            CHECK_NEAR(slref_trimmed_logistic_fourier(ss[i], ns[j]), q, 1e-12);
        }
}

/* ---- SRBF exact reference ---- */

#define SRBF_NPH 1024
typedef struct srbf_tab {
    const sl_material *m;
    double to, po, tj, pj, lam;
    int p;
    double tab[3][SRBF_NPH]; /* Nbar_p(-pi + 2 pi j / SRBF_NPH) */
} srbf_tab;

/* G_th cos ti M_p(ti) times the periodic trapezoid over phi_i of G_ph(phi_i) Nbar_p(phi_o - phi_i)
 * on the tabulated Nbar_p (spectrally accurate: both are smooth and periodic). */
static double srbf_tab_outer(double ti, void *vc) {
    const srbf_tab *c = vc;
    double cti = cos(ti);
    if (!(cti > 0.0)) return 0.0;
    double sd = sin(0.5 * (ti - c->tj)), gth = exp(-4.0 * sd * sd / (c->lam * c->lam));
    double kap = 2.0 * cti * cos(c->tj) / (c->lam * c->lam);
    double mp = exp(slref_chiang_log_mp(c->m, c->p, ti, c->to)), sum = 0.0, d = 2 * CPI / SRBF_NPH;
    if (c->p == 3) return gth * cti * mp * slref_chiang_energy(c->m, 0, 3, c->to) * slref_i0e(kap);
    for (int j = 0; j < SRBF_NPH; j++) {
        double s2 = sin(0.5 * (c->po - (-CPI + j * d) - c->pj));
        sum += exp(-2.0 * kap * s2 * s2) * c->tab[c->p][j];
    }
    return gth * cti * mp * sum * d;
}

/* eval srbf --backend reference for chiang (Fourier series of the trimmed logistic, srbf_ref.c)
 * against a different route to the same integral: Nbar_p tabulated by the scatter reference and
 * the azimuth by the trapezoid rule. The contract asks 1e-4 of max(I, 0.03 int G); checked at
 * 1e-6 (measured 5e-15 and below). */
TEST(chiang_srbf_ref_vs_tabulated) {
    const char *mats[2] = {"{\"model\": \"chiang\", \"melanin\": 0.3}",
                           "{\"model\": \"chiang\", \"sigma_a\": 0.2, \"radial_roughness\": 1, "
                           "\"roughness\": 0.1}"};
    const double lams[2] = {0.3, 0.05};
    static srbf_tab c;
    for (int i = 0; i < 2; i++) {
        sl_material m;
        chiang_mat(mats[i], &m);
        c.m = &m;
        c.to = 0.4;
        c.po = 0.3;
        c.tj = -0.2 - 0.2 * m.alpha[0];
        c.pj = i ? 0.4 : 2.5;
        c.lam = lams[i];
        for (int p = 0; p < 3; p++)
            for (int j = 0; j < SRBF_NPH; j++)
                c.tab[p][j] = slref_chiang_azimuthal(&m, 0, p, c.to, -CPI + j * 2 * CPI / SRBF_NPH);
        double out[5], floor_ = 0.03 * slref_srbf_lobe_integral(c.lam);
        slref_srbf(&m, 0, c.to, c.po, c.tj, c.pj, c.lam, out);
        double tot = 0.0;
        for (c.p = 0; c.p < 4; c.p++) {
            double pts[13];
            int n = 0;
            for (int k = -4; k <= 4; k++)
                pts[n++] = c.tj + 0.5 * k * c.lam;
            for (int q = 0; q < 4; q++)
                pts[n++] = -slref_chiang_theta_o_lobe(&m, q, c.to);
            double v = slq_integrate_pts(srbf_tab_outer, &c, -CPI / 2, CPI / 2, pts, (size_t)n,
                                         1e-10, 1e-300, 40, NULL);
            tot += v;
            CHECK_MSG(slref_srbf_error(out[c.p], v, c.lam) <= 1e-6,
                      "%s lambda %g mode %d: srbf_ref %.12g tabulated %.12g", mats[i], c.lam, c.p,
                      out[c.p], v);
        }
        CHECK(fabs(out[4] - tot) / fmax(tot, floor_) <= 1e-6);
    }
}

/* ---- the float twin ---- */

/* C twin (the float header, as cpu/fiber_c.c runs it) vs reference on every row of every
 * material. Stated tolerance 2e-4 in the metric of chiang_errors: the panel rule is chosen for
 * ~1e-5 (docs/numerics-chiang.md), float phases add ~1e-7/s relative (1e-5 at s = 0.01); measured
 * worst 1.0e-5. Zero NaN/Inf. */
TEST(chiang_c_vs_reference) {
    float in[4 * 128], out[5 * 128];
    double worst = 0.0;
    for (size_t i = 0; i < CHIANG_NROWS; i++) {
        sl_material m;
        chiang_mat(chiang_rows[i], &m);
        int n = chiang_dirs(&m, in);
        for (int ch = 0; ch < 3; ch += 2) {
            sl_fiber_params fp;
            sl_material_to_fiber(&m, ch, &fp);
            CHECK(slc_scatter_width(&fp) == 5);
            slc_scatter_batch(&fp, (size_t)n, in, out);
            for (int r = 0; r < n; r++) {
                const float *x = in + 4 * r;
                double ref[5], err[5];
                slref_chiang_scatter(&m, ch, x[0], x[1], x[2], x[3], ref);
                chiang_errors(&m, ch, x, ref, out + 5 * r, err);
                for (int p = 0; p < 5; p++) {
                    if (err[p] > worst) worst = err[p];
                    CHECK_MSG(err[p] <= 2e-4,
                              "%s ch %d: ti %.9g phi_i %.9g to %.9g phi_o %.9g p %d: c %.9g "
                              "ref %.9g (err %.3g)",
                              chiang_rows[i], ch, x[0], x[1], x[2], x[3], p, out[5 * r + p], ref[p],
                              err[p]);
                }
            }
        }
    }
    printf("  c vs reference: worst %.2e (tolerance 2e-4)\n", worst);
}

/* OpenCL (fiber.cl's sl_scatter_eval) vs the reference with the same tolerance, and vs the C twin:
 * the same float code, but device math (PoCL/GPU sin, asin, exp within the OpenCL ulp bounds) and
 * possibly fused multiply-adds, so not bit-identical: 1e-4 in the same metric (phase rounding
 * amplified by 1/s at s = 0.01; measured 3.9e-6 on PoCL). */
TEST(chiang_opencl_vs_reference) {
    sl_device dev;
    sl_err e = {{0}};
    SL_TEST_OPEN_CL(&dev, &e);
    unsigned long k0 = sl_cl_kernels_enqueued();
    float in[4 * 128], out[5 * 128], cout_[5 * 128];
    double worst = 0.0, worst_c = 0.0;
    for (size_t i = 0; i < CHIANG_NROWS; i++) {
        sl_material m;
        chiang_mat(chiang_rows[i], &m);
        int n = chiang_dirs(&m, in);
        sl_fiber_params fp;
        sl_material_to_fiber(&m, 0, &fp);
        int rc = slcl_scatter_batch(dev.cl, &fp, (size_t)n, in, out, &e);
        CHECK_MSG(rc == 0, "slcl_scatter_batch: %s", e.msg);
        if (rc) break;
        slc_scatter_batch(&fp, (size_t)n, in, cout_);
        for (int r = 0; r < n; r++) {
            const float *x = in + 4 * r;
            double ref[5], err[5], cref[5], errc[5];
            slref_chiang_scatter(&m, 0, x[0], x[1], x[2], x[3], ref);
            chiang_errors(&m, 0, x, ref, out + 5 * r, err);
            for (int p = 0; p < 5; p++)
                cref[p] = cout_[5 * r + p];
            chiang_errors(&m, 0, x, cref, out + 5 * r, errc);
            for (int p = 0; p < 5; p++) {
                worst = fmax(worst, err[p]);
                worst_c = fmax(worst_c, errc[p]);
                CHECK_MSG(err[p] <= 2e-4 && errc[p] <= 1e-4,
                          "%s: ti %.9g to %.9g phi %.9g p %d: opencl %.9g c %.9g ref %.9g",
                          chiang_rows[i], x[0], x[2], x[3] - x[1], p, out[5 * r + p],
                          cout_[5 * r + p], ref[p]);
            }
        }
    }
    CHECK_CL_RAN(k0);
    printf("  opencl vs reference: worst %.2e; vs c: worst %.2e\n", worst, worst_c);
    sl_device_close(&dev);
}

/* Deterministic uniform [0, 1) (LCG), so the sweep is reproducible. */
static double chiang_rand(unsigned *s) {
    *s = *s * 1664525u + 1013904223u;
    return (double)(*s >> 8) / 16777216.0;
}

/* Random materials over the whole parameter range (roughness and radial roughness 0.02..1, coat
 * up to 0.95, offset +-10 deg, eta 1.05..3.05, sigma_a 0..50) and random directions, a fifth of
 * them grazing, some on R's cone: the C twin within 2e-4 of the reference (measured 3.6e-5 over
 * these 400; 1.6e-4 over 20000, the worst always R with coat > 0.9, a lobe of sigma ~ 0.1 deg,
 * where a float rounding of 1e-7 rad in theta moves M by ~3e-7 / sigma), no NaN/Inf. For the
 * measurements of docs/numerics-chiang.md, SL_CHIANG_SWEEP=N sets the sample count and
 * SL_CHIANG_SWEEP_RR=lo,hi the radial roughness range (uniform; then only printed, not checked). */
TEST(chiang_c_vs_reference_sweep) {
    unsigned seed = 5;
    double worst = 0.0, lim = CGRAZE, rr_lo = 0.0, rr_hi = 0.0;
    const char *env_n = getenv("SL_CHIANG_SWEEP"), *env_rr = getenv("SL_CHIANG_SWEEP_RR");
    int n = env_n ? atoi(env_n) : 400;
    if (env_rr && sscanf(env_rr, "%lf,%lf", &rr_lo, &rr_hi) != 2) rr_lo = rr_hi = 0.0;
    for (int i = 0; i < n; i++) {
        sl_material m;
        sl_material_default(&m);
        m.model = SL_MODEL_CHIANG;
        sl_chiang *c = &m.chiang;
        c->roughness = 0.02 + 0.98 * pow(chiang_rand(&seed), 2);
        c->radial_roughness = 0.02 + 0.98 * pow(chiang_rand(&seed), 2);
        if (rr_hi > 0.0) c->radial_roughness = rr_lo + (rr_hi - rr_lo) * chiang_rand(&seed);
        c->coat = chiang_rand(&seed) < 0.3 ? 0.95 * chiang_rand(&seed) : 0.0;
        c->offset = (chiang_rand(&seed) - 0.5) * 20 * CPI / 180;
        m.eta = 1.05 + 2 * chiang_rand(&seed);
        c->sigma_a_given = 1;
        double sg = chiang_rand(&seed) < 0.3 ? 0.0 : 50 * pow(chiang_rand(&seed), 3);
        m.sigma_a[0] = m.sigma_a[1] = m.sigma_a[2] = sg;
        sl_chiang_derive(&m);
        sl_fiber_params fp;
        sl_material_to_fiber(&m, 0, &fp);
        float x[4] = {(float)((2 * chiang_rand(&seed) - 1) * lim), 0.0f,
                      (float)((2 * chiang_rand(&seed) - 1) * lim),
                      (float)((2 * chiang_rand(&seed) - 1) * CPI)};
        if (i % 5 == 1) x[2] = (float)(chiang_rand(&seed) < 0.5 ? lim : -lim);
        if (i % 5 == 2) x[0] = (float)(chiang_rand(&seed) < 0.5 ? lim : -lim);
        if (i % 7 == 3) x[0] = (float)fmax(-lim, fmin(lim, 2 * m.alpha[0] - x[2]));
        if (i % 4 == 0) x[3] = 0.0f;
        float out[5];
        double ref[5], err[5];
        sl_chiang_scatter(&fp, x[0], x[1], x[2], x[3], out);
        slref_chiang_scatter(&m, 0, x[0], x[1], x[2], x[3], ref);
        chiang_errors(&m, 0, x, ref, out, err);
        for (int p = 0; p < 5; p++) {
            worst = fmax(worst, err[p]);
            CHECK_MSG(err[p] <= 2e-4 || rr_hi > 0.0,
                      "sample %d p %d: float %.9g ref %.9g (err %.3g)", i, p, out[p], ref[p],
                      err[p]);
        }
    }
    printf("  c vs reference, random sweep: worst %.2e (tolerance 2e-4)\n", worst);
}

/* Panels: the default rule gives >= SL_CHIANG_PANELS_MIN, grows as 1/s, stops at the cap. */
TEST(chiang_panels_rule) {
    sl_fiber_params fp;
    memset(&fp, 0, sizeof fp);
    fp.logistic_s = 4.28f;
    CHECK(sl_chiang_default_panels(&fp) == SL_CHIANG_PANELS_MIN);
    fp.logistic_s = 0.0101738f; /* radial roughness 0.05 */
    CHECK(sl_chiang_default_panels(&fp) == 59);
    fp.logistic_s = 1e-5f;
    CHECK(sl_chiang_default_panels(&fp) == SL_CHIANG_PANELS_MAX);
}
