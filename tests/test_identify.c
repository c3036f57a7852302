/* test_identify.c: what the data can and cannot determine (the seed
 * paper's Eq. 10, 22: thin bonded curves see M = Z E* only; k = 2 with
 * free offsets is a parabola), said in words, each message triggered by a plan built to
 * cause it, and undetermined parameters never reported as numbers. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "scene.h"
#include "testlib.h"

static void
show(const lf_warnings *w)
{
    size_t i;
    for (i = 0; i < w->n; i++)
        printf("  said: %s\n", w->msg[i]);
}

int
main(void)
{
    scene s;
    lf_fit_result r;
    lf_error err;
    int st;

    gsl_set_error_handler_off();

    /* bonded curves only: M and w, not nu or E* */
    s = scene_default("only bonded");
    s.sim.noise = 0.005;
    s.sim.past_c = 2.0;
    scene_add(&s, 2, 1e-3, 1e-6, LF_BASE_BONDED);
    scene_add(&s, 3, 1e-3, 1e-6, LF_BASE_BONDED);
    /* no nu at all: refused, never a default (issue 35) */
    st = scene_fit(&s, 5, &r, &err);
    t_int(st, LF_EDATA, "only bonded, no nu: refused");
    t_contains(err.msg, "a bonded layer needs Poisson's ratio nu, and these curves do not "
               "determine it", "only bonded, no nu: says so");
    /* nu held by the fitter's rule at a value the caller gave (AUTO): the
     * data fix only M */
    s.fit.nu.value = 0.3;
    st = scene_fit(&s, 5, &r, &err);
    t_int(st, LF_OK, "only bonded: converges");
    show(&r.identifiability);
    t_true(t_says(&r.identifiability, "only bonded curves: the data fix M = Z*E* = "),
           "only bonded: M message");
    t_true(t_says(&r.identifiability, "nu is not determined (fix nu or add a frictionless curve)"),
           "only bonded: nu advice");
    t_true(!r.nu.determined && isnan(r.nu.value) && isnan(r.nu.se), "only bonded: nu has no number");
    t_true(!r.Estar.determined && isnan(r.Estar.value), "only bonded: E* has no number");
    t_true(r.M.determined && fabs(r.M.value / (lf_thin_Z(LF_BASE_BONDED, 0.35) * 1.85e9) - 1) < 5 * r.M.se / r.M.value,
           "only bonded: M determined, within 5 se of Z E*");
    t_true(r.w.determined, "only bonded: w determined");
    lf_fit_result_free(&r);
    /* the same with nu forced free: the SVD finds the E*-nu direction */
    s.fit.nu.mode = LF_PARAM_FREE;
    st = scene_fit(&s, 5, &r, &err);
    t_true(st == LF_OK || st == LF_ENOCONV, "only bonded, nu forced free: a result");
    if (st == LF_OK || st == LF_ENOCONV) {
        show(&r.identifiability);
        t_true(!r.nu.determined && !r.Estar.determined && isnan(r.nu.value),
               "only bonded, nu forced free: nu and E* not determined");
        t_true(t_says(&r.identifiability, "only bonded curves"), "only bonded, nu forced free: said");
        t_true(isnan(r.cov[r.npar * 1 + 1]), "only bonded, nu forced free: no covariance for E*");
        lf_fit_result_free(&r);
    }
    scene_free(&s);

    /* frictionless only: nu plays no part */
    s = scene_default("only frictionless");
    scene_add(&s, 2, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
    scene_add(&s, 3, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
    t_int(scene_fit(&s, 5, &r, &err), LF_OK, "only frictionless: converges");
    t_true(t_says(&r.identifiability, "frictionless curves do not depend on nu"), "only frictionless: said");
    t_true(!r.nu.free && !r.nu.determined && isnan(r.nu.value), "only frictionless: nu has no number");
    t_true(isnan(r.M.value), "only frictionless: no M of bonded layers");
    lf_fit_result_free(&r);
    scene_free(&s);

    /* k = 2 alone, no baseline, free F0 and z0: w and F0 degenerate */
    s = scene_default("k=2 alone");
    s.sim.past_c = 0.9;
    s.sim.noise = 0.002;
    scene_add(&s, 2, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
    st = scene_fit(&s, 5, &r, &err);
    t_true(st == LF_OK || st == LF_ENOCONV, "k=2 alone: a result");
    if (st == LF_OK || st == LF_ENOCONV) {
        show(&r.identifiability);
        t_true(t_says(&r.identifiability, "k = 2 alone with free F0 and z0 cannot separate w from the force offset"),
               "k=2 alone: said");
        t_true(!r.w.determined && isnan(r.w.value) && isnan(r.w.se), "k=2 alone: w has no number");
        t_true(isnan(r.curves[0].F0), "k=2 alone: F0 has no number");
        t_true(r.Estar.determined, "k=2 alone: E* still determined");
        lf_fit_result_free(&r);
    }
    /* ... and held F0 restores w */
    s.fix_F0 = 1;
    t_int(scene_fit(&s, 5, &r, &err), LF_OK, "k=2 alone, F0 held: converges");
    t_true(r.w.determined, "k=2 alone, F0 held: w determined");
    t_true(!t_says(&r.identifiability, "k = 2 alone"), "k=2 alone, F0 held: not said");
    lf_fit_result_free(&r);
    scene_free(&s);

    /* adhesion far below the noise: an upper bound only */
    s = scene_default("weak adhesion");
    s.mat.w = 2e-7;
    s.sim.noise = 0.01;
    s.sim.delta_min = -20e-9;
    scene_add(&s, 2, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
    scene_add(&s, 3, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
    st = scene_fit(&s, 5, &r, &err);
    t_true(st == LF_OK || st == LF_ENOCONV, "weak adhesion: a result");
    if (st == LF_OK || st == LF_ENOCONV) {
        show(&r.identifiability);
        t_true(t_says(&r.identifiability, "adhesion below the noise: w < "), "weak adhesion: said");
        t_true(r.w.upper_bound_only && isnan(r.w.value) && r.w.ci95[1] > s.mat.w,
               "weak adhesion: bound above the truth, no value");
        lf_fit_result_free(&r);
    }
    scene_free(&s);

    /* mixed plan: everything determined, and said so */
    s = scene_default("mixed");
    s.sim.noise = 0.005;
    s.sim.past_c = 2.0;
    s.sim.delta_max = 20e-9;
    s.fit.max_b_over_a = 0.5;
    scene_add(&s, 2, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
    scene_add(&s, 3, 1e-3, 1e-6, LF_BASE_BONDED);
    t_int(scene_fit(&s, 5, &r, &err), LF_OK, "mixed: converges");
    t_true(t_says(&r.identifiability, "every free parameter is determined"), "mixed: said");
    t_true(r.nu.determined && r.Estar.determined && r.w.determined, "mixed: all determined");
    t_true((r.curves[0].b_over_a_pulloff > 0.5)
           == t_says(&r.curves[0].warnings, "at pull-off: the thin-layer assumption b << a is strained"),
           "mixed: b/a warning follows --max-b-over-a");
    t_true(r.corr[0 * r.npar + 1] == r.corr[1 * r.npar + 0] && fabs(r.corr[0]) - 1 < 1e-12,
           "mixed: correlation symmetric with unit diagonal");
    lf_fit_result_free(&r);
    scene_free(&s);

    /* a layer thicker than the contact is wide, fitted as thin: past b = a
     * the model does not apply, which is more than strained */
    s = scene_default("thick layer as thin");
    s.sim.noise = 0.005;
    scene_add(&s, 2, 1e-3, 20e-6, LF_BASE_FRICTIONLESS);
    st = scene_fit(&s, 5, &r, &err);
    t_true(st == LF_OK || st == LF_ENOCONV, "thick layer as thin: a result");
    if (st == LF_OK || st == LF_ENOCONV) {
        show(&r.curves[0].warnings);
        t_true(r.curves[0].b_over_a_pulloff > 1.0, "thick layer as thin: b/a = %.3g at pull-off",
               r.curves[0].b_over_a_pulloff);
        t_true(t_says(&r.curves[0].warnings, "at pull-off: the thin-layer model does not apply"),
               "thick layer as thin: 'does not apply' said");
        t_true(!t_says(&r.curves[0].warnings, "at pull-off: the thin-layer assumption b << a is strained"),
                "thick layer as thin: not merely 'strained'");
        lf_fit_result_free(&r);
    }
    scene_free(&s);
    return t_summary();
}
