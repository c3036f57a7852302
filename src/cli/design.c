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

#define MAX_GRID 200

typedef struct {
    const char *plan, *noise, *model, *target, *grid, *vary, *plot, *csv, *json;
    double w, E, nu, delta_max, model_tol;
    long points, choose;
    int fix_nu;
} design_args;

/* ---- small helpers ------------------------------------------------------ */

/* "1%", "0.01" -> fraction; "2uN" -> force. */
static void
parse_noise(const char *text, lf_design_settings *s)
{
    char buf[64], *end;
    size_t len = strlen(text);
    double v;
    lf_error err;

    if (len > 0 && len < sizeof buf && text[len - 1] == '%') {
        memcpy(buf, text, len - 1);
        buf[len - 1] = '\0';
        errno = 0;
        v = strtod(buf, &end);
        if (end != buf && *end == '\0' && errno == 0 && v > 0 && isfinite(v)) {
            s->noise_rel = v / 100.0;
            return;
        }
    } else {
        errno = 0;
        v = strtod(text, &end);
        if (end != text && *end == '\0') {
            if (errno == 0 && v > 0 && isfinite(v)) {
                s->noise_rel = v;
                return;
            }
        } else if (lf_units_parse(text, LF_Q_FORCE, &v, &err) == LF_OK && v > 0) {
            s->noise_abs = v;
            return;
        }
    }
    cli_die(CLI_EXIT_USAGE, "design: --noise: '%s' is not a positive fraction or force "
            "(e.g. --noise 1%% or --noise 2uN)", text);
}

/* The grid: "k=2,2.5,3", "delta_max=20nm:200nm:10", "b=0.1um:10um:9:log". */
static size_t
parse_grid(const char *text, lf_design_factor *factor, double *values)
{
    char name[32], buf[512], *tok, *save = NULL;
    const char *eq = strchr(text, '=');
    lf_quantity q;
    size_t n = 0, len;
    int f;

    if (eq == NULL || (len = (size_t) (eq - text)) == 0 || len >= sizeof name)
        cli_die(CLI_EXIT_USAGE, "design: --grid '%s': expected FACTOR=VALUES "
                "(e.g. --grid k=2,2.5,3 or --grid delta_max=20nm:200nm:10)", text);
    memcpy(name, text, len);
    name[len] = '\0';
    if ((f = lf_design_factor_find(name)) < 0)
        cli_die(CLI_EXIT_USAGE, "design: --grid: unknown factor '%s' "
                "(k, delta_max, points, b, R or baseline)", name);
    *factor = (lf_design_factor) f;
    q = lf_design_factor_quantity(*factor);
    if (strlen(eq + 1) >= sizeof buf)
        cli_die(CLI_EXIT_USAGE, "design: --grid: too long");
    strcpy(buf, eq + 1);
    if (strchr(buf, ':') != NULL) {
        char *part[4];
        double lo, hi;
        long count;
        int np = 0, logs = 0;
        lf_error err;
        char *end;
        for (tok = strtok_r(buf, ":", &save); tok != NULL && np < 4; tok = strtok_r(NULL, ":", &save))
            part[np++] = tok;
        if (np == 4 && strcmp(part[3], "log") == 0)
            logs = 1;
        else if (np != 3 || tok != NULL)
            cli_die(CLI_EXIT_USAGE, "design: --grid '%s': a range is LO:HI:N or LO:HI:N:log", text);
        if (lf_units_parse(part[0], q, &lo, &err) != LF_OK
            || lf_units_parse(part[1], q, &hi, &err) != LF_OK)
            cli_die(CLI_EXIT_USAGE, "design: --grid '%s': %s", text, err.msg);
        errno = 0;
        count = strtol(part[2], &end, 10);
        if (end == part[2] || *end != '\0' || errno != 0 || count < 2 || count > MAX_GRID)
            cli_die(CLI_EXIT_USAGE, "design: --grid '%s': N must be a whole number from 2 to %d",
                    text, MAX_GRID);
        if (logs && !(lo > 0 && hi > 0))
            cli_die(CLI_EXIT_USAGE, "design: --grid '%s': a log range needs LO, HI > 0", text);
        for (n = 0; n < (size_t) count; n++) {
            double t = (double) n / (double) (count - 1);
            values[n] = logs ? lo * pow(hi / lo, t) : lo + t * (hi - lo);
            if (*factor == LF_FACTOR_POINTS)
                values[n] = floor(values[n] + 0.5);
        }
        return n;
    }
    for (tok = strtok_r(buf, ",", &save); tok != NULL; tok = strtok_r(NULL, ",", &save)) {
        lf_error err;
        if (n == MAX_GRID)
            cli_die(CLI_EXIT_USAGE, "design: --grid: at most %d values", MAX_GRID);
        if (lf_units_parse(tok, q, &values[n], &err) != LF_OK)
            cli_die(CLI_EXIT_USAGE, "design: --grid '%s': %s", text, err.msg);
        n++;
    }
    if (n == 0)
        cli_die(CLI_EXIT_USAGE, "design: --grid '%s': no values", text);
    return n;
}

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

static void
json_estimate(FILE *f, const char *name, const lf_design_estimate *e, const char *tail)
{
    fprintf(f, "\"%s\": {\"free\": %s, \"determined\": %s, \"stderr\": ", name,
            e->free ? "true" : "false", e->determined ? "true" : "false");
    report_json_number(f, e->se);
    fputs(", \"relative_stderr\": ", f);
    report_json_number(f, e->rel);
    if (e->upper_bound_only)
        fputs(", \"upper_bound_only\": true", f);
    if (e->why != NULL) {
        fputs(", \"why_not_determined\": ", f);
        report_json_string(f, e->why);
    }
    fprintf(f, "}%s", tail);
}

static void
json_warnings(FILE *f, const lf_warnings *w)
{
    size_t i;
    fputc('[', f);
    for (i = 0; i < w->n; i++) {
        fputs(i ? ", " : "", f);
        report_json_string(f, w->msg[i]);
    }
    fputc(']', f);
}

static void
json_set(FILE *f, const lf_design_result *r, int curves, const lf_design_plan *plan)
{
    size_t j;

    fputs("{", f);
    json_estimate(f, "w", &r->w, ", ");
    json_estimate(f, "Estar", &r->Estar, ", ");
    json_estimate(f, "nu", &r->nu, ", ");
    json_estimate(f, "M", &r->M, ", ");
    fputs("\"corr_w_Estar\": ", f);
    report_json_number(f, r->corr_wE);
    fprintf(f, ", \"free_parameters\": %zu, \"determined\": %zu, \"log_det_information\": ",
            r->npar, r->ndetermined);
    report_json_number(f, r->logdet);
    fputs(", \"identifiability\": ", f);
    json_warnings(f, &r->identifiability);
    fputs(", \"notes\": ", f);
    json_warnings(f, &r->notes);
    fputs(", \"candidates\": [", f);
    for (j = 0; j < r->ncurves; j++) {
        const lf_design_curve_info *ci = &r->curves[j];
        const lf_design_candidate *cd = &plan->rows[ci->index];
        if (!curves) {
            fprintf(f, "%s%zu", j ? ", " : "", ci->index + 1);
            continue;
        }
        fprintf(f, "%s\n    {\"row\": %zu, \"name\": ", j ? "," : "", ci->index + 1);
        report_json_string(f, cd->name);
        fputs(", \"k\": ", f);
        report_json_number(f, cd->probe.k);
        fputs(", \"R_m\": ", f);
        report_json_number(f, cd->probe.R);
        fputs(", \"b_m\": ", f);
        report_json_number(f, cd->probe.b);
        fprintf(f, ", \"interface\": \"%s\", \"branch\": \"%s\", \"points\": %zu, "
                "\"points_past_detachment\": %zu, \"delta_min_m\": ", cli_base_name(cd->probe.base),
                cd->branch == LF_BRANCH_LOAD ? "load" : "unload", ci->n, ci->n_past);
        report_json_number(f, ci->delta_lo);
        fputs(", \"delta_max_m\": ", f);
        report_json_number(f, ci->delta_hi);
        fputs(", \"delta_detach_m\": ", f);
        report_json_number(f, ci->delta_detach);
        fprintf(f, ", \"z0_free\": %s, \"F0_free\": %s, \"noise_sd_N\": ",
                ci->free_z0 ? "true" : "false", ci->free_F0 ? "true" : "false");
        report_json_number(f, ci->sigma);
        fputs(", \"max_force_N\": ", f);
        report_json_number(f, ci->fmax);
        fputs(", \"model\": ", f);
        report_json_string(f, ci->model->name);
        fputs(", \"model_reason\": ", f);
        report_json_string(f, ci->model_reason);
        fputs(", \"thin_bias_se\": ", f);
        report_json_number(f, ci->thin_bias);
        fputs(", \"b_over_a\": [", f);
        report_json_number(f, ci->ba_min);
        fputs(", ", f);
        report_json_number(f, ci->ba_max);
        fputs("], \"b_over_a_pulloff\": ", f);
        report_json_number(f, ci->ba_pulloff);
        fputs("}", f);
    }
    fputs(curves ? "\n  ]}" : "]}", f);
}

/* ---- the parts of a run ------------------------------------------------ */

typedef struct {
    size_t n;
    lf_design_result *without;   /* n: the set without candidate i */
    int *done;
} contributions;

static void
compute_contributions(lf_design *d, size_t n, contributions *c)
{
    int *use = malloc(n * sizeof *use);
    size_t i;
    lf_error err;

    c->n = n;
    c->without = calloc(n, sizeof *c->without);
    c->done = calloc(n, sizeof *c->done);
    if (!use || !c->without || !c->done)
        cli_die(CLI_EXIT_FAIL, "design: out of memory");
    for (i = 0; i < n && n > 1; i++) {
        size_t k;
        for (k = 0; k < n; k++)
            use[k] = k != i;
        if (lf_design_eval(d, use, &c->without[i], &err) != LF_OK)
            cli_die(CLI_EXIT_FAIL, "design: %s", err.msg);
        c->done[i] = 1;
    }
    free(use);
}

static void
text_contributions(FILE *f, const lf_design_plan *plan, const lf_design_result *all,
                   const contributions *c)
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
        fprintf(f, "  %-12s %-14s %-14s %-14s ", vb, rel_text(a, sizeof a, &res[v].w, 0),
                rel_text(b, sizeof b, &res[v].Estar, 0), rel_text(d, sizeof d, &res[v].nu, 1));
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
    design_args a;
    const cli_opt opts[] = {
        { "w", CLI_ADHESION, &a.w }, { "E", CLI_PRESSURE, &a.E }, { "nu", CLI_NUMBER, &a.nu },
        { "fix-nu", CLI_FLAG, &a.fix_nu }, { "noise", CLI_STRING, &a.noise },
        { "points", CLI_COUNT, &a.points }, { "delta-max", CLI_LENGTH, &a.delta_max },
        { "model", CLI_STRING, &a.model }, { "model-tol", CLI_NUMBER, &a.model_tol },
        { "choose", CLI_COUNT, &a.choose }, { "target", CLI_STRING, &a.target },
        { "grid", CLI_STRING, &a.grid }, { "vary", CLI_STRING, &a.vary },
        { "plot", CLI_STRING, &a.plot }, { "csv", CLI_STRING, &a.csv },
        { "json", CLI_STRING, &a.json }, { NULL, CLI_FLAG, NULL }
    };
    lf_design_settings s = lf_design_settings_default();
    lf_design_plan *plan = NULL;
    lf_design *d = NULL;
    lf_design_result all;
    contributions con = { 0, NULL, NULL };
    lf_design_choice choice;
    lf_design_result chosen_r, *sweep = NULL;
    lf_design_factor factor = LF_FACTOR_K;
    lf_design_target target = LF_TARGET_W;
    lf_error err;
    double values[MAX_GRID];
    size_t nv = 0, i, which = (size_t) -1, nsets = 1;
    int npos, help, exh_status = -1, *best = NULL;
    char scope[128] = "every candidate", a1[48], a2[48], l[96];
    FILE *out = stdout;

    memset(&a, 0, sizeof a);
    a.w = a.E = a.nu = a.delta_max = a.model_tol = NAN;
    a.points = a.choose = -1;
    a.model = "auto";
    a.target = "w";
    memset(&choice, 0, sizeof choice);
    memset(&chosen_r, 0, sizeof chosen_r);
    cli_parse("design", argc, argv, opts, &npos, &help);
    if (help) {
        fputs(usage_text, stdout);
        return CLI_EXIT_OK;
    }
    if (npos != 1)
        cli_die(CLI_EXIT_USAGE, "design: give one design plan (see 'layerfit design --help')");
    a.plan = argv[0];
    if (isnan(a.w) || isnan(a.E))
        cli_die(CLI_EXIT_USAGE, "design: --w and --E are required (e.g. --w 10mJ/m2 --E 1GPa)");
    if (!(a.w > 0))
        cli_die(CLI_EXIT_USAGE, "design: --w must be > 0 (its error is given relative to it)");
    if (!(a.E > 0))
        cli_die(CLI_EXIT_USAGE, "design: --E must be > 0");
    s.truth.w = a.w;
    s.truth.Estar = a.E;
    if (!isnan(a.nu)) {
        if (!(a.nu >= 0 && a.nu < 0.5))
            cli_die(CLI_EXIT_USAGE, "design: --nu must lie in [0, 0.5) (got %g)", a.nu);
        s.truth.nu = a.nu;
    }
    s.fix_nu = a.fix_nu;
    if (a.noise != NULL)
        parse_noise(a.noise, &s);
    if (a.points >= 0) {
        if (a.points < 5)
            cli_die(CLI_EXIT_USAGE, "design: --points must be at least 5");
        s.points = (size_t) a.points;
    }
    if (!isnan(a.delta_max)) {
        if (!(a.delta_max > 0))
            cli_die(CLI_EXIT_USAGE, "design: --delta-max must be > 0 (e.g. --delta-max 50nm)");
        s.delta_max = a.delta_max;
    }
    if (strcmp(a.model, "auto") != 0) {
        s.model = lf_model_type_find(a.model);
        if (s.model == NULL)
            cli_die(CLI_EXIT_USAGE, "design: unknown model '%s' (auto, thin, exact, halfspace)", a.model);
    }
    if (!isnan(a.model_tol)) {
        if (!(a.model_tol > 0))
            cli_die(CLI_EXIT_USAGE, "design: --model-tol must be > 0 (e.g. --model-tol 0.2)");
        if (s.model != NULL)
            cli_die(CLI_EXIT_USAGE, "design: --model-tol applies to --model auto only");
        s.choose.tol = a.model_tol;
    }
    if (lf_design_target_find(a.target) < 0)
        cli_die(CLI_EXIT_USAGE, "design: --target must be w, E, nu or all (got '%s')", a.target);
    target = (lf_design_target) lf_design_target_find(a.target);
    if (a.grid != NULL && a.choose >= 0)
        cli_die(CLI_EXIT_USAGE, "design: --grid and --choose are separate questions (give one)");
    if ((a.plot != NULL || a.csv != NULL || a.vary != NULL) && a.grid == NULL)
        cli_die(CLI_EXIT_USAGE, "design: --plot, --csv and --vary go with --grid");
    if (a.plot != NULL && plot_terminal(a.plot) == NULL)
        cli_die(CLI_EXIT_USAGE, "design: --plot %s: the file must end in .svg or .png", a.plot);
    if (a.grid != NULL)
        nv = parse_grid(a.grid, &factor, values);
    {
        lf_input in;
        cli_input_guard("design", a.plan);
        if (lf_input_read(a.plan, LF_INPUT_STREAM | LF_INPUT_TEXT, &in, &err) != LF_OK)
            cli_die_error(CLI_EXIT_USAGE, &err);
        cli_input_note(a.plan, in.sha256);
        cli_output_note("design", a.json);
        cli_output_note("design", a.csv);
        cli_output_note("design", a.plot);
        if (lf_design_plan_parse(in.data, in.len, a.plan, &plan, &err) != LF_OK)
            cli_die_error(CLI_EXIT_USAGE, &err);
        lf_input_free(&in);
    }
    if (a.choose == 0 || (a.choose > 0 && (size_t) a.choose > plan->n))
        cli_die(CLI_EXIT_USAGE, "design: --choose must lie between 1 and the %zu candidates",
                plan->n);
    if (a.vary != NULL) {
        char *end;
        long k = strtol(a.vary, &end, 10);
        for (i = 0; i < plan->n; i++)
            if (strcmp(plan->rows[i].name, a.vary) == 0)
                which = i;
        if (which == (size_t) -1 && *end == '\0' && end != a.vary && k >= 1 && (size_t) k <= plan->n)
            which = (size_t) k - 1;
        if (which == (size_t) -1)
            cli_die(CLI_EXIT_USAGE, "design: --vary %s: no candidate of that name or number", a.vary);
        snprintf(scope, sizeof scope, "candidate %s", cand_label(l, sizeof l, &plan->rows[which], which));
    }

    d = lf_design_alloc(&s, plan->n, plan->rows, &err);
    if (d == NULL)
        cli_die(err.status == LF_ENOMEM || err.status == LF_ENUMERIC ? CLI_EXIT_FAIL : CLI_EXIT_USAGE,
                "design: %s", err.msg);
    if (lf_design_eval(d, NULL, &all, &err) != LF_OK)
        cli_die(CLI_EXIT_FAIL, "design: %s", err.msg);
    compute_contributions(d, plan->n, &con);
    if (a.choose > 0) {
        if (lf_design_choose(d, (size_t) a.choose, target, &choice, &err) != LF_OK)
            cli_die(CLI_EXIT_FAIL, "design: %s", err.msg);
        best = calloc(plan->n, sizeof *best);
        if (best == NULL)
            cli_die(CLI_EXIT_FAIL, "design: out of memory");
        for (i = 0; i < (size_t) a.choose; i++)
            nsets = nsets * (plan->n - i) / (i + 1);
        if (nsets <= 2000) {
            lf_design_score sc;
            exh_status = lf_design_exhaustive(d, (size_t) a.choose, target, 2000, best, &sc, &err);
            if (exh_status != LF_OK)
                cli_die(CLI_EXIT_FAIL, "design: %s", err.msg);
        }
        if (lf_design_eval(d, choice.chosen, &chosen_r, &err) != LF_OK)
            cli_die(CLI_EXIT_FAIL, "design: %s", err.msg);
    }
    if (nv > 0) {
        sweep = calloc(nv, sizeof *sweep);
        if (sweep == NULL)
            cli_die(CLI_EXIT_FAIL, "design: out of memory");
        if (lf_design_sweep(&s, plan->n, plan->rows, factor, which, nv, values, sweep, &err) != LF_OK)
            cli_die(err.status == LF_EINVAL ? CLI_EXIT_USAGE : CLI_EXIT_FAIL, "design: --grid: %s",
                    err.msg);
    }

    /* the text, unless standard output carries --json - or --csv - */
    if (!(a.json != NULL && strcmp(a.json, "-") == 0) && !(a.csv != NULL && strcmp(a.csv, "-") == 0)) {
        fprintf(out, "layerfit design: %zu candidate%s; truth w = %s, E* = %s, nu = %.4g%s; noise ",
                plan->n, plan->n == 1 ? "" : "s", cli_human(a1, sizeof a1, s.truth.w, "J/m^2"),
                cli_human(a2, sizeof a2, s.truth.Estar, "Pa"), s.truth.nu, s.fix_nu ? " (held)" : "");
        if (isfinite(s.noise_abs))
            fprintf(out, "sd %s", cli_human(a1, sizeof a1, s.noise_abs, "N"));
        else
            fprintf(out, "%.3g%% of each curve's largest |force|", 100.0 * s.noise_rel);
        fprintf(out, "; model %s\n", s.model ? s.model->name : "auto");
        text_curves(out, plan, &all);
        text_set(out, "the whole set", &all, plan, &s);
        text_contributions(out, plan, &all, &con);
        if (a.choose > 0) {
            text_choice(out, plan, &choice, target, exh_status, best, nsets);
            text_set(out, "the chosen set", &chosen_r, plan, &s);
        }
        if (nv > 0)
            text_sweep(out, factor, nv, values, sweep, scope);
    }
    if (a.csv != NULL)
        csv_sweep(a.csv, factor, nv, values, sweep);
    if (a.plot != NULL)
        draw_sweep(a.plot, factor, nv, values, sweep, scope);
    if (a.json != NULL) {
        cli_out o;
        char msg[4400];
        FILE *f = cli_out_open(&o, a.json, msg, sizeof msg);
        if (f == NULL)
            cli_die(CLI_EXIT_FAIL, "design: %s", msg);
        fputs("{\n  \"truth\": {\"w_J_m2\": ", f);
        report_json_number(f, s.truth.w);
        fputs(", \"Estar_Pa\": ", f);
        report_json_number(f, s.truth.Estar);
        fputs(", \"nu\": ", f);
        report_json_number(f, s.truth.nu);
        fprintf(f, ", \"nu_held\": %s},\n  \"noise\": {\"relative\": ", s.fix_nu ? "true" : "false");
        report_json_number(f, isfinite(s.noise_abs) ? NAN : s.noise_rel);
        fputs(", \"sd_N\": ", f);
        report_json_number(f, s.noise_abs);
        fputs("},\n  \"model\": ", f);
        report_json_string(f, s.model ? s.model->name : "auto");
        fputs(",\n  \"set\": ", f);
        json_set(f, &all, 1, plan);
        fputs(",\n  \"without\": [", f);
        for (i = 0; i < con.n; i++) {
            if (!con.done[i])
                continue;
            fprintf(f, "%s\n    {\"row\": %zu, \"set\": ", i ? "," : "", i + 1);
            json_set(f, &con.without[i], 0, plan);
            fputs("}", f);
        }
        fputs(con.n > 1 ? "\n  ]" : "]", f);
        if (a.choose > 0) {
            size_t st;
            fprintf(f, ",\n  \"choice\": {\"target\": \"%s\", \"steps\": [",
                    lf_design_target_name(target));
            for (st = 0; st < choice.nsteps; st++) {
                const lf_design_step *sp = &choice.steps[st];
                fprintf(f, "%s\n    {\"added\": %zu, \"score\": ", st ? "," : "", sp->added + 1);
                report_json_number(f, sp->score.target_determined ? sp->score.value : NAN);
                fputs(", ", f);
                json_estimate(f, "w", &sp->w, ", ");
                json_estimate(f, "Estar", &sp->Estar, ", ");
                json_estimate(f, "nu", &sp->nu, ", \"runner_up\": ");
                if (sp->runner_up == (size_t) -1)
                    fputs("null}", f);
                else
                    fprintf(f, "%zu}", sp->runner_up + 1);
            }
            fputs("\n  ], \"chosen\": [", f);
            for (i = 0, st = 0; i < plan->n; i++)
                if (choice.chosen[i])
                    fprintf(f, "%s%zu", st++ ? ", " : "", i + 1);
            fputs("], \"exhaustive_best\": ", f);
            if (exh_status == LF_OK) {
                fputc('[', f);
                for (i = 0, st = 0; i < plan->n; i++)
                    if (best[i])
                        fprintf(f, "%s%zu", st++ ? ", " : "", i + 1);
                fputc(']', f);
            } else {
                fputs("null", f);
            }
            fputs(", \"set\": ", f);
            json_set(f, &chosen_r, 0, plan);
            fputs("}", f);
        }
        if (nv > 0) {
            size_t v;
            fprintf(f, ",\n  \"sweep\": {\"factor\": \"%s\", \"candidate\": ",
                    lf_design_factor_name(factor));
            if (which == (size_t) -1)
                fputs("null", f);
            else
                fprintf(f, "%zu", which + 1);
            fputs(", \"points\": [", f);
            for (v = 0; v < nv; v++) {
                fprintf(f, "%s\n    {\"value\": ", v ? "," : "");
                report_json_number(f, values[v]);
                fputs(", \"set\": ", f);
                json_set(f, &sweep[v], 0, plan);
                fputs("}", f);
            }
            fputs("\n  ]}", f);
        }
        fputs(",\n  \"provenance\": ", f);
        cli_provenance_json(f, "  ", command_line);
        fputs("\n}\n", f);
        if (cli_out_commit(&o, msg, sizeof msg) != 0)
            cli_die(CLI_EXIT_FAIL, "design: %s", msg);
    }

    lf_design_result_free(&all);
    for (i = 0; i < con.n; i++)
        lf_design_result_free(&con.without[i]);
    free(con.without);
    free(con.done);
    lf_design_choice_free(&choice);
    lf_design_result_free(&chosen_r);
    for (i = 0; i < nv; i++)
        lf_design_result_free(&sweep[i]);
    free(sweep);
    free(best);
    lf_design_free(d);
    lf_design_plan_free(plan);
    return CLI_EXIT_OK;
}
