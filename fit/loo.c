/* loo.c: leave one out, a policy run only when every one of three or
 * more curves disagrees with the joint fit.  Contract: refit without each
 * curve in turn (guess, solve and assess: guess.c, solve.c, uncertainty.c,
 * never the driver that called this) and name the one whose absence lets
 * all the others agree, or say the disagreement is general. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit.h"

/* The fit g from its automatic guess, solved and assessed as the driver
 * does but without leave-one-out: 1 with *r filled when it converged to
 * an answer (not degenerate), else 0 and *r empty.  With g->k2_waits the
 * assessment leaves out the k = 2 check's refit (a joint fit again, with
 * w held higher), taking w as not open above (see leave_one_out). */
static int
refit(lf_fit *g, lf_fit_result *r)
{
    fit_start start;
    fit_run run;

    memset(r, 0, sizeof *r);
    if (lf_fit_guess(g, &start, NULL) != LF_OK
        || lf_fit_solve_run(g, &start, &run, NULL, NULL) != LF_OK || !run.converged)
        return 0;
    if (lf_fit_assess(g, g->ws.x->data, &run, r, NULL) != LF_OK) {
        lf_fit_result_free(r);
        return 0;
    }
    r->converged = 1;
    lf_fit_degenerate_end(r);
    if (!r->converged) {
        lf_fit_result_free(r);
        return 0;
    }
    return 1;
}

int
lf_fit_loo_due(const lf_fit_result *res)
{
    size_t j, bad = 0;

    for (j = 0; j < res->ncurves; j++)
        bad += !res->curves[j].consistent;
    return res->ncurves >= 3 && bad == res->ncurves;
}

/* w's verdict decides whether the fit r is degenerate: no other material
 * parameter (nor M) is determined. */
static int
w_decides(const lf_fit_result *r)
{
    return !(r->Estar.free && r->Estar.determined) && !(r->nu.free && r->nu.determined)
           && !r->M.determined;
}

/* Every curve of three or more disagrees with the joint fit: refit
 * without each in turn (the curves f's, or cc[0..n-1] under s where f is
 * NULL, like then lending its layout to the first refit).  When exactly
 * one curve's absence lets all the others agree, that curve is named;
 * when none or several do, the disagreement is reported as general.
 *
 * Each refit is first assessed without the k = 2 check's refit, which
 * can only take w's verdict away (judge.c: the other estimates, every
 * curve's residuals and so its agreement do not depend on it).  What is
 * read here of a refit needs that verdict only where the refit is a
 * candidate (its curves all agree: its w is then quoted) or where w's
 * verdict alone decides whether it is degenerate; there the refit is
 * made again with the check, as it was before, so every answer is the
 * same. */
static void
leave_one_out(const lf_fit_settings *s, size_t n, const lf_fit *f, const lf_fit_curve *cc,
              const lf_fit *like, lf_fit_result *res)
{
    size_t j, i, m, culprit = 0, ncul = 0;
    lf_fit_curve *sub = malloc(n * sizeof *sub);
    double *worst = malloc(n * sizeof *worst);
    lf_material *mat = malloc(n * sizeof *mat);
    /* the last refit's fit: its curves' layout (all but one of the next
     * refit's curves) lends the next one its depth orders and noise */
    lf_fit *prev = NULL;

    if (sub == NULL || worst == NULL || mat == NULL)
        goto done;
    /* a second curve whose absence helps settles the words (several help):
     * the other refits would change nothing said */
    for (j = 0; j < n && ncul < 2; j++) {
        lf_fit *g;
        lf_fit_result r;
        int ok = 1;
        for (i = 0, m = 0; i < n; i++)
            if (i != j)
                sub[m++] = f != NULL ? f->c[i].data : cc[i];
        worst[j] = HUGE_VAL;
        g = lf_fit_alloc_like(s, m, sub, f != NULL ? f : prev != NULL ? prev : like, NULL);
        if (g == NULL)
            continue;
        g->k2_waits = 1;
        if (refit(g, &r)) {
            for (i = 0; i < m; i++)
                ok &= r.curves[i].consistent;
            if (g->k2_waited && (ok || w_decides(&r))) {
                lf_fit_result_free(&r);
                lf_fit_free(prev);
                prev = g;
                g = lf_fit_alloc_like(s, m, sub, prev, NULL);
                if (g == NULL || !refit(g, &r)) {
                    lf_fit_free(g);
                    continue;
                }
                for (i = 0, ok = 1; i < m; i++)
                    ok &= r.curves[i].consistent;
            }
            worst[j] = 0.0;
            for (i = 0; i < m; i++)
                worst[j] = lf_fmax(worst[j], r.curves[i].chi2_per_point);
            mat[j].w = r.w.value;
            mat[j].Estar = r.Estar.value;
            if (ok) {
                culprit = j;
                ncul++;
            }
            lf_fit_result_free(&r);
        }
        lf_fit_free(prev);     /* the next refit's layout from this one's */
        prev = g;
    }
    if (ncul == 1) {
        const lf_fit_curve_result *cr = &res->curves[culprit];
        for (j = 0; j < n; j++)
            res->curves[j].consistent = j != culprit;
        lf_warn(&res->warnings, "curve %zu (%s) disagrees with the others: its residuals are "
                "%.3g times its noise (runs test z = %.3g); fitted without it, the other curves "
                "agree (chi2/point at most %.3g; w = %.4g J/m^2, E* = %.4g Pa): check its k, R, "
                "b, interface and segment", culprit + 1, cr->name ? cr->name : "",
                sqrt(cr->chi2_per_point), cr->runs_z, worst[culprit], mat[culprit].w,
                mat[culprit].Estar);
    } else {
        lf_warn(&res->warnings, "the curves disagree with the model fitted to them all, and %s "
                "(chi2/point of the worst curve %.3g): check the model and each curve's probe",
                ncul == 0 ? "leaving out any one curve does not help"
                          : "leaving out one of several curves helps",
                res->curves[0].chi2_per_point);
    }
done:
    lf_fit_free(prev);
    free(sub);
    free(worst);
    free(mat);
}


void
lf_fit_leave_one_out(lf_fit *f, lf_fit_result *res)
{
    leave_one_out(&f->set, f->ncurves, f, NULL, NULL, res);
}

void
lf_fit_leave_one_out_at(const lf_fit_settings *s, size_t n, const lf_fit_curve *cc,
                        lf_fit_result *res, size_t at, const lf_fit *like)
{
    lf_warnings *w = &res->warnings;
    size_t n0 = w->n, i;

    leave_one_out(s, n, NULL, cc, like, res);
    if (at >= n0)
        return;
    /* its words where the assessment would have put them: rotate the new
     * messages w[n0..] in front of w[at..n0) */
    for (i = n0; i < w->n; i++) {
        char *m = w->msg[i];
        memmove(w->msg + at + 1, w->msg + at, (i - at) * sizeof *w->msg);
        w->msg[at++] = m;
    }
}
