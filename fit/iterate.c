/* iterate.c: the trust-region iteration (GSL's gsl_multifit_nlinear, the
 * method chosen in the settings) and its stopping rules, every tolerance
 * named in fit.h.  Converged means one of:
 *  - GSL's tests on the step (xtol) or the gradient (gtol);
 *  - no step lowers the cost and the scaled gradient is at rounding level
 *    (FIT_GRAD_ROUNDING), or no coordinate step does (FIT_DESCENT_*): a
 *    kink where a point meets the contact edge;
 *  - the iteration limit with the cost flat (FIT_FLAT_*);
 *  - w driven to where it no longer changes the fit (FIT_DEAD_COLUMN),
 *    which the assessment reports as a bound.
 * Everything else is "not converged", with the reason in words. */
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>

#include "fit.h"

/* ---- the solver: lm.c for "lm" with the analytic Jacobian, else GSL ---- */

static gsl_vector *
cur_x(lf_fit *f)
{
    return f->ws.own ? f->ws.lm.x : gsl_multifit_nlinear_position(f->gsl);
}

static gsl_vector *
cur_r(lf_fit *f)
{
    return f->ws.own ? f->ws.lm.r : gsl_multifit_nlinear_residual(f->gsl);
}

/* GSL's Jacobian at the current point (lm.c keeps J^T J and J^T r only). */
static gsl_matrix *
gsl_J(lf_fit *f)
{
    return gsl_multifit_nlinear_jac(f->gsl);
}

static size_t
cur_niter(lf_fit *f)
{
    return f->ws.own ? f->ws.lm.niter : gsl_multifit_nlinear_niter(f->gsl);
}

/* Evaluations of the residuals; a Jacobian by differences (GSL's or
 * gsl_block.c's) counts one per column. */
static size_t
cur_evals(lf_fit *f)
{
    if (f->ws.own)
        return f->ws.lm.nevalf + f->ws.lm.nevaldf;
    return f->fdf.nevalf + f->fdf.nevaldf * (f->fdf.df == lf_fit_jacobian_fd ? f->np : 1);
}

static int
solver_init(lf_fit *f, const gsl_vector *x, int allow_own)
{
    f->ws.own = allow_own && f->fdf.df == lf_fit_jacobian && strcmp(f->set.method, "lm") == 0;
    if (f->ws.own)
        return lf_fit_lm_init(f, x);
    if (lf_fit_gsl(f) != LF_OK)
        return GSL_ENOMEM;
    return gsl_multifit_nlinear_init(x, &f->fdf, f->gsl);
}

static int
solver_iterate(lf_fit *f)
{
    return f->ws.own ? lf_fit_lm_iterate(f) : gsl_multifit_nlinear_iterate(f->gsl);
}

static int
solver_test(lf_fit *f, int *info)
{
    return f->ws.own ? lf_fit_lm_test(f, f->set.xtol, f->set.gtol, info)
                    : gsl_multifit_nlinear_test(f->set.xtol, f->set.gtol, f->set.ftol, info,
                                                f->gsl);
}

/* A solver status in words.  GSL_EDOM comes from our own residual and
 * Jacobian callbacks (problem.c): the model cannot be evaluated at the
 * parameters tried. */
static const char *
status_words(int status)
{
    if (status == GSL_EDOM)
        return "the model cannot be evaluated at the parameters the solver tried "
               "(outside the model's domain)";
    return gsl_strerror(status);
}

void
lf_fit_run_says(fit_run *run, lf_fit_stop stop, const char *fmt, ...)
{
    va_list ap;

    run->converged = stop == LF_STOP_CONVERGED;
    run->stop = stop;
    run->user_test = 0;
    va_start(ap, fmt);
    vsnprintf(run->why, sizeof run->why, fmt, ap);
    va_end(ap);
}

void
lf_fit_run_verdict_from(fit_run *run, const fit_run *from)
{
    run->converged = from->converged;
    run->stop = from->stop;
    run->user_test = from->user_test;
    memcpy(run->why, from->why, sizeof run->why);
}

/* Why the solver stopped: run's verdict and its words. */
static void
stop_reason(int status, int info, size_t maxiter, fit_run *run)
{
    if (status == GSL_SUCCESS) {
        lf_fit_run_says(run, LF_STOP_CONVERGED, "converged (%s)",
                        info == FIT_INFO_CHI2 ? "chi2 within reach of its minimum"
                        : info == FIT_INFO_CREEP ? "steps far below the standard errors"
                        : info == FIT_INFO_BASIN ? "the first solution's basin"
                        : info == 1 ? "small step" : "small gradient");
        run->user_test = info == 1 || info == 2;
    } else if (status == GSL_EMAXITER) {
        lf_fit_run_says(run, LF_STOP_ITERATIONS, "not converged: the limit of %zu iterations "
                        "per solve reached", maxiter);
    } else if (status == GSL_ENOPROG) {
        lf_fit_run_says(run, LF_STOP_NO_PROGRESS, "not converged: no further progress possible");
    } else {
        lf_fit_run_says(run, LF_STOP_FAILED, "not converged: %s", status_words(status));
    }
}

/* GSL gives up (ENOPROG) when no step lowers the cost any more; at an exact
 * zero-residual solution this is success.  Accept it when the scaled
 * gradient is at rounding level. */
static int
at_minimum(lf_fit *f)
{
    gsl_vector *r = cur_r(f);
    size_t i, k;
    double rn = gsl_blas_dnrm2(r);

    for (k = 0; k < f->np; k++) {
        double g = 0.0, cn = 0.0;
        if (f->ws.own) {     /* J^T r and the column's squared norm, from lm.c */
            g = f->ws.lm.g[k];
            cn = lf_arrow_get(&f->ws.lm.A, k, k);
        } else {
            const gsl_matrix *J = gsl_J(f);
            for (i = 0; i < f->nres; i++) {
                double jik = gsl_matrix_get(J, i, k);
                g += jik * gsl_vector_get(r, i);
                cn += jik * jik;
            }
        }
        if (fabs(g) > FIT_GRAD_ROUNDING * sqrt(cn) * rn + 1e-300)
            return 0;
    }
    return 1;
}

/* No coordinate step of +-h (internal units: relative for w and E*,
 * fractions of the depth span and force scale for the offsets) lowers the
 * cost at x: a minimum, smooth or at a kink of the model, where GSL's
 * gradient test need not pass.  With move, every step is tried, and x moves
 * along the one that lowers the cost most, the step doubled while the cost
 * keeps falling (when one does), and *gain is the fall of chi2 relative to
 * chi2 / dof. */
static int
no_descent_move(lf_fit *f, gsl_vector *x, int move, double *gain)
{
    static const double h[] = FIT_DESCENT_STEPS;
    const size_t nh = sizeof h / sizeof h[0];
    gsl_vector *r = f->ws.r2;
    double c0, rn, best, best_step = 0.0;
    size_t k, q, best_k = 0;
    int sign, ok = 1;

    if (lf_fit_residuals(x, f, r) != GSL_SUCCESS)
        return 0;
    rn = gsl_blas_dnrm2(r);
    c0 = rn * rn;
    best = c0 * (1.0 - FIT_DESCENT_REL);
    for (k = 0; k < f->np && (ok || move); k++) {
        double xk = gsl_vector_get(x, k);
        for (q = 0; q < nh && (ok || move); q++)
            for (sign = -1; sign <= 1 && (ok || move); sign += 2) {
                gsl_vector_set(x, k, xk + sign * h[q]);
                if (lf_fit_residuals(x, f, r) == GSL_SUCCESS) {
                    rn = gsl_blas_dnrm2(r);
                    if (rn * rn < best) {
                        ok = 0;
                        best = rn * rn;
                        best_k = k;
                        best_step = sign * h[q];
                    }
                }
            }
        gsl_vector_set(x, k, xk);
    }
    if (move && !ok) {
        /* on along that coordinate, doubling the step while the cost falls */
        double xk = gsl_vector_get(x, best_k);
        int dbl;
        for (dbl = 0; dbl < 40; dbl++) {
            gsl_vector_set(x, best_k, xk + 2.0 * best_step);
            if (lf_fit_residuals(x, f, r) != GSL_SUCCESS)
                break;
            rn = gsl_blas_dnrm2(r);
            if (!(rn * rn < best))
                break;
            best = rn * rn;
            best_step *= 2.0;
        }
        gsl_vector_set(x, best_k, xk + best_step);
    }
    if (gain != NULL)
        *gain = c0 > 0 ? (c0 - lf_fmin(best, c0)) / (c0 / (double) (f->nres - f->np)) : 0.0;
    f->ws.xcache_ok = 0;
    return ok;
}

static int
no_descent(lf_fit *f, gsl_vector *x)
{
    return no_descent_move(f, x, 0, NULL);
}

/* The cost (half chi2) at the solver's position. */
static double
cur_cost(lf_fit *f)
{
    double r;

    if (f->ws.own)
        return f->ws.lm.cost;
    r = gsl_blas_dnrm2(cur_r(f));
    return 0.5 * r * r;
}

/* After each iteration: remember the cost. */
static void
track_cost(lf_fit *f, size_t iter)
{
    f->ws.cost_hist[iter % (FIT_FLAT_ITERS + 1)] = cur_cost(f);
}

/* The solver's Jacobian J and residuals r at its position, examined once
 * per iteration (rows read in place):
 *  - returns 0 when a column is not finite or negligible (below
 *    FIT_DEAD_COLUMN of the largest), with that column in *which.  A
 *    parameter that stops mattering (w driven towards zero leaves its
 *    column near zero) sends GSL's subspace2D method into an endless loop
 *    solving a quartic of NaNs; the other methods stall;
 *  - *dchi2 = g^T (J^T J)^-1 g, g = J^T r: the decrease of chi2 that a full
 *    Gauss-Newton step predicts, which is also the squared distance to the
 *    minimum of the local quadratic measured in standard errors (residuals
 *    are in units of the noise).  HUGE_VAL when J^T J is not positive
 *    definite. */
static int
examine_jacobian(lf_fit *f, size_t *which, double *dchi2)
{
    const size_t p = f->np;
    const fit_arrow *A = &f->ws.lm.A;
    double *g = f->ws.grad, *big = f->ws.colmax, top = 0.0, low = HUGE_VAL;
    size_t k;

    *dchi2 = HUGE_VAL;
    for (k = 0; k < p; k++)
        f->ws.ainv[k] = NAN;
    if (f->ws.own) {         /* lm.c has J^T J and J^T r already */
        memcpy(g, f->ws.lm.g, p * sizeof *g);
        memcpy(big, f->ws.lm.colmax, p * sizeof *big);
    } else {
        lf_fit_normal_of_jacobian(f, gsl_J(f), cur_r(f)->data, &f->ws.gsl_jtj, g, big);
        A = &f->ws.gsl_jtj;
    }
    for (k = 0; k < p; k++) {
        if (!isfinite(big[k]) || !isfinite(g[k]))
            return 0;
        top = lf_fmax(top, big[k]);
        if (big[k] < low) {
            low = big[k];
            *which = k;
        }
    }
    if (!(low > FIT_DEAD_COLUMN * top))
        return 0;
    /* the block Cholesky of J^T J (block.c), then |L^-1 g|^2 and the
     * diagonal of (J^T J)^-1 */
    if (!lf_arrow_factor(&f->ws.jchol, A, NULL, 0.0, 1e-14))
        return 1;
    *dchi2 = lf_arrow_norm2(&f->ws.jchol, g, f->ws.lm.Ah);
    lf_arrow_inv_diag(&f->ws.jchol, f->ws.ainv);
    return 1;
}

/* lm.c's last accepted step, from x_prev to x, moved every parameter by
 * less than sqrt(step) of its standard error (sqrt(chi2/dof (J^T J)^-1_kk)
 * at x) and lowered chi2 by less than step chi2/dof, step the larger of
 * FIT_CREEP_CHI2 and the solve's chi2_step: a creep (at a kink of the cost
 * the Gauss-Newton test need not pass) that no longer moves any estimate. */
static int
creeping(lf_fit *f, double chi2dof)
{
    const fit_lm *lm = &f->ws.lm;
    const double step = lf_fmax(f->chi2_step, FIT_CREEP_CHI2), tol = sqrt(step);
    size_t k;

    if (!f->ws.own || lm->niter == 0 || !(2.0 * (lm->cost_prev - lm->cost) <= step * chi2dof))
        return 0;
    for (k = 0; k < f->np; k++)
        if (!(fabs(lm->x->data[k] - lm->xt->data[k]) <= tol * sqrt(chi2dof * f->ws.ainv[k])))
            return 0;
    return 1;
}

/* chi2 / dof at the solver's position: the square of the factor by which
 * the reported standard errors are scaled. */
static double
chi2_per_dof(lf_fit *f)
{
    return 2.0 * cur_cost(f) / (double) (f->nres - f->np);
}

int
lf_fit_gn_at(const lf_fit *f, const gsl_vector *x)
{
    return f->ws.gn_ok && memcmp(f->ws.gn_x, x->data, f->np * sizeof *x->data) == 0;
}

/* What the verdict (verdict.c) asks at the end, kept where the Jacobian is
 * examined: the Gauss-Newton decrease of chi2 at the solver's position, from
 * the analytic Jacobian, when J^T J is positive definite. */
static void
remember_gn(lf_fit *f, double dchi2, double chi2dof)
{
    f->ws.gn_ok = f->fdf.df == lf_fit_jacobian && dchi2 < HUGE_VAL;
    if (!f->ws.gn_ok)
        return;
    memcpy(f->ws.gn_x, cur_x(f)->data, f->np * sizeof *f->ws.gn_x);
    f->ws.gn_dchi2 = dchi2;
    f->ws.gn_chi2 = chi2dof * (double) (f->nres - f->np);
}

/* A second start's position back in the first solution's basin: every
 * parameter within its tolerance of the first's (internal coordinates),
 * the cost within FIT_SAME_COST of the first's (second_start.c). */
static int
in_basin(lf_fit *f)
{
    const double *x = cur_x(f)->data;
    size_t k;

    if (!(fabs(cur_cost(f) - f->ws.basin_cost) <= FIT_SAME_COST))
        return 0;       /* above it, or already lower: another minimum */
    for (k = 0; k < f->np; k++)
        if (!(fabs(f->x0_internal[k] + x[k] - 1.0 - f->ws.basin_x[k]) <= f->ws.basin_tol[k]))
            return 0;
    return 1;
}

/* gsl_multifit_nlinear_driver with the Jacobian examined before each
 * iteration and the cost recorded after it.  Stops with GSL_SUCCESS and
 * *info = FIT_INFO_CHI2 when a Gauss-Newton step would lower chi2 by less
 * than chi2_step chi2/dof (FIT_CHI2_STEP: the estimates are then within
 * sqrt(FIT_CHI2_STEP) of their reported standard errors of the minimum),
 * else by GSL's tests; where the Gauss-Newton step's chi2 stays above
 * f->stop_above, with f->stopped_above set.  An unusable
 * Jacobian ends the run with GSL_EBADFUNC and the negligible column in
 * *dead. */
static int
drive(lf_fit *f, int *info, size_t *dead)
{
    size_t iter = 0;
    int status;
    double dchi2, chi2dof;

    *info = 0;
    do {
        if (!examine_jacobian(f, dead, &dchi2))
            return GSL_EBADFUNC;
        chi2dof = chi2_per_dof(f);
        remember_gn(f, dchi2, chi2dof);
        /* a run that only asks whether chi2 ends below a level: not from
         * here (dchi2 is HUGE_VAL where J^T J is not positive definite) */
        if (f->stop_above > 0 && chi2dof * (double) (f->nres - f->np) - dchi2 > f->stop_above) {
            f->stopped_above = 1;
            return GSL_SUCCESS;
        }
        if (dchi2 <= f->chi2_step * chi2dof) {
            *info = FIT_INFO_CHI2;
            return GSL_SUCCESS;
        }
        if (creeping(f, chi2dof)) {
            *info = FIT_INFO_CREEP;
            return GSL_SUCCESS;
        }
        status = solver_iterate(f);
        if (status == GSL_ENOPROG && iter == 0) {
            *info = status;
            return GSL_EMAXITER;
        }
        if (status != GSL_SUCCESS && status != GSL_ENOPROG)
            return status;
        track_cost(f, iter);
        if (f->ws.basin_on && in_basin(f)) {
            f->ws.basin_hit = 1;
            *info = FIT_INFO_BASIN;
            return GSL_SUCCESS;
        }
        /* lm.c's GSL_ENOPROG (no step accepted) ends the run; GSL's
         * driver goes on after its first iteration, and so does this loop */
        status = status == GSL_ENOPROG && f->ws.own ? GSL_ENOPROG : solver_test(f, info);
    } while (status == GSL_CONTINUE && ++iter < f->set.max_iter);
    if (iter >= f->set.max_iter && status != GSL_SUCCESS)
        status = GSL_EMAXITER;
    return status;
}

/* x = the solver's position */
static void
take_position(lf_fit *f, gsl_vector *x)
{
    gsl_vector_memcpy(x, cur_x(f));
}

/* Solve again from x after a stall (allow_own: lm.c may take it), its
 * iterations and evaluations counted into run; GSL's "no step lowers the
 * cost from the start" (EMAXITER, info ENOPROG) comes back as ENOPROG.
 * *started is 0 (nothing run or counted) when the solver cannot start at
 * x. */
static int
solve_again(lf_fit *f, gsl_vector *x, int allow_own, fit_run *run, int *info, size_t *dead,
            int *started)
{
    size_t more;
    int status = solver_init(f, x, allow_own);

    *started = status == GSL_SUCCESS;
    if (!*started)
        return status;
    status = drive(f, info, dead);
    more = cur_niter(f);
    run->iters += more;
    run->evals += cur_evals(f);
    if (status == GSL_EMAXITER && *info == GSL_ENOPROG && more < f->set.max_iter)
        status = GSL_ENOPROG;
    return status;
}

/* The end of a run that drive() stopped at f->stop_above: x the solver's
 * position, where chi2 exceeds that level. */
static int
above_end(lf_fit *f, gsl_vector *x, fit_run *run)
{
    take_position(f, x);
    lf_fit_run_says(run, LF_STOP_NO_PROGRESS, "not converged: stopped where a Gauss-Newton step "
                    "cannot bring chi2 down to the level asked");
    return LF_OK;
}

int
lf_fit_iterate(lf_fit *f, gsl_vector *x, int after_scan, fit_run *run, lf_error *err)
{
    int status, info = 0;
    size_t dead = 0, iters, nudge;
    int kink = 0, started;
    double gain = 0.0;

    run->converged = 0;
    gsl_vector_memcpy(f->ws.x0, x);
    status = solver_init(f, x, 1);
    if (status != GSL_SUCCESS)
        return lf_fail(err, LF_ENUMERIC, "the model cannot be evaluated at the starting point (%s)",
                       status_words(status));
    f->stopped_above = 0;
    status = drive(f, &info, &dead);
    if (f->stopped_above) {
        run->iters += cur_niter(f);
        run->evals += cur_evals(f);
        return above_end(f, x, run);
    }
    if (f->ws.own && status != GSL_SUCCESS && status != GSL_EBADFUNC) {
        /* lm.c stalled (at a kink of the cost, where steps are rejected or
         * creep): the same start with GSL's trust region, whose path
         * differs there */
        run->iters += cur_niter(f);
        run->evals += cur_evals(f);
        status = solver_init(f, f->ws.x0, 0);
        if (status != GSL_SUCCESS)
            return lf_fail(err, LF_ENUMERIC, "the model cannot be evaluated at the starting "
                           "point (%s)", status_words(status));
        status = drive(f, &info, &dead);
    }
    iters = cur_niter(f);
    run->iters += iters;
    run->evals += cur_evals(f);
    if (status == GSL_EBADFUNC) {
        take_position(f, x);
        if ((int) dead == f->imat[FIT_W]) {
            /* the assessment reports w as bounded or undetermined */
            lf_fit_run_says(run, LF_STOP_CONVERGED, "converged (w driven towards zero, where "
                            "it no longer changes the fit)");
        } else {
            lf_fit_run_says(run, LF_STOP_DEAD_PARAMETER, "not converged: parameter %zu no "
                            "longer changes the fit", dead + 1);
        }
        return LF_OK;
    }
    if (status == GSL_EMAXITER && iters > FIT_FLAT_ITERS) {
        /* GSL numbers the iteration that just ended iters - 1 */
        double now = f->ws.cost_hist[(iters - 1) % (FIT_FLAT_ITERS + 1)];
        double then = f->ws.cost_hist[iters % (FIT_FLAT_ITERS + 1)];
        if (then - now <= lf_fmax(FIT_FLAT_REL * now, FIT_FLAT_ABS)) {
            take_position(f, x);
            lf_fit_run_says(run, LF_STOP_CONVERGED, "converged (chi2 fell by %.2g over the "
                            "last %d iterations)", 2.0 * (then - now), FIT_FLAT_ITERS);
            return LF_OK;
        }
    }
    /* GSL reports "no step lowers the cost from the start" as EMAXITER
     * with info ENOPROG.  after_scan: x is a converged solution moved by
     * the contact-point scan or a reweighting */
    if (status == GSL_EMAXITER && info == GSL_ENOPROG && iters < f->set.max_iter)
        status = GSL_ENOPROG;
    stop_reason(status, info, f->set.max_iter, run);
    take_position(f, x);
    if (status == GSL_ENOPROG && !at_minimum(f) && f->fdf.df != NULL && !no_descent(f, x)) {
        /* the analytic derivatives, guarded at the contact edge, can point
         * nowhere useful there: go on with finite differences, which see the
         * residuals as they are (GSL's, in block form where that gives
         * GSL's numbers: gsl_block.c) */
        f->fdf.df = lf_fit_block_fd(f);
        status = solve_again(f, x, 0, run, &info, &dead, &started);
        f->fdf.df = lf_fit_jacobian;
        if (f->stopped_above)
            return above_end(f, x, run);
        stop_reason(status, info, f->set.max_iter, run);
        take_position(f, x);
    }
    for (nudge = 0; status == GSL_ENOPROG && nudge < FIT_NUDGES && !at_minimum(f)
                    && !no_descent_move(f, x, 1, &gain); nudge++) {
        /* the solver's steps, analytic and finite-difference, all rise, yet a
         * coordinate step lowers the cost (a kink the quadratic model cannot
         * see): take that step and solve on from there; a step that gains
         * less than chi2_step of chi2/dof is the rounding of a kink's
         * minimum, where the Gauss-Newton test cannot pass */
        if (gain < f->chi2_step) {
            kink = 1;
            break;
        }
        status = solve_again(f, x, 1, run, &info, &dead, &started);
        if (!started)
            break;
        if (f->stopped_above)
            return above_end(f, x, run);
        if (status == GSL_EBADFUNC) {
            status = GSL_ENOPROG;       /* judged below as the stall it ends */
            take_position(f, x);
            break;
        }
        stop_reason(status, info, f->set.max_iter, run);
        take_position(f, x);
    }
    if (status == GSL_ENOPROG && !at_minimum(f) && !after_scan && (kink || no_descent(f, x))) {
        lf_fit_run_says(run, LF_STOP_CONVERGED, "converged (no step lowers the cost: a kink "
                        "where a point meets the contact edge)");
        return LF_OK;
    }
    if (status == GSL_ENOPROG && (at_minimum(f) || after_scan)) {
        /* after the contact-point scan the cost sits at a kink of the
         * model, where the gradient need not vanish */
        lf_fit_run_says(run, LF_STOP_CONVERGED, "%s", after_scan
                        ? "converged (no step lowers the cost from the previous solution)"
                        : "converged (no further decrease at a stationary point)");
    }
    take_position(f, x);
    return LF_OK;
}

