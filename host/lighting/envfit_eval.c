/* envfit_eval.c: the fit objective on one pyramid level and its exact (analytic) gradient.
 *
 * A map pixel holds the mean radiance over its area, so a lobe is compared with its mean over
 * each pixel, B_j(p) = (1/Omega_p) integral_pixel G_j, not with its value at the pixel centre
 * (a sun one pixel wide is then represented by a narrow lobe of the right power instead of a
 * pixel-wide Gaussian whose tails add ~30 % of power). Two forms, both preserving the lobe's
 * integral (sum_p Omega_p B_j(p) = integral G_j):
 *  - narrow lobes (lambda < EFL_NARROW pixels): G ~ exp(-(dth^2 + s^2 dph^2) / lambda^2) near
 *    its centre (s = sin th_mu), integrated over the pixel's [th0, th1] x [ph0, ph1] with erf:
 *    B = Theta * P / Omega_p, Theta = integral_th0^th1 e^{-(th-th_mu)^2/l^2} dth and
 *    P = s integral_ph0^ph1 e^{-s^2 (ph-ph_mu)^2/l^2} dph (sin th ~ s inside the lobe);
 *  - broad lobes: the box filter widens the Gaussian's variance by h^2/12 per axis
 *    (h = pi / height), i.e. lambda_e^2 = lambda^2 + h^2/6 at amplitude A = lambda^2/lambda_e^2;
 *    B = A exp(a_e (omega . mu - 1)), a_e = 2 / lambda_e^2, evaluated at the pixel centre.
 * At the switch (lambda = EFL_NARROW h) the two forms differ by ~1e-4 of the lobe's peak.
 *
 * F = 1/2 sum_p Omega_p |sum_j c_j B_j(p) - L_p|^2. Gradient per lobe (weights c, tangent-plane
 * direction steps u1, u2 along t1, t2, s = ln lambda), broad form:
 *   dB/du_i = B a_e (omega . t_i),  dB/ds = B (2 (1 - A) - 2 A a_e (omega . mu - 1));
 * narrow form: derivatives of the erf differences (below), chained through
 *   d th_mu/du_i = -t_i.y / s,  d ph_mu/du_i = (mu.x t_i.z - mu.z t_i.x) / s^2.
 * Rows are split into fixed blocks (efl_parallel); per-block sums are reduced in block order. */
#include "lighting/envfit_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NBLOCKS_MAX 64
#define SQRT_PI 1.7724538509055160273

typedef struct lobe_pre {
    double mu[3], t1[3], t2[3], c[3];
    double lambda;
    double a; /* broad: a_e; the support uses it */
    double A; /* broad: amplitude lambda^2 / lambda_e^2 */
    int narrow;
    double th, ph, s; /* narrow: centre angles, sin th */
    double dth_du[2], dph_du[2];
} lobe_pre;

typedef struct eval_job {
    efl_eval *ev;
    const lobe_pre *pre;
    int n, nblocks;
    double *part; /* per block: 1 (objective) or 6n (gradient) doubles */
} eval_job;

static double wrap_pi(double x) {
    while (x > M_PI)
        x -= 2 * M_PI;
    while (x <= -M_PI)
        x += 2 * M_PI;
    return x;
}

void efl_widened(const efl_level *lv, double lambda, double *A, double *a_e) {
    double h = M_PI / lv->h, l2 = lambda * lambda, k = h * h / 6;
    *A = l2 / (l2 + k);
    *a_e = 2.0 / (l2 + k);
}

static void prepare(const efl_level *lv, const sl_lobe *lobes, int n, lobe_pre *pre) {
    double h = M_PI / lv->h;
    for (int j = 0; j < n; j++) {
        lobe_pre *p = &pre[j];
        memset(p, 0, sizeof *p);
        memcpy(p->mu, lobes[j].dir, sizeof p->mu);
        efl_tangent(p->mu, p->t1, p->t2);
        memcpy(p->c, lobes[j].rgb, sizeof p->c);
        p->lambda = lobes[j].lambda;
        if (!(p->lambda > 0)) { /* a directional light has no radiance image: leave it out */
            p->lambda = 1;
            p->c[0] = p->c[1] = p->c[2] = 0;
        }
        efl_widened(lv, p->lambda, &p->A, &p->a);
        p->s = sqrt(p->mu[0] * p->mu[0] + p->mu[2] * p->mu[2]);
        /* The separable erf form needs the lobe clear of the poles (s >> lambda). */
        p->narrow = p->lambda < EFL_NARROW * h && p->s > 8 * p->lambda + 2 * h;
        if (p->narrow) {
            p->th = acos(fmax(-1.0, fmin(1.0, p->mu[1])));
            p->ph = atan2(p->mu[0], -p->mu[2]);
            const double *t[2] = {p->t1, p->t2};
            for (int i = 0; i < 2; i++) {
                p->dth_du[i] = -t[i][1] / p->s;
                p->dph_du[i] = (p->mu[0] * t[i][2] - p->mu[2] * t[i][0]) / (p->s * p->s);
            }
        }
    }
}

static int nblocks_for(const efl_level *lv) {
    return lv->h < NBLOCKS_MAX ? lv->h : NBLOCKS_MAX;
}

/* Narrow lobe, row y: Theta and its derivatives with respect to th_mu and ln lambda. */
typedef struct row_erf {
    double T, dT_dth, dT_dl;
} row_erf;

static void narrow_row(const efl_level *lv, const lobe_pre *p, int y, row_erf *r) {
    double th0 = M_PI * y / lv->h, th1 = M_PI * (y + 1) / lv->h, l = p->lambda;
    double b0 = th0 - p->th, b1 = th1 - p->th;
    double e0 = exp(-b0 * b0 / (l * l)), e1 = exp(-b1 * b1 / (l * l));
    r->T = 0.5 * l * SQRT_PI * (erf(b1 / l) - erf(b0 / l));
    r->dT_dth = -(e1 - e0);
    r->dT_dl = r->T - (b1 * e1 - b0 * e0);
}

/* Narrow lobe: the row span in which it matters (6 lambda + one pixel around its centre). */
static void narrow_span(const efl_level *lv, const lobe_pre *p, int *y0, int *y1, int *x0,
                        int *nx) {
    double h = M_PI / lv->h, R = 6 * p->lambda + h;
    *y0 = (int)floor((p->th - R) / h);
    *y1 = (int)ceil((p->th + R) / h);
    if (*y0 < 0) *y0 = 0;
    if (*y1 > lv->h - 1) *y1 = lv->h - 1;
    double Rp = (6 * p->lambda) / p->s + 2 * M_PI / lv->w;
    double xc = (p->ph + M_PI) * lv->w / (2 * M_PI) - 0.5, half = Rp * lv->w / (2 * M_PI);
    long a0 = (long)floor(xc - half), a1 = (long)ceil(xc + half);
    if (a1 - a0 + 1 >= lv->w) {
        *x0 = 0;
        *nx = lv->w;
        return;
    }
    long m = a0 % lv->w;
    *x0 = (int)(m < 0 ? m + lv->w : m);
    *nx = (int)(a1 - a0 + 1);
}

/* Narrow lobe, pixel x: P and its derivatives with respect to th_mu (via s), ph_mu, ln lambda. */
typedef struct col_erf {
    double P, dP_dth, dP_dph, dP_dl;
} col_erf;

static void narrow_col(const efl_level *lv, const lobe_pre *p, int x, col_erf *c) {
    double dph = 2 * M_PI / lv->w, l = p->lambda, s = p->s;
    double d = wrap_pi(2 * M_PI * (x + 0.5) / lv->w - M_PI - p->ph);
    double f0 = d - 0.5 * dph, f1 = d + 0.5 * dph;
    double e0 = exp(-s * s * f0 * f0 / (l * l)), e1 = exp(-s * s * f1 * f1 / (l * l));
    c->P = 0.5 * l * SQRT_PI * (erf(s * f1 / l) - erf(s * f0 / l));
    double ds = f1 * e1 - f0 * e0; /* dP/ds */
    c->dP_dth = ds * (p->mu[1]);   /* ds/dth_mu = cos th_mu = mu.y */
    c->dP_dph = -s * (e1 - e0);
    c->dP_dl = c->P - s * ds;
}

static void objective_block(void *ctx, int b) {
    eval_job *jb = ctx;
    const efl_eval *ev = jb->ev;
    const efl_level *lv = ev->lv;
    int w = lv->w, y0 = (int)((long)b * lv->h / jb->nblocks),
        y1 = (int)((long)(b + 1) * lv->h / jb->nblocks);
    double F = 0;
    for (int y = y0; y < y1; y++) {
        double *r = ev->res + (size_t)y * w * 3;
        const float *L = lv->rgb + (size_t)y * w * 3;
        if (ev->bg) {
            const double *g = ev->bg + (size_t)y * w * 3;
            for (int i = 0; i < w * 3; i++)
                r[i] = g[i] - (double)L[i];
        } else {
            for (int i = 0; i < w * 3; i++)
                r[i] = -(double)L[i];
        }
        double ct = lv->ct[y], st = lv->st[y];
        for (int j = 0; j < jb->n; j++) {
            const lobe_pre *p = &jb->pre[j];
            if (p->c[0] == 0 && p->c[1] == 0 && p->c[2] == 0) continue;
            if (p->narrow) {
                int ya, yb, x0, nx;
                narrow_span(lv, p, &ya, &yb, &x0, &nx);
                if (y < ya || y > yb) continue;
                row_erf re;
                narrow_row(lv, p, y, &re);
                double f = re.T / lv->om[y];
                for (int i = 0, x = x0; i < nx; i++, x = (x + 1 == w ? 0 : x + 1)) {
                    col_erf ce;
                    narrow_col(lv, p, x, &ce);
                    double B = f * ce.P;
                    r[x * 3 + 0] += p->c[0] * B;
                    r[x * 3 + 1] += p->c[1] * B;
                    r[x * 3 + 2] += p->c[2] * B;
                }
                continue;
            }
            int x0, nx;
            efl_row_span(lv, y, p->mu, p->a, ev->cut, &x0, &nx);
            double Am = ct * p->mu[1] - 1.0;
            double c0 = p->c[0] * p->A, c1 = p->c[1] * p->A, c2 = p->c[2] * p->A;
            for (int i = 0, x = x0; i < nx; i++, x = (x + 1 == w ? 0 : x + 1)) {
                double d = Am + st * (lv->sp[x] * p->mu[0] - lv->cp[x] * p->mu[2]);
                double G = exp(p->a * d);
                r[x * 3 + 0] += c0 * G;
                r[x * 3 + 1] += c1 * G;
                r[x * 3 + 2] += c2 * G;
            }
        }
        double row = 0;
        for (int i = 0; i < w * 3; i++)
            row += r[i] * r[i];
        F += row * lv->om[y];
    }
    jb->part[b] = 0.5 * F;
}

double efl_objective(efl_eval *ev, const sl_lobe *lobes, int n) {
    lobe_pre *pre = sl_malloc(sizeof *pre * (size_t)(n ? n : 1));
    prepare(ev->lv, lobes, n, pre);
    int nb = nblocks_for(ev->lv);
    double part[NBLOCKS_MAX];
    eval_job jb = {ev, pre, n, nb, part};
    efl_parallel(ev->threads, nb, objective_block, &jb);
    double F = 0;
    for (int b = 0; b < nb; b++)
        F += part[b];
    free(pre);
    return F;
}

static void gradient_block(void *ctx, int b) {
    eval_job *jb = ctx;
    const efl_eval *ev = jb->ev;
    const efl_level *lv = ev->lv;
    int w = lv->w, n = jb->n, y0 = (int)((long)b * lv->h / jb->nblocks),
        y1 = (int)((long)(b + 1) * lv->h / jb->nblocks);
    double *g = jb->part + (size_t)b * 6 * n;
    memset(g, 0, sizeof(double) * 6 * (size_t)n);
    for (int y = y0; y < y1; y++) {
        const double *r = ev->res + (size_t)y * w * 3;
        double ct = lv->ct[y], st = lv->st[y], om = lv->om[y];
        for (int j = 0; j < n; j++) {
            const lobe_pre *p = &jb->pre[j];
            double *gj = g + 6 * j;
            if (p->narrow) {
                int ya, yb, x0, nx;
                narrow_span(lv, p, &ya, &yb, &x0, &nx);
                if (y < ya || y > yb) continue;
                row_erf re;
                narrow_row(lv, p, y, &re);
                /* om * B = T * P: the solid angle cancels. */
                double s0 = 0, s1 = 0, s2 = 0, sth = 0, sph = 0, sl = 0;
                for (int i = 0, x = x0; i < nx; i++, x = (x + 1 == w ? 0 : x + 1)) {
                    col_erf ce;
                    narrow_col(lv, p, x, &ce);
                    const double *rr = r + x * 3;
                    double wr = rr[0] * p->c[0] + rr[1] * p->c[1] + rr[2] * p->c[2];
                    double B = re.T * ce.P;
                    s0 += rr[0] * B;
                    s1 += rr[1] * B;
                    s2 += rr[2] * B;
                    sth += wr * (re.dT_dth * ce.P + re.T * ce.dP_dth);
                    sph += wr * re.T * ce.dP_dph;
                    sl += wr * (re.dT_dl * ce.P + re.T * ce.dP_dl);
                }
                gj[0] += s0;
                gj[1] += s1;
                gj[2] += s2;
                gj[3] += sth * p->dth_du[0] + sph * p->dph_du[0];
                gj[4] += sth * p->dth_du[1] + sph * p->dph_du[1];
                gj[5] += sl;
                continue;
            }
            int x0, nx;
            efl_row_span(lv, y, p->mu, p->a, ev->cut, &x0, &nx);
            if (!nx) continue;
            double Am = ct * p->mu[1] - 1.0, B1 = ct * p->t1[1], B2 = ct * p->t2[1];
            double s0 = 0, s1 = 0, s2 = 0, su1 = 0, su2 = 0, ss = 0, sw = 0;
            for (int i = 0, x = x0; i < nx; i++, x = (x + 1 == w ? 0 : x + 1)) {
                double sp = lv->sp[x], cp = lv->cp[x];
                double d = Am + st * (sp * p->mu[0] - cp * p->mu[2]);
                double G = exp(p->a * d);
                const double *rr = r + x * 3;
                s0 += rr[0] * G;
                s1 += rr[1] * G;
                s2 += rr[2] * G;
                double wG = (rr[0] * p->c[0] + rr[1] * p->c[1] + rr[2] * p->c[2]) * G;
                su1 += wG * (B1 + st * (sp * p->t1[0] - cp * p->t1[2]));
                su2 += wG * (B2 + st * (sp * p->t2[0] - cp * p->t2[2]));
                ss += wG * d;
                sw += wG;
            }
            double oA = om * p->A;
            gj[0] += oA * s0;
            gj[1] += oA * s1;
            gj[2] += oA * s2;
            gj[3] += oA * p->a * su1;
            gj[4] += oA * p->a * su2;
            gj[5] += oA * (2 * (1 - p->A) * sw - 2 * p->A * p->a * ss);
        }
    }
}

void efl_gradient(efl_eval *ev, const sl_lobe *lobes, int n, double *grad) {
    lobe_pre *pre = sl_malloc(sizeof *pre * (size_t)(n ? n : 1));
    prepare(ev->lv, lobes, n, pre);
    int nb = nblocks_for(ev->lv);
    double *part = sl_malloc(sizeof(double) * 6 * (size_t)n * nb + 1);
    eval_job jb = {ev, pre, n, nb, part};
    efl_parallel(ev->threads, nb, gradient_block, &jb);
    memset(grad, 0, sizeof(double) * 6 * (size_t)n);
    for (int b = 0; b < nb; b++)
        for (int i = 0; i < 6 * n; i++)
            grad[i] += part[(size_t)b * 6 * n + i];
    free(part);
    free(pre);
}
