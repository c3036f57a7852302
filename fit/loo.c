/* loo.c: leave one out, a policy run only when every one of three or
 * more curves disagrees with the joint fit.  Contract: refit without each
 * curve in turn (guess and solve, no further leave-one-out) and name the
 * one whose absence lets all the others agree, or say the disagreement is
 * general. */
#include <math.h>
#include <stdlib.h>

#include "fit.h"

/* Every curve of three or more disagrees with the joint fit: refit
 * without each in turn.  When exactly one curve's absence lets all the
 * others agree, that curve is named; when none or several do, the
 * disagreement is reported as general. */
void
lf_fit_leave_one_out(lf_fit *f, lf_fit_result *res)
{
    size_t j, i, m, culprit = 0, ncul = 0, n = f->ncurves;
    lf_fit_curve *sub = malloc(n * sizeof *sub);
    double *worst = malloc(n * sizeof *worst);
    lf_material *mat = malloc(n * sizeof *mat);

    if (sub == NULL || worst == NULL || mat == NULL)
        goto done;
    for (j = 0; j < n; j++) {
        lf_fit *g;
        lf_fit_result r;
        fit_start start;
        int ok = 1, st;
        for (i = 0, m = 0; i < n; i++)
            if (i != j)
                sub[m++] = f->c[i].data;
        worst[j] = HUGE_VAL;
        g = lf_fit_alloc(&f->set, m, sub, NULL);
        if (g == NULL)
            continue;
        st = lf_fit_guess(g, &start, NULL);
        if (st == LF_OK)
            st = lf_fit_solve(g, &start, 0, &r, NULL);
        if (st == LF_ENOCONV)
            lf_fit_result_free(&r);
        if (st == LF_OK) {
            worst[j] = 0.0;
            for (i = 0; i < m; i++) {
                ok &= r.curves[i].consistent;
                worst[j] = lf_fmax(worst[j], r.curves[i].chi2_per_point);
            }
            mat[j].w = r.w.value;
            mat[j].Estar = r.Estar.value;
            if (ok) {
                culprit = j;
                ncul++;
            }
            lf_fit_result_free(&r);
        }
        lf_fit_free(g);
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
    free(sub);
    free(worst);
    free(mat);
}

