/* test_dual.c: the dual-scattering material terms (docs/dual.md): the double reference
 * (cpu/reference/dual_ref.c, adaptive quadrature over phi of the reference N_t) and the float
 * form (kernels/dual_material.h: h-space Gauss-Legendre, tables) against independent
 * computations written here: brute-force midpoint sums over h with this file's own Fresnel and
 * absorption, the TRT weight convolved by a direct sum over the circle, closed forms at grazing
 * incidence, Zinke 2008's backscattering formulas typed in again, and an explicit layer-adding
 * iteration for the multiple-scattering share. */
#include "test.h"

#include "passes/volume/dual.h"
#include "dual_c.h"
#include "dual_ref.h"

#include <stdlib.h>
#include <string.h>

#define DPI 3.14159265358979323846
#define DDEG (DPI / 180.0)

/* ---- independent brute force (this file only) ---- */

/* Unpolarised dielectric Fresnel from outside into index eta at incidence cosine ci. */
static double dual_fresnel(double eta, double ci) {
    double s2 = (1.0 - ci * ci) / (eta * eta);
    if (s2 >= 1.0) return 1.0;
    double ct = sqrt(1.0 - s2);
    double rs = (ci - eta * ct) / (ci + eta * ct), rp = (eta * ci - ct) / (eta * ci + ct);
    return 0.5 * (rs * rs + rp * rp);
}

/* A_t(u) of numerics.md sec. 3 at h = sin u, exact Fresnel, eccentricity 1. */
static double dual_A(int t, double eta, double sigma_a, double td, double u) {
    double F = dual_fresnel(eta, cos(td) * cos(u));
    if (t == 0) return F;
    double etap = sqrt(eta * eta - sin(td) * sin(td)) / cos(td);
    double ctt = sqrt(1.0 - sin(td) * sin(td) / (eta * eta));
    double sg = sin(u) / etap;
    double T = exp(-2.0 * sigma_a / ctt * sqrt(1.0 - sg * sg));
    return t == 1 ? (1 - F) * (1 - F) * T : (1 - F) * (1 - F) * F * T * T;
}

/* Phi(t, sin u) = 2t asin(sin u / eta') - 2u + t pi, wrapped to (-pi, pi]. */
static double dual_phi(int t, double eta, double td, double u) {
    double etap = sqrt(eta * eta - sin(td) * sin(td)) / cos(td);
    double x = 2.0 * t * asin(sin(u) / etap) - 2.0 * u + t * DPI;
    x = fmod(x + DPI, 2.0 * DPI);
    if (x < 0) x += 2.0 * DPI;
    return x - DPI;
}

/* |y| on (-pi, pi] convolved with exp(2(cos x - 1)/w^2) / its integral: a direct midpoint sum
 * over the circle (4000 points). */
static double dual_wconv(double x, double w) {
    const int n = 4000;
    double num = 0, den = 0;
    for (int k = 0; k < n; k++) {
        double y = -DPI + (k + 0.5) * 2.0 * DPI / n;
        double g = exp(2.0 * (cos(x - y) - 1.0) / (w * w));
        num += fabs(y) * g;
        den += g;
    }
    return num / den;
}

/* a_{f,t} and a_{b,t} by the identity int w(phi) N_t dphi = 1/2 int A_t(h) w(Phi_t(h)) dh
 * (docs/dual.md): midpoint sum over u in (-pi/2, pi/2), nu points. */
static void dual_brute_mode(int t, double eta, double sigma_a, double td, double wc, int nu,
                            double *af, double *ab) {
    double sf = 0, sb = 0, du = DPI / nu;
    for (int k = 0; k < nu; k++) {
        double u = -DPI / 2 + (k + 0.5) * du;
        double a = dual_A(t, eta, sigma_a, td, u) * cos(u) * du;
        double phi = dual_phi(t, eta, td, u);
        double W = t == 2 ? dual_wconv(phi, wc) : fabs(phi);
        sf += a * W;
        sb += a * (DPI - W);
    }
    *af = sf / (2.0 * DPI);
    *ab = sb / (2.0 * DPI);
}

static void dual_mat(sl_material *m, double sigma_a) {
    sl_material_default(m);
    m->sigma_a[0] = m->sigma_a[1] = m->sigma_a[2] = sigma_a;
}

/* ---- tests ---- */

/* sigma_a = 0: a_f + a_b = 1/2 int (F + (1-F)^2 + (1-F)^2 F) dh, the energy of R + TT + TRT
 * (the orders above TRT carry (1-F) F^2). Reference quadrature is ~1e-9; the midpoint sum over
 * 20000 points ~1e-8: tolerance 1e-6. Float (Gauss-Legendre, float): 2e-5. */
TEST(dual_energy_sigma0) {
    sl_material m;
    dual_mat(&m, 0.0);
    sl_fiber_params fp;
    sl_material_to_fiber(&m, 0, &fp);
    float rho[SL_DUAL_MAXJ];
    int nj = sl_dual_vm_coefs(fp.caustic_width, rho);
    const double tds[] = {0.0, 0.4, 0.9, 1.3, 1.55};
    for (int i = 0; i < 5; i++) {
        double td = tds[i], e = 0;
        const int n = 20000;
        for (int k = 0; k < n; k++) {
            double h = -1.0 + (k + 0.5) * 2.0 / n;
            double F = dual_fresnel(m.eta, cos(td) * sqrt(1 - h * h));
            e += (F + (1 - F) * (1 - F) * (1 + F)) * (2.0 / n);
        }
        e *= 0.5;
        double out[9];
        slref_dual_terms(&m, 0, td, out);
        CHECK_NEAR(out[0] + out[1], e, 1e-6);
        CHECK(out[0] + out[1] < 1.0);
        float fo[9];
        sl_dual_terms(&fp, (float)td, rho, nj, fo);
        CHECK_NEAR(fo[0] + fo[1], e, 2e-5);
    }
}

/* Per-mode a_f, a_b against the brute-force sum over h (TRT's caustic convolution done by a
 * direct sum over the circle). Midpoint sums with 3000 points in u: ~1e-6 relative (checked by
 * halving); tolerance 2e-5 relative + 1e-7 absolute for both backends (float: ~1e-6). */
TEST(dual_modes_bruteforce) {
    struct {
        double sigma_a, eta, wc_deg, td;
    } cs[] = {
        {0.36, 1.55, 15, 0.2}, {0.0, 1.55, 15, 1.1}, {1.5, 1.9, 6, 0.6}, {0.1, 1.3, 30, 1.45}};
    for (size_t c = 0; c < sizeof cs / sizeof cs[0]; c++) {
        sl_material m;
        dual_mat(&m, cs[c].sigma_a);
        m.eta = cs[c].eta;
        m.caustic_width = cs[c].wc_deg * DDEG;
        sl_fiber_params fp;
        sl_material_to_fiber(&m, 0, &fp);
        float rho[SL_DUAL_MAXJ];
        int nj = sl_dual_vm_coefs(fp.caustic_width, rho);
        double raf[3], rab[3];
        float faf[3], fab[3];
        slref_dual_attenuations(&m, 0, cs[c].td, raf, rab);
        sl_dual_attenuations(&fp, (float)cs[c].td, rho, nj, faf, fab);
        for (int t = 0; t < 3; t++) {
            double af, ab;
            dual_brute_mode(t, m.eta, cs[c].sigma_a, cs[c].td, m.caustic_width, 3000, &af, &ab);
            CHECK_NEAR(raf[t], af, 2e-5 * af + 1e-7);
            CHECK_NEAR(rab[t], ab, 2e-5 * ab + 1e-7);
            CHECK_NEAR(faf[t], af, 2e-5 * af + 1e-7);
            CHECK_NEAR(fab[t], ab, 2e-5 * ab + 1e-7);
        }
    }
}

/* theta_d = pi/2: cos i = 0, F = 1 for every h, only R carries light with N_R = cos(phi/2)/4:
 * a_b = 2/pi int_0^pi (pi - phi) cos(phi/2)/4 dphi = 2/pi, a_f = 1 - 2/pi; every shift and
 * width is R's. Tolerances: reference 1e-7, float table 2e-6 (float rounding). */
TEST(dual_grazing_edge) {
    sl_material m;
    dual_mat(&m, 0.36);
    double out[9];
    slref_dual_terms(&m, 0, DPI / 2, out);
    CHECK_NEAR(out[0], 1.0 - 2.0 / DPI, 1e-7);
    CHECK_NEAR(out[1], 2.0 / DPI, 1e-7);
    CHECK_NEAR(out[2], m.alpha[0], 1e-7);
    CHECK_NEAR(out[3], m.alpha[0], 1e-7);
    CHECK_NEAR(out[4], m.beta[0], 1e-7);
    CHECK_NEAR(out[5], m.beta[0], 1e-7);
    sl_fiber_params fp;
    sl_material_to_fiber(&m, 0, &fp);
    float in[2] = {1.5707963f, -1.5707963f}, fo[18];
    slc_ms_material_batch(&fp, 2, in, fo);
    for (int r = 0; r < 2; r++) {
        CHECK_NEAR(fo[r * 9 + 0], 1.0 - 2.0 / DPI, 2e-6);
        CHECK_NEAR(fo[r * 9 + 1], 2.0 / DPI, 2e-6);
        CHECK_NEAR(fo[r * 9 + 4], m.beta[0], 2e-6);
    }
}

/* Zinke 2008's local backscattering typed in again (A_1 + A_3, Delta_b, sigma_b as printed, d_b
 * 0.7) and Xu's attenuation-weighted shifts and squared widths, on pseudo-random inputs, against
 * both combiners. Tolerances: double 1e-12 relative, float 2e-5 relative + 1e-7. */
TEST(dual_combine_zinke) {
    unsigned s = 12345;
    for (int it = 0; it < 200; it++) {
        double af[3], ab[3], al[3], be[3];
        float faf[3], fab[3], fal[3], fbe[3];
        for (int t = 0; t < 3; t++) {
            s = s * 1103515245u + 12345u;
            af[t] = (s >> 8) / 16777216.0 * 0.3;
            s = s * 1103515245u + 12345u;
            ab[t] = (s >> 8) / 16777216.0 * 0.2;
            s = s * 1103515245u + 12345u;
            al[t] = ((s >> 8) / 16777216.0 - 0.5) * 0.4;
            s = s * 1103515245u + 12345u;
            be[t] = 0.02 + (s >> 8) / 16777216.0 * 0.5;
            faf[t] = (float)af[t];
            fab[t] = (float)ab[t];
            fal[t] = (float)al[t];
            fbe[t] = (float)be[t];
        }
        double Af = af[0] + af[1] + af[2], Ab = ab[0] + ab[1] + ab[2];
        double alf = (af[0] * al[0] + af[1] * al[1] + af[2] * al[2]) / Af;
        double alb = (ab[0] * al[0] + ab[1] * al[1] + ab[2] * al[2]) / Ab;
        double bf =
            sqrt((af[0] * be[0] * be[0] + af[1] * be[1] * be[1] + af[2] * be[2] * be[2]) / Af);
        double bb =
            sqrt((ab[0] * be[0] * be[0] + ab[1] * be[1] * be[1] + ab[2] * be[2] * be[2]) / Ab);
        double A1 = Ab * Af * Af / (1 - Af * Af);
        double A3 = pow(Ab, 3) * Af * Af / pow(1 - Af * Af, 3);
        double D = alb * (1 - 2 * Ab * Ab / pow(1 - Af * Af, 2)) +
                   alf * (2 * pow(1 - Af * Af, 2) + 4 * Af * Af * Ab * Ab) / pow(1 - Af * Af, 3);
        double sg =
            (1 + 0.7 * Af * Af) *
            (Ab * sqrt(2 * bf * bf + bb * bb) + pow(Ab, 3) * sqrt(2 * bf * bf + 3 * bb * bb)) /
            (Ab + pow(Ab, 3) * (2 * bf + 3 * bb));
        double want[9] = {Af, Ab, alf, alb, bf, bb, A1 + A3, D, sg};
        double out[9];
        float fo[9];
        slref_dual_combine(af, ab, al, be, out);
        sl_dual_combine(faf, fab, fal, fbe, fo);
        for (int k = 0; k < 9; k++) {
            CHECK_NEAR(out[k], want[k], 1e-12 * fabs(want[k]) + 1e-15);
            CHECK_NEAR(fo[k], want[k], 2e-5 * fabs(want[k]) + 1e-7);
        }
    }
}

/* The C twin's table (what `eval --backend c` and the renderer use) against the reference over
 * a set of materials and theta_d. Tolerances (docs/dual.md, measured worst 1.6e-3 relative, at
 * small A_b of dark hair): attenuations and A_b 3e-3 relative + 1e-6; shifts, widths, Delta_b and
 * sigma_b 3e-4 rad + 3e-3 relative. */
TEST(dual_table_vs_reference) {
    struct {
        double sigma_a, eta, wc_deg, alpha_deg, beta_deg;
        int schlick;
    } cs[] = {{0.36, 1.55, 15, -7.5, 7.5, 0},
              {0.0, 1.55, 15, -3, 4, 0},
              {3.0, 1.55, 15, -7.5, 12, 0},
              {0.2, 1.9, 5, -10, 6, 1},
              {0.6, 1.3, 40, 2, 20, 0}};
    const double tds[] = {0.0, 0.05, 0.37, 0.81, 1.1, 1.33, 1.49, 1.565};
    for (size_t c = 0; c < sizeof cs / sizeof cs[0]; c++) {
        sl_material m;
        dual_mat(&m, cs[c].sigma_a);
        m.eta = cs[c].eta;
        m.caustic_width = cs[c].wc_deg * DDEG;
        m.fresnel = cs[c].schlick ? SL_FRESNEL_SCHLICK : SL_FRESNEL_EXACT;
        double a = cs[c].alpha_deg * DDEG, b = cs[c].beta_deg * DDEG;
        m.alpha[0] = a, m.alpha[1] = -a / 2, m.alpha[2] = -3 * a / 2;
        m.beta[0] = b, m.beta[1] = b / 2, m.beta[2] = 2 * b;
        sl_fiber_params fp;
        sl_material_to_fiber(&m, 0, &fp);
        float in[8], fo[8 * 9];
        for (int i = 0; i < 8; i++)
            in[i] = (float)tds[i];
        slc_ms_material_batch(&fp, 8, in, fo);
        for (int i = 0; i < 8; i++) {
            double out[9];
            slref_dual_terms(&m, 0, tds[i], out);
            for (int k = 0; k < 9; k++) {
                int angle = k >= 2 && k != 6;
                double tol = angle ? 3e-4 + 3e-3 * fabs(out[k]) : 3e-3 * fabs(out[k]) + 1e-6;
                CHECK_MSG(fabs(fo[i * 9 + k] - out[k]) <= tol,
                          "case %zu td %g term %d: c %.9g ref %.9g", c, tds[i], k,
                          (double)fo[i * 9 + k], out[k]);
            }
        }
    }
}

/* Eccentric fiber: TRT averaged over the fiber's roll (docs/dual.md): float (8-point
 * Gauss-Legendre in the roll angle) vs reference (adaptive), eccentricity changing TRT and
 * leaving R and TT alone. */
TEST(dual_eccentric) {
    sl_material m;
    dual_mat(&m, 0.36);
    m.eccentricity = 0.85;
    double raf[3], rab[3];
    slref_dual_attenuations(&m, 0, 0.3, raf, rab);
    sl_fiber_params fp;
    sl_material_to_fiber(&m, 0, &fp);
    float rho[SL_DUAL_MAXJ], faf[3], fab[3];
    int nj = sl_dual_vm_coefs(fp.caustic_width, rho);
    sl_dual_attenuations(&fp, 0.3f, rho, nj, faf, fab);
    /* 8-point Gauss-Legendre in the roll vs adaptive: 1e-4 relative. */
    CHECK_NEAR(faf[2], raf[2], 1e-4 * raf[2]);
    CHECK_NEAR(fab[2], rab[2], 1e-4 * rab[2]);
    sl_material m1;
    dual_mat(&m1, 0.36);
    double af1[3], ab1[3];
    slref_dual_attenuations(&m1, 0, 0.3, af1, ab1);
    CHECK(fabs(rab[2] - ab1[2]) > 1e-4); /* eccentricity changes TRT */
    CHECK_NEAR(raf[0], af1[0], 1e-15);   /* and nothing else */
    CHECK_NEAR(rab[1], ab1[1], 1e-15);
}

/* More absorption darkens: a_f and A_b strictly decrease with sigma_a, a_b never increases
 * (its R part does not depend on sigma_a); all stay in [0, 1]. Float tables, 129 nodes. */
TEST(dual_darkening) {
    const double sig[] = {0.0, 0.1, 0.3, 1.0, 3.0, 10.0};
    float prev[SL_DUAL_TABLE_FLOATS];
    float *tab = malloc(SL_DUAL_TABLE_FLOATS * sizeof *tab);
    for (int s = 0; s < 6; s++) {
        sl_material m;
        dual_mat(&m, sig[s]);
        sl_fiber_params fp;
        sl_material_to_fiber(&m, 0, &fp);
        slc_dual_table(&fp, tab);
        for (int i = 0; i < SL_DUAL_N - 1; i++) { /* the last node is grazing: no TT/TRT at all */
            float af = tab[SL_DUAL_AF * SL_DUAL_N + i], ab = tab[SL_DUAL_AB * SL_DUAL_N + i];
            float Ab = tab[SL_DUAL_A_B * SL_DUAL_N + i];
            CHECK(af >= 0 && ab >= 0 && af + ab <= 1.0f && Ab >= 0);
            if (s > 0) {
                /* Within ~0.07 rad of grazing TT and TRT carry < 1e-7 and a_f, A_b are R's alone,
                 * independent of sigma_a up to float rounding: strict only below 1.5. */
                int strict = sl_dual_node(i) < 1.5f;
                float paf = prev[SL_DUAL_AF * SL_DUAL_N + i],
                      pAb = prev[SL_DUAL_A_B * SL_DUAL_N + i];
                CHECK_MSG(strict ? af < paf : af <= paf * (1 + 1e-6f), "a_f node %d sigma %g", i,
                          sig[s]);
                CHECK_MSG(ab <= prev[SL_DUAL_AB * SL_DUAL_N + i] * (1 + 1e-6f), "a_b node %d", i);
                CHECK_MSG(strict ? Ab < pAb : Ab <= pAb * (1 + 1e-6f), "A_b node %d", i);
            }
        }
        memcpy(prev, tab, sizeof prev);
    }
    free(tab);
}

/* Xu Eq. 31's mean by the SAT against a fine trapezoid average of the interpolated row, on
 * intervals inside, across 0 (the row is even) and touching pi/2. Tolerance 2e-5 (float sums). */
TEST(dual_sat_mean) {
    sl_material m;
    dual_mat(&m, 0.36);
    sl_fiber_params fp;
    sl_material_to_fiber(&m, 0, &fp);
    float *tab = malloc(SL_DUAL_TABLE_FLOATS * sizeof *tab);
    slc_dual_table(&fp, tab);
    const double iv[][2] = {
        {0.1, 0.5}, {-0.3, 0.7}, {1.2, 1.5707963}, {-1.5707963, -1.0}, {0.0, 1.5707963}};
    for (int r = 0; r < 2; r++) {
        int row = r ? SL_DUAL_SIGMA_B : SL_DUAL_DELTA_B;
        for (int j = 0; j < 5; j++) {
            double a = iv[j][0], b = iv[j][1], sum = 0;
            const int n = 20000;
            for (int k = 0; k <= n; k++) {
                double x = a + (b - a) * k / n;
                sum += (k == 0 || k == n ? 0.5 : 1.0) * sl_dual_lookup(tab, row, (float)x);
            }
            double want = sum / n;
            CHECK_NEAR(sl_dual_mean(tab, row, (float)a, (float)b), want, 2e-5);
        }
    }
    free(tab);
}

/* The infinite-stack reflectance against adding layers one at a time (R_{n+1} = r + t^2 R_n /
 * (1 - r R_n) from R_0 = 0, to convergence), and the share: dark hair (eumelanin 8) well below
 * 0.05, blond (0.3) above 0.2, white (sigma_a 0) above 0.5, monotone in melanin. */
TEST(dual_ms_share_dark_blond) {
    const double rt[][2] = {{0.1, 0.4}, {0.05, 0.9}, {0.3, 0.3}, {0.02, 0.0}};
    for (int i = 0; i < 4; i++) {
        double R = 0;
        for (int k = 0; k < 100000; k++)
            R = rt[i][0] + rt[i][1] * rt[i][1] * R / (1 - rt[i][0] * R);
        CHECK_NEAR(sl_dual_stack_reflectance(rt[i][0], rt[i][1]), R, 1e-9);
    }
    const double mel[] = {0.0, 0.3, 1.3, 8.0};
    double share[4];
    for (int i = 0; i < 4; i++) {
        sl_material m;
        sl_material_default(&m);
        const double k[3] = {0.419, 0.697, 1.37}; /* d'Eon 2011 Sec. 6.1, numerics.md sec. 2 */
        for (int c = 0; c < 3; c++)
            m.sigma_a[c] = mel[i] * k[c];
        m.sigma_a_rgb = 1;
        share[i] = sl_dual_ms_share(&m);
        CHECK(share[i] >= 0 && share[i] < 1);
        if (i) CHECK(share[i] < share[i - 1]);
    }
    CHECK(share[0] > 0.5);
    CHECK(share[1] > 0.2);
    CHECK(share[3] < 0.01);
    /* deon and chiang have their own terms now (kernels/dual_ec.h; this test said "< 0, not
     * evaluated" before): the same ordering holds, white above 0.5, dark below 0.01. */
    for (int model = SL_MODEL_DEON; model <= SL_MODEL_CHIANG; model++) {
        double prev = 2.0;
        for (int i = 0; i < 4; i++) {
            sl_material d;
            sl_material_default(&d);
            d.model = model;
            if (model == SL_MODEL_CHIANG) sl_chiang_derive(&d);
            const double k[3] = {0.419, 0.697, 1.37};
            for (int c = 0; c < 3; c++)
                d.sigma_a[c] = mel[i] * k[c];
            d.sigma_a_rgb = 1;
            double sd = sl_dual_ms_share(&d);
            CHECK(sd >= 0 && sd < prev);
            if (i == 0) CHECK(sd > 0.5);
            if (i == 3) CHECK(sd < 0.01);
            prev = sd;
        }
    }
}

/* ---- the stack behind a shading point (sl_dual_stack, docs/volume.md "The stack behind") ---- */

/* R_N, T_N of N identical layers by the adding equations, one layer at a time (independent of
 * dual.c's Kubelka-Munk closed form): R' = r + t^2 R / (1 - r R), T' = t T / (1 - r R). */
static void stack_iterate(double r, double t, int N, double *R, double *T) {
    double Rn = 0.0, Tn = 1.0;
    for (int k = 0; k < N; k++) {
        double d = 1.0 - r * Rn;
        Rn = r + t * t * Rn / d;
        Tn = t * Tn / d;
    }
    *R = Rn, *T = Tn;
}

/* The closed forms against the layer-by-layer adding at N = 0..40 within 1e-9 (both are exact;
 * the rest is rounding), on absorbing, lossless (r + t = 1: the b -> 0 limit), nearly lossless
 * (b tiny: cancellation), t = 0 (kappa = inf) and tiny-r stacks; real N lies between its integer
 * neighbours; N -> inf gives R_inf (checked above by its own iteration) and T = 0. */
TEST(dual_stack_closed_forms_match_adding) {
    const double rt[][2] = {{0.1, 0.8}, {0.2574, 0.7426}, {0.3, 0.7 - 1e-7}, {0.05, 0.5},
                            {0.4, 0.0}, {1e-6, 0.9},      {0.2617, 0.7383}};
    for (int i = 0; i < 7; i++) {
        sl_dual_stack s;
        sl_dual_stack_init(rt[i][0], rt[i][1], 0.3, &s);
        for (int N = 0; N <= 40; N++) {
            double R, T;
            stack_iterate(rt[i][0], rt[i][1], N, &R, &T);
            CHECK_NEAR(sl_dual_stack_reflectance_n(&s, N), R, 1e-9);
            CHECK_NEAR(sl_dual_stack_transmittance_n(&s, N), T, 1e-9);
            if (N) {
                double Rh = sl_dual_stack_reflectance_n(&s, N - 0.5),
                       Th = sl_dual_stack_transmittance_n(&s, N - 0.5), R0, T0;
                stack_iterate(rt[i][0], rt[i][1], N - 1, &R0, &T0);
                CHECK(Rh >= R0 - 1e-12 && Rh <= R + 1e-12);
                CHECK(Th <= T0 + 1e-12 && Th >= T - 1e-12);
            }
        }
        CHECK_NEAR(sl_dual_stack_reflectance_n(&s, INFINITY),
                   sl_dual_stack_reflectance(rt[i][0], rt[i][1]), 1e-9);
        CHECK_NEAR(sl_dual_stack_transmittance_n(&s, INFINITY), 0.0, 1e-12);
        CHECK(isfinite(sl_dual_stack_reflectance_n(&s, 1e300)));
    }
}

/* The light at a fiber between m layers in front and n behind: the front stack's transmission
 * and every round trip between the two stacks, T_m sum_k (R_m R_n)^k, summed here term by term,
 * relative to the march's t^m. No layer in front: 1 whatever is behind; nothing behind: T_m / t^m
 * (> 1: the front stack's own interreflections). A white furnace's deep point (lossless, an
 * infinite stack behind) receives the whole flux: factor 1 / t^m. */
TEST(dual_stack_incident_factor_series) {
    const double rt[][2] = {{0.1, 0.8}, {0.2574, 0.7426}, {0.05, 0.5}};
    for (int i = 0; i < 3; i++) {
        sl_dual_stack s;
        sl_dual_stack_init(rt[i][0], rt[i][1], 0.3, &s);
        for (int m = 0; m <= 12; m += 3)
            for (int n = 0; n <= 12; n += 4) {
                double Rm, Tm, Rn, Tn, sum = 0.0, term = 1.0;
                stack_iterate(rt[i][0], rt[i][1], m, &Rm, &Tm);
                stack_iterate(rt[i][0], rt[i][1], n, &Rn, &Tn);
                for (int k = 0; k < 100000 && term > 1e-17; k++, term *= Rm * Rn)
                    sum += term;
                double want = Tm * sum / pow(rt[i][1], m);
                CHECK_REL(sl_dual_stack_incident_factor(&s, m, n), want, 1e-9);
            }
        CHECK_NEAR(sl_dual_stack_incident_factor(&s, 0.0, 50.0), 1.0, 1e-12);
    }
    sl_dual_stack w;
    sl_dual_stack_init(0.2574, 0.7426, 0.42, &w);
    CHECK_REL(sl_dual_stack_incident_factor(&w, 6.0, INFINITY), 1.0 / pow(0.7426, 6.0), 1e-9);
    CHECK(sl_dual_stack_incident_factor(&w, 1e6, 3.0) <= SL_DUAL_STACK_MAX_FACTOR);
}

/* The local backscattering's weight: nothing behind, nothing back (0); a semi-infinite stack,
 * (R_inf - r) / A_b; one layer behind, (R_2 - r) / A_b with R_2 = r + t^2 r / (1 - r^2); no
 * tabulated A_b: 1 (the tables' value stands). */
TEST(dual_stack_local_factor_limits) {
    const double r = 0.1, t = 0.8, Ab = 0.07;
    sl_dual_stack s;
    sl_dual_stack_init(r, t, Ab, &s);
    CHECK_NEAR(sl_dual_stack_local_factor(&s, 0.0), 0.0, 1e-15);
    CHECK_REL(sl_dual_stack_local_factor(&s, 1.0), (t * t * r / (1 - r * r)) / Ab, 1e-9);
    CHECK_REL(sl_dual_stack_local_factor(&s, INFINITY), (sl_dual_stack_reflectance(r, t) - r) / Ab,
              1e-9);
    double prev = 0.0;
    for (double n = 0.25; n < 64; n *= 2) {
        double f = sl_dual_stack_local_factor(&s, n);
        CHECK(f > prev);
        prev = f;
    }
    sl_dual_stack z;
    sl_dual_stack_init(r, t, 0.0, &z);
    CHECK_NEAR(sl_dual_stack_local_factor(&z, 5.0), 1.0, 0);
}
