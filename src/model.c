/* model.c: the table of forward models, their shared domain checks and the
 * lf_model object that binds a model to one probe. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "exact.h"
#include "internal.h"

struct lf_model {
    const lf_model_type *type;
    lf_probe probe;
    void *state;
};

const lf_model_type *const lf_model_types[] = {
    &lf_model_thin,
    &lf_model_exact,
    &lf_model_halfspace,
    NULL
};

const lf_model_type *
lf_model_type_find(const char *name)
{
    size_t i;
    for (i = 0; lf_model_types[i] != NULL; i++)
        if (strcmp(lf_model_types[i]->name, name) == 0)
            return lf_model_types[i];
    return NULL;
}

int
lf_material_check(const lf_material *m, lf_base base, lf_error *err)
{
    if (!(isfinite(m->w) && m->w >= 0))
        return lf_fail(err, LF_EINVAL, "w must be a finite work of adhesion >= 0 (got %g J/m^2)", m->w);
    if (!(isfinite(m->Estar) && m->Estar > 0))
        return lf_fail(err, LF_EINVAL, "E* must be a finite modulus > 0 (got %g Pa)", m->Estar);
    if (base == LF_BASE_BONDED && !(isfinite(m->nu) && m->nu >= 0 && m->nu < 0.5))
        return lf_fail(err, LF_EINVAL, "nu must lie in [0, 0.5) for a bonded layer (got %g)", m->nu);
    return LF_OK;
}

const lf_model_type *
lf_model_type_cheapest(lf_model_scope scope)
{
    const lf_model_type *best = NULL;
    size_t i;

    for (i = 0; lf_model_types[i] != NULL; i++)
        if (lf_model_types[i]->scope == scope && (best == NULL || lf_model_types[i]->cost < best->cost))
            best = lf_model_types[i];
    return best;
}

lf_model *
lf_model_alloc(const lf_model_type *type, const lf_probe *probe, lf_error *err)
{
    lf_model *m;

    if (type == NULL) {
        lf_fail(err, LF_EINVAL, "no model given");
        return NULL;
    }
    if (lf_probe_check(probe, err) != LF_OK)
        return NULL;
    m = calloc(1, sizeof *m);
    if (m == NULL) {
        lf_fail(err, LF_ENOMEM, "out of memory allocating a model");
        return NULL;
    }
    m->type = type;
    m->probe = *probe;
    if (type->alloc != NULL && type->alloc(&m->state, probe, err) != LF_OK) {
        lf_model_free(m);
        return NULL;
    }
    return m;
}

void
lf_model_free(lf_model *m)
{
    if (m == NULL)
        return;
    if (m->type->free != NULL && m->state != NULL)
        m->type->free(m->state);
    free(m);
}

const lf_model_type *
lf_model_get_type(const lf_model *m)
{
    return m->type;
}

const lf_probe *
lf_model_get_probe(const lf_model *m)
{
    return &m->probe;
}

/* mat checked, and within the model's range of nu for a bonded layer. */
static int
material_in(const lf_model *m, const lf_material *mat, lf_error *err)
{
    int status = lf_material_check(mat, m->probe.base, err);

    if (status == LF_OK && m->probe.base == LF_BASE_BONDED && m->type->nu_max > 0
        && mat->nu > m->type->nu_max)
        return lf_fail(err, LF_EINVAL, "model %s: nu must be <= %g for a bonded layer (got %g)",
                       m->type->name, m->type->nu_max, mat->nu);
    return status;
}

/* An evaluation's arguments checked: mat (material_in) and every
 * indentation finite. */
static int
eval_args_in(const lf_model *m, const lf_material *mat, size_t n, const double *delta,
             lf_error *err)
{
    size_t i;
    int status = material_in(m, mat, err);

    if (status != LF_OK)
        return status;
    for (i = 0; i < n; i++)
        if (!isfinite(delta[i]))
            return lf_fail(err, LF_EINVAL, "indentation %zu is not finite", i);
    return LF_OK;
}

int
lf_model_eval(const lf_model *m, const lf_material *mat, lf_branch branch,
              size_t n, const double *delta, lf_eval *out, lf_error *err)
{
    int status = eval_args_in(m, mat, n, delta, err);

    if (status != LF_OK)
        return status;
    status = m->type->eval(m->state, &m->probe, mat, branch, n, delta, out);
    if (status != LF_OK)
        return lf_fail(err, status, "model %s failed to evaluate", m->type->name);
    return LF_OK;
}

int
lf_model_eval_roots(const lf_model *m, const lf_material *mat, lf_branch branch,
                    size_t n, const double *delta, lf_eval *out, double *roots)
{
    int status;

    if (m->type != &lf_model_exact || roots == NULL)
        return lf_model_eval(m, mat, branch, n, delta, out, NULL);
    status = eval_args_in(m, mat, n, delta, NULL);
    if (status != LF_OK)
        return status;
    return lf_exact_eval_warm(m->state, &m->probe, mat, branch, n, delta, out, roots);
}

int
lf_model_pulloff(const lf_model *m, const lf_material *mat, lf_pulloff *out,
                 lf_error *err)
{
    int status = material_in(m, mat, err);

    if (status != LF_OK)
        return status;
    status = m->type->pulloff(m->state, &m->probe, mat, out);
    if (status != LF_OK)
        return lf_fail(err, status, "model %s: no pull-off", m->type->name);
    return LF_OK;
}

int
lf_model_prepare(lf_model *m, double nu_lo, double nu_hi, lf_error *err)
{
    if (!(nu_lo <= nu_hi))
        return lf_fail(err, LF_EINVAL, "nu range [%g, %g] is empty", nu_lo, nu_hi);
    if (m->type->prepare == NULL || m->probe.base != LF_BASE_BONDED)
        return LF_OK;
    return m->type->prepare(m->state, &m->probe, nu_lo, nu_hi, err);
}

/* ---------------------------------------------------------------------
 * Where a model can be evaluated.  Each model computes in SI, with powers
 * of k of the lengths (b^k, R^(k-1), k^((k+2)/k)): far enough from k = 2,
 * or with lengths far from the micrometre, these leave double precision
 * and the model's numbers become 0, inf or NaN.  Rather than bounds on k,
 * R and b that would hold for one model and not another, the model is
 * tried where a curve lives, from detachment over ten pull-off widths as
 * `layerfit model` draws it: the pull-off and 16 points of the unloading
 * branch must be finite, an adhesive material must pull off (P_po < 0 at
 * a_po > 0), and the deepest point must press (P > 0).
 * ------------------------------------------------------------------- */

#define REGION_POINTS 16

#define LEAVES_DOUBLE "its numbers leave double precision for these k, R and b"

static int
region_fail(const lf_model *m, const lf_material *mat, lf_error *err, const char *why,
            double at)
{
    char where[64] = "", b[48] = "", shape[64];

    if (!isnan(at))
        snprintf(where, sizeof where, " at an indentation of %.4g m", at);
    if (m->type->scope != LF_SCOPE_HALFSPACE)
        snprintf(b, sizeof b, ", b = %g m", m->probe.b);
    if (lf_probe_uses_R(&m->probe))
        snprintf(shape, sizeof shape, "R = %g m", m->probe.R);
    else        /* a cone's or a stated B's R shapes nothing */
        snprintf(shape, sizeof shape, "B = %g m^%g", lf_probe_prefactor(&m->probe),
                 1.0 - m->probe.k);
    return lf_fail(err, LF_EINVAL, "model %s cannot be evaluated at k = %g, %s%s "
                   "(w = %g J/m^2, E* = %g Pa): %s%s", m->type->name, m->probe.k, shape,
                   b, mat->w, mat->Estar, why, where);
}

int
lf_model_check_region(const lf_model *m, const lf_material *mat, lf_error *err)
{
    lf_pulloff po;
    lf_eval e[REGION_POINTS];
    double delta[REGION_POINTS], span, scale;
    size_t i;
    int status;

    if ((status = lf_model_pulloff(m, mat, &po, err)) != LF_OK)
        return status;
    if (!(isfinite(po.delta_detach) && isfinite(po.P_detach) && isfinite(po.a_detach)
          && isfinite(po.delta_po) && isfinite(po.P_po) && isfinite(po.a_po)
          && isfinite(po.sigma_po) && isfinite(po.P_jump) && isfinite(po.c)))
        return region_fail(m, mat, err, "its pull-off is not a finite number: " LEAVES_DOUBLE,
                           NAN);
    if (mat->w > 0 && !(po.P_po < 0 && po.a_po > 0))
        return region_fail(m, mat, err, "it finds no pull-off for an adhesive material (no "
                           "stable adhesive branch, or " LEAVES_DOUBLE ")", NAN);
    span = fmax(fabs(po.delta_po - po.delta_detach), fabs(po.delta_detach));
    /* without adhesion the curve starts at 0: a thousandth of the layer
     * (of R for a half-space) */
    scale = m->type->scope == LF_SCOPE_HALFSPACE ? lf_probe_length(&m->probe)
                                                 : fmin(m->probe.b, lf_probe_length(&m->probe));
    if (!(span > 0))
        span = 1e-4 * scale;
    for (i = 0; i < REGION_POINTS; i++)
        delta[i] = po.delta_detach + 10.0 * span * (double) (i + 1) / REGION_POINTS;
    if ((status = lf_model_eval(m, mat, LF_BRANCH_UNLOAD, REGION_POINTS, delta, e, err)) != LF_OK)
        return status;
    for (i = 0; i < REGION_POINTS; i++)
        if (!(isfinite(e[i].P) && isfinite(e[i].a) && isfinite(e[i].dP_ddelta)
              && isfinite(e[i].dP_dlogw) && isfinite(e[i].dP_dlogE) && isfinite(e[i].dP_dnu)))
            return region_fail(m, mat, err, "its force is not a finite number: " LEAVES_DOUBLE,
                               delta[i]);
    if (!(e[REGION_POINTS - 1].P > 0 && e[REGION_POINTS - 1].a > 0))
        return region_fail(m, mat, err, "it gives no compressive force: " LEAVES_DOUBLE,
                           delta[REGION_POINTS - 1]);
    return LF_OK;
}

int
lf_model_check_probe(const lf_model_type *type, const lf_probe *probe, lf_error *err)
{
    const lf_material paper = { 0.01, 1e9, 0.3 };
    lf_model *m = lf_model_alloc(type, probe, err);
    int status;

    if (m == NULL)
        return err != NULL && err->status != LF_OK ? err->status : LF_EINVAL;
    status = lf_model_check_region(m, &paper, err);
    lf_model_free(m);
    return status;
}

double
lf_jkr_sphere_a_po(double R, double w, double Estar)
{
    return cbrt(9.0 * M_PI * R * R * w / (8.0 * Estar));
}

const char *
lf_thin_scope(double b_over_a, double limit)
{
    if (!(b_over_a > limit))
        return NULL;
    return b_over_a < 1.0 ? "the thin-layer assumption b << a is strained"
                          : "the thin-layer model does not apply: it assumes b << a, and at b = a "
                            "its force is already off by a quarter to a factor 5; the exact model "
                            "covers any b";
}
