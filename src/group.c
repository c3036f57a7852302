/* group.c: samples of a list of curve files by a rule (lf_plan_group):
 * a header field of each file, a regular expression on its name, or its
 * folder -- so that `layerfit fit --batch *.txt --group-by ...` fits each
 * sample's curves jointly without a hand-written plan. */
#include <ctype.h>
#include <regex.h>
#include <stdlib.h>
#include <string.h>

#include "readers.h"

/* The header field key of the first curve of path, trimmed, into buf. */
static int
field_of(const char *path, long index, const char *key, const lf_read_opts *o, char *buf,
         size_t n, lf_error *err)
{
    lf_file *f = NULL;
    lf_curve *c = NULL;
    const char *v;
    size_t a, b;
    int status = lf_file_open(path, 0, o, &f, NULL, err);

    if (status == LF_OK)
        status = lf_file_curve(f, index >= 0 ? (size_t) index : 0, &c, NULL, err);
    lf_file_close(f);
    if (status != LF_OK)
        return status;
    v = lf_curve_meta(c, key);
    if (v == NULL) {
        lf_curve_free(c);
        return lf_fail(err, LF_EDATA, "%s: its header has no field '%s' to group by (layerfit "
                       "check lists its fields)", path, key);
    }
    for (a = 0; isspace((unsigned char) v[a]); a++)
        ;
    for (b = strlen(v); b > a && isspace((unsigned char) v[b - 1]); b--)
        ;
    if (b - a >= n)
        b = a + n - 1;
    memcpy(buf, v + a, b - a);
    buf[b - a] = '\0';
    lf_curve_free(c);
    if (buf[0] == '\0')
        return lf_fail(err, LF_EDATA, "%s: its header field '%s' is empty: no sample to group "
                       "it by", path, key);
    return LF_OK;
}

/* The regex's first group (else its whole match) in the name of path. */
static int
name_of(const char *path, const regex_t *re, char *buf, size_t n, lf_error *err)
{
    const char *slash = strrchr(path, '/'), *name = slash != NULL ? slash + 1 : path;
    regmatch_t m[2];
    size_t len;
    int g;

    if (regexec(re, name, 2, m, 0) != 0)
        return lf_fail(err, LF_EDATA, "%s: its name does not match the --group-by pattern",
                       path);
    g = m[1].rm_so >= 0 ? 1 : 0;
    len = (size_t) (m[g].rm_eo - m[g].rm_so);
    if (len == 0)
        return lf_fail(err, LF_EDATA, "%s: the --group-by pattern matches nothing of its name",
                       path);
    if (len >= n)
        len = n - 1;
    memcpy(buf, name + m[g].rm_so, len);
    buf[len] = '\0';
    return LF_OK;
}

int
lf_plan_group(lf_plan *plan, const char *rule, const lf_read_opts *o, lf_error *err)
{
    enum { FIELD, NAME, DIR } kind;
    regex_t re;
    char buf[512];
    size_t i;
    int status = LF_OK;

    if (strncmp(rule, "field:", 6) == 0 && rule[6] != '\0')
        kind = FIELD;
    else if (strncmp(rule, "name:", 5) == 0 && rule[5] != '\0')
        kind = NAME;
    else if (strcmp(rule, "dir") == 0)
        kind = DIR;
    else
        return lf_fail(err, LF_EINVAL, "unknown grouping '%s' (field:KEY, a header field; "
                       "name:REGEX, a pattern in the file names; or dir, their folders)", rule);
    if (kind == NAME) {
        int rc = regcomp(&re, rule + 5, REG_EXTENDED);
        if (rc != 0) {
            regerror(rc, &re, buf, sizeof buf);
            return lf_fail(err, LF_EINVAL, "the pattern of '%s' is not a regular expression: %s",
                           rule, buf);
        }
    }
    for (i = 0; i < plan->n && status == LF_OK; i++) {
        lf_plan_row *r = &plan->rows[i];
        char *s;
        if (kind == FIELD) {
            status = field_of(r->file, r->index, rule + 6, o, buf, sizeof buf, err);
        } else if (kind == NAME) {
            status = name_of(r->file, &re, buf, sizeof buf, err);
        } else {
            const char *slash = strrchr(r->file, '/');
            size_t len = slash == NULL ? 1 : slash == r->file ? 1 : (size_t) (slash - r->file);
            if (len >= sizeof buf)
                len = sizeof buf - 1;
            memcpy(buf, slash == NULL ? "." : slash == r->file ? "/" : r->file, len);
            buf[len] = '\0';
        }
        if (status != LF_OK)
            break;
        if ((s = lf_strdup(buf)) == NULL) {
            status = lf_fail(err, LF_ENOMEM, "out of memory");
            break;
        }
        free(r->sample);
        r->sample = s;
    }
    if (kind == NAME)
        regfree(&re);
    return status;
}
