/* envfit_lm.c: bounded Levenberg-Marquardt refinement of all lobe parameters on one level.
 *
 * Unknowns per lobe: rgb weights c (>= 0), direction (tangent-plane step u1, u2, then
 * renormalised) and s = ln lambda (in [ln lam_lo, ln lam_hi]). The gradient is the exact
 * gradient of the pixel objective (envfit_eval.c); the Gauss-Newton matrix J^T Omega J is
 * replaced by its continuous limit, the closed-form L2(sphere) products of the Jacobian columns
 * (envfit_gram.c). That matrix only steers the steps: the objective and its gradient, hence the
 * fixed point, are the pixel ones, and every step is accepted only if the pixel objective drops.
 * Bounds: variables at a bound whose gradient points outward are held (projected Newton,
 * Bertsekas 1982); the remaining step is projected back into the box. Damping follows
 * Nielsen's gain-ratio rule. */
#include "lighting/envfit_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Gauss-Newton matrix (P x P, P = 6n, row-major) at the given lobes, for the pixel model of
 * level lv. Each lobe is its widened Gaussian A exp(x_e . omega - |x_e|), x_e = a_e mu
 * (envfit_eval.c); every Jacobian column is A (b0 G_e + b . dG_e/dx_e) with
 *   weight c: b0 = 1, b = 0;  u_i: b = a_e t_i;  s = ln lambda: b0 = 2 (1 - A), b = -2 a_e A mu
 * (geometry columns are further scaled by the channel's weight), so every entry is
 * A_j A_k B_j^T K B_k with K = [[I, dI/dx_k], [dI/dx_j, d2I/dx_j dx_k]] (envfit_gram.c). */
static void build_gn(const efl_level *lv, const sl_lobe *lobes, int n, double *H) {
    int P = 6 * n;
    memset(H, 0, sizeof(double) * (size_t)P * P);
    double(*Bm)[4][3] = sl_malloc(sizeof *Bm * (size_t)n); /* Bm[j][comp][u1,u2,s] */
    double(*x)[3] = sl_malloc(sizeof *x * (size_t)n);
    double *Am = sl_malloc(sizeof(double) * (size_t)n);
    for (int j = 0; j < n; j++) {
        double t1[3], t2[3], A, a;
        const double *mu = lobes[j].dir;
        efl_tangent(mu, t1, t2);
        efl_widened(lv, lobes[j].lambda, &A, &a);
        Am[j] = A;
        Bm[j][0][0] = Bm[j][0][1] = 0;
        Bm[j][0][2] = 2 * (1 - A);
        for (int r = 0; r < 3; r++) {
            Bm[j][1 + r][0] = a * t1[r];
            Bm[j][1 + r][1] = a * t2[r];
            Bm[j][1 + r][2] = -2.0 * a * A * mu[r];
            x[j][r] = a * mu[r];
        }
    }
    for (int j = 0; j < n; j++) {
        for (int k = j; k < n; k++) {
            efl_pair pr;
            efl_sg_pair(x[j], x[k], 1, &pr);
            if (pr.I == 0) continue;
            double K[4][4], KB[4][3], sc = Am[j] * Am[k];
            K[0][0] = pr.I;
            for (int r = 0; r < 3; r++) {
                K[0][1 + r] = pr.dI_dx2[r];
                K[1 + r][0] = pr.dI_dx1[r];
                for (int q = 0; q < 3; q++)
                    K[1 + r][1 + q] = pr.M[r][q];
            }
            for (int r = 0; r < 4; r++)
                for (int q = 0; q < 3; q++) {
                    KB[r][q] = 0;
                    for (int m = 0; m < 4; m++)
                        KB[r][q] += K[r][m] * Bm[k][m][q];
                }
            double Pk[3], Pj[3], Q[3][3];
            for (int al = 0; al < 3; al++) {
                Pk[al] = KB[0][al]; /* int G_j * dG_k/d geo_al */
                Pj[al] = 0;         /* int dG_j/d geo_al * G_k */
                for (int m = 0; m < 4; m++)
                    Pj[al] += Bm[j][m][al] * K[m][0];
                for (int be = 0; be < 3; be++) {
                    Q[al][be] = 0;
                    for (int m = 0; m < 4; m++)
                        Q[al][be] += Bm[j][m][al] * KB[m][be];
                }
            }
            const double *cj = lobes[j].rgb, *ck = lobes[k].rgb;
            double cc = cj[0] * ck[0] + cj[1] * ck[1] + cj[2] * ck[2];
            double blk[6][6] = {{0}};
            for (int ch = 0; ch < 3; ch++) {
                blk[ch][ch] = sc * pr.I;
                for (int be = 0; be < 3; be++) {
                    blk[ch][3 + be] = sc * ck[ch] * Pk[be];
                    blk[3 + be][ch] = sc * cj[ch] * Pj[be];
                }
            }
            for (int al = 0; al < 3; al++)
                for (int be = 0; be < 3; be++)
                    blk[3 + al][3 + be] = sc * cc * Q[al][be];
            for (int r = 0; r < 6; r++)
                for (int c = 0; c < 6; c++) {
                    H[(size_t)(6 * j + r) * P + 6 * k + c] = blk[r][c];
                    H[(size_t)(6 * k + c) * P + 6 * j + r] = blk[r][c];
                }
        }
    }
    free(Bm);
    free(x);
    free(Am);
}

/* In-place Cholesky of the m x m matrix A (row-major); returns -1 if not positive definite. */
static int cholesky(double *A, int m) {
    for (int j = 0; j < m; j++) {
        double s = A[(size_t)j * m + j];
        for (int k = 0; k < j; k++)
            s -= A[(size_t)j * m + k] * A[(size_t)j * m + k];
        if (!(s > 0)) return -1;
        double d = sqrt(s);
        A[(size_t)j * m + j] = d;
        for (int i = j + 1; i < m; i++) {
            double t = A[(size_t)i * m + j];
            const double *ai = A + (size_t)i * m, *aj = A + (size_t)j * m;
            for (int k = 0; k < j; k++)
                t -= ai[k] * aj[k];
            A[(size_t)i * m + j] = t / d;
        }
    }
    return 0;
}

static void chol_solve(const double *A, int m, double *b) {
    for (int i = 0; i < m; i++) {
        double t = b[i];
        for (int k = 0; k < i; k++)
            t -= A[(size_t)i * m + k] * b[k];
        b[i] = t / A[(size_t)i * m + i];
    }
    for (int i = m - 1; i >= 0; i--) {
        double t = b[i];
        for (int k = i + 1; k < m; k++)
            t -= A[(size_t)k * m + i] * b[k];
        b[i] = t / A[(size_t)i * m + i];
    }
}

/* Applies step d (P entries) to lobes -> out, projecting onto the bounds; d is overwritten
 * with the step actually taken (for the predicted decrease). */
static void apply_step(const sl_lobe *lobes, int n, double *d, double s_lo, double s_hi,
                       sl_lobe *out) {
    for (int j = 0; j < n; j++) {
        const sl_lobe *L = &lobes[j];
        sl_lobe *o = &out[j];
        double *dj = d + 6 * j;
        for (int ch = 0; ch < 3; ch++) {
            double c = L->rgb[ch] + dj[ch];
            if (c < 0) c = 0;
            dj[ch] = c - L->rgb[ch];
            o->rgb[ch] = c;
        }
        double t1[3], t2[3], m[3];
        efl_tangent(L->dir, t1, t2);
        for (int k = 0; k < 3; k++)
            m[k] = L->dir[k] + dj[3] * t1[k] + dj[4] * t2[k];
        double nm = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
        for (int k = 0; k < 3; k++)
            o->dir[k] = m[k] / nm;
        double s = log(L->lambda), s2 = s + dj[5];
        if (s2 < s_lo) s2 = s_lo;
        if (s2 > s_hi) s2 = s_hi;
        dj[5] = s2 - s;
        o->lambda = exp(s2);
    }
}

double efl_lm(efl_eval *ev, sl_lobe *lobes, int n, const efl_lm_opts *o, int *iters,
              sl_progress *prog, double prog_lo, double prog_hi) {
    int P = 6 * n;
    double s_lo = log(o->lam_lo), s_hi = log(o->lam_hi);
    /* Start inside the bounds. */
    for (int j = 0; j < n; j++) {
        if (lobes[j].lambda < o->lam_lo) lobes[j].lambda = o->lam_lo;
        if (lobes[j].lambda > o->lam_hi) lobes[j].lambda = o->lam_hi;
    }
    double *H = sl_malloc(sizeof(double) * (size_t)P * P);
    double *A = sl_malloc(sizeof(double) * (size_t)P * P);
    double *g = sl_malloc(sizeof(double) * P), *d = sl_malloc(sizeof(double) * P);
    double *rhs = sl_malloc(sizeof(double) * P), *Hd = sl_malloc(sizeof(double) * P);
    int *freev = sl_malloc(sizeof(int) * P);
    sl_lobe *trial = sl_malloc(sizeof *trial * (size_t)n);
    double F = efl_objective(ev, lobes, n);
    efl_gradient(ev, lobes, n, g);
    double damp = 1e-3, nu = 2;
    int it = 0, small = 0;
    for (; it < o->max_iter; it++) {
        build_gn(ev->lv, lobes, n, H);
        /* Free variables: not held at a bound by an outward gradient; a lobe with no weight has
         * no say over its geometry (its Jacobian columns vanish). */
        int m = 0;
        for (int j = 0; j < n; j++) {
            int dead = lobes[j].rgb[0] <= 0 && lobes[j].rgb[1] <= 0 && lobes[j].rgb[2] <= 0;
            double s = log(lobes[j].lambda);
            for (int v = 0; v < 6; v++) {
                int i = 6 * j + v;
                int held = 0;
                if (v < 3)
                    held = lobes[j].rgb[v] <= 0 && g[i] > 0;
                else if (dead)
                    held = 1;
                else if (v == 5)
                    held = (s <= s_lo + 1e-12 && g[i] > 0) || (s >= s_hi - 1e-12 && g[i] < 0);
                if (!held && H[(size_t)i * P + i] > 0) freev[m++] = i;
            }
        }
        if (m == 0) break;
        double F_old = F;
        int accepted = 0;
        for (int attempt = 0; attempt < 12 && !accepted; attempt++) {
            for (int a = 0; a < m; a++) {
                for (int b = 0; b < m; b++)
                    A[(size_t)a * m + b] = H[(size_t)freev[a] * P + freev[b]];
                A[(size_t)a * m + a] *= 1.0 + damp;
                rhs[a] = -g[freev[a]];
            }
            if (cholesky(A, m)) {
                damp *= nu;
                nu *= 2;
                continue;
            }
            chol_solve(A, m, rhs);
            memset(d, 0, sizeof(double) * P);
            for (int a = 0; a < m; a++)
                d[freev[a]] = rhs[a];
            apply_step(lobes, n, d, s_lo, s_hi, trial);
            /* Predicted decrease of the quadratic model for the step actually taken. */
            double pred = 0;
            for (int i = 0; i < P; i++) {
                if (d[i] == 0) {
                    Hd[i] = 0;
                    continue;
                }
                double t = 0;
                const double *hr = H + (size_t)i * P;
                for (int k = 0; k < P; k++)
                    t += hr[k] * d[k];
                Hd[i] = t;
            }
            for (int i = 0; i < P; i++)
                pred -= d[i] * (g[i] + 0.5 * Hd[i]);
            double F_new = efl_objective(ev, trial, n);
            if (F_new < F && isfinite(F_new)) {
                double rho = pred > 0 ? (F - F_new) / pred : 0.5;
                double t = 2 * rho - 1;
                double f = 1 - t * t * t;
                damp *= f > 1.0 / 3 ? f : 1.0 / 3;
                if (damp < 1e-9) damp = 1e-9;
                nu = 2;
                memcpy(lobes, trial, sizeof *trial * (size_t)n);
                F = F_new;
                accepted = 1;
            } else {
                damp *= nu;
                nu *= 2;
            }
        }
        if (!accepted) {
            /* The residual buffer holds the last rejected trial: restore it. */
            efl_objective(ev, lobes, n);
            break;
        }
        efl_gradient(ev, lobes, n, g);
        if (prog) sl_progress_update(prog, prog_lo + (prog_hi - prog_lo) * (it + 1) / o->max_iter);
        /* Converged after three steps in a row that gain almost nothing. */
        small = F_old - F <= o->rel_tol * F_old ? small + 1 : 0;
        if (small >= 3) {
            it++;
            break;
        }
    }
    if (iters) *iters = it;
    free(H);
    free(A);
    free(g);
    free(d);
    free(rhs);
    free(Hd);
    free(freev);
    free(trial);
    return F;
}
