/* lm.c: the Levenberg-Marquardt iteration of the "lm" method, on the
 * small normal matrix (formed without J, problem.c).
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
 * a rejected one mu *= nu, nu *= 2.  mu starts at mu0 max_k (J^T J)_kk /
 * D_k^2 = mu0 (D^2 starts as J^T J's diagonal; mu0 = FIT_LM_MU0 = 1e-3, or
 * a profile's own, profile.c).  After
 * FIT_LM_MAX_REJECT rejections in a row the iteration reports
 * GSL_ENOPROG, as GSL's trust region does.
 *
 * From the second iteration of a solve on, each trial point's free force
 * offsets (and slopes) are set to their least-squares values before its
 * cost is taken (lf_fit_project_offsets, problem.c: the residuals are
 * linear in them, so this costs no evaluation), and the gain ratio counts
 * that decrease too, which lets the damping fall as fast as the valley of
 * the other parameters allows (variable projection).  Without it a step
 * that moves w or a contact point moves the offsets only along the
 * linearisation, and the iteration creeps along the curved valley this
 * leaves: with z0 and F0 free (paper-offsets) 26 -> 15 iterations per fit
 * at 1% noise and 65 -> 19 at 5% (layerfit bench), and the minima it
 * ends in no worse (1% noise, 1000 seeds: chi2 lower than without it in
 * 193, higher in 137; by more than 1 in 14 and in 1).  The first step of
 * a solve is taken plain, so that its gain ratio measures the linear model
 * alone before the damping follows the projected decrease: projecting from
 * the first step left one seed of 90 in the hard-case suite
 * (tests/test_hard.c, unsorted rows) at a kink of the cost 3.7 chi2 above
 * the minimum the plain path finds.
 *
 * A trial step raises ln w and moves ln E* by at most FIT_LM_MAX_LOG_STEP
 * (a decade; clip_log_step): from a start far below the data's w the
 * Gauss-Newton step asks for hundreds of e-folds, and the rejected trials
 * that shrank it left the damping so large that the climb took an e-fold
 * an iteration (two probes, 1% noise, a start 4 decades low: 35 -> 16
 * evaluations; at 5% noise from the automatic start, whose w is the
 * floor where no curve shows adhesion clearly, 17.7 -> 15.4 on average).
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

/* A = J^T J (lower triangle), g = J^T r, colmax = max |J_ik| per column
 * at the current point (problem.c, J never formed), whose cost |r|^2 / 2
 * the caller has; D2 grows to the squared column norms. */
static int
normal_equations(lf_fit *f, double cost)
{
    fit_lm *lm = &f->ws.lm;
    const size_t p = f->np;
    size_t k;

    lm->nevaldf++;
    if (lf_fit_normal_sums(f, lm->x->data, lm->r->data, lm->A, lm->g, lm->colmax) != GSL_SUCCESS)
        return GSL_EDOM;
    lm->cost = cost;
    for (k = 0; k < p; k++)
        lm->D2[k] = lf_fmax(lm->D2[k], lm->A[k * p + k]);
    return GSL_SUCCESS;
}

int
lf_fit_lm_init(lf_fit *f, const gsl_vector *x)
{
    fit_lm *lm = &f->ws.lm;
    size_t k, p = f->np;
    double ss;

    gsl_vector_memcpy(lm->x, x);
    lm->niter = lm->nevalf = lm->nevaldf = 0;
    lm->nevalf++;
    if (lf_fit_residuals_ss(f, lm->x, lm->r, &ss) != GSL_SUCCESS)
        return GSL_EDOM;
    memset(lm->D2, 0, p * sizeof *lm->D2);
    if (normal_equations(f, 0.5 * ss) != GSL_SUCCESS)
        return GSL_EDOM;
    for (k = 0; k < p; k++)
        if (!(lm->D2[k] > 0))
            lm->D2[k] = 1.0;
    /* D^2 is J^T J's diagonal here, so every scaled diagonal is 1 and mu
     * is in units of it */
    lm->mu = f->mu0;
    lm->mu_first = NAN;
    lm->nu = 2.0;
    return GSL_SUCCESS;
}

/* The step h shortened, direction kept, so that it raises ln w and moves
 * ln E* by at most FIT_LM_MAX_LOG_STEP; 0 when it was not.  Where the cost
 * is nearly flat in ln w (a start with w far below what the data hold, no
 * adhesion seen yet) the Gauss-Newton step asks for hundreds of e-folds
 * up: the damping would then climb through rejected trials, one
 * evaluation each, to a value so large that the way up is walked an
 * e-fold an iteration while it falls again.  A step down in w is left
 * whole: towards no adhesion the cost flattens for good, and the long
 * step is how a fit finds that w is not determined (verdict.c). */
static int
clip_log_step(const lf_fit *f, double *h)
{
    double m = 0.0;
    size_t k;

    if (f->imat[FIT_W] >= 0)
        m = h[f->imat[FIT_W]];
    if (f->imat[FIT_E] >= 0)
        m = lf_fmax(m, fabs(h[f->imat[FIT_E]]));
    if (!(m > FIT_LM_MAX_LOG_STEP))
        return 0;
    for (k = 0; k < f->np; k++)
        h[k] *= FIT_LM_MAX_LOG_STEP / m;
    return 1;
}

int
lf_fit_lm_iterate(lf_fit *f)
{
    fit_lm *lm = &f->ws.lm;
    const size_t p = f->np, n = f->nres;
    size_t k, i, reject;

    for (reject = 0; reject < FIT_LM_MAX_REJECT; reject++) {
        double pred = 0.0, cost_t, ss = 0.0, rho;
        if (!damped_solve(p, lm->A, lm->D2, lm->mu, lm->g, lm->L, lm->h->data)) {
            lm->mu *= lm->nu;
            lm->nu *= 2.0;
            continue;
        }
        if (clip_log_step(f, lm->h->data)) {
            /* predicted decrease of the shortened step: -g^T h - h^T A h / 2 */
            const double *h = lm->h->data;
            for (k = 0; k < p; k++) {
                double Ah = 0.0;
                size_t l;
                for (l = 0; l < p; l++)
                    Ah += (k >= l ? lm->A[k * p + l] : lm->A[l * p + k]) * h[l];
                pred -= h[k] * (lm->g[k] + 0.5 * Ah);
            }
        } else {
            /* predicted decrease: h^T (mu D^2 h - g) / 2 */
            for (k = 0; k < p; k++)
                pred += lm->h->data[k] * (lm->mu * lm->D2[k] * lm->h->data[k] - lm->g[k]);
            pred *= 0.5;
        }
        for (k = 0; k < p; k++)
            lm->xt->data[k] = lm->x->data[k] + lm->h->data[k];
        lm->nevalf++;
        if (lf_fit_residuals_ss(f, lm->xt, lm->rt, &ss) == GSL_SUCCESS) {
            if (lm->niter > 0 && lf_fit_project_offsets(f, lm->xt->data, lm->rt->data))
                for (i = 0, ss = 0.0; i < n; i++)
                    ss += lm->rt->data[i] * lm->rt->data[i];
            cost_t = 0.5 * ss;
        } else {
            cost_t = HUGE_VAL;
        }
        rho = pred > 0 && isfinite(cost_t) ? (lm->cost - cost_t) / pred : -1.0;
        if (rho > 0) {
            double t = 2.0 * rho - 1.0;
            gsl_vector *tx = lm->x, *tr = lm->r;     /* views: swap them, not their numbers */
            lm->x = lm->xt;
            lm->xt = tx;
            lm->r = lm->rt;
            lm->rt = tr;
            lm->cost_prev = lm->cost;
            if (lm->niter == 0)
                lm->mu_first = lm->mu;
            if (normal_equations(f, cost_t) != GSL_SUCCESS)
                return GSL_EDOM;
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
    const fit_lm *lm = &f->ws.lm;
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
