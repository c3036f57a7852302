/* fit_figure.c: what the figures of a fit draw, for `layerfit fit --plot`
 * and a binding's plot alike: each curve's fitted model on a grid of
 * depths in instrument coordinates, classed out of contact, stable or
 * unstable under force control (after the seed paper's Fig. 3), with the
 * pull-off point and the offsets it is drawn with (lf_fit_figure_curve in
 * layerfit.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "internal.h"

double
lf_fit_result_value(const lf_fit_result *res, const char *name)
{
    size_t i;

    for (i = 0; i < res->npar; i++)
        if (strcmp(res->names[i], name) == 0)
            return res->value[i];
    return NAN;
}

/* Curve j's offset or slope (what: "z0", "F0", "s") to draw with: the
 * reported one, else where the fit ended (the report gives no number for
 * what the data do not determine), else 0 (none fitted). */
static double
at_end(const lf_fit_result *res, const char *what, size_t j, double reported)
{
    char name[32];
    double v;

    if (isfinite(reported))
        return reported;
    snprintf(name, sizeof name, "%s[%zu]", what, j + 1);
    v = lf_fit_result_value(res, name);
    return isfinite(v) ? v : 0.0;
}

/* The material to draw with: the fitted one; where E* is not determined
 * (bonded curves alone fix only M = Z E*), E* = M with nu = 0 (Z = 1) draws
 * the same thin-layer curve; a w the data do not determine is drawn where
 * the fit ended (the curve it fitted; titles say "not determined"). */
static int
draw_material(const lf_fit_result *res, lf_material *m)
{
    m->w = isfinite(res->w.value) ? res->w.value : lf_fit_result_value(res, "w");
    m->Estar = res->Estar.value;
    m->nu = isfinite(res->nu.value) ? res->nu.value : 0.3;
    if (!isfinite(m->Estar) && isfinite(res->M.value)) {
        m->Estar = res->M.value;
        m->nu = 0.0;
    }
    if (!isfinite(m->w) && res->w.upper_bound_only)
        m->w = 0.0;
    return isfinite(m->w) && isfinite(m->Estar) ? 0 : -1;
}

int
lf_fit_figure_curve(const lf_fit_result *res, size_t j, const lf_fit_curve *c, size_t n,
                    double *z, double *F, int *cls, lf_fit_figure *out, lf_error *err)
{
    const lf_fit_curve_result *cr;
    const lf_model_type *type;
    lf_material mat;
    lf_model *model;
    lf_eval *ev;
    double lo = INFINITY, hi = -INFINITY, s;
    size_t i;
    int status;

    if (j >= res->ncurves || n == 1)
        return lf_fail(err, LF_EINVAL, "curve %zu of %zu, %zu points", j + 1, res->ncurves, n);
    cr = &res->curves[j];
    out->z0 = at_end(res, "z0", j, cr->z0);
    out->F0 = at_end(res, "F0", j, cr->F0);
    out->slope = at_end(res, "s", j, cr->slope);
    out->z_po = out->F_po = NAN;
    out->delta_detach = cr->pulloff.delta_detach;
    out->delta_po = cr->pulloff.delta_po;
    out->have = 0;
    s = isfinite(out->slope) ? out->slope : 0.0;
    if (n == 0)
        return LF_OK;
    /* each curve's own model (under --model auto the fit's is "mixed") */
    type = lf_model_type_find(cr->model != NULL ? cr->model : res->model ? res->model : "thin");
    if (type == NULL || draw_material(res, &mat) != 0)
        return LF_OK;
    if ((model = lf_model_alloc(type, &c->probe, err)) == NULL)
        return LF_OK;
    for (i = 0; i < c->n; i++) {
        double d = c->depth[i] - out->z0;
        lo = fmin(lo, d);
        hi = fmax(hi, d);
    }
    if (cr->branch == LF_BRANCH_UNLOAD && isfinite(cr->pulloff.delta_detach))
        lo = fmin(lo, cr->pulloff.delta_detach - 0.05 * (hi - cr->pulloff.delta_detach));
    if ((ev = malloc(n * sizeof *ev)) == NULL) {
        lf_model_free(model);
        return lf_fail(err, LF_ENOMEM, "out of memory");
    }
    for (i = 0; i < n; i++)
        z[i] = lo + (hi - lo) * (double) i / (double) (n - 1);     /* delta, for now */
    status = hi > lo ? lf_model_eval(model, &mat, cr->branch, n, z, ev, err) : LF_EINVAL;
    lf_model_free(model);
    if (status != LF_OK) {
        free(ev);
        return LF_OK;
    }
    for (i = 0; i < n; i++) {
        F[i] = ev[i].P + out->F0 + s * z[i];
        cls[i] = ev[i].a <= 0.0 ? 0 : ev[i].dP_ddelta > 0.0 ? 1 : 2;
        z[i] += out->z0;
    }
    free(ev);
    if (cr->branch == LF_BRANCH_UNLOAD && cr->pulloff_determined && isfinite(cr->pulloff.P_po)) {
        out->z_po = cr->pulloff.delta_po + out->z0;
        out->F_po = cr->pulloff.P_po + out->F0 + s * cr->pulloff.delta_po;
    }
    out->have = 1;
    return LF_OK;
}

int
lf_fit_job_figure(const lf_fit_job *j, size_t i, size_t n, double *z, double *F, int *cls,
                  lf_fit_figure *out, lf_error *err)
{
    const lf_fit_input *in = lf_fit_job_input(j);

    if (i >= in->n)
        return lf_fail(err, LF_EINVAL, "curve %zu of %zu", i + 1, in->n);
    return lf_fit_figure_curve(lf_fit_job_result(j), i, &in->curves[i], n, z, F, cls, out, err);
}
