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

/* The material parameters' JSON keys, in the order LF_MAT_W, _E, _NU. */
static const char *const mat_key[3] = { "w", "Estar", "nu" };

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

/* A range as stated: {"lo": .., "hi": .., "relative": ..}, or null. */
static void
jrange(lf_str *b, const lf_range *r)
{
    if (isnan(r->lo) && isnan(r->hi)) {
        lf_str_puts(b, "null");
        return;
    }
    lf_str_puts(b, "{\"lo\": ");
    jnum(b, r->lo);
    lf_str_puts(b, ", \"hi\": ");
    jnum(b, r->hi);
    lf_str_printf(b, ", \"relative\": %s}", r->relative ? "true" : "false");
}

/* ", "window": {...}" of a curve: the window as stated (relative: as
 * fractions) and as placed on the curve's depth and force (open: null),
 * the points kept; null when it keeps everything. */
static void
jwindow(lf_str *b, const lf_window_placed *w)
{
    const struct { const char *key; double v; } num[] = {
        { "depth_lo_m", w->depth_lo }, { "depth_hi_m", w->depth_hi },
        { "force_lo_N", w->force_lo }, { "force_hi_N", w->force_hi },
    };
    size_t i;

    lf_str_puts(b, ",\n     \"window\": ");
    if (!w->active) {
        lf_str_puts(b, "null");
        return;
    }
    lf_str_puts(b, "{\"depth_range\": ");
    jrange(b, &w->window.depth);
    lf_str_puts(b, ", \"force_range\": ");
    jrange(b, &w->window.force);
    for (i = 0; i < sizeof num / sizeof num[0]; i++) {
        lf_str_printf(b, ", \"%s\": ", num[i].key);
        jnum(b, num[i].v);          /* an open side (infinite) is null */
    }
    lf_str_printf(b, ", \"points_kept\": %zu, \"points\": %zu}", w->n_kept, w->n_in);
}

static void
jcurve(lf_str *b, const lf_report_info *in, const lf_fit_result *r, size_t j)
{
    const lf_fit_curve_result *c = &r->curves[j];
    int nolayer = no_layer(in, r, j);
    int po = c->pulloff_determined;
    const struct { const char *key; double v; } num[] = {
        { "k", c->probe.k }, { "R", lf_probe_uses_R(&c->probe) ? c->probe.R : NAN },
        { "b", nolayer ? NAN : c->probe.b },
        { "B", lf_probe_prefactor(&c->probe) },
        { "half_angle_rad", c->probe.tip == LF_TIP_CONE || c->probe.tip == LF_TIP_PYRAMID
                            ? c->probe.angle : NAN },
        { "cone_half_angle_rad", lf_probe_cone_angle(&c->probe) },
        { "z0", c->z0 }, { "z0_stderr", c->z0_se }, { "F0", c->F0 },
        { "F0_stderr", c->F0_se }, { "noise_sigma", c->sigma },
        { "quantum_N", c->quantum > 0 ? c->quantum : NAN }, { "rms", c->rms },
        { "P_po", po ? c->pulloff.P_po : NAN }, { "a_po", po ? c->pulloff.a_po : NAN },
        { "sigma_po", po ? c->pulloff.sigma_po : NAN },
        { "b_over_a_min_contact", nolayer ? NAN : c->b_over_a_min_contact },
        { "b_over_a_pulloff", nolayer || !po ? NAN : c->b_over_a_pulloff },
        { "chi2_per_point", c->chi2_per_point }, { "p_value", c->p_value },
        { "runs_z", c->runs_z }, { "corr_time", c->corr_time }, { "n_eff", c->n_eff },
        { "noise_sd", c->noise_sd }, { "misfit_rel", c->misfit_rel }, { "shape", c->shape }
    };
    size_t i;

    lf_str_puts(b, "    {");
    lf_str_json_name(b, "file", c->name);
    for (i = 0; i < sizeof num / sizeof num[0]; i++) {
        lf_str_printf(b, ", \"%s\": ", num[i].key);
        jnum(b, num[i].v);
    }
    lf_str_puts(b, ",\n     \"tip\": ");
    lf_str_json(b, lf_tip_name(c->probe.tip));
    lf_str_puts(b, ", \"interface\": ");
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
    if (c->model_by_group)      /* a batch's curve decided with its group */
        lf_str_puts(b, ", \"model_decided_by\": \"group\"");
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
    lf_str_puts(b, ",\n     \"alone\": {");
    for (i = 0; i < 3; i++) {       /* LF_MAT_W, LF_MAT_E, LF_MAT_NU */
        lf_str_printf(b, "%s\"%s\": ", i ? ", " : "", mat_key[i]);
        jnum(b, c->alone.value[i]);
        lf_str_printf(b, ", \"%s_stderr\": ", mat_key[i]);
        jnum(b, c->alone.se[i]);
    }
    lf_str_puts(b, "}");
    if (in->observed != NULL) {  /* what the curve shows without a model */
        double v[LF_NOBSERVED];
        lf_observed_values(&in->observed[j], v);
        for (i = 0; i < LF_NOBSERVED; i++) {
            lf_str_printf(b, "%s\"%s\": ", i == 0 ? ",\n     " : ", ", lf_observed_keys[i]);
            jnum(b, v[i]);
        }
        lf_str_puts(b, ", \"instrument_model\": ");
        lf_str_json_or_null(b, in->observed[j].instrument_model[0]
                               ? in->observed[j].instrument_model : NULL);
        lf_str_puts(b, ", \"contact_point_method\": ");
        lf_str_json(b, LF_CONTACT_METHOD);
    }
    if (in->window != NULL)
        jwindow(b, &in->window[j]);
    lf_str_puts(b, ", \"warnings\": ");
    jwarnings(b, &c->warnings);
    lf_str_printf(b, "}%s\n", j + 1 < r->ncurves ? "," : "");
}

/* [lo, hi] */
static void
jpair(lf_str *b, const double x[2])
{
    lf_str_puts(b, "[");
    jnum(b, x[0]);
    lf_str_puts(b, ", ");
    jnum(b, x[1]);
    lf_str_puts(b, "]");
}

static void
jpopulation(lf_str *b, const char *key, const lf_population_estimate *e, const char *indent,
            int last)
{
    const struct { const char *key; double v; } num[] = {
        { "mean", e->mean }, { "sd", e->sd }, { "median", e->median }, { "q1", e->q1 },
        { "q3", e->q3 }, { "Q", e->Q }, { "p_homogeneous", e->p_homogeneous }, { "I2", e->I2 },
        { "tau", e->tau }, { "tau_rel", e->tau_rel }, { "population_mean", e->population_mean },
    };
    const struct { const char *key; const double *v; } pair[] = {
        { "tau_ci95", e->tau_ci95 }, { "tau_rel_ci95", e->tau_rel_ci95 },
        { "population_ci95", e->population_ci95 },
    };
    size_t i;

    lf_str_printf(b, "%s    \"%s\": {\"n\": %zu", indent, key, e->n);
    for (i = 0; i < sizeof num / sizeof num[0]; i++) {
        lf_str_printf(b, ", \"%s\": ", num[i].key);
        jnum(b, num[i].v);
    }
    for (i = 0; i < sizeof pair / sizeof pair[0]; i++) {
        lf_str_printf(b, ", \"%s\": ", pair[i].key);
        jpair(b, pair[i].v);
    }
    lf_str_puts(b, ", \"why_not_determined\": ");
    lf_str_json_or_null(b, e->why);
    lf_str_printf(b, "}%s\n", last ? "" : ",");
}

/* The object "heterogeneity" (the fit's, a batch summary's groups'). */
static void
jheterogeneity(lf_str *b, const lf_heterogeneity *h, const char *indent)
{
    const struct { const char *key; double v; } num[] = {
        { "p_homogeneous", h->p_homogeneous }, { "I2", h->I2 }, { "Q", h->Q }, { "df", h->df }
    };
    size_t i;

    lf_str_printf(b, "{\"curves\": %zu", h->curves);
    for (i = 0; i < sizeof num / sizeof num[0]; i++) {
        lf_str_printf(b, ", \"%s\": ", num[i].key);
        jnum(b, num[i].v);
    }
    lf_str_printf(b, ",\n%s  \"parameters\": {\n", indent);
    jpopulation(b, mat_key[LF_MAT_W], &h->w, indent, 0);
    jpopulation(b, mat_key[LF_MAT_E], &h->Estar, indent, 0);
    jpopulation(b, mat_key[LF_MAT_NU], &h->nu, indent, 1);
    lf_str_printf(b, "%s  },\n%s  \"probes\": {\"count\": %zu, \"tested\": %zu, \"p\": ",
                  indent, indent, h->probes, h->probes_tested);
    jnum(b, h->probes_p);
    lf_str_printf(b, ", \"disagree\": %s, \"departs\": ", h->probes_disagree ? "true" : "false");
    if (h->probes_disagree) {
        const struct { const char *key; double v; } at[] = {
            { "k", h->probe_departs.k }, { "R", h->probe_departs.R }, { "b", h->probe_departs.b }
        };
        for (i = 0; i < sizeof at / sizeof at[0]; i++) {
            lf_str_printf(b, "%s\"%s\": ", i ? ", " : "{", at[i].key);
            jnum(b, at[i].v);
        }
        lf_str_puts(b, ", \"interface\": ");
        lf_str_json(b, base_name(h->probe_departs.base));
        lf_str_puts(b, ", \"parameter\": ");
        lf_str_json(b, h->probe_param >= 0 ? mat_key[h->probe_param] : "");
        lf_str_puts(b, ", \"difference\": ");
        jnum(b, h->probe_diff);
        lf_str_puts(b, ", \"z\": ");
        jnum(b, h->probe_z);
        lf_str_puts(b, "}");
    } else {
        lf_str_puts(b, "null");
    }
    lf_str_printf(b, "}\n%s}", indent);
}

char *
lf_heterogeneity_json(const lf_heterogeneity *h, const char *indent)
{
    lf_str b = { NULL, 0, 0, 0 };
    char *out;

    jheterogeneity(&b, h, indent);
    return lf_str_take(&b, &out, NULL) == LF_OK ? out : NULL;
}

/* "assumed": what the fit held or read rather than fitted. */
static void
jassumed(lf_str *b, const lf_report_info *in)
{
    size_t i;

    lf_str_puts(b, "  \"assumed\": [");
    for (i = 0; i < in->nassumed; i++) {
        const lf_assumption *a = &in->assumed[i];
        lf_str_printf(b, "%s\n    {\"parameter\": ", i ? "," : "");
        lf_str_json(b, a->name);
        lf_str_puts(b, ", \"value\": ");
        jnum(b, a->value);
        lf_str_puts(b, ", \"unit\": ");
        lf_str_json(b, a->unit);
        if (a->first == 0)
            lf_str_puts(b, ", \"curves\": null");
        else
            lf_str_printf(b, ", \"curves\": [%zu, %zu]", a->first, a->last);
        lf_str_puts(b, ", \"source\": ");
        lf_str_json(b, a->source);
        lf_str_puts(b, "}");
    }
    lf_str_printf(b, "%s],\n", in->nassumed ? "\n  " : "");
}

int
lf_fit_result_json(const lf_fit_result *r, const lf_report_info *info, char **json,
                   lf_error *err)
{
    static const lf_report_info none = { NULL, NAN, NULL, NULL, NULL, 0, NULL, NULL };
    const lf_report_info *in = info != NULL ? info : &none;
    lf_str b = { NULL, 0, 0, 0 };
    size_t i, j;

    lf_str_puts(&b, "{\n");
    jassumed(&b, in);
    lf_str_puts(&b, "  \"heterogeneity\": ");
    jheterogeneity(&b, &r->heterogeneity, "  ");
    lf_str_puts(&b, ",\n  \"parameters\": {\n");
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
        size_t k;
        lf_str_puts(&b, i ? ",\n    " : "\n    ");
        lf_str_puts(&b, "[");
        for (k = 0; k < r->npar; k++) {
            lf_str_puts(&b, k ? ", " : "");
            jnum(&b, lf_fit_result_cov(r, i, k));
        }
        lf_str_puts(&b, "]");
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
