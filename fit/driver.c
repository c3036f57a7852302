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
    s.w.guess = s.Estar.guess = s.nu.guess = NAN;
    s.fit_slope = 0;
    s.max_iter = 200;
    s.xtol = 1e-11;
    s.gtol = 1e-12;
    s.ftol = 0.0;
    s.rcond = 1e-7;
    s.max_b_over_a = 0.1;
    s.loss = LF_LOSS_LINEAR;
    s.loss_scale = NAN;
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

typedef struct {
    double z;
    size_t i;
} depth_index;

static int
cmp_depth_index(const void *a, const void *b)
{
    const depth_index *x = a, *y = b;
    if (x->z != y->z)
        return (x->z > y->z) - (x->z < y->z);
    return (x->i > y->i) - (x->i < y->i);
}

/* f->order: each curve's points sorted by depth, ties in file order, so
 * that nothing the fit computes depends on the order of the rows. */
static int
depth_order(lf_fit *f)
{
    size_t j, i, nmax = 0;
    depth_index *di;

    for (j = 0; j < f->ncurves; j++)
        nmax = f->c[j].data.n > nmax ? f->c[j].data.n : nmax;
    di = malloc(nmax * sizeof *di);
    if (di == NULL)
        return LF_ENOMEM;
    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        for (i = 0; i < c->data.n; i++) {
            di[i].z = c->data.depth[i];
            di[i].i = i;
        }
        qsort(di, c->data.n, sizeof *di, cmp_depth_index);
        for (i = 0; i < c->data.n; i++)
            f->order[c->row + i] = di[i].i;
    }
    free(di);
    return LF_OK;
}

const char *
lf_loss_name(lf_loss loss)
{
    switch (loss) {
    case LF_LOSS_HUBER:  return "huber";
    case LF_LOSS_CAUCHY: return "cauchy";
    default:             return "linear";
    }
}

int
lf_loss_find(const char *name)
{
    int l;
    for (l = LF_LOSS_LINEAR; l <= LF_LOSS_CAUCHY; l++)
        if (strcmp(name, lf_loss_name((lf_loss) l)) == 0)
            return l;
    return -1;
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
        c->sigma = fit_noise_sigma(c->data.depth, c->data.force, f->order + c->row, c->data.n,
                                   f->work);
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
    if (settings->loss > LF_LOSS_CAUCHY
        || !(isnan(settings->loss_scale) || (settings->loss_scale > 0 && isfinite(settings->loss_scale)))) {
        lf_fail(err, LF_EINVAL, "fit settings out of range (loss, loss_scale > 0)");
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
    f->alt_w = NAN;
    f->trs = *methods[im].trs;
    f->ncurves = ncurves;
    f->c = calloc(ncurves, sizeof *f->c);
    if (f->c == NULL)
        goto nomem;
    for (j = 0; j < ncurves; j++) {
        f->c[j].data = curves[j];
        f->c[j].model = lf_model_alloc(curves[j].model ? curves[j].model : settings->model,
                                       &curves[j].probe, err);
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
    f->scan_ev = calloc(f->ndata, sizeof *f->scan_ev);
    f->sqrtw = malloc(f->ndata * sizeof *f->sqrtw);
    f->delta = calloc(f->ndata, sizeof *f->delta);
    f->work = calloc(f->ndata > 2 * NSUB_MAX ? f->ndata : 2 * NSUB_MAX, sizeof *f->work);
    f->sub = calloc(3 * NSUB_MAX + GUESS_NODES, sizeof *f->sub);
    f->order = malloc(f->ndata * sizeof *f->order);
    if (!f->x0_internal || !f->xcache || !f->ev || !f->scan_ev || !f->sqrtw || !f->delta
        || !f->work || !f->sub
        || !f->order || depth_order(f) != LF_OK)
        goto nomem;
    par.trs = f->trs;
    par.scale = gsl_multifit_nlinear_scale_more;
    par.solver = gsl_multifit_nlinear_solver_cholesky;
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
    free(f->order);
    free(f->scan_ev);
    free(f->sqrtw);
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

/* No coordinate step of +-h (internal units: relative for w and E*,
 * fractions of the depth span and force scale for the offsets) lowers the
 * cost at x: a minimum, smooth or at a kink of the model, where GSL's
 * gradient test need not pass. */
static int
no_descent(lf_fit *f, gsl_vector *x)
{
    const double h[3] = { 1e-4, 1e-6, 1e-8 };
    gsl_vector *r = gsl_vector_alloc(f->nres);
    double c0, rn;
    size_t k, q;
    int sign, ok = 1;

    if (r == NULL || fit_residuals(x, f, r) != GSL_SUCCESS) {
        gsl_vector_free(r);
        return 0;
    }
    rn = gsl_blas_dnrm2(r);
    c0 = rn * rn;
    for (k = 0; k < f->np && ok; k++) {
        double xk = gsl_vector_get(x, k);
        for (q = 0; q < 3 && ok; q++)
            for (sign = -1; sign <= 1 && ok; sign += 2) {
                gsl_vector_set(x, k, xk + sign * h[q]);
                if (fit_residuals(x, f, r) == GSL_SUCCESS) {
                    rn = gsl_blas_dnrm2(r);
                    ok = !(rn * rn < c0 * (1.0 - 1e-12));
                }
            }
        gsl_vector_set(x, k, xk);
    }
    f->xcache_ok = 0;
    gsl_vector_free(r);
    return ok;
}

/* After each iteration: remember the cost. */
static void
track_cost(const size_t iter, void *params, const gsl_multifit_nlinear_workspace *w)
{
    lf_fit *f = params;
    double r = gsl_blas_dnrm2(gsl_multifit_nlinear_residual(w));
    f->cost_hist[iter % (FIT_FLAT_ITERS + 1)] = 0.5 * r * r;
}

/* 1 when every column of the solver's Jacobian is finite and not
 * negligible.  A parameter that stops mattering (w driven towards zero
 * leaves its column near zero) sends GSL's subspace2D method into an
 * endless loop solving a quartic of NaNs; the other methods stall. */
static int
jacobian_usable(lf_fit *f, size_t *which)
{
    const gsl_matrix *J = gsl_multifit_nlinear_jac(f->gsl);
    size_t i, k;
    double top = 0.0, low = HUGE_VAL;

    for (k = 0; k < J->size2; k++) {
        double big = 0.0;
        for (i = 0; i < J->size1; i++) {
            double v = fabs(gsl_matrix_get(J, i, k));
            if (!isfinite(v))
                return 0;
            big = fmax(big, v);
        }
        top = fmax(top, big);
        if (big < low) {
            low = big;
            *which = k;
        }
    }
    /* the internal coordinates are all of order one, so a column 1e-12 of
     * the largest belongs to a parameter that no longer matters */
    return low > 1e-12 * top;
}

/* gsl_multifit_nlinear_driver with the Jacobian checked before each
 * iteration and the cost recorded after it.  An unusable Jacobian ends the
 * run with GSL_EBADFUNC and the negligible column in *dead. */
static int
drive(lf_fit *f, int *info, size_t *dead)
{
    size_t iter = 0;
    int status;

    *info = 0;
    do {
        if (!jacobian_usable(f, dead))
            return GSL_EBADFUNC;
        status = gsl_multifit_nlinear_iterate(f->gsl);
        if (status == GSL_ENOPROG && iter == 0) {
            *info = status;
            return GSL_EMAXITER;
        }
        track_cost(iter, f, f->gsl);
        status = gsl_multifit_nlinear_test(f->set.xtol, f->set.gtol, f->set.ftol, info, f->gsl);
    } while (status == GSL_CONTINUE && ++iter < f->set.max_iter);
    if (iter >= f->set.max_iter && status != GSL_SUCCESS)
        status = GSL_EMAXITER;
    return status;
}

/* Run the trust-region iteration from x (overwritten with where it
 * stopped); *iters counts its iterations.  after_scan: x comes from
 * edge_scan. */
static int
solve(lf_fit *f, gsl_vector *x, int after_scan, size_t *iters, char *why, size_t nwhy,
      int *converged, lf_error *err)
{
    int status, info = 0;
    size_t i, dead = 0;

    *converged = 0;
    status = gsl_multifit_nlinear_init(x, &f->fdf, f->gsl);
    if (status != GSL_SUCCESS)
        return lf_fail(err, LF_ENUMERIC, "the model cannot be evaluated at the starting point (%s)",
                       gsl_strerror(status));
    status = drive(f, &info, &dead);
    *iters = gsl_multifit_nlinear_niter(f->gsl);
    if (status == GSL_EBADFUNC) {
        for (i = 0; i < f->np; i++)
            gsl_vector_set(x, i, gsl_vector_get(gsl_multifit_nlinear_position(f->gsl), i));
        if ((int) dead == f->imat[FIT_W]) {
            /* the assessment reports w as bounded or undetermined */
            *converged = 1;
            snprintf(why, nwhy, "converged (w driven towards zero, where it no longer "
                     "changes the fit)");
        } else {
            snprintf(why, nwhy, "not converged: parameter %zu no longer changes the fit", dead + 1);
        }
        return LF_OK;
    }
    if (status == GSL_EMAXITER && *iters > FIT_FLAT_ITERS) {
        /* GSL numbers the iteration that just ended iters - 1 */
        double now = f->cost_hist[(*iters - 1) % (FIT_FLAT_ITERS + 1)];
        double then = f->cost_hist[*iters % (FIT_FLAT_ITERS + 1)];
        if (then - now <= fmax(FIT_FLAT_REL * now, FIT_FLAT_ABS)) {
            for (i = 0; i < f->np; i++)
                gsl_vector_set(x, i, gsl_vector_get(gsl_multifit_nlinear_position(f->gsl), i));
            *converged = 1;
            snprintf(why, nwhy, "converged (chi2 fell by %.2g over the last %d iterations)",
                     2.0 * (then - now), FIT_FLAT_ITERS);
            return LF_OK;
        }
    }
    /* GSL reports "no step lowers the cost from the start" as EMAXITER
     * with info ENOPROG.  after_scan: x is a converged solution moved by
     * the contact-point scan or a reweighting */
    if (status == GSL_EMAXITER && info == GSL_ENOPROG && *iters < f->set.max_iter)
        status = GSL_ENOPROG;
    stop_reason(status, info, f->set.max_iter, why, nwhy, converged);
    for (i = 0; i < f->np; i++)
        gsl_vector_set(x, i, gsl_vector_get(gsl_multifit_nlinear_position(f->gsl), i));
    if (status == GSL_ENOPROG && !at_minimum(f) && f->fdf.df != NULL && !no_descent(f, x)) {
        /* the analytic derivatives, guarded at the contact edge, can point
         * nowhere useful there: go on with finite differences, which see the
         * residuals as they are */
        size_t more;
        f->fdf.df = NULL;
        status = gsl_multifit_nlinear_init(x, &f->fdf, f->gsl);
        if (status == GSL_SUCCESS)
            status = drive(f, &info, &dead);
        f->fdf.df = fit_jacobian;
        more = gsl_multifit_nlinear_niter(f->gsl);
        *iters += more;
        if (status == GSL_EMAXITER && info == GSL_ENOPROG && more < f->set.max_iter)
            status = GSL_ENOPROG;
        stop_reason(status, info, f->set.max_iter, why, nwhy, converged);
        for (i = 0; i < f->np; i++)
            gsl_vector_set(x, i, gsl_vector_get(gsl_multifit_nlinear_position(f->gsl), i));
    }
    if (status == GSL_ENOPROG && !at_minimum(f) && !after_scan && no_descent(f, x)) {
        *converged = 1;
        snprintf(why, nwhy, "converged (no step lowers the cost: a kink where a point meets "
                 "the contact edge)");
        return LF_OK;
    }
    if (status == GSL_ENOPROG && (at_minimum(f) || after_scan)) {
        /* after the contact-point scan the cost sits at a kink of the
         * model, where the gradient need not vanish */
        *converged = 1;
        snprintf(why, nwhy, after_scan ? "converged (no step lowers the cost from the previous "
                 "solution)" : "converged (no further decrease at a stationary point)");
    }
    for (i = 0; i < f->np; i++)
        gsl_vector_set(x, i, gsl_vector_get(gsl_multifit_nlinear_position(f->gsl), i));
    return LF_OK;
}

/* Curve j's weighted sum of squares (robust weights included) at material
 * mat and contact point z0, with its force offset (when free) at its best
 * value for them, returned in *F0; slope as given.  HUGE_VAL when the model cannot be evaluated. */
static double
curve_cost(lf_fit *f, size_t j, const lf_material *mat, double z0, double *F0,
           double slope)
{
    const fit_curve *c = &f->c[j];
    double *delta = f->work, sum = 0.0, ss = 0.0;
    const double *sw = f->sqrtw + c->row;
    lf_eval *e = f->scan_ev;
    size_t i, n = c->data.n;

    for (i = 0; i < n; i++)
        delta[i] = c->data.depth[i] - z0;
    if (lf_model_eval(c->model, mat, c->data.branch, n, delta, e, NULL) != LF_OK)
        return HUGE_VAL;
    if (c->iF0 >= 0) {
        double wsum = 0.0;
        for (i = 0; i < n; i++) {
            double wt = sw[i] * sw[i];
            sum += wt * (c->data.force[i] - e[i].P - slope * delta[i]);
            wsum += wt;
        }
        *F0 = sum / wsum;
    }
    for (i = 0; i < n; i++) {
        double r = (e[i].P + *F0 + slope * delta[i] - c->data.force[i]) / c->sigma * sw[i];
        ss += r * r;
    }
    return isfinite(ss) ? ss : HUGE_VAL;
}

#define SCAN_HALF 8

/* The model has a kink where contact ends (a vertical tangent for k > 2),
 * and the cost a kink at every data point that crosses it: a gradient
 * method stops at the nearest one.  For each free contact point, try
 * placing the edge between each pair of neighbouring points within
 * SCAN_HALF of where it is, the force offset re-solved, the rest held;
 * move x to the best when it lowers the cost.  Returns 1 if it moved. */
static int
edge_scan(lf_fit *f, gsl_vector *x)
{
    size_t j;
    int moved = 0;

    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        const size_t *ord = f->order + c->row;
        lf_material mat;
        lf_pulloff po;
        double z0, F0, slope, edge, best, bestz0, bestF0, F0c;
        size_t lo, hi, q, n = c->data.n, pos;

        if (c->iz0 < 0 || n < 3)
            continue;
        fit_unpack(f, x->data, &mat, &z0, &F0, &slope, j);
        if (lf_model_pulloff(c->model, &mat, &po, NULL) != LF_OK)
            continue;
        /* the edge in depth: detachment on unloading, z0 on loading */
        edge = c->data.branch == LF_BRANCH_UNLOAD ? z0 + po.delta_detach : z0;
        for (pos = 0; pos < n && c->data.depth[ord[pos]] < edge; pos++)
            ;
        F0c = F0;
        best = curve_cost(f, j, &mat, z0, &F0c, slope);
        bestz0 = z0;
        bestF0 = F0c;
        lo = pos > SCAN_HALF ? pos - SCAN_HALF : 1;
        hi = pos + SCAN_HALF < n ? pos + SCAN_HALF : n - 1;
        for (q = lo; q <= hi; q++) {
            double zq = 0.5 * (c->data.depth[ord[q - 1]] + c->data.depth[ord[q]]);
            double z0q = c->data.branch == LF_BRANCH_UNLOAD ? zq - po.delta_detach : zq;
            double F0q = F0, v;
            if (!(c->data.depth[ord[q]] > c->data.depth[ord[q - 1]]))
                continue;
            v = curve_cost(f, j, &mat, z0q, &F0q, slope);
            if (v < best * (1.0 - 1e-12)) {
                best = v;
                bestz0 = z0q;
                bestF0 = F0q;
            }
        }
        if (bestz0 != z0) {
            /* back to x: internal = x0 + x - 1, z0 = L internal, F0 = Fs internal */
            gsl_vector_set(x, (size_t) c->iz0, bestz0 / c->L - f->x0_internal[c->iz0] + 1.0);
            if (c->iF0 >= 0)
                gsl_vector_set(x, (size_t) c->iF0, bestF0 / c->Fs - f->x0_internal[c->iF0] + 1.0);
            moved = 1;
        }
    }
    f->xcache_ok = 0;
    return moved;
}

#define MAX_SCANS 4

/* Iterate from the origin (x = 1), then scan the contact points and
 * iterate again while the scan finds a lower cost.  Adds to *iters and
 * *evals. */
static int
run_from_origin(lf_fit *f, gsl_vector *x, size_t *iters, size_t *evals, char *why,
                size_t nwhy, int *converged, lf_error *err)
{
    size_t it;
    int scan, status;

    gsl_vector_set_all(x, 1.0);
    f->xcache_ok = 0;
    status = solve(f, x, 0, &it, why, nwhy, converged, err);
    *iters += it;
    *evals += f->fdf.nevalf + f->fdf.nevaldf;
    for (scan = 0; status == LF_OK && scan < MAX_SCANS && edge_scan(f, x); scan++) {
        status = solve(f, x, 1, &it, why, nwhy, converged, err);
        *iters += it;
        *evals += f->fdf.nevalf + f->fdf.nevaldf;
    }
    return status;
}

/* Half the sum of squared residuals at x; HUGE_VAL if not computable. */
static double
cost_at(lf_fit *f, const gsl_vector *x, gsl_vector *r)
{
    double n;
    if (fit_residuals(x, f, r) != GSL_SUCCESS)
        return HUGE_VAL;
    n = gsl_blas_dnrm2(r);
    return 0.5 * n * n;
}

/* Make the point x the origin: material and offsets into f, x = 1. */
static void
rebase(lf_fit *f, gsl_vector *x)
{
    lf_material mat;
    double z0, F0, slope;
    size_t j;

    for (j = 0; j < f->ncurves; j++) {
        fit_unpack(f, x->data, &mat, &z0, &F0, &slope, j);
        f->c[j].z0 = z0;
        f->c[j].F0 = F0;
        f->c[j].slope = slope;
    }
    fit_unpack(f, x->data, &mat, &z0, &F0, &slope, f->ncurves);
    f->mat = mat;
    fit_set_origin(f);
    gsl_vector_set_all(x, 1.0);
}

/* Fit again from the material start (offsets profiled there) and keep
 * whichever of that and the solution at x has the lower cost; *won = 1
 * when the new start did, *ratio = the other's cost over the winner's. */
static int
second_start(lf_fit *f, gsl_vector *x, gsl_vector *r, const lf_material *start,
             size_t *iters, size_t *evals, char *why, size_t nwhy, int *converged, int *won,
             double *ratio, lf_error *err)
{
    double cost_first = cost_at(f, x, r), cost_second;
    double *keep = malloc((3 * f->ncurves + 1) * sizeof *keep);
    lf_material mat_first;
    char why2[160];
    int conv2, status;
    size_t j;

    *won = 0;
    *ratio = 1.0;
    if (keep == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory");
    rebase(f, x);
    mat_first = f->mat;
    for (j = 0; j < f->ncurves; j++) {
        keep[3 * j] = f->c[j].z0;
        keep[3 * j + 1] = f->c[j].F0;
        keep[3 * j + 2] = f->c[j].slope;
    }
    f->mat = *start;
    fit_guess_offsets(f);
    status = run_from_origin(f, x, iters, evals, why2, sizeof why2, &conv2, err);
    cost_second = cost_at(f, x, r);
    /* a converged run beats an unconverged one at about the same cost; else
     * the lower cost wins, an unconverged run only by a clear margin */
    if (status == LF_OK
        && ((conv2 && !*converged && cost_second <= cost_first * (1.0 + 1e-6))
            || (conv2 == *converged && cost_second < cost_first * (1.0 - 1e-9))
            || (!conv2 && *converged && cost_second < cost_first * (1.0 - 1e-4)))) {
        *won = 1;
        *ratio = cost_first / cost_second;
        *converged = conv2;
        snprintf(why, nwhy, "%s", why2);
    } else if (status == LF_OK) {
        f->mat = mat_first;
        for (j = 0; j < f->ncurves; j++) {
            f->c[j].z0 = keep[3 * j];
            f->c[j].F0 = keep[3 * j + 1];
            f->c[j].slope = keep[3 * j + 2];
        }
        fit_set_origin(f);
        gsl_vector_set_all(x, 1.0);
        f->xcache_ok = 0;
    }
    free(keep);
    return status;
}

#define MAX_REWEIGHT 50

/* Robust loss by iteratively reweighted least squares: with u the residual
 * in units of loss_scale noise sd, the weights are min(1, 1/|u|) (Huber)
 * or 1/(1 + u^2) (Cauchy); refit from where the last fit ended until no
 * weight's square root moves by more than 1e-4. */
static int
reweight(lf_fit *f, gsl_vector *x, gsl_vector *r, size_t *iters, size_t *evals, char *why,
         size_t nwhy, int *converged, size_t *rounds, lf_error *err)
{
    const double scale = !isnan(f->set.loss_scale) ? f->set.loss_scale
                         : f->set.loss == LF_LOSS_HUBER ? 1.345 : 2.385;
    size_t round, k;
    int status = LF_OK, scan;

    for (round = 0; round < MAX_REWEIGHT; round++) {
        double moved = 0.0;
        size_t it;
        if (fit_residuals(x, f, r) != GSL_SUCCESS)
            return lf_fail(err, LF_ENUMERIC, "the model cannot be evaluated while reweighting");
        for (k = 0; k < f->ndata; k++) {
            double u = fabs(gsl_vector_get(r, k) / f->sqrtw[k]) / scale, wt, s;
            wt = f->set.loss == LF_LOSS_HUBER ? (u <= 1.0 ? 1.0 : 1.0 / u) : 1.0 / (1.0 + u * u);
            s = sqrt(wt);
            moved = fmax(moved, fabs(s - f->sqrtw[k]));
            f->sqrtw[k] = s;
        }
        f->xcache_ok = 0;
        *rounds = round + 1;
        if (moved < 1e-4)
            break;
        status = solve(f, x, 1, &it, why, nwhy, converged, err);
        *iters += it;
        *evals += f->fdf.nevalf + f->fdf.nevaldf;
        for (scan = 0; status == LF_OK && scan < MAX_SCANS && edge_scan(f, x); scan++) {
            status = solve(f, x, 1, &it, why, nwhy, converged, err);
            *iters += it;
            *evals += f->fdf.nevalf + f->fdf.nevaldf;
        }
        if (status != LF_OK)
            return status;
    }
    if (round == MAX_REWEIGHT) {
        *converged = 0;
        snprintf(why, nwhy, "not converged: the robust weights still move after %d rounds",
                 MAX_REWEIGHT);
    }
    return status;
}

/* Every curve of three or more disagrees with the joint fit: refit
 * without each in turn.  When exactly one curve's absence lets all the
 * others agree, that curve is named; when none or several do, the
 * disagreement is reported as general. */
static void
leave_one_out(lf_fit *f, lf_fit_result *res)
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
        int ok = 1, st;
        for (i = 0, m = 0; i < n; i++)
            if (i != j)
                sub[m++] = f->c[i].data;
        worst[j] = HUGE_VAL;
        g = lf_fit_alloc(&f->set, m, sub, NULL);
        if (g == NULL)
            continue;
        g->no_loo = 1;
        st = lf_fit_run(g, &r, NULL);
        if (st == LF_ENOCONV)
            lf_fit_result_free(&r);
        if (st == LF_OK) {
            worst[j] = 0.0;
            for (i = 0; i < m; i++) {
                ok &= r.curves[i].consistent;
                worst[j] = fmax(worst[j], r.curves[i].chi2_per_point);
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

/* The name of the curves' model, or "mixed". */
static const char *
model_name(const lf_fit *f)
{
    const lf_model_type *t = lf_model_get_type(f->c[0].model);
    size_t j;

    for (j = 1; j < f->ncurves; j++)
        if (lf_model_get_type(f->c[j].model) != t)
            return "mixed";
    return t->name;
}

int
fit_solve(lf_fit *f, lf_fit_result *res, lf_error *err)
{
    gsl_vector *x = NULL, *r = NULL;
    int status, converged;
    char why[160];
    size_t iters = 0, evals = 0, i;
    lf_material user;

    memset(res, 0, sizeof *res);
    f->xcache_ok = 0;
    for (iters = 0; iters < f->ndata; iters++)
        f->sqrtw[iters] = 1.0;
    iters = 0;
    x = gsl_vector_alloc(f->np);
    r = gsl_vector_alloc(f->nres);
    if (x == NULL || r == NULL) {
        gsl_vector_free(x);
        gsl_vector_free(r);
        return lf_fail(err, LF_ENOMEM, "out of memory");
    }
    user = f->mat;
    status = run_from_origin(f, x, &iters, &evals, why, sizeof why, &converged, err);
    if (status == LF_OK && f->user_start) {
        /* A user's starting point is a second start, not a replacement:
         * the cost has kinks wherever a point crosses the contact edge, and
         * a start a factor of 3 off can end in a minimum whose misfit,
         * local to the edge, neither chi2 (the noise is only estimated)
         * nor the runs test reliably shows.  So the fit is repeated from
         * the automatic guess and the lower cost wins. */
        double ratio;
        int won;
        status = second_start(f, x, r, &f->auto_mat, &iters, &evals, why, sizeof why,
                              &converged, &won, &ratio, err);
        if (status == LF_OK && won)
            lf_warn(&res->warnings, "the fit from the given starting point (w = %.4g J/m^2, "
                    "E* = %.4g Pa) ended at a cost %.4g times higher than from the automatic "
                    "guess; the result below starts from the automatic guess",
                    user.w, user.Estar, ratio);
    }
    if (status == LF_OK && isfinite(f->alt_w)) {
        /* the automatic guess's runner-up, when close: another basin */
        lf_material alt = f->auto_mat;
        double ratio;
        int won;
        alt.w = f->alt_w;
        status = second_start(f, x, r, &alt, &iters, &evals, why, sizeof why, &converged,
                              &won, &ratio, err);
    }
    f->user_start = 0;          /* warm starts after this one are the caller's */
    f->alt_w = NAN;
    if (status == LF_OK && f->set.loss != LF_LOSS_LINEAR)
        status = reweight(f, x, r, &iters, &evals, why, sizeof why, &converged, &res->reweightings,
                          err);
    res->iterations = iters;
    gsl_vector_free(r);
    if (status != LF_OK) {
        gsl_vector_free(x);
        lf_warnings_free(&res->warnings);
        return status;
    }
    res->evaluations = evals;
    status = fit_assess(f, x->data, res, err);
    gsl_vector_free(x);
    if (status != LF_OK) {
        lf_fit_result_free(res);
        return status;
    }
    res->converged = converged;
    snprintf(res->stop_reason, sizeof res->stop_reason, "%s", why);
    if (!f->no_loo && f->ncurves >= 3) {
        size_t j, bad = 0;
        for (j = 0; j < f->ncurves; j++)
            bad += !res->curves[j].consistent;
        if (bad == f->ncurves)
            leave_one_out(f, res);
    }
    res->method = f->set.method;
    res->loss = lf_loss_name(f->set.loss);
    res->model = model_name(f);
    res->model_rounds = 1;
    for (i = 0; i < f->ncurves; i++) {
        res->curves[i].model = lf_model_get_type(f->c[i].model)->name;
        snprintf(res->curves[i].model_reason, sizeof res->curves[i].model_reason,
                 "as requested");
        res->curves[i].thin_bias = NAN;
        res->curves[i].thin_bias_se[0] = res->curves[i].thin_bias_se[1] = NAN;
        res->curves[i].thin_bias_se[2] = NAN;
    }
    if (!converged) {
        lf_warn(&res->warnings, "the fit did not converge (%s): the numbers below are where it stopped", why);
        return LF_ENOCONV;
    }
    return LF_OK;
}

int
lf_fit_run(lf_fit *f, lf_fit_result *res, lf_error *err)
{
    int status;

    memset(res, 0, sizeof *res);
    f->xcache_ok = 0;
    status = fit_guess(f, err);
    if (status != LF_OK)
        return status;
    return fit_solve(f, res, err);
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
