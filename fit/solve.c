/* solve.c: the solve of one fit from its origin and the restarts the data
 * call for, without the assessment:
 *
 *   solve      lf_fit_solve_scanned (iterate.c + edge_scan.c)
 *   restarts   a second start from the automatic guess when the user gave
 *              one, or from the guess's runner-up w, or from a higher w when
 *              a few shallow points end out of contact (second_start.c);
 *              robust reweighting when the loss is not linear (reweight.c)
 *   end        the honest end (verdict.c)
 *
 * Calls go down only: the driver (driver.c), the held refits of profiles
 * (hold.c) and leave-one-out (loo.c) call this file, which calls none of
 * them. */
#include <math.h>
#include <string.h>

#include "fit.h"

int
lf_fit_solve_run(lf_fit *f, const fit_start *start, fit_run *run_out, lf_warnings *warn,
                 lf_error *err)
{
    gsl_vector *x = f->ws.x;
    fit_run run;
    int status;
    size_t i;

    memset(&run, 0, sizeof run);
    lf_fit_invalidate(f);
    for (i = 0; i < f->ndata; i++)
        f->ws.sqrtw[i] = 1.0;
    status = lf_fit_solve_scanned(f, x, 1, &run, err);
    if (status == LF_OK && start != NULL && start->user) {
        /* A user's starting point is a second start, not a replacement:
         * the cost has kinks wherever a point crosses the contact edge, and
         * a start a factor of 3 off can end in a minimum whose misfit,
         * local to the edge, neither chi2 (the noise is only estimated)
         * nor the runs test reliably shows.  So the fit is repeated from
         * the automatic guess and the lower cost wins. */
        double ratio;
        status = lf_fit_second_start(f, x, &start->automatic, &run, &ratio, err);
        if (status == LF_OK && ratio > 1.0 && warn != NULL)
            lf_warn(warn, "the fit from the given starting point (w = %.4g J/m^2, "
                    "E* = %.4g Pa) ended at a cost %.4g times higher than from the automatic "
                    "guess; the result below starts from the automatic guess",
                    start->mat.w, start->mat.Estar, ratio);
    }
    if (status == LF_OK && start != NULL && isfinite(start->alt_w)) {
        /* the automatic guess's runner-up, when close: another basin */
        lf_material alt = start->automatic;
        double ratio;
        alt.w = start->alt_w;
        status = lf_fit_second_start(f, x, &alt, &run, &ratio, err);
    }
    if (status == LF_OK && start != NULL && f->imat[FIT_W] >= 0 && lf_fit_edge_doubt(f, x)) {
        /* a few shallow points out of contact: w (and with it the contact
         * radius at detachment) may be stuck low; start again higher */
        lf_material up;
        double z0, F0, slope, ratio;
        lf_fit_unpack(f, x->data, &up, &z0, &F0, &slope, f->ncurves);
        up.w *= FIT_EDGE_W_UP;
        status = lf_fit_second_start(f, x, &up, &run, &ratio, err);
    }
    if (status == LF_OK && f->set.loss != LF_LOSS_LINEAR)
        status = lf_fit_reweight(f, x, &run, err);
    if (status == LF_OK)
        status = lf_fit_honest_end(f, x, &run, err);
    *run_out = run;
    return status;
}
