/* profile.c: profile-likelihood intervals of w, E* and nu.
 *
 * The linear (Wald) interval value +- 1.96 se assumes chi2 is quadratic in
 * the parameter (in ln w and ln E*, in nu) over the interval.  Where the
 * data are weak (offsets free, few probes) it is not, and the interval
 * covers the truth far less often than 95%.  The profile of a parameter is
 * chi2 minimised over every other parameter with that one held; its 95%
 * interval is where the profile stays within 3.84 s^2 of the minimum (s^2 =
 * se_scale^2: the noise scale and its correlation, uncertainty.c).
 *
 * Rule: the profile is evaluated at the two Wald endpoints first.  When
 * both rises are within PROFILE_TOL of 3.84 s^2, the curvature bears out
 * the linear interval and it stays ("linear (Wald)").  Otherwise each side
 * is searched outwards (doubling the step) until the profile reaches the
 * threshold, then bisected: the interval is asymmetric where the data are.
 * A side the profile never reaches within PROFILE_LOG_RANGE (ln units) of
 * w or E*, or up to nu's bounds, is open: w's lower bound then is 0, nu's
 * the bound of its range; an open upper side of w or E* means the data do
 * not bound it, and the estimate is marked not determined.
 *
 * Each profile point is a fit with the parameter held, warm-started at the
 * best fit's material and offsets (per curve with the model the fit used). */
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#include "fit.h"

#define Z95 1.959963984540054
#define CHI2_95 3.841458820694124
#define PROFILE_TOL 0.25
#define PROFILE_LOG_RANGE 12.0
#define PROFILE_BISECT 10

typedef struct {
    const lf_fit_settings *s;
    size_t nc;
    lf_fit_curve *cc;          /* the curves, each with its fitted model */
    const lf_fit_result *best;
    int which;                 /* FIT_W, FIT_E, FIT_NU */
    double thr;                /* 3.84 s^2 */
    size_t fits;
} prof;

/* The fitted value of the parameter called name (the solution, even where
 * the report says "not determined"), else fallback. */
static double
best_value(const lf_fit_result *r, const char *name, double fallback)
{
    size_t k;
    for (k = 0; k < r->npar; k++)
        if (strcmp(r->names[k], name) == 0 && isfinite(r->value[k]))
            return r->value[k];
    return fallback;
}

/* chi2 minus the best chi2 with parameter `which` held at v (NaN on a
 * failed fit). */
static double
rise(prof *p, double v)
{
    lf_fit_settings s = *p->s;
    lf_fit_param *par = p->which == FIT_W ? &s.w : p->which == FIT_E ? &s.Estar : &s.nu;
    lf_fit_result r;
    lf_fit *g;
    size_t j;
    int st, offsets_known = 1;
    double out = NAN;

    par->mode = LF_PARAM_FIXED;
    par->value = v;
    g = lf_fit_alloc(&s, p->nc, p->cc, NULL);
    if (g == NULL)
        return NAN;
    g->mat.w = best_value(p->best, "w", p->best->w.value);
    g->mat.Estar = best_value(p->best, "E*", p->best->Estar.value);
    g->mat.nu = best_value(p->best, "nu", p->best->nu.value);
    if (!isfinite(g->mat.nu))
        g->mat.nu = p->s->nu.value;
    if (!isfinite(g->mat.w))
        g->mat.w = 0.0;
    if (p->which == FIT_W)
        g->mat.w = v;
    else if (p->which == FIT_E)
        g->mat.Estar = v;
    else
        g->mat.nu = v;
    for (j = 0; j < p->nc; j++) {
        char name[32];
        double z0, F0, sl;
        snprintf(name, sizeof name, "z0[%zu]", j + 1);
        z0 = best_value(p->best, name, p->best->curves[j].z0);
        snprintf(name, sizeof name, "F0[%zu]", j + 1);
        F0 = best_value(p->best, name, p->best->curves[j].F0);
        snprintf(name, sizeof name, "s[%zu]", j + 1);
        sl = best_value(p->best, name, p->best->curves[j].slope);
        if (g->c[j].iz0 >= 0 && isfinite(z0))
            g->c[j].z0 = z0;
        else if (g->c[j].iz0 >= 0)
            offsets_known = 0;
        if (g->c[j].iF0 >= 0 && isfinite(F0))
            g->c[j].F0 = F0;
        else if (g->c[j].iF0 >= 0)
            offsets_known = 0;
        g->c[j].slope = isfinite(sl) ? sl : 0.0;
    }
    if (offsets_known)
        lf_fit_set_origin(g);
    else
        lf_fit_guess_offsets(g);
    st = lf_fit_solve(g, NULL, 0, &r, NULL);
    p->fits++;
    if (st == LF_OK || st == LF_ENOCONV) {
        out = r.chi2 - p->best->chi2;
        lf_fit_result_free(&r);
    }
    lf_fit_free(g);
    return out;
}

/* Map between the searched coordinate t and the parameter. */
static double
param_of(const prof *p, double t)
{
    return p->which == FIT_NU ? t : exp(t);
}

/* The point on one side (dir = -1 or +1) where the profile reaches the
 * threshold, from t_hat with first step h; *open when it never does. */
static double
search_side(prof *p, double t_hat, double h, int dir, double tmin, double tmax, int *open)
{
    double a = 0.0, b = h, ra;
    int i;

    *open = 0;
    for (;;) {
        double t = t_hat + dir * b, rb;
        if (t <= tmin || t >= tmax) {
            t = dir < 0 ? tmin : tmax;
            rb = rise(p, param_of(p, t));
            if (!(rb >= p->thr)) {
                *open = 1;
                return t;
            }
            b = fabs(t - t_hat);
            break;
        }
        rb = rise(p, param_of(p, t));
        if (rb >= p->thr || !isfinite(rb))
            break;
        a = b;
        b *= 2.0;
    }
    ra = 0.0;
    (void) ra;
    for (i = 0; i < PROFILE_BISECT; i++) {
        double m = 0.5 * (a + b), rm = rise(p, param_of(p, t_hat + dir * m));
        if (rm >= p->thr || !isfinite(rm))
            b = m;
        else
            a = m;
    }
    return t_hat + dir * 0.5 * (a + b);
}

/* Profile one estimate; 1 when its interval changed. */
static int
profile_one(prof *p, lf_fit_estimate *e, int always)
{
    double t_hat, se_t, tmin, tmax, lo, hi, r_lo, r_hi;
    int open_lo = 0, open_hi = 0;

    int bound_only = e->upper_bound_only && p->which == FIT_W;

    if (!e->free || (!e->determined && !bound_only) || (!bound_only && !(e->se > 0)))
        return 0;
    if (p->which == FIT_NU) {
        t_hat = e->value;
        se_t = e->se;
        tmin = 0.0;
        tmax = 0.5 - 1e-9;
    } else if (bound_only) {
        /* w below two se: the solution's w, however small, and steps of a
         * factor e^0.5 */
        double w = best_value(p->best, "w", 0.0);
        t_hat = log(fmax(w, 1e-3 * e->ci95[1]));
        se_t = 0.5 / Z95;
        tmin = t_hat - PROFILE_LOG_RANGE;
        tmax = t_hat + PROFILE_LOG_RANGE;
    } else {
        t_hat = log(e->value);
        se_t = e->se / e->value;
        tmin = t_hat - PROFILE_LOG_RANGE;
        tmax = t_hat + PROFILE_LOG_RANGE;
    }
    e->interval_method = "linear (Wald)";
    if (!bound_only && !always) {
        r_lo = t_hat - Z95 * se_t > tmin ? rise(p, param_of(p, t_hat - Z95 * se_t)) : NAN;
        r_hi = t_hat + Z95 * se_t < tmax ? rise(p, param_of(p, t_hat + Z95 * se_t)) : NAN;
        if (fabs(r_lo / p->thr - 1.0) < PROFILE_TOL && fabs(r_hi / p->thr - 1.0) < PROFILE_TOL)
            return 0;
    }
    lo = search_side(p, t_hat, fmin(Z95 * se_t, 0.5 * (t_hat - tmin)), -1, tmin, tmax, &open_lo);
    hi = search_side(p, t_hat, fmin(Z95 * se_t, 0.5 * (tmax - t_hat)), +1, tmin, tmax, &open_hi);
    e->interval_method = "profile likelihood";
    e->ci95[0] = open_lo && p->which == FIT_W ? 0.0 : param_of(p, lo);
    e->ci95[1] = param_of(p, hi);
    if (bound_only && !open_lo) {
        /* the profile closes below: the data do bound w from below */
        e->upper_bound_only = 0;
        e->determined = 1;
        e->value = exp(t_hat);
        e->se = e->value * (hi - lo) / (2.0 * Z95);   /* the interval's width */
    }
    if (p->which == FIT_NU) {
        e->ci95[0] = fmax(e->ci95[0], 0.0);
        e->ci95[1] = fmin(e->ci95[1], 0.5);
    }
    if (open_hi && p->which != FIT_NU) {
        /* the data do not bound it from above */
        e->determined = 0;
        e->ci95[1] = NAN;
        if (bound_only) {
            e->upper_bound_only = 0;
            e->ci95[0] = NAN;
        }
    }
    return 1;
}

int
lf_fit_profile(const lf_fit_settings *settings, size_t ncurves, const lf_fit_curve *curves,
               lf_fit_result *res, int always, lf_error *err)
{
    prof p;
    size_t j;

    if (res == NULL || res->ncurves != ncurves)
        return lf_fail(err, LF_EINVAL, "lf_fit_profile: the result is not of these curves");
    if (settings->loss != LF_LOSS_LINEAR)
        return LF_OK;       /* chi2 of a robust loss is not a likelihood */
    memset(&p, 0, sizeof p);
    p.cc = malloc((ncurves ? ncurves : 1) * sizeof *p.cc);
    if (p.cc == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory");
    for (j = 0; j < ncurves; j++) {
        p.cc[j] = curves[j];
        if (res->curves[j].model != NULL) {
            const lf_model_type *t = lf_model_type_find(res->curves[j].model);
            if (t != NULL)
                p.cc[j].model = t;
        }
    }
    p.s = settings;
    p.nc = ncurves;
    p.best = res;
    p.thr = CHI2_95 * res->se_scale * res->se_scale;
    p.which = FIT_W;
    profile_one(&p, &res->w, always);
    p.which = FIT_E;
    profile_one(&p, &res->Estar, always);
    p.which = FIT_NU;
    profile_one(&p, &res->nu, always);
    res->profile_fits = p.fits;
    free(p.cc);
    return LF_OK;
}

int
lf_fit_w_open_above(lf_fit *f, const lf_fit_result *r, double factor)
{
    prof p;
    size_t j;
    double w, up;
    int open;

    if (f->imat[FIT_W] < 0)
        return 0;
    w = r->value[f->imat[FIT_W]];
    if (!(w > 0) || !(r->se_scale > 0))
        return 0;
    memset(&p, 0, sizeof p);
    p.cc = malloc(f->ncurves * sizeof *p.cc);
    if (p.cc == NULL)
        return 0;
    for (j = 0; j < f->ncurves; j++) {
        p.cc[j] = f->c[j].data;
        p.cc[j].model = lf_model_get_type(f->c[j].model);
    }
    p.s = &f->set;
    p.nc = f->ncurves;
    p.best = r;
    p.which = FIT_W;
    p.thr = CHI2_95 * r->se_scale * r->se_scale;
    up = rise(&p, w * factor);
    open = isfinite(up) && up < p.thr;
    free(p.cc);
    return open;
}
