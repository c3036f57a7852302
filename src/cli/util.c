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
    case CLI_ANGLE:    opt.quantity = LF_Q_ANGLE; break;
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
    if (!isfinite(x))
        return;             /* never "nan" or "inf": an empty CSV cell */
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

/* "OUT.summary.EXT": OUT without its .csv or .jsonl (free). */
char *
cli_summary_path(const char *out, const char *ext)
{
    size_t len = strlen(out), stem = len;
    char *p;
    if (len > 4 && strcmp(out + len - 4, ".csv") == 0)
        stem = len - 4;
    else if (len > 6 && strcmp(out + len - 6, ".jsonl") == 0)
        stem = len - 6;
    p = malloc(stem + strlen(ext) + 10);
    if (p == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    sprintf(p, "%.*s.summary.%s", (int) stem, out, ext);
    return p;
}
