/* csvsplit.c: lines, comments and records of the CSV files layerfit reads
 * (see csvsplit.h).  Bytes go to libcsv one at a time, so that the place of
 * every field and of every malformed quote is known exactly; this costs a
 * function call per byte, which is small next to the parsing of numbers. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csv.h>

#include "csvsplit.h"

typedef struct {
    const char *name;
    const lf_csv_handler *h;
    lf_error *err;
    int status;               /* first failure or LF_CSV_STOP */
    struct csv_parser csv;

    char *line;               /* the physical line being gathered */
    size_t len, cap;
    long lineno;              /* number of that line */
    int prev_cr;              /* the last byte was CR: an LF after it is eaten */

    char delim;               /* 0 until the header has been seen */
    long nrecords;
    int in_record;            /* libcsv holds an unfinished record */
    long rec_line;
    size_t rec_bytes;

    char *fbuf;               /* fields of the record, back to back */
    size_t flen, fcap;
    struct { size_t off; long line, col; } *fpos;
    size_t nf, nfcap;
    char **ftext;             /* the record as handed over */
    long *fline, *fcol;
    size_t ntcap;
    long cur_col;             /* column of the byte being parsed */
    long fstart_line, fstart_col;
    int fbegun, fquoted;      /* the field has a byte other than a space;
                                 its first such byte was a quote */
} splitter;

static int
grow(void **p, size_t *cap, size_t need, size_t size)
{
    size_t n = *cap ? *cap : 16;
    void *q;
    if (need <= *cap)
        return 0;
    while (n < need)
        n *= 2;
    q = realloc(*p, n * size);
    if (q == NULL)
        return -1;
    *p = q;
    *cap = n;
    return 0;
}

static int
nomem(splitter *s)
{
    s->status = lf_fail_at(s->err, LF_ENOMEM, s->name, s->lineno, 0,
                           "out of memory");
    return s->status;
}

static int
is_blank(unsigned char c)
{
    return c == ' ' || c == '\t';
}

/* libcsv: only the space is blank, so that a tab can be a delimiter. */
static int
csv_space(unsigned char c)
{
    return c == ' ';
}

/* libcsv: end of a field.  Keeps the text and where it started.  Blanks
 * around an unquoted field are dropped; a quoted field is kept byte for
 * byte (libcsv has dropped the spaces outside its quotes). */
static void
on_field(void *data, size_t n, void *vs)
{
    splitter *s = vs;
    const char *text = data ? data : "";
    size_t b = 0, e = n;
    int quoted = s->fquoted;

    s->fbegun = s->fquoted = 0;
    if (s->status != LF_OK)
        return;
    while (!quoted && b < e && is_blank((unsigned char) text[b]))
        b++;
    while (!quoted && e > b && is_blank((unsigned char) text[e - 1]))
        e--;
    if (grow((void **) &s->fbuf, &s->fcap, s->flen + (e - b) + 1, 1) != 0
        || grow((void **) &s->fpos, &s->nfcap, s->nf + 1, sizeof *s->fpos) != 0) {
        nomem(s);
        return;
    }
    memcpy(s->fbuf + s->flen, text + b, e - b);
    s->fpos[s->nf].off = s->flen;
    s->fpos[s->nf].line = s->fstart_line;
    s->fpos[s->nf].col = s->fstart_col;
    s->flen += e - b;
    s->fbuf[s->flen++] = '\0';
    s->nf++;
    s->fstart_line = s->lineno;
    s->fstart_col = s->cur_col + 1;
}

/* libcsv: end of a record.  Hands it to the caller. */
static void
on_record(int c, void *vs)
{
    splitter *s = vs;
    lf_csv_record r;
    size_t i;

    (void) c;
    s->in_record = 0;
    if (s->status != LF_OK)
        return;
    if (s->nf > s->ntcap) {
        size_t cap = s->ntcap, cap2 = s->ntcap, cap3 = s->ntcap;
        if (grow((void **) &s->ftext, &cap, s->nf, sizeof *s->ftext) != 0
            || grow((void **) &s->fline, &cap2, s->nf, sizeof *s->fline) != 0
            || grow((void **) &s->fcol, &cap3, s->nf, sizeof *s->fcol) != 0) {
            nomem(s);
            return;
        }
        s->ntcap = cap;   /* all three grew to the same size */
    }
    for (i = 0; i < s->nf; i++) {
        s->ftext[i] = s->fbuf + s->fpos[i].off;
        s->fline[i] = s->fpos[i].line;
        s->fcol[i] = s->fpos[i].col;
    }
    r.index = s->nrecords++;
    r.line = s->rec_line;
    r.n = s->nf;
    r.text = s->ftext;
    r.fline = s->fline;
    r.fcol = s->fcol;
    r.delim = s->delim;
    s->status = s->h->record(s->h->ctx, &r, s->err);
    s->nf = 0;
    s->flen = 0;
}

/* The delimiter of a header line: the most frequent of tab, ';' and ','
 * outside quotes, in that order of preference on a tie. */
static char
detect_delim(const char *t, size_t n)
{
    size_t tabs = 0, semis = 0, commas = 0, i;
    int quoted = 0;
    for (i = 0; i < n; i++) {
        if (t[i] == '"')
            quoted = !quoted;
        else if (!quoted)
            tabs += t[i] == '\t', semis += t[i] == ';', commas += t[i] == ',';
    }
    if (tabs > 0 && tabs >= semis && tabs >= commas)
        return '\t';
    if (semis > 0 && semis >= commas)
        return ';';
    return ',';
}

/* Give one byte to libcsv; col is its column. */
static int
parse_byte(splitter *s, char c, long col)
{
    s->cur_col = col;
    if (!s->fbegun && c != ' ') {
        s->fbegun = 1;
        s->fquoted = c == '"';
    }
    if (csv_parse(&s->csv, &c, 1, on_field, on_record, s) != 1 && s->status == LF_OK)
        s->status = lf_fail_at(s->err, LF_EFORMAT, s->name, s->lineno, col,
                               "malformed quotes (quote a whole field, and double "
                               "the quotes inside it: \"a \"\"b\"\"\")");
    return s->status;
}

/* A whole record on one line without quotes (the usual data row): split
 * at the delimiter here, as libcsv would, without a call per byte.  libcsv
 * stays where it was, between records. */
static int
split_line(splitter *s, char *t, size_t n)
{
    size_t i, start = 0;
    long col = 0;

    for (i = 0; i < n && s->status == LF_OK; i++) {
        if (((unsigned char) t[i] & 0xC0) != 0x80)
            col++;
        if (t[i] == s->delim) {
            s->cur_col = col;
            on_field(t + start, i - start, s);
            start = i + 1;
        }
    }
    s->cur_col = col + 1;
    on_field(t + start, n - start, s);
    on_record('\n', s);
    return s->status;
}

/* Handle one complete physical line, without its terminator (term: '\r'
 * or '\n', what ended it; '\n' at the end of the input). */
static int
process_line(splitter *s, char *t, size_t n, char term)
{
    size_t i, b;
    long col = 0;
    int fresh = !s->in_record;   /* the line starts a record */

    if (s->lineno == 1) {
        if (n >= 2 && ((unsigned char) t[0] == 0xFF || (unsigned char) t[0] == 0xFE)
            && ((unsigned char) t[1] == 0xFE || (unsigned char) t[1] == 0xFF))
            return s->status = lf_fail_at(s->err, LF_EFORMAT, s->name, 1, 1,
                                          "UTF-16 text (save the file as UTF-8 CSV)");
        if (n >= 3 && memcmp(t, "\xEF\xBB\xBF", 3) == 0)
            t += 3, n -= 3;
    }
    for (i = 0; i < n; i++) {
        unsigned char c = (unsigned char) t[i];
        if ((c & 0xC0) != 0x80)
            col++;
        if ((c < 0x20 && c != '\t') || c == 0x7F)
            return s->status = lf_fail_at(s->err, LF_EFORMAT, s->name, s->lineno, col,
                                          "binary data: control byte 0x%02X (expected "
                                          "a text CSV file)", c);
    }
    if (s->h->line != NULL) {
        t[n] = '\0';
        return s->status = s->h->line(s->h->ctx, s->lineno, t, n, s->err);
    }
    if (!s->in_record) {
        for (b = 0; b < n && is_blank((unsigned char) t[b]); b++)
            ;
        if (b == n)
            return LF_OK;
        if (t[b] == '#') {
            size_t e = n;
            t[e] = '\0';
            for (b++; b < e && is_blank((unsigned char) t[b]); b++)
                ;
            while (e > b && is_blank((unsigned char) t[e - 1]))
                t[--e] = '\0';
            if (s->h->comment != NULL)
                s->status = s->h->comment(s->h->ctx, s->lineno, t + b,
                                          s->delim == 0, s->err);
            return s->status;
        }
        if (s->delim == 0) {
            s->delim = detect_delim(t, n);
            csv_set_delim(&s->csv, (unsigned char) s->delim);
        }
        s->in_record = 1;
        s->rec_line = s->fstart_line = s->lineno;
        s->fstart_col = 1;
        s->rec_bytes = 0;
    } else {
        s->rec_bytes++;       /* the line break inside the quoted field */
    }
    s->rec_bytes += n;
    if (s->rec_bytes > (size_t) LF_CSV_MAX_LINE)
        return s->status = lf_fail_at(s->err, LF_EFORMAT, s->name, s->fstart_line,
                                      s->fstart_col, "row longer than 1 MiB (is a "
                                      "quote left open here?)");
    if (fresh && memchr(t, '"', n) == NULL)
        return split_line(s, t, n);
    col = 0;
    for (i = 0; i < n && s->status == LF_OK; i++) {
        if (((unsigned char) t[i] & 0xC0) != 0x80)
            col++;
        parse_byte(s, t[i], col);
    }
    if (s->status == LF_OK)     /* a line break inside quotes is kept as it was */
        parse_byte(s, term, col + 1);
    return s->status;   /* in_record still set: a quoted field goes on */
}

static int
end_line(splitter *s, char term)
{
    if (grow((void **) &s->line, &s->cap, s->len + 1, 1) != 0)
        return nomem(s);
    s->line[s->len] = '\0';
    process_line(s, s->line, s->len, term);
    s->len = 0;
    s->lineno++;
    return s->status;
}

static int
feed(splitter *s, const char *buf, size_t n)
{
    size_t i = 0, j;
    while (i < n && s->status == LF_OK) {
        char c = buf[i];
        if (c == '\n' || c == '\r') {
            if (!(c == '\n' && s->prev_cr))     /* an LF after a CR ends no line */
                end_line(s, c);
            else if (s->in_record && s->status == LF_OK) {
                /* ... but inside quotes it is kept: CRLF stays CRLF */
                s->rec_bytes++;
                parse_byte(s, c, 0);
            }
            s->prev_cr = c == '\r';
            i++;
            continue;
        }
        for (j = i + 1; j < n && buf[j] != '\n' && buf[j] != '\r'; j++)
            ;
        s->prev_cr = 0;
        if (s->len + (j - i) > (size_t) LF_CSV_MAX_LINE)
            return s->status = lf_fail_at(s->err, LF_EFORMAT, s->name, s->lineno, 0,
                                          "line longer than 1 MiB (lines must end "
                                          "within %ld bytes; is this a CSV file?)",
                                          LF_CSV_MAX_LINE);
        if (grow((void **) &s->line, &s->cap, s->len + (j - i) + 2, 1) != 0)
            return nomem(s);
        memcpy(s->line + s->len, buf + i, j - i);
        s->len += j - i;
        i = j;
    }
    return s->status;
}

static int
finish(splitter *s)
{
    if (s->status == LF_OK && s->len > 0)
        end_line(s, '\n');
    if (s->status == LF_OK && s->in_record)
        s->status = lf_fail_at(s->err, LF_EFORMAT, s->name, s->fstart_line,
                               s->fstart_col, "quote opened here is never closed "
                               "(end the field with \")");
    return s->status;
}

static int
start(splitter *s, const char *name, const lf_csv_handler *h, lf_error *err)
{
    memset(s, 0, sizeof *s);
    s->name = name ? name : "";
    s->h = h;
    s->err = err;
    s->lineno = 1;
    lf_error_clear(err);
    if (csv_init(&s->csv, CSV_STRICT | CSV_APPEND_NULL) != 0)
        return s->status = lf_fail_at(err, LF_ENOMEM, s->name, 0, 0, "out of memory");
    csv_set_space_func(&s->csv, csv_space);
    return LF_OK;
}

static int
stop(splitter *s)
{
    int status = s->status == LF_CSV_STOP ? LF_OK : s->status;
    csv_free(&s->csv);
    free(s->line);
    free(s->fbuf);
    free(s->fpos);
    free(s->fline);
    free(s->fcol);
    free(s->ftext);
    return status;
}

int
lf_csv_read_buffer(const char *buf, size_t len, size_t chunk, const char *name,
                   const lf_csv_handler *h, lf_error *err)
{
    splitter s;
    size_t at = 0;

    if (start(&s, name, h, err) != LF_OK)
        return s.status;
    if (chunk == 0)
        chunk = len;
    while (at < len && s.status == LF_OK) {
        size_t n = len - at < chunk ? len - at : chunk;
        feed(&s, buf + at, n);
        at += n;
    }
    finish(&s);
    return stop(&s);
}

int
lf_csv_read_file(const char *path, const lf_csv_handler *h, lf_error *err)
{
    char block[65536];
    splitter s;
    ssize_t n;
    int fd, status;

    lf_error_clear(err);
    /* a regular file, checked on the open descriptor (input.c), no
     * larger than the inputs read whole: what is read is kept */
    if ((status = lf_input_open(path, 0, &fd, err)) != LF_OK)
        return status;
    if ((status = lf_input_check_size(fd, path, err)) != LF_OK) {
        close(fd);
        return status;
    }
    if (start(&s, path, h, err) == LF_OK) {
        while (s.status == LF_OK) {
            n = read(fd, block, sizeof block);
            if (n < 0 && errno == EINTR)
                continue;
            if (n < 0) {
                s.status = lf_fail_at(err, LF_EIO, path, 0, 0, "read error: %s", strerror(errno));
                break;
            }
            if (n == 0)
                break;
            feed(&s, block, (size_t) n);
        }
        finish(&s);
    }
    close(fd);
    return stop(&s);
}

int
lf_csv_read_input(const lf_source *in, const lf_csv_handler *h, lf_error *err)
{
    return lf_csv_read_buffer(in->buf ? in->buf : "", in->len, in->chunk, in->name, h, err);
}

/* ---------------------------------------------------------------------- */

int
lf_csv_ieq(const char *a, const char *b)
{
    for (; *a && *b; a++, b++)
        if (tolower((unsigned char) *a) != tolower((unsigned char) *b))
            return 0;
    return *a == *b;
}

static void
copy_trimmed(char *dst, size_t n, const char *b, const char *e)
{
    size_t len;
    if (e < b)
        e = b;
    while (b < e && is_blank((unsigned char) *b))
        b++;
    while (e > b && is_blank((unsigned char) e[-1]))
        e--;
    len = (size_t) (e - b);
    if (n == 0)
        return;
    if (len >= n)
        len = n - 1;
    memcpy(dst, b, len);
    dst[len] = '\0';
}

/* Spell the micro sign as 'u', in place. */
static void
ascii_micro(char *u)
{
    char *w = u;
    const unsigned char *r = (const unsigned char *) u;
    while (*r) {
        if ((r[0] == 0xC2 && r[1] == 0xB5) || (r[0] == 0xCE && r[1] == 0xBC)) {
            *w++ = 'u';
            r += 2;
        } else if (r[0] == 0xB5) {
            *w++ = 'u';
            r++;
        } else {
            *w++ = (char) *r++;
        }
    }
    *w = '\0';
}

void
lf_csv_header_cell(const char *cell, char *name, size_t nname, char *unit,
                   size_t nunit)
{
    const char *end = cell + strlen(cell), *cut;
    char close;

    while (end > cell && is_blank((unsigned char) end[-1]))
        end--;
    close = end > cell ? end[-1] : '\0';
    if ((close == ')' || close == ']')
        && (cut = memchr(cell, close == ')' ? '(' : '[', (size_t) (end - cell))) != NULL
        && cut > cell) {
        copy_trimmed(name, nname, cell, cut);
        copy_trimmed(unit, nunit, cut + 1, end - 1);
    } else if ((cut = strstr(cell, " / ")) != NULL && cut + 3 <= end) {
        copy_trimmed(name, nname, cell, cut);
        copy_trimmed(unit, nunit, cut + 3, end);
    } else if ((cut = strrchr(cell, '_')) != NULL && cut > cell) {
        copy_trimmed(name, nname, cell, cut);
        copy_trimmed(unit, nunit, cut + 1, end);
    } else {
        copy_trimmed(name, nname, cell, end);
        copy_trimmed(unit, nunit, end, end);
    }
    ascii_micro(unit);
}

void
lf_csv_decimal_point(char *text, int decimal_comma)
{
    char *comma;
    if (!decimal_comma || strchr(text, '.') != NULL)
        return;
    comma = strchr(text, ',');
    if (comma != NULL && strchr(comma + 1, ',') == NULL)
        *comma = '.';
}

/* The value of a plain decimal [sign] digits [. digits] [e [sign] digits]
 * of at most 15 significant digits whose scale is 10^-22 to 10^22, in one
 * correctly rounded multiplication or division of two exact doubles
 * (Clinger's fast path), hence the same double as strtod.  0 for any other
 * text (strtod reads it). */
static int
fast_decimal(const char *t, size_t n, char point, double *value)
{
    static const double p10[] = {
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11,
        1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22
    };
    const char *p = t, *end = t + n;
    unsigned long long m = 0;
    int neg = 0, sig = 0, digits = 0, scale = 0, e = 0, eneg = 0, edigits = 0;
    double v;

    if (p < end && (*p == '+' || *p == '-'))
        neg = *p++ == '-';
    for (; p < end && *p >= '0' && *p <= '9'; p++, digits++)
        if (sig > 0 || *p != '0')
            m = m * 10 + (unsigned) (*p - '0'), sig++;
    if (p < end && *p == point)
        for (p++; p < end && *p >= '0' && *p <= '9'; p++, digits++, scale--)
            if (sig > 0 || *p != '0')
                m = m * 10 + (unsigned) (*p - '0'), sig++;
    if (digits == 0 || sig > 15)
        return 0;
    if (p < end && (*p == 'e' || *p == 'E')) {
        p++;
        if (p < end && (*p == '+' || *p == '-'))
            eneg = *p++ == '-';
        for (; p < end && *p >= '0' && *p <= '9' && edigits < 5; p++, edigits++)
            e = e * 10 + (*p - '0');
        if (edigits == 0)
            return 0;
    }
    if (p != end)
        return 0;
    scale += eneg ? -e : e;
    if (scale > 22 || scale < -22)
        return 0;
    v = (double) m;
    v = scale >= 0 ? v * p10[scale] : v / p10[-scale];
    *value = neg ? -v : v;
    return 1;
}

/* Read in place: a plain decimal (the usual cell) in one pass by
 * fast_decimal, whose grammar admits nothing the checks below refuse; any
 * other text is checked (the characters a decimal may hold, at least one
 * digit) and read, and copied only where a decimal comma goes to strtod as
 * a point. */
int
lf_csv_number(const char *text, int decimal_comma, double *value)
{
    char buf[80], *end;
    const char *p = text + (text[0] == '+' || text[0] == '-');
    size_t n = strlen(text), i, commas = 0, comma = 0;
    int digits = 0, dot = 0;

    if (n == 0)
        return LF_NUM_EMPTY;
    if (n >= sizeof buf)
        return LF_NUM_BAD;
    if (fast_decimal(text, n, '.', value))
        return LF_NUM_OK;
    if ((*p == 'n' || *p == 'N' || *p == 'i' || *p == 'I')
        && (lf_csv_ieq(p, "nan") || lf_csv_ieq(p, "inf") || lf_csv_ieq(p, "infinity")))
        return LF_NUM_NONFINITE;
    for (i = 0; i < n; i++) {
        const char c = text[i];
        if (c >= '0' && c <= '9')
            digits = 1;
        else if (c == '.')
            dot = 1;
        else if (c == ',')
            comma = commas++ == 0 ? i : comma;
        else if (!(c == '+' || c == '-' || c == 'e' || c == 'E'))
            return LF_NUM_BAD;
    }
    /* a comma is the decimal point where lf_csv_decimal_point makes it one:
     * the only one, with no point */
    if (commas > 0 && !(decimal_comma && !dot && commas == 1))
        return LF_NUM_BAD;
    if (!digits)
        return LF_NUM_BAD;
    if (commas > 0 && fast_decimal(text, n, ',', value))
        return LF_NUM_OK;
    errno = 0;
    if (commas > 0) {
        memcpy(buf, text, n + 1);
        buf[comma] = '.';
        *value = strtod(buf, &end);
        if (end != buf + n)
            return LF_NUM_BAD;
    } else {
        *value = strtod(text, &end);
        if (end != text + n)
            return LF_NUM_BAD;
    }
    if (errno == ERANGE && fabs(*value) > 1.0)
        return LF_NUM_NONFINITE;
    return LF_NUM_OK;
}

size_t
lf_utf8_len(const unsigned char *s)
{
    unsigned char c = s[0];
    size_t n, i;
    if (c < 0x80)
        return 1;
    if (c >= 0xC2 && c <= 0xDF)
        n = 2;
    else if (c >= 0xE0 && c <= 0xEF)
        n = 3;
    else if (c >= 0xF0 && c <= 0xF4)
        n = 4;
    else
        return 0;
    for (i = 1; i < n; i++)
        if ((s[i] & 0xC0) != 0x80)
            return 0;
    /* overlong forms, surrogates and code points above U+10FFFF */
    if ((c == 0xE0 && s[1] < 0xA0) || (c == 0xED && s[1] > 0x9F)
        || (c == 0xF0 && s[1] < 0x90) || (c == 0xF4 && s[1] > 0x8F))
        return 0;
    return n;
}

int
lf_csv_is_text(const lf_csv_record *r)
{
    size_t i, k;
    for (i = 0; i < r->n; i++) {
        const unsigned char *t = (const unsigned char *) r->text[i];
        for (; *t; t += k)
            if ((k = lf_utf8_len(t)) == 0)
                return 0;
    }
    return 1;
}

const char *
lf_csv_excerpt(const char *text, char *buf, size_t n)
{
    const unsigned char *r = (const unsigned char *) text;
    size_t w = 0, shown = 0;

    while (*r && w + 8 < n && shown < 40) {
        size_t k = lf_utf8_len(r);
        if (k == 0 || (k == 1 && (*r < 0x20 || *r == 0x7F))) {
            buf[w++] = '?';
            r++;
        } else {
            memcpy(buf + w, r, k);
            w += k;
            r += k;
        }
        shown++;
    }
    if (*r && w + 4 <= n) {
        memcpy(buf + w, "...", 3);
        w += 3;
    }
    buf[w] = '\0';
    return buf;
}

int
lf_csv_columns(const char *file, const lf_csv_record *r, const lf_csv_column *cols,
               int ncols, const char *hint, long *col, double *factor, int *has_unit,
               lf_error *err)
{
    char name[256], unit[256], buf[64];
    size_t i;
    int c;

    for (c = 0; c < ncols; c++) {
        col[c] = -1;
        factor[c] = 1.0;
        has_unit[c] = 0;
    }
    for (i = 0; i < r->n; i++) {
        lf_error e;
        for (c = 0; c < ncols; c++)
            if (lf_csv_ieq(r->text[i], cols[c].name))
                break;
        if (c < ncols) {
            unit[0] = '\0';
        } else {
            lf_csv_header_cell(r->text[i], name, sizeof name, unit, sizeof unit);
            for (c = 0; c < ncols; c++)
                if (lf_csv_ieq(name, cols[c].name))
                    break;
        }
        if (c == ncols && !lf_csv_is_text(r))
            return lf_fail_at(err, LF_EFORMAT, file, r->line, 1, LF_CSV_NOT_TEXT);
        if (c == ncols)
            return lf_fail_at(err, LF_EFORMAT, file, r->fline[i], r->fcol[i],
                              "unknown column '%s' (%s)", lf_csv_excerpt(r->text[i], buf, sizeof buf),
                              hint);
        if (col[c] >= 0)
            return lf_fail_at(err, LF_EFORMAT, file, r->fline[i], r->fcol[i],
                              "second %s column (keep one)", cols[c].name);
        col[c] = (long) i;
        if (unit[0] == '\0')
            continue;
        if (cols[c].q == LF_Q_DIMENSIONLESS || cols[c].unit_in_cells != NULL)
            return lf_fail_at(err, LF_EUNIT, file, r->fline[i], r->fcol[i],
                              "column %s takes no unit in its header (name it '%s'%s%s)",
                              cols[c].name, cols[c].name, cols[c].unit_in_cells ? "; " : "",
                              cols[c].unit_in_cells ? cols[c].unit_in_cells : "");
        if (lf_units_factor(unit, cols[c].q, &factor[c], &e) != LF_OK)
            return lf_fail_at(err, e.status, file, r->fline[i], r->fcol[i],
                              "column %s: %s", cols[c].name, e.msg);
        has_unit[c] = 1;
    }
    for (c = 0; c < ncols; c++)
        if (cols[c].required && col[c] < 0)
            return lf_fail_at(err, LF_EFORMAT, file, r->line, 1,
                              "no %s column in the header (%s)", cols[c].name, hint);
    return LF_OK;
}

int
lf_csv_cell_number(const char *file, const lf_csv_record *r, long k,
                   const lf_csv_column *col, int has_unit, double factor,
                   int decimal_comma, double *v, lf_error *err)
{
    const char *t = r->text[k];
    char *text, buf[64];
    lf_error e;
    int status;

    if (col->q == LF_Q_DIMENSIONLESS || has_unit) {
        status = lf_csv_number(t, decimal_comma, v);
        if (status == LF_NUM_OK) {
            *v *= factor;
            return LF_OK;
        }
        if (status == LF_NUM_NONFINITE)
            return lf_fail_at(err, LF_EFORMAT, file, r->fline[k], r->fcol[k],
                              "%s '%s' is not a finite number", col->name,
                              lf_csv_excerpt(t, buf, sizeof buf));
        return lf_fail_at(err, LF_EFORMAT, file, r->fline[k], r->fcol[k],
                          "%s '%s' is not a number (%s)", col->name,
                          lf_csv_excerpt(t, buf, sizeof buf),
                          has_unit ? "the header gives the unit, so a bare "
                          "number such as 1.5" : "e.g. 2");
    }
    /* a copy as long as the cell: a cut cell could read as another value */
    if ((text = lf_strdup(t)) == NULL)
        return lf_fail_at(err, LF_ENOMEM, file, r->line, 0, "out of memory");
    lf_csv_decimal_point(text, decimal_comma);
    status = lf_units_parse(text, col->q, v, &e);
    free(text);
    if (status != LF_OK)
        return lf_fail_at(err, e.status, file, r->fline[k], r->fcol[k], "%s: %s",
                          col->name, e.msg);
    return LF_OK;
}

int
lf_csv_row_cells(const char *file, const lf_csv_record *r, size_t ncols, lf_error *err)
{
    size_t n = r->n;

    while (n > ncols && r->text[n - 1][0] == '\0')
        n--;
    if (n != ncols)
        return lf_fail_at(err, LF_EFORMAT, file, r->line, n > ncols ? r->fcol[ncols] : 1,
                          "row has %zu cell%s, the header %zu (give each column "
                          "a cell; leave optional ones empty)", n, n == 1 ? "" : "s", ncols);
    return LF_OK;
}

int
lf_csv_cell_interface(const char *file, const lf_csv_record *r, long k, lf_base *base,
                      lf_error *err)
{
    char buf[64];

    if (lf_csv_ieq(r->text[k], "frictionless"))
        *base = LF_BASE_FRICTIONLESS;
    else if (lf_csv_ieq(r->text[k], "bonded"))
        *base = LF_BASE_BONDED;
    else
        return lf_fail_at(err, LF_EFORMAT, file, r->fline[k], r->fcol[k],
                          "unknown interface '%s' (expected frictionless or bonded)",
                          lf_csv_excerpt(r->text[k], buf, sizeof buf));
    return LF_OK;
}
