/* csv_curve.c: one force-depth curve from a CSV file, in SI units.
 *
 * The header names the columns; depth and force are found by name (depth,
 * indentation, displacement, delta / force, load, P), with their units in
 * the header ("depth_nm", "Load (µN)", "Indentation [um]") or from the
 * options.  Optional time and segment columns are kept; other columns are
 * ignored.  Without a segment column the curve is split at its deepest
 * point.  Every value is checked; what cannot be read is an error with its
 * line and column, what a person should know is a warning. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "readers.h"

enum { COL_DEPTH, COL_FORCE, COL_TIME, COL_SEGMENT, NCOL };

static const struct {
    const char *what;           /* for messages */
    const char *names[5];       /* accepted header names, NULL-ended */
    lf_quantity q;
} roles[NCOL] = {
    { "depth", { "depth", "indentation", "displacement", "delta", NULL }, LF_Q_LENGTH },
    { "force", { "force", "load", "P", NULL }, LF_Q_FORCE },
    { "time", { "time", NULL }, LF_Q_TIME },
    { "segment", { "segment", NULL }, LF_Q_DIMENSIONLESS },
};

typedef struct {
    const char *name;
    lf_read_opts opts;
    lf_warnings *warn;
    lf_curve *c;
    size_t cap, metacap;
    int have_header;
    long header_line;
    size_t ncols;
    long col[NCOL];             /* index of each role's column, or -1 */
    char head[NCOL][64];        /* its header cell, for messages */
    double factor[NCOL];
    char unit[NCOL][64];        /* the unit each column is read in */
    const char *unit_from[NCOL];    /* where that unit came from */
    int decimal_comma;
    char seg_word[16];     /* the last segment cell's text and its segment */
    int seg_last;
    long ncomments, dropped, first_dropped;
    long skipped, first_skipped;
} reader;

void
lf_read_opts_default(lf_read_opts *o)
{
    o->depth_unit = NULL;
    o->force_unit = NULL;
    o->skip_bad_rows = 0;
    o->format = NULL;
    o->spring_constant = NAN;
    o->sensitivity = NAN;
    o->sensitivity_per_amp = 0;
}

const char *
lf_segment_name(lf_segment seg)
{
    return seg == LF_SEG_LOAD ? "load" : seg == LF_SEG_HOLD ? "hold" : "unload";
}

int
lf_segment_find(const char *word)
{
    return lf_csv_segment_word(word);
}

int
lf_csv_segment_word(const char *w)
{
    static const char *const load[] = { "load", "loading", "approach", "extend", NULL };
    static const char *const unload[] = { "unload", "unloading", "retract", "withdraw", NULL };
    static const char *const hold[] = { "hold", "holding", "pause", "dwell", NULL };
    size_t i;
    for (i = 0; load[i] != NULL; i++)
        if (lf_csv_ieq(w, load[i]))
            return LF_SEG_LOAD;
    for (i = 0; hold[i] != NULL; i++)
        if (lf_csv_ieq(w, hold[i]))
            return LF_SEG_HOLD;
    for (i = 0; unload[i] != NULL; i++)
        if (lf_csv_ieq(w, unload[i]))
            return LF_SEG_UNLOAD;
    return -1;
}

static int
role_of(const char *name)
{
    int r;
    size_t i;
    for (r = 0; r < NCOL; r++)
        for (i = 0; roles[r].names[i] != NULL; i++)
            if (lf_csv_ieq(name, roles[r].names[i]))
                return r;
    return -1;
}

/* The unit a role's column is read in: the option, else the header's. */
static int
column_unit(reader *rd, int role, const char *header_unit, long line, long col,
            lf_error *err)
{
    const char *opt = role == COL_DEPTH ? rd->opts.depth_unit
                    : role == COL_FORCE ? rd->opts.force_unit : NULL;
    const char *unit = opt != NULL ? opt : header_unit;
    lf_error e;

    if (opt != NULL && header_unit[0] != '\0' && strcmp(opt, header_unit) != 0)
        lf_warn(rd->warn, "%s:%ld:%ld: the header gives '%s' for %s; the unit "
                "given in the options, '%s', is used", rd->name, line, col,
                header_unit, roles[role].what, opt);
    rd->unit_from[role] = opt != NULL ? "from --" : "from the header";
    if (role == COL_TIME && unit[0] == '\0') {
        lf_warn(rd->warn, "%s:%ld:%ld: time column '%s' has no unit; seconds "
                "assumed", rd->name, line, col, rd->head[role]);
        unit = "s";
        rd->unit_from[role] = "assumed";
    }
    lf_csv_excerpt(unit, rd->unit[role], sizeof rd->unit[role]);
    if (unit[0] == '\0')
        return lf_fail_at(err, LF_EUNIT, rd->name, line, col,
                          "%s column '%s' has no unit (name it in the header, "
                          "e.g. %s_%s or %s (%s), or give --%s-unit)",
                          roles[role].what, rd->head[role], rd->head[role],
                          role == COL_DEPTH ? "nm" : "uN", rd->head[role],
                          role == COL_DEPTH ? "nm" : "µN", roles[role].what);
    if (lf_units_factor(unit, roles[role].q, &rd->factor[role], &e) != LF_OK) {
        if (opt != NULL)
            return lf_fail_at(err, e.status, rd->name, 0, 0, "--%s-unit: %s",
                              roles[role].what, e.msg);
        return lf_fail_at(err, e.status, rd->name, line, col, "%s column '%s': %s",
                          roles[role].what, rd->head[role], e.msg);
    }
    return LF_OK;
}

/* "a, b or c": the names a role's column may have. */
static const char *
name_list(int role, char *buf, size_t n)
{
    size_t i, len = 0;
    buf[0] = '\0';
    for (i = 0; roles[role].names[i] != NULL; i++) {
        const char *sep = i == 0 ? "" : roles[role].names[i + 1] ? ", " : " or ";
        len += (size_t) snprintf(buf + len, len < n ? n - len : 0, "%s%s", sep,
                                 roles[role].names[i]);
    }
    return buf;
}

/* What the header says, for `layerfit check`: the columns used, their units
 * and the factor to SI, and the columns left out. */
static void
header_info(reader *rd, const lf_csv_record *r)
{
    static const char *const si[NCOL] = { "m", "N", "s", "" };
    char buf[64], name[256], unit[256];
    lf_warnings *info = &rd->c->info;
    size_t i;
    int role;

    lf_warn(info, "header: line %ld, delimiter %s%s", r->line,
            r->delim == '\t' ? "tab" : r->delim == ';' ? "';'" : "','",
            rd->decimal_comma ? ", decimal comma" : "");
    for (role = 0; role < COL_SEGMENT; role++) {
        if (rd->col[role] < 0)
            continue;
        if (strcmp(rd->unit_from[role], "from --") == 0)
            lf_warn(info, "%s: column %ld '%s' in %s (from --%s-unit), x %.6g to %s",
                    roles[role].what, rd->col[role] + 1, rd->head[role], rd->unit[role],
                    roles[role].what, rd->factor[role], si[role]);
        else
            lf_warn(info, "%s: column %ld '%s' in %s (%s), x %.6g to %s",
                    roles[role].what, rd->col[role] + 1, rd->head[role], rd->unit[role],
                    rd->unit_from[role], rd->factor[role], si[role]);
    }
    for (i = 0; i < r->n; i++) {
        lf_csv_header_cell(r->text[i], name, sizeof name, unit, sizeof unit);
        if (role_of(name) < 0)
            lf_warn(info, "ignored: column %zu '%s'", i + 1,
                    lf_csv_excerpt(r->text[i], buf, sizeof buf));
    }
}

static int
read_header(reader *rd, const lf_csv_record *r, lf_error *err)
{
    char name[256], unit[256], units[NCOL][256], buf[64];
    double dummy;
    size_t i;
    int role;

    rd->have_header = 1;
    rd->header_line = r->line;
    rd->ncols = r->n;
    rd->decimal_comma = r->delim == ';';
    for (role = 0; role < NCOL; role++)
        rd->col[role] = -1;
    for (i = 0; i < r->n; i++) {
        lf_csv_header_cell(r->text[i], name, sizeof name, unit, sizeof unit);
        role = role_of(name);
        if (role < 0)
            continue;
        if (rd->col[role] >= 0)
            return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[i], r->fcol[i],
                              "second %s column '%s' (column '%s' is the %s "
                              "already; keep one, or rename the other)",
                              roles[role].what, lf_csv_excerpt(r->text[i], buf, sizeof buf),
                              rd->head[role], roles[role].what);
        rd->col[role] = (long) i;
        lf_csv_excerpt(r->text[i], rd->head[role], sizeof rd->head[role]);
        strcpy(units[role], unit);
    }
    for (role = COL_DEPTH; role <= COL_FORCE; role++) {
        if (rd->col[role] >= 0)
            continue;
        if (!lf_csv_is_text(r))
            return lf_fail_at(err, LF_EFORMAT, rd->name, r->line, 1, LF_CSV_NOT_TEXT);
        if (r->n > 0 && lf_csv_number(r->text[0], rd->decimal_comma, &dummy) == LF_NUM_OK)
            return lf_fail_at(err, LF_EFORMAT, rd->name, r->line, 1,
                              "the first row is data, not a header (start with a "
                              "header naming the columns, e.g. depth_nm,force_uN)");
        return lf_fail_at(err, LF_EFORMAT, rd->name, r->line, 1,
                          "no %s column in the header (name one %s, with its "
                          "unit, e.g. %s)", roles[role].what, name_list(role, name, sizeof name),
                          role == COL_DEPTH ? "depth_nm" : "force_uN");
    }
    for (role = 0; role < COL_SEGMENT; role++) {
        long c = rd->col[role];
        int status;
        if (c < 0)
            continue;
        status = column_unit(rd, role, units[role], r->fline[c], r->fcol[c], err);
        if (status != LF_OK)
            return status;
    }
    header_info(rd, r);
    return LF_OK;
}

static int
grow_points(reader *rd)
{
    size_t cap = rd->cap ? 2 * rd->cap : 256;
    if (lf_curve_reserve(rd->c, cap, rd->col[COL_TIME] >= 0) != 0)
        return -1;
    rd->cap = cap;
    return 0;
}

/* A row with a missing cell: an error, or skipped under skip_bad_rows. */
static int
bad_row(reader *rd, const lf_csv_record *r, long col, lf_error *err,
        const char *what)
{
    if (rd->opts.skip_bad_rows) {
        if (rd->skipped++ == 0)
            rd->first_skipped = r->line;
        return LF_OK;
    }
    return lf_fail_at(err, LF_EFORMAT, rd->name, r->line, col,
                      "%s (every row needs a cell in each column; "
                      "--skip-bad-rows skips such rows)", what);
}

static int
read_row(reader *rd, const lf_csv_record *r, lf_error *err)
{
    double v[COL_SEGMENT];
    char buf[64], what[160];
    size_t i, n = r->n;
    int role, seg = LF_SEG_LOAD;
    lf_curve *c = rd->c;

    while (n > rd->ncols && r->text[n - 1][0] == '\0')
        n--;            /* empty cells after the last column are harmless */
    if (n > rd->ncols)
        return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[rd->ncols],
                          r->fcol[rd->ncols], "row has %zu cells, the header "
                          "%zu (is the delimiter '%s' used inside a number? "
                          "quote such cells)", n, rd->ncols,
                          r->delim == '\t' ? "\\t" : r->delim == ';' ? ";" : ",");
    if (n < rd->ncols) {
        long col = n > 0 ? r->fcol[n - 1] + (long) strlen(r->text[n - 1]) : 1;
        snprintf(what, sizeof what, "row has %zu cell%s, the header %zu", n,
                 n == 1 ? "" : "s", rd->ncols);
        return bad_row(rd, r, col, err, what);
    }
    for (role = 0; role < NCOL; role++) {
        long k = rd->col[role];
        const char *t;
        int status;
        if (k < 0)
            continue;
        t = r->text[k];
        if (t[0] == '\0') {
            snprintf(what, sizeof what, "empty %s cell", roles[role].what);
            return bad_row(rd, r, r->fcol[k], err, what);
        }
        if (role == COL_SEGMENT) {
            /* a segment's word repeats on every one of its rows */
            if (strcmp(t, rd->seg_word) == 0) {
                seg = rd->seg_last;
                continue;
            }
            seg = lf_csv_segment_word(t);
            if (seg >= 0 && strlen(t) < sizeof rd->seg_word) {
                strcpy(rd->seg_word, t);
                rd->seg_last = seg;
            }
            if (seg < 0)
                return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                                  "unknown segment '%s' (expected load, approach, "
                                  "extend, hold, pause, dwell, unload, retract or "
                                  "withdraw)",
                                  lf_csv_excerpt(t, buf, sizeof buf));
            continue;
        }
        status = lf_csv_number(t, rd->decimal_comma, &v[role]);
        if (status == LF_NUM_OK) {
            v[role] *= rd->factor[role];
            if (!isfinite(v[role]))
                status = LF_NUM_NONFINITE;
        }
        if (status == LF_NUM_BAD)
            return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                              "%s '%s' is not a number (expected a decimal number "
                              "such as %s)", rd->head[role],
                              lf_csv_excerpt(t, buf, sizeof buf),
                              rd->decimal_comma ? "12,5 or 12.5" : "12.5");
        if (status == LF_NUM_NONFINITE)
            return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                              "%s '%s' is not a finite number (give a measured "
                              "value, or delete the row)", rd->head[role],
                              lf_csv_excerpt(t, buf, sizeof buf));
    }
    if (c->n == rd->cap && grow_points(rd) != 0)
        return lf_fail_at(err, LF_ENOMEM, rd->name, r->line, 0, "out of memory");
    i = c->n++;
    c->depth[i] = v[COL_DEPTH];
    c->force[i] = v[COL_FORCE];
    if (c->time != NULL)
        c->time[i] = v[COL_TIME];
    c->segment[i] = (unsigned char) seg;
    c->line[i] = r->line;
    return LF_OK;
}

static int
on_record(void *ctx, const lf_csv_record *r, lf_error *err)
{
    reader *rd = ctx;
    return r->index == 0 ? read_header(rd, r, err) : read_row(rd, r, err);
}

/* "# key: value" before the header is metadata; other comments are dropped. */
static int
on_comment(void *ctx, long line, const char *text, int before_header, lf_error *err)
{
    reader *rd = ctx;
    const char *colon = strchr(text, ':');
    lf_curve *c = rd->c;
    size_t klen;

    rd->ncomments++;
    if (before_header && colon != NULL && colon > text) {
        lf_meta *m;
        klen = (size_t) (colon - text);
        while (klen > 0 && (text[klen - 1] == ' ' || text[klen - 1] == '\t'))
            klen--;
        if (c->nmeta == rd->metacap) {
            size_t cap = rd->metacap ? 2 * rd->metacap : 8;
            m = realloc(c->meta, cap * sizeof *m);
            if (m == NULL)
                return lf_fail_at(err, LF_ENOMEM, rd->name, line, 0, "out of memory");
            c->meta = m;
            rd->metacap = cap;
        }
        m = &c->meta[c->nmeta];
        colon++;
        colon += strspn(colon, " \t");
        m->key = malloc(klen + 1);
        m->value = lf_strdup(colon);
        if (m->key == NULL || m->value == NULL) {
            free(m->key);
            free(m->value);
            return lf_fail_at(err, LF_ENOMEM, rd->name, line, 0, "out of memory");
        }
        memcpy(m->key, text, klen);
        m->key[klen] = '\0';
        c->nmeta++;
        return LF_OK;
    }
    if (rd->dropped++ == 0)
        rd->first_dropped = line;
    return LF_OK;
}


/* Warn where depth runs backwards within a segment. */
static void
warn_monotonic(const reader *rd)
{
    const lf_curve *c = rd->c;
    static const int segs[2] = { LF_SEG_LOAD, LF_SEG_UNLOAD };   /* load first */
    int seg, q;
    for (q = 0; q < 2; q++) {
        size_t i, prev = 0, back = 0;
        int have = 0;
        long first = 0;
        seg = segs[q];
        for (i = 0; i < c->n; i++) {
            if (c->segment[i] != seg)
                continue;
            if (have && (seg == LF_SEG_LOAD ? c->depth[i] < c->depth[prev]
                                            : c->depth[i] > c->depth[prev])) {
                if (back++ == 0)
                    first = c->line[i];
            }
            prev = i;
            have = 1;
        }
        if (back > 0)
            lf_warn(rd->warn, "%s:%ld: depth %s at %zu point%s of the %sing "
                    "segment (first here)", rd->name, first,
                    seg == LF_SEG_LOAD ? "decreases" : "increases", back,
                    back == 1 ? "" : "s", lf_segment_name((lf_segment) seg));
    }
}

static int
finish(reader *rd, lf_error *err)
{
    if (!rd->have_header) {
        if (rd->ncomments > 0)
            return lf_fail_at(err, LF_EFORMAT, rd->name, 0, 0,
                              "no header row, only comments (the first line that "
                              "is not a comment names the columns, e.g. depth_nm,force_uN)");
        return lf_fail_at(err, LF_EFORMAT, rd->name, 0, 0,
                          "empty file (expected a header such as depth_nm,force_uN "
                          "and one row per point)");
    }
    if (rd->c->n == 0)
        return lf_fail_at(err, LF_EDATA, rd->name, rd->header_line, 0,
                          "header but no data rows (expected one row of %s and %s "
                          "per point below it)", rd->head[COL_DEPTH], rd->head[COL_FORCE]);
    if (rd->col[COL_SEGMENT] < 0)   /* a hold at the deepest point, if any */
        lf_segments_from_profile(rd->c, rd->c->depth, rd->c->force, "depth");
    if (rd->dropped > 0)
        lf_warn(rd->warn, "%s:%ld: dropped %ld comment line%s (first here; only "
                "'# key: value' lines above the header are kept, as metadata)",
                rd->name, rd->first_dropped, rd->dropped, rd->dropped == 1 ? "" : "s");
    if (rd->skipped > 0)
        lf_warn(rd->warn, "%s:%ld: skipped %ld row%s with missing cells (first here)",
                rd->name, rd->first_skipped, rd->skipped, rd->skipped == 1 ? "" : "s");
    warn_monotonic(rd);
    return LF_OK;
}

static int
csv_read(const lf_source *in, const lf_read_opts *o, lf_curve *c, lf_warnings *warn,
         lf_error *err)
{
    lf_csv_handler h = { 0 };   /* callbacks not set stay NULL */
    reader rd;
    int status;

    memset(&rd, 0, sizeof rd);
    rd.name = in->name;
    rd.opts = *o;
    rd.warn = warn;
    rd.c = c;
    h.ctx = &rd;
    h.record = on_record;
    h.comment = on_comment;
    h.line = NULL;
    status = lf_csv_read_input(in, &h, err);
    if (status == LF_OK)
        status = finish(&rd, err);
    if (status != LF_OK)
        return status;
    if (rd.col[COL_SEGMENT] >= 0)
        lf_warn(&c->info, "segments: from column %ld '%s' (load %zu, hold %zu, unload "
                "%zu points)", rd.col[COL_SEGMENT] + 1, rd.head[COL_SEGMENT], lf_curve_segment(c, LF_SEG_LOAD, NULL, NULL),
                lf_curve_segment(c, LF_SEG_HOLD, NULL, NULL),
                lf_curve_segment(c, LF_SEG_UNLOAD, NULL, NULL));
    if (rd.skipped > 0)
        lf_warn(&c->info, "skipped: %ld row%s with missing cells (--skip-bad-rows)",
                rd.skipped, rd.skipped == 1 ? "" : "s");
    return LF_OK;
}

/* Anything not claimed by an instrument's reader is tried as CSV. */
static int
csv_sniff(const char *head, size_t len)
{
    (void) head;
    (void) len;
    return 1;
}

const lf_reader_type lf_reader_csv = {
    "csv", "CSV with a header row on line 1 naming depth and force (datasets/README.md)",
    csv_sniff, csv_read
};

void
lf_curve_free(lf_curve *c)
{
    size_t i;
    if (c == NULL)
        return;
    for (i = 0; i < c->nmeta; i++) {
        free(c->meta[i].key);
        free(c->meta[i].value);
    }
    free(c->meta);
    free(c->file);
    free(c->depth);
    free(c->force);
    free(c->time);
    free(c->segment);
    free(c->line);
    lf_warnings_free(&c->info);
    free(c);
}

size_t
lf_curve_segment(const lf_curve *c, lf_segment seg, double *depth, double *force)
{
    size_t i, m = 0;
    for (i = 0; i < c->n; i++) {
        if (c->segment[i] != seg)
            continue;
        if (depth != NULL)
            depth[m] = c->depth[i];
        if (force != NULL)
            force[m] = c->force[i];
        m++;
    }
    return m;
}

int
lf_curve_check_fit(const lf_curve *c, lf_segment seg, size_t min_points, lf_error *err)
{
    size_t i, m = 0, first = 0;
    int nonzero = 0, varies = 0;
    const char *name = lf_segment_name(seg);

    for (i = 0; i < c->n; i++) {
        if (c->segment[i] != seg)
            continue;
        if (m++ == 0)
            first = i;
        nonzero |= c->force[i] != 0.0;
        varies |= c->depth[i] != c->depth[first];
    }
    if (m < min_points || m == 0)
        return lf_fail_at(err, LF_EDATA, c->file, m ? c->line[first] : 0, 0,
                          "the %sing segment has %zu point%s (a fit needs at "
                          "least %zu)", name, m, m == 1 ? "" : "s", min_points);
    if (!nonzero)
        return lf_fail_at(err, LF_EDATA, c->file, c->line[first], 0,
                          "force is 0 at every point of the %sing segment (is the "
                          "force column the right one?)", name);
    if (!varies)
        return lf_fail_at(err, LF_EDATA, c->file, c->line[first], 0,
                          "depth is %g m at every point of the %sing segment (is the "
                          "depth column the right one?)", c->depth[first], name);
    return LF_OK;
}
