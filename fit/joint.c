/* joint.c: a fit of several curves of one material, honest about how
 * they differ (lf_fit_joint; the steps are in layerfit.h):
 *
 *   joint fit A   from the automatic guess (choose.c or driver.c)
 *   singles       each curve alone, nu held at A's value where A fitted it
 *                 (bonded and frictionless curves together: a curve alone
 *                 would not fix it)
 *   joint fit B   from the pooled singles: the material at their
 *                 random-effects mean (hetero.c), each curve's offsets at
 *                 its own fit's, with the models A chose; the lower chi2
 *                 of A and B is the fit
 *   assessment    of the winner alone where it can wait (A from the
 *                 automatic guess, not the auto model choice, which
 *                 assesses its own rounds; B always): the chi2 of each
 *                 run decides, and the loser's assessment (its
 *                 decomposition, the k = 2 check's refit, leave-one-out's
 *                 N refits) would be thrown away
 *   intervals     lf_fit_profile (profile.c, after descend.c's search)
 *   spread        lf_heterogeneity_of over the singles (hetero.c)
 *
 * Two starts because the cost of real curves is a staircase of basins (a
 * jump wherever a point crosses the model's abrupt contact edge): the
 * automatic guess and the pooled singles land in different ones as often
 * as not, and the lower is the estimate. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "fit.h"

/* Fit one curve alone into *e (its estimates, NaN where not determined or
 * not converged) and off[0..2] (its offsets at the solution, NaN where
 * none); nu held at the joint fit's where that fitted it (see the top);
 * like (NULL: none), a fit of the curves, lends its layout to the fit and
 * its profile's. */
static void
single(const lf_fit_settings *settings, const lf_choose_settings *choose,
       const lf_fit_curve *curve, double nu, const lf_fit *like, lf_curve_estimate *e,
       double *off)
{
    lf_fit_settings s = *settings;
    lf_fit_result r;
    int st;

    lf_curve_estimate_none(e, &curve->probe);
    off[0] = off[1] = off[2] = NAN;
    if (s.nu.mode == LF_PARAM_AUTO && isfinite(nu)) {
        s.nu.mode = LF_PARAM_FIXED;
        s.nu.value = nu;
    }
    if (choose != NULL) {
        lf_choose_settings cs = *choose;
        cs.thin_comparison = 0;
        st = lf_fit_choose_driver(&s, &cs, 1, curve, &r, NULL);
    } else {
        /* lf_fit_driver, its fit's layout from like */
        lf_fit *f = lf_fit_alloc_like(&s, 1, curve, like, NULL);
        memset(&r, 0, sizeof r);
        st = f != NULL ? lf_fit_run(f, &r, NULL) : LF_EINVAL;
        lf_fit_free(f);
    }
    if (st != LF_OK && st != LF_ENOCONV)
        return;
    lf_fit_profile_at(&s, 1, curve, &r, LF_PROFILE_SCREEN, FIT_LOO_NONE, like, NULL);
    if (r.converged)
        lf_curve_estimate_of(&r, e);
    off[0] = lf_fit_best_value(&r, "z0[1]", NAN);
    off[1] = lf_fit_best_value(&r, "F0[1]", NAN);
    off[2] = lf_fit_best_value(&r, "s[1]", NAN);
    lf_fit_result_free(&r);
}

/* Joint fit A: assessed in the result (a == NULL), or its run's solution
 * in a, assessed only when it wins (see the top). */
typedef struct {
    lf_fit *a;
    fit_run run;
} joint_a;

/* A's material at its solution (held values as held) and its models into
 * model[0..n-1]; *nu_free whether A fitted nu.  The values are those its
 * assessment reports (lf_fit_assess unpacks the same x). */
static lf_material
a_solution(const joint_a *ja, const lf_fit_result *res, size_t n, const lf_model_type **model,
           int *nu_free)
{
    static const char *const name[3] = { "w", "E*", "nu" };
    lf_material m;
    size_t j;

    if (ja->a != NULL) {
        double z0, F0, slope;
        lf_fit_unpack(ja->a, ja->a->ws.x->data, &m, &z0, &F0, &slope, n);
        *nu_free = ja->a->imat[FIT_NU] >= 0;
        for (j = 0; j < n; j++)
            model[j] = lf_model_get_type(ja->a->c[j].model);
        return m;
    }
    m.w = lf_fit_best_value(res, name[0], res->w.value);
    m.Estar = lf_fit_best_value(res, name[1], res->Estar.value);
    m.nu = lf_fit_best_value(res, name[2], res->nu.value);
    *nu_free = isfinite(lf_fit_best_value(res, name[2], NAN));
    for (j = 0; j < n; j++)
        model[j] = res->curves[j].model != NULL ? lf_model_type_find(res->curves[j].model) : NULL;
    return m;
}

/* The start of joint fit B: the singles' population mean of each material
 * parameter where two or more curves determine it, the one curve's where
 * one does, else A's solution (a). */
static lf_material
pooled(const lf_heterogeneity *h, const lf_material *a, size_t n, const lf_curve_estimate *each)
{
    const lf_population_estimate *pe[3] = { &h->w, &h->Estar, &h->nu };
    const double av[3] = { a->w, a->Estar, a->nu };
    double v[3];
    int m;

    for (m = 0; m < 3; m++) {
        size_t i;
        v[m] = pe[m]->population_mean;
        for (i = 0; i < n && !isfinite(v[m]); i++)
            if (pe[m]->n == 1 && isfinite(each[i].value[m]))
                v[m] = each[i].value[m];
        if (!isfinite(v[m]))
            v[m] = av[m];
    }
    return (lf_material) { v[0], v[1], v[2] };
}

/* Joint fit B from mat and the singles' offsets (NaN: profiled at mat),
 * on A's models (model[j], NULL: the curve's own; like, A's fit where it
 * waits, lends its layout), nu where held by mat
 * out of range at nu_a: its run, not assessed, in *fb (at its solution)
 * and *run, b holding the run's totals; LF_EINVAL when it cannot be
 * made. */
static int
from_pooled(const lf_fit_settings *s, size_t n, const lf_fit_curve *curves, const lf_fit *like,
            const lf_model_type *const *model, double nu_a, const lf_material *mat,
            const double *off, lf_fit **fb, fit_run *run, lf_fit_result *b)
{
    lf_fit_curve *cc = malloc(n * sizeof *cc);
    lf_fit *f;
    size_t j;
    int st;

    memset(b, 0, sizeof *b);
    *fb = NULL;
    if (cc == NULL)
        return LF_ENOMEM;
    for (j = 0; j < n; j++) {
        cc[j] = curves[j];
        if (model[j] != NULL)
            cc[j].model = model[j];
    }
    f = lf_fit_alloc_like(s, n, cc, like, NULL);
    free(cc);
    if (f == NULL || !(mat->w > 0) || !(mat->Estar > 0)) {
        lf_fit_free(f);
        return LF_EINVAL;
    }
    /* what is held stays at its value (lf_fit_alloc put it in f->mat) */
    if (f->imat[FIT_W] >= 0)
        f->mat.w = mat->w;
    if (f->imat[FIT_E] >= 0)
        f->mat.Estar = mat->Estar;
    if (f->imat[FIT_NU] >= 0)
        f->mat.nu = mat->nu > 0 && mat->nu < 0.5 ? mat->nu : nu_a;
    lf_fit_guess_offsets(f);
    for (j = 0; j < n; j++) {
        if (f->c[j].iz0 >= 0 && isfinite(off[3 * j]))
            f->c[j].z0 = off[3 * j];
        if (f->c[j].iF0 >= 0 && isfinite(off[3 * j + 1]))
            f->c[j].F0 = off[3 * j + 1];
        if (f->c[j].islope >= 0)
            f->c[j].slope = isfinite(off[3 * j + 2]) ? off[3 * j + 2] : 0.0;
    }
    lf_fit_set_origin(f);
    st = lf_fit_solve_begin(f, NULL, run, b, NULL);
    if (st != LF_OK) {
        lf_fit_free(f);
        return st;
    }
    *fb = f;
    return LF_OK;
}

/* chi2 of f at its run's solution (the assessment's sum, bit for bit). */
static double
run_chi2(lf_fit *f)
{
    double ss = HUGE_VAL;

    if (lf_fit_residuals_ss(f, f->ws.x, f->ws.r, &ss) != GSL_SUCCESS)
        return HUGE_VAL;
    return ss;
}

/* Assess A where it waited (ja->a), into res: its status; *loo_at where
 * its leave-one-out's words go (lf_fit_solve_end_at). */
static int
a_assess(joint_a *ja, lf_fit_result *res, size_t *loo_at, lf_error *err)
{
    int st = LF_OK;

    if (ja->a != NULL) {
        st = lf_fit_solve_end_at(ja->a, &ja->run, res, loo_at, err);
        lf_fit_free(ja->a);
        ja->a = NULL;
    }
    return st;
}

int
lf_fit_joint(const lf_fit_settings *settings, const lf_choose_settings *choose,
             size_t n, const lf_fit_curve *curves, int intervals, lf_fit_result *res,
             lf_error *err)
{
    lf_curve_estimate *each = NULL;
    const lf_model_type **model = NULL;
    double *off = NULL;
    joint_a ja;
    lf_fit *like = NULL;        /* B's fit, whose layout the profile's fits take */
    lf_error perr;
    /* res's leave-one-out, left waiting for the result finally reported
     * (lf_fit_profile_at): the descent or a profile may replace res */
    size_t loo_at = FIT_LOO_NONE, loo_b = FIT_LOO_NONE;
    size_t j;
    int st;

    memset(res, 0, sizeof *res);
    memset(&ja, 0, sizeof ja);
    if (n >= 2 && choose == NULL) {
        /* A's assessment waits for B's run (see the top) */
        if ((ja.a = lf_fit_alloc(settings, n, curves, err)) == NULL)
            return err ? err->status : LF_EINVAL;
        st = lf_fit_run_begin(ja.a, &ja.run, res, err);
        if (st != LF_OK) {
            lf_fit_free(ja.a);
            return st;
        }
    } else {
        st = choose != NULL ? lf_fit_choose_driver(settings, choose, n, curves, res, err)
                            : lf_fit_driver(settings, n, curves, res, err);
        if (st != LF_OK && st != LF_ENOCONV)
            return st;
    }
    if (n >= 2) {
        lf_heterogeneity h;
        lf_material ma;
        int nu_free;
        each = malloc(n * sizeof *each);
        off = malloc(3 * n * sizeof *off);
        model = malloc(n * sizeof *model);
        if (each == NULL || off == NULL || model == NULL) {
            free(each);
            free(off);
            free(model);
            lf_fit_free(ja.a);
            lf_fit_result_free(res);
            return lf_fail(err, LF_ENOMEM, "out of memory");
        }
        ma = a_solution(&ja, res, n, model, &nu_free);
        for (j = 0; j < n; j++)
            single(settings, choose, &curves[j], nu_free ? ma.nu : NAN, ja.a, &each[j],
                   off + 3 * j);
        if (lf_heterogeneity_of(n, each, &h, NULL) == LF_OK) {
            lf_material m = pooled(&h, &ma, n, each);
            lf_fit_result b;
            lf_fit *fb;
            fit_run rb;
            int sb = from_pooled(settings, n, curves, ja.a, model, nu_free ? ma.nu : 0.25, &m, off,
                                 &fb, &rb, &b);
            int lower = sb == LF_OK
                        && run_chi2(fb) < (ja.a != NULL ? run_chi2(ja.a) : res->chi2) * (1.0 - 1e-9);
            /* B wins where it converged like A, or better, at a lower chi2:
             * assessed only then (and A, where it waited and B did not
             * converge) */
            if (lower) {
                sb = lf_fit_solve_end_at(fb, &rb, &b, &loo_b, NULL);
                if ((sb == LF_OK || sb == LF_ENOCONV) && !b.converged && ja.a != NULL)
                    st = a_assess(&ja, res, &loo_at, err);
            }
            if (st != LF_OK && st != LF_ENOCONV) {
                if (sb == LF_OK || sb == LF_ENOCONV)
                    lf_fit_result_free(&b);
                lf_fit_free(fb);
                free(each);
                free(off);
                free(model);
                return st;
            }
            if (lower && (sb == LF_OK || sb == LF_ENOCONV)
                && (ja.a != NULL || b.converged >= res->converged)) {
                if (ja.a != NULL) {     /* A, not assessed: its totals */
                    b.iterations += res->iterations;
                    b.evaluations += res->evaluations;
                    lf_fit_free(ja.a);
                    ja.a = NULL;
                } else {
                    lf_fit_keep_choice(&b, res);
                }
                lf_fit_result_free(res);
                *res = b;
                loo_at = loo_b;
                st = b.converged ? LF_OK : LF_ENOCONV;
            } else if (sb == LF_OK || sb == LF_ENOCONV) {
                res->iterations += b.iterations;
                res->evaluations += b.evaluations;
                lf_fit_result_free(&b);
            }
            like = fb;
        }
    }
    free(model);
    if (ja.a != NULL && (st = a_assess(&ja, res, &loo_at, err)) != LF_OK && st != LF_ENOCONV) {
        lf_fit_free(like);
        free(each);
        free(off);
        return st;
    }
    if (lf_fit_profile_at(settings, n, curves, res, intervals, loo_at, like, &perr) != LF_OK)
        lf_warn(&res->warnings, "the intervals could not be made (%s): the linear ones stand",
                perr.msg);
    lf_fit_free(like);
    if (st == LF_OK && !res->converged)
        st = LF_ENOCONV;        /* a local minimum, or nothing determined */
    if (n >= 2) {
        for (j = 0; j < n; j++)
            res->curves[j].alone = each[j];
        lf_heterogeneity_of(n, each, &res->heterogeneity, NULL);
    } else if (res->converged) {
        lf_curve_estimate_of(res, &res->curves[0].alone);
    }
    free(each);
    free(off);
    return st;
}
