/* cli/util.c: messages, option parsing and number formatting for the
 * layerfit command. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli.h"

void
cli_die(int code, const char *fmt, ...)
{
    va_list ap;
    fputs("layerfit: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    exit(code);
}

void
cli_die_error(int code, const lf_error *err)
{
    fputs("layerfit: ", stderr);
    if (err->file[0] != '\0') {
        fprintf(stderr, "%s:", err->file);
        if (err->line > 0)
            fprintf(stderr, "%ld:", err->line);
        if (err->column > 0)
            fprintf(stderr, "%ld:", err->column);
        fputc(' ', stderr);
    }
    fprintf(stderr, "%s\n", err->msg[0] ? err->msg : lf_strerror(err->status));
    exit(code);
}

void
cli_print_warnings(const lf_warnings *w)
{
    size_t i;
    for (i = 0; i < w->n; i++)
        fprintf(stderr, "layerfit: warning: %s\n", w->msg[i]);
}

static lf_quantity
kind_quantity(cli_kind kind)
{
    switch (kind) {
    case CLI_LENGTH:   return LF_Q_LENGTH;
    case CLI_FORCE:    return LF_Q_FORCE;
    case CLI_ADHESION: return LF_Q_ADHESION;
    case CLI_PRESSURE: return LF_Q_PRESSURE;
    case CLI_ANGLE:    return LF_Q_ANGLE;
    default:           return LF_Q_DIMENSIONLESS;
    }
}

static void
set_value(const char *cmd, const cli_opt *o, const char *value)
{
    lf_error err;
    char *end;

    switch (o->kind) {
    case CLI_STRING:
        *(const char **) o->target = value;
        return;
    case CLI_NUMBER:
        errno = 0;
        *(double *) o->target = strtod(value, &end);
        if (end == value || *end != '\0' || errno == ERANGE
            || !isfinite(*(double *) o->target))
            cli_die(CLI_EXIT_USAGE, "%s: --%s: '%s' is not a number (e.g. --%s 0.3)",
                    cmd, o->name, value, o->name);
        return;
    case CLI_COUNT: {
        long v;
        errno = 0;
        v = strtol(value, &end, 10);
        if (end == value || *end != '\0' || errno == ERANGE || v < 0)
            cli_die(CLI_EXIT_USAGE, "%s: --%s: '%s' is not a whole number >= 0 (e.g. --%s 200)",
                    cmd, o->name, value, o->name);
        *(long *) o->target = v;
        return;
    }
    default:
        if (lf_units_parse(value, kind_quantity(o->kind), (double *) o->target, &err) != LF_OK)
            cli_die(CLI_EXIT_USAGE, "%s: --%s: %s", cmd, o->name, err.msg);
        return;
    }
}

void
cli_parse(const char *cmd, int argc, char **argv, const cli_opt *opts,
          int *npos, int *help)
{
    int i, np = 0;

    *help = 0;
    for (i = 1; i < argc; i++) {
        const char *arg = argv[i], *eq, *value;
        const cli_opt *o;
        size_t len;

        if (strncmp(arg, "--", 2) != 0 || arg[2] == '\0') {
            if (strcmp(arg, "--") == 0) {
                while (++i < argc)
                    argv[np++] = argv[i];
                break;
            }
            argv[np++] = argv[i];
            continue;
        }
        arg += 2;
        if (strcmp(arg, "help") == 0) {
            *help = 1;
            continue;
        }
        eq = strchr(arg, '=');
        len = eq ? (size_t) (eq - arg) : strlen(arg);
        for (o = opts; o->name != NULL; o++)
            if (strlen(o->name) == len && strncmp(o->name, arg, len) == 0)
                break;
        if (o->name == NULL)
            cli_die(CLI_EXIT_USAGE, "%s: unknown option '--%.*s' (see 'layerfit %s --help')",
                    cmd, (int) len, arg, cmd);
        if (o->kind == CLI_FLAG) {
            if (eq != NULL)
                cli_die(CLI_EXIT_USAGE, "%s: --%s takes no value", cmd, o->name);
            *(int *) o->target = 1;
            continue;
        }
        if (eq != NULL)
            value = eq + 1;
        else if (i + 1 < argc)
            value = argv[++i];
        else
            cli_die(CLI_EXIT_USAGE, "%s: --%s needs a value", cmd, o->name);
        set_value(cmd, o, value);
    }
    *npos = np;
}

int
cli_base(const char *word)
{
    if (strcmp(word, "frictionless") == 0)
        return LF_BASE_FRICTIONLESS;
    if (strcmp(word, "bonded") == 0)
        return LF_BASE_BONDED;
    return -1;
}

int
cli_model_ignores_b(const char *model)
{
    const lf_model_type *t = model != NULL ? lf_model_type_find(model) : NULL;
    return t != NULL && t->scope == LF_SCOPE_HALFSPACE;
}

const char *
cli_base_name(lf_base base)
{
    return base == LF_BASE_BONDED ? "bonded" : "frictionless";
}

void
cli_print_double(FILE *f, double x)
{
    char buf[40];
    snprintf(buf, sizeof buf, "%.15g", x);
    if (isfinite(x) && strtod(buf, NULL) != x)
        snprintf(buf, sizeof buf, "%.17g", x);
    fputs(buf, f);
}

char *
cli_human(char *buf, size_t n, double x, const char *unit)
{
    static const struct { double scale; const char *prefix; } pre[] = {
        { 1e12, "T" }, { 1e9, "G" }, { 1e6, "M" }, { 1e3, "k" }, { 1, "" },
        { 1e-3, "m" }, { 1e-6, "µ" }, { 1e-9, "n" }, { 1e-12, "p" }, { 1e-15, "f" }
    };
    size_t i, last = sizeof pre / sizeof pre[0] - 1;
    double ax = fabs(x);

    if (isnan(x)) {             /* no NaN reaches an output */
        snprintf(buf, n, "undefined");
        return buf;
    }
    if (isinf(x) || x == 0.0) {  /* "0", never "-0" */
        snprintf(buf, n, "%s%s %s", x < 0 ? "-" : "", x == 0.0 ? "0" : "infinite", unit);
        return buf;
    }
    for (i = 0; i < last; i++)
        if (ax >= pre[i].scale * 0.9995)
            break;
    snprintf(buf, n, "%.4g %s%s", x / pre[i].scale, pre[i].prefix, unit);
    return buf;
}

double
cli_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double) t.tv_sec + 1e-9 * (double) t.tv_nsec;
}

double
cli_fitted_value(const lf_fit_result *res, const char *name)
{
    size_t i;

    for (i = 0; i < res->npar; i++)
        if (strcmp(res->names[i], name) == 0)
            return res->value[i];
    return NAN;
}

int
cli_curve_disagrees(const lf_fit_curve_result *cr)
{
    return !cr->consistent && cr->agreement != 1;
}

size_t
cli_disagreeing(const lf_fit_result *r, char *buf, size_t n)
{
    size_t j, count = 0, len = 0;

    if (n > 0)
        buf[0] = '\0';
    if (!r->converged)
        return 0;
    for (j = 0; j < r->ncurves; j++) {
        int w;
        if (!cli_curve_disagrees(&r->curves[j]))
            continue;
        w = snprintf(buf + len, n - len, "%s%zu", count ? ", " : "", j + 1);
        if (w > 0 && (size_t) w < n - len)
            len += (size_t) w;
        count++;
    }
    return count;
}

void
cli_refuse_options(int argc, char **argv, const char *const *names, size_t n, const char *why)
{
    size_t k;
    int i;

    for (i = 0; i < argc; i++)
        for (k = 0; k < n; k++) {
            size_t len = strlen(names[k]);
            if (strncmp(argv[i], names[k], len) == 0
                && (argv[i][len] == '\0' || argv[i][len] == '='))
                cli_die(CLI_EXIT_USAGE, "fit: %s is for %s", names[k], why);
        }
}
