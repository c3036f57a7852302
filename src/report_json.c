/* report_json.c: a fit result as JSON (SI, numbers that read back exactly,
 * NaN as null): the document `layerfit fit --json` writes and a binding's
 * to_dict() reads, one writer for both.  See lf_fit_result_json in
 * layerfit.h. */
#include <math.h>
#include <stdlib.h>

#include "internal.h"

static const char *
branch_name(lf_branch b)
{
    return b == LF_BRANCH_LOAD ? "load" : "unload";
}

static const char *
base_name(lf_base base)
{
    return base == LF_BASE_BONDED ? "bonded" : "frictionless";
}

/* Curve j has no layer: none given (b a stand-in), or its model (the
 * half-space) uses none. */
static int
no_layer(const lf_report_info *in, const lf_fit_result *r, size_t j)
{
    const lf_model_type *t = r->curves[j].model != NULL ? lf_model_type_find(r->curves[j].model)
                                                        : NULL;
    return (t != NULL && t->scope == LF_SCOPE_HALFSPACE)
           || (in->origin != NULL && in->origin[j].b == NULL);
}

static void
jnum(lf_str *b, double x)
{
    lf_str_number(b, x, "null");
}

/* A JSON array of n numbers. */
static void
jnums(lf_str *b, const double *x, size_t n)
{
    size_t i;
    lf_str_puts(b, "[");
    for (i = 0; i < n; i++) {
        lf_str_puts(b, i ? ", " : "");
        jnum(b, x[i]);
    }
    lf_str_puts(b, "]");
}

static void
jwarnings(lf_str *b, const lf_warnings *w)
{
    size_t i;
    lf_str_puts(b, "[");
    for (i = 0; i < w->n; i++) {
        if (i)
            lf_str_puts(b, ", ");
        lf_str_json(b, w->msg[i]);
    }
    lf_str_puts(b, "]");
}

static void
jestimate(lf_str *b, const char *name, const lf_fit_estimate *e, int last)
{
    lf_str_printf(b, "    \"%s\": {\"value\": ", name);
    jnum(b, e->value);
    lf_str_puts(b, ", \"stderr\": ");
    jnum(b, e->se);
    lf_str_puts(b, ", \"ci95\": [");
    jnum(b, e->ci95[0]);
    lf_str_puts(b, ", ");
    jnum(b, e->ci95[1]);
    lf_str_puts(b, "], \"ci95_method\": ");
    lf_str_json_or_null(b, lf_interval_method(e));
    lf_str_printf(b, ", \"free\": %s, \"determined\": %s, \"upper_bound_only\": %s",
                  e->free ? "true" : "false", e->determined ? "true" : "false",
                  e->upper_bound_only ? "true" : "false");
    if (e->why != NULL) {
        lf_str_puts(b, ", \"why_not_determined\": ");
        lf_str_json(b, e->why);
    }
    lf_str_printf(b, "}%s\n", last ? "" : ",");
}

static void
jcurve(lf_str *b, const lf_report_info *in, const lf_fit_result *r, size_t j)
{
    const lf_fit_curve_result *c = &r->curves[j];
    int nolayer = no_layer(in, r, j);
    int po = c->pulloff_determined;
    const struct { const char *key; double v; } num[] = {
        { "k", c->probe.k }, { "R", c->probe.R },
        { "b", nolayer ? NAN : c->probe.b },
        { "z0", c->z0 }, { "z0_stderr", c->z0_se }, { "F0", c->F0 },
        { "F0_stderr", c->F0_se }, { "noise_sigma", c->sigma }, { "rms", c->rms },
        { "P_po", po ? c->pulloff.P_po : NAN }, { "a_po", po ? c->pulloff.a_po : NAN },
        { "sigma_po", po ? c->pulloff.sigma_po : NAN },
        { "b_over_a_min_contact", nolayer ? NAN : c->b_over_a_min_contact },
        { "b_over_a_pulloff", nolayer || !po ? NAN : c->b_over_a_pulloff },
        { "chi2_per_point", c->chi2_per_point }, { "p_value", c->p_value },
        { "runs_z", c->runs_z }, { "corr_time", c->corr_time }, { "n_eff", c->n_eff },
        { "noise_sd", c->noise_sd }, { "misfit_rel", c->misfit_rel }
    };
    size_t i;

    lf_str_puts(b, "    {");
    lf_str_json_name(b, "file", c->name);
    for (i = 0; i < sizeof num / sizeof num[0]; i++) {
        lf_str_printf(b, ", \"%s\": ", num[i].key);
        jnum(b, num[i].v);
    }
    lf_str_puts(b, ",\n     \"interface\": ");
    lf_str_json_or_null(b, nolayer ? NULL : base_name(c->probe.base));
    lf_str_printf(b, ", \"branch\": \"%s\", \"points\": %zu, "
                  "\"z0_free\": %s, \"F0_free\": %s, \"consistent\": %s, \"downweighted\": %zu",
                  branch_name(c->branch), c->n,
                  c->z0_free ? "true" : "false", c->F0_free ? "true" : "false",
                  c->consistent ? "true" : "false", c->downweighted);
    lf_str_printf(b, ", \"agreement\": \"%s\"", c->agreement == 2 ? "within the noise"
                  : c->agreement == 1 ? "systematic deviations" : "disagrees");
    lf_str_puts(b, ",\n     \"model\": ");
    lf_str_json(b, c->model);
    lf_str_puts(b, ", \"model_reason\": ");
    lf_str_json(b, c->model_reason);
    lf_str_puts(b, ", \"thin_bias_in_se\": ");
    jnum(b, c->thin_bias);
    if (in->origin != NULL) {   /* where R, b and the AFM constants came from */
        const lf_curve_origin *o = &in->origin[j];
        const struct { const char *key, *s; int num; double v; } src[] = {
            { "R_source", o->R, 0, 0 }, { "b_source", nolayer ? NULL : o->b, 0, 0 },
            { "spring_constant", NULL, 1, o->spring_constant },
            { "spring_constant_source", o->spring_constant_source, 0, 0 },
            { "sensitivity", NULL, 1, o->sensitivity },
            { "sensitivity_unit", o->sensitivity_source ? o->sensitivity_unit : NULL, 0, 0 },
            { "sensitivity_source", o->sensitivity_source, 0, 0 },
        };
        for (i = 0; i < sizeof src / sizeof src[0]; i++) {
            lf_str_printf(b, "%s\"%s\": ", i == 0 ? ",\n     " : ", ", src[i].key);
            if (src[i].num)
                jnum(b, src[i].v);
            else
                lf_str_json_or_null(b, src[i].s);
        }
    }
    lf_str_puts(b, ", \"warnings\": ");
    jwarnings(b, &c->warnings);
    lf_str_printf(b, "}%s\n", j + 1 < r->ncurves ? "," : "");
}

int
lf_fit_result_json(const lf_fit_result *r, const lf_report_info *info, char **json,
                   lf_error *err)
{
    static const lf_report_info none = { NULL, NAN, NULL, NULL };
    const lf_report_info *in = info != NULL ? info : &none;
    lf_str b = { NULL, 0, 0, 0 };
    size_t i, j;

    lf_str_puts(&b, "{\n  \"parameters\": {\n");
    jestimate(&b, "w", &r->w, 0);
    jestimate(&b, "Estar", &r->Estar, 0);
    jestimate(&b, "nu", &r->nu, 0);
    jestimate(&b, "M", &r->M, 1);
    lf_str_puts(&b, "  },\n  \"fit\": {\"chi2\": ");
    jnum(&b, r->chi2);
    lf_str_printf(&b, ", \"dof\": %zu, \"se_scale\": ", r->dof);
    jnum(&b, r->se_scale);
    lf_str_printf(&b, ", \"iterations\": %zu, \"evaluations\": %zu, \"converged\": %s, \"stop\": ",
                  r->iterations, r->evaluations, r->converged ? "true" : "false");
    lf_str_json(&b, lf_fit_stop_name(r->stop));
    lf_str_puts(&b, ", \"stop_reason\": ");
    lf_str_json(&b, r->stop_reason);
    lf_str_puts(&b, ", \"method\": ");
    lf_str_json(&b, r->method);
    lf_str_puts(&b, ", \"loss\": ");
    lf_str_json(&b, r->loss);
    lf_str_puts(&b, ", \"model\": ");
    lf_str_json(&b, r->model);
    lf_str_puts(&b, ", \"model_request\": ");
    lf_str_json(&b, in->model_request ? in->model_request : r->model);
    lf_str_printf(&b, ", \"model_rounds\": %zu, \"model_tol\": ", r->model_rounds);
    jnum(&b, in->model_tol);
    lf_str_puts(&b, "},\n  \"thin_comparison\": ");
    if (r->thin.done) {
        lf_str_puts(&b, "{\n");
        jestimate(&b, "w", &r->thin.w, 0);
        jestimate(&b, "Estar", &r->thin.Estar, 0);
        jestimate(&b, "nu", &r->thin.nu, 0);
        lf_str_puts(&b, "    \"w_rel_diff\": ");
        jnum(&b, r->thin.w_rel);
        lf_str_puts(&b, ", \"Estar_rel_diff\": ");
        jnum(&b, r->thin.Estar_rel);
        lf_str_puts(&b, ", \"nu_diff\": ");
        jnum(&b, r->thin.nu_diff);
        lf_str_puts(&b, ", \"w_diff_in_se\": ");
        jnum(&b, r->thin.w_in_se);
        lf_str_puts(&b, ", \"chi2\": ");
        jnum(&b, r->thin.chi2);
        lf_str_printf(&b, ", \"converged\": %s\n  }", r->thin.converged ? "true" : "false");
    } else {
        lf_str_puts(&b, "null");
    }
    lf_str_puts(&b, ",\n  \"free_parameters\": [");
    for (i = 0; i < r->npar; i++) {
        lf_str_puts(&b, i ? ", " : "");
        lf_str_json(&b, r->names[i]);
    }
    lf_str_puts(&b, "],\n  \"values\": ");
    jnums(&b, r->value, r->npar);
    lf_str_puts(&b, ",\n  \"covariance\": [");
    for (i = 0; i < r->npar; i++) {
        lf_str_puts(&b, i ? ",\n    " : "\n    ");
        jnums(&b, r->cov + i * r->npar, r->npar);
    }
    lf_str_puts(&b, "],\n  \"singular_values\": ");
    jnums(&b, r->singular, r->npar);
    lf_str_puts(&b, ",\n  \"curves\": [\n");
    for (j = 0; j < r->ncurves; j++)
        jcurve(&b, in, r, j);
    lf_str_puts(&b, "  ],\n  \"identifiability\": ");
    jwarnings(&b, &r->identifiability);
    lf_str_puts(&b, ",\n  \"warnings\": ");
    jwarnings(&b, &r->warnings);
    if (in->provenance != NULL) {
        lf_str_puts(&b, ",\n  \"provenance\": ");
        lf_str_provenance(&b, "  ", in->provenance);
    }
    lf_str_puts(&b, "\n}\n");
    return lf_str_take(&b, json, err);
}
