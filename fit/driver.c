/* driver.c: one run of a fit -- the start, the solve from it with its
 * restarts (solve.c), the assessment (uncertainty.c), leave-one-out when
 * every one of three or more curves disagrees (loo.c) -- and the one-call
 * driver.
 *
 *   start      lf_fit_guess (guess.c), or the current origin (a warm start)
 *   solve      lf_fit_solve_run (solve.c)
 *   assess     lf_fit_assess (uncertainty.c)
 *   policies   leave-one-out (loo.c), which refits through solve.c and
 *              uncertainty.c, never through this file */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "fit.h"

/* The name of the curves' model, or "mixed". */
static const char *
model_name(const lf_fit *f)
{
    const lf_model_type *t = lf_model_get_type(f->c[0].model);
    size_t j;

    for (j = 1; j < f->ncurves; j++)
        if (lf_model_get_type(f->c[j].model) != t)
            return "mixed";
    return t->name;
}

int
lf_fit_solve_begin(lf_fit *f, const fit_start *start, fit_run *run, lf_fit_result *res,
                   lf_error *err)
{
    int status;

    memset(res, 0, sizeof *res);
    status = lf_fit_solve_run(f, start, run, &res->warnings, err);
    res->iterations = run->iters;
    res->reweightings = run->reweightings;
    if (status != LF_OK) {
        lf_warnings_free(&res->warnings);
        return status;
    }
    res->evaluations = run->evals;
    return LF_OK;
}

int
lf_fit_solve(lf_fit *f, const fit_start *start, lf_fit_result *res, lf_error *err)
{
    fit_run run;
    int status = lf_fit_solve_begin(f, start, &run, res, err);

    return status != LF_OK ? status : lf_fit_solve_end(f, &run, res, err);
}

int
lf_fit_solve_end(lf_fit *f, const fit_run *run, lf_fit_result *res, lf_error *err)
{
    return lf_fit_solve_end_at(f, run, res, NULL, err);
}

int
lf_fit_solve_end_at(lf_fit *f, const fit_run *run, lf_fit_result *res, size_t *loo_at,
                    lf_error *err)
{
    gsl_vector *x = f->ws.x;
    int status;
    size_t i;

    status = lf_fit_assess(f, x->data, run, res, err);
    if (status != LF_OK) {
        lf_fit_result_free(res);
        return status;
    }
    res->converged = run->converged;
    res->stop = run->stop;
    snprintf(res->stop_reason, sizeof res->stop_reason, "%s", run->why);
    if (loo_at != NULL)
        *loo_at = FIT_LOO_NONE;
    if (lf_fit_loo_due(res)) {
        if (loo_at != NULL)
            *loo_at = res->warnings.n;      /* its words go here when it runs */
        else
            lf_fit_leave_one_out(f, res);
    }
    res->method = f->set.method;
    res->loss = lf_loss_name(f->set.loss);
    res->model = model_name(f);
    res->model_rounds = 1;
    for (i = 0; i < f->ncurves; i++) {
        res->curves[i].model = lf_model_get_type(f->c[i].model)->name;
        snprintf(res->curves[i].model_reason, sizeof res->curves[i].model_reason,
                 "as requested");
        res->curves[i].thin_bias = NAN;
        res->curves[i].thin_bias_se[0] = res->curves[i].thin_bias_se[1] = NAN;
        res->curves[i].thin_bias_se[2] = NAN;
    }
    if (!run->converged) {
        lf_warn(&res->warnings, "the fit did not converge (%s): the numbers below are where it "
                "stopped", run->why);
        return LF_ENOCONV;
    }
    lf_fit_degenerate_end(res);
    return res->converged ? LF_OK : LF_ENOCONV;
}

const char *
lf_fit_stop_name(lf_fit_stop stop)
{
    switch (stop) {
    case LF_STOP_CONVERGED: return "converged";
    case LF_STOP_ITERATIONS: return "iteration limit";
    case LF_STOP_NO_PROGRESS: return "no progress";
    case LF_STOP_STALLED: return "stalled";
    case LF_STOP_DEAD_PARAMETER: return "parameter without effect";
    case LF_STOP_RAN_AWAY: return "ran away";
    case LF_STOP_REWEIGHTING: return "weights moving";
    case LF_STOP_DEGENERATE: return "degenerate";
    case LF_STOP_FAILED: return "failed";
    }
    return "unknown";
}

int
lf_fit_run_begin(lf_fit *f, fit_run *run, lf_fit_result *res, lf_error *err)
{
    int status;

    fit_start start;

    memset(res, 0, sizeof *res);
    lf_fit_invalidate(f);
    status = lf_fit_refuse_degenerate(f, err);
    if (status != LF_OK)
        return status;
    status = lf_fit_guess(f, &start, err);
    if (status != LF_OK)
        return status;
    return lf_fit_solve_begin(f, &start, run, res, err);
}

int
lf_fit_run(lf_fit *f, lf_fit_result *res, lf_error *err)
{
    fit_run run;
    int status = lf_fit_run_begin(f, &run, res, err);

    return status != LF_OK ? status : lf_fit_solve_end(f, &run, res, err);
}

int
lf_fit_driver(const lf_fit_settings *settings, size_t ncurves,
              const lf_fit_curve *curves, lf_fit_result *res, lf_error *err)
{
    lf_fit *f = lf_fit_alloc(settings, ncurves, curves, err);
    int status;

    memset(res, 0, sizeof *res);
    if (f == NULL)
        return err ? err->status : LF_EINVAL;
    status = lf_fit_run(f, res, err);
    lf_fit_free(f);
    return status;
}

int
lf_fit_check_jacobian(lf_fit *f, const lf_material *mat, double *max_rel_err,
                      lf_error *err)
{
    gsl_vector *x = gsl_vector_alloc(f->np), *r1 = gsl_vector_alloc(f->nres);
    gsl_vector *r2 = gsl_vector_alloc(f->nres);
    gsl_matrix *J = gsl_matrix_alloc(f->nres, f->np);
    size_t i, k;
    int status = LF_OK;

    *max_rel_err = 0.0;
    if (!x || !r1 || !r2 || !J) {
        status = lf_fail(err, LF_ENOMEM, "out of memory");
        goto done;
    }
    f->mat = *mat;
    for (i = 0; i < f->ncurves; i++)
        f->c[i].slope = 0.0;
    lf_fit_set_origin(f);
    gsl_vector_set_all(x, 1.0);
    if (lf_fit_jacobian(x, f, J) != GSL_SUCCESS) {
        status = lf_fail(err, LF_ENUMERIC, "the model cannot be evaluated");
        goto done;
    }
    for (k = 0; k < f->np; k++) {
        const double h = 1e-6;
        double colmax = 0.0, worst = 0.0;
        gsl_vector_set(x, k, 1.0 + h);
        status = lf_fit_residuals(x, f, r1);
        gsl_vector_set(x, k, 1.0 - h);
        status |= lf_fit_residuals(x, f, r2);
        gsl_vector_set(x, k, 1.0);
        if (status != GSL_SUCCESS) {
            status = lf_fail(err, LF_ENUMERIC, "the model cannot be evaluated");
            goto done;
        }
        for (i = 0; i < f->nres; i++) {
            double fd = (gsl_vector_get(r1, i) - gsl_vector_get(r2, i)) / (2 * h);
            colmax = lf_fmax(colmax, fabs(gsl_matrix_get(J, i, k)));
            worst = lf_fmax(worst, fabs(fd - gsl_matrix_get(J, i, k)));
        }
        if (colmax > 0)
            *max_rel_err = lf_fmax(*max_rel_err, worst / colmax);
    }
done:
    gsl_vector_free(x);
    gsl_vector_free(r1);
    gsl_vector_free(r2);
    gsl_matrix_free(J);
    return status;
}
