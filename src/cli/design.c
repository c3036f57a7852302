/* cli/design.c: `layerfit design PLAN`: what a planned set of curves would
 * measure, before the lab records them.  Reads the design plan, hands the
 * candidates to the library (fit/design.c: predicted errors, model choice,
 * greedy choice, sweeps) and prints the answer as text, JSON, a CSV table
 * and a gnuplot figure. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"
#include "plot.h"
#include "report.h"

static const char usage_text[] =
    "usage: layerfit design PLAN.csv --w ADHESION --E PRESSURE [options]\n"
    "\n"
    "Predicts the standard errors of w, E* and nu that a joint fit of the planned\n"
    "curves would reach (the Cramer-Rao bound, with every free offset estimated\n"
    "too), says what the curves would not determine and why, and what each\n"
    "candidate adds.  Curves are taken to follow the exact layer model and are\n"
    "judged with the model `layerfit fit --model auto` would use.\n"
    "\n"
    "PLAN.csv: one candidate curve per row, columns k,R,b,interface and optional\n"
    "name,delta_max,delta_min,points,baseline,z0,F0,segment,noise (see the man page).\n"
    "\n"
    "options:\n"
    "  --nu NU            Poisson's ratio of the layer (0.3)\n"
    "  --fix-nu           nu is known and held, as with fit --fix-nu\n"
    "  --noise X          force noise sd: a fraction of each curve's largest |force|\n"
    "                     (1% or 0.01, the default 1%) or a force (2uN)\n"
    "  --points N         points per curve where the plan gives none (200)\n"
    "  --delta-max L      deepest indentation where the plan gives none (50nm)\n"
    "  --model NAME       auto (default), thin, exact or halfspace: the fit's model\n"
    "  --model-tol X      bias allowed to a cheaper model, in standard errors (0.2)\n"
    "  --choose N         pick the N candidates that best determine --target, greedily\n"
    "  --target T         w (default), E, nu, or all (D-optimal: largest log det of\n"
    "                     the information of w, E*, nu with the offsets profiled out)\n"
    "  --grid F=V1,V2,..  sweep factor F over the values (or F=LO:HI:N, N values\n"
    "                     evenly spaced; F=LO:HI:N:log for log spacing); F is k,\n"
    "                     delta_max, points, b, R or baseline; values take units\n"
    "  --vary ROW         sweep only this candidate (its name or row number)\n"
    "  --plot FILE        figure of the sweep, .svg or .png (needs --grid)\n"
    "  --csv FILE         the sweep's table as CSV (needs --grid)\n"
    "  --json FILE        everything in SI as JSON\n"
    "exit status: 0 done, 1 failure, 2 bad input\n";

/* "8.7%", "+- 0.0031", or words ("upper bound": w below two of its
 * standard errors, which a fit reports as an upper bound): never a NaN. */
static const char *
rel_text(char *buf, size_t n, const lf_design_estimate *e, int absolute)
{
    if (!e->free)
        snprintf(buf, n, "not fitted");
    else if (e->upper_bound_only)
        snprintf(buf, n, "upper bound");   /* below two of its se */
    else if (!e->determined)
        snprintf(buf, n, "undetermined");
    else if (absolute)
        snprintf(buf, n, "+-%.2g", e->se);
    else
        snprintf(buf, n, "%.3g%%", 100.0 * e->rel);
    return buf;
}

static const char *
cand_label(char *buf, size_t n, const lf_design_candidate *c, size_t i)
{
    snprintf(buf, n, "[%zu] %s", i + 1, c->name);
    return buf;
}

/* ---- text ---------------------------------------------------------------- */

/* e's line; why it is not determined is the judgement's (e->why, or the
 * notes below the estimates). */
static void
text_estimate(FILE *f, const char *name, const lf_design_estimate *e, const char *unit,
              const char *not_free)
{
    char a[48];
    if (!e->free)
        fprintf(f, "  %-4s not fitted: %s\n", name, not_free);
    else if (e->upper_bound_only)
        fprintf(f, "  %-4s not determined: below two of its standard errors, a fit would report "
                "only an upper bound\n", name);
    else if (!e->determined)
        fprintf(f, "  %-4s not determined%s%s\n", name, e->why ? ": " : "", e->why ? e->why : "");
    else if (unit[0] == '\0')
        fprintf(f, "  %-4s +- %.2g\n", name, e->se);
    else
        fprintf(f, "  %-4s +- %s (%.3g%%)\n", name, cli_human(a, sizeof a, e->se, unit),
                100.0 * e->rel);
}

static void
text_list(FILE *f, const char *title, const lf_warnings *w)
{
    size_t i;
    if (w->n == 0)
        return;
    fprintf(f, "\n%s\n", title);
    for (i = 0; i < w->n; i++)
        fprintf(f, "  %s\n", w->msg[i]);
}

static void
text_curves(FILE *f, const lf_design_plan *plan, const lf_design_result *r)
{
    char a[48], b[48], c[48], d[48], l[96];
    size_t j;

    fprintf(f, "\ncandidates (each as it would be recorded and fitted)\n");
    for (j = 0; j < r->ncurves; j++) {
        const lf_design_curve_info *ci = &r->curves[j];
        const lf_design_candidate *cd = &plan->rows[ci->index];
        fprintf(f, "  %s: k = %g, R = %s, b = %s, %s, %s branch, %zu points\n",
                cand_label(l, sizeof l, cd, ci->index), cd->probe.k,
                cli_human(a, sizeof a, cd->probe.R, "m"), cli_human(b, sizeof b, cd->probe.b, "m"),
                cli_base_name(cd->probe.base), cd->branch == LF_BRANCH_LOAD ? "load" : "unload",
                ci->n);
        fprintf(f, "      indentation %s to %s, detachment at %s: %zu points past it%s\n",
                cli_human(a, sizeof a, ci->delta_lo, "m"), cli_human(b, sizeof b, ci->delta_hi, "m"),
                cli_human(c, sizeof c, ci->delta_detach, "m"), ci->n_past,
                ci->n_past == 0 ? " (no baseline)" : " (baseline)");
        fprintf(f, "      z0 %s, F0 %s; noise %s (largest |force| %s)\n",
                ci->free_z0 ? "free" : "fixed", ci->free_F0 ? "free" : "fixed",
                cli_human(c, sizeof c, ci->sigma, "N"), cli_human(d, sizeof d, ci->fmax, "N"));
        fprintf(f, "      model %s: %s\n", ci->model->name, ci->model_reason);
        if (isfinite(ci->ba_min))
            fprintf(f, "      thin-layer validity: b/a %.3g to %.3g in contact", ci->ba_min, ci->ba_max);
        else
            fprintf(f, "      thin-layer validity: no point in contact");
        if (isfinite(ci->ba_pulloff))
            fprintf(f, ", %.3g at pull-off", ci->ba_pulloff);
        fprintf(f, " (the thin-layer model wants b/a << 1)\n");
    }
}

static void
text_set(FILE *f, const char *title, const lf_design_result *r, const lf_design_plan *plan,
         const lf_design_settings *s)
{
    size_t j, nb = 0;

    for (j = 0; j < r->ncurves; j++)
        nb += plan->rows[r->curves[j].index].probe.base == LF_BASE_BONDED;
    fprintf(f, "\n%s (predicted standard errors: the Cramer-Rao bound of the joint fit)\n", title);
    text_estimate(f, "w", &r->w, "J/m^2", "");
    text_estimate(f, "E*", &r->Estar, "Pa", "");
    text_estimate(f, "nu", &r->nu, "",
                  s->fix_nu ? "held at the given value (--fix-nu)"
                  : nb == 0 ? "frictionless curves do not depend on it"
                            : "bonded curves alone do not determine it");
    if (r->M.determined && !r->Estar.determined)
        text_estimate(f, "M", &r->M, "Pa", "");
    if (isfinite(r->corr_wE))
        fprintf(f, "  corr(w, E*) = %+.3f\n", r->corr_wE);
    fprintf(f, "  %zu free parameters (offsets included)\n", r->npar);
    text_list(f, "what the data would determine:", &r->identifiability);
    text_list(f, "notes:", &r->notes);
}

/* ---- JSON ---------------------------------------------------------------- */

/* ---- the parts of a run ------------------------------------------------ */

static void
text_contributions(FILE *f, const lf_design_plan *plan, const lf_design_result *all,
                   const lf_design_report *c)
{
    char a[32], b[32], d[32], l[96], lab[128];
    size_t i;
    int width = 14;

    if (c->n < 2)
        return;
    for (i = 0; i < c->n; i++) {
        int len = snprintf(lab, sizeof lab, "without %s", cand_label(l, sizeof l, &plan->rows[i], i));
        width = len > width ? len : width;
    }
    fprintf(f, "\nwhat each candidate adds (the predicted errors without it)\n");
    fprintf(f, "  %-*s  %-14s %-14s %s\n", width, "set", "w", "E*", "nu");
    fprintf(f, "  %-*s  %-14s %-14s %s\n", width, "all candidates", rel_text(a, sizeof a, &all->w, 0),
            rel_text(b, sizeof b, &all->Estar, 0), rel_text(d, sizeof d, &all->nu, 1));
    for (i = 0; i < c->n; i++) {
        const lf_design_result *r = &c->without[i];
        snprintf(lab, sizeof lab, "without %s", cand_label(l, sizeof l, &plan->rows[i], i));
        fprintf(f, "  %-*s  %-14s %-14s %s\n", width, lab, rel_text(a, sizeof a, &r->w, 0),
                rel_text(b, sizeof b, &r->Estar, 0), rel_text(d, sizeof d, &r->nu, 1));
    }
}

static const char *
target_words(lf_design_target t)
{
    switch (t) {
    case LF_TARGET_W: return "the smallest error of w";
    case LF_TARGET_E: return "the smallest error of E*";
    case LF_TARGET_NU: return "the smallest error of nu";
    default: return "the largest log det of the information of w, E*, nu (D-optimal)";
    }
}

static void
text_step_score(FILE *f, const lf_design_score *s, lf_design_target t)
{
    if (!s->target_determined)
        fprintf(f, "%s not determined (%zu of w, E*, nu determined)",
                t == LF_TARGET_ALL ? "nothing" : lf_design_target_name(t), s->ndetermined);
    else if (t == LF_TARGET_ALL)
        fprintf(f, "log det %.4g (%zu of w, E*, nu determined)", s->value, s->ndetermined);
    else if (t == LF_TARGET_NU)
        fprintf(f, "nu +-%.2g", -s->value);
    else
        fprintf(f, "%s +-%.3g%%", t == LF_TARGET_W ? "w" : "E*", -100.0 * s->value);
}

static void
text_choice(FILE *f, const lf_design_plan *plan, const lf_design_choice *ch, lf_design_target t,
            int exh_status, const int *best, size_t nsets_note)
{
    char a[32], b[32], d[32], l[96];
    size_t s, i;
    int same = 1;

    fprintf(f, "\nchoice of %zu candidate%s for %s (greedy: each step adds the candidate\n"
            "that gives %s)\n", ch->nsteps, ch->nsteps == 1 ? "" : "s",
            lf_design_target_name(t), target_words(t));
    for (s = 0; s < ch->nsteps; s++) {
        const lf_design_step *sp = &ch->steps[s];
        fprintf(f, "  step %zu: add %s: ", s + 1, cand_label(l, sizeof l, &plan->rows[sp->added], sp->added));
        text_step_score(f, &sp->score, t);
        fprintf(f, "\n          the set then gives w %s, E* %s, nu %s\n", rel_text(a, sizeof a, &sp->w, 0),
                rel_text(b, sizeof b, &sp->Estar, 0), rel_text(d, sizeof d, &sp->nu, 1));
        if (sp->runner_up != (size_t) -1) {
            fprintf(f, "          next best: %s (",
                    cand_label(l, sizeof l, &plan->rows[sp->runner_up], sp->runner_up));
            text_step_score(f, &sp->runner_score, t);
            fprintf(f, ")\n");
        }
    }
    fprintf(f, "  chosen:");
    for (i = 0; i < plan->n; i++)
        if (ch->chosen[i])
            fprintf(f, " %s", cand_label(l, sizeof l, &plan->rows[i], i));
    fputc('\n', f);
    if (exh_status == LF_OK) {
        for (i = 0; i < plan->n; i++)
            same &= (ch->chosen[i] != 0) == (best[i] != 0);
        if (same)
            fprintf(f, "  the greedy choice is also the best of all %zu sets of %zu "
                    "(exhaustive search)\n", nsets_note, ch->nsteps);
        else {
            fprintf(f, "  the best of all %zu sets of %zu (exhaustive search) differs:", nsets_note,
                    ch->nsteps);
            for (i = 0; i < plan->n; i++)
                if (best[i])
                    fprintf(f, " %s", cand_label(l, sizeof l, &plan->rows[i], i));
            fputc('\n', f);
        }
    }
}

static double
plot_y(const lf_design_estimate *e, int absolute)
{
    return e->determined ? (absolute ? e->se : 100.0 * e->rel) : NAN;
}

static void
draw_sweep(const char *file, lf_design_factor factor, size_t nv, const double *x,
           const lf_design_result *res, const char *scope)
{
    static const char *names[3] = { "w: se/w (%)", "E*: se/E* (%)", "nu: se x 100" };
    double *xs = malloc(3 * nv * sizeof *xs), *ys = malloc(3 * nv * sizeof *ys);
    plot_series ser[3];
    plot_figure fig;
    char msg[600], xlabel[96], title[200];
    size_t s, v, ns = 0;
    double xscale = 1.0;
    const char *xunit = "";

    if (!xs || !ys)
        cli_die(CLI_EXIT_FAIL, "design: out of memory");
    if (lf_design_factor_quantity(factor) == LF_Q_LENGTH) {
        xscale = 1e9;
        xunit = " (nm)";
        for (v = 0; v < nv; v++)
            if (x[v] >= 1e-6)
                xscale = 1e6, xunit = " (um)";
    }
    for (s = 0; s < 3; s++) {
        size_t k = 0;
        for (v = 0; v < nv; v++) {
            const lf_design_estimate *e = s == 0 ? &res[v].w : s == 1 ? &res[v].Estar : &res[v].nu;
            double y = s == 2 ? 100.0 * plot_y(e, 1) : plot_y(e, 0);
            if (!isfinite(y))
                continue;           /* undetermined: no point */
            xs[s * nv + k] = x[v] * xscale;
            ys[s * nv + k] = y;
            k++;
        }
        if (k == 0)
            continue;
        ser[ns].title = names[s];
        ser[ns].n = k;
        ser[ns].x = xs + s * nv;
        ser[ns].y = ys + s * nv;
        ser[ns].dashed = 0;
        ser[ns].color = (int) s;
        ser[ns].points = 0;
        ns++;
    }
    snprintf(xlabel, sizeof xlabel, "%s%s", lf_design_factor_name(factor), xunit);
    snprintf(title, sizeof title, "predicted standard error against %s (%s)",
             lf_design_factor_name(factor), scope);
    fig.title = title;
    fig.xlabel = xlabel;
    fig.ylabel = "predicted standard error";
    fig.logx = 0;
    fig.logy = 1;
    fig.nseries = ns;
    fig.series = ser;
    if (ns == 0) {
        cli_say("warning: design: nothing is determined anywhere in the sweep: "
                "no figure drawn");
    } else {
        if (plot_draw(&fig, file, msg, sizeof msg) != 0)
            cli_die(CLI_EXIT_FAIL, "design: --plot: %s", msg);
    }
    free(xs);
    free(ys);
}

static void
value_text(char *buf, size_t n, lf_design_factor factor, double v)
{
    if (lf_design_factor_quantity(factor) == LF_Q_LENGTH)
        cli_human(buf, n, v, "m");
    else
        snprintf(buf, n, "%g", v);
}

/* A field width for s that printf (which counts bytes) pads to width
 * characters: one more for each UTF-8 continuation byte (the 'µ' of µm). */
static int
text_width(const char *s, int width)
{
    const unsigned char *p;
    for (p = (const unsigned char *) s; *p; p++)
        width += (*p & 0xC0) == 0x80;
    return width;
}

static void
text_sweep(FILE *f, lf_design_factor factor, size_t nv, const double *x,
           const lf_design_result *res, const char *scope)
{
    char a[32], b[32], d[32], vb[48];
    size_t v, j;

    fprintf(f, "\nsweep of %s over %zu values (%s); predicted errors of the whole set\n",
            lf_design_factor_name(factor), nv, scope);
    fprintf(f, "  %-12s %-14s %-14s %-14s %s\n", lf_design_factor_name(factor), "w", "E*", "nu",
            "models (by candidate)");
    for (v = 0; v < nv; v++) {
        value_text(vb, sizeof vb, factor, x[v]);
        rel_text(a, sizeof a, &res[v].w, 0);
        rel_text(b, sizeof b, &res[v].Estar, 0);
        rel_text(d, sizeof d, &res[v].nu, 1);
        fprintf(f, "  %-*s %-*s %-*s %-*s ", text_width(vb, 12), vb, text_width(a, 14), a,
                text_width(b, 14), b, text_width(d, 14), d);
        for (j = 0; j < res[v].ncurves; j++)
            fprintf(f, "%s%s", j ? "," : "", res[v].curves[j].model->name);
        fputc('\n', f);
    }
}

static void
csv_sweep(const char *path, lf_design_factor factor, size_t nv, const double *x,
          const lf_design_result *res)
{
    cli_out o;
    char msg[4400];
    FILE *f = cli_out_open(&o, path, msg, sizeof msg);
    size_t v;

    if (f == NULL)
        cli_die(CLI_EXIT_FAIL, "design: %s", msg);

    fprintf(f, "%s%s,w_se_J_m2,w_rel_se,Estar_se_Pa,Estar_rel_se,nu_se,w_determined,"
            "Estar_determined,nu_determined\n", lf_design_factor_name(factor),
            lf_design_factor_quantity(factor) == LF_Q_LENGTH ? "_m" : "");
    for (v = 0; v < nv; v++) {
        const double cells[5] = { res[v].w.se, res[v].w.rel, res[v].Estar.se, res[v].Estar.rel,
                                  res[v].nu.se };
        int k;
        cli_print_double(f, x[v]);
        for (k = 0; k < 5; k++) {
            fputc(',', f);
            if (isfinite(cells[k]))    /* empty cell: not determined */
                cli_print_double(f, cells[k]);
        }
        fprintf(f, ",%d,%d,%d\n", res[v].w.determined, res[v].Estar.determined,
                res[v].nu.determined);
    }
    if (cli_out_commit(&o, msg, sizeof msg) != 0)
        cli_die(CLI_EXIT_FAIL, "design: %s", msg);
}

/* ---- the command ---------------------------------------------------------- */

int
cli_design(int argc, char **argv, const char *command_line)
{
    const char *plot = NULL, *csv = NULL, *json = NULL;
    lf_design_options *o = lf_design_options_alloc();
    cli_opt opts[3 + 16 + 1] = {
        { "plot", CLI_STRING, &plot }, { "csv", CLI_STRING, &csv }, { "json", CLI_STRING, &json },
    };
    lf_design_settings s;
    lf_design_plan *plan = NULL;
    lf_design_report *rep = NULL;
    lf_design_factor factor;
    lf_error err;
    double values[200];
    size_t nv, i, no = 3;
    int npos, help;
    char scope[128] = "every candidate", a1[48], a2[48], l[96];
    const char *plan_path;
    FILE *out = stdout;

    if (o == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    for (i = 0; lf_design_option_table[i].name != NULL; i++, no++) {
        if (no == 3 + 16)           /* a table that outgrew the room: never silently */
            cli_die(CLI_EXIT_FAIL, "design: more options than room for them");
        opts[no].name = lf_design_option_table[i].name;
        opts[no].kind = lf_design_option_table[i].kind == LF_OPTION_FLAG ? CLI_DESIGN_FLAG
                                                                        : CLI_DESIGN;
        opts[no].target = o;
    }
    opts[no].name = NULL;
    cli_parse("design", argc, argv, opts, &npos, &help);
    if (help) {
        fputs(usage_text, stdout);
        lf_design_options_free(o);
        return CLI_EXIT_OK;
    }
    if (npos != 1)
        cli_die(CLI_EXIT_USAGE, "design: give one design plan (see 'layerfit design --help')");
    plan_path = argv[0];
    if (lf_design_options_settings(o, &s, &err) != LF_OK)
        cli_die(CLI_EXIT_USAGE, "design: %s", err.msg);
    if ((plot != NULL || csv != NULL || lf_design_options_get(o, "vary") != NULL)
        && lf_design_options_get(o, "grid") == NULL)
        cli_die(CLI_EXIT_USAGE, "design: --plot, --csv and --vary go with --grid");
    if (plot != NULL && plot_terminal(plot) == NULL)
        cli_die(CLI_EXIT_USAGE, "design: --plot %s: the file must end in .svg or .png", plot);
    if (lf_design_options_grid(o, &factor, values, &nv, &err) != LF_OK)
        cli_die(CLI_EXIT_USAGE, "design: %s", err.msg);
    {
        lf_input in;
        cli_input_guard("design", plan_path);
        if (lf_input_read(plan_path, LF_INPUT_STREAM | LF_INPUT_TEXT, &in, &err) != LF_OK)
            cli_die_error(CLI_EXIT_USAGE, &err);
        cli_input_note(plan_path, in.sha256);
        cli_output_note("design", json);
        cli_output_note("design", csv);
        cli_output_note("design", plot);
        if (lf_design_plan_parse(in.data, in.len, plan_path, &plan, &err) != LF_OK)
            cli_die_error(CLI_EXIT_USAGE, &err);
        lf_input_free(&in);
    }
    /* the whole set, what each adds, the choice, the sweep: the library's */
    if (lf_design_run(o, plan, &rep, &err) != LF_OK)
        cli_die(err.status == LF_EINVAL || err.status == LF_EDATA ? CLI_EXIT_USAGE : CLI_EXIT_FAIL,
                "design: %s", err.msg);
    if (rep->which != (size_t) -1)
        snprintf(scope, sizeof scope, "candidate %s",
                 cand_label(l, sizeof l, &plan->rows[rep->which], rep->which));

    /* the text, unless standard output carries --json - or --csv - */
    if (!(json != NULL && strcmp(json, "-") == 0) && !(csv != NULL && strcmp(csv, "-") == 0)) {
        fprintf(out, "layerfit design: %zu candidate%s; truth w = %s, E* = %s, nu = %.4g%s; noise ",
                plan->n, plan->n == 1 ? "" : "s", cli_human(a1, sizeof a1, s.truth.w, "J/m^2"),
                cli_human(a2, sizeof a2, s.truth.Estar, "Pa"), s.truth.nu, s.fix_nu ? " (held)" : "");
        if (isfinite(s.noise_abs))
            fprintf(out, "sd %s", cli_human(a1, sizeof a1, s.noise_abs, "N"));
        else
            fprintf(out, "%.3g%% of each curve's largest |force|", 100.0 * s.noise_rel);
        fprintf(out, "; model %s\n", s.model ? s.model->name : "auto");
        text_curves(out, plan, &rep->all);
        text_set(out, "the whole set", &rep->all, plan, &s);
        text_contributions(out, plan, &rep->all, rep);
        if (rep->nchoose > 0) {
            text_choice(out, plan, &rep->choice, rep->target, rep->exhaustive ? LF_OK : -1, rep->best,
                        rep->nsets);
            text_set(out, "the chosen set", &rep->chosen, plan, &s);
        }
        if (rep->nsweep > 0)
            text_sweep(out, rep->factor, rep->nsweep, rep->values, rep->sweep, scope);
    }
    if (csv != NULL)
        csv_sweep(csv, rep->factor, rep->nsweep, rep->values, rep->sweep);
    if (plot != NULL)
        draw_sweep(plot, rep->factor, rep->nsweep, rep->values, rep->sweep, scope);
    if (json != NULL) {
        cli_out jo;
        char msg[4400], *doc;
        lf_provenance prov;
        FILE *f = cli_out_open(&jo, json, msg, sizeof msg);
        if (f == NULL)
            cli_die(CLI_EXIT_FAIL, "design: %s", msg);
        cli_provenance_of(command_line, &prov);
        if (lf_design_report_json(rep, &prov, &doc, &err) != LF_OK)
            cli_die(CLI_EXIT_FAIL, "design: %s", err.msg);
        fputs(doc, f);
        lf_free(doc);
        cli_provenance_free(&prov);
        if (cli_out_commit(&jo, msg, sizeof msg) != 0)
            cli_die(CLI_EXIT_FAIL, "design: %s", msg);
    }
    lf_design_report_free(rep);
    lf_design_plan_free(plan);
    lf_design_options_free(o);
    return CLI_EXIT_OK;
}
