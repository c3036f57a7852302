/* driver.c: the fit's life cycle (alloc, run, free) around GSL's
 * gsl_multifit_nlinear trust-region solver.
 *
 * The workspace is sized once from the curves; runs reuse it.  GSL's error
 * handler must be off in the calling program (the layerfit command and the
 * tests turn it off); every GSL status is checked here. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>

#include "fit.h"

#define NSUB_MAX 64

static const struct {
    const char *name;
    const gsl_multifit_nlinear_trs *const *trs;
} methods[] = {
    { "lm", &gsl_multifit_nlinear_trs_lm },
    { "lmaccel", &gsl_multifit_nlinear_trs_lmaccel },
    { "dogleg", &gsl_multifit_nlinear_trs_dogleg },
    { "ddogleg", &gsl_multifit_nlinear_trs_ddogleg },
    { "subspace2D", &gsl_multifit_nlinear_trs_subspace2D },
};

const char *const lf_fit_methods[] = {
    "lm", "lmaccel", "dogleg", "ddogleg", "subspace2D", NULL
};

lf_fit_settings
lf_fit_settings_default(void)
{
    lf_fit_settings s;
    memset(&s, 0, sizeof s);
    s.model = &lf_model_thin;
    s.method = "lm";
    s.jacobian = LF_JAC_ANALYTIC;
    s.w.mode = s.Estar.mode = s.nu.mode = LF_PARAM_AUTO;
    s.w.value = s.Estar.value = NAN;
    s.nu.value = 0.3;
    s.w.prior_sd = s.Estar.prior_sd = s.nu.prior_sd = NAN;
    s.fit_slope = 0;
    s.max_iter = 200;
    s.xtol = 1e-11;
    s.gtol = 1e-12;
    s.ftol = 0.0;
    s.rcond = 1e-7;
    s.max_b_over_a = 0.1;
    return s;
}

static int
check_curve(const lf_fit_curve *c, size_t j, lf_error *err)
{
    size_t i;
    const char *name = c->name ? c->name : "";

    if (lf_probe_check(&c->probe, err) != LF_OK)
        return lf_fail(err, LF_EINVAL, "curve %zu (%s): %s", j + 1, name, err ? err->msg : "bad probe");
    if (c->branch != LF_BRANCH_UNLOAD && c->branch != LF_BRANCH_LOAD)
        return lf_fail(err, LF_EINVAL, "curve %zu (%s): unknown branch", j + 1, name);
    if (c->n < 5 || c->depth == NULL || c->force == NULL)
        return lf_fail(err, LF_EDATA, "curve %zu (%s): %zu points, a fit needs at least 5",
                       j + 1, name, c->n);
    for (i = 0; i < c->n; i++)
        if (!isfinite(c->depth[i]) || !isfinite(c->force[i]))
            return lf_fail(err, LF_EDATA, "curve %zu (%s): point %zu is not finite",
                           j + 1, name, i + 1);
    if (!(isfinite(c->z0) || isnan(c->z0)) || !(isfinite(c->F0) || isnan(c->F0)))
        return lf_fail(err, LF_EINVAL, "curve %zu (%s): held z0 and F0 must be finite",
                       j + 1, name);
    return LF_OK;
}

/* Depth span, force scale, guard width and noise of each curve. */
static int
curve_scales(lf_fit *f, lf_error *err)
{
    size_t i, j;

    for (j = 0; j < f->ncurves; j++) {
        fit_curve *c = &f->c[j];
        double zmin = HUGE_VAL, zmax = -HUGE_VAL, fbig = 0.0;
        for (i = 0; i < c->data.n; i++) {
            zmin = fmin(zmin, c->data.depth[i]);
            zmax = fmax(zmax, c->data.depth[i]);
            fbig = fmax(fbig, fabs(c->data.force[i]));
        }
        if (!(zmax > zmin) || !(fbig > 0))
            return lf_fail(err, LF_EDATA, "curve %zu (%s): depth or force does not vary",
                           j + 1, c->data.name ? c->data.name : "");
        c->L = zmax - zmin;
        c->Fs = fbig;
        c->eps = 1e-3 * c->L / (double) (c->data.n - 1);
        c->sigma = fit_noise_sigma(c->data.force, c->data.n, f->work);
    }
    return LF_OK;
}

lf_fit *
lf_fit_alloc(const lf_fit_settings *settings, size_t ncurves,
             const lf_fit_curve *curves, lf_error *err)
{
    lf_fit *f;
    gsl_multifit_nlinear_parameters par = gsl_multifit_nlinear_default_parameters();
    size_t j, nm = sizeof methods / sizeof methods[0], im;

    if (settings->model == NULL || settings->method == NULL) {
        lf_fail(err, LF_EINVAL, "fit settings need a model and a method");
        return NULL;
    }
    for (im = 0; im < nm; im++)
        if (strcmp(methods[im].name, settings->method) == 0)
            break;
    if (im == nm) {
        lf_fail(err, LF_EINVAL, "unknown method '%s' (lm, lmaccel, dogleg, ddogleg, subspace2D)",
                settings->method);
        return NULL;
    }
    if (settings->jacobian > LF_JAC_CENTRAL || settings->max_iter == 0
        || !(settings->rcond > 0 && settings->rcond < 1)
        || !(settings->max_b_over_a > 0)) {
        lf_fail(err, LF_EINVAL, "fit settings out of range (jacobian, max_iter, rcond, max_b_over_a)");
        return NULL;
    }
    if (ncurves == 0) {
        lf_fail(err, LF_EDATA, "no curves to fit");
        return NULL;
    }
    for (j = 0; j < ncurves; j++)
        if (check_curve(&curves[j], j, err) != LF_OK)
            return NULL;
    f = calloc(1, sizeof *f);
    if (f == NULL)
        goto nomem;
    f->set = *settings;
    f->trs = *methods[im].trs;
    f->ncurves = ncurves;
    f->c = calloc(ncurves, sizeof *f->c);
    if (f->c == NULL)
        goto nomem;
    for (j = 0; j < ncurves; j++) {
        f->c[j].data = curves[j];
        f->c[j].model = lf_model_alloc(settings->model, &curves[j].probe, err);
        if (f->c[j].model == NULL) {
            lf_fit_free(f);
            return NULL;
        }
    }
    if (fit_problem_setup(f, err) != LF_OK) {
        lf_fit_free(f);
        return NULL;
    }
    f->nsub_max = NSUB_MAX;
    f->x0_internal = calloc(f->np, sizeof *f->x0_internal);
    f->xcache = calloc(f->np, sizeof *f->xcache);
    f->ev = calloc(f->ndata, sizeof *f->ev);
    f->delta = calloc(f->ndata, sizeof *f->delta);
    f->work = calloc(f->ndata > 2 * NSUB_MAX ? f->ndata : 2 * NSUB_MAX, sizeof *f->work);
    f->sub = calloc(3 * NSUB_MAX + GUESS_NODES, sizeof *f->sub);
    if (!f->x0_internal || !f->xcache || !f->ev || !f->delta || !f->work || !f->sub)
        goto nomem;
    par.trs = f->trs;
    par.scale = gsl_multifit_nlinear_scale_more;
    par.solver = gsl_multifit_nlinear_solver_qr;
    par.fdtype = settings->jacobian == LF_JAC_CENTRAL ? GSL_MULTIFIT_NLINEAR_CTRDIFF
                                                      : GSL_MULTIFIT_NLINEAR_FWDIFF;
    f->gsl = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &par, f->nres, f->np);
    if (f->gsl == NULL)
        goto nomem;
    f->fdf.f = fit_residuals;
    f->fdf.df = settings->jacobian == LF_JAC_ANALYTIC ? fit_jacobian : NULL;
    f->fdf.fvv = NULL;
    f->fdf.n = f->nres;
    f->fdf.p = f->np;
    f->fdf.params = f;
    if (curve_scales(f, err) != LF_OK) {
        lf_fit_free(f);
        return NULL;
    }
    return f;
nomem:
    lf_fit_free(f);
    lf_fail(err, LF_ENOMEM, "out of memory allocating a fit");
    return NULL;
}

void
lf_fit_free(lf_fit *f)
{
    size_t j;

    if (f == NULL)
        return;
    if (f->c != NULL)
        for (j = 0; j < f->ncurves; j++)
            lf_model_free(f->c[j].model);
    free(f->c);
    free(f->x0_internal);
    free(f->xcache);
    free(f->ev);
    free(f->delta);
    free(f->work);
    free(f->sub);
    if (f->gsl != NULL)
        gsl_multifit_nlinear_free(f->gsl);
    free(f);
}

/* Why GSL stopped, in words; sets *converged. */
static void
stop_reason(int status, int info, size_t maxiter, char *buf, size_t n,
            int *converged)
{
    *converged = 0;
    if (status == GSL_SUCCESS) {
        *converged = 1;
        snprintf(buf, n, "converged (%s)", info == 1 ? "small step" : "small gradient");
    } else if (status == GSL_EMAXITER) {
        snprintf(buf, n, "not converged: %zu iterations reached", maxiter);
    } else if (status == GSL_ENOPROG) {
        snprintf(buf, n, "not converged: no further progress possible");
    } else {
        snprintf(buf, n, "not converged: %s", gsl_strerror(status));
    }
}

/* GSL gives up (ENOPROG) when no step lowers the cost any more; at an exact
 * zero-residual solution this is success.  Accept it when the scaled
 * gradient is at rounding level. */
static int
at_minimum(lf_fit *f)
{
    gsl_vector *r = gsl_multifit_nlinear_residual(f->gsl);
    gsl_matrix *J = gsl_multifit_nlinear_jac(f->gsl);
    size_t i, k;
    double rn = gsl_blas_dnrm2(r);

    for (k = 0; k < f->np; k++) {
        double g = 0.0, cn = 0.0;
        for (i = 0; i < f->nres; i++) {
            double jik = gsl_matrix_get(J, i, k);
            g += jik * gsl_vector_get(r, i);
            cn += jik * jik;
        }
        if (fabs(g) > 1e-8 * sqrt(cn) * rn + 1e-300)
            return 0;
    }
    return 1;
}

int
lf_fit_run(lf_fit *f, lf_fit_result *res, lf_error *err)
{
    gsl_vector *x = NULL;
    int status, info = 0, converged;
    char why[160];
    size_t i;

    memset(res, 0, sizeof *res);
    f->xcache_ok = 0;
    status = fit_guess(f, err);
    if (status != LF_OK)
        return status;
    x = gsl_vector_alloc(f->np);
    if (x == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory");
    gsl_vector_set_all(x, 1.0);
    f->fdf.nevalf = f->fdf.nevaldf = 0;
    status = gsl_multifit_nlinear_init(x, &f->fdf, f->gsl);
    if (status != GSL_SUCCESS) {
        gsl_vector_free(x);
        return lf_fail(err, LF_ENUMERIC, "the model cannot be evaluated at the initial guess (%s)",
                       gsl_strerror(status));
    }
    status = gsl_multifit_nlinear_driver(f->set.max_iter, f->set.xtol, f->set.gtol,
                                         f->set.ftol, NULL, NULL, &info, f->gsl);
    stop_reason(status, info, f->set.max_iter, why, sizeof why, &converged);
    if (status == GSL_ENOPROG && at_minimum(f)) {
        converged = 1;
        snprintf(why, sizeof why, "converged (no further decrease at a stationary point)");
    }
    for (i = 0; i < f->np; i++)
        gsl_vector_set(x, i, gsl_vector_get(gsl_multifit_nlinear_position(f->gsl), i));
    res->iterations = gsl_multifit_nlinear_niter(f->gsl);
    res->evaluations = f->fdf.nevalf + f->fdf.nevaldf;
    status = fit_assess(f, x->data, res, err);
    gsl_vector_free(x);
    if (status != LF_OK) {
        lf_fit_result_free(res);
        return status;
    }
    res->converged = converged;
    snprintf(res->stop_reason, sizeof res->stop_reason, "%s", why);
    res->method = f->set.method;
    res->model = f->set.model->name;
    if (!converged) {
        lf_warn(&res->warnings, "the fit did not converge (%s): the numbers below are where it stopped", why);
        return LF_ENOCONV;
    }
    return LF_OK;
}

int
lf_fit_driver(const lf_fit_settings *settings, size_t ncurves,
              const lf_fit_curve *curves, lf_fit_result *res, lf_error *err)
{
    lf_fit *f = lf_fit_alloc(settings, ncurves, curves, err);
    int status;

    memset(res, 0, sizeof *res);
    if (f == NULL)
        return err ? err->status : LF_EINVAL;
    status = lf_fit_run(f, res, err);
    lf_fit_free(f);
    return status;
}

int
lf_fit_check_jacobian(lf_fit *f, const lf_material *mat, double *max_rel_err,
                      lf_error *err)
{
    gsl_vector *x = gsl_vector_alloc(f->np), *r1 = gsl_vector_alloc(f->nres);
    gsl_vector *r2 = gsl_vector_alloc(f->nres);
    gsl_matrix *J = gsl_matrix_alloc(f->nres, f->np);
    size_t i, k;
    int status = LF_OK;

    *max_rel_err = 0.0;
    if (!x || !r1 || !r2 || !J) {
        status = lf_fail(err, LF_ENOMEM, "out of memory");
        goto done;
    }
    f->mat = *mat;
    for (i = 0; i < f->ncurves; i++)
        f->c[i].slope = 0.0;
    fit_set_origin(f);
    gsl_vector_set_all(x, 1.0);
    if (fit_jacobian(x, f, J) != GSL_SUCCESS) {
        status = lf_fail(err, LF_ENUMERIC, "the model cannot be evaluated");
        goto done;
    }
    for (k = 0; k < f->np; k++) {
        const double h = 1e-6;
        double colmax = 0.0, worst = 0.0;
        gsl_vector_set(x, k, 1.0 + h);
        status = fit_residuals(x, f, r1);
        gsl_vector_set(x, k, 1.0 - h);
        status |= fit_residuals(x, f, r2);
        gsl_vector_set(x, k, 1.0);
        if (status != GSL_SUCCESS) {
            status = lf_fail(err, LF_ENUMERIC, "the model cannot be evaluated");
            goto done;
        }
        for (i = 0; i < f->nres; i++) {
            double fd = (gsl_vector_get(r1, i) - gsl_vector_get(r2, i)) / (2 * h);
            colmax = fmax(colmax, fabs(gsl_matrix_get(J, i, k)));
            worst = fmax(worst, fabs(fd - gsl_matrix_get(J, i, k)));
        }
        if (colmax > 0)
            *max_rel_err = fmax(*max_rel_err, worst / colmax);
    }
done:
    gsl_vector_free(x);
    gsl_vector_free(r1);
    gsl_vector_free(r2);
    gsl_matrix_free(J);
    return status;
}
