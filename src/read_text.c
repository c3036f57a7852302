/* read_text.c: generic delimited text whose column header is not on line
 * 1: any lines of metadata, then the first row that names columns and is
 * followed by numeric rows (src/read_table.c); tab-, semicolon-, comma- or
 * space-separated, decimal comma wherever the delimiter is not a comma.
 * Depth and force are found by name as in the CSV reader (depth,
 * indentation, displacement, delta, separation / force, load, P), with
 * their units in the header or from --depth-unit / --force-unit; columns of
 * those names in volts or amperes are raw signals and are ignored. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "readers.h"

static const char *const depth_names[] = { "depth", "indentation", "displacement", "delta",
                                           "separation", NULL };
static const char *const force_names[] = { "force", "load", "P", NULL };
static const char *const time_names[] = { "time", NULL };

static int
is_signal(const char *unit)
{
    double f;
    return unit[0] != '\0' && (lf_units_factor(unit, LF_Q_VOLTAGE, &f, NULL) == LF_OK
                               || lf_units_factor(unit, LF_Q_CURRENT, &f, NULL) == LF_OK);
}

/* The column of a role: by name, not a raw signal; two are an error. */
static int
find_role(const lf_text_table *t, const char *const *names, const char *what, lf_curve *c,
          const char *file, int *col, lf_error *err)
{
    size_t j, i;
    *col = -1;
    for (j = 0; j < t->ncol; j++)
        for (i = 0; names[i] != NULL; i++) {
            if (!lf_csv_ieq(t->name[j], names[i]))
                continue;
            if (is_signal(t->unit[j])) {
                lf_warn(&c->info, "ignored: column %zu '%s' (a raw signal)", j + 1, t->cell[j]);
                break;
            }
            if (*col >= 0)
                return lf_fail_at(err, LF_EFORMAT, file, t->header_line, 0,
                                  "second %s column '%s' (column '%s' is the %s already)",
                                  what, t->cell[j], t->cell[*col], what);
            *col = (int) j;
            break;
        }
    return LF_OK;
}

static int
role_factor(const lf_text_table *t, int j, lf_quantity q, const char *opt, const char *what,
            const char *file, double *f, lf_warnings *warn, lf_error *err)
{
    lf_error e;
    if (opt != NULL) {
        if (t->unit[j][0] != '\0' && strcmp(t->unit[j], opt) != 0)
            lf_warn(warn, "%s: the header gives '%s' for %s; the unit given in the options, "
                    "'%s', is used", file, t->unit[j], what, opt);
        if (lf_units_factor(opt, q, f, &e) != LF_OK)
            return lf_fail_at(err, e.status, file, 0, 0, "--%s-unit: %s", what, e.msg);
        return LF_OK;
    }
    if (t->unit[j][0] == '\0' && q == LF_Q_TIME) {
        *f = 1.0;
        return LF_OK;
    }
    if (t->unit[j][0] == '\0')
        return lf_fail_at(err, LF_EUNIT, file, t->header_line, 0,
                          "%s column '%s' has no unit (give --%s-unit)", what, t->cell[j], what);
    return lf_text_table_factor(t, j, q, f, err);
}

int
lf_text_curve(lf_text_table *t, const lf_source *in, const lf_read_opts *o, lf_curve *c,
              lf_warnings *warn, lf_error *err)
{
    int jd, jf, jt, status;
    double fd, ff, ft = 1.0;
    size_t i;

    if ((status = find_role(t, depth_names, "depth", c, in->name, &jd, err)) != LF_OK
        || (status = find_role(t, force_names, "force", c, in->name, &jf, err)) != LF_OK
        || (status = find_role(t, time_names, "time", c, in->name, &jt, err)) != LF_OK)
        return status;
    if (jd < 0 || jf < 0)
        return lf_fail_at(err, LF_EFORMAT, in->name, t->header_line, 0,
                          "no %s column in the table header (name one %s, with its unit)",
                          jd < 0 ? "depth" : "force",
                          jd < 0 ? "depth, indentation or displacement" : "force or load");
    if ((status = role_factor(t, jd, LF_Q_LENGTH, o->depth_unit, "depth", in->name, &fd,
                              warn, err)) != LF_OK
        || (status = role_factor(t, jf, LF_Q_FORCE, o->force_unit, "force", in->name, &ff,
                                 warn, err)) != LF_OK
        || (jt >= 0 && (status = role_factor(t, jt, LF_Q_TIME, NULL, "time", in->name, &ft,
                                             warn, err)) != LF_OK))
        return status;
    if (lf_curve_reserve(c, t->n, jt >= 0) != 0)
        return lf_fail_at(err, LF_ENOMEM, in->name, 0, 0, "out of memory");
    for (i = 0; i < t->n; i++) {
        c->depth[i] = fd * t->col[jd][i];
        c->force[i] = ff * t->col[jf][i];
        if (jt >= 0)
            c->time[i] = ft * t->col[jt][i];
        c->line[i] = t->line[i];
    }
    c->n = t->n;
    lf_warn(&c->info, "table: header on line %ld, delimiter %s%s", t->header_line,
            t->delim == '\t' ? "tab" : t->delim == ' ' ? "spaces" : t->delim == ';' ? "';'" : "','",
            t->decimal_comma ? ", decimal comma" : "");
    lf_warn(&c->info, "depth: column %d '%s', x %.6g to m", jd + 1, t->cell[jd], fd);
    lf_warn(&c->info, "force: column %d '%s', x %.6g to N", jf + 1, t->cell[jf], ff);
    if (jt >= 0)
        lf_warn(&c->info, "time: column %d '%s'", jt + 1, t->cell[jt]);
    if (lf_is_clamped(c->depth, c->n))
        lf_warn(warn, "%s: depth column '%s' is clamped: %zu points sit exactly at its "
                "minimum (it may hide the pull-off)", in->name, t->cell[jd],
                lf_count_at_min(c->depth, c->n));
    lf_segments_from_profile(c, c->depth, c->force, "depth (or load)");
    return LF_OK;
}

/* Whether word occurs in line, any case. */
static int
has_word(const char *line, const char *word)
{
    size_t n = strlen(word), i, k;
    for (i = 0; line[i] != '\0'; i++) {
        for (k = 0; k < n && line[i + k] != '\0'; k++)
            if ((line[i + k] | 0x20) != word[k])
                break;
        if (k == n)
            return 1;
    }
    return 0;
}

/* Claim text whose table is not where the CSV reader looks: a header row
 * with depth and force names below line 1, or separated by spaces. */
static int
text_sniff(const char *head, size_t len)
{
    char line[1024];
    size_t i = 0, lines = 0;
    while (i < len && lines < 200) {
        size_t n = 0, b = 0;
        int k, has_d = 0;
        while (i < len && head[i] != '\n' && head[i] != '\r') {
            if (n + 1 < sizeof line)
                line[n++] = head[i];
            i++;
        }
        while (i < len && (head[i] == '\n' || head[i] == '\r'))
            i++;
        line[n] = '\0';
        while (line[b] == ' ' || line[b] == '\t')
            b++;
        if (line[b] == '\0' || line[b] == '#')    /* the CSV reader skips these */
            continue;
        lines++;
        for (k = 0; depth_names[k] != NULL; k++)
            has_d |= has_word(line, depth_names[k]);
        if (!has_d || !(has_word(line, "force") || has_word(line, "load")))
            continue;
        if (lines > 1)
            return 30;
        /* on the first line: the CSV reader's, unless only blanks separate
         * the names */
        return strchr(line, '\t') == NULL && strchr(line, ',') == NULL
            && strchr(line, ';') == NULL ? 30 : 0;
    }
    return 0;
}

int
lf_text_read(const lf_source *in, const lf_read_opts *o, lf_curve *c, lf_warnings *warn,
             lf_error *err)
{
    lf_text_table t;
    int status;
    memset(&t, 0, sizeof t);
    t.skip_bad_rows = o->skip_bad_rows;
    status = lf_text_table_read(&t, in, c, err);
    if (status == LF_OK)
        status = lf_text_curve(&t, in, o, c, warn, err);
    if (status == LF_OK)
        return lf_text_table_finish(&t, c, warn, err);
    lf_text_table_free(&t);
    return status;
}

const lf_reader_type lf_reader_text = {
    "text", "delimited text with metadata lines above the column header (tab, ';', ',' or "
    "spaces; decimal comma)",
    text_sniff, lf_text_read
};
