/* text.c: text the library writes for its callers -- a growable string,
 * numbers that read back exactly, numbers for people with an SI prefix,
 * and text from data escaped for JSON (the JSON, HTML and batch writers of
 * report_json.c, report_html.c and batch.c, and the command's own outputs
 * through command.h).  Nothing here prints. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include "internal.h"

void
lf_free(void *p)
{
    free(p);
}

const char *
lf_version(void)
{
    return LF_VERSION;
}

/* ------------------------------------------------------------------------
 * A growable string.
 * --------------------------------------------------------------------- */

/* Room for need more bytes and a NUL; 0, or -1 (b->failed set). */
static int
str_reserve(lf_str *b, size_t need)
{
    size_t cap;
    char *s;

    if (b->failed)
        return -1;
    if (b->len + need < b->cap)
        return 0;
    cap = b->cap ? b->cap : 256;
    while (cap <= b->len + need)
        cap *= 2;
    if ((s = realloc(b->s, cap)) == NULL) {
        b->failed = 1;
        return -1;
    }
    b->s = s;
    b->cap = cap;
    return 0;
}

void
lf_str_put(lf_str *b, const char *s, size_t n)
{
    if (str_reserve(b, n) != 0)
        return;
    memcpy(b->s + b->len, s, n);
    b->len += n;
    b->s[b->len] = '\0';
}

void
lf_str_puts(lf_str *b, const char *s)
{
    lf_str_put(b, s, strlen(s));
}

void
lf_str_put_cb(void *ctx, const char *s, size_t n)
{
    lf_str_put((lf_str *) ctx, s, n);
}

void
lf_str_printf(lf_str *b, const char *fmt, ...)
{
    va_list ap;
    int need;

    if (b->failed)
        return;
    va_start(ap, fmt);
    need = vsnprintf(b->s ? b->s + b->len : NULL, b->s ? b->cap - b->len : 0, fmt, ap);
    va_end(ap);
    if (need < 0) {
        b->failed = 1;
        return;
    }
    if (b->s != NULL && (size_t) need < b->cap - b->len) {
        b->len += (size_t) need;
        return;
    }
    if (str_reserve(b, (size_t) need) != 0)
        return;
    va_start(ap, fmt);
    vsnprintf(b->s + b->len, b->cap - b->len, fmt, ap);
    va_end(ap);
    b->len += (size_t) need;
}

int
lf_str_take(lf_str *b, char **out, lf_error *err)
{
    *out = NULL;
    if (!b->failed)
        str_reserve(b, 0);      /* an empty string is "" */
    if (b->failed) {
        free(b->s);
        memset(b, 0, sizeof *b);
        return lf_fail(err, LF_ENOMEM, "out of memory writing a report");
    }
    *out = b->s;
    memset(b, 0, sizeof *b);
    return LF_OK;
}

void
lf_str_free(lf_str *b)
{
    free(b->s);
    memset(b, 0, sizeof *b);
}

/* ------------------------------------------------------------------------
 * Numbers.
 * --------------------------------------------------------------------- */

const char *
lf_number_text(char buf[40], double x)
{
    snprintf(buf, 40, "%.15g", x);
    if (isfinite(x) && strtod(buf, NULL) != x)
        snprintf(buf, 40, "%.17g", x);
    return buf;
}

void
lf_str_number(lf_str *b, double x, const char *nonfinite)
{
    char buf[40];

    lf_str_puts(b, isfinite(x) ? lf_number_text(buf, x) : nonfinite);
}

char *
lf_human(char *buf, size_t n, double x, const char *unit)
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

/* ------------------------------------------------------------------------
 * Text from data, escaped for where it goes.
 * --------------------------------------------------------------------- */

int
lf_utf8_valid(const char *s)
{
    const unsigned char *p = (const unsigned char *) s;
    while (*p) {
        size_t n = lf_utf8_len(p);
        if (n == 0)
            return 0;
        p += n;
    }
    return 1;
}

void
lf_text_clean(const char *s, int keep_newlines, void (*put)(void *, const char *, size_t),
              void *ctx)
{
    const unsigned char *p = (const unsigned char *) (s ? s : "");
    while (*p) {
        size_t n = lf_utf8_len(p);
        if (n == 0) {
            put(ctx, "\xEF\xBF\xBD", 3);   /* U+FFFD */
            p++;
        } else if (n == 1 && (*p < 0x20 || *p == 0x7F) && !(keep_newlines && *p == '\n')) {
            put(ctx, " ", 1);
            p++;
        } else {
            put(ctx, (const char *) p, n);
            p += n;
        }
    }
}

void
lf_json_escape(const char *s, void (*put)(void *, const char *, size_t), void *ctx)
{
    const unsigned char *p = (const unsigned char *) (s ? s : "");
    put(ctx, "\"", 1);
    while (*p) {
        size_t n = lf_utf8_len(p);
        char buf[8];
        if (n == 0) {
            put(ctx, "\\ufffd", 6);
            p++;
            continue;
        }
        if (*p == '"' || *p == '\\') {
            buf[0] = '\\';
            buf[1] = (char) *p;
            put(ctx, buf, 2);
        } else if (*p == '\n') {
            put(ctx, "\\n", 2);
        } else if (*p < 0x20 || *p == 0x7F) {
            snprintf(buf, sizeof buf, "\\u%04x", *p);
            put(ctx, buf, 6);
        } else {
            put(ctx, (const char *) p, n);
        }
        p += n;
    }
    put(ctx, "\"", 1);
}

void
lf_percent_escape(const char *s, void (*put)(void *, const char *, size_t), void *ctx)
{
    const unsigned char *p = (const unsigned char *) (s ? s : "");
    put(ctx, "\"", 1);
    for (; *p; p++) {
        if (*p > 0x20 && *p < 0x7F && *p != '%' && *p != '"' && *p != '\\') {
            put(ctx, (const char *) p, 1);
        } else {
            char buf[4];
            snprintf(buf, sizeof buf, "%%%02X", *p);
            put(ctx, buf, 3);
        }
    }
    put(ctx, "\"", 1);
}

void
lf_csv_cell(const char *s, int raw, void (*put)(void *, const char *, size_t), void *ctx)
{
    const char *p;
    size_t len;
    int formula, quote;

    s = s != NULL ? s : "";
    len = strlen(s);
    formula = !raw && s[0] != '\0' && strchr("=+-@\t\r", s[0]) != NULL;
    quote = strpbrk(s, ",\"\r\n") != NULL
            || (len > 0 && (s[0] == ' ' || s[0] == '\t' || s[len - 1] == ' ' || s[len - 1] == '\t'));
    if (quote)
        put(ctx, "\"", 1);
    if (formula)
        put(ctx, "'", 1);
    for (p = s; *p; p++) {
        put(ctx, p, 1);
        if (*p == '"')            /* then the cell is quoted */
            put(ctx, "\"", 1);
    }
    if (quote)
        put(ctx, "\"", 1);
}

void
lf_str_json(lf_str *b, const char *s)
{
    lf_json_escape(s, lf_str_put_cb, b);
}

void
lf_str_json_or_null(lf_str *b, const char *s)
{
    if (s == NULL)
        lf_str_puts(b, "null");
    else
        lf_str_json(b, s);
}

void
lf_str_json_name(lf_str *b, const char *key, const char *name)
{
    lf_str_printf(b, "\"%s\": ", key);
    lf_str_json(b, name);
    if (name != NULL && !lf_utf8_valid(name)) {
        lf_str_printf(b, ", \"%s_raw\": ", key);
        lf_percent_escape(name, lf_str_put_cb, b);
    }
}

/* ------------------------------------------------------------------------
 * Provenance.
 * --------------------------------------------------------------------- */

void
lf_str_provenance(lf_str *b, const char *indent, const lf_provenance *p)
{
    size_t i, n = p != NULL ? p->ninputs : 0;

    lf_str_printf(b, "{\n%s  \"layerfit\": \"%s\",\n%s  \"command_line\": ", indent, LF_VERSION,
                  indent);
    lf_str_json_or_null(b, p != NULL ? p->command_line : NULL);
    lf_str_printf(b, ",\n%s  \"inputs\": [", indent);
    for (i = 0; i < n; i++) {
        const char *sha = p->sha256 != NULL ? p->sha256[i] : NULL;
        lf_str_printf(b, "%s\n%s    {", i ? "," : "", indent);
        lf_str_json_name(b, "file", p->input[i]);
        lf_str_puts(b, ", \"sha256\": ");
        if (sha != NULL && sha[0] != '\0')
            lf_str_printf(b, "\"%s\"}", sha);
        else
            lf_str_puts(b, "null}");
    }
    lf_str_printf(b, "%s%s]\n%s}", n ? "\n  " : "", n ? indent : "", indent);
}

int
lf_provenance_json(const lf_provenance *p, const char *indent, char **json, lf_error *err)
{
    lf_str b = { NULL, 0, 0, 0 };

    lf_str_provenance(&b, indent != NULL ? indent : "", p);
    return lf_str_take(&b, json, err);
}
