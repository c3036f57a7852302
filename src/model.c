/* model.c: the table of forward models, their shared domain checks and the
 * lf_model object that binds a model to one probe. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

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

int
lf_model_eval(const lf_model *m, const lf_material *mat, lf_branch branch,
              size_t n, const double *delta, lf_eval *out, lf_error *err)
{
    size_t i;
    int status = material_in(m, mat, err);

    if (status != LF_OK)
        return status;
    for (i = 0; i < n; i++)
        if (!isfinite(delta[i]))
            return lf_fail(err, LF_EINVAL, "indentation %zu is not finite", i);
    status = m->type->eval(m->state, &m->probe, mat, branch, n, delta, out);
    if (status != LF_OK)
        return lf_fail(err, status, "model %s failed to evaluate", m->type->name);
    return LF_OK;
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
