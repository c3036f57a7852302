/* second_start.c: a second start, a policy for costs with more than one
 * basin.  Contract: solve again from another material (the user's guess
 * against the automatic one, or the guess's runner-up w), every curve's
 * offsets profiled there, and keep whichever solution has the lower cost.
 *
 * The cost has kinks wherever a point crosses the contact edge, so a start
 * a factor of a few off can end in another minimum.  One such minimum is
 * common enough to look for: w too low, and with it the contact radius at
 * detachment, so that a few of a curve's shallowest points fall out of
 * contact where the data have no baseline to say so (a true baseline
 * leaves many points out).  lf_fit_edge_doubt finds it; the driver then
 * starts again from FIT_EDGE_W_UP times the w found.  A start whose
 * material the first solution already lies next to (within FIT_ALT_LOG_SEP
 * in ln w and ln E*) would find that solution again and is not run. */
#include <math.h>
#include <string.h>

#include "fit.h"

/* 1 when the material at x is within FIT_ALT_LOG_SEP of `from` in ln w and
 * ln E* (and nu within FIT_ALT_LOG_SEP / 4, its range being a quarter). */
static int
same_basin(lf_fit *f, const gsl_vector *x, const lf_material *from)
{
    lf_material m;
    double z0, F0, slope;

    lf_fit_unpack(f, x->data, &m, &z0, &F0, &slope, f->ncurves);
    return fabs(log(m.w / from->w)) < FIT_ALT_LOG_SEP
           && fabs(log(m.Estar / from->Estar)) < FIT_ALT_LOG_SEP
           && fabs(m.nu - from->nu) < 0.25 * FIT_ALT_LOG_SEP;
}

/* The first solution x (cost `cost`) as the basin the second start stops
 * in, when it converged: its internal coordinates and FIT_SAME_SE of each
 * standard error (from the solver's last look at its Jacobian, which must
 * have been at x; else no basin is set). */
static void
set_basin(lf_fit *f, const gsl_vector *x, double cost, int converged)
{
    const double chi2dof = 2.0 * cost / (double) (f->nres > f->np ? f->nres - f->np : 1);
    size_t k;

    f->ws.basin_on = f->ws.basin_hit = 0;
    if (!converged || !lf_fit_gn_at(f, x))
        return;
    for (k = 0; k < f->np; k++) {
        f->ws.basin_x[k] = f->x0_internal[k] + x->data[k] - 1.0;
        f->ws.basin_tol[k] = FIT_SAME_SE * sqrt(chi2dof * f->ws.ainv[k]);
        if (!(f->ws.basin_tol[k] > 0))
            return;
    }
    f->ws.basin_cost = cost;
    f->ws.basin_on = 1;
}

int
lf_fit_second_start(lf_fit *f, gsl_vector *x, const lf_material *from, fit_run *run,
                 double *ratio, lf_error *err)
{
    double cost_first, cost_second, *keep = f->ws.keep;
    lf_material mat_first;
    fit_run second;
    int status, win, same;
    size_t j;

    *ratio = 1.0;
    if (same_basin(f, x, from))
        return LF_OK;
    cost_first = lf_fit_cost(f, x, f->ws.r);
    set_basin(f, x, cost_first, run->converged);
    lf_fit_rebase(f, x);
    mat_first = f->mat;
    for (j = 0; j < f->ncurves; j++) {
        keep[3 * j] = f->c[j].z0;
        keep[3 * j + 1] = f->c[j].F0;
        keep[3 * j + 2] = f->c[j].slope;
    }
    f->mat = *from;
    lf_fit_guess_offsets(f);
    memset(&second, 0, sizeof second);
    status = lf_fit_solve_scanned(f, x, 1, &second, err);
    same = f->ws.basin_hit;
    f->ws.basin_on = f->ws.basin_hit = 0;
    run->iters += second.iters;
    run->evals += second.evals;
    if (status != LF_OK)
        return status;
    cost_second = same ? HUGE_VAL : lf_fit_cost(f, x, f->ws.r);
    /* a converged run beats an unconverged one at about the same cost; else
     * the lower cost wins, an unconverged run only by a clear margin */
    win = (second.converged && !run->converged
           && cost_second <= cost_first * (1.0 + FIT_SECOND_TIE_REL))
          || (second.converged == run->converged
              && cost_second < cost_first * (1.0 - FIT_SECOND_WIN_REL))
          || (!second.converged && run->converged
              && cost_second < cost_first * (1.0 - FIT_SECOND_CLEAR_REL));
    if (win) {
        *ratio = cost_first / cost_second;
        lf_fit_run_verdict_from(run, &second);
        return LF_OK;
    }
    f->mat = mat_first;
    for (j = 0; j < f->ncurves; j++) {
        f->c[j].z0 = keep[3 * j];
        f->c[j].F0 = keep[3 * j + 1];
        f->c[j].slope = keep[3 * j + 2];
    }
    lf_fit_set_origin(f);
    gsl_vector_set_all(x, 1.0);
    return LF_OK;
}

int
lf_fit_edge_doubt(lf_fit *f, const gsl_vector *x)
{
    size_t j, i;

    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        lf_material m;
        lf_pulloff po;
        double z0, F0, slope, edge;
        size_t out = 0;

        if (c->iz0 < 0)
            continue;
        lf_fit_unpack(f, x->data, &m, &z0, &F0, &slope, j);
        if (lf_model_pulloff(c->model, &m, &po, NULL) != LF_OK)
            continue;
        edge = c->data.branch == LF_BRANCH_UNLOAD ? z0 + po.delta_detach : z0;
        for (i = 0; i < c->data.n; i++)
            out += c->data.depth[i] < edge;
        if (out > 0 && out < FIT_EDGE_FEW_OUT)
            return 1;
    }
    return 0;
}
