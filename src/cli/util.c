/* cli/util.c: messages, option parsing and number formatting for the
 * layerfit command. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli.h"

/* Text for stderr, on one line: a control character (a line break in a
 * file name would split the message, an escape sequence would drive the
 * terminal), DEL, a C1 control (U+0080..U+009F) or a byte that is not
 * UTF-8 is written as \n, \r, \t or \xHH; everything else as it is. */
static void
put_escaped(FILE *f, const char *s)
{
    const unsigned char *p = (const unsigned char *) s;
    while (*p) {
        size_t n = lf_utf8_len(p), i;
        if (n == 1 && *p >= 0x20 && *p != 0x7F) {
            fputc(*p++, f);
        } else if (n > 1 && !(n == 2 && p[0] == 0xC2 && p[1] < 0xA0)) {
            fwrite(p, 1, n, f);
            p += n;
        } else if (*p == '\n' || *p == '\r' || *p == '\t') {
            fputs(*p == '\n' ? "\\n" : *p == '\r' ? "\\r" : "\\t", f);
            p++;
        } else {
            for (i = 0; i < (n ? n : 1); i++)
                fprintf(f, "\\x%02x", *p++);
        }
    }
}

/* "layerfit: " + the message, escaped, + a line break. */
static void
say(const char *fmt, va_list ap)
{
    char small[1024], *text = small;
    va_list aq;
    int len;

    va_copy(aq, ap);
    len = vsnprintf(small, sizeof small, fmt, aq);
    va_end(aq);
    if (len >= (int) sizeof small && (text = malloc((size_t) len + 1)) != NULL)
        vsnprintf(text, (size_t) len + 1, fmt, ap);
    else if (text == NULL)
        text = small;   /* out of memory: the message cut short */
    fputs("layerfit: ", stderr);
    put_escaped(stderr, len < 0 ? fmt : text);
    fputc('\n', stderr);
    if (text != small)
        free(text);
}

void
cli_say(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    say(fmt, ap);
    va_end(ap);
}

void
cli_die(int code, const char *fmt, ...)
{
    va_list ap;
    cli_warnings_flush();
    va_start(ap, fmt);
    say(fmt, ap);
    va_end(ap);
    exit(code);
}

void
cli_die_error(int code, const lf_error *err)
{
    char where[600] = "";
    size_t k = 0;

    if (err->file[0] != '\0') {
        k = (size_t) snprintf(where, sizeof where, "%s:", err->file);
        if (err->line > 0 && k < sizeof where)
            k += (size_t) snprintf(where + k, sizeof where - k, "%ld:", err->line);
        if (err->column > 0 && k < sizeof where)
            k += (size_t) snprintf(where + k, sizeof where - k, "%ld:", err->column);
        if (k < sizeof where)
            snprintf(where + k, sizeof where - k, " ");
    }
    cli_die(code, "%s%s", where, err->msg[0] ? err->msg : lf_strerror(err->status));
}

/* ---- warnings, with those that repeat summarised ------------------------
 * A warning's kind is its text after the place it names ("FILE:LINE: ")
 * with every number taken out: the first WARN_SHOWN of a kind are printed,
 * the others counted and said in one line at the end of the run. */
#define WARN_SHOWN 3
#define WARN_KINDS 256
static struct {
    char *kind, *first;   /* the kind, and its first message */
    size_t count;
} kinds[WARN_KINDS];
static size_t nkinds;
static int flush_set;

/* The kind of a message (malloc'ed; NULL when out of memory). */
static char *
warning_kind(const char *msg)
{
    const char *p = strstr(msg, ": ");
    char *k, *q;

    p = p != NULL ? p + 2 : msg;
    if ((k = malloc(strlen(p) + 1)) == NULL)
        return NULL;
    for (q = k; *p; p++)
        if (*p >= '0' && *p <= '9') {
            if (q == k || q[-1] != '#')
                *q++ = '#';
        } else {
            *q++ = *p;
        }
    *q = '\0';
    return k;
}

/* n with its thousands apart: 100488 -> "100 488". */
static void
grouped(char *buf, size_t size, size_t n)
{
    char digits[32];
    size_t len = (size_t) snprintf(digits, sizeof digits, "%zu", n), i, o = 0;
    for (i = 0; i < len && o + 2 < size; i++) {
        if (i > 0 && (len - i) % 3 == 0)
            buf[o++] = ' ';
        buf[o++] = digits[i];
    }
    buf[o] = '\0';
}

void
cli_warnings_flush(void)
{
    size_t i;
    for (i = 0; i < nkinds; i++) {
        char n[48];
        if (kinds[i].count <= WARN_SHOWN)
            continue;
        grouped(n, sizeof n, kinds[i].count - WARN_SHOWN);
        fprintf(stderr, "layerfit: warning: ... and %s more like it (", n);
        put_escaped(stderr, kinds[i].first);
        fputs(")\n", stderr);
        kinds[i].count = WARN_SHOWN;   /* said once */
    }
}

static void
flush_at_exit(void)
{
    size_t i;
    cli_warnings_flush();
    for (i = 0; i < nkinds; i++) {
        free(kinds[i].kind);
        free(kinds[i].first);
    }
    nkinds = 0;
}

void
cli_print_warnings(const lf_warnings *w)
{
    size_t i, j;

    if (!flush_set) {
        atexit(flush_at_exit);
        flush_set = 1;
    }
    for (i = 0; i < w->n; i++) {
        char *kind = warning_kind(w->msg[i]);
        for (j = 0; kind != NULL && j < nkinds && strcmp(kinds[j].kind, kind) != 0; j++)
            ;
        if (kind != NULL && j == nkinds && nkinds < WARN_KINDS) {
            const char *place_end = strstr(w->msg[i], ": ");
            const char *text = place_end != NULL ? place_end + 2 : w->msg[i];
            if ((kinds[j].first = malloc(strlen(text) + 1)) != NULL) {
                strcpy(kinds[j].first, text);
                kinds[j].kind = kind;
                kinds[j].count = 0;
                kind = NULL;
                nkinds++;
            }
        }
        free(kind);
        if (j < nkinds && ++kinds[j].count > WARN_SHOWN)
            continue;
        fputs("layerfit: warning: ", stderr);
        put_escaped(stderr, w->msg[i]);
        fputc('\n', stderr);
    }
}

int
cli_parse_size(const char *text, double *bytes)
{
    static const struct { const char *suffix; double factor; } units[] = {
        { "", 1.0 }, { "B", 1.0 }, { "kB", 1e3 }, { "MB", 1e6 }, { "GB", 1e9 }, { "TB", 1e12 },
        { "K", 1024.0 }, { "KiB", 1024.0 }, { "M", 1048576.0 }, { "MiB", 1048576.0 },
        { "G", 1073741824.0 }, { "GiB", 1073741824.0 }, { "T", 1099511627776.0 },
        { "TiB", 1099511627776.0 }
    };
    char *end;
    double v;
    size_t i;

    errno = 0;
    v = strtod(text, &end);
    if (end == text || errno == ERANGE || !isfinite(v) || !(v >= 1.0))
        return -1;
    while (*end == ' ')
        end++;
    for (i = 0; i < sizeof units / sizeof units[0]; i++)
        if (strcmp(end, units[i].suffix) == 0) {
            *bytes = v * units[i].factor;
            return 0;
        }
    return -1;
}

static lf_quantity
kind_quantity(cli_kind kind)
{
    switch (kind) {
    case CLI_LENGTH:   return LF_Q_LENGTH;
    case CLI_FORCE:    return LF_Q_FORCE;
    case CLI_ADHESION: return LF_Q_ADHESION;
    case CLI_PRESSURE: return LF_Q_PRESSURE;
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
    if (!isfinite(x))
        return;             /* never "nan" or "inf": an empty CSV cell */
    snprintf(buf, sizeof buf, "%.15g", x);
    if (strtod(buf, NULL) != x)
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
