/* layout.c: a fit's settings defaults, the problem's layout (which rows
 * and parameters belong to which curve, each curve's scales, noise and
 * depth order) and the workspace, all sized once from the curves in
 * lf_fit_alloc; runs reuse them and allocate nothing.
 *
 * GSL's error handler must be off in the calling program (the layerfit
 * command and the tests turn it off); every GSL status is checked. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "fit.h"

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
    s.nu.value = NAN;           /* no assumed nu: bonded curves that need
                                   one and cannot determine it are refused */
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

/* order[0..n-1]: the points of z by depth, ties in file order.  Curves
 * recorded in order of depth (either way) need no sort; di is scratch for
 * the others. */
static void
sort_by_depth(const double *z, size_t n, size_t *order, depth_index *di)
{
    size_t i, up = 1, down = 1, strict = 1;

    for (i = 1; i < n && (up || down); i++) {
        up &= z[i] >= z[i - 1];
        down &= z[i] <= z[i - 1];
        strict &= z[i] < z[i - 1];
    }
    if (up) {
        for (i = 0; i < n; i++)
            order[i] = i;
        return;
    }
    if (down && strict) {   /* reversed, no equal depths (a retraction as recorded) */
        for (i = 0; i < n; i++)
            order[i] = n - 1 - i;
        return;
    }
    if (down) {     /* reversed, each run of equal depths kept in file order */
        size_t m = 0, end = n;
        while (end > 0) {
            size_t a = end - 1;
            while (a > 0 && z[a - 1] == z[end - 1])
                a--;
            for (i = a; i < end; i++)
                order[m++] = i;
            end = a;
        }
        return;
    }
    for (i = 0; i < n; i++) {
        di[i].z = z[i];
        di[i].i = i;
    }
    qsort(di, n, sizeof *di, cmp_depth_index);
    for (i = 0; i < n; i++)
        order[i] = di[i].i;
}

/* The curve of like (NULL: none) with the points of f's curve j, the same
 * depth and force arrays (at index j, else searched), or NULL: what the
 * layout derives from the points alone (depth order, noise, quantum) is
 * then taken from it. */
static const fit_curve *
same_points(const lf_fit *like, const lf_fit *f, size_t j)
{
    const lf_fit_curve *b = &f->c[j].data;
    size_t i;

    for (i = 0; like != NULL && i < like->ncurves; i++) {
        const fit_curve *c = &like->c[(j + i) % like->ncurves];
        if (c->data.depth == b->depth && c->data.force == b->force && c->data.n == b->n)
            return c;
    }
    return NULL;
}

/* f->order: each curve's points sorted by depth, ties in file order, so
 * that nothing the fit computes depends on the order of the rows (di:
 * scratch for the longest curve); like's where it has the same points. */
static void
depth_order(lf_fit *f, const lf_fit *like, depth_index *di)
{
    size_t j;

    for (j = 0; j < f->ncurves; j++) {
        size_t *order = f->order + f->c[j].row;
        const fit_curve *c = same_points(like, f, j);
        if (c != NULL)
            memcpy(order, like->order + c->row, f->c[j].data.n * sizeof *order);
        else
            sort_by_depth(f->c[j].data.depth, f->c[j].data.n, order, di);
    }
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

/* Depth span, force scale, guard width and noise of each curve (start:
 * scratch of n + 1 for the longest); the noise and quantum like's where it
 * has the same points. */
static int
curve_scales(lf_fit *f, const lf_fit *like, size_t *start, lf_error *err)
{
    size_t i, j;

    for (j = 0; j < f->ncurves; j++) {
        fit_curve *c = &f->c[j];
        const fit_curve *lc;
        /* every point is finite (check_curve) and f->order sorts the depths */
        const double zmin = c->data.depth[f->order[c->row]];
        const double zmax = c->data.depth[f->order[c->row + c->data.n - 1]];
        double flo = c->data.force[0], fhi = flo, fbig;
        for (i = 1; i < c->data.n; i++) {
            const double F = c->data.force[i];
            flo = F < flo ? F : flo;
            fhi = F > fhi ? F : fhi;
        }
        fbig = lf_fmax(fabs(flo), fabs(fhi));
        c->zlo = zmin;
        c->zhi = zmax;
        c->flo = flo;
        c->fhi = fhi;
        if (!(zmax > zmin) || !(fbig > 0))
            return lf_fail(err, LF_EDATA, "curve %zu (%s): depth or force does not vary",
                           j + 1, c->data.name ? c->data.name : "");
        for (i = 0; i < c->data.n; i++)
            f->ws.zsort[c->row + i] = c->data.depth[f->order[c->row + i]];
        c->L = zmax - zmin;
        c->Fs = fbig;
        c->eps = 1e-3 * c->L / (double) (c->data.n - 1);
        if ((lc = same_points(like, f, j)) != NULL) {
            c->sigma = lc->sigma;
            c->quantum = lc->quantum;
            lf_fit_guess_subsample(f, j);
            continue;
        }
        c->sigma = lf_fit_noise_sigma(c->data.depth, c->data.force, f->order + c->row,
                                      c->data.n, fbig, f->ws.work);
        c->quantum = lf_fit_quantum(c->data.force, c->data.n, fbig, f->ws.work, start);
        /* a quantized signal's noise is never below its step's own: the
         * rounding error of a step q is uniform, of sd q / sqrt(12) (smooth
         * data on a coarse lattice leave most point-to-point departures at
         * exactly 0, and the median estimate with them) */
        c->sigma = lf_fmax(c->sigma, c->quantum / sqrt(12.0));
        lf_fit_guess_subsample(f, j);
    }
    return LF_OK;
}

/* The workspace's numbers, carved from one block (fit_work lists what
 * each holds); vectors and matrices are views into it. */
static double *
take(double **at, size_t n)
{
    double *p = *at;
    *at += n;
    return p;
}

static gsl_vector *
take_vector(gsl_vector *v, double **at, size_t n)
{
    v->size = n;
    v->stride = 1;
    v->data = take(at, n);
    v->block = NULL;
    v->owner = 0;
    return v;
}

static int
work_alloc(lf_fit *f)
{
    fit_work *w = &f->ws;
    const size_t np = f->np, nd = f->ndata, nr = f->nres, nc = f->ncurves;
    const size_t nwork = 3 * nd > 2 * GUESS_NSUB ? 3 * nd : 2 * GUESS_NSUB;
    /* the parameter- and curve-sized numbers, zeroed; then those sized by
     * the data, each written before it is read (zeroing them cost more
     * than a model evaluation of small data) */
    const size_t small = 2 * np                     /* x0_internal, xcache */
                         + (2 * nc + 1) * GUESS_NSUB + GUESS_NODES   /* sub, node */
                         + 9 * nc                   /* keep, off, noise_s1 */
                         + 10 * np                  /* lm.g, lm.D2, lm.colmax, lm.Ah, grad,
                                                       colmax, ainv, gn_x, basin_x, basin_tol */
                         + 6 * np;                  /* lm.x, xt, h, x, x2, x0 */
    const size_t total = small + 4 * nd + nwork     /* sqrtw, delta, noise_e, zsort, work */
                         + 4 * nr;                  /* lm.r, rt, r, r2 */
    double *at;
    gsl_vector *v = w->vectors;
    size_t k;

    w->block = malloc(total * sizeof *w->block);
    if (w->block == NULL)
        return LF_ENOMEM;
    memset(w->block, 0, small * sizeof *w->block);
    at = w->block;
    f->x0_internal = take(&at, np);
    w->xcache = take(&at, np);
    w->sub = take(&at, 2 * GUESS_NSUB * nc);
    w->node = take(&at, GUESS_NSUB + GUESS_NODES);
    w->keep = take(&at, 3 * nc);
    w->off = take(&at, 4 * nc);
    w->noise_s1 = take(&at, 2 * nc);
    w->lm.Ah = take(&at, np);
    w->lm.g = take(&at, np);
    w->lm.D2 = take(&at, np);
    w->lm.colmax = take(&at, np);
    w->grad = take(&at, np);
    w->colmax = take(&at, np);
    w->ainv = take(&at, np);
    w->gn_x = take(&at, np);
    w->basin_x = take(&at, np);
    w->basin_tol = take(&at, np);
    w->lm.x = take_vector(v++, &at, np);
    w->lm.xt = take_vector(v++, &at, np);
    w->lm.h = take_vector(v++, &at, np);
    w->x = take_vector(v++, &at, np);
    w->x2 = take_vector(v++, &at, np);
    w->x0 = take_vector(v++, &at, np);
    w->sqrtw = take(&at, nd);
    w->delta = take(&at, nd);
    w->noise_e = take(&at, nd);
    w->zsort = take(&at, nd);
    w->work = take(&at, nwork);
    w->lm.r = take_vector(v++, &at, nr);
    w->lm.rt = take_vector(v++, &at, nr);
    w->r = take_vector(v++, &at, nr);
    w->r2 = take_vector(v++, &at, nr);
    /* J^T J in block form, and its factors (block.c) */
    if (lf_fit_arrow_alloc(f, 0, &w->lm.A) != LF_OK || lf_arrow_copy_layout(&w->gsl_jtj, &w->lm.A) != LF_OK
        || lf_arrow_chol_alloc(&w->lm.L, &w->lm.A) != LF_OK
        || lf_arrow_chol_alloc(&w->jchol, &w->lm.A) != LF_OK)
        return LF_ENOMEM;
    /* least squares until a robust loss reweights: the guess's cost
     * comparisons (guess_model.c) run before any solve */
    for (k = 0; k < nd; k++)
        w->sqrtw[k] = 1.0;
    return LF_OK;
}

lf_fit *
lf_fit_alloc(const lf_fit_settings *settings, size_t ncurves,
             const lf_fit_curve *curves, lf_error *err)
{
    return lf_fit_alloc_like(settings, ncurves, curves, NULL, err);
}

lf_fit *
lf_fit_alloc_like(const lf_fit_settings *settings, size_t ncurves,
                  const lf_fit_curve *curves, const lf_fit *like, lf_error *err)
{
    lf_fit *f;
    gsl_multifit_nlinear_parameters par = gsl_multifit_nlinear_default_parameters();
    size_t j, nm = sizeof methods / sizeof methods[0], im, nmax;
    void *scratch = NULL;       /* the longest curve's: its depth sort's (nmax depth_index)
                                   and then its quantum's (nmax + 1 size_t) */

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
    f->chi2_step = FIT_CHI2_STEP;
    f->mu0 = FIT_LM_MU0;
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
    if (lf_fit_problem_setup(f, err) != LF_OK) {
        lf_fit_free(f);
        return NULL;
    }
    /* nu held: each model resolves what it needs for that nu now (the
     * exact model's tables), so that no evaluation of the run builds or
     * looks up anything; a free nu is resolved as the fit meets it */
    if (f->imat[FIT_NU] < 0 && isfinite(f->mat.nu))
        for (j = 0; j < ncurves; j++)
            if (lf_model_prepare(f->c[j].model, f->mat.nu, f->mat.nu, err) != LF_OK) {
                lf_fit_free(f);
                return NULL;
            }
    f->order = malloc(f->ndata * sizeof *f->order);
    /* not zeroed: every reader of ev comes after an evaluation that wrote
     * it (problem.c eval_all), and scan_ev is the scan's scratch */
    for (j = 0, nmax = 0; j < ncurves; j++)
        nmax = curves[j].n > nmax ? curves[j].n : nmax;
    f->ws.ev = malloc((f->ndata + nmax) * sizeof *f->ws.ev);
    /* not zeroed either: a model reads a curve's roots only after its head
     * says they are its own (roots[0] = NAN below: none yet) */
    f->ws.roots = malloc((LF_MODEL_ROOTS_SIZE(f->ndata) + LF_MODEL_ROOTS_HEAD * ncurves)
                         * sizeof *f->ws.roots);
    scratch = malloc(nmax * sizeof(depth_index) + sizeof(size_t));
    if (f->order == NULL || f->ws.ev == NULL || f->ws.roots == NULL || scratch == NULL
        || work_alloc(f) != LF_OK)
        goto nomem;
    for (j = 0; j < ncurves; j++)
        lf_fit_roots(f, j)[0] = NAN;
    depth_order(f, like, scratch);
    f->ws.scan_ev = f->ws.ev + f->ndata;
    /* GSL's workspace: made when a run first needs it (lf_fit_gsl) */
    f->gsl_par = par;
    f->gsl_par.trs = f->trs;
    f->gsl_par.scale = lf_fit_scale_more;           /* GSL's "more", block form */
    f->gsl_par.solver = lf_fit_solver_normal;       /* GSL's "cholesky", block form */
    f->gsl_par.fdtype = settings->jacobian == LF_JAC_CENTRAL ? GSL_MULTIFIT_NLINEAR_CTRDIFF
                                                             : GSL_MULTIFIT_NLINEAR_FWDIFF;
    f->fdf.f = lf_fit_residuals;
    f->fdf.df = settings->jacobian == LF_JAC_ANALYTIC ? lf_fit_jacobian : NULL;
    f->fdf.fvv = NULL;
    f->fdf.n = f->nres;
    f->fdf.p = f->np;
    f->fdf.params = f;
    if (curve_scales(f, like, scratch, err) != LF_OK) {
        free(scratch);
        lf_fit_free(f);
        return NULL;
    }
    free(scratch);
    return f;
nomem:
    free(scratch);
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
    free(f->order);
    free(f->ws.ev);
    free(f->ws.roots);
    free(f->ws.block);
    lf_arrow_chol_free(&f->ws.lm.L);
    lf_arrow_chol_free(&f->ws.jchol);
    lf_arrow_free(&f->ws.gsl_jtj);
    lf_arrow_free(&f->ws.lm.A);
    if (f->gsl != NULL)
        gsl_multifit_nlinear_free(f->gsl);
    lf_fit_fd_free(f);
    free(f);
}


int
lf_fit_gsl(lf_fit *f)
{
    if (f->gsl == NULL)
        f->gsl = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &f->gsl_par, f->nres,
                                            f->np);
    return f->gsl != NULL ? lf_fit_fd_alloc(f) : LF_ENOMEM;
}
