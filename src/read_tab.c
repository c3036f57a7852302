/* read_tab.c: afmformats' tab-separated export (.tab).
 *
 * Layout, as afmformats writes it: "# afmformats VERSION", a JSON object
 * of metadata between "# BEGIN METADATA" and "# END METADATA" (each line
 * behind "# "), then "# " and the column names separated by tabs, then one
 * tab-separated row per point.  Its writer leaves out the line break after
 * the column names, so the first row is glued to them ("...\ttime-6.77e-10\t
 * 5.51e-05..."): the row is taken from there.  Columns (afmformats'
 * names, SI units): force (N), height (measured) and height (piezo) (m,
 * JPK's convention: growing away from the sample), tip position (m),
 * segment (False / 0 approach, True / 1 retract), time (s), index.
 *
 * Used: force; depth = -tip position where the file has it, else
 * -(height + force / k) (the measured height first), k the metadata's
 * "spring constant"; position from "position x" / "position y" (m). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "readers.h"

enum { C_FORCE, C_HMEAS, C_HPIEZO, C_TIP, C_SEGMENT, C_TIME, C_INDEX, NC };
static const char *const col_name[NC] = {
    "force", "height (measured)", "height (piezo)", "tip position", "segment", "time", "index"
};

typedef struct {
    lf_curve *c;
    const char *name;
    int in_meta, meta_done, have_header;
    char *json;             /* the metadata block */
    size_t jlen, jcap;
    int col[16];            /* the role of each column, or -1 */
    size_t ncol;
    double *v[NC];          /* the columns read */
    size_t n, cap;
    long first_line;
    lf_warnings *warn;
} tab_reader;

static int
tab_sniff(const char *head, size_t len)
{
    char buf[4096];
    lf_sniff_text(head, len, buf, sizeof buf);
    if (strstr(buf, "# BEGIN METADATA") != NULL && strstr(buf, "# afmformats") != NULL)
        return 95;
    if (strstr(buf, "# BEGIN METADATA") != NULL && strstr(buf, "# END METADATA") != NULL)
        return 70;
    return 0;
}

/* ---- a flat JSON object: "key": value pairs ---------------------------- */

static const char *
json_string(const char *p, char *out, size_t n)
{
    size_t w = 0;
    if (*p != '"')
        return NULL;
    for (p++; *p && *p != '"'; p++) {
        char ch = *p;
        if (ch == '\\' && p[1] != '\0') {
            p++;
            ch = *p == 'n' ? '\n' : *p == 't' ? '\t' : *p;
            if (*p == 'u') {            /* \uXXXX: kept as '?' */
                size_t k;
                for (k = 0; k < 4 && p[1] != '\0' && p[1] != '"'; k++)
                    p++;
                ch = '?';
            }
        }
        if (w + 1 < n)
            out[w++] = ch;
    }
    out[w] = '\0';
    return *p == '"' ? p + 1 : NULL;
}

/* Each "key": scalar of the object into the curve's metadata (nested
 * values skipped). */
static void
json_meta(lf_curve *c, const char *p)
{
    char key[128], val[256];
    p = strchr(p, '{');
    if (p == NULL)
        return;
    p++;
    for (;;) {
        p += strspn(p, " \t\r\n,");
        if (*p != '"')
            return;
        if ((p = json_string(p, key, sizeof key)) == NULL)
            return;
        p += strspn(p, " \t\r\n");
        if (*p != ':')
            return;
        p++;
        p += strspn(p, " \t\r\n");
        if (*p == '"') {
            if ((p = json_string(p, val, sizeof val)) == NULL)
                return;
        } else if (*p == '{' || *p == '[') {
            int depth = 0;
            for (; *p; p++) {
                depth += *p == '{' || *p == '[';
                depth -= *p == '}' || *p == ']';
                if (depth == 0) {
                    p++;
                    break;
                }
            }
            continue;
        } else {
            size_t n = strcspn(p, ",}\r\n");
            snprintf(val, sizeof val, "%.*s", (int) (n < sizeof val - 1 ? n : sizeof val - 1), p);
            while (strlen(val) > 0 && (val[strlen(val) - 1] == ' ' || val[strlen(val) - 1] == '\t'))
                val[strlen(val) - 1] = '\0';
            p += n;
        }
        lf_curve_add_meta(c, key, val);
    }
}

/* ---- the table ----------------------------------------------------------- */

static int
role_of(const char *cell, size_t *used)
{
    int r;
    for (r = 0; r < NC; r++) {
        size_t n = strlen(col_name[r]);
        if (strncmp(cell, col_name[r], n) == 0) {
            *used = n;
            return r;
        }
    }
    return -1;
}

static int
add_row(tab_reader *t, char **cells, size_t n, long line, lf_error *err)
{
    size_t j;
    int r;
    if (n != t->ncol)
        return lf_fail_at(err, LF_EFORMAT, t->name, line, 1, "row has %zu cells, the column "
                          "line names %zu", n, t->ncol);
    if (t->n == t->cap) {
        size_t cap = t->cap ? 2 * t->cap : 1024;
        for (r = 0; r < NC; r++) {
            double *p = realloc(t->v[r], cap * sizeof *p);
            if (p == NULL)
                return lf_fail_at(err, LF_ENOMEM, t->name, line, 0, "out of memory");
            t->v[r] = p;
        }
        if (lf_curve_reserve(t->c, cap, 0) != 0)
            return lf_fail_at(err, LF_ENOMEM, t->name, line, 0, "out of memory");
        t->cap = cap;
    }
    for (r = 0; r < NC; r++)
        t->v[r][t->n] = NAN;
    for (j = 0; j < n; j++) {
        double x;
        char buf[64];
        if (t->col[j] < 0)
            continue;
        if (t->col[j] == C_SEGMENT && (strcmp(cells[j], "False") == 0 || strcmp(cells[j], "True") == 0)) {
            x = cells[j][0] == 'T';
        } else if (lf_csv_number(cells[j], 0, &x) != LF_NUM_OK || !isfinite(x)) {
            return lf_fail_at(err, LF_EFORMAT, t->name, line, 0, "%s '%s' is not a number",
                              col_name[t->col[j]], lf_csv_excerpt(cells[j], buf, sizeof buf));
        }
        t->v[t->col[j]][t->n] = x;
    }
    t->c->line[t->n] = line;
    t->n++;
    return LF_OK;
}

/* The column line, and the first row glued to it. */
static int
column_line(tab_reader *t, char *text, long line, lf_error *err)
{
    char *cells[64], *rest[64];
    size_t n = lf_split_cells(text, '\t', cells, NULL, 64), j, nrest = 0, used;
    for (j = 0; j < n; j++) {
        int r = role_of(cells[j], &used);
        if (nrest > 0) {
            rest[nrest++] = cells[j];
            continue;
        }
        if (t->ncol >= 16)
            return lf_fail_at(err, LF_EFORMAT, t->name, line, 0, "more than 16 columns");
        t->col[t->ncol++] = r;          /* -1: a column layerfit needs not */
        if (r < 0)
            continue;
        if (cells[j][used] != '\0')     /* the glued first row starts here */
            rest[nrest++] = cells[j] + used;
    }
    t->have_header = 1;
    if (t->col[0] < 0 && t->ncol == 1)
        return lf_fail_at(err, LF_EFORMAT, t->name, line, 0, "the column line names no column "
                          "afmformats writes (force, height (measured), ...)");
    return nrest > 0 ? add_row(t, rest, nrest, line, err) : LF_OK;
}

static int
on_line(void *ctx, long line, char *text, size_t len, lf_error *err)
{
    tab_reader *t = ctx;
    char *cells[64];
    size_t n;
    (void) len;
    if (text[0] == '#') {
        char *p = text + 1 + strspn(text + 1, " ");
        if (t->have_header)
            return LF_OK;
        if (strncmp(p, "BEGIN METADATA", 14) == 0) {
            t->in_meta = 1;
            return LF_OK;
        }
        if (strncmp(p, "END METADATA", 12) == 0) {
            t->in_meta = 0;
            t->meta_done = 1;
            return LF_OK;
        }
        if (t->in_meta) {
            size_t k = strlen(p);
            if (t->jlen + k + 2 > t->jcap) {
                size_t cap = 2 * (t->jcap + k + 2);
                char *j = realloc(t->json, cap);
                if (j == NULL)
                    return lf_fail_at(err, LF_ENOMEM, t->name, line, 0, "out of memory");
                t->json = j;
                t->jcap = cap;
            }
            memcpy(t->json + t->jlen, p, k);
            t->jlen += k;
            t->json[t->jlen++] = '\n';
            t->json[t->jlen] = '\0';
            return LF_OK;
        }
        if (strchr(p, '\t') != NULL && t->meta_done)
            return column_line(t, p, line, err);
        return LF_OK;
    }
    if (text[strspn(text, " \t")] == '\0')
        return LF_OK;
    if (!t->have_header)
        return lf_fail_at(err, LF_EFORMAT, t->name, line, 1, "data before the '# force\\t...' "
                          "line that names the columns");
    n = lf_split_cells(text, '\t', cells, NULL, 64);
    return add_row(t, cells, n, line, err);
}

static int
has(const tab_reader *t, int role)
{
    size_t j;
    for (j = 0; j < t->ncol; j++)
        if (t->col[j] == role)
            return 1;
    return 0;
}

static int
tab_read(const lf_source *in, const lf_read_opts *o, lf_curve *c, lf_warnings *warn,
         lf_error *err)
{
    lf_csv_handler h = { 0 };
    tab_reader t;
    int status, r, h_col;
    size_t i;
    double k;

    memset(&t, 0, sizeof t);
    t.c = c;
    t.name = in->name;
    t.warn = warn;
    h.ctx = &t;
    h.line = on_line;
    status = lf_csv_read_input(in, &h, err);
    if (status == LF_OK && t.json != NULL)
        json_meta(c, t.json);
    if (status == LF_OK && !t.have_header)
        status = lf_fail_at(err, LF_EFORMAT, in->name, 0, 0, "no '# force\\t...' line naming "
                            "the columns after the metadata");
    if (status == LF_OK && !has(&t, C_FORCE))
        status = lf_fail_at(err, LF_EFORMAT, in->name, 0, 0, "no force column");
    h_col = has(&t, C_TIP) ? C_TIP : has(&t, C_HMEAS) ? C_HMEAS : has(&t, C_HPIEZO) ? C_HPIEZO : -1;
    if (status == LF_OK && h_col < 0)
        status = lf_fail_at(err, LF_EFORMAT, in->name, 0, 0, "no tip position or height column");
    k = lf_number_or_nan(lf_curve_meta(c, "spring constant"));
    if (status == LF_OK && h_col != C_TIP)
        status = lf_afm_spring_constant(c, k, "spring constant", o,
                                        "to turn the force into a deflection for the "
                                        "tip-sample separation", err);
    if (status == LF_OK) {
        int have_seg = has(&t, C_SEGMENT);
        for (i = 0; i < t.n; i++) {
            double f = t.v[C_FORCE][i];
            c->force[i] = f;
            c->depth[i] = h_col == C_TIP ? -t.v[C_TIP][i] : -(t.v[h_col][i] + f / c->spring_constant);
            c->segment[i] = (unsigned char) (have_seg && t.v[C_SEGMENT][i] >= 0.5 ? LF_SEG_UNLOAD
                                                                                    : LF_SEG_LOAD);
        }
        c->n = t.n;
        if (has(&t, C_TIME) && t.n > 0 && lf_curve_reserve(c, t.cap, 1) == 0)
            for (i = 0; i < t.n; i++)
                c->time[i] = t.v[C_TIME][i];
        if (!have_seg && t.n > 0)
            lf_segments_from_profile(c, c->depth, c->force, "depth");
        c->x = lf_number_or_nan(lf_curve_meta(c, "position x"));
        c->y = lf_number_or_nan(lf_curve_meta(c, "position y"));
        if (isnan(c->x) || isnan(c->y))
            c->x = c->y = NAN;
        else
            lf_warn(&c->info, "position: x %.6g m, y %.6g m (metadata 'position x', 'position "
                    "y')", c->x, c->y);
        if (lf_curve_meta(c, "grid index x") != NULL && lf_curve_meta(c, "grid index y") != NULL) {
            c->grid_i = lf_whole(lf_number_or_nan(lf_curve_meta(c, "grid index x")), 0, 1000000, -1);
            c->grid_j = lf_whole(lf_number_or_nan(lf_curve_meta(c, "grid index y")), 0, 1000000, -1);
            if (c->grid_i < 0 || c->grid_j < 0)
                c->grid_i = c->grid_j = -1;
        }
        lf_warn(&c->info, "force: column 'force' (N)");
        if (h_col == C_TIP)
            lf_warn(&c->info, "depth: -'tip position' (into the sample positive)");
        else
            lf_warn(&c->info, "depth: tip-sample separation = -('%s' + force / k) (into the "
                    "sample positive)", col_name[h_col]);
        if (have_seg)
            lf_warn(&c->info, "segments: from the segment column (False approach, True retract)");
        status = lf_curve_finish(c, warn, err);
    }
    for (r = 0; r < NC; r++)
        free(t.v[r]);
    free(t.json);
    return status;
}

const lf_reader_type lf_reader_tab = {
    "tab", "afmformats' tab-separated export (.tab: JSON metadata block, then force, "
    "height (measured), height (piezo), segment, time)",
    tab_sniff, tab_read
};
