/* test_hetero.c: how much curves of one material differ (fit/hetero.c):
 * the random-effects meta-analysis against an independent computation on
 * a classic data set, the edge cases (one curve, identical curves, a
 * parameter no curve determines), the probe comparison and the
 * multivariate Q. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "testlib.h"
#include "layerfit.h"

/* The 13 BCG vaccine trials (Colditz et al. 1994, JAMA 271:698), log risk
 * ratios and their sampling variances.  Reference values from an
 * independent computation (scipy: the restricted likelihood maximised
 * numerically, the Q-profile ends by Brent's method), which agree with
 * the metafor package's rma(method = "REML", test = "knha") on these data:
 * Q = 152.233, tau^2 = 0.3132 [0.1197, 1.1115], mu = -0.7145. */
static const double bcg_y[13] = {
    -0.8893113339202054, -1.5853886572014306, -1.3480731482996928, -1.4415511900213054,
    -0.21754732221129572, -0.786115585818864, -1.6208982235983922, 0.011952333523841173,
    -0.4694176487381487, -1.3713448034727846, -0.33935882833839015, 0.4459134005713783,
    -0.017313948216879493 };
static const double bcg_v[13] = {
    0.32558476500396133, 0.19458112139814385, 0.4153679653679654, 0.020010031902247573,
    0.05121017216963086, 0.0069056184559087574, 0.22301724757231517, 0.0039615792978177295,
    0.056434210463248966, 0.07302479361302891, 0.01241221397155972, 0.5325058452001528,
    0.0714046596839863 };

static lf_curve_estimate
estimate(double w, double w_se, double E, double E_se, double nu, double nu_se)
{
    lf_curve_estimate e;
    memset(&e, 0, sizeof e);
    e.value[LF_MAT_W] = w;
    e.se[LF_MAT_W] = w_se;
    e.value[LF_MAT_E] = E;
    e.se[LF_MAT_E] = E_se;
    e.value[LF_MAT_NU] = nu;
    e.se[LF_MAT_NU] = nu_se;
    e.corr_wE = NAN;
    e.ci95[0][0] = e.ci95[0][1] = e.ci95[1][0] = e.ci95[1][1] = e.ci95[2][0] = e.ci95[2][1] = NAN;
    e.probe.k = 2;
    e.probe.R = 1e-3;
    e.probe.b = 1e-6;
    e.probe.base = LF_BASE_FRICTIONLESS;
    return e;
}

/* E* = 2.385 GPa exp(y_i) with se = value sqrt(v_i): on ln E* the BCG data. */
static void
bcg(void)
{
    lf_curve_estimate e[13];
    lf_heterogeneity h;
    const double E0 = 2.385e9;
    size_t i;

    for (i = 0; i < 13; i++)
        e[i] = estimate(NAN, NAN, E0 * exp(bcg_y[i]), E0 * exp(bcg_y[i]) * sqrt(bcg_v[i]),
                        NAN, NAN);
    t_int(lf_heterogeneity_of(13, e, &h, NULL), LF_OK, "bcg: analysed");
    t_int((long) h.curves, 13, "bcg: curves");
    t_int((long) h.Estar.n, 13, "bcg: E* from every curve");
    t_rel(h.Estar.Q, 152.233008, 1e-6, "bcg: Cochran's Q");
    t_rel(h.Estar.p_homogeneous, 1.99676e-26, 1e-4, "bcg: p of Q");
    t_rel(h.Estar.I2, 0.921173, 1e-5, "bcg: I^2 = (Q - df) / Q");
    t_rel(h.Estar.tau_rel * h.Estar.tau_rel, 0.313243, 1e-5, "bcg: tau^2 (REML)");
    t_rel(h.Estar.tau_rel_ci95[0] * h.Estar.tau_rel_ci95[0], 0.119718, 1e-5,
          "bcg: tau^2 lower end (Q-profile)");
    t_rel(h.Estar.tau_rel_ci95[1] * h.Estar.tau_rel_ci95[1], 1.111479, 1e-5,
          "bcg: tau^2 upper end (Q-profile)");
    t_rel(log(h.Estar.population_mean / E0), -0.714532, 1e-5, "bcg: mu");
    t_rel(log(h.Estar.population_ci95[0] / E0), -1.108444, 1e-5, "bcg: HKSJ lower end");
    t_rel(log(h.Estar.population_ci95[1] / E0), -0.320621, 1e-5, "bcg: HKSJ upper end");
    t_rel(h.Estar.tau, h.Estar.tau_rel * h.Estar.population_mean, 1e-12, "bcg: tau in Pa");
    /* the multivariate Q of one parameter is its own */
    t_rel(h.Q, h.Estar.Q, 1e-9, "bcg: overall Q = E*'s");
    t_rel(h.df, 12.0, 1e-12, "bcg: overall dof");
    t_true(h.w.n == 0 && h.w.why != NULL && isnan(h.w.tau) && isnan(h.w.population_mean),
           "bcg: w determined by no curve: null with a reason");
    t_int((long) h.probes, 1, "bcg: one probe");
    t_true(isnan(h.probes_p), "bcg: no probe comparison");
}

/* Identical estimates: Q = 0, tau = 0 (interval [0, 0]), the population
 * interval the t-interval of a mean of no spread (zero width). */
/* A precise pair that agrees and an imprecise curve far off: the restricted
 * likelihood has two maxima, and REML's tau is the higher one (tau^2 =
 * 4.5093, found by a bounded minimiser), inside its Q-profile interval;
 * the fixed point from the DerSimonian-Laird value stopped at the pair's
 * spread (tau 0.044), below that interval (0.92 to 14.8). */
static void
two_maxima(void)
{
    static const double E[3] = { 437.0, 25150.0, 26730.0 }, sd[3] = { 1.0, 0.007, 0.006 };
    lf_curve_estimate e[3];
    lf_heterogeneity h;
    size_t i;

    for (i = 0; i < 3; i++)
        e[i] = estimate(NAN, NAN, E[i], E[i] * sd[i], NAN, NAN);
    t_int(lf_heterogeneity_of(3, e, &h, NULL), LF_OK, "two maxima: analysed");
    t_rel(h.Estar.tau_rel * h.Estar.tau_rel, 4.509303, 1e-5, "two maxima: tau^2 (REML, the higher)");
    t_true(h.Estar.tau_rel >= h.Estar.tau_rel_ci95[0] && h.Estar.tau_rel <= h.Estar.tau_rel_ci95[1],
           "two maxima: tau inside its Q-profile interval");
}

static void
edge_cases(void)
{
    lf_curve_estimate e[4];
    lf_heterogeneity h;
    size_t i;

    for (i = 0; i < 4; i++)
        e[i] = estimate(10e-3, 1e-3, 1e9, 1e7, 0.3, 0.01);
    t_int(lf_heterogeneity_of(4, e, &h, NULL), LF_OK, "identical: analysed");
    t_abs(h.Estar.Q, 0.0, 1e-12, "identical: Q = 0");
    t_abs(h.Estar.tau, 0.0, 1e-12, "identical: tau = 0");
    t_abs(h.Estar.tau_ci95[1], 0.0, 1e-12, "identical: tau's upper end 0");
    t_rel(h.Estar.population_mean, 1e9, 1e-12, "identical: population mean");
    t_rel(h.nu.population_mean, 0.3, 1e-12, "identical: nu's population mean (linear)");
    t_abs(h.I2, 0.0, 1e-12, "identical: I^2 = 0");
    t_rel(h.df, 9.0, 1e-12, "identical: overall dof 3 parameters x 3");
    t_rel(h.p_homogeneous, 1.0, 1e-12, "identical: p = 1");
    t_rel(h.Estar.median, 1e9, 1e-12, "identical: median");
    /* one curve: the descriptive numbers, no spread */
    t_int(lf_heterogeneity_of(1, e, &h, NULL), LF_OK, "one curve: analysed");
    t_rel(h.w.mean, 10e-3, 1e-12, "one curve: its mean");
    t_true(isnan(h.w.sd) && isnan(h.w.tau) && isnan(h.w.population_mean) && h.w.why != NULL,
           "one curve: no spread, said why");
    t_true(isnan(h.p_homogeneous), "one curve: no test");
    t_int(lf_heterogeneity_of(0, NULL, &h, NULL), LF_OK, "no curves: nothing");
    t_int((long) h.curves, 0, "no curves: curves 0");
    t_int(lf_heterogeneity_of(3, NULL, &h, NULL), LF_EINVAL, "no estimates: refused");
    /* w of one curve not determined (k = 2 without baseline): the others'
     * are analysed; with one left, w is not determined from single curves */
    e[1].value[LF_MAT_W] = NAN;
    e[2].value[LF_MAT_W] = NAN;
    e[3].value[LF_MAT_W] = NAN;
    t_int(lf_heterogeneity_of(4, e, &h, NULL), LF_OK, "w of one: analysed");
    t_int((long) h.w.n, 1, "w of one: n");
    t_true(h.w.why != NULL && strstr(h.w.why, "single curves") != NULL,
           "w of one: not determined from single curves");
    t_rel(h.df, 6.0, 1e-12, "w of one: overall Q over E* and nu");
}

/* Two probes (k = 2 and k = 3), six curves each, spread 5% from spot to
 * spot; the k = 3 curves read E* 30% high (model error): named. */
static void
probes_disagree(void)
{
    lf_curve_estimate e[12];
    lf_heterogeneity h;
    /* fixed spot deviations, SD about 5% */
    static const double u[6] = { 0.04, -0.06, 0.02, 0.07, -0.03, -0.04 };
    size_t i;

    for (i = 0; i < 12; i++) {
        double E = 1e9 * exp(u[i % 6]) * (i >= 6 ? 1.3 : 1.0);
        e[i] = estimate(10e-3 * exp(u[(i + 2) % 6]), 1e-4, E, 0.01 * E, NAN, NAN);
        if (i >= 6)
            e[i].probe.k = 3;
    }
    t_int(lf_heterogeneity_of(12, e, &h, NULL), LF_OK, "probes: analysed");
    t_int((long) h.probes, 2, "probes: two");
    t_true(h.probes_p < 0.05 && h.probes_disagree, "probes: they disagree (p = %.3g)",
           h.probes_p);
    t_int(h.probe_param, LF_MAT_E, "probes: in E*");
    t_true(fabs(h.probe_diff) > 0.2 && fabs(h.probe_diff) < 0.4,
           "probes: by about 30%% (%.3g)", h.probe_diff);
    /* the same with no offset: no model error */
    for (i = 6; i < 12; i++) {
        e[i].value[LF_MAT_E] /= 1.3;
        e[i].se[LF_MAT_E] /= 1.3;
    }
    t_int(lf_heterogeneity_of(12, e, &h, NULL), LF_OK, "probes agree: analysed");
    t_true(!h.probes_disagree && h.probes_p > 0.05, "probes agree: p = %.3g", h.probes_p);
    /* one curve per probe: not testable */
    t_int(lf_heterogeneity_of(2, e + 5, &h, NULL), LF_OK, "one per probe: analysed");
    t_true(isnan(h.probes_p) && h.probes == 2, "one per probe: no test");
}

/* w and E* correlated within each curve: the multivariate Q weighs their
 * joint departure by each curve's covariance, not as two independent
 * tests. */
static void
correlated(void)
{
    lf_curve_estimate e[2];
    lf_heterogeneity h;

    /* both move up by one se in the second curve: with correlation 0.9
     * that is the curve's likely direction, Q small */
    e[0] = estimate(10e-3, 1e-4, 1e9, 1e7, NAN, NAN);
    e[1] = estimate(10e-3 * exp(1.414e-2), 1e-4, 1e9 * exp(1.414e-2), 1e7, NAN, NAN);
    e[0].corr_wE = e[1].corr_wE = 0.9;
    t_int(lf_heterogeneity_of(2, e, &h, NULL), LF_OK, "correlated: analysed");
    t_true(h.Q < h.w.Q + h.Estar.Q, "correlated: joint Q %.3g below the sum %.3g", h.Q,
           h.w.Q + h.Estar.Q);
    /* against the correlation, far beyond */
    e[1].value[LF_MAT_E] = 1e9 * exp(-1.414e-2);
    t_int(lf_heterogeneity_of(2, e, &h, NULL), LF_OK, "anti: analysed");
    t_true(h.Q > h.w.Q + h.Estar.Q, "anti: joint Q %.3g above the sum %.3g", h.Q,
           h.w.Q + h.Estar.Q);
}

int
main(void)
{
    gsl_set_error_handler_off();
    bcg();
    two_maxima();
    edge_cases();
    probes_disagree();
    correlated();
    return t_summary();
}
