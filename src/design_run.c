/* design_run.c: what `layerfit design PLAN` answers, for the command and
 * for bindings alike: its options by name (lf_design_option_table), the
 * whole set of candidates, what each adds (the set without it), a greedy
 * choice checked against an exhaustive search of small sets, a sweep of a
 * factor, and the --json document of it all (lf_design_run,
 * lf_design_report_json in layerfit.h).  The predictions are fit/design.c's. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "internal.h"

#define MAX_GRID 200

enum {
    D_W, D_E, D_NU, D_FIX_NU, D_NOISE, D_POINTS, D_DELTA_MAX, D_MODEL, D_MODEL_TOL, D_CHOOSE,
    D_TARGET, D_GRID, D_VARY, D_COUNT
};

const lf_option lf_design_option_table[] = {
    { "w", LF_OPTION_QUANTITY, LF_Q_ADHESION },
    { "E", LF_OPTION_QUANTITY, LF_Q_PRESSURE },
    { "nu", LF_OPTION_NUMBER, LF_Q_DIMENSIONLESS },
    { "fix-nu", LF_OPTION_FLAG, LF_Q_DIMENSIONLESS },
    { "noise", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "points", LF_OPTION_COUNT, LF_Q_DIMENSIONLESS },
    { "delta-max", LF_OPTION_QUANTITY, LF_Q_LENGTH },
    { "model", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "model-tol", LF_OPTION_NUMBER, LF_Q_DIMENSIONLESS },
    { "choose", LF_OPTION_COUNT, LF_Q_DIMENSIONLESS },
    { "target", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "grid", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "vary", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { NULL, LF_OPTION_FLAG, LF_Q_DIMENSIONLESS }
};

struct lf_design_options {
    char *text[D_COUNT];
    double value[D_COUNT];
};

lf_design_options *
lf_design_options_alloc(void)
{
    lf_design_options *o = calloc(1, sizeof *o);
    size_t i;

    if (o != NULL)
        for (i = 0; i < D_COUNT; i++)
            o->value[i] = NAN;
    return o;
}

void
lf_design_options_free(lf_design_options *o)
{
    size_t i;

    if (o == NULL)
        return;
    for (i = 0; i < D_COUNT; i++)
        free(o->text[i]);
    free(o);
}

int
lf_design_options_set(lf_design_options *o, const char *name, const char *value, lf_error *err)
{
    return lf_optset_set(lf_design_option_table, o->text, o->value, name, value, err);
}

const char *
lf_design_options_get(const lf_design_options *o, const char *name)
{
    return lf_optset_get(lf_design_option_table, o->text, name);
}

/* "1%", "0.01" -> fraction; "2uN" -> force. */
static int
parse_noise(const char *text, lf_design_settings *s, lf_error *err)
{
    char buf[64], *end;
    size_t len = strlen(text);
    double v;
    lf_error e;

    if (len > 0 && len < sizeof buf && text[len - 1] == '%') {
        memcpy(buf, text, len - 1);
        buf[len - 1] = '\0';
        errno = 0;
        v = strtod(buf, &end);
        if (end != buf && *end == '\0' && errno == 0 && v > 0 && isfinite(v)) {
            s->noise_rel = v / 100.0;
            return LF_OK;
        }
    } else {
        errno = 0;
        v = strtod(text, &end);
        if (end != text && *end == '\0') {
            if (errno == 0 && v > 0 && isfinite(v)) {
                s->noise_rel = v;
                return LF_OK;
            }
        } else if (lf_units_parse(text, LF_Q_FORCE, &v, &e) == LF_OK && v > 0) {
            s->noise_abs = v;
            return LF_OK;
        }
    }
    return lf_fail(err, LF_EINVAL, "--noise: '%s' is not a positive fraction or force "
                   "(e.g. --noise 1%% or --noise 2uN)", text);
}

int
lf_design_options_settings(const lf_design_options *o, lf_design_settings *s, lf_error *err)
{
    const double *v = o->value;
    const char *model = o->text[D_MODEL] != NULL ? o->text[D_MODEL] : "auto";
    const char *target = o->text[D_TARGET] != NULL ? o->text[D_TARGET] : "w";
    int status;

    *s = lf_design_settings_default();
    if (isnan(v[D_W]) || isnan(v[D_E]))
        return lf_fail(err, LF_EINVAL, "--w and --E are required (e.g. --w 10mJ/m2 --E 1GPa)");
    if (!(v[D_W] > 0))
        return lf_fail(err, LF_EINVAL, "--w must be > 0 (its error is given relative to it)");
    if (!(v[D_E] > 0))
        return lf_fail(err, LF_EINVAL, "--E must be > 0");
    s->truth.w = v[D_W];
    s->truth.Estar = v[D_E];
    if (!isnan(v[D_NU])) {
        if (!(v[D_NU] >= 0 && v[D_NU] < 0.5))
            return lf_fail(err, LF_EINVAL, "--nu must lie in [0, 0.5) (got %g)", v[D_NU]);
        s->truth.nu = v[D_NU];
    }
    s->fix_nu = o->text[D_FIX_NU] != NULL;
    if (o->text[D_NOISE] != NULL && (status = parse_noise(o->text[D_NOISE], s, err)) != LF_OK)
        return status;
    if (!isnan(v[D_POINTS])) {
        if (v[D_POINTS] < 5)
            return lf_fail(err, LF_EINVAL, "--points must be at least 5");
        s->points = (size_t) v[D_POINTS];
    }
    if (!isnan(v[D_DELTA_MAX])) {
        if (!(v[D_DELTA_MAX] > 0))
            return lf_fail(err, LF_EINVAL, "--delta-max must be > 0 (e.g. --delta-max 50nm)");
        s->delta_max = v[D_DELTA_MAX];
    }
    if (strcmp(model, "auto") != 0 && (s->model = lf_model_type_find(model)) == NULL)
        return lf_fail(err, LF_EINVAL, "unknown model '%s' (auto, thin, exact, halfspace)", model);
    if (!isnan(v[D_MODEL_TOL])) {
        if (!(v[D_MODEL_TOL] > 0))
            return lf_fail(err, LF_EINVAL, "--model-tol must be > 0 (e.g. --model-tol 0.2)");
        if (s->model != NULL)
            return lf_fail(err, LF_EINVAL, "--model-tol applies to --model auto only");
        s->choose.tol = v[D_MODEL_TOL];
    }
    if (lf_design_target_find(target) < 0)
        return lf_fail(err, LF_EINVAL, "--target must be w, E, nu or all (got '%s')", target);
    if (o->text[D_GRID] != NULL && o->text[D_CHOOSE] != NULL)
        return lf_fail(err, LF_EINVAL, "--grid and --choose are separate questions (give one)");
    return LF_OK;
}

int
lf_design_options_grid(const lf_design_options *o, lf_design_factor *factor, double *values,
                       size_t *nv, lf_error *err)
{
    const char *text = o->text[D_GRID], *eq;
    char name[32], buf[512], *tok, *save = NULL;
    lf_quantity q;
    size_t n = 0, len;
    lf_error e;
    int f;

    *nv = 0;
    if (text == NULL)
        return LF_OK;
    eq = strchr(text, '=');
    if (eq == NULL || (len = (size_t) (eq - text)) == 0 || len >= sizeof name)
        return lf_fail(err, LF_EINVAL, "--grid '%s': expected FACTOR=VALUES (e.g. --grid "
                       "k=2,2.5,3 or --grid delta_max=20nm:200nm:10)", text);
    memcpy(name, text, len);
    name[len] = '\0';
    if ((f = lf_design_factor_find(name)) < 0)
        return lf_fail(err, LF_EINVAL, "--grid: unknown factor '%s' (k, delta_max, points, b, R "
                       "or baseline)", name);
    *factor = (lf_design_factor) f;
    q = lf_design_factor_quantity(*factor);
    if (strlen(eq + 1) >= sizeof buf)
        return lf_fail(err, LF_EINVAL, "--grid: too long");
    strcpy(buf, eq + 1);
    if (strchr(buf, ':') != NULL) {
        char *part[4], *end;
        double lo, hi;
        long count;
        int np = 0, logs = 0;
        for (tok = strtok_r(buf, ":", &save); tok != NULL && np < 4; tok = strtok_r(NULL, ":", &save))
            part[np++] = tok;
        if (np == 4 && strcmp(part[3], "log") == 0)
            logs = 1;
        else if (np != 3 || tok != NULL)
            return lf_fail(err, LF_EINVAL, "--grid '%s': a range is LO:HI:N or LO:HI:N:log", text);
        if (lf_units_parse(part[0], q, &lo, &e) != LF_OK
            || lf_units_parse(part[1], q, &hi, &e) != LF_OK)
            return lf_fail(err, LF_EINVAL, "--grid '%s': %s", text, e.msg);
        errno = 0;
        count = strtol(part[2], &end, 10);
        if (end == part[2] || *end != '\0' || errno != 0 || count < 2 || count > MAX_GRID)
            return lf_fail(err, LF_EINVAL, "--grid '%s': N must be a whole number from 2 to %d",
                           text, MAX_GRID);
        if (logs && !(lo > 0 && hi > 0))
            return lf_fail(err, LF_EINVAL, "--grid '%s': a log range needs LO, HI > 0", text);
        for (n = 0; n < (size_t) count; n++) {
            double t = (double) n / (double) (count - 1);
            values[n] = logs ? lo * pow(hi / lo, t) : lo + t * (hi - lo);
            if (*factor == LF_FACTOR_POINTS)
                values[n] = floor(values[n] + 0.5);
        }
        *nv = n;
        return LF_OK;
    }
    for (tok = strtok_r(buf, ",", &save); tok != NULL; tok = strtok_r(NULL, ",", &save)) {
        if (n == MAX_GRID)
            return lf_fail(err, LF_EINVAL, "--grid: at most %d values", MAX_GRID);
        if (lf_units_parse(tok, q, &values[n], &e) != LF_OK)
            return lf_fail(err, LF_EINVAL, "--grid '%s': %s", text, e.msg);
        n++;
    }
    if (n == 0)
        return lf_fail(err, LF_EINVAL, "--grid '%s': no values", text);
    *nv = n;
    return LF_OK;
}

void
lf_design_report_free(lf_design_report *r)
{
    size_t i;

    if (r == NULL)
        return;
    lf_design_result_free(&r->all);
    for (i = 0; r->without != NULL && i < r->n; i++)
        lf_design_result_free(&r->without[i]);
    free(r->without);
    free(r->without_done);
    lf_design_choice_free(&r->choice);
    lf_design_result_free(&r->chosen);
    for (i = 0; r->sweep != NULL && i < r->nsweep; i++)
        lf_design_result_free(&r->sweep[i]);
    free(r->sweep);
    free(r->values);
    free(r->best);
    free(r);
}

/* The set without each candidate in turn (what each adds). */
static int
contributions(lf_design *d, lf_design_report *r, lf_error *err)
{
    size_t n = r->n, i, k;
    int *use = malloc((n ? n : 1) * sizeof *use), status = LF_OK;

    r->without = calloc(n ? n : 1, sizeof *r->without);
    r->without_done = calloc(n ? n : 1, sizeof *r->without_done);
    if (use == NULL || r->without == NULL || r->without_done == NULL) {
        free(use);
        return lf_fail(err, LF_ENOMEM, "out of memory");
    }
    for (i = 0; i < n && n > 1 && status == LF_OK; i++) {
        for (k = 0; k < n; k++)
            use[k] = k != i;
        status = lf_design_eval(d, use, &r->without[i], err);
        r->without_done[i] = status == LF_OK;
    }
    free(use);
    return status;
}

int
lf_design_run(const lf_design_options *o, const lf_design_plan *plan, lf_design_report **out,
              lf_error *err)
{
    lf_design_report *r = calloc(1, sizeof *r);
    lf_design *d = NULL;
    const char *vary = o->text[D_VARY];
    double values[MAX_GRID];
    size_t i;
    int status;

    *out = NULL;
    if (r == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory");
    r->plan = plan;
    r->n = plan->n;
    r->which = (size_t) -1;
    r->target = (lf_design_target) lf_design_target_find(o->text[D_TARGET] ? o->text[D_TARGET]
                                                                            : "w");
    if ((status = lf_design_options_settings(o, &r->settings, err)) != LF_OK
        || (status = lf_design_options_grid(o, &r->factor, values, &r->nsweep, err)) != LF_OK)
        goto fail;
    if (vary != NULL && r->nsweep == 0) {
        status = lf_fail(err, LF_EINVAL, "--plot, --csv and --vary go with --grid");
        goto fail;
    }
    if (!isnan(o->value[D_CHOOSE])) {
        if (o->value[D_CHOOSE] < 1 || o->value[D_CHOOSE] > (double) plan->n) {
            status = lf_fail(err, LF_EINVAL, "--choose must lie between 1 and the %zu candidates",
                             plan->n);
            goto fail;
        }
        r->nchoose = (size_t) o->value[D_CHOOSE];
    }
    if (vary != NULL) {
        char *end;
        long k = strtol(vary, &end, 10);
        for (i = 0; i < plan->n; i++)
            if (strcmp(plan->rows[i].name, vary) == 0)
                r->which = i;
        if (r->which == (size_t) -1 && *end == '\0' && end != vary && k >= 1
            && (size_t) k <= plan->n)
            r->which = (size_t) k - 1;
        if (r->which == (size_t) -1) {
            status = lf_fail(err, LF_EINVAL, "--vary %s: no candidate of that name or number",
                             vary);
            goto fail;
        }
    }
    if ((d = lf_design_alloc(&r->settings, plan->n, plan->rows, err)) == NULL) {
        status = err != NULL ? err->status : LF_ENOMEM;
        goto fail;
    }
    if ((status = lf_design_eval(d, NULL, &r->all, err)) != LF_OK
        || (status = contributions(d, r, err)) != LF_OK)
        goto fail;
    if (r->nchoose > 0) {
        size_t nsets = 1;
        if ((status = lf_design_choose(d, r->nchoose, r->target, &r->choice, err)) != LF_OK)
            goto fail;
        if ((r->best = calloc(plan->n, sizeof *r->best)) == NULL) {
            status = lf_fail(err, LF_ENOMEM, "out of memory");
            goto fail;
        }
        for (i = 0; i < r->nchoose; i++)
            nsets = nsets * (plan->n - i) / (i + 1);
        r->nsets = nsets;
        if (nsets <= 2000) {
            lf_design_score sc;
            if ((status = lf_design_exhaustive(d, r->nchoose, r->target, 2000, r->best, &sc,
                                               err)) != LF_OK)
                goto fail;
            r->exhaustive = 1;
        }
        if ((status = lf_design_eval(d, r->choice.chosen, &r->chosen, err)) != LF_OK)
            goto fail;
    }
    if (r->nsweep > 0) {
        r->values = malloc(r->nsweep * sizeof *r->values);
        r->sweep = calloc(r->nsweep, sizeof *r->sweep);
        if (r->values == NULL || r->sweep == NULL) {
            status = lf_fail(err, LF_ENOMEM, "out of memory");
            goto fail;
        }
        memcpy(r->values, values, r->nsweep * sizeof *values);
        if ((status = lf_design_sweep(&r->settings, plan->n, plan->rows, r->factor, r->which,
                                      r->nsweep, r->values, r->sweep, err)) != LF_OK) {
            if (err != NULL) {
                char msg[sizeof err->msg];
                memcpy(msg, err->msg, sizeof msg);
                lf_fail(err, status, "--grid: %s", msg);
            }
            goto fail;
        }
    }
    lf_design_free(d);
    *out = r;
    return LF_OK;
fail:
    lf_design_free(d);
    lf_design_report_free(r);
    return status;
}

/* ---- the JSON document ---------------------------------------------------- */

static void
jestimate(lf_str *b, const char *name, const lf_design_estimate *e, const char *tail)
{
    lf_str_printf(b, "\"%s\": {\"free\": %s, \"determined\": %s, \"stderr\": ", name,
                  e->free ? "true" : "false", e->determined ? "true" : "false");
    lf_str_number(b, e->se, "null");
    lf_str_puts(b, ", \"relative_stderr\": ");
    lf_str_number(b, e->rel, "null");
    if (e->upper_bound_only)
        lf_str_puts(b, ", \"upper_bound_only\": true");
    if (e->why != NULL) {
        lf_str_puts(b, ", \"why_not_determined\": ");
        lf_str_json(b, e->why);
    }
    lf_str_printf(b, "}%s", tail);
}

static void
jwarnings(lf_str *b, const lf_warnings *w)
{
    size_t i;
    lf_str_puts(b, "[");
    for (i = 0; i < w->n; i++) {
        lf_str_puts(b, i ? ", " : "");
        lf_str_json(b, w->msg[i]);
    }
    lf_str_puts(b, "]");
}

/* One evaluated set: the predictions, and the candidates (in full, or
 * their row numbers). */
static void
jset(lf_str *b, const lf_design_result *r, int curves, const lf_design_plan *plan)
{
    size_t j;

    lf_str_puts(b, "{");
    jestimate(b, "w", &r->w, ", ");
    jestimate(b, "Estar", &r->Estar, ", ");
    jestimate(b, "nu", &r->nu, ", ");
    jestimate(b, "M", &r->M, ", ");
    lf_str_puts(b, "\"corr_w_Estar\": ");
    lf_str_number(b, r->corr_wE, "null");
    lf_str_printf(b, ", \"free_parameters\": %zu, \"determined\": %zu, \"log_det_information\": ",
                  r->npar, r->ndetermined);
    lf_str_number(b, r->logdet, "null");
    lf_str_puts(b, ", \"identifiability\": ");
    jwarnings(b, &r->identifiability);
    lf_str_puts(b, ", \"notes\": ");
    jwarnings(b, &r->notes);
    lf_str_puts(b, ", \"candidates\": [");
    for (j = 0; j < r->ncurves; j++) {
        const lf_design_curve_info *ci = &r->curves[j];
        const lf_design_candidate *cd = &plan->rows[ci->index];
        if (!curves) {
            lf_str_printf(b, "%s%zu", j ? ", " : "", ci->index + 1);
            continue;
        }
        lf_str_printf(b, "%s\n    {\"row\": %zu, \"name\": ", j ? "," : "", ci->index + 1);
        lf_str_json(b, cd->name);
        lf_str_puts(b, ", \"k\": ");
        lf_str_number(b, cd->probe.k, "null");
        lf_str_puts(b, ", \"R_m\": ");
        lf_str_number(b, cd->probe.R, "null");
        lf_str_puts(b, ", \"b_m\": ");
        lf_str_number(b, cd->probe.b, "null");
        lf_str_printf(b, ", \"interface\": \"%s\", \"branch\": \"%s\", \"points\": %zu, "
                      "\"points_past_detachment\": %zu, \"delta_min_m\": ",
                      cd->probe.base == LF_BASE_BONDED ? "bonded" : "frictionless",
                      cd->branch == LF_BRANCH_LOAD ? "load" : "unload", ci->n, ci->n_past);
        lf_str_number(b, ci->delta_lo, "null");
        lf_str_puts(b, ", \"delta_max_m\": ");
        lf_str_number(b, ci->delta_hi, "null");
        lf_str_puts(b, ", \"delta_detach_m\": ");
        lf_str_number(b, ci->delta_detach, "null");
        lf_str_printf(b, ", \"z0_free\": %s, \"F0_free\": %s, \"noise_sd_N\": ",
                      ci->free_z0 ? "true" : "false", ci->free_F0 ? "true" : "false");
        lf_str_number(b, ci->sigma, "null");
        lf_str_puts(b, ", \"max_force_N\": ");
        lf_str_number(b, ci->fmax, "null");
        lf_str_puts(b, ", \"model\": ");
        lf_str_json(b, ci->model->name);
        lf_str_puts(b, ", \"model_reason\": ");
        lf_str_json(b, ci->model_reason);
        lf_str_puts(b, ", \"thin_bias_se\": ");
        lf_str_number(b, ci->thin_bias, "null");
        lf_str_puts(b, ", \"b_over_a\": [");
        lf_str_number(b, ci->ba_min, "null");
        lf_str_puts(b, ", ");
        lf_str_number(b, ci->ba_max, "null");
        lf_str_puts(b, "], \"b_over_a_pulloff\": ");
        lf_str_number(b, ci->ba_pulloff, "null");
        lf_str_puts(b, "}");
    }
    lf_str_puts(b, curves ? "\n  ]}" : "]}");
}

int
lf_design_report_json(const lf_design_report *r, const lf_provenance *prov, char **json,
                      lf_error *err)
{
    const lf_design_settings *s = &r->settings;
    const lf_design_plan *plan = r->plan;
    lf_str b = { NULL, 0, 0, 0 };
    size_t i, st;

    lf_str_puts(&b, "{\n  \"truth\": {\"w_J_m2\": ");
    lf_str_number(&b, s->truth.w, "null");
    lf_str_puts(&b, ", \"Estar_Pa\": ");
    lf_str_number(&b, s->truth.Estar, "null");
    lf_str_puts(&b, ", \"nu\": ");
    lf_str_number(&b, s->truth.nu, "null");
    lf_str_printf(&b, ", \"nu_held\": %s},\n  \"noise\": {\"relative\": ",
                  s->fix_nu ? "true" : "false");
    lf_str_number(&b, isfinite(s->noise_abs) ? NAN : s->noise_rel, "null");
    lf_str_puts(&b, ", \"sd_N\": ");
    lf_str_number(&b, s->noise_abs, "null");
    lf_str_puts(&b, "},\n  \"model\": ");
    lf_str_json(&b, s->model ? s->model->name : "auto");
    lf_str_puts(&b, ",\n  \"set\": ");
    jset(&b, &r->all, 1, plan);
    lf_str_puts(&b, ",\n  \"without\": [");
    for (i = 0; i < r->n; i++) {
        if (!r->without_done[i])
            continue;
        lf_str_printf(&b, "%s\n    {\"row\": %zu, \"set\": ", i ? "," : "", i + 1);
        jset(&b, &r->without[i], 0, plan);
        lf_str_puts(&b, "}");
    }
    lf_str_puts(&b, r->n > 1 ? "\n  ]" : "]");
    if (r->nchoose > 0) {
        lf_str_printf(&b, ",\n  \"choice\": {\"target\": \"%s\", \"steps\": [",
                      lf_design_target_name(r->target));
        for (st = 0; st < r->choice.nsteps; st++) {
            const lf_design_step *sp = &r->choice.steps[st];
            lf_str_printf(&b, "%s\n    {\"added\": %zu, \"score\": ", st ? "," : "",
                          sp->added + 1);
            lf_str_number(&b, sp->score.target_determined ? sp->score.value : NAN, "null");
            lf_str_puts(&b, ", ");
            jestimate(&b, "w", &sp->w, ", ");
            jestimate(&b, "Estar", &sp->Estar, ", ");
            jestimate(&b, "nu", &sp->nu, ", \"runner_up\": ");
            if (sp->runner_up == (size_t) -1)
                lf_str_puts(&b, "null}");
            else
                lf_str_printf(&b, "%zu}", sp->runner_up + 1);
        }
        lf_str_puts(&b, "\n  ], \"chosen\": [");
        for (i = 0, st = 0; i < plan->n; i++)
            if (r->choice.chosen[i])
                lf_str_printf(&b, "%s%zu", st++ ? ", " : "", i + 1);
        lf_str_puts(&b, "], \"exhaustive_best\": ");
        if (r->exhaustive) {
            lf_str_puts(&b, "[");
            for (i = 0, st = 0; i < plan->n; i++)
                if (r->best[i])
                    lf_str_printf(&b, "%s%zu", st++ ? ", " : "", i + 1);
            lf_str_puts(&b, "]");
        } else {
            lf_str_puts(&b, "null");
        }
        lf_str_puts(&b, ", \"set\": ");
        jset(&b, &r->chosen, 0, plan);
        lf_str_puts(&b, "}");
    }
    if (r->nsweep > 0) {
        lf_str_printf(&b, ",\n  \"sweep\": {\"factor\": \"%s\", \"candidate\": ",
                      lf_design_factor_name(r->factor));
        if (r->which == (size_t) -1)
            lf_str_puts(&b, "null");
        else
            lf_str_printf(&b, "%zu", r->which + 1);
        lf_str_puts(&b, ", \"points\": [");
        for (i = 0; i < r->nsweep; i++) {
            lf_str_printf(&b, "%s\n    {\"value\": ", i ? "," : "");
            lf_str_number(&b, r->values[i], "null");
            lf_str_puts(&b, ", \"set\": ");
            jset(&b, &r->sweep[i], 0, plan);
            lf_str_puts(&b, "}");
        }
        lf_str_puts(&b, "\n  ]}");
    }
    if (prov != NULL) {
        lf_str_puts(&b, ",\n  \"provenance\": ");
        lf_str_provenance(&b, "  ", prov);
    }
    lf_str_puts(&b, "\n}\n");
    return lf_str_take(&b, json, err);
}
