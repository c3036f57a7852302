/* reweight.c: a robust loss, a policy run only when the settings ask for
 * one.  Contract: from the least-squares solution at x, iteratively
 * reweighted least squares until the weights settle.
 *
 * With u the residual in units of loss_scale noise sd, the weights are
 * min(1, 1/|u|) (Huber) or 1/(1 + u^2) (Cauchy); each round refits from
 * where the last ended, until no weight's square root moves by more than
 * FIT_REWEIGHT_TOL (at most FIT_MAX_REWEIGHT rounds).
 *
 * The noise sd that u is measured in is, per curve, the larger of the
 * noise model's (noise.c: correlated noise of real curves is larger than
 * the point-to-point estimate) and 1.4826 times the median absolute
 * residual of the least-squares solution: a robust loss down-weights the
 * few points that stand out, never most of a curve. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "fit.h"

int
lf_fit_reweight(lf_fit *f, gsl_vector *x, fit_run *run, lf_error *err)
{
    const double scale = !isnan(f->set.loss_scale) ? f->set.loss_scale
                         : f->set.loss == LF_LOSS_HUBER ? 1.345 : 2.385;
    gsl_vector *r = f->ws.r;
    size_t round, k, j;
    int status = LF_OK;
    double *inflate = malloc((f->ncurves ? f->ncurves : 1) * sizeof *inflate);

    if (inflate == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory");
    if (lf_fit_residuals(x, f, r) != GSL_SUCCESS) {
        free(inflate);
        return lf_fail(err, LF_ENUMERIC, "the model cannot be evaluated while reweighting");
    }
    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        double tau, noise, mad;
        size_t i;
        lf_fit_curve_noise(f, j, r, &tau, &noise);
        for (i = 0; i < c->data.n; i++)
            f->ws.work[i] = fabs(gsl_vector_get(r, c->row + i));
        mad = 1.4826 * lf_fit_median(f->ws.work, c->data.n);   /* units of sigma */
        inflate[j] = lf_fmax(1.0, lf_fmax(noise / c->sigma, mad));
    }
    for (round = 0; round < FIT_MAX_REWEIGHT; round++) {
        double moved = 0.0;
        if (lf_fit_residuals(x, f, r) != GSL_SUCCESS) {
            free(inflate);
            return lf_fail(err, LF_ENUMERIC, "the model cannot be evaluated while reweighting");
        }
        for (j = 0; j < f->ncurves; j++)
        for (k = f->c[j].row; k < f->c[j].row + f->c[j].data.n; k++) {
            double u = fabs(gsl_vector_get(r, k) / f->ws.sqrtw[k]) / (scale * inflate[j]), wt, s;
            wt = f->set.loss == LF_LOSS_HUBER ? (u <= 1.0 ? 1.0 : 1.0 / u) : 1.0 / (1.0 + u * u);
            s = sqrt(wt);
            moved = lf_fmax(moved, fabs(s - f->ws.sqrtw[k]));
            f->ws.sqrtw[k] = s;
        }
        lf_fit_invalidate(f);
        run->reweightings = round + 1;
        if (moved < FIT_REWEIGHT_TOL)
            break;
        status = lf_fit_solve_scanned(f, x, 0, run, err);
        if (status != LF_OK) {
            free(inflate);
            return status;
        }
    }
    free(inflate);
    if (round == FIT_MAX_REWEIGHT) {
        lf_fit_run_says(run, LF_STOP_REWEIGHTING, "not converged: the robust weights still "
                        "move after %d rounds", FIT_MAX_REWEIGHT);
    }
    return status;
}
