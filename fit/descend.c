/* descend.c: the minimum, always.  Before any interval is made, the fit's
 * estimate becomes the lowest chi2 a search around it finds, in every
 * interval mode (lf_fit_profile calls lf_fit_descend first, for
 * LF_PROFILE_LINEAR too), so that no estimate depends on the intervals
 * asked; and a lower point found anywhere (here, or by a profile's held
 * refits) restarts the fit from there (lf_fit_refit_lower).
 *
 * Where the model's contact edge is abrupt (the half-space's detachment
 * under displacement control, a k > 2 probe's edge), chi2 jumps each time a
 * point crosses it and is smooth between the jumps: a staircase of basins,
 * and the solver ends in one of them.  A lower one can lie a few standard
 * errors away: eleven PEG hydrogel exports fitted jointly as half-spaces
 * end at chi2 9.02e7 (w = 1.098 mJ/m^2), while 8.70e7 lies six standard
 * errors of w away, chi2 falling by jumps of some 1e6 along the way.  So
 * chi2 is evaluated on each determined material parameter's linear path
 * (every other free parameter moved by its regression on it, from the
 * covariance: the valley of the local quadratic) at DESCEND_STEPS standard
 * errors either side, one evaluation of the model per point and no fit;
 * the lowest point below the fit's chi2 by FIT_PROFILE_LOWER of the
 * profile's threshold restarts the fit there, and the search is made again
 * from the new minimum, at most DESCEND_ROUNDS times. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit.h"

/* multiples of the standard error walked either side (the walk's points
 * t = -0.5, 0.5, -1, 1, ...: FIT_WALK_N in all) */
static const double descend_steps[FIT_WALK_N / 2] = { 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0 };
#define DESCEND_NSTEPS (FIT_WALK_N / 2)
#define DESCEND_ROUNDS 3

static const char *const mat_name[FIT_NMAT] = { "w", "E*", "nu" };

/* The index of parameter name in res, npar when it is not free. */
static size_t
index_of(const lf_fit_result *res, const char *name)
{
    size_t i;
    for (i = 0; i < res->npar; i++)
        if (strcmp(res->names[i], name) == 0)
            return i;
    return res->npar;
}

int
lf_fit_path_chi2(fit_prof *p, const lf_fit_result *res, int which, int strict, size_t nt,
                 const double *t, double *chi2, lf_material *mat_low, double *off_low)
{
    const size_t nc = p->nc;
    lf_fit *g;
    gsl_vector *r;
    size_t i, j, np = res->npar, k = index_of(res, mat_name[which]), q, qq, *by_t;
    double best = HUGE_VAL, **slot;
    lf_material mat;
    int found = 0;

    for (q = 0; q < nt; q++)
        chi2[q] = NAN;
    if (k == np || !(lf_fit_result_cov(res, k, k) > 0))
        return 0;
    /* one fit of the curves for every path: each point sets all it uses
     * (the material, the free offsets, the origin) */
    if (p->walker == NULL)
        p->walker = lf_fit_alloc_like(p->s, nc, p->cc, p->like, NULL);
    g = p->walker;
    if (g == NULL || g->np != np)
        return 0;
    r = gsl_vector_alloc(g->nres);
    by_t = malloc((nt ? nt : 1) * sizeof *by_t);
    slot = malloc(np * sizeof *slot);
    if (r == NULL || by_t == NULL || slot == NULL) {
        gsl_vector_free(r);
        free(by_t);
        free(slot);
        return 0;
    }
    /* where each parameter's value goes (NULL: nowhere) */
    for (i = 0; i < np; i++) {
        size_t jj;
        slot[i] = NULL;
        if (strcmp(res->names[i], "w") == 0)
            slot[i] = &mat.w;
        else if (strcmp(res->names[i], "E*") == 0)
            slot[i] = &mat.Estar;
        else if (strcmp(res->names[i], "nu") == 0)
            slot[i] = &mat.nu;
        else if (sscanf(res->names[i], "z0[%zu]", &jj) == 1 && jj >= 1 && jj <= nc)
            slot[i] = &g->c[jj - 1].z0;
        else if (sscanf(res->names[i], "F0[%zu]", &jj) == 1 && jj >= 1 && jj <= nc)
            slot[i] = &g->c[jj - 1].F0;
        else if (sscanf(res->names[i], "s[%zu]", &jj) == 1 && jj >= 1 && jj <= nc)
            slot[i] = &g->c[jj - 1].slope;
    }
    /* the points in the order of t: each starts the exact model at the
     * roots of its neighbour on the path (lf_model_eval_roots; a point
     * across the estimate, the next of t = -0.5, 0.5, -1, 1, ..., lies
     * too far for those) */
    for (q = 0; q < nt; q++) {
        size_t m = q;
        for (; m > 0 && t[by_t[m - 1]] > t[q]; m--)
            by_t[m] = by_t[m - 1];
        by_t[m] = q;
    }
    for (i = 0; i < g->ndata; i++)
        g->ws.sqrtw[i] = 1.0;        /* least squares (as lf_fit_solve sets) */
    for (qq = 0; qq < nt; qq++) {
        double d, cost;
        int ok = 1;
        q = by_t[qq];
        d = t[q] * sqrt(lf_fit_result_cov(res, k, k));
        mat.w = lf_fit_best_value(res, "w", res->w.value);
        mat.Estar = lf_fit_best_value(res, "E*", res->Estar.value);
        mat.nu = lf_fit_best_value(res, "nu", isfinite(res->nu.value) ? res->nu.value
                                                                      : g->mat.nu);
        for (j = 0; j < nc; j++)
            g->c[j].slope = 0.0;
        for (i = 0; i < np && ok; i++) {
            double c = lf_fit_result_cov(res, i, k) / lf_fit_result_cov(res, k, k), v;
            if (!isfinite(c) && !strict)
                c = 0.0;        /* an undetermined one stays where it is */
            v = res->value[i] + c * d;
            if (!isfinite(v)) {
                ok = 0;
                break;
            }
            if (slot[i] != NULL)
                *slot[i] = v;
        }
        if (!ok || !(mat.w > 0) || !(mat.Estar > 0)
            || (g->imat[FIT_NU] >= 0 && !(mat.nu > 0.0 && mat.nu < 0.5)))
            continue;
        g->mat = mat;
        lf_fit_set_origin(g);
        gsl_vector_set_all(g->ws.x, 1.0);
        cost = lf_fit_cost(g, g->ws.x, r);
        if (!isfinite(cost))
            continue;
        chi2[q] = 2.0 * cost;
        if (mat_low != NULL && chi2[q] < best) {
            best = chi2[q];
            found = 1;
            *mat_low = mat;
            for (j = 0; j < nc; j++) {
                off_low[3 * j] = g->c[j].z0;
                off_low[3 * j + 1] = g->c[j].F0;
                off_low[3 * j + 2] = g->c[j].slope;
            }
        }
    }
    gsl_vector_free(r);
    free(by_t);
    free(slot);
    return found;
}

void
lf_fit_walk_chi2(fit_prof *p, int which, size_t nt, const double *t, double *chi2)
{
    const lf_fit_result *res = p->best;
    size_t i, q, k = index_of(res, mat_name[which]);
    int walked = p->walk_stamp == p->moves + 1 && p->walk_ok[which] && k < res->npar;

    /* the walk moved a parameter without a covariance by 0 (not strict) */
    for (i = 0; walked && i < res->npar; i++)
        walked = isfinite(lf_fit_result_cov(res, i, k));
    for (q = 0; walked && q < nt; q++) {
        for (i = 0; i < FIT_WALK_N && descend_steps[i / 2] * (i % 2 ? 1.0 : -1.0) != t[q]; i++)
            ;
        walked = i < FIT_WALK_N;
        if (walked)
            chi2[q] = p->walk_chi2[which][i];
    }
    if (!walked)
        lf_fit_path_chi2(p, res, which, 1, nt, t, chi2, NULL, NULL);
}

int
lf_fit_refit_from(const lf_fit_settings *s, size_t nc, const lf_fit_curve *cc,
                  const lf_material *mat, const double *off, lf_fit_result *nr,
                  size_t *loo_at)
{
    lf_fit *g = lf_fit_alloc(s, nc, cc, NULL);
    fit_run run;
    size_t j;
    int st;

    memset(nr, 0, sizeof *nr);
    if (g == NULL)
        return LF_EINVAL;
    g->mat = *mat;
    for (j = 0; j < nc; j++) {
        if (g->c[j].iz0 >= 0 && isfinite(off[3 * j]))
            g->c[j].z0 = off[3 * j];
        if (g->c[j].iF0 >= 0 && isfinite(off[3 * j + 1]))
            g->c[j].F0 = off[3 * j + 1];
        g->c[j].slope = isfinite(off[3 * j + 2]) ? off[3 * j + 2] : 0.0;
    }
    lf_fit_set_origin(g);
    st = lf_fit_solve_begin(g, NULL, &run, nr, NULL);
    if (st == LF_OK)
        st = lf_fit_solve_end_at(g, &run, nr, loo_at, NULL);
    lf_fit_free(g);
    return st;
}

int
lf_fit_refit_lower(fit_prof *p, lf_fit_result *res, const char *where)
{
    lf_fit_result nr;
    size_t loo_at = FIT_LOO_NONE;
    int st;

    /* leave-one-out waits: only the point finally reported needs it (it
     * decides nothing here) */
    st = lf_fit_refit_from(p->s, p->nc, p->cc, &p->lower_mat, p->lower_off, &nr, &loo_at);
    p->fits++;
    if (st != LF_OK && st != LF_ENOCONV)
        return 0;
    if (!(nr.chi2 < res->chi2 - FIT_PROFILE_LOWER * p->thr)) {
        lf_fit_result_free(&nr);
        return 0;
    }
    if (st == LF_OK) {
        lf_warn(&nr.warnings, "the %s of %s passed below the first fit's minimum (chi2 "
                "%.6g, here %.6g): the fit was continued from there", where, mat_name[p->which],
                res->chi2, nr.chi2);
    } else {
        char why[sizeof nr.stop_reason];
        lf_warn(&nr.warnings, "the %s of %s passed below the first fit's minimum (chi2 "
                "%.6g, at %s = %.6g: %.6g), so that was a local minimum; the fit continued "
                "from there stopped at chi2 %.6g without converging (%s): these are the numbers "
                "where it stopped", where, mat_name[p->which], res->chi2, mat_name[p->which],
                p->which == FIT_W ? p->lower_mat.w : p->which == FIT_E ? p->lower_mat.Estar
                                                                        : p->lower_mat.nu,
                p->lower_chi2, nr.chi2, nr.stop_reason);
        snprintf(why, sizeof why, "%s", nr.stop_reason);
        snprintf(nr.stop_reason, sizeof nr.stop_reason, "not converged: below a local "
                 "minimum the fit went on and stopped (%.90s)",
                 strncmp(why, "not converged: ", 15) == 0 ? why + 15 : why);
    }
    lf_fit_keep_choice(&nr, res);
    lf_fit_result_free(res);
    *res = nr;
    p->moves++;
    p->loo_due = loo_at != FIT_LOO_NONE;
    p->loo_at = loo_at;
    return st == LF_OK ? 1 : 2;
}

void
lf_fit_refit_settle(fit_prof *p, lf_fit_result *res)
{
    if (p->loo_due)
        lf_fit_leave_one_out_at(p->s, p->nc, p->cc, res, p->loo_at,
                                p->walker != NULL ? p->walker : p->like);
    p->loo_due = 0;
}

int
lf_fit_descend(fit_prof *p, lf_fit_result *res)
{
    static const int which[FIT_NMAT] = { FIT_W, FIT_E, FIT_NU };
    double t[2 * DESCEND_NSTEPS], *chi2;
    double *off = malloc((p->nc ? 3 * p->nc : 1) * sizeof *off);
    size_t q;
    int round, k, moved = 0;

    if (off == NULL)
        return 0;
    for (q = 0; q < DESCEND_NSTEPS; q++) {
        t[2 * q] = -descend_steps[q];
        t[2 * q + 1] = descend_steps[q];
    }
    for (round = 0; round < DESCEND_ROUNDS && res->converged; round++) {
        const lf_fit_estimate *e[FIT_NMAT] = { &res->w, &res->Estar, &res->nu };
        double thr = lf_fit_hold_threshold(res);
        int found = 0;
        p->walk_stamp = p->moves + 1;
        p->best = res;
        p->thr = thr;
        p->lower_chi2 = res->chi2 - FIT_PROFILE_LOWER * thr;
        for (k = 0; k < FIT_NMAT; k++) {
            lf_material m;
            size_t i;
            p->walk_ok[k] = 0;
            if (!e[k]->free || !e[k]->determined)
                continue;
            chi2 = p->walk_chi2[k];
            p->walk_ok[k] = 1;
            if (!lf_fit_path_chi2(p, res, k, 0, 2 * DESCEND_NSTEPS, t, chi2, &m, off))
                continue;
            for (i = 0; i < 2 * DESCEND_NSTEPS; i++)
                if (chi2[i] < p->lower_chi2)
                    break;
            if (i == 2 * DESCEND_NSTEPS)
                continue;
            /* the lowest point of this path (lf_fit_path_chi2 kept it) */
            p->lower_chi2 = chi2[i];
            for (; i < 2 * DESCEND_NSTEPS; i++)
                p->lower_chi2 = lf_fmin(p->lower_chi2, chi2[i]);
            p->which = which[k];
            p->lower_mat = m;
            memcpy(p->lower_off, off, 3 * p->nc * sizeof *off);
            found = 1;
        }
        if (!found || lf_fit_refit_lower(p, res, "linear path") == 0)
            break;
        moved = 1;
    }
    free(off);
    return moved;
}
