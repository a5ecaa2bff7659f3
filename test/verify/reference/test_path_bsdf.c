/* test_path_bsdf.c: the path tracer's fiber at one hit (cpu/reference/fiber_bsdf.h and the model
 * files, mp_sample.h, fiber_hit.h): the sign of the offset h against a specular reflection
 * computed from the cylinder, M_p sampling against its density, for every model that the
 * sampled density integrates to 1 and matches the samples (chi-square on theta_i x phi_i bins)
 * and that the estimate E[f / pdf] is the albedo integral of f, the per-hit d'Eon fiber averaged
 * over h against the reference's width-averaged f, and chiang's evaluation against chiang_hit. */
#include "test.h"

#include "chiang_hit.h"
#include "deon_hit.h"
#include "deon_ref.h"
#include "fiber_bsdf.h"
#include "fiber_hit.h"
#include "furnace_ref.h"
#include "mp_sample.h"
#include "path_rng.h"
#include "quad.h"
#include "raytrace_ref.h"
#include "render_ref.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

static void unit3(double v[3]) {
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; k++)
        v[k] /= l;
}
static double dot3(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* A ray reflected specularly off a round fiber, from the cylinder's own geometry: the reflected
 * direction is the path's omega_i, so phi_o - phi_i must be Phi(0, h) = -2 asin h and theta_i =
 * -theta_o, with h from slref_fiber_offset, and from Embree's hit on the same fiber. */
TEST(path_offset_reflection_phi) {
    double p0[3] = {0.3, -0.2, 0.1}, u[3] = {1, 0.3, 0.2}, v[3], w[3], r = 0.05;
    unit3(u);
    slref_fiber_frame(u, v, w);
    /* one strand along u through p0 (2 points), for Embree */
    sl_hair hr;
    memset(&hr, 0, sizeof hr);
    uint32_t first[2] = {0, 2};
    float pos[6];
    for (int k = 0; k < 3; k++)
        pos[k] = (float)(p0[k] - 5 * u[k]), pos[3 + k] = (float)(p0[k] + 5 * u[k]);
    hr.num_strands = 1, hr.num_points = 2, hr.strand_first = first, hr.pos = pos;
    hr.default_radius = (float)r;
    slref_rt *rt = NULL;
    sl_err e;
    CHECK(slref_rt_build(&hr, &rt, &e) == 0);
    slref_rng g;
    slref_rng_seed(&g, 7, 0, 0);
    double worst = 0, worst_rt = 0, worst_th = 0;
    for (int i = 0; i < 200; i++) {
        double to = (slref_rng_unit(&g) - 0.5) * 2.6, po = (slref_rng_unit(&g) - 0.5) * 2 * PI;
        double wo[3], d[3], o[3];
        slref_frame_dir(u, v, w, to, po, wo);
        for (int k = 0; k < 3; k++)
            d[k] = -wo[k];
        /* origin: far along omega_o, moved by a random vector (not along the offset's axis) */
        double q[3] = {slref_rng_unit(&g) - 0.5, slref_rng_unit(&g) - 0.5,
                       slref_rng_unit(&g) - 0.5};
        for (int k = 0; k < 3; k++)
            o[k] = p0[k] + 2 * r * q[k] + 3.0 * wo[k];
        /* the cylinder |(o + t d - p0)_perp| = r, nearer root */
        double a[3], b[3];
        double oq[3] = {o[0] - p0[0], o[1] - p0[1], o[2] - p0[2]};
        double ou = dot3(oq, u), du = dot3(d, u);
        for (int k = 0; k < 3; k++)
            a[k] = oq[k] - ou * u[k], b[k] = d[k] - du * u[k];
        double A = dot3(b, b), B = 2 * dot3(a, b), C = dot3(a, a) - r * r, disc = B * B - 4 * A * C;
        if (disc <= 0) continue; /* misses */
        double t = (-B - sqrt(disc)) / (2 * A), n[3], refl[3];
        for (int k = 0; k < 3; k++)
            n[k] = (a[k] + t * b[k]) / r;
        double dn = dot3(d, n);
        for (int k = 0; k < 3; k++)
            refl[k] = d[k] - 2 * dn * n[k];
        double ti, pi_, t2, p2;
        slref_frame_angles(u, v, w, refl, &ti, &pi_);
        slref_frame_angles(u, v, w, wo, &t2, &p2);
        double h = slref_fiber_offset(o, d, p0, u, r);
        double err = fabs(remainder((p2 - pi_) - (-2 * asin(h)), 2 * PI));
        worst = fmax(worst, err);
        worst_th = fmax(worst_th, fabs(ti + t2));
        /* the same h from Embree's hit: the primitive's axis and radius */
        slref_hit hit;
        if (slref_rt_intersect(rt, o, d, INFINITY, &hit)) {
            double ax[3], rad, ut[3];
            slref_rt_prim_axis(rt, hit.prim, hit.u, ax, &rad);
            slref_rt_prim_info(rt, hit.prim, NULL, NULL, ut);
            worst_rt = fmax(worst_rt, fabs(slref_fiber_offset(o, d, ax, ut, rad) - h));
        }
    }
    /* float geometry in Embree (positions and tangent): h agrees to ~1e-5 */
    CHECK_MSG(worst < 1e-9, "phi_o - phi_i differs from -2 asin h by %g", worst);
    CHECK_MSG(worst_th < 1e-9, "theta_i differs from -theta_o by %g", worst_th);
    CHECK_MSG(worst_rt < 1e-4, "h from the Embree hit differs by %g", worst_rt);
    slref_rt_free(rt);
}

/* Chi-square statistic's bound: dof + 5 sqrt(2 dof) (a normal approximation, ~3e-7 one-sided:
 * with a fixed seed the test is deterministic; a wrong density moves it by orders). */
static double chi2_bound(int dof) {
    return dof + 5.0 * sqrt(2.0 * dof);
}

typedef struct mp_ctx {
    double v, to;
} mp_ctx;
static double mp_cos(double ti, void *c) {
    const mp_ctx *m = c;
    return exp(slref_deon_log_mp(m->v, ti, m->to)) * cos(ti);
}

TEST(path_mp_sample_density) {
    static const double V[4] = {0.004, 0.05, 0.4, 3.0}, TO[3] = {0.35, -1.2, 1.9};
    enum { NB = 40, NS = 100000 };
    for (int iv = 0; iv < 4; iv++)
        for (int io = 0; io < 3; io++) {
            mp_ctx c = {V[iv], TO[io]};
            double prob[NB], tot = 0;
            for (int b = 0; b < NB; b++) {
                double a = -PI / 2 + PI * b / NB, z = a + PI / NB;
                prob[b] = slq_integrate(mp_cos, &c, a, z, 1e-10, 1e-14, 40, NULL);
                tot += prob[b];
            }
            CHECK_NEAR(tot, 1.0, 1e-6);
            int cnt[NB] = {0};
            slref_rng g;
            slref_rng_seed(&g, 11, (uint64_t)iv, (uint64_t)io);
            for (int s = 0; s < NS; s++) {
                double u1 = slref_rng_unit(&g), u2 = slref_rng_unit(&g);
                double ti = slref_mp_sample(c.v, c.to, u1, u2);
                int b = (int)floor((ti + PI / 2) / PI * NB);
                cnt[b < 0 ? 0 : (b >= NB ? NB - 1 : b)]++;
            }
            double chi = 0, rest_e = 0, rest_o = 0;
            int dof = -1;
            for (int b = 0; b < NB; b++) {
                double ex = prob[b] * NS;
                if (ex < 5) {
                    rest_e += ex, rest_o += cnt[b];
                    continue;
                }
                chi += (cnt[b] - ex) * (cnt[b] - ex) / ex, dof++;
            }
            if (rest_e >= 5) chi += (rest_o - rest_e) * (rest_o - rest_e) / rest_e, dof++;
            CHECK_MSG(chi < chi2_bound(dof), "v %g theta_o' %g: chi2 %.1f, dof %d", c.v, c.to, chi,
                      dof);
        }
}

/* ---- every model: density integrates to 1, matches the samples, E[f/pdf] = albedo ---- */

enum { TB = 24, PB = 48, SUB = 3 };
static const double GL4_X[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                0.8611363115940526};
static const double GL4_W[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                0.3478548451374538};

/* Integrates pdf (and, with f, the channel-0 f) cos theta over bin (i, j) of TB x PB on
 * theta_i in [-pi/2, pi/2], phi_i in [phi_o - pi, phi_o + pi): SUB x SUB cells of 4 x 4
 * Gauss-Legendre points. */
static void bin_integrals(const slref_bsdf *b, int i, int j, double *pdf_int, double *f_int) {
    double dt = PI / TB, dp = 2 * PI / PB, p = 0, fs = 0;
    for (int si = 0; si < SUB; si++)
        for (int sj = 0; sj < SUB; sj++) {
            double t0 = -PI / 2 + i * dt + si * dt / SUB,
                   p0 = b->phi_o - PI + j * dp + sj * dp / SUB;
            for (int a = 0; a < 4; a++)
                for (int c = 0; c < 4; c++) {
                    double ti = t0 + (GL4_X[a] + 1) * dt / (2 * SUB);
                    double pi_ = p0 + (GL4_X[c] + 1) * dp / (2 * SUB);
                    double wgt = GL4_W[a] * GL4_W[c] * dt / (2 * SUB) * dp / (2 * SUB) * cos(ti);
                    p += wgt * slref_bsdf_pdf(b, ti, pi_);
                    if (f_int) {
                        double f[3];
                        slref_bsdf_eval(b, ti, pi_, f, NULL);
                        fs += wgt * f[0];
                    }
                }
        }
    *pdf_int = p;
    if (f_int) *f_int = fs;
}

/* Samples ns directions: chi-square of their bins against the density's bin integrals, the
 * density's total, and (mc not NULL) the mean of f / pdf (channel 0) in *mc, its standard error
 * in *se; albedo_quad (may be NULL): the bins' quadrature of f. */
static void check_sampling(const char *what, const slref_bsdf *b, int ns, double *total, double *mc,
                           double *se, double *albedo_quad) {
    static double prob[TB][PB];
    static int cnt[TB][PB];
    double tot = 0, alb = 0;
    for (int i = 0; i < TB; i++)
        for (int j = 0; j < PB; j++) {
            double fi;
            bin_integrals(b, i, j, &prob[i][j], albedo_quad ? &fi : NULL);
            tot += prob[i][j];
            if (albedo_quad) alb += fi;
            cnt[i][j] = 0;
        }
    *total = tot;
    if (albedo_quad) *albedo_quad = alb;
    slref_rng g;
    slref_rng_seed(&g, 5, (uint64_t)(b->theta_o * 1e6), (uint64_t)((b->h + 2) * 1e6));
    double s = 0, s2 = 0, worst_pdf = 0;
    int fails = 0;
    for (int k = 0; k < ns; k++) {
        double ti, pi_, pdf, f[3];
        if (!slref_bsdf_sample(b, &g, &ti, &pi_, &pdf)) {
            fails++;
            continue;
        }
        /* the density returned is the density function's value there */
        worst_pdf = fmax(worst_pdf, fabs(pdf - slref_bsdf_pdf(b, ti, pi_)) / pdf);
        if (mc) {
            slref_bsdf_eval(b, ti, pi_, f, NULL);
            double wgt = f[0] / pdf;
            s += wgt, s2 += wgt * wgt;
        }
        int i = (int)floor((ti + PI / 2) / PI * TB);
        double rel = remainder(pi_ - (b->phi_o - PI), 2 * PI);
        if (rel < 0) rel += 2 * PI;
        int j = (int)floor(rel / (2 * PI) * PB);
        cnt[i < 0 ? 0 : (i >= TB ? TB - 1 : i)][j < 0 ? 0 : (j >= PB ? PB - 1 : j)]++;
    }
    if (mc) {
        *mc = s / ns;
        *se = sqrt(fmax(0.0, s2 / ns - (*mc) * (*mc)) / ns);
    }
    double chi = 0, re = 0, ro = 0;
    int dof = -1;
    for (int i = 0; i < TB; i++)
        for (int j = 0; j < PB; j++) {
            double ex = prob[i][j] / tot * (ns - fails);
            if (ex < 5) {
                re += ex, ro += cnt[i][j];
                continue;
            }
            chi += (cnt[i][j] - ex) * (cnt[i][j] - ex) / ex, dof++;
        }
    if (re >= 5) chi += (ro - re) * (ro - re) / re, dof++;
    if (getenv("SL_TEST_VERBOSE"))
        fprintf(stderr, "%s: total %.8f chi2 %.1f dof %d mc %.6f se %.2g alb %.6f\n", what, tot,
                chi, dof, mc ? *mc : 0, se ? *se : 0, albedo_quad ? *albedo_quad : 0);
    CHECK_MSG(worst_pdf < 1e-12, "%s: returned pdf differs from slref_bsdf_pdf by %g", what,
              worst_pdf);
    CHECK_MSG(fails <= ns / 10000, "%s: %d of %d samples failed", what, fails, ns);
    CHECK_MSG(dof > 20 && chi < chi2_bound(dof), "%s: chi2 %.1f, dof %d", what, chi, dof);
}

static void chiang_material(sl_material *m, double melanin, double rough, double radial) {
    sl_material_default(m);
    m->model = SL_MODEL_CHIANG;
    m->chiang.melanin = melanin;
    m->chiang.roughness = rough;
    m->chiang.radial_roughness = radial;
    sl_chiang_derive(m);
}

TEST(path_bsdf_chiang_sampling) {
    sl_material m;
    static const double TO[3] = {0.2, -0.9, 1.35}, H[3] = {0.1, -0.7, 0.95};
    for (int k = 0; k < 3; k++) {
        chiang_material(&m, k == 0 ? 0.0 : 0.5, 0.3 + 0.1 * k, 0.3 + 0.15 * k);
        slref_bsdf b;
        slref_bsdf_init(&b, &m, TO[k], 0.4, H[k]);
        double tot, mc, se, alb;
        char what[64];
        snprintf(what, sizeof what, "chiang theta_o %g h %g", TO[k], H[k]);
        check_sampling(what, &b, 80000, &tot, &mc, &se, &alb);
        CHECK_MSG(fabs(tot - 1) < 1e-4, "%s: density integrates to %.7f", what, tot);
        /* albedo of the hit: sum_p A_p (each M_p and N_p normalised), = 1 at melanin 0 */
        double asum = b.ck[0].A[0] + b.ck[0].A[1] + b.ck[0].A[2] + b.ck[0].A[3];
        CHECK_MSG(fabs(alb - asum) < 1e-4 * asum, "%s: quadrature %.7f vs sum A_p %.7f", what, alb,
                  asum);
        if (k == 0) CHECK_NEAR(asum, 1.0, 1e-12);
        CHECK_MSG(fabs(mc - asum) < 4 * se + 1e-12, "%s: E[f/pdf] %.6f +- %.2g vs %.6f", what, mc,
                  se, asum);
        /* one channel's sampling is exact: f / pdf = sum_p A_p for a grey fiber (se ~ 0) */
        if (k == 0) CHECK_MSG(se < 1e-9, "%s: f/pdf not constant (se %g)", what, se);
    }
}

TEST(path_bsdf_chiang_eval_matches_hit) {
    sl_material m;
    chiang_material(&m, 0.6, 0.35, 0.4);
    slref_bsdf b;
    slref_bsdf_init(&b, &m, 0.3, -0.8, -0.35);
    double worst = 0;
    for (int i = 0; i < 50; i++) {
        double ti = -1.5 + 3.0 * i / 49, pi_ = -3 + 6.0 * ((i * 7) % 50) / 49;
        double f[3], lob[SLREF_NLOBES][3];
        slref_bsdf_eval(&b, ti, pi_, f, lob);
        for (int c = 0; c < 3; c++) {
            slref_chiang_hit k;
            double out[4];
            slref_chiang_hit_init(&m, c, 0.3, -0.35, &k);
            double want = slref_chiang_hit_f(&m, &k, ti, 0.3, -0.8 - pi_, out);
            worst = fmax(worst, fabs(f[c] - want) / (want + 1e-300));
            for (int p = 0; p < 4; p++)
                worst = fmax(worst, fabs(lob[p][c] - out[p]) / (want + 1e-300));
        }
    }
    CHECK_MSG(worst < 1e-12, "relative difference %g", worst);
}

/* d'Eon white: sigma_a 0, one alpha (0) and one beta for every order: albedo 1 per hit. */
static void deon_material(sl_material *m, int white) {
    sl_material_default(m);
    m->model = SL_MODEL_DEON;
    if (white) {
        m->sigma_a[0] = m->sigma_a[1] = m->sigma_a[2] = 0;
        for (int t = 0; t < 3; t++)
            m->alpha[t] = 0, m->beta[t] = 10 * PI / 180;
    }
}

TEST(path_bsdf_deon_sampling) {
    sl_material m;
    static const double TO[3] = {0.25, -1.0, 1.3}, H[3] = {0.3, -0.85, 0.0};
    for (int k = 0; k < 3; k++) {
        deon_material(&m, k == 0);
        if (k == 2) m.sigma_a[0] = 0.2, m.sigma_a[1] = 0.5, m.sigma_a[2] = 1.1;
        slref_bsdf b;
        slref_bsdf_init(&b, &m, TO[k], 1.1, H[k]);
        double tot, mc, se, alb = 1;
        char what[64];
        snprintf(what, sizeof what, "deon theta_o %g h %g", TO[k], H[k]);
        /* white (k = 0): the albedo is 1 and f / pdf is exactly 1 (deon_hit.h), so the f
         * quadrature is skipped there (the deon evaluation is the costly one) */
        check_sampling(what, &b, 60000, &tot, &mc, &se, k == 0 ? NULL : &alb);
        CHECK_MSG(fabs(tot - 1) < 1e-4, "%s: density integrates to %.7f", what, tot);
        if (k == 0) CHECK_MSG(se < 1e-9, "%s: white f/pdf not constant (se %g)", what, se);
        CHECK_MSG(fabs(mc - alb) < 4 * se + 1e-4 * alb, "%s: E[f/pdf] %.6f +- %.2g vs %.6f", what,
                  mc, se, alb);
    }
}

typedef struct h_ctx {
    const sl_material *m;
    double ti, to, phi;
} h_ctx;
static double hit_f_of_h(double h, void *c) {
    const h_ctx *x = c;
    return 0.5 * slref_deon_hit_f(x->m, 0, h, x->ti, x->to, x->phi, NULL);
}

/* 1/2 integral over h of the per-hit f is d'Eon's f (deon_ref.h, Eq. 10 integrated by the
 * reference with its own breakpoints): both adaptive, to ~1e-7. */
TEST(path_deon_hit_average) {
    sl_material m;
    deon_material(&m, 0);
    static const double Q[5][3] = {
        {-0.3, 0.2, 0.1}, {0.5, 0.4, 2.9}, {-1.0, 0.9, -1.2}, {0.1, -0.2, 3.1}, {0.7, -0.6, 0.6}};
    for (int q = 0; q < 5; q++) {
        h_ctx c = {&m, Q[q][0], Q[q][1], Q[q][2]};
        double pts[64];
        int np = 0;
        for (int k = 1; k < 64; k++)
            pts[np++] = -1 + 2.0 * k / 64; /* resolves the narrow detectors in h */
        double got = slq_integrate_pts(hit_f_of_h, &c, -1, 1, pts, np, 1e-10, 1e-14, 50, NULL);
        double out[SL_MATERIAL_MAX_ORDERS + 3];
        slref_deon_scatter(&m, 0, Q[q][0], 0.0, Q[q][1], Q[q][2], out);
        double want = out[m.orders + 2];
        CHECK_MSG(fabs(got - want) <= 1e-6 * want + 1e-12, "query %d: %.10g vs %.10g", q, got,
                  want);
    }
}

/* Marschner: the width-averaged f is costly (~45 us: the TRT convolution), so the density is
 * checked alone and E[f/pdf] on 3000 samples against the reference's furnace integral
 * (furnace_ref.h; lobes twice the default widths, where it takes ~2 s instead of ~5). */
TEST(path_bsdf_marschner_sampling) {
    sl_material m;
    sl_material_default(&m);
    for (int t = 0; t < 3; t++)
        m.beta[t] *= 2;
    m.caustic_width *= 2;
    slref_bsdf b;
    slref_bsdf_init(&b, &m, 0.4, 0.2, 0.0);
    double tot;
    check_sampling("marschner density", &b, 150000, &tot, NULL, NULL, NULL);
    CHECK_MSG(fabs(tot - 1) < 1e-4, "density integrates to %.7f", tot);
    /* E[f/pdf] with f evaluated: 3000 samples */
    slref_rng g;
    slref_rng_seed(&g, 3, 1, 2);
    double s = 0, s2 = 0;
    int n = 3000;
    for (int k = 0; k < n; k++) {
        double ti, pi_, pdf, f[3];
        if (!slref_bsdf_sample(&b, &g, &ti, &pi_, &pdf)) continue;
        slref_bsdf_eval(&b, ti, pi_, f, NULL);
        s += f[0] / pdf, s2 += (f[0] / pdf) * (f[0] / pdf);
    }
    double mean = s / n, err = sqrt((s2 / n - mean * mean) / n);
    double alb = slref_furnace(&m, 0, 0.4, 0.2);
    CHECK_MSG(fabs(mean - alb) < 4 * err, "E[f/pdf] %.5f +- %.2g vs furnace %.5f", mean, err, alb);
}
