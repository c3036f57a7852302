/* profile.c: profile-likelihood intervals of w, E* and nu.
 *
 * The linear (Wald) interval value +- 1.96 se assumes chi2 is quadratic in
 * the parameter (in ln w and ln E*, in nu) over the interval.  Where the
 * data are weak (offsets free, few probes) it is not, and the interval
 * covers the truth far less often than 95%.  The profile of a parameter is
 * chi2 minimised over every other parameter with that one held; its 95%
 * interval is where the profile's rise stays below the threshold s^2
 * F(1, n_eff - p) (s^2 = se_scale^2: the noise scale and its correlation,
 * uncertainty.c; n_eff the independent points; 3.84 s^2 for many points).
 *
 * Rule: unless the screen (screen_passes: chi2 along the linear path and
 * a Gauss-Newton step's prediction of the refits, no fit) says the linear
 * interval stands, the profile is evaluated at the two Wald endpoints (in
 * every mode but LF_PROFILE_ALWAYS: single fits and batches alike).  When
 * both rises are within PROFILE_TOL of the threshold, the curvature bears
 * out the linear interval and it stays ("linear (Wald)").  Otherwise
 * each side is searched outwards (doubling the step, or shorter where a
 * quadratic profile would pass 2.5 times the threshold: grow_to) until the
 * profile reaches the threshold, and on past it until the rise is PROFILE_FAR
 * times the threshold (a weak parameter's profile can dip below it again:
 * the interval is the hull of the set below), then the last crossing is
 * bisected: the interval is asymmetric where the data are.  A w below two
 * se is searched in w itself, down to 0.  A side the profile never leaves
 * within PROFILE_LOG_RANGE (ln units) of w or E*, or up to nu's bounds, is
 * open: w's lower bound then is 0, nu's the bound of its range; an open
 * upper side of w or E* means the data do not bound it, and the estimate
 * is marked not determined.  A profile point below the best fit's chi2
 * means the fit stopped in a local minimum: it is continued from there,
 * replaces the result, and the profiles start again.
 *
 * Each profile point is a fit with the parameter held (hold.c). */
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <gsl/gsl_sort.h>
#include <gsl/gsl_statistics_double.h>

#include "fit.h"

#define PROFILE_TOL 0.25
#define PROFILE_LOG_RANGE 12.0
#define PROFILE_BISECT 6
/* past the first crossing, the search goes on until the rise exceeds this
 * many times the threshold (7.7 s^2 for 95%: p = 0.006) */
#define PROFILE_FAR 2.0
/* inside the set, the step doubles, or where shorter, the next point aims
 * where a quadratic profile would rise to this many times the threshold
 * (past the crossing and the far rise in one refit, nearer the estimate
 * than a doubled step, which can rise to nine times the threshold there at
 * a far higher cost per refit), at least PROFILE_GROW_MIN times as far out
 * as the last */
#define PROFILE_AIM 2.5
#define PROFILE_GROW_MIN 1.25
/* refits from a lower profile point, at most */
#define PROFILE_MAX_REFITS 3
/* the threshold's calibration: data sets and their seed */
#define PROFILE_BOOT 200
#define PROFILE_BOOT_SEED 20141u

/* Map between the searched coordinate t and the parameter. */
static double
param_of(const fit_prof *p, double t)
{
    return p->which == FIT_NU || p->linear ? t : exp(t);
}

/* The crossing of the threshold in [a, b] (distances from t_hat, the rise
 * ra < thr at a, rb >= thr or NaN at b), to tol: the bracket is narrowed
 * until it is at most tol wide (search_side: 2^-PROFILE_BISECT of its
 * width, what PROFILE_BISECT bisections give, or of the side's first step
 * where the bracket is narrower), and its midpoint returned.  Where the
 * profile is quadratic the square root of the rise is linear in the
 * distance, so each trial aims where the straight line through the
 * bracket's ends crosses (false position, with the Illinois rule: an end
 * that stays twice counts half), just past it by a quarter of the final
 * width towards the end that moved last, so that two trials near the
 * crossing close the bracket from both sides.  Three trials that do not
 * halve the bracket (a kink, where points enter or leave contact, bends the
 * line) make the next a bisection: the answer is a crossing within
 * bisection's final width. */
static double
cross_in(fit_prof *p, double t_hat, int dir, double a, double ra, double b, double rb, double tol,
         int *jump)
{
    const double sthr = sqrt(p->thr);
    double ga = sqrt(lf_fmax(ra, 0.0)) - sthr, gb = isfinite(rb) ? sqrt(rb) - sthr : NAN;
    double width[3] = { HUGE_VAL, HUGE_VAL, HUGE_VAL };   /* 1, 2, 3 trials ago */
    int last = 0, i;

    for (i = 0; i < 3 * PROFILE_BISECT && b - a > tol; i++) {
        double m, rm;
        if (b - a > 0.5 * width[2] || !isfinite(gb) || !(gb > ga)) {
            m = 0.5 * (a + b);
        } else {
            m = a + (b - a) * (-ga) / (gb - ga);
            m += last > 0 ? 0.25 * tol : -0.25 * tol;
            m = lf_fmin(lf_fmax(m, a + 0.25 * tol), b - 0.25 * tol);
        }
        width[2] = width[1];
        width[1] = width[0];
        width[0] = b - a;
        rm = lf_fit_hold_rise(p, param_of(p, t_hat + dir * m));
        if (rm >= p->thr || !isfinite(rm)) {
            b = m;
            rb = rm;
            gb = isfinite(rm) ? sqrt(rm) - sthr : NAN;
            if (last < 0)
                ga *= 0.5;      /* a stayed twice */
            last = -1;
        } else {
            a = m;
            ra = rm;
            ga = sqrt(lf_fmax(rm, 0.0)) - sthr;
            if (last > 0)
                gb *= 0.5;
            last = 1;
        }
    }
    /* across the final bracket a smooth profile rises by a few percent of
     * the threshold; by more than all of it, chi2 jumps: a point crosses
     * the model's abrupt contact edge there */
    *jump = isfinite(rb) && rb - ra > p->thr;
    return t_hat + dir * 0.5 * (a + b);
}

/* The factor on the distance from the estimate that takes a rise r (at
 * that distance, below the target) to the target where the profile is
 * quadratic, at least PROFILE_GROW_MIN (HUGE_VAL where r <= 0). */
static double
grow_to(double r, double target)
{
    return r > 0.0 ? lf_fmax(sqrt(target / r), PROFILE_GROW_MIN) : HUGE_VAL;
}

/* The point on one side (dir = -1 or +1) where the profile leaves the
 * confidence set for good, from t_hat with first step h, whose rise r_h
 * (NaN: not known) the caller may have computed already; *open when it
 * never does within [tmin, tmax].  Steps double until the rise reaches the
 * threshold, or are shorter where a quadratic profile would pass
 * PROFILE_AIM times it sooner (grow_to); a weak parameter's profile can dip
 * below it again further out (kinks where points enter or leave contact),
 * so the search goes on until the rise exceeds PROFILE_FAR times the
 * threshold, in steps of at least a quarter of the distance so far (aimed
 * at PROFILE_AIM times the threshold above it, a quarter in a dip), and a
 * dip moves the side out to it (the interval is the hull of the set where
 * the rise stays below the threshold).
 * The last crossing is then found to bisection's precision (cross_in).
 * (Regula falsi on the square root of the rise, stopped when the rise was
 * near the threshold, moved the paper-offsets coverage of w from 94.0% to
 * 92.5%: at the kinks a rise near the threshold can be far from the
 * crossing.  cross_in stops on the bracket's width alone.) */
static double
search_side(fit_prof *p, double t_hat, double h, double r_h, int dir, double tmin, double tmax,
            int *open, int *jump)
{
    double a = 0.0, b = 0.0, ra = 0.0, rb = NAN, d = 0.0, step = h;
    double edge = dir < 0 ? t_hat - tmin : tmax - t_hat;
    int crossed = 0;

    *open = *jump = 0;
    for (;;) {
        double rd;
        d = lf_fmin(d + step, edge);
        rd = d == h && isfinite(r_h) ? r_h : lf_fit_hold_rise(p, param_of(p, t_hat + dir * d));
        if (!isfinite(rd) || rd >= p->thr) {
            if (!crossed || b <= a) {
                b = d;                  /* the first point above after a */
                rb = rd;
            }
            crossed = 1;
        } else {
            a = d;                      /* inside (again) */
            ra = rd;
            b = 0.0;
        }
        if (d >= edge || !isfinite(rd) || (crossed && rd >= PROFILE_FAR * p->thr))
            break;
        if (!crossed)
            step = lf_fmin(2.0 * step, (grow_to(rd, PROFILE_AIM * p->thr) - 1.0) * d);
        else if (rd >= p->thr)
            step = (grow_to(rd, PROFILE_AIM * p->thr) - 1.0) * d;    /* 0.25-0.58 d */
        else
            step = 0.25 * d;    /* in a dip */
    }
    if (!crossed || b <= a) {
        *open = 1;
        return t_hat + dir * edge;
    }
    return cross_in(p, t_hat, dir, a, ra, b, rb, ldexp(lf_fmax(b - a, h), -PROFILE_BISECT), jump);
}

/* The screen: 1 when the check of the linear interval (the refits at its
 * two ends, profile_one) can be foregone, its rises sure to be within
 * PROFILE_TOL of the threshold.  Two signs that the local quadratic holds,
 * with no fit:
 * - chi2 along the linear path (every other free parameter moved by its
 *   regression on this one, from the covariance) at 1 and 3 standard
 *   errors either side rises as the quadratic does, t^2 / 1.96^2 times
 *   the threshold, to within SCREEN_QUAD of it (a point crossing the
 *   contact edge there bends it);
 * - at each end, the refit's first Gauss-Newton step from its start
 *   (lf_fit_hold_predict: one evaluation of the model and its Jacobian)
 *   predicts a rise within PROFILE_TOL - SCREEN_MARGIN of the threshold,
 *   and lowers chi2 from the start by less than SCREEN_STEP of it (a
 *   longer step leaves the quadratic it extrapolates).
 * Chi2 along the path alone (the batch's screen before) passed 27 and 43
 * of some 400 checks that failed, on 200 curves of the synthetic force map
 * (thin with linear intervals, and by default): the path ran 25-35% of the
 * threshold above the profile where the valley bends.  These rules pass
 * none of the 301 checks there that fail, and 269 of the 508 that pass
 * (the prediction is within 0.01 of the refit's rise in the median, 0.19
 * at the 95th percentile); each of their 1 596 passes in `layerfit bench
 * --coverage` (three scenes, 400 seeds) and 1 780 on the 1 024-curve map
 * (default, thin with linear intervals, exact) agreed with the refits.  A
 * quadratic's agreement to 25% or 30% let one through in each: a refit
 * that crossed a contact-edge kink to a rise of 0.67 or 0.23 of the
 * threshold where its first step predicted 0.92 or 0.94. */
#define SCREEN_QUAD 0.2
#define SCREEN_MARGIN 0.05
#define SCREEN_STEP 0.3
static int
screen_passes(fit_prof *p, double t_hat, double se_t, double tmin, double tmax)
{
    static const double t[4] = { -1.0, 1.0, -3.0, 3.0 };
    double chi2[4];
    int q, side;

    lf_fit_walk_chi2(p, p->which, 4, t, chi2);     /* descend.c's walk's, where it holds them */
    for (q = 0; q < 4; q++) {
        double quad = p->thr * t[q] * t[q] / (FIT_Z95 * FIT_Z95);
        if (!isfinite(chi2[q]) || !(fabs((chi2[q] - p->best->chi2) / quad - 1.0) < SCREEN_QUAD))
            return 0;
    }
    for (side = -1; side <= 1; side += 2) {
        double start, rise, tt = t_hat + side * FIT_Z95 * se_t;
        if (!(tt > tmin && tt < tmax))
            return 0;
        rise = lf_fit_hold_predict(p, param_of(p, tt), &start);
        if (!isfinite(rise) || !(fabs(rise / p->thr - 1.0) < PROFILE_TOL - SCREEN_MARGIN)
            || !(start - rise < SCREEN_STEP * p->thr))
            return 0;
    }
    return 1;
}

/* The threshold's calibration where the profile is used: the rise's 95%
 * point under data like these.  Near the contact edge the force has an
 * infinite slope (k > 2), the information on the offsets and w gathers in
 * the few points closest to it, and the rise at the truth no longer follows
 * F(1, m): its 95% point can lie 15% higher (the paper's probes with free
 * offsets: the profile interval then covers 93%).  So B data sets are drawn
 * from the fitted curves with white Gaussian noise of each curve's fitted
 * level (seeded: the same answer every run), each is fitted with
 * everything free and with the parameter held at its estimate (both warm
 * started at the fit), and the rise over chi2/dof is collected; the
 * threshold is multiplied by its 95% point over F's (never below 1: the
 * calibration widens, it does not narrow; a bootstrap of B = 200 sets its
 * point to some 10%). */
static double
calibrate(fit_prof *p, double v_hat)
{
    const lf_fit_result *res = p->best;
    lf_fit_curve *boot = malloc(p->nc * sizeof *boot), *data = p->cc;
    double **force = calloc(p->nc, sizeof *force), *t = malloc(PROFILE_BOOT * sizeof *t);
    double s2 = res->chi2 / (double) res->dof, kappa = 1.0, f95;
    double *lower = p->lower_off;
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    size_t j, i, b, nt = 0;
    int which = p->which, ok = boot && force && t && rng;

    for (j = 0; ok && j < p->nc; j++) {
        force[j] = malloc(data[j].n * sizeof *force[j]);
        ok = force[j] != NULL && res->curves[j].fitted != NULL && res->curves[j].n == data[j].n;
        if (ok) {
            boot[j] = data[j];
            boot[j].force = force[j];
        }
    }
    if (!ok || !(s2 > 0))
        goto done;
    gsl_rng_set(rng, PROFILE_BOOT_SEED);
    p->cc = boot;
    p->lower_off = NULL;        /* a lower point of made-up data means nothing */
    for (b = 0; b < PROFILE_BOOT; b++) {
        double free_chi2, held_chi2;
        for (j = 0; j < p->nc; j++) {
            double sd = res->curves[j].sigma * sqrt(s2);
            for (i = 0; i < data[j].n; i++)
                force[j][i] = res->curves[j].fitted[i] + sd * gsl_ran_gaussian(rng, 1.0);
        }
        p->which = -1;
        free_chi2 = lf_fit_hold_rise(p, NAN) + res->chi2;
        p->which = which;
        held_chi2 = lf_fit_hold_rise(p, v_hat) + res->chi2;
        if (isfinite(free_chi2) && isfinite(held_chi2) && free_chi2 > 0)
            t[nt++] = lf_fmax(held_chi2 - free_chi2, 0.0) / (free_chi2 / (double) res->dof);
    }
    p->cc = data;
    p->lower_off = lower;
    lf_fit_free(p->held);       /* a fit of the made-up data */
    p->held = NULL;
    f95 = lf_fit_f95((double) res->dof);
    if (nt >= PROFILE_BOOT / 2) {
        gsl_sort(t, 1, nt);
        kappa = lf_fmax(1.0, gsl_stats_quantile_from_sorted_data(t, 1, nt, 0.95) / f95);
    }
done:
    p->which = which;
    for (j = 0; force != NULL && j < p->nc; j++)
        free(force[j]);
    free(force);
    free(boot);
    free(t);
    gsl_rng_free(rng);
    return kappa;
}

/* Profile one estimate; 1 when its interval changed. */
static int
profile_one(fit_prof *p, lf_fit_estimate *e)
{
    double t_hat, se_t, tmin, tmax, lo, hi, r_lo = NAN, r_hi = NAN, thr;
    int open_lo = 0, open_hi = 0, jump_lo = 0, jump_hi = 0;

    int bound_only = e->upper_bound_only && p->which == FIT_W;

    p->linear = 0;
    p->mu0 = NAN;
    if (!e->free || (!e->determined && !bound_only) || (!bound_only && !(e->se > 0)))
        return 0;
    if (p->which == FIT_NU) {
        t_hat = e->value;
        se_t = e->se;
        tmin = 0.0;
        tmax = 0.5 - 1e-9;
    } else if (bound_only) {
        /* w below two se: near 0 the profile is searched in w itself (its
         * log would stretch the flat part below), from the solution's w
         * down to 0 and up in steps from a quarter of the one-sided bound */
        double w = lf_fmax(lf_fit_best_value(p->best, "w", 0.0), 0.0);
        p->linear = 1;
        t_hat = w;
        se_t = 0.25 * e->ci95[1] / FIT_Z95;
        tmin = 0.0;
        tmax = exp(PROFILE_LOG_RANGE) * lf_fmax(w, e->ci95[1]);
    } else {
        t_hat = log(e->value);
        se_t = e->se / e->value;
        tmin = t_hat - PROFILE_LOG_RANGE;
        tmax = t_hat + PROFILE_LOG_RANGE;
    }
    e->interval_method = "linear (Wald)";
    if (!bound_only && p->mode != LF_PROFILE_ALWAYS) {
        if (screen_passes(p, t_hat, se_t, tmin, tmax))
            return 0;
        r_lo = t_hat - FIT_Z95 * se_t > tmin ? lf_fit_hold_rise(p, param_of(p, t_hat - FIT_Z95 * se_t)) : NAN;
        r_hi = t_hat + FIT_Z95 * se_t < tmax ? lf_fit_hold_rise(p, param_of(p, t_hat + FIT_Z95 * se_t)) : NAN;
        if (fabs(r_lo / p->thr - 1.0) < PROFILE_TOL && fabs(r_hi / p->thr - 1.0) < PROFILE_TOL)
            return 0;
    }
    thr = p->thr;
    if (p->calibrate)
        p->thr *= calibrate(p, param_of(p, t_hat));
    /* the rises at the linear ends, where known, are each side's first step */
    lo = search_side(p, t_hat, lf_fmin(FIT_Z95 * se_t, 0.5 * (t_hat - tmin)),
                     FIT_Z95 * se_t <= 0.5 * (t_hat - tmin) ? r_lo : NAN, -1, tmin, tmax, &open_lo,
                     &jump_lo);
    hi = search_side(p, t_hat, lf_fmin(FIT_Z95 * se_t, 0.5 * (tmax - t_hat)),
                     FIT_Z95 * se_t <= 0.5 * (tmax - t_hat) ? r_hi : NAN, +1, tmin, tmax, &open_hi,
                     &jump_hi);
    p->thr = thr;
    e->interval_method = "profile likelihood";
    /* A side that ends where chi2 jumps ends at a point crossing the
     * model's abrupt contact edge, which real curves, detaching gradually,
     * do not have: there the profile measures the model's step, not the
     * data.  Such a side is never reported narrower than the linear one
     * (the PEG exports' joint fit put E*'s upper end 0.94 se from E*, a
     * single point's jump of 8 thresholds). */
    if (!bound_only && jump_lo && t_hat - FIT_Z95 * se_t > tmin && t_hat - FIT_Z95 * se_t < lo) {
        lo = t_hat - FIT_Z95 * se_t;
        e->interval_method = LF_INTERVAL_JUMP;
    }
    if (!bound_only && jump_hi && t_hat + FIT_Z95 * se_t < tmax && t_hat + FIT_Z95 * se_t > hi) {
        hi = t_hat + FIT_Z95 * se_t;
        e->interval_method = LF_INTERVAL_JUMP;
    }
    e->ci95[0] = open_lo && p->which == FIT_W ? 0.0 : param_of(p, lo);
    e->ci95[1] = param_of(p, hi);
    if (bound_only && !open_lo) {
        /* the profile closes below: the data do bound w from below */
        e->upper_bound_only = 0;
        e->determined = 1;
        e->value = t_hat;
        e->se = (hi - lo) / (2.0 * FIT_Z95);   /* the interval's width */
    }
    if (p->which == FIT_NU) {
        e->ci95[0] = lf_fmax(e->ci95[0], 0.0);
        e->ci95[1] = lf_fmin(e->ci95[1], 0.5);
    }
    if (open_hi && p->which != FIT_NU) {
        /* the data do not bound it from above: no estimate to report, at
         * most a lower bound (none when the profile is open below too: a
         * w down to 0 or an E* down to the end of the search) */
        e->determined = 0;
        e->value = e->se = NAN;
        e->ci95[1] = NAN;
        if (open_lo)
            e->ci95[0] = NAN;
        if (bound_only) {
            e->upper_bound_only = 0;
            e->ci95[0] = NAN;
        }
    } else if (open_lo && p->which == FIT_E) {
        /* bound from above only: the lower end would be the end of the
         * search, not a bound of the data (w's lower end 0 is w's own) */
        e->determined = 0;
        e->value = e->se = NAN;
        e->ci95[0] = NAN;
    }
    return 1;
}

/* Every free estimate's interval is the linear one, found by `method`
 * (NULL: plain linear).  One that spans everything is no estimate: a w or
 * E* whose standard error exceeds its value (its log-normal 95% interval is
 * wider than a factor e^1.96 = 7 each way, 50 in all), or a nu whose
 * interval covers all of [0, 0.5], is marked not determined (an upper
 * bound of w stays one). */
static void
intervals_linear(lf_fit_result *r, const char *method)
{
    lf_fit_estimate *e[FIT_NMAT] = { &r->w, &r->Estar, &r->nu };
    int k;

    for (k = 0; k < FIT_NMAT; k++) {
        lf_fit_estimate *x = e[k];
        if (!x->free)
            continue;
        x->interval_method = method;
        if (!x->determined)
            continue;
        if (k != FIT_NU && !(x->se < x->value))
            lf_fit_estimate_drop(x, "its standard error exceeds its value (the linear 95% "
                                 "interval spans more than a factor 50)");
        else if (k == FIT_NU && !(x->ci95[0] > 0.0 || x->ci95[1] < 0.5))
            lf_fit_estimate_drop(x, "its linear 95% interval covers every nu from 0 to 0.5");
    }
}

/* Every free estimate's interval: the linear one where the fit stopped. */
static void
intervals_at_stop(lf_fit_result *r)
{
    intervals_linear(r, LF_INTERVAL_AT_STOP);
}

/* What follows the intervals' verdicts: the pull-off follows w's, and a fit
 * where none is determined is degenerate. */
static void
verdicts_follow(lf_fit_result *res)
{
    lf_fit_pulloff_follows(res);
    lf_fit_degenerate_end(res);
    lf_fit_bound_words(res);
}

int
lf_fit_profile(const lf_fit_settings *settings, size_t ncurves, const lf_fit_curve *curves,
               lf_fit_result *res, int always, lf_error *err)
{
    return lf_fit_profile_at(settings, ncurves, curves, res, always, FIT_LOO_NONE, NULL, err);
}

int
lf_fit_profile_at(const lf_fit_settings *settings, size_t ncurves, const lf_fit_curve *curves,
                  lf_fit_result *res, int always, size_t loo_at, const lf_fit *like,
                  lf_error *err)
{
    static const int which[FIT_NMAT] = { FIT_W, FIT_E, FIT_NU };
    fit_prof p;
    size_t j;
    int round, k, linear;

    if (res == NULL || res->ncurves != ncurves)
        return lf_fail(err, LF_EINVAL, "lf_fit_profile: the result is not of these curves");
    memset(&p, 0, sizeof p);
    p.like = like;
    p.cc = malloc((ncurves ? ncurves : 1) * sizeof *p.cc);
    p.lower_off = malloc((ncurves ? 3 * ncurves : 1) * sizeof *p.lower_off);
    if (p.cc == NULL || p.lower_off == NULL) {
        free(p.cc);
        free(p.lower_off);
        if (loo_at != FIT_LOO_NONE)
            lf_fit_leave_one_out_at(settings, ncurves, curves, res, loo_at, like);
        return lf_fail(err, LF_ENOMEM, "out of memory");
    }
    for (j = 0; j < ncurves; j++) {
        p.cc[j] = curves[j];
        if (res->curves[j].model != NULL) {
            const lf_model_type *t = lf_model_type_find(res->curves[j].model);
            if (t != NULL)
                p.cc[j].model = t;
        }
    }
    /* res's own leave-one-out, where its assessment left it waiting: made
     * only if no lower point replaces res (lf_fit_refit_settle) */
    p.loo_due = loo_at != FIT_LOO_NONE;
    p.loo_at = loo_at;
    if (!res->converged) {
        /* rises from a point that is no minimum measure nothing (they go
         * negative where the fit would have gone on) */
        lf_fit_refit_settle(&p, res);
        intervals_at_stop(res);
        verdicts_follow(res);
        free(p.cc);
        free(p.lower_off);
        return LF_OK;
    }
    p.s = settings;
    p.nc = ncurves;
    /* the linear intervals reported: the search of the check all the same
     * (its refits are where lower minima are found) */
    linear = (always & 3) == LF_PROFILE_LINEAR || (always & LF_PROFILE_REPORT_LINEAR) != 0;
    p.mode = (always & 3) == LF_PROFILE_LINEAR ? LF_PROFILE_CHECK : always & 3;
    p.calibrate = (always & LF_PROFILE_CALIBRATE) != 0 && !linear;
    /* the minimum, always, whatever the intervals asked (descend.c); the
     * chi2 of a robust loss is no likelihood: its minimum is the
     * reweighting's */
    if (settings->loss == LF_LOSS_LINEAR)
        lf_fit_descend(&p, res);
    if (!res->converged) {
        intervals_at_stop(res);         /* below a local minimum, no minimum reached */
    } else if (settings->loss != LF_LOSS_LINEAR) {
        intervals_linear(res, NULL);    /* chi2 of a robust loss is no likelihood */
    } else {
        for (round = 0;; round++) {
            lf_fit_estimate *e[FIT_NMAT] = { &res->w, &res->Estar, &res->nu };
            lf_fit_estimate copy[FIT_NMAT];
            int moved;
            p.best = res;
            p.thr = lf_fit_hold_threshold(res);
            p.lower_chi2 = res->chi2;
            for (k = 0; k < FIT_NMAT && !(p.lower_chi2 < res->chi2); k++) {
                p.which = which[k];
                copy[k] = *e[k];
                profile_one(&p, linear ? &copy[k] : e[k]);
            }
            /* a lower point: refit there and profile again (res is
             * converged: a refit that is not ends the rounds) */
            if (!(p.lower_chi2 < res->chi2) || round >= PROFILE_MAX_REFITS)
                break;
            moved = lf_fit_refit_lower(&p, res, "profile");
            if (moved == 2)
                intervals_at_stop(res);
            if (moved != 1)
                break;
        }
        if (linear && res->converged)
            intervals_linear(res, LF_INTERVAL_UNCHECKED);
    }
    lf_fit_refit_settle(&p, res);       /* res is final: its leave-one-out */
    res->profile_fits = p.fits;
    verdicts_follow(res);
    lf_fit_free(p.walker);
    lf_fit_free(p.held);
    free(p.cc);
    free(p.lower_off);
    return LF_OK;
}
