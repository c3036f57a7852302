/* fit_options.c: the options of `layerfit fit`, one table for the command
 * and for programs and bindings, which set them by name from text as the
 * command line gives them and get the settings of the fit they ask for
 * (lf_fit_options_request), the probe of a single curve
 * (lf_fit_options_probe), and the fit itself as the command makes it
 * (lf_fit_request_run).  See layerfit.h. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "internal.h"

/* The options in the order of lf_fit_option_table. */
enum {
    O_METHOD, O_JACOBIAN, O_MODEL, O_SEGMENT, O_NU, O_FIX_NU, O_FIX_Z0, O_FIX_F0, O_MAX_BA,
    O_MODEL_TOL, O_SLOPE, O_MAX_ITER, O_GUESS_W, O_GUESS_E, O_GUESS_NU, O_LOSS, O_LOSS_SCALE,
    O_INTERVALS, O_FORMAT, O_SPRING, O_SENSITIVITY, O_DEPTH_UNIT, O_FORCE_UNIT, O_SKIP_BAD,
    O_K, O_R, O_B, O_INTERFACE, O_TIP, O_HALF_ANGLE, O_PREFACTOR, O_DEPTH_RANGE, O_FORCE_RANGE,
    O_SAMPLE, O_GROUP_BY, O_MODEL_EACH, O_COUNT
};

const lf_option lf_fit_option_table[] = {
    { "method", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "jacobian", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "model", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "segment", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "nu", LF_OPTION_NUMBER, LF_Q_DIMENSIONLESS },
    { "fix-nu", LF_OPTION_NUMBER, LF_Q_DIMENSIONLESS },
    { "fix-z0", LF_OPTION_QUANTITY, LF_Q_LENGTH },
    { "fix-F0", LF_OPTION_QUANTITY, LF_Q_FORCE },
    { "max-b-over-a", LF_OPTION_NUMBER, LF_Q_DIMENSIONLESS },
    { "model-tol", LF_OPTION_NUMBER, LF_Q_DIMENSIONLESS },
    { "slope", LF_OPTION_FLAG, LF_Q_DIMENSIONLESS },
    { "max-iter", LF_OPTION_COUNT, LF_Q_DIMENSIONLESS },
    { "guess-w", LF_OPTION_QUANTITY, LF_Q_ADHESION },
    { "guess-E", LF_OPTION_QUANTITY, LF_Q_PRESSURE },
    { "guess-nu", LF_OPTION_NUMBER, LF_Q_DIMENSIONLESS },
    { "loss", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "loss-scale", LF_OPTION_NUMBER, LF_Q_DIMENSIONLESS },
    { "intervals", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "format", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "spring-constant", LF_OPTION_TEXT, LF_Q_STIFFNESS },
    { "sensitivity", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "depth-unit", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "force-unit", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "skip-bad-rows", LF_OPTION_FLAG, LF_Q_DIMENSIONLESS },
    { "k", LF_OPTION_NUMBER, LF_Q_DIMENSIONLESS },
    { "R", LF_OPTION_QUANTITY, LF_Q_LENGTH },
    { "b", LF_OPTION_QUANTITY, LF_Q_LENGTH },
    { "interface", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "tip", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "half-angle", LF_OPTION_QUANTITY, LF_Q_ANGLE },
    { "B", LF_OPTION_NUMBER, LF_Q_DIMENSIONLESS },
    { "depth-range", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "force-range", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "sample", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "group-by", LF_OPTION_TEXT, LF_Q_DIMENSIONLESS },
    { "model-each", LF_OPTION_FLAG, LF_Q_DIMENSIONLESS },
    { NULL, LF_OPTION_FLAG, LF_Q_DIMENSIONLESS }
};

/* What each option holds: its text (a copy, NULL when not given) and,
 * for numbers, its value (NaN when not given). */
struct lf_fit_options {
    char *text[O_COUNT];
    double value[O_COUNT];
    lf_read_opts read;          /* filled by lf_fit_options_read */
    lf_fit_request req;         /* filled by lf_fit_options_checked */
};

/* The default words of the text options (NULL: none). */
static const char *
default_text(size_t i)
{
    switch (i) {
    case O_METHOD:    return "lm";
    case O_JACOBIAN:  return "analytic";
    case O_MODEL:     return "auto";
    case O_LOSS:      return "linear";
    case O_INTERVALS: return "auto";
    default:          return NULL;
    }
}

lf_fit_options *
lf_fit_options_alloc(void)
{
    lf_fit_options *o = calloc(1, sizeof *o);
    size_t i;

    if (o == NULL)
        return NULL;
    for (i = 0; i < O_COUNT; i++)
        o->value[i] = NAN;
    lf_read_opts_default(&o->read);
    return o;
}

void
lf_fit_options_free(lf_fit_options *o)
{
    size_t i;

    if (o == NULL)
        return;
    for (i = 0; i < O_COUNT; i++)
        free(o->text[i]);
    free(o);
}

const char *
lf_fit_options_get(const lf_fit_options *o, const char *name)
{
    return lf_optset_get(lf_fit_option_table, o->text, name);
}

/* An option's text: as given, or its default. */
static const char *
text_of(const lf_fit_options *o, size_t i)
{
    return o->text[i] != NULL ? o->text[i] : default_text(i);
}

int
lf_option_number(const lf_option *opt, const char *text, double *x, lf_error *err)
{
    char *end;
    lf_error e;

    switch (opt->kind) {
    case LF_OPTION_NUMBER:
        errno = 0;
        *x = strtod(text, &end);
        if (end == text || *end != '\0' || errno == ERANGE || !isfinite(*x))
            return lf_fail(err, LF_EINVAL, "--%s: '%s' is not a number (e.g. --%s 0.3)",
                           opt->name, text, opt->name);
        return LF_OK;
    case LF_OPTION_COUNT: {
        long v;
        errno = 0;
        v = strtol(text, &end, 10);
        if (end == text || *end != '\0' || errno == ERANGE || v < 0)
            return lf_fail(err, LF_EINVAL, "--%s: '%s' is not a whole number >= 0 (e.g. --%s 200)",
                           opt->name, text, opt->name);
        *x = (double) v;
        return LF_OK;
    }
    case LF_OPTION_QUANTITY:
        if (lf_units_parse(text, opt->quantity, x, &e) != LF_OK)
            return lf_fail(err, e.status, "--%s: %s", opt->name, e.msg);
        return LF_OK;
    default:
        return lf_fail(err, LF_EINVAL, "--%s takes no number", opt->name);
    }
}

int
lf_optset_set(const lf_option *table, char **text, double *values, const char *name,
              const char *value, lf_error *err)
{
    const lf_option *opt;
    size_t i;
    char *copy;
    double x = NAN;
    int status;

    for (i = 0; table[i].name != NULL; i++)
        if (strcmp(table[i].name, name) == 0)
            break;
    opt = &table[i];
    if (opt->name == NULL)
        return lf_fail(err, LF_EINVAL, "unknown option '--%s'", name);
    if (opt->kind == LF_OPTION_FLAG) {
        if (value != NULL)
            return lf_fail(err, LF_EINVAL, "--%s takes no value", opt->name);
        value = "1";
    } else if (value == NULL) {
        return lf_fail(err, LF_EINVAL, "--%s needs a value", opt->name);
    } else if (opt->kind != LF_OPTION_TEXT
               && (status = lf_option_number(opt, value, &x, err)) != LF_OK) {
        return status;
    }
    if ((copy = lf_strdup(value)) == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory");
    free(text[i]);
    text[i] = copy;
    values[i] = x;
    return LF_OK;
}

const char *
lf_optset_get(const lf_option *table, char *const *text, const char *name)
{
    size_t i;

    for (i = 0; table[i].name != NULL; i++)
        if (strcmp(table[i].name, name) == 0)
            return text[i];
    return NULL;
}

int
lf_fit_options_set(lf_fit_options *o, const char *name, const char *value, lf_error *err)
{
    return lf_optset_set(lf_fit_option_table, o->text, o->value, name, value, err);
}

/* "csv, chiaro, ..." of every reader, for a message. */
static void
reader_names(char *list, size_t n)
{
    size_t r, len = 0;

    list[0] = '\0';
    for (r = 0; lf_reader_types[r] != NULL; r++)
        len += (size_t) snprintf(list + len, len < n ? n - len : 0, "%s%s", r ? ", " : "",
                                 lf_reader_types[r]->name);
}

const lf_read_opts *
lf_fit_options_read(lf_fit_options *o, lf_error *err)
{
    lf_error e;

    lf_read_opts_default(&o->read);
    o->read.format = o->text[O_FORMAT];
    if (o->read.format != NULL && lf_reader_find(o->read.format) == NULL) {
        char list[400];
        reader_names(list, sizeof list);
        lf_fail(err, LF_EINVAL, "unknown format '%s' (%s)", o->read.format, list);
        return NULL;
    }
    o->read.depth_unit = o->text[O_DEPTH_UNIT];
    o->read.force_unit = o->text[O_FORCE_UNIT];
    o->read.skip_bad_rows = o->text[O_SKIP_BAD] != NULL;
    if (lf_read_opts_constants(&o->read, o->text[O_SPRING], o->text[O_SENSITIVITY], &e) != LF_OK) {
        lf_fail(err, e.status, "%s", e.msg);
        return NULL;
    }
    return &o->read;
}

const lf_fit_request *
lf_fit_options_checked(lf_fit_options *o, lf_error *err)
{
    return lf_fit_options_request(o, &o->req, err) == LF_OK ? &o->req : NULL;
}

int
lf_fit_options_request(lf_fit_options *o, lf_fit_request *req, lf_error *err)
{
    lf_fit_settings *s = &req->fit;
    lf_choose_settings *cs = &req->choose;
    lf_input_settings *is = &req->input;
    const char *model = text_of(o, O_MODEL), *method = text_of(o, O_METHOD);
    const char *jac = text_of(o, O_JACOBIAN), *intervals = text_of(o, O_INTERVALS);
    const char *segment = text_of(o, O_SEGMENT), *loss = text_of(o, O_LOSS);
    const double *v = o->value;
    double nu;
    size_t i;
    lf_error e;

    *s = lf_fit_settings_default();
    *cs = lf_choose_settings_default();
    *is = lf_input_settings_default();
    req->model = model;
    req->nu_option = NULL;
    req->model_auto = strcmp(model, "auto") == 0;
    s->model = req->model_auto ? &lf_model_thin : lf_model_type_find(model);
    if (s->model == NULL)
        return lf_fail(err, LF_EINVAL, "unknown model '%s' (auto, thin, exact, halfspace)", model);
    for (i = 0; lf_fit_methods[i] != NULL; i++)
        if (strcmp(lf_fit_methods[i], method) == 0)
            break;
    if (lf_fit_methods[i] == NULL)
        return lf_fail(err, LF_EINVAL, "unknown method '%s' (lm, lmaccel, dogleg, ddogleg, "
                       "subspace2D)", method);
    s->method = lf_fit_methods[i];
    if (strcmp(jac, "analytic") == 0)
        s->jacobian = LF_JAC_ANALYTIC;
    else if (strcmp(jac, "forward") == 0)
        s->jacobian = LF_JAC_FORWARD;
    else if (strcmp(jac, "central") == 0)
        s->jacobian = LF_JAC_CENTRAL;
    else
        return lf_fail(err, LF_EINVAL, "--jacobian must be analytic, forward or central (got "
                       "'%s')", jac);
    if (!isnan(v[O_MAX_BA])) {
        if (!(v[O_MAX_BA] > 0))
            return lf_fail(err, LF_EINVAL, "--max-b-over-a must be > 0 (e.g. --max-b-over-a 0.1)");
        s->max_b_over_a = v[O_MAX_BA];
    }
    if (!isnan(v[O_MODEL_TOL])) {
        if (!(v[O_MODEL_TOL] > 0) || !isfinite(v[O_MODEL_TOL]))
            return lf_fail(err, LF_EINVAL, "--model-tol must be a number > 0 (e.g. --model-tol 0.2)");
        if (!req->model_auto)
            return lf_fail(err, LF_EINVAL, "--model-tol applies to --model auto only");
        cs->tol = v[O_MODEL_TOL];
    }
    if (o->text[O_MODEL_EACH] != NULL) {
        if (!req->model_auto)
            return lf_fail(err, LF_EINVAL, "--model-each applies to --model auto only");
        cs->each = 1;
    }
    if (strcmp(intervals, "auto") == 0)
        req->profile = LF_PROFILE_CHECK;
    else if (strcmp(intervals, "linear") == 0)
        req->profile = LF_PROFILE_LINEAR;
    else
        return lf_fail(err, LF_EINVAL, "--intervals must be auto or linear (got '%s')", intervals);
    if (segment != NULL) {
        /* the words of a plan's segment column */
        int seg = lf_segment_find(segment);
        if (seg == LF_SEG_HOLD)
            return lf_fail(err, LF_EINVAL, "--segment %s is a hold, which is never fitted "
                           "(unload, retract or withdraw; load, approach or extend)", segment);
        if (seg < 0)
            return lf_fail(err, LF_EINVAL, "--segment must be unload (retract, withdraw) or load "
                           "(approach, extend) (got '%s')", segment);
        is->segment = seg;
    }
    if (o->text[O_DEPTH_RANGE] != NULL
        && lf_range_parse(o->text[O_DEPTH_RANGE], LF_Q_LENGTH, &is->window.depth, &e) != LF_OK)
        return lf_fail(err, e.status, "--depth-range: %s", e.msg);
    if (o->text[O_FORCE_RANGE] != NULL
        && lf_range_parse(o->text[O_FORCE_RANGE], LF_Q_FORCE, &is->window.force, &e) != LF_OK)
        return lf_fail(err, e.status, "--force-range: %s", e.msg);
    is->z0 = v[O_FIX_Z0];
    is->F0 = v[O_FIX_F0];
    is->min_points = LF_FIT_MIN_POINTS;     /* the same test as `layerfit check` */
    if ((is->read = lf_fit_options_read(o, err)) == NULL)
        return err != NULL ? err->status : LF_EINVAL;
    s->fit_slope = o->text[O_SLOPE] != NULL;
    if (!isnan(v[O_GUESS_W]) && !(v[O_GUESS_W] > 0))
        return lf_fail(err, LF_EINVAL, "--guess-w must be > 0 (e.g. --guess-w 10mJ/m2)");
    if (!isnan(v[O_GUESS_E]) && !(v[O_GUESS_E] > 0))
        return lf_fail(err, LF_EINVAL, "--guess-E must be > 0 (e.g. --guess-E 1GPa)");
    if (!isnan(v[O_GUESS_NU]) && !(v[O_GUESS_NU] > 0 && v[O_GUESS_NU] < 0.5))
        return lf_fail(err, LF_EINVAL, "--guess-nu must lie in (0, 0.5) (e.g. --guess-nu 0.3)");
    if (lf_loss_find(loss) < 0)
        return lf_fail(err, LF_EINVAL, "--loss must be linear, huber or cauchy (got '%s')", loss);
    s->loss = (lf_loss) lf_loss_find(loss);
    if (!isnan(v[O_LOSS_SCALE]) && !(v[O_LOSS_SCALE] > 0))
        return lf_fail(err, LF_EINVAL, "--loss-scale must be > 0 (e.g. --loss-scale 1.345)");
    s->loss_scale = v[O_LOSS_SCALE];
    s->w.guess = v[O_GUESS_W];
    s->Estar.guess = v[O_GUESS_E];
    s->nu.guess = v[O_GUESS_NU];
    if (v[O_MAX_ITER] == 0)
        return lf_fail(err, LF_EINVAL, "--max-iter: '0' is not a whole number >= 1 (e.g. "
                       "--max-iter 200)");
    if (v[O_MAX_ITER] > 0)
        s->max_iter = (size_t) v[O_MAX_ITER];
    /* nu given holds it (and wins over a plan's nu column) */
    nu = !isnan(v[O_FIX_NU]) ? v[O_FIX_NU] : v[O_NU];
    if (!isnan(nu)) {
        if (!(nu >= 0 && nu < 0.5))
            return lf_fail(err, LF_EINVAL, "nu must lie in [0, 0.5) (got %g)", nu);
        s->nu.mode = LF_PARAM_FIXED;
        s->nu.value = nu;
    }
    req->nu_option = !isnan(v[O_FIX_NU]) ? "--fix-nu" : !isnan(v[O_NU]) ? "--nu" : NULL;
    return LF_OK;
}

void
lf_fit_options_statement(const lf_fit_options *o, lf_probe_statement *a)
{
    const lf_model_type *t = lf_model_type_find(text_of(o, O_MODEL));

    a->k = o->value[O_K];
    a->R = o->value[O_R];
    a->B = o->value[O_PREFACTOR];
    a->half_angle = o->value[O_HALF_ANGLE];
    a->b = o->value[O_B];
    a->tip = o->text[O_TIP];
    a->interface = o->text[O_INTERFACE];
    a->model = text_of(o, O_MODEL);
    a->halfspace = t != NULL && t->scope == LF_SCOPE_HALFSPACE;
}

int
lf_fit_options_probe(const lf_fit_options *o, lf_probe *p, int *single, lf_error *err)
{
    lf_probe_statement a;
    int status;

    lf_fit_options_statement(o, &a);
    *single = 0;
    if (!lf_probe_shape_stated(&a)) {
        /* a plan gives each curve's probe in its own row: an option that
         * would be ignored is refused */
        if (!isnan(a.R) || !isnan(a.b) || a.interface != NULL)
            return lf_fail(err, LF_EINVAL, "--%s applies to curve files (with --k or --tip); a "
                           "plan gives each curve's probe in its row (columns k, R, b, interface, "
                           "tip, half_angle, prefactor; R may read 'header')",
                           !isnan(a.R) ? "R" : !isnan(a.b) ? "b" : "interface");
        return LF_OK;
    }
    if ((status = lf_probe_state(&a, p, err)) != LF_OK)
        return status;
    *single = 1;
    return LF_OK;
}

int
lf_fit_request_run(const lf_fit_request *req, const lf_fit_input *in, unsigned flags,
                   lf_fit_result *res, lf_warnings *notes, lf_error *err)
{
    lf_fit_settings s = req->fit;
    int batch = (flags & LF_RUN_BATCH) != 0, status;
    lf_error e;
    size_t j;

    lf_fit_input_apply_nu(in, &s);
    /* the joint fit, each curve alone, the intervals (profile-likelihood
     * where the linear ones are unreliable, a batch after the profile's
     * cheap screen; --intervals linear: the linear ones, the search for the
     * minimum made all the same) and how the curves differ (lf_fit_joint) */
    status = lf_fit_joint(&s, req->model_auto ? &req->choose : NULL, in->n, in->curves,
                          !batch ? req->profile
                          : LF_PROFILE_SCREEN | (req->profile == LF_PROFILE_LINEAR
                                                 ? LF_PROFILE_REPORT_LINEAR : 0), res, err);
    if (status != LF_OK && status != LF_ENOCONV)
        return status;
    for (j = 0; j < in->n && in->origin[j].b != NULL; j++)
        ;           /* a curve without a layer has no thin-layer comparison */
    if (!batch && !req->model_auto && s.model != &lf_model_thin && j == in->n
        && lf_fit_compare_thin(&s, in->n, in->curves, res, &e) != LF_OK)
        lf_warn(notes, "the thin-layer comparison fit failed: %s", e.msg);
    if (status == LF_OK && !res->converged)
        status = LF_ENOCONV;    /* a local minimum, or nothing determined */
    return status;
}
