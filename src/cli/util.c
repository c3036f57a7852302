/* cli/util.c: messages, option parsing and number formatting for the
 * layerfit command. */
#include <errno.h>
#include <limits.h>
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

/* The library's kind of an option of the command's own. */
static lf_option
lib_option(const cli_opt *o)
{
    lf_option opt = { o->name, LF_OPTION_QUANTITY, LF_Q_DIMENSIONLESS };
    switch (o->kind) {
    case CLI_NUMBER:   opt.kind = LF_OPTION_NUMBER; break;
    case CLI_COUNT:    opt.kind = LF_OPTION_COUNT; break;
    case CLI_LENGTH:   opt.quantity = LF_Q_LENGTH; break;
    case CLI_FORCE:    opt.quantity = LF_Q_FORCE; break;
    case CLI_ADHESION: opt.quantity = LF_Q_ADHESION; break;
    default:           opt.quantity = LF_Q_PRESSURE; break;
    }
    return opt;
}

static void
set_value(const char *cmd, const cli_opt *o, const char *value)
{
    lf_error err;
    lf_option opt;
    double x;

    switch (o->kind) {
    case CLI_STRING:
        *(const char **) o->target = value;
        return;
    case CLI_FIT:
    case CLI_FIT_FLAG:
    case CLI_DESIGN:
    case CLI_DESIGN_FLAG:
        if ((o->kind == CLI_FIT || o->kind == CLI_FIT_FLAG
             ? lf_fit_options_set(o->target, o->name, value, &err)
             : lf_design_options_set(o->target, o->name, value, &err)) != LF_OK)
            cli_die(err.status == LF_ENOMEM ? CLI_EXIT_FAIL : CLI_EXIT_USAGE, "%s: %s", cmd,
                    err.msg);
        return;
    default:
        opt = lib_option(o);
        if (lf_option_number(&opt, value, &x, &err) != LF_OK)
            cli_die(CLI_EXIT_USAGE, "%s: %s", cmd, err.msg);
        if (o->kind == CLI_COUNT)   /* whole, >= 0; LONG_MAX where a long ends */
            *(long *) o->target = x < 9.2e18 ? (long) x : LONG_MAX;
        else
            *(double *) o->target = x;
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
        if (o->kind == CLI_FLAG || o->kind == CLI_FIT_FLAG || o->kind == CLI_DESIGN_FLAG) {
            if (eq != NULL)
                cli_die(CLI_EXIT_USAGE, "%s: --%s takes no value", cmd, o->name);
            if (o->kind != CLI_FLAG)
                set_value(cmd, o, NULL);
            else
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
    fputs(lf_number_text(buf, x), f);
}

double
cli_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double) t.tv_sec + 1e-9 * (double) t.tv_nsec;
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
