/* solve.c: the trust-region iteration (GSL's gsl_multifit_nlinear, the
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
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>

#include "fit.h"

/* Why GSL stopped, in words; sets *converged. */
static void
stop_reason(int status, int info, size_t maxiter, char *buf, size_t n,
            int *converged)
{
    *converged = 0;
    if (status == GSL_SUCCESS) {
        *converged = 1;
        snprintf(buf, n, "converged (%s)", info == 1 ? "small step" : "small gradient");
    } else if (status == GSL_EMAXITER) {
        snprintf(buf, n, "not converged: %zu iterations reached", maxiter);
    } else if (status == GSL_ENOPROG) {
        snprintf(buf, n, "not converged: no further progress possible");
    } else {
        snprintf(buf, n, "not converged: %s", gsl_strerror(status));
    }
}

/* GSL gives up (ENOPROG) when no step lowers the cost any more; at an exact
 * zero-residual solution this is success.  Accept it when the scaled
 * gradient is at rounding level. */
static int
at_minimum(lf_fit *f)
{
    gsl_vector *r = gsl_multifit_nlinear_residual(f->gsl);
    gsl_matrix *J = gsl_multifit_nlinear_jac(f->gsl);
    size_t i, k;
    double rn = gsl_blas_dnrm2(r);

    for (k = 0; k < f->np; k++) {
        double g = 0.0, cn = 0.0;
        for (i = 0; i < f->nres; i++) {
            double jik = gsl_matrix_get(J, i, k);
            g += jik * gsl_vector_get(r, i);
            cn += jik * jik;
        }
        if (fabs(g) > FIT_GRAD_ROUNDING * sqrt(cn) * rn + 1e-300)
            return 0;
    }
    return 1;
}

/* No coordinate step of +-h (internal units: relative for w and E*,
 * fractions of the depth span and force scale for the offsets) lowers the
 * cost at x: a minimum, smooth or at a kink of the model, where GSL's
 * gradient test need not pass. */
static int
no_descent(lf_fit *f, gsl_vector *x)
{
    static const double h[] = FIT_DESCENT_STEPS;
    const size_t nh = sizeof h / sizeof h[0];
    gsl_vector *r = f->w.r2;
    double c0, rn;
    size_t k, q;
    int sign, ok = 1;

    if (lf_fit_residuals(x, f, r) != GSL_SUCCESS)
        return 0;
    rn = gsl_blas_dnrm2(r);
    c0 = rn * rn;
    for (k = 0; k < f->np && ok; k++) {
        double xk = gsl_vector_get(x, k);
        for (q = 0; q < nh && ok; q++)
            for (sign = -1; sign <= 1 && ok; sign += 2) {
                gsl_vector_set(x, k, xk + sign * h[q]);
                if (lf_fit_residuals(x, f, r) == GSL_SUCCESS) {
                    rn = gsl_blas_dnrm2(r);
                    ok = !(rn * rn < c0 * (1.0 - FIT_DESCENT_REL));
                }
            }
        gsl_vector_set(x, k, xk);
    }
    f->w.xcache_ok = 0;
    return ok;
}

/* After each iteration: remember the cost. */
static void
track_cost(const size_t iter, void *params, const gsl_multifit_nlinear_workspace *w)
{
    lf_fit *f = params;
    double r = gsl_blas_dnrm2(gsl_multifit_nlinear_residual(w));
    f->w.cost_hist[iter % (FIT_FLAT_ITERS + 1)] = 0.5 * r * r;
}

/* 1 when every column of the solver's Jacobian is finite and not
 * negligible.  A parameter that stops mattering (w driven towards zero
 * leaves its column near zero) sends GSL's subspace2D method into an
 * endless loop solving a quartic of NaNs; the other methods stall. */
static int
jacobian_usable(lf_fit *f, size_t *which)
{
    const gsl_matrix *J = gsl_multifit_nlinear_jac(f->gsl);
    size_t i, k;
    double top = 0.0, low = HUGE_VAL;

    for (k = 0; k < J->size2; k++) {
        double big = 0.0;
        for (i = 0; i < J->size1; i++) {
            double v = fabs(gsl_matrix_get(J, i, k));
            if (!isfinite(v))
                return 0;
            big = fmax(big, v);
        }
        top = fmax(top, big);
        if (big < low) {
            low = big;
            *which = k;
        }
    }
    return low > FIT_DEAD_COLUMN * top;
}

/* gsl_multifit_nlinear_driver with the Jacobian checked before each
 * iteration and the cost recorded after it.  An unusable Jacobian ends the
 * run with GSL_EBADFUNC and the negligible column in *dead. */
static int
drive(lf_fit *f, int *info, size_t *dead)
{
    size_t iter = 0;
    int status;

    *info = 0;
    do {
        if (!jacobian_usable(f, dead))
            return GSL_EBADFUNC;
        status = gsl_multifit_nlinear_iterate(f->gsl);
        if (status == GSL_ENOPROG && iter == 0) {
            *info = status;
            return GSL_EMAXITER;
        }
        track_cost(iter, f, f->gsl);
        status = gsl_multifit_nlinear_test(f->set.xtol, f->set.gtol, f->set.ftol, info, f->gsl);
    } while (status == GSL_CONTINUE && ++iter < f->set.max_iter);
    if (iter >= f->set.max_iter && status != GSL_SUCCESS)
        status = GSL_EMAXITER;
    return status;
}

/* x = the solver's position */
static void
take_position(lf_fit *f, gsl_vector *x)
{
    gsl_vector_memcpy(x, gsl_multifit_nlinear_position(f->gsl));
}

int
lf_fit_iterate(lf_fit *f, gsl_vector *x, int after_scan, fit_run *run, lf_error *err)
{
    int status, info = 0, *converged = &run->converged;
    size_t dead = 0, iters;
    char *why = run->why;
    const size_t nwhy = sizeof run->why;

    *converged = 0;
    status = gsl_multifit_nlinear_init(x, &f->fdf, f->gsl);
    if (status != GSL_SUCCESS)
        return lf_fail(err, LF_ENUMERIC, "the model cannot be evaluated at the starting point (%s)",
                       gsl_strerror(status));
    status = drive(f, &info, &dead);
    iters = gsl_multifit_nlinear_niter(f->gsl);
    run->iters += iters;
    run->evals += f->fdf.nevalf + f->fdf.nevaldf;
    if (status == GSL_EBADFUNC) {
        take_position(f, x);
        if ((int) dead == f->imat[FIT_W]) {
            /* the assessment reports w as bounded or undetermined */
            *converged = 1;
            snprintf(why, nwhy, "converged (w driven towards zero, where it no longer "
                     "changes the fit)");
        } else {
            snprintf(why, nwhy, "not converged: parameter %zu no longer changes the fit", dead + 1);
        }
        return LF_OK;
    }
    if (status == GSL_EMAXITER && iters > FIT_FLAT_ITERS) {
        /* GSL numbers the iteration that just ended iters - 1 */
        double now = f->w.cost_hist[(iters - 1) % (FIT_FLAT_ITERS + 1)];
        double then = f->w.cost_hist[iters % (FIT_FLAT_ITERS + 1)];
        if (then - now <= fmax(FIT_FLAT_REL * now, FIT_FLAT_ABS)) {
            take_position(f, x);
            *converged = 1;
            snprintf(why, nwhy, "converged (chi2 fell by %.2g over the last %d iterations)",
                     2.0 * (then - now), FIT_FLAT_ITERS);
            return LF_OK;
        }
    }
    /* GSL reports "no step lowers the cost from the start" as EMAXITER
     * with info ENOPROG.  after_scan: x is a converged solution moved by
     * the contact-point scan or a reweighting */
    if (status == GSL_EMAXITER && info == GSL_ENOPROG && iters < f->set.max_iter)
        status = GSL_ENOPROG;
    stop_reason(status, info, f->set.max_iter, why, nwhy, converged);
    take_position(f, x);
    if (status == GSL_ENOPROG && !at_minimum(f) && f->fdf.df != NULL && !no_descent(f, x)) {
        /* the analytic derivatives, guarded at the contact edge, can point
         * nowhere useful there: go on with finite differences, which see the
         * residuals as they are */
        size_t more;
        f->fdf.df = NULL;
        status = gsl_multifit_nlinear_init(x, &f->fdf, f->gsl);
        if (status == GSL_SUCCESS)
            status = drive(f, &info, &dead);
        f->fdf.df = lf_fit_jacobian;
        more = gsl_multifit_nlinear_niter(f->gsl);
        run->iters += more;
        run->evals += f->fdf.nevalf + f->fdf.nevaldf;
        if (status == GSL_EMAXITER && info == GSL_ENOPROG && more < f->set.max_iter)
            status = GSL_ENOPROG;
        stop_reason(status, info, f->set.max_iter, why, nwhy, converged);
        take_position(f, x);
    }
    if (status == GSL_ENOPROG && !at_minimum(f) && !after_scan && no_descent(f, x)) {
        *converged = 1;
        snprintf(why, nwhy, "converged (no step lowers the cost: a kink where a point meets "
                 "the contact edge)");
        return LF_OK;
    }
    if (status == GSL_ENOPROG && (at_minimum(f) || after_scan)) {
        /* after the contact-point scan the cost sits at a kink of the
         * model, where the gradient need not vanish */
        *converged = 1;
        snprintf(why, nwhy, after_scan ? "converged (no step lowers the cost from the previous "
                 "solution)" : "converged (no further decrease at a stationary point)");
    }
    take_position(f, x);
    return LF_OK;
}

