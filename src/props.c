/* props.c: Java properties files (the text files of a JPK archive).
 *
 * The format of java.util.Properties.load: one "key=value" (or "key:
 * value", or "key value") per logical line; '#' or '!' start a comment
 * line; a backslash at the end of a line joins the next one (its leading
 * blanks dropped); backslash escapes \t \n \r \f, \uXXXX (UTF-16, written
 * here as UTF-8), and a backslash before any other character stands for
 * that character ("2013-05-27 13\:57\:09").  Keys are kept sorted, so that
 * a lookup is a binary search; a key given twice keeps its last value. */
#include <stdlib.h>
#include <string.h>

#include "readers.h"

static int
is_blank(char c)
{
    return c == ' ' || c == '\t' || c == '\f';
}

/* Append the UTF-8 encoding of code point u to out (room for 4 bytes). */
static size_t
put_utf8(char *out, unsigned u)
{
    if (u < 0x80) {
        out[0] = (char) u;
        return 1;
    }
    if (u < 0x800) {
        out[0] = (char) (0xC0 | (u >> 6));
        out[1] = (char) (0x80 | (u & 0x3F));
        return 2;
    }
    if (u >= 0xD800 && u <= 0xDFFF)     /* a lone surrogate: the replacement character */
        u = 0xFFFD;
    out[0] = (char) (0xE0 | (u >> 12));
    out[1] = (char) (0x80 | ((u >> 6) & 0x3F));
    out[2] = (char) (0x80 | (u & 0x3F));
    return 3;
}

static int
hexval(char c)
{
    return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10
         : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
}

/* Unescape the logical line that starts at text[*at] into out (which has
 * room for the line), up to its end; *at is moved past the line.  *sep
 * gets the offset in out where the value starts (after the key and its
 * separator), -1 when the line is blank or a comment. */
static size_t
logical_line(const char *text, size_t len, size_t *at, char *out, long *sep)
{
    size_t i = *at, w = 0;
    int in_key = 1, after_key = 0;

    *sep = -1;
    while (i < len && is_blank(text[i]))
        i++;
    if (i < len && (text[i] == '#' || text[i] == '!')) {
        while (i < len && text[i] != '\n' && text[i] != '\r')
            i++;
        *at = i;
        return 0;
    }
    for (; i < len && text[i] != '\n' && text[i] != '\r'; i++) {
        char c = text[i];
        if (after_key) {
            /* blanks, then at most one '=' or ':', then blanks */
            if (is_blank(c))
                continue;
            if ((c == '=' || c == ':') && after_key == 1) {
                after_key = 2;
                continue;
            }
            after_key = 0;
        }
        if (c == '\\') {
            if (i + 1 >= len) {
                i++;
                break;
            }
            c = text[++i];
            if (c == '\n' || c == '\r') {   /* a continued line */
                if (c == '\r' && i + 1 < len && text[i + 1] == '\n')
                    i++;
                while (i + 1 < len && is_blank(text[i + 1]))
                    i++;
                continue;
            }
            if (c == 'u' && i + 4 < len) {
                int h[4], k, ok = 1;
                for (k = 0; k < 4; k++)
                    ok &= (h[k] = hexval(text[i + 1 + (size_t) k])) >= 0;
                if (ok) {
                    w += put_utf8(out + w, (unsigned) (h[0] << 12 | h[1] << 8 | h[2] << 4 | h[3]));
                    i += 4;
                    continue;
                }
            }
            out[w++] = c == 't' ? '\t' : c == 'n' ? '\n' : c == 'r' ? '\r' : c == 'f' ? '\f' : c;
            continue;
        }
        if (in_key && (c == '=' || c == ':' || is_blank(c))) {
            in_key = 0;
            out[w++] = '\0';
            *sep = (long) w;
            after_key = c == '=' || c == ':' ? 2 : 1;
            continue;
        }
        out[w++] = c;
    }
    if (in_key && w > 0) {      /* a key without a value */
        out[w++] = '\0';
        *sep = (long) w;
    }
    out[w] = '\0';
    *at = i;
    return w;
}

static int
cmp_kv(const void *a, const void *b)
{
    const lf_prop *x = a, *y = b;
    int c = strcmp(x->key, y->key);
    /* the later of two equal keys sorts last: a lookup finds the last one */
    return c != 0 ? c : x->key < y->key ? -1 : x->key > y->key;
}

int
lf_props_parse(lf_props *p, const char *text, size_t len)
{
    size_t at = 0, cap = 0, w = 0;
    char *line;

    memset(p, 0, sizeof *p);
    /* every logical line fits in its own length plus two NULs */
    p->buf = malloc(len + 2 * (len / 2 + 2) + 1);
    if (p->buf == NULL)
        return LF_ENOMEM;
    while (at < len) {
        long sep;
        size_t n;
        line = p->buf + w;
        n = logical_line(text, len, &at, line, &sep);
        while (at < len && (text[at] == '\n' || text[at] == '\r'))
            at++;
        if (sep < 0 || line[0] == '\0')
            continue;
        if (p->n == cap) {
            lf_prop *kv;
            cap = cap ? 2 * cap : 64;
            kv = realloc(p->kv, cap * sizeof *kv);
            if (kv == NULL) {
                lf_props_free(p);
                return LF_ENOMEM;
            }
            p->kv = kv;
        }
        p->kv[p->n].key = line;
        p->kv[p->n].value = line + sep;
        p->kv[p->n].klen = (size_t) sep - 1;
        p->n++;
        w += n + 1;
    }
    /* pointers into buf stay valid: buf is not moved after this */
    qsort(p->kv, p->n, sizeof *p->kv, cmp_kv);
    return LF_OK;
}

const char *
lf_props_get(const lf_props *p, const char *key)
{
    size_t lo = 0, hi = p->n;
    const char *found = NULL;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        int c = strcmp(p->kv[mid].key, key);
        if (c <= 0) {
            if (c == 0)
                found = p->kv[mid].value;
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    return found;
}

const char *
lf_props_suffix(const lf_props *p, const char *suffix, const char **key)
{
    size_t i, ns = strlen(suffix);
    for (i = 0; i < p->n; i++) {
        size_t nk = p->kv[i].klen;
        if (nk >= ns && memcmp(p->kv[i].key + nk - ns, suffix, ns) == 0) {
            if (key != NULL)
                *key = p->kv[i].key;
            return p->kv[i].value;
        }
    }
    return NULL;
}

void
lf_props_free(lf_props *p)
{
    if (p == NULL)
        return;
    free(p->buf);
    free(p->kv);
    memset(p, 0, sizeof *p);
}
