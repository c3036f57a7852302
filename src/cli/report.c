/* report.c: a fit result as text for people, as JSON (SI) and as a
 * per-point CSV.  See report.h. */
#include <math.h>
#include <string.h>

#include "cli.h"
#include "report.h"

static const char *
branch_name(lf_branch b)
{
    return b == LF_BRANCH_LOAD ? "load" : "unload";
}

static void
text_estimate(FILE *f, const char *name, const lf_fit_estimate *e, const char *unit)
{
    char v[48], s[48], lo[48], hi[48];
    const char *words;

    if (e->upper_bound_only && isfinite(e->ci95[1])) {
        fprintf(f, "  %-4s < %s (95%%, one-sided): adhesion below the noise\n", name,
                cli_human(hi, sizeof hi, e->ci95[1], unit));
        return;
    }
    if ((words = cli_bound_text(e, name, unit, lo, sizeof lo)) != NULL) {
        if (words[0] == '\0')
            fprintf(f, "  %-4s not determined: the data do not bound it (its profile likelihood "
                    "stays below the 95%% threshold over the whole range searched)\n", name);
        else
            fprintf(f, "  %-4s not determined: the data bound it only from %s, %s "
                    "(95%%, profile likelihood)\n", name,
                    isfinite(e->ci95[0]) ? "below" : "above", words);
        return;
    }
    if (!e->determined) {       /* why: the judgement's (fit/judge.c) */
        fprintf(f, "  %-4s not determined%s%s\n", name, e->why ? ": " : "", e->why ? e->why : "");
        return;
    }
    if (!e->free) {
        if (unit[0] == '\0')
            fprintf(f, "  %-4s = %.4g (fixed)\n", name, e->value);
        else
            fprintf(f, "  %-4s = %s (fixed)\n", name, cli_human(v, sizeof v, e->value, unit));
        return;
    }
    if (unit[0] == '\0')
        fprintf(f, "  %-4s = %.4f +- %.2g   95%% [%.4f, %.4f]", name, e->value, e->se,
                e->ci95[0], e->ci95[1]);
    else
        fprintf(f, "  %-4s = %s +- %s (%.2g%%)   95%% [%s, %s]", name,
                cli_human(v, sizeof v, e->value, unit), cli_human(s, sizeof s, e->se, unit),
                100.0 * e->se / e->value, cli_human(lo, sizeof lo, e->ci95[0], unit),
                cli_human(hi, sizeof hi, e->ci95[1], unit));
    if ((words = cli_interval_words(e, 0)) != NULL)
        fprintf(f, " (%s)", words);
    fputc('\n', f);
}

static void
list(FILE *f, const char *prefix, const lf_warnings *w)
{
    size_t i;
    for (i = 0; i < w->n; i++)
        fprintf(f, "%s%s\n", prefix, w->msg[i]);
}

/* "14% higher" / "0.09% lower" / "the same" */
static const char *
higher_lower(char *buf, size_t n, double rel)
{
    if (!isfinite(rel))
        snprintf(buf, n, "(not comparable)");
    else if (fabs(rel) < 5e-5)
        snprintf(buf, n, "the same");
    else
        snprintf(buf, n, "%.2g%% %s", 100.0 * fabs(rel), rel > 0 ? "higher" : "lower");
    return buf;
}

/* What the thin-layer closed form would have given (res->thin). */
static void
text_thin(FILE *f, const lf_fit_result *r)
{
    const lf_fit_thin_comparison *t = &r->thin;
    char v[48], h[48];

    if (!t->done)
        return;
    if (t->w.determined && r->w.determined) {
        fprintf(f, "\nthe thin-layer model would give w %s (%s",
                higher_lower(h, sizeof h, t->w_rel), cli_human(v, sizeof v, t->w.value, "J/m^2"));
        if (isfinite(t->w_in_se))
            fprintf(f, ", %+.2g standard errors", t->w_in_se);
        fprintf(f, ")");
    } else {
        fprintf(f, "\nthe thin-layer model would give w %s",
                t->w.determined ? cli_human(v, sizeof v, t->w.value, "J/m^2")
                                : "not determined");
    }
    if (t->Estar.determined && r->Estar.determined)
        fprintf(f, ", E* %s (%s)", higher_lower(h, sizeof h, t->Estar_rel),
                cli_human(v, sizeof v, t->Estar.value, "Pa"));
    if (t->nu.determined && t->nu.free && r->nu.determined)
        fprintf(f, ", nu %.4f (%+.4f)", t->nu.value, t->nu_diff);
    fprintf(f, "%s\n", t->converged ? "" : " [that fit did not converge]");
}

/* Curve j has no layer: none given (b a stand-in), or its model (the
 * half-space) uses none. */
static int
no_layer(const report_input *in, const lf_fit_result *r, size_t j)
{
    return cli_model_ignores_b(r->curves[j].model) || (in->origin != NULL && in->origin[j].b == NULL);
}

/* "      from: R file header, spring constant 0.032 N/m file header, ...":
 * where a curve's probe radius, thickness and AFM constants came from. */
static void
origin_text(FILE *f, const lf_curve_origin *o, int nolayer)
{
    fprintf(f, "      from: R %s, b %s", o->R != NULL ? o->R : "option",
            o->b == NULL ? "none (half-space)"
            : nolayer ? "not used (half-space model)" : o->b);
    if (o->spring_constant_source != NULL)
        fprintf(f, ", spring constant %.4g N/m %s", o->spring_constant,
                o->spring_constant_source);
    if (o->sensitivity_source != NULL)
    {
        double v;
        const char *u = lf_sensitivity_shown(o->sensitivity, o->sensitivity_unit, &v);
        fprintf(f, ", sensitivity %.4g %s %s", v, u, o->sensitivity_source);
    }
    fputc('\n', f);
}

static void
put_indented(void *ctx, const char *line)
{
    fprintf((FILE *) ctx, "  %s\n", line);
}

/* The top of the report: what was assumed, then how the curves differ. */
static void
text_top(FILE *f, const report_input *in, const lf_fit_result *r)
{
    size_t i, shown = 0;
    char buf[200];

    for (i = 0; i < in->nassumed; i++) {
        if (strcmp(in->assumed[i].name, "R") == 0)
            continue;       /* said above, per file */
        fprintf(f, "%s%s", shown++ ? "\n  " : "\nassumed, not fitted:\n  ",
                lf_assumption_text(buf, sizeof buf, &in->assumed[i], r->ncurves));
    }
    if (shown)
        fputc('\n', f);
    if (r->heterogeneity.curves >= 2) {
        fprintf(f, "\nhow the %zu curves differ (each also fitted alone):\n", r->heterogeneity.curves);
        cli_hetero_lines(&r->heterogeneity, put_indented, f);
    }
}

void
report_text(FILE *f, const report_input *in, const lf_fit_result *r)
{
    char a[48], b[48], c[48], d[48], shape[160];
    size_t i, j, k;

    if (in->model_request != NULL && strcmp(in->model_request, "auto") == 0)
        fprintf(f, "layerfit fit: %zu curve%s, model auto (%s; %zu fit%s, tolerance %.2g se), "
                "method %s: %s\n", r->ncurves, r->ncurves == 1 ? "" : "s", r->model,
                r->model_rounds, r->model_rounds == 1 ? "" : "s", in->model_tol, r->method,
                r->stop_reason);
    else
        fprintf(f, "layerfit fit: %zu curve%s, model %s, method %s: %s\n", r->ncurves,
                r->ncurves == 1 ? "" : "s", r->model, r->method, r->stop_reason);
    if (r->loss != NULL && strcmp(r->loss, "linear") != 0)
        fprintf(f, "robust loss %s (%zu reweighting rounds)\n", r->loss, r->reweightings);
    if (!r->converged)
        fprintf(f, "*** NOT CONVERGED: the values below are where the fit stopped ***\n");
    text_top(f, in, r);
    if (r->corr_time > 1.5)
        fprintf(f, "\nmaterial (+- one standard error, scaled by sqrt(chi2/dof x correlation "
                "time %.3g) = %.3g)\n", r->corr_time, r->se_scale);
    else
        fprintf(f, "\nmaterial (+- one standard error, scaled by sqrt(chi2/dof) = %.3g)\n",
                r->se_scale);
    text_estimate(f, "w", &r->w, "J/m^2");
    text_estimate(f, "E*", &r->Estar, "Pa");
    text_estimate(f, "nu", &r->nu, "");
    if (r->M.determined && r->M.free)
        text_estimate(f, "M", &r->M, "Pa");
    text_thin(f, r);
    fprintf(f, "\nfree parameters:");
    for (i = 0; i < r->npar; i++)
        fprintf(f, " %s", r->names[i]);
    fprintf(f, "\nchi2/dof = %.4g / %zu = %.4g   iterations %zu, evaluations %zu\n",
            r->chi2, r->dof, r->chi2 / (double) r->dof, r->iterations, r->evaluations);
    fprintf(f, "\ncorrelations of the material parameters:\n");
    for (i = 0; i < r->npar; i++) {
        if (strcmp(r->names[i], "w") && strcmp(r->names[i], "E*") && strcmp(r->names[i], "nu"))
            continue;
        for (k = i + 1; k < r->npar; k++) {
            double rho = r->corr[i * r->npar + k];
            if (isnan(rho) || fabs(rho) < 0.3)
                continue;
            fprintf(f, "  corr(%s, %s) = %+.3f\n", r->names[i], r->names[k], rho);
        }
    }
    fprintf(f, "\ncurves (predicted from the fit)\n");
    for (j = 0; j < r->ncurves; j++) {
        const lf_fit_curve_result *cr = &r->curves[j];
        fprintf(f, "  [%zu] ", j + 1);
        cli_put_clean(f, cr->name);
        if (no_layer(in, r, j))
            fprintf(f, ": %s, no layer (half-space), %s branch, %zu points\n",
                    cli_probe_words(shape, sizeof shape, &cr->probe), branch_name(cr->branch),
                    cr->n);
        else
            fprintf(f, ": %s, b = %s, %s, %s branch, %zu points\n",
                    cli_probe_words(shape, sizeof shape, &cr->probe),
                    cli_human(b, sizeof b, cr->probe.b, "m"), cli_base_name(cr->probe.base),
                    branch_name(cr->branch), cr->n);
        if (in->origin != NULL)
            origin_text(f, &in->origin[j], no_layer(in, r, j));
        if (in->window != NULL && in->observed != NULL)
            cli_window_text(f, &in->window[j], &in->observed[j]);
        fprintf(f, "      z0 = %s%s, F0 = %s%s, noise %s, rms residual %s",
                isnan(cr->z0) ? "not determined" : cli_human(a, sizeof a, cr->z0, "m"),
                cr->z0_free ? "" : " (fixed)",
                isnan(cr->F0) ? "not determined" : cli_human(b, sizeof b, cr->F0, "N"),
                cr->F0_free ? "" : " (fixed)",
                cli_human(c, sizeof c, cr->sigma, "N"), cli_human(d, sizeof d, cr->rms, "N"));
        if (cr->quantum > 0)
            fprintf(f, "; force quantized at %s", cli_human(a, sizeof a, cr->quantum, "N"));
        fputc('\n', f);
        if (cr->corr_time > 1.5)
            fprintf(f, "      correlated noise: one independent point in %.3g (%.0f of %zu), "
                    "noise %s at that lag\n", cr->corr_time, cr->n_eff, cr->n,
                    cli_human(a, sizeof a, cr->noise_sd, "N"));
        if (cr->pulloff_determined)
            fprintf(f, "      pull-off %s, contact radius %s, mean tension %s\n",
                    cli_human(a, sizeof a, cr->pulloff.P_po, "N"),
                    cli_human(b, sizeof b, cr->pulloff.a_po, "m"),
                    cli_human(c, sizeof c, cr->pulloff.sigma_po, "Pa"));
        else
            fputs("      pull-off not determined (w is not)\n", f);
        if (in->observed != NULL)
            cli_observed_text(f, &in->observed[j], cr);
        if (!no_layer(in, r, j)) {    /* no layer: no b/a */
            fprintf(f, "      b/a = %.3g at the shallowest contact point", cr->b_over_a_min_contact);
            if (cr->pulloff_determined)
                fprintf(f, ", %.3g at pull-off", cr->b_over_a_pulloff);
            fputc('\n', f);
        }
        if (cr->model != NULL) {
            fprintf(f, "      model %s: %s\n", cr->model, cr->model_reason);
            /* the choice's biases are in standard errors of the noise alone */
            if (strstr(cr->model_reason, " se") != NULL && r->se_scale > 1.5)
                fprintf(f, "      (the model choice's se are those of the noise alone; the "
                        "errors reported above are %.3g times larger)\n", r->se_scale);
        }
        if (r->heterogeneity.curves >= 2) {
            const lf_curve_estimate *e = &cr->alone;
            fprintf(f, "      fitted alone: w %s, E* %s",
                    isfinite(e->value[LF_MAT_W]) ? cli_human(a, sizeof a, e->value[LF_MAT_W], "J/m^2")
                                                 : "not determined",
                    isfinite(e->value[LF_MAT_E]) ? cli_human(b, sizeof b, e->value[LF_MAT_E], "Pa")
                                                 : "not determined");
            if (isfinite(e->value[LF_MAT_NU]))
                fprintf(f, ", nu %.4f", e->value[LF_MAT_NU]);
            fputc('\n', f);
        }
        if (cr->agreement == 1)
            fprintf(f, "      agreement: chi2/point %.3g (p = %.2g), runs test z = %.2f: the model "
                    "describes the shape, with systematic deviations of %.2g%% of the force "
                    "range (beyond the noise)\n", cr->chi2_per_point, cr->p_value, cr->runs_z,
                    100.0 * cr->misfit_rel);
        else
            fprintf(f, "      agreement: chi2/point %.3g (p = %.2g), runs test z = %.2f: %s\n",
                    cr->chi2_per_point, cr->p_value, cr->runs_z,
                    cli_curve_disagrees(cr) ? "DISAGREES" : "consistent");
        if (cr->downweighted > 0)
            fprintf(f, "      %zu points down-weighted by the %s loss\n", cr->downweighted,
                    r->loss);
        list(f, "      warning: ", &cr->warnings);
    }
    fprintf(f, "\nwhat the data determine:\n");
    list(f, "  ", &r->identifiability);
    if (r->warnings.n > 0) {
        fprintf(f, "\nwarnings:\n");
        list(f, "  ", &r->warnings);
    }
}

/* ---- JSON: the library's writer ----------------------------------------- */

void
report_json_number(FILE *f, double x)
{
    if (isfinite(x))
        cli_print_double(f, x);
    else
        fputs("null", f);
}

void
report_json_string(FILE *f, const char *s)
{
    cli_json_string(f, s);
}

void
report_json(FILE *f, const report_input *in, const lf_fit_result *r)
{
    lf_provenance prov;
    lf_report_info info;
    lf_error err;
    char *json;

    cli_provenance_of(in->command_line, &prov);
    info.model_request = in->model_request;
    info.model_tol = in->model_tol;
    info.origin = in->origin;
    info.provenance = &prov;
    info.assumed = in->assumed;
    info.nassumed = in->nassumed;
    info.observed = in->observed;
    info.window = in->window;
    if (lf_fit_result_json(r, &info, &json, &err) != LF_OK)
        cli_die(CLI_EXIT_FAIL, "fit: %s", err.msg);
    fputs(json, f);
    lf_free(json);
    cli_provenance_free(&prov);
}

void
report_curves(FILE *f, const report_input *in, const lf_fit_result *r)
{
    size_t i, j;

    fputs("depth_m,force_N,fitted_N,residual_N,contact_radius_m,curve\n", f);
    for (j = 0; j < r->ncurves; j++) {
        const lf_fit_curve *c = &in->curves[j];
        for (i = 0; i < c->n; i++) {
            cli_print_double(f, c->depth[i]);
            fputc(',', f);
            cli_print_double(f, c->force[i]);
            fputc(',', f);
            cli_print_double(f, r->curves[j].fitted[i]);
            fputc(',', f);
            cli_print_double(f, c->force[i] - r->curves[j].fitted[i]);
            fputc(',', f);
            cli_print_double(f, r->curves[j].contact_radius[i]);
            fprintf(f, ",%zu\n", j + 1);
        }
    }
}
