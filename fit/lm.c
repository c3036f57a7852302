/* lm.c: the Levenberg-Marquardt iteration of the "lm" method, on the
 * small normal matrix.
 *
 * A fit has a few parameters (2 to about 10) and hundreds of rows, so one
 * step is cheap once J is known: the step h solves
 *     (J^T J + mu D^2) h = -J^T r
 * by Cholesky of the p x p matrix, D the largest column norms of J seen so
 * far (More's scaling, as GSL's gsl_multifit_nlinear_scale_more), and mu
 * follows Nielsen's rule (Madsen, Nielsen and Tingleff, "Methods for
 * non-linear least squares problems", 2004, eq. 3.14; GSL's lm.c does the
 * same): with rho the actual over the predicted decrease of the cost, an
 * accepted step (rho > 0) sets mu *= max(1/3, 1 - (2 rho - 1)^3), nu = 2;
 * a rejected one mu *= nu, nu *= 2.  mu starts at 1e-3 max_k (J^T J)_kk /
 * D_k^2.  After FIT_LM_MAX_REJECT rejections in a row the iteration
 * reports GSL_ENOPROG, as GSL's trust region does.
 *
 * Unlike GSL's driver it keeps no vectors it does not need, evaluates the
 * Jacobian only at accepted points (where the model evaluation of the
 * residuals is reused, problem.c caching it by x) and allocates nothing:
 * the workspace is part of fit_work. */
#include <math.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "fit.h"

/* Cholesky solve of (A + mu diag(D2)) h = -g, p x p, A symmetric (lower
 * triangle used); L is scratch.  0 when not positive definite. */
static int
damped_solve(size_t p, const double *A, const double *D2, double mu, const double *g,
             double *L, double *h)
{
    size_t k, l, q;

    for (k = 0; k < p; k++)
        for (l = 0; l <= k; l++) {
            double s = A[k * p + l] + (k == l ? mu * D2[k] : 0.0);
            for (q = 0; q < l; q++)
                s -= L[k * p + q] * L[l * p + q];
            if (k == l) {
                if (!(s > 0))
                    return 0;
                L[k * p + k] = sqrt(s);
            } else {
                L[k * p + l] = s / L[l * p + l];
            }
        }
    for (k = 0; k < p; k++) {
        double s = -g[k];
        for (q = 0; q < k; q++)
            s -= L[k * p + q] * h[q];
        h[k] = s / L[k * p + k];
    }
    for (k = p; k-- > 0;) {
        double s = h[k];
        for (q = k + 1; q < p; q++)
            s -= L[q * p + k] * h[q];
        h[k] = s / L[k * p + k];
    }
    return 1;
}

/* The sums of the normal equations over rows [0, n) of J (row stride
 * tda): A += J^T J (lower triangle), g += J^T r, big = max |J_ik| per
 * column; returns |r|^2.  P > 0: a compile-time column count (the
 * constant lets the compiler keep the sums in registers); P = 0: p. */
LF_KERNEL double
ne_sums(const double *J, size_t tda, const double *r, size_t n, size_t P, size_t p,
        double *A, double *g, double *big)
{
    enum { PK = 6 };
    double a[PK * PK] = { 0 }, gk[PK] = { 0 }, bk[PK] = { 0 }, ss = 0.0;
    /* a constant P: the sums in the local arrays, else straight in A, g, big */
    const size_t m = P ? P : p, stride = P ? (size_t) PK : p;
    double *sa = P ? a : A, *sg = P ? gk : g, *sb = P ? bk : big;
    size_t i, k, l;

    for (i = 0; i < n; i++) {
        const double *row = J + i * tda, ri = r[i];
        ss += ri * ri;
        for (k = 0; k < m; k++) {
            const double v = fabs(row[k]);
            sg[k] += row[k] * ri;
            /* a NaN leaves the maximum (as lf_fmax would); it reaches g */
            sb[k] = v > sb[k] ? v : sb[k];
            for (l = 0; l <= k; l++)
                sa[k * stride + l] += row[k] * row[l];
        }
    }
    for (k = 0; k < P; k++) {
        g[k] = gk[k];
        big[k] = bk[k];
        for (l = 0; l <= k; l++)
            A[k * p + l] = a[k * PK + l];
    }
    return ss;
}

/* A = J^T J (lower triangle), g = J^T r, colmax = max |J_ik| per column
 * and cost = |r|^2 / 2 at the current point; D2 grows to the squared
 * column norms. */
static void
normal_equations(lf_fit *f)
{
    fit_lm *lm = &f->w.lm;
    const gsl_matrix *J = lm->J;
    const size_t n = J->size1, p = J->size2;
    const double *r = lm->r->data;
    size_t k;
    double ss;

    memset(lm->A, 0, p * p * sizeof *lm->A);
    memset(lm->g, 0, p * sizeof *lm->g);
    memset(lm->colmax, 0, p * sizeof *lm->colmax);
    switch (p) {
    case 1: ss = ne_sums(J->data, J->tda, r, n, 1, p, lm->A, lm->g, lm->colmax); break;
    case 2: ss = ne_sums(J->data, J->tda, r, n, 2, p, lm->A, lm->g, lm->colmax); break;
    case 3: ss = ne_sums(J->data, J->tda, r, n, 3, p, lm->A, lm->g, lm->colmax); break;
    case 4: ss = ne_sums(J->data, J->tda, r, n, 4, p, lm->A, lm->g, lm->colmax); break;
    case 5: ss = ne_sums(J->data, J->tda, r, n, 5, p, lm->A, lm->g, lm->colmax); break;
    case 6: ss = ne_sums(J->data, J->tda, r, n, 6, p, lm->A, lm->g, lm->colmax); break;
    default: ss = ne_sums(J->data, J->tda, r, n, 0, p, lm->A, lm->g, lm->colmax); break;
    }
    lm->cost = 0.5 * ss;
    for (k = 0; k < p; k++)
        lm->D2[k] = lf_fmax(lm->D2[k], lm->A[k * p + k]);
}

int
lf_fit_lm_init(lf_fit *f, const gsl_vector *x)
{
    fit_lm *lm = &f->w.lm;
    size_t k, p = f->np;
    double big = 0.0;

    gsl_vector_memcpy(lm->x, x);
    lm->niter = lm->nevalf = lm->nevaldf = 0;
    lm->nevalf++;
    if (lf_fit_residuals(lm->x, f, lm->r) != GSL_SUCCESS)
        return GSL_EDOM;
    lm->nevaldf++;
    if (lf_fit_jacobian(lm->x, f, lm->J) != GSL_SUCCESS)
        return GSL_EDOM;
    memset(lm->D2, 0, p * sizeof *lm->D2);
    normal_equations(f);
    for (k = 0; k < p; k++)
        if (lm->D2[k] > 0)
            big = lf_fmax(big, lm->A[k * p + k] / lm->D2[k]);
    for (k = 0; k < p; k++)
        if (!(lm->D2[k] > 0))
            lm->D2[k] = 1.0;
    lm->mu = FIT_LM_MU0 * (big > 0 ? big : 1.0);
    lm->nu = 2.0;
    return GSL_SUCCESS;
}

int
lf_fit_lm_iterate(lf_fit *f)
{
    fit_lm *lm = &f->w.lm;
    const size_t p = f->np, n = f->nres;
    size_t k, i, reject;

    for (reject = 0; reject < FIT_LM_MAX_REJECT; reject++) {
        double pred = 0.0, cost_t, ss = 0.0, rho;
        if (!damped_solve(p, lm->A, lm->D2, lm->mu, lm->g, lm->L, lm->h->data)) {
            lm->mu *= lm->nu;
            lm->nu *= 2.0;
            continue;
        }
        for (k = 0; k < p; k++) {
            lm->xt->data[k] = lm->x->data[k] + lm->h->data[k];
            /* predicted decrease: h^T (mu D^2 h - g) / 2 */
            pred += lm->h->data[k] * (lm->mu * lm->D2[k] * lm->h->data[k] - lm->g[k]);
        }
        pred *= 0.5;
        lm->nevalf++;
        if (lf_fit_residuals(lm->xt, f, lm->rt) == GSL_SUCCESS) {
            for (i = 0; i < n; i++)
                ss += lm->rt->data[i] * lm->rt->data[i];
            cost_t = 0.5 * ss;
        } else {
            cost_t = HUGE_VAL;
        }
        rho = pred > 0 && isfinite(cost_t) ? (lm->cost - cost_t) / pred : -1.0;
        if (rho > 0) {
            double t = 2.0 * rho - 1.0;
            gsl_vector_swap(lm->x, lm->xt);
            gsl_vector_swap(lm->r, lm->rt);
            lm->cost_prev = lm->cost;
            lm->nevaldf++;
            if (lf_fit_jacobian(lm->x, f, lm->J) != GSL_SUCCESS)
                return GSL_EDOM;
            normal_equations(f);
            lm->mu *= lf_fmax(1.0 / 3.0, 1.0 - t * t * t);
            lm->nu = 2.0;
            lm->niter++;
            return GSL_SUCCESS;
        }
        lm->mu *= lm->nu;
        lm->nu *= 2.0;
    }
    lm->niter++;
    return GSL_ENOPROG;
}

int
lf_fit_lm_test(const lf_fit *f, double xtol, double gtol, int *info)
{
    const fit_lm *lm = &f->w.lm;
    size_t k;
    int small_step = 1;
    double gmax = 0.0;

    *info = 0;
    /* the step just taken: x - xt holds it after the swap */
    for (k = 0; k < f->np; k++) {
        double xk = lm->x->data[k], dx = fabs(xk - lm->xt->data[k]);
        small_step &= dx <= xtol * (fabs(xk) + xtol);
        gmax = lf_fmax(gmax, fabs(lm->g[k]) * lf_fmax(fabs(xk), 1.0));
    }
    if (small_step) {
        *info = 1;
        return GSL_SUCCESS;
    }
    if (gmax <= gtol * lf_fmax(lm->cost, 1.0)) {
        *info = 2;
        return GSL_SUCCESS;
    }
    return GSL_CONTINUE;
}
