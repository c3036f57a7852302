/* verdict.c: an honest end.  The solver's own stopping rules say when it
 * stopped; these checks say whether where it stopped is an answer.
 *
 *   refuse     before fitting: a curve whose force is constant, or does
 *              not rise above its noise (2 sqrt(2 ln n) + 2 sd) and is not correlated with
 *              depth either (|r| < 3/sqrt(n)), has no contact signal and is
 *              refused with a message: there is nothing to fit.
 *   offsets    a free force offset F0 more than one force range outside
 *              the data's forces, or a free contact point z0 more than two
 *              depth spans outside the data's depths (a curve wholly in
 *              contact puts z0 before its first point), is not an answer: not
 *              converged, and why.
 *   stall      at the end, the Gauss-Newton step from the solution predicts
 *              how much chi2 could still fall.  When it is more than one
 *              (scaled) standard error's worth and a step along it really
 *              lowers the cost, the solve continues from there; if it still
 *              could fall that much, the fit stalled: not converged.  When
 *              a run that stopped short (e.g. "no further progress") sits
 *              where that step would lower chi2 by less than FIT_ROUNDING_SE2
 *              standard errors squared, it is at a minimum within rounding:
 *              converged.  Where no step along the Gauss-Newton direction
 *              lowers the cost (a kink, or a direction the linear model
 *              gets wrong), or the convergence was claimed by the solver's
 *              own step or gradient test (tolerances the user sets), the
 *              solver is restarted from the solution (made the origin) with
 *              the default tolerances and budget: if that lowers chi2
 *              by more than a quarter se^2, it was not a minimum either
 *              (continued once, then a stall). */
#include <math.h>
#include <stdio.h>
#include <string.h>


#include "fit.h"

#define FIT_ROUNDING_SE2 1e-4    /* GN decrease, in se^2, of a minimum */
#define FIT_STALL_SE2 1.0        /* GN decrease, in se^2, of a stall */
#define FIT_STALL_SLOPE 16.0     /* the most a trial step may beat its slope by */

/* The correlation of curve c's force with its depth: a contact signal
 * rises with depth even where the noise estimate is inflated (few
 * points). */
static double
depth_force_corr(const fit_curve *c)
{
    double mz = 0, mf = 0, szz = 0, sff = 0, szf = 0;
    size_t i;

    for (i = 0; i < c->data.n; i++) {
        mz += c->data.depth[i];
        mf += c->data.force[i];
    }
    mz /= (double) c->data.n;
    mf /= (double) c->data.n;
    for (i = 0; i < c->data.n; i++) {
        double dz = c->data.depth[i] - mz, df = c->data.force[i] - mf;
        szz += dz * dz;
        sff += df * df;
        szf += dz * df;
    }
    return szz > 0 && sff > 0 ? szf / sqrt(szz * sff) : 0.0;
}

int
lf_fit_refuse_degenerate(const lf_fit *f, lf_error *err)
{
    size_t j;
    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        const double lo = c->flo, hi = c->fhi;
        /* pure noise of n points spans about 2 sqrt(2 ln n) sd; the
         * correlation is asked only of a span within that */
        if (!(hi > lo) || (!(hi - lo > (2.0 * sqrt(2.0 * log((double) c->data.n)) + 2.0) * c->sigma)
                           && fabs(depth_force_corr(c)) < 3.0 / sqrt((double) c->data.n)))
            return lf_fail(err, LF_EDATA, "curve %zu (%s): no contact signal: the force varies "
                           "by only %.3g N (%.3g times its noise sd %.3g N); nothing to fit",
                           j + 1, c->data.name ? c->data.name : "", hi - lo,
                           c->sigma > 0 ? (hi - lo) / c->sigma : 0.0, c->sigma);
    }
    return LF_OK;
}

/* When an offset at x lies far outside its curve's data, run's verdict:
 * ran away, in words, with the offset's column. */
static void
offsets_outside(const lf_fit *f, const double *x, fit_run *run)
{
    size_t j;
    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        lf_material m;
        const double flo = c->flo, fhi = c->fhi, zlo = c->zlo, zhi = c->zhi;
        double z0, F0, s;
        lf_fit_unpack(f, x, &m, &z0, &F0, &s, j);
        if (c->iF0 >= 0 && !(F0 >= flo - (fhi - flo) && F0 <= fhi + (fhi - flo))) {
            lf_fit_run_says(run, LF_STOP_RAN_AWAY, "not converged: curve %zu's force offset "
                            "F0 = %.4g N lies far outside its forces [%.4g, %.4g] N", j + 1, F0,
                            flo, fhi);
            run->ran_col = c->iF0;
            return;
        }
        if (c->iz0 >= 0 && !(z0 >= zlo - 2.0 * (zhi - zlo) && z0 <= zhi + 2.0 * (zhi - zlo))) {
            lf_fit_run_says(run, LF_STOP_RAN_AWAY, "not converged: curve %zu's contact point "
                            "z0 = %.4g m lies far outside its depths [%.4g, %.4g] m", j + 1, z0,
                            zlo, zhi);
            run->ran_col = c->iz0;
            return;
        }
    }
}

/* The Gauss-Newton step at x (internal coordinates, into step) and the
 * decrease of chi2 it predicts; NaN when it cannot be computed.  From the
 * block Cholesky of J^T J (block.c) where every pivot is above
 * FIT_GN_PIVOT of its diagonal (J's columns far from dependent: the normal
 * equations, which square J's condition, lose nothing that matters) and
 * the SVD below would cut no direction (trace(J^T J) trace((J^T J)^-1),
 * a bound on S_0^2 / S_min^2, below 1e20): step = -(J^T J)^-1 J^T r, the
 * decrease -g^T step, the SVD's within rounding.  Otherwise, up to
 * FIT_DENSE_P parameters, from the SVD J = U S V^T (decomp.c, unscaled: QR,
 * then the small R): step = -V S^-1 U^T r over the directions with
 * S_l > 1e-10 S_0, the decrease of chi2 = sum (U_l . r)^2 over them (the
 * damped normal equations' step, where w is not determined, found no
 * decrease the SVD's finds, and a claimed convergence stood above a lower
 * point); beyond, the Cholesky of J^T J + 1e-20 diag(J^T J), its
 * directions below 1e-10 of each column's scale damped away. */
#define FIT_GN_PIVOT 1e-8
static double
gn_step(lf_fit *f, const gsl_vector *x, gsl_vector *step)
{
    const size_t p = f->np;
    fit_arrow *A = &f->ws.gsl_jtj;
    double *g = f->ws.grad, *d2 = f->ws.colmax, dec = NAN;
    size_t i;
    int ok;

    if (lf_fit_residuals(x, f, f->ws.r2) != GSL_SUCCESS
        || lf_fit_normal_sums(f, x->data, f->ws.r2->data, A, g, d2) != GSL_SUCCESS)
        return NAN;
    ok = lf_arrow_factor(&f->ws.jchol, A, NULL, 0.0, FIT_GN_PIVOT);
    if (ok) {
        /* and no direction the SVD would cut: S_max^2 / S_min^2 is at most
         * trace(J^T J) trace((J^T J)^-1) (step as scratch) */
        double tr = 0.0, tri = 0.0;
        lf_arrow_diag(A, d2);
        lf_arrow_inv_diag(&f->ws.jchol, step->data);
        for (i = 0; i < p; i++) {
            tr += d2[i];
            tri += step->data[i];
        }
        ok = tr * tri < 1e20;
    }
    if (!ok && p <= FIT_DENSE_P) {
        fit_decomp d;
        double *coef;
        size_t l;

        if (lf_fit_decomp_alloc(&d, f->nres, p) != LF_OK)
            return NAN;
        if (lf_fit_jacobian(x, f, d.QR) == GSL_SUCCESS
            && lf_fit_decomp_factor(&d, 1e-10, 0) == LF_OK) {
            coef = d.work->data;       /* the factorisation's scratch, free again */
            lf_fit_decomp_project(&d, f->ws.r2->data, coef);   /* (U_l . r) / S_l */
            gsl_vector_set_zero(step);
            dec = 0.0;
            for (l = 0; l < d.rank; l++) {
                const double sl = gsl_vector_get(d.S, l);
                dec += coef[l] * sl * coef[l] * sl;
                for (i = 0; i < p; i++)
                    step->data[i] -= gsl_matrix_get(d.V, i, l) * coef[l];
            }
        }
        lf_fit_decomp_free(&d);
        return dec;
    }
    if (!ok) {
        lf_arrow_diag(A, d2);
        if (!lf_arrow_factor(&f->ws.jchol, A, d2, 1e-20, 0.0))
            return NAN;
    }
    for (i = 0; i < p; i++)
        step->data[i] = -g[i];
    lf_arrow_solve(&f->ws.jchol, step->data, step->data);
    dec = 0.0;
    for (i = 0; i < p; i++)
        dec -= g[i] * step->data[i];
    return dec;
}

int
lf_fit_honest_end(lf_fit *f, gsl_vector *x, fit_run *run, lf_error *err)
{
    gsl_vector *step = gsl_vector_alloc(f->np), *trial = gsl_vector_alloc(f->np);
    double chi2, s2, dec;
    int status = LF_OK, round;

    if (step == NULL || trial == NULL) {
        gsl_vector_free(step);
        gsl_vector_free(trial);
        return lf_fail(err, LF_ENOMEM, "out of memory");
    }
    for (round = 0; round < 2; round++) {
        /* the solver's last look at its Jacobian, when it was here: the
         * step itself is needed only when it would be tried */
        int known = lf_fit_gn_at(f, x);
        double c0, c1 = HUGE_VAL;
        int lower = 0;
        chi2 = known ? f->ws.gn_chi2 : 2.0 * lf_fit_cost(f, x, f->ws.r);
        s2 = lf_fmax(1.0, chi2 / (double) (f->nres > f->np ? f->nres - f->np : 1));
        c0 = 0.5 * chi2;
        dec = known ? f->ws.gn_dchi2 : gn_step(f, x, step);
        if (known && isfinite(dec) && run->converged && dec > FIT_STALL_SE2 * s2)
            dec = gn_step(f, x, step);
        if (!isfinite(dec))
            break;
        if (!run->converged && dec < FIT_ROUNDING_SE2 * s2 && run->stop != LF_STOP_ITERATIONS) {
            lf_fit_run_says(run, LF_STOP_CONVERGED, "converged (at a minimum within rounding: "
                            "a Gauss-Newton step would lower chi2 by only %.2g)", dec);
            break;
        }
        /* a run the solver stopped for its own limits (iterations, no
         * progress) keeps its verdict; only a claimed convergence is
         * checked for a stall */
        if (!run->converged)
            break;
        if (dec > FIT_STALL_SE2 * s2) {
            /* a real step down?  halve until the cost (half chi2) falls by
             * want, while a step of t along the Gauss-Newton direction could
             * give it: the cost falls by t dec to first order, and a fall
             * FIT_STALL_SLOPE times that is not looked for (at a kink every
             * trial fails, and thirty halvings cost thirty evaluations of
             * the model) */
            const double want = 0.25 * FIT_STALL_SE2 * s2;
            double t = 1.0;
            int h;
            for (h = 0; h < 30 && FIT_STALL_SLOPE * t * dec >= want; h++, t *= 0.5) {
                size_t i;
                for (i = 0; i < f->np; i++)
                    trial->data[i] = x->data[i] + t * step->data[i];
                c1 = lf_fit_cost(f, trial, f->ws.r2);
                if (c1 < c0 - want) {
                    lower = 1;
                    break;
                }
            }
        }
        if (!lower && (dec > FIT_STALL_SE2 * s2 || run->user_test)) {
            /* no step along it (a kink, or a direction the linear model gets
             * wrong), or a convergence claimed by the solver's own step or
             * gradient test (their tolerances are the user's): the solver
             * restarted from here decides */
            fit_run again;
            lf_fit_settings user = f->set, def = lf_fit_settings_default();
            memset(&again, 0, sizeof again);
            /* from a fresh origin at x (the solver's scaling starts anew) */
            lf_fit_rebase(f, x);        /* (invalidates what was computed at x) */
            gsl_vector_memcpy(trial, x);
            /* with the default tolerances and budget: the judge's own */
            f->set.xtol = def.xtol;
            f->set.gtol = def.gtol;
            f->set.ftol = def.ftol;
            f->set.max_iter = def.max_iter;
            status = lf_fit_solve_scanned(f, trial, 0, &again, err);
            f->set = user;
            if (status != LF_OK)
                break;
            run->iters += again.iters;
            run->evals += again.evals;
            c1 = lf_fit_cost(f, trial, f->ws.r2);
            lower = c1 < c0 - 0.25 * FIT_STALL_SE2 * s2;
            if (lower && round == 0) {
                /* the restart went on from there: its verdict stands, checked
                 * again in the next round */
                gsl_vector_memcpy(x, trial);
                lf_fit_run_verdict_from(run, &again);
                continue;
            }
        }
        if (!lower)
            break;
        if (round == 1) {
            lf_fit_run_says(run, LF_STOP_STALLED, "not converged: stalled away from a "
                            "minimum (a step still lowers chi2 by %.3g, %.3g standard errors "
                            "squared)", 2.0 * (c0 - c1), 2.0 * (c0 - c1) / s2);
            break;
        }
        gsl_vector_memcpy(x, trial);
        lf_fit_invalidate(f);
        status = lf_fit_solve_scanned(f, x, 0, run, err);
        if (status != LF_OK)
            break;
    }
    if (status == LF_OK)
        offsets_outside(f, x->data, run);
    gsl_vector_free(step);
    gsl_vector_free(trial);
    return status;
}

/* 1 when some material parameter is free and the data determine none of
 * the free ones (nor M = Z E*, what bonded curves alone fix). */
static int
none_determined(const lf_fit_result *r)
{
    const lf_fit_estimate *e[FIT_NMAT] = { &r->w, &r->Estar, &r->nu };
    int any_free = 0, k;

    for (k = 0; k < FIT_NMAT; k++) {
        any_free |= e[k]->free;
        if (e[k]->free && e[k]->determined)
            return 0;
    }
    return any_free && !r->M.determined;
}

void
lf_fit_degenerate_end(lf_fit_result *r)
{
    if (!r->converged || !none_determined(r))
        return;
    r->converged = 0;
    r->stop = LF_STOP_DEGENERATE;
    snprintf(r->stop_reason, sizeof r->stop_reason, "not converged: degenerate: the data "
             "determine none of the material parameters fitted");
    lf_warn(&r->warnings, "the fit stopped where the data determine none of the material "
            "parameters fitted (w, E*, nu): the numbers below describe no minimum to report");
}
