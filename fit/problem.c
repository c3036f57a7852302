/* problem.c: the least-squares problem of a joint fit -- which parameters
 * are free, how the GSL vector maps to them (see fit.h), and the weighted
 * residuals and Jacobian across all curves.
 *
 * Residual of point i of curve j:
 *     r = (P(delta_i) + F0_j + s_j delta_i - F_i) / sigma_j,  delta_i = z_i - z0_j
 * with P from any lf_model_type.  Derivatives come from the model
 * (dP/ddelta, dP/dln w, dP/dln E*, dP/dnu) by the chain rule.  The callbacks
 * do not allocate. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "fit.h"

double
lf_fit_nu_of_u(double u)
{
    return 0.25 * (1.0 + tanh(u));
}

double
lf_fit_u_of_nu(double nu)
{
    return atanh(4.0 * nu - 1.0);
}

double
lf_fit_dnu_du(double u)
{
    double t = tanh(u);
    return 0.25 * (1.0 - t * t);
}

/* The internal coordinate of free parameter i at x. */
static double
internal(const lf_fit *f, const double *x, int i)
{
    return f->x0_internal[i] + x[i] - 1.0;
}

/* exp() kept finite and positive. */
static double
exp_clamped(double v)
{
    return exp(lf_fmin(lf_fmax(v, -700.0), 700.0));
}

void
lf_fit_unpack(const lf_fit *f, const double *x, lf_material *mat, double *z0,
           double *F0, double *slope, size_t j)
{
    const fit_curve *c;

    *mat = f->mat;
    if (f->imat[FIT_W] >= 0)
        mat->w = exp_clamped(internal(f, x, f->imat[FIT_W]));
    if (f->imat[FIT_E] >= 0)
        mat->Estar = exp_clamped(internal(f, x, f->imat[FIT_E]));
    if (f->imat[FIT_NU] >= 0)
        mat->nu = lf_fit_nu_of_u(internal(f, x, f->imat[FIT_NU]));
    if (j >= f->ncurves)
        return;
    c = &f->c[j];
    *z0 = c->iz0 >= 0 ? c->L * internal(f, x, c->iz0) : c->z0;
    *F0 = c->iF0 >= 0 ? c->Fs * internal(f, x, c->iF0) : c->F0;
    *slope = c->islope >= 0 ? c->Fs / c->L * internal(f, x, c->islope) : c->slope;
}

void
lf_fit_invalidate(lf_fit *f)
{
    f->ws.xcache_ok = 0;
    f->ws.gn_ok = 0;
}

void
lf_fit_set_origin(lf_fit *f)
{
    size_t j;

    if (f->imat[FIT_W] >= 0)
        f->x0_internal[f->imat[FIT_W]] = log(f->mat.w);
    if (f->imat[FIT_E] >= 0)
        f->x0_internal[f->imat[FIT_E]] = log(f->mat.Estar);
    if (f->imat[FIT_NU] >= 0)
        f->x0_internal[f->imat[FIT_NU]] = lf_fit_u_of_nu(f->mat.nu);
    for (j = 0; j < f->ncurves; j++) {
        fit_curve *c = &f->c[j];
        if (c->iz0 >= 0)
            f->x0_internal[c->iz0] = c->z0 / c->L;
        if (c->iF0 >= 0)
            f->x0_internal[c->iF0] = c->F0 / c->Fs;
        if (c->islope >= 0)
            f->x0_internal[c->islope] = c->slope * c->L / c->Fs;
    }
    lf_fit_invalidate(f);
}

/* Curve j's model depends on nu: a bonded layer under a model with a
 * thickness (the half-space ignores the interface). */
static int
uses_nu(const lf_fit *f, size_t j)
{
    return f->c[j].data.probe.base == LF_BASE_BONDED
           && lf_model_get_type(f->c[j].model)->scope != LF_SCOPE_HALFSPACE;
}

/* nu held (not fitted): no assumed value, and none where the curves'
 * models do not hold.  A bonded layer needs nu, and bonded curves alone do
 * not determine it (they fix M = Z E*): without a value given, LF_EDATA,
 * never a default.  At nu >= FIT_NU_INCOMPRESSIBLE a bonded layer is nearly
 * incompressible: the thin-layer form's Z = (1-nu)^2/(1-2nu) passes 250 and
 * its limit needs a contact far wider than 18 thicknesses (Jaffar 1989,
 * Chadwick 2002); a model that states no limit of its own (nu_max 0) is
 * refused there, one that does (the exact model's tables end at 0.4995) is
 * refused beyond it. */
static int
held_nu_check(const lf_fit *f, lf_error *err)
{
    const double nu = f->set.nu.value;
    size_t j;

    for (j = 0; j < f->ncurves; j++) {
        const lf_model_type *t = lf_model_get_type(f->c[j].model);
        const char *name = f->c[j].data.name ? f->c[j].data.name : "";
        if (!uses_nu(f, j))
            continue;
        if (!isfinite(nu))
            return lf_fail(err, LF_EDATA, "curve %zu (%s): a bonded layer needs Poisson's ratio "
                           "nu, and these curves do not determine it (bonded curves alone fix "
                           "only M = Z E*): give nu (a plan's nu column, or layerfit fit --nu), or "
                           "add a frictionless curve of the same material, with which nu is "
                           "fitted", j + 1, name);
        if (t->nu_max > 0 ? nu > t->nu_max : nu >= FIT_NU_INCOMPRESSIBLE) {
            char v[32];
            /* every digit where fewer would read 0.5 */
            snprintf(v, sizeof v, "%.6g", nu);
            if (strcmp(v, "0.5") == 0)
                snprintf(v, sizeof v, "%.17g", nu);
            return lf_fail(err, LF_EINVAL, "curve %zu (%s): a bonded layer at nu = %s is "
                           "nearly incompressible, where the %s model does not hold (%s); "
                           "the exact model holds up to nu = %g, no model of layerfit beyond",
                           j + 1, name, v, t->name,
                           t->nu_max > 0 ? "its tables end below this nu"
                                         : "the thin-layer form's Z = (1-nu)^2/(1-2nu) diverges",
                           FIT_NU_INCOMPRESSIBLE);
        }
    }
    return LF_OK;
}

int
lf_fit_problem_setup(lf_fit *f, lf_error *err)
{
    const lf_fit_settings *s = &f->set;
    size_t j, row = 0;
    int np = 0, nu_prior = isfinite(s->nu.prior_sd) && s->nu.prior_sd > 0;

    f->any_bonded = f->any_frictionless = 0;
    for (j = 0; j < f->ncurves; j++) {
        if (f->c[j].data.probe.base == LF_BASE_BONDED)
            f->any_bonded = 1;
        else
            f->any_frictionless = 1;
    }
    /* Z = M / E*: nu follows when E* is seen by frictionless curves or held */
    f->nu_determinable = f->any_bonded
                         && (f->any_frictionless || s->Estar.mode == LF_PARAM_FIXED);
    f->imat[FIT_W] = s->w.mode == LF_PARAM_FIXED ? -1 : np++;
    f->imat[FIT_E] = s->Estar.mode == LF_PARAM_FIXED ? -1 : np++;
    f->nu_prior = 0;
    if (s->nu.mode == LF_PARAM_FREE
        || (s->nu.mode == LF_PARAM_AUTO && f->any_bonded
            && (f->nu_determinable || nu_prior))) {
        f->imat[FIT_NU] = np++;
        f->nu_prior = nu_prior;
    } else {
        f->imat[FIT_NU] = -1;
    }
    f->mat.w = s->w.value;
    f->mat.Estar = s->Estar.value;
    f->mat.nu = s->nu.value;
    if (s->nu.mode == LF_PARAM_FIXED || isfinite(s->nu.value))
        if (!(s->nu.value >= 0 && s->nu.value < 0.5))
            return lf_fail(err, LF_EINVAL, "nu must lie in [0, 0.5) (got %g)", s->nu.value);
    if (nu_prior && !isfinite(s->nu.value))
        return lf_fail(err, LF_EINVAL, "a prior on nu needs its mean (nu.value)");
    if (f->imat[FIT_NU] < 0) {
        int status = held_nu_check(f, err);
        if (status != LF_OK)
            return status;
        if (!isfinite(f->mat.nu))
            f->mat.nu = FIT_NU_UNUSED;  /* no curve depends on it */
    }
    if (!isnan(s->w.guess) && !(s->w.guess > 0 && isfinite(s->w.guess)))
        return lf_fail(err, LF_EINVAL, "a guess of w must be finite and > 0 (got %g)", s->w.guess);
    if (!isnan(s->Estar.guess) && !(s->Estar.guess > 0 && isfinite(s->Estar.guess)))
        return lf_fail(err, LF_EINVAL, "a guess of E* must be finite and > 0 (got %g)",
                       s->Estar.guess);
    if (!isnan(s->nu.guess) && !(s->nu.guess > 0 && s->nu.guess < 0.5))
        return lf_fail(err, LF_EINVAL, "a guess of nu must lie in (0, 0.5) (got %g)", s->nu.guess);
    if (s->w.mode == LF_PARAM_FIXED && !(s->w.value >= 0 && isfinite(s->w.value)))
        return lf_fail(err, LF_EINVAL, "a fixed w must be finite and >= 0 (got %g)", s->w.value);
    if (s->Estar.mode == LF_PARAM_FIXED && !(s->Estar.value > 0 && isfinite(s->Estar.value)))
        return lf_fail(err, LF_EINVAL, "a fixed E* must be finite and > 0 (got %g)", s->Estar.value);
    for (j = 0; j < f->ncurves; j++) {
        fit_curve *c = &f->c[j];
        c->row = row;
        row += c->data.n;
        c->iz0 = isnan(c->data.z0) ? np++ : -1;
        c->iF0 = isnan(c->data.F0) ? np++ : -1;
        c->islope = s->fit_slope ? np++ : -1;
        c->z0 = isnan(c->data.z0) ? 0.0 : c->data.z0;
        c->F0 = isnan(c->data.F0) ? 0.0 : c->data.F0;
        c->slope = 0.0;
    }
    f->ndata = row;
    f->nres = row + (size_t) f->nu_prior;
    f->np = (size_t) np;
    if (f->np == 0)
        return lf_fail(err, LF_EINVAL, "nothing to fit: every parameter is fixed");
    if (f->nres <= f->np)
        return lf_fail(err, LF_EDATA, "%zu points cannot fit %zu parameters",
                       f->ndata, f->np);
    return LF_OK;
}

/* Evaluate the model at every point for x, caching the result. */
static int
eval_all(lf_fit *f, const double *x)
{
    size_t i, j;
    lf_material mat;
    double z0, F0, slope;

    if (f->ws.xcache_ok && memcmp(x, f->ws.xcache, f->np * sizeof *x) == 0)
        return LF_OK;
    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        double *delta = f->ws.delta + c->row;
        lf_fit_unpack(f, x, &mat, &z0, &F0, &slope, j);
        for (i = 0; i < c->data.n; i++)
            delta[i] = c->data.depth[i] - z0;
        if (lf_model_eval_roots(c->model, &mat, c->data.branch, c->data.n, delta,
                                f->ws.ev + c->row, lf_fit_roots(f, j)) != LF_OK)
            return LF_ENUMERIC;
    }
    memcpy(f->ws.xcache, x, f->np * sizeof *x);
    f->ws.xcache_ok = 1;
    return LF_OK;
}

double *
lf_fit_roots(lf_fit *f, size_t j)
{
    return f->ws.roots + LF_MODEL_ROOTS_SIZE(f->c[j].row) + LF_MODEL_ROOTS_HEAD * j;
}

void
lf_fit_model_changed(lf_fit *f, size_t j)
{
    const fit_curve *c = &f->c[j];
    lf_material mat;
    double z0, F0, slope;

    f->ws.gn_ok = 0;
    if (!f->ws.xcache_ok)
        return;
    lf_fit_unpack(f, f->ws.xcache, &mat, &z0, &F0, &slope, j);
    if (lf_model_eval_roots(c->model, &mat, c->data.branch, c->data.n, f->ws.delta + c->row,
                            f->ws.ev + c->row, lf_fit_roots(f, j)) != LF_OK)
        f->ws.xcache_ok = 0;
}

int
lf_fit_eval_at(lf_fit *f, const double *x)
{
    return eval_all(f, x);
}

int
lf_fit_residuals_ss(lf_fit *f, const gsl_vector *xv, gsl_vector *r, double *ss_out)
{
    const double *x = xv->data;
    size_t i, j;
    lf_material mat;
    double z0, F0, slope, ss = 0.0;

    if (eval_all(f, x) != LF_OK)
        return GSL_EDOM;
    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        const double inv_sigma = 1.0 / c->sigma;
        /* through local pointers: the stores into r would make the loop
         * read f's again at every point */
        const lf_eval *ev = f->ws.ev + c->row;
        const double *delta = f->ws.delta + c->row, *sw = f->ws.sqrtw + c->row;
        const double *force = c->data.force;
        const size_t n = c->data.n, stride = r->stride;
        double *rc = r->data + c->row * stride;
        lf_fit_unpack(f, x, &mat, &z0, &F0, &slope, j);
        for (i = 0; i < n; i++) {
            const double v = (ev[i].P + F0 + slope * delta[i] - force[i]) * inv_sigma * sw[i];
            if (!isfinite(v))
                return GSL_EDOM;
            rc[i * stride] = v;
            ss += v * v;
        }
    }
    if (f->nu_prior) {
        double v;
        lf_fit_unpack(f, x, &mat, &z0, &F0, &slope, f->ncurves);
        v = (mat.nu - f->set.nu.value) / f->set.nu.prior_sd;
        gsl_vector_set(r, f->ndata, v);
        ss += v * v;
    }
    if (ss_out != NULL)
        *ss_out = ss;
    return GSL_SUCCESS;
}

int
lf_fit_residuals(const gsl_vector *xv, void *params, gsl_vector *r)
{
    return lf_fit_residuals_ss(params, xv, r, NULL);
}

int
lf_fit_curve_residuals(lf_fit *f, const double *x, size_t j, double *delta, lf_eval *ev,
                       double *r)
{
    const fit_curve *c = &f->c[j];
    const double inv_sigma = 1.0 / c->sigma;
    lf_material mat;
    double z0, F0, slope;
    size_t i;

    lf_fit_unpack(f, x, &mat, &z0, &F0, &slope, j);
    if (ev == NULL) {           /* f's evaluation holds */
        delta = f->ws.delta + c->row;
        ev = f->ws.ev + c->row;
    } else {
        for (i = 0; i < c->data.n; i++)
            delta[i] = c->data.depth[i] - z0;
        if (lf_model_eval_roots(c->model, &mat, c->data.branch, c->data.n, delta, ev, NULL)
            != LF_OK)
            return GSL_EDOM;
    }
    for (i = 0; i < c->data.n; i++) {
        const size_t k = c->row + i;
        /* lf_fit_residuals_ss's expression */
        r[i] = (ev[i].P + F0 + slope * delta[i] - c->data.force[i]) * inv_sigma * f->ws.sqrtw[k];
        if (!isfinite(r[i]))
            return GSL_EDOM;
    }
    return GSL_SUCCESS;
}

/* Each curve's free force offset F0 (and slope) set to its least-squares
 * value given the rest of x, from the residuals r at x: the residuals are
 * linear in them, with columns Fs sqrtw/sigma (and Fs/L delta
 * sqrtw/sigma), so this is a 1 x 1 (or 2 x 2) solve per curve, and x and
 * r are updated in place.  The model's evaluation at x does not depend on
 * them and stays valid: the cache follows x.  lm.c says why. */
int
lf_fit_project_offsets(lf_fit *f, double *x, double *r)
{
    const int cached = f->ws.xcache_ok && memcmp(x, f->ws.xcache, f->np * sizeof *x) == 0;
    size_t i, j;
    int any = 0;

    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        const double *sw = f->ws.sqrtw + c->row, *d = f->ws.delta + c->row;
        double *rr = r + c->row, saa = 0.0, sab = 0.0, sbb = 0.0, sar = 0.0, sbr = 0.0;
        double da = 0.0, db = 0.0, det;
        const size_t n = c->data.n;
        if (c->iF0 < 0 && c->islope < 0)
            continue;
        any = 1;
        /* the columns without their constant factors: a = sqrtw, b = delta
         * sqrtw (moves da, db in units of sigma) */
        if (c->islope < 0) {            /* F0 alone: the usual case */
            for (i = 0; i < n; i++) {
                saa += sw[i] * sw[i];
                sar += sw[i] * rr[i];
            }
            if (!(saa > 0))
                continue;
            da = -sar / saa;
            for (i = 0; i < n; i++)
                rr[i] += da * sw[i];
        } else {
            for (i = 0; i < n; i++) {
                const double a = sw[i], b = d[i] * sw[i];
                saa += a * a;
                sar += a * rr[i];
                sab += a * b;
                sbb += b * b;
                sbr += b * rr[i];
            }
            if (c->iF0 >= 0) {
                det = saa * sbb - sab * sab;
                if (!(det > 1e-12 * saa * sbb))
                    continue;
                da = -(sbb * sar - sab * sbr) / det;
                db = -(saa * sbr - sab * sar) / det;
            } else {
                if (!(sbb > 0))
                    continue;
                db = -sbr / sbb;
            }
            for (i = 0; i < n; i++)
                rr[i] += (da + db * d[i]) * sw[i];
        }
        if (c->iF0 >= 0) {
            x[c->iF0] += da * c->sigma / c->Fs;
            if (cached)
                f->ws.xcache[c->iF0] = x[c->iF0];
        }
        if (c->islope >= 0) {
            x[c->islope] += db * c->sigma * c->L / c->Fs;
            if (cached)
                f->ws.xcache[c->islope] = x[c->islope];
        }
    }
    return any;
}

/* ---- the Jacobian, and the normal equations without it ---------------- */

/* The six columns a curve's rows can touch, in the order of the entries
 * row_entries() gives: w, E*, nu (the material's), then the curve's own
 * z0, F0 and slope.  A curve's map keeps the free ones: sel[q] names which
 * of the six its q-th column is, mult[q] the factor of the coordinate
 * (internal or physical), col[q] its index in x.  Also what the rows
 * need: the curve's material, slope and detachment point. */
typedef struct {
    size_t m;
    int sel[6], col[6];
    double mult[6];
    lf_material mat;
    double slope, ddet;
    double edge_hi;             /* ddet + eps where edge holds the model there,
                                   else ddet: a row of indentation d takes edge
                                   where ddet < d < edge_hi */
    const lf_model *model;      /* the model the rows are of */
    lf_eval edge;
} row_map;

/* The column in x of the six a curve's rows can touch (row_entries'
 * order), -1 when it is held. */
static int
column_of(const lf_fit *f, size_t j, size_t q)
{
    const fit_curve *c = &f->c[j];
    const int col[6] = { f->imat[FIT_W], f->imat[FIT_E], f->imat[FIT_NU], c->iz0, c->iF0,
                         c->islope };
    return col[q];
}

/* The factor of each of the six columns of curve j at x (material mat
 * there) on the model's derivatives (dP/dln w, dP/dln E*, dP/dnu,
 * dP/ddelta, 1, delta).  physical = 0: derivatives with respect to the
 * internal coordinates (= x); 1: with respect to w, E*, nu, z0, F0, s
 * (d(internal)/d(physical) is 1/w, 1/E*, du/dnu, 1/L, 1/Fs, L/Fs). */
static void
coordinate_mult(const lf_fit *f, const double *x, size_t j, const lf_material *mat,
                int physical, double mult[6])
{
    const fit_curve *c = &f->c[j];
    const int inu = f->imat[FIT_NU];

    mult[0] = physical ? 1.0 / mat->w : 1.0;
    mult[1] = physical ? 1.0 / mat->Estar : 1.0;
    mult[2] = physical || inu < 0 ? 1.0 : lf_fit_dnu_du(internal(f, x, inu));
    mult[3] = physical ? -1.0 : -c->L;
    mult[4] = physical ? 1.0 : c->Fs;
    mult[5] = physical ? 1.0 : c->Fs / c->L;
}

/* Curve j's map at x (physical as in coordinate_mult), for its model or
 * (model not NULL) another. */
static void
curve_map_of(const lf_fit *f, const double *x, size_t j, int physical, const lf_model *model,
             row_map *map)
{
    const fit_curve *c = &f->c[j];
    double mult[6], z0, F0;
    lf_pulloff po;
    size_t q;

    lf_fit_unpack(f, x, &map->mat, &z0, &F0, &map->slope, j);
    coordinate_mult(f, x, j, &map->mat, physical, mult);
    map->m = 0;
    for (q = 0; q < 6; q++) {
        const int col = column_of(f, j, q);
        if (col >= 0) {
            map->sel[map->m] = (int) q;
            map->col[map->m] = col;
            map->mult[map->m++] = mult[q];
        }
    }
    /* on unloading, a point closer than eps to detachment, where the
     * derivatives blow up, takes those of the point eps inside contact:
     * evaluated here, once for the curve's rows (a call among them would
     * keep their sums in memory) */
    map->model = model != NULL ? model : c->model;
    map->ddet = map->edge_hi = -HUGE_VAL;
    if (c->data.branch == LF_BRANCH_UNLOAD
        && lf_model_pulloff(map->model, &map->mat, &po, NULL) == LF_OK) {
        double d2;
        map->ddet = map->edge_hi = po.delta_detach;
        d2 = map->ddet + c->eps;
        if (lf_model_eval(map->model, &map->mat, c->data.branch, 1, &d2, &map->edge, NULL)
            == LF_OK)
            map->edge_hi = d2;
    }
}

static void
curve_map(const lf_fit *f, const double *x, size_t j, int physical, row_map *map)
{
    curve_map_of(f, x, j, physical, NULL, map);
}

/* The six numbers a row of indentation d can hold, the model's evaluation
 * e there, in the columns' numbering (before their factors): dP/dln w,
 * dP/dln E*, dP/dnu, dP/ddelta + slope, 1, d. */
LF_KERNEL void
row_values(const row_map *map, double d, const lf_eval *e, double *t)
{
    if (d > map->ddet && d < map->edge_hi)      /* never unless unloading */
        e = &map->edge;
    t[0] = e->dP_dlogw;
    t[1] = e->dP_dlogE;
    t[2] = e->dP_dnu;
    t[3] = e->dP_ddelta + map->slope;
    t[4] = 1.0;
    t[5] = d;
}

/* The entries of the row of indentation d, the model's evaluation e there,
 * in the map's columns into v[0..M-1] (unweighted by sigma and the robust
 * weight: ws multiplies them); sel is map->sel or, in the instances for
 * the usual columns, a constant copy of it. */
LF_KERNEL void
row_entries(const row_map *map, size_t M, const int *sel, double d,
            const lf_eval *e, double ws, double *v)
{
    double t[6];
    size_t q;

    row_values(map, d, e, t);
#pragma GCC unroll 6
    for (q = 0; q < M; q++)
        v[q] = t[sel[q]] * map->mult[q] * ws;
}

/* The nu prior's row (row ndata): its one entry, in nu's column, with
 * respect to the internal coordinate u (physical = 0) or nu itself. */
static double
prior_entry(const lf_fit *f, const double *x, int physical)
{
    const double dnu = physical ? 1.0 : lf_fit_dnu_du(internal(f, x, f->imat[FIT_NU]));
    return dnu / f->set.nu.prior_sd;
}

/* Curve c's rows of J, M columns (a compile-time constant in each
 * instance), into J's rows (zeros elsewhere already). */
LF_KERNEL void
curve_rows(const lf_fit *f, const fit_curve *c, const row_map *map, size_t M, gsl_matrix *J)
{
    const double inv_sigma = 1.0 / c->sigma;
    size_t i, q;

    for (i = 0; i < c->data.n; i++) {
        const size_t k = c->row + i;
        double v[6], *row = J->data + k * J->tda;
        row_entries(map, M, map->sel, f->ws.delta[k], &f->ws.ev[k], f->ws.sqrtw[k] * inv_sigma,
                    v);
#pragma GCC unroll 6
        for (q = 0; q < M; q++)
            row[map->col[q]] = v[q];
    }
}

/* Fill J, rows weighted by 1/sigma (physical as in curve_map). */
static int
fill_jacobian(lf_fit *f, const double *x, gsl_matrix *J, int physical)
{
    size_t i, j;
    row_map map;

    if (eval_all(f, x) != LF_OK)
        return GSL_EDOM;
    /* the zeros of every row at once (a call per row costs more than the
     * row's numbers) */
    if (J->tda == J->size2)
        memset(J->data, 0, J->size1 * J->size2 * sizeof *J->data);
    else
        for (i = 0; i < J->size1; i++)
            memset(J->data + i * J->tda, 0, J->size2 * sizeof *J->data);
    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        curve_map(f, x, j, physical, &map);
        switch (map.m) {
        case 0: break;
        case 1: curve_rows(f, c, &map, 1, J); break;
        case 2: curve_rows(f, c, &map, 2, J); break;
        case 3: curve_rows(f, c, &map, 3, J); break;
        case 4: curve_rows(f, c, &map, 4, J); break;
        case 5: curve_rows(f, c, &map, 5, J); break;
        default: curve_rows(f, c, &map, 6, J); break;
        }
    }
    if (f->nu_prior)
        J->data[f->ndata * J->tda + (size_t) f->imat[FIT_NU]] = prior_entry(f, x, physical);
    return GSL_SUCCESS;
}

/* Curve c's rows of J^T J (lower triangle, local 6 x 6), J^T r and the
 * column maxima, M columns (a compile-time constant in each instance, so
 * the sums stay in registers; so is sel in the instances for the usual
 * columns). */
LF_KERNEL void
curve_sums(const lf_fit *f, const fit_curve *c, const row_map *map, size_t M,
           const int *sel, const double *r, double *sa, double *sg, double *sb)
{
    const double inv_sigma = 1.0 / c->sigma;
    /* the curve's numbers through local pointers: the sums are stored
     * nowhere in the loop, so nothing is read again */
    const double *delta = f->ws.delta + c->row, *sw = f->ws.sqrtw + c->row, *rc = r + c->row;
    const lf_eval *ev = f->ws.ev + c->row;
    const size_t n = c->data.n;
    double a[36] = { 0 }, gk[6] = { 0 }, bk[6] = { 0 };
    size_t i, q, l;

    for (i = 0; i < n; i++) {
        const double ri = rc[i];
        double v[6];
        row_entries(map, M, sel, delta[i], &ev[i], sw[i] * inv_sigma, v);
        /* unrolled (M is constant): the sums stay in registers */
#pragma GCC unroll 6
        for (q = 0; q < M; q++) {
            const double av = fabs(v[q]);
            gk[q] += v[q] * ri;
            /* a NaN leaves the maximum (as lf_fmax would); it reaches g */
            bk[q] = av > bk[q] ? av : bk[q];
#pragma GCC unroll 6
            for (l = 0; l <= q; l++)
                a[q * 6 + l] += v[q] * v[l];
        }
    }
    for (q = 0; q < M; q++) {
        sg[q] = gk[q];
        sb[q] = bk[q];
        for (l = 0; l <= q; l++)
            sa[q * 6 + l] = a[q * 6 + l];
    }
}

#if defined(__SSE2__)
/* curve_sums with the columns two to a register, for a constant sel: the
 * row's entries v[2p], v[2p+1] side by side (a missing last one 0), and
 * each sum a lane of its own, its products added in the rows' order as
 * curve_sums adds them (each lane curve_sums' operations on its sum: the
 * same bits in about half the instructions).  Lane q % 2 of A[q/2][l]
 * holds a[q][l] for l <= q (the other lanes, sums a[q][l] with q < l,
 * are taken and not read); of G[q/2] g[q], of B[q/2] the maximum of
 * |v[q]|. */
LF_KERNEL void
curve_sums_pairs(const lf_fit *f, const fit_curve *c, const row_map *map, size_t M,
                 const int *sel, const double *r, double *sa, double *sg, double *sb)
{
    const size_t P = (M + 1) / 2;
    const double inv_sigma = 1.0 / c->sigma;
    const double *delta = f->ws.delta + c->row, *sw = f->ws.sqrtw + c->row, *rc = r + c->row;
    const lf_eval *ev = f->ws.ev + c->row;
    const size_t n = c->data.n;
    const __m128d sign = _mm_set1_pd(-0.0);
    __m128d A[3][6], G[3], B[3], mult[3];
    size_t i, p, l, q;

    for (p = 0; p < P; p++) {
        mult[p] = _mm_set_pd(2 * p + 1 < M ? map->mult[2 * p + 1] : 0.0, map->mult[2 * p]);
        G[p] = B[p] = _mm_setzero_pd();
        for (l = 0; l < M; l++)
            A[p][l] = _mm_setzero_pd();
    }
    for (i = 0; i < n; i++) {
        const __m128d ws = _mm_set1_pd(sw[i] * inv_sigma), ri = _mm_set1_pd(rc[i]);
        double t[6];
        __m128d v[3];
        row_values(map, delta[i], &ev[i], t);
#pragma GCC unroll 3
        for (p = 0; p < P; p++)
            v[p] = _mm_mul_pd(_mm_mul_pd(_mm_set_pd(2 * p + 1 < M ? t[sel[2 * p + 1]] : 0.0,
                                                    t[sel[2 * p]]), mult[p]), ws);
#pragma GCC unroll 6
        for (l = 0; l < M; l++) {
            const __m128d vl = l % 2 ? _mm_unpackhi_pd(v[l / 2], v[l / 2])
                                     : _mm_unpacklo_pd(v[l / 2], v[l / 2]);
#pragma GCC unroll 3
            for (p = l / 2; p < P; p++)
                A[p][l] = _mm_add_pd(A[p][l], _mm_mul_pd(v[p], vl));
        }
#pragma GCC unroll 3
        for (p = 0; p < P; p++) {
            G[p] = _mm_add_pd(G[p], _mm_mul_pd(v[p], ri));
            /* max(|v|, b): |v| where |v| > b, else b (a NaN leaves b) */
            B[p] = _mm_max_pd(_mm_andnot_pd(sign, v[p]), B[p]);
        }
    }
    for (q = 0; q < M; q++) {
        double lane[2];
        _mm_storeu_pd(lane, G[q / 2]);
        sg[q] = lane[q % 2];
        _mm_storeu_pd(lane, B[q / 2]);
        sb[q] = lane[q % 2];
        for (l = 0; l <= q; l++) {
            _mm_storeu_pd(lane, A[q / 2][l]);
            sa[q * 6 + l] = lane[q % 2];
        }
    }
}
#define CURVE_SUMS_CONST curve_sums_pairs
#else
#define CURVE_SUMS_CONST curve_sums
#endif

/* The columns a curve's rows touch most often, in row_entries' numbering:
 * w and E*, with nu, with the curve's z0 and F0, with both. */
static const int SEL_WE[] = { 0, 1 }, SEL_WEN[] = { 0, 1, 2 }, SEL_WEZF[] = { 0, 1, 3, 4 },
                 SEL_WENZF[] = { 0, 1, 2, 3, 4 };

static int
sel_is(const row_map *map, const int *sel, size_t m)
{
    return map->m == m && memcmp(map->sel, sel, m * sizeof *sel) == 0;
}

/* curve_sums for the map's columns: an instance with constant columns for
 * the usual ones, else one per count. */
static void
sums_of(const lf_fit *f, const fit_curve *c, const row_map *map, const double *r, double *sa,
        double *sg, double *sb)
{
    if (sel_is(map, SEL_WE, 2))
        CURVE_SUMS_CONST(f, c, map, 2, SEL_WE, r, sa, sg, sb);
    else if (sel_is(map, SEL_WEZF, 4))
        CURVE_SUMS_CONST(f, c, map, 4, SEL_WEZF, r, sa, sg, sb);
    else if (sel_is(map, SEL_WEN, 3))
        CURVE_SUMS_CONST(f, c, map, 3, SEL_WEN, r, sa, sg, sb);
    else if (sel_is(map, SEL_WENZF, 5))
        CURVE_SUMS_CONST(f, c, map, 5, SEL_WENZF, r, sa, sg, sb);
    else
        switch (map->m) {
        case 1: curve_sums(f, c, map, 1, map->sel, r, sa, sg, sb); break;
        case 2: curve_sums(f, c, map, 2, map->sel, r, sa, sg, sb); break;
        case 3: curve_sums(f, c, map, 3, map->sel, r, sa, sg, sb); break;
        case 4: curve_sums(f, c, map, 4, map->sel, r, sa, sg, sb); break;
        case 5: curve_sums(f, c, map, 5, map->sel, r, sa, sg, sb); break;
        default: curve_sums(f, c, map, 6, map->sel, r, sa, sg, sb); break;
        }
}

int
lf_fit_arrow_alloc(const lf_fit *f, size_t extra, fit_arrow *A)
{
    unsigned char *q = malloc(f->ncurves ? f->ncurves : 1);
    size_t j, m = extra;
    int k, st;

    if (q == NULL)
        return LF_ENOMEM;
    for (k = 0; k < FIT_NMAT; k++)
        m += f->imat[k] >= 0;
    for (j = 0; j < f->ncurves; j++)
        q[j] = (unsigned char) ((f->c[j].iz0 >= 0) + (f->c[j].iF0 >= 0) + (f->c[j].islope >= 0));
    st = lf_arrow_alloc(A, m, f->ncurves, q);
    free(q);
    return st;
}

int
lf_fit_normal_sums(lf_fit *f, const double *x, const double *r, fit_arrow *A, double *g,
                   double *colmax)
{
    const size_t p = f->np;
    size_t j, q, l;

    if (eval_all(f, x) != LF_OK)
        return GSL_EDOM;
    lf_arrow_zero(A);
    memset(g, 0, p * sizeof *g);
    memset(colmax, 0, p * sizeof *colmax);
    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        double sa[36], sg[6], sb[6];
        row_map map;

        curve_map(f, x, j, 0, &map);
        if (map.m == 0)
            continue;
        sums_of(f, c, &map, r, sa, sg, sb);
        for (q = 0; q < map.m; q++) {
            const size_t cq = (size_t) map.col[q];
            g[cq] += sg[q];
            /* as the maximum above: a NaN in sb stays out, the sums carry it */
            colmax[cq] = sb[q] > colmax[cq] ? sb[q] : colmax[cq];
            for (l = 0; l <= q; l++)
                lf_arrow_add(A, j, cq, (size_t) map.col[l], sa[q * 6 + l]);
        }
    }
    if (f->nu_prior) {      /* the prior's row: one entry, in nu's column */
        const size_t inu = (size_t) f->imat[FIT_NU];
        const double v = prior_entry(f, x, 0), ri = r[f->ndata];
        lf_arrow_add(A, f->ncurves, inu, inu, v * v);
        g[inu] += v * ri;
        colmax[inu] = lf_fmax(colmax[inu], fabs(v));
    }
    return GSL_SUCCESS;
}

/* Rows [i0, i1) of J, whose entries outside the columns cols[0..nc) are
 * zero, into block j of A (of the prior's rows: the head alone), g and
 * colmax: their products summed in a dense nc x nc lower triangle first,
 * then added to A once. */
static void
add_rows(fit_arrow *A, size_t j, const gsl_matrix *J, const double *r, size_t i0, size_t i1,
         const size_t *cols, size_t nc, double *g, double *colmax)
{
    double S[(FIT_MMAX + FIT_QMAX) * (FIT_MMAX + FIT_QMAX)] = { 0.0 };
    size_t i, a, b;

    if (i0 == i1)
        return;
    for (i = i0; i < i1; i++) {
        const double *row = J->data + i * J->tda, ri = r[i];
        for (a = 0; a < nc; a++) {
            const double v = row[cols[a]];
            colmax[cols[a]] = lf_fmax(colmax[cols[a]], fabs(v));
            g[cols[a]] += v * ri;
            for (b = 0; b <= a; b++)
                S[a * nc + b] += v * row[cols[b]];
        }
    }
    for (a = 0; a < nc; a++)
        for (b = 0; b <= a; b++)
            lf_arrow_add(A, j, cols[a], cols[b], S[a * nc + b]);
}

void
lf_fit_normal_of_jacobian(const lf_fit *f, const gsl_matrix *J, const double *r, fit_arrow *A,
                          double *g, double *colmax)
{
    const size_t p = f->np, m = A->m;
    size_t j, a, cols[FIT_MMAX + FIT_QMAX], nc;

    lf_arrow_zero(A);
    memset(g, 0, p * sizeof *g);
    memset(colmax, 0, p * sizeof *colmax);
    for (a = 0; a < m; a++)
        cols[a] = a;
    for (j = 0; j < f->ncurves; j++) {
        /* a curve's rows: the material's columns and its own */
        for (a = 0, nc = m; a < A->q[j]; a++)
            cols[nc++] = A->at[j] + a;
        add_rows(A, j, J, r, f->c[j].row, f->c[j].row + f->c[j].data.n, cols, nc, g, colmax);
    }
    /* the prior's: nu's alone */
    add_rows(A, f->ncurves, J, r, f->ndata, f->nres, cols, m, g, colmax);
}

int
lf_fit_jacobian(const gsl_vector *x, void *params, gsl_matrix *J)
{
    return fill_jacobian(params, x->data, J, 0);
}

int
lf_fit_jacobian_physical(lf_fit *f, const double *x, gsl_matrix *J)
{
    return fill_jacobian(f, x, J, 1);
}

int
lf_fit_jacobian_physical_nu(lf_fit *f, const double *x, gsl_matrix *J)
{
    gsl_matrix_view free_part = gsl_matrix_submatrix(J, 0, 0, J->size1, f->np);
    const int sel[1] = { 2 };       /* row_entries' dP/dnu */
    size_t i, j;
    row_map map;

    if (fill_jacobian(f, x, &free_part.matrix, 1) != GSL_SUCCESS)
        return GSL_EDOM;
    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        curve_map(f, x, j, 1, &map);
        map.mult[0] = 1.0;
        for (i = 0; i < c->data.n; i++) {
            const size_t k = c->row + i;
            double v;
            row_entries(&map, 1, sel, f->ws.delta[k], &f->ws.ev[k], f->ws.sqrtw[k] / c->sigma,
                        &v);
            gsl_matrix_set(J, k, f->np, v);
        }
    }
    for (i = f->ndata; i < J->size1; i++)
        gsl_matrix_set(J, i, f->np, 0.0);
    return GSL_SUCCESS;
}

int
lf_fit_curve_rows(lf_fit *f, const double *x, size_t j, lf_model *model, lf_eval *ev,
                  int with_nu, double *rows, size_t *mcols)
{
    const fit_curve *c = &f->c[j];
    const double inv_sigma = 1.0 / c->sigma, *delta = f->ws.delta + c->row;
    const lf_eval *e = f->ws.ev + c->row;
    int sel[7];
    row_map map, wide;
    size_t i, q, m = 0, k;

    if (eval_all(f, x) != LF_OK)
        return GSL_EDOM;
    curve_map_of(f, x, j, 1, model, &map);
    if (model != NULL) {
        if (lf_model_eval(model, &map.mat, c->data.branch, c->data.n, delta, ev, NULL) != LF_OK)
            return GSL_EDOM;
        e = ev;
    }
    /* the material's free columns, dP/dnu (with_nu), then the curve's own:
     * row_entries' numbering keeps that order */
    wide = map;
    for (q = 0, k = 0; q < map.m; q++) {
        if (with_nu && map.sel[q] >= 3 && m == k) {
            sel[k] = 2;
            wide.mult[k++] = 1.0;
        }
        sel[k] = map.sel[q];
        wide.mult[k++] = map.mult[q];
        m += map.sel[q] < 3;
    }
    if (with_nu && m == k) {
        sel[k] = 2;
        wide.mult[k++] = 1.0;
    }
    wide.m = k;
    *mcols = m + (size_t) (with_nu != 0);
    for (i = 0; i < c->data.n; i++)
        row_entries(&wide, k, sel, delta[i], &e[i], f->ws.sqrtw[c->row + i] * inv_sigma,
                    rows + i * k);
    return GSL_SUCCESS;
}

double
lf_fit_prior_entry(const lf_fit *f, const double *x, int physical)
{
    return f->nu_prior ? prior_entry(f, x, physical) : 0.0;
}

void
lf_fit_internal_scale(const lf_fit *f, const double *x, double *c)
{
    lf_material mat;
    double z0, F0, slope, mi[6], mp[6];
    size_t j, q;

    for (j = 0; j < f->ncurves; j++) {
        lf_fit_unpack(f, x, &mat, &z0, &F0, &slope, j);
        coordinate_mult(f, x, j, &mat, 0, mi);
        coordinate_mult(f, x, j, &mat, 1, mp);
        for (q = 0; q < 6; q++) {
            const int col = column_of(f, j, q);
            if (col >= 0)
                c[col] = mi[q] / mp[q];
        }
    }
}

double
lf_fit_cost(lf_fit *f, const gsl_vector *x, gsl_vector *r)
{
    double n;
    if (lf_fit_residuals(x, f, r) != GSL_SUCCESS)
        return HUGE_VAL;
    n = gsl_blas_dnrm2(r);
    return 0.5 * n * n;
}

void
lf_fit_rebase(lf_fit *f, gsl_vector *x)
{
    lf_material mat;
    double z0, F0, slope;
    size_t j;

    for (j = 0; j < f->ncurves; j++) {
        lf_fit_unpack(f, x->data, &mat, &z0, &F0, &slope, j);
        f->c[j].z0 = z0;
        f->c[j].F0 = F0;
        f->c[j].slope = slope;
    }
    lf_fit_unpack(f, x->data, &mat, &z0, &F0, &slope, f->ncurves);
    f->mat = mat;
    lf_fit_set_origin(f);
    gsl_vector_set_all(x, 1.0);
}
