/* read_hysitron.c: Hysitron (Bruker) TriboIndenter exports.
 *
 * The text export, as the instrument writes it: a few header lines (the
 * date, "Number of Points = N"), then a tab-separated table
 *     Depth (nm)  Load (µN)  Time (s)  Depth (V)  Load (V)
 * with the micro sign as the Latin-1 byte 0xB5.  The voltage columns are
 * the raw transducer signals and are ignored.  Depth is the indenter's
 * displacement, positive into the sample; the load is positive pushing.
 * Segments: loading, a hold at the peak load (load-controlled), unloading,
 * from the load and depth profiles.
 *
 * The .hld file: "File Version: Hysitron ..." and "Key: value unit"
 * header lines (the test's segments among them: "Segment Begin Demand",
 * "Segment End Demand", "Segment Points"), then tables, each announced by
 * "NAME Data Points: N", a line of column names with their units after an
 * underscore ("Time_s  Disp_nm  Force_µN ..."), and N rows: the sample
 * approach, the drift measurement, and the test itself.  The first table
 * with a displacement and a force column is read (the test's); the others
 * are named by `check`.  Segments: consecutive blocks of "Segment Points"
 * rows, loading where the demand rises, unloading where it falls, a hold
 * where it stays; from the profile when the counts do not add up. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "readers.h"

static int
hysitron_sniff(const char *head, size_t len)
{
    char buf[4096];
    lf_sniff_text(head, len, buf, sizeof buf);
    if (strncmp(buf, "File Version: Hysitron", 22) == 0)
        return 95;
    if (strstr(buf, "Number of Points = ") != NULL && strstr(buf, "Depth (nm)\tLoad (") != NULL)
        return 90;
    if (strstr(buf, "Depth (nm)\tLoad (") != NULL && strstr(buf, "\tDepth (V)") != NULL)
        return 70;
    if (strstr(buf, "\nDepth (nm)\tLoad (") != NULL && strstr(buf, "\tTime (s)") != NULL)
        return 50;
    return 0;
}

#define HLD_MAX_SEG 64

typedef struct {
    lf_curve *c;
    const char *name;
    int state;                  /* 0 header, 1 a table's column line next, 2 its rows */
    int reading;                /* the rows are the table read */
    int done;                   /* a table was read */
    long rows_left;
    char table[64], read_name[64], others[400];
    double seg_begin[HLD_MAX_SEG], seg_end[HLD_MAX_SEG];
    long seg_points[HLD_MAX_SEG];
    size_t nseg_begin, nseg_end, nseg_points;
    int jd, jf, jt;
    size_t ncol;
    double fd, ff, ft;
    char cd[64], cf[64];
    size_t cap;
} hld_reader;

static int
hld_columns(hld_reader *h, char *text, long line, lf_error *err)
{
    char *cells[64], name[96], unit[32];
    size_t n = lf_split_cells(text, '\t', cells, NULL, 64), j;
    lf_error e;
    h->jd = h->jf = h->jt = -1;
    for (j = 0; j < n; j++) {
        lf_csv_header_cell(cells[j], name, sizeof name, unit, sizeof unit);
        if (h->jd < 0 && (lf_csv_ieq(name, "Disp") || lf_csv_ieq(name, "Depth")))
            h->jd = (int) j;
        else if (h->jf < 0 && (lf_csv_ieq(name, "Force") || lf_csv_ieq(name, "Load")))
            h->jf = (int) j;
        else if (h->jt < 0 && lf_csv_ieq(name, "Time"))
            h->jt = (int) j;
        else
            continue;
        if (lf_units_factor(unit, j == (size_t) h->jd ? LF_Q_LENGTH : j == (size_t) h->jf
                            ? LF_Q_FORCE : LF_Q_TIME, j == (size_t) h->jd ? &h->fd
                            : j == (size_t) h->jf ? &h->ff : &h->ft, &e) != LF_OK)
            return lf_fail_at(err, LF_EUNIT, h->name, line, 0, "column '%s': %s", cells[j], e.msg);
        if (j == (size_t) h->jd)
            lf_latin1_to_utf8(cells[j], h->cd, sizeof h->cd);
        else if (j == (size_t) h->jf)
            lf_latin1_to_utf8(cells[j], h->cf, sizeof h->cf);
    }
    h->ncol = n;
    h->reading = !h->done && h->jd >= 0 && h->jf >= 0;
    if (h->reading) {
        snprintf(h->read_name, sizeof h->read_name, "%s", h->table);
        h->cap = 0;
    } else {
        size_t len = strlen(h->others);
        snprintf(h->others + len, sizeof h->others - len, "%s%s (%ld rows)", len ? ", " : "",
                 h->table, h->rows_left);
    }
    return LF_OK;
}

static int
hld_line(void *ctx, long line, char *text, size_t len, lf_error *err)
{
    hld_reader *h = ctx;
    char *colon, buf[64];
    (void) len;
    if (text[strspn(text, " \t")] == '\0')
        return LF_OK;
    if (h->state == 1) {
        h->state = h->rows_left > 0 ? 2 : 0;
        return hld_columns(h, text, line, err);
    }
    if (h->state == 2) {
        char *cells[64];
        size_t n = lf_split_cells(text, '\t', cells, NULL, 64), i;
        double d, f, t = NAN;
        if (--h->rows_left == 0)
            h->state = 0;
        if (!h->reading)
            return LF_OK;
        if (n != h->ncol)
            return lf_fail_at(err, LF_EFORMAT, h->name, line, 1, "row has %zu cells, the "
                              "table's column line %zu", n, h->ncol);
        if (lf_csv_number(cells[h->jd], 0, &d) != LF_NUM_OK
            || lf_csv_number(cells[h->jf], 0, &f) != LF_NUM_OK
            || (h->jt >= 0 && lf_csv_number(cells[h->jt], 0, &t) != LF_NUM_OK))
            return lf_fail_at(err, LF_EFORMAT, h->name, line, 1, "'%s' is not a row of numbers",
                              lf_csv_excerpt(text, buf, sizeof buf));
        if (h->c->n == h->cap) {
            size_t cap = h->cap ? 2 * h->cap : 1024;
            if (lf_curve_reserve(h->c, cap, h->jt >= 0) != 0)
                return lf_fail_at(err, LF_ENOMEM, h->name, line, 0, "out of memory");
            h->cap = cap;
        }
        i = h->c->n++;
        h->c->depth[i] = h->fd * d;
        h->c->force[i] = h->ff * f;
        if (h->jt >= 0)
            h->c->time[i] = h->ft * t;
        h->c->segment[i] = LF_SEG_LOAD;
        h->c->line[i] = line;
        if (h->rows_left == 0) {
            h->reading = 0;
            h->done = 1;
        }
        return LF_OK;
    }
    if ((colon = strstr(text, " Data Points:")) != NULL) {
        double n = lf_number_or_nan(colon + 13);
        *colon = '\0';
        if (!(n >= 0 && n < 1e9))
            return lf_fail_at(err, LF_EFORMAT, h->name, line, 0, "'%s Data Points' without a "
                              "count", lf_csv_excerpt(text, buf, sizeof buf));
        lf_latin1_to_utf8(text, h->table, sizeof h->table);
        h->rows_left = (long) n;
        h->state = 1;
        return LF_OK;
    }
    if ((colon = strchr(text, ':')) != NULL) {
        char *v = colon + 1 + strspn(colon + 1, " \t");
        *colon = '\0';
        if (strcmp(text, "Segment Begin Demand") == 0 && h->nseg_begin < HLD_MAX_SEG)
            h->seg_begin[h->nseg_begin++] = strtod(v, NULL);
        else if (strcmp(text, "Segment End Demand") == 0 && h->nseg_end < HLD_MAX_SEG)
            h->seg_end[h->nseg_end++] = strtod(v, NULL);
        else if (strcmp(text, "Segment Points") == 0 && h->nseg_points < HLD_MAX_SEG)
            h->seg_points[h->nseg_points++] = strtol(v, NULL, 10);
        if (text[0] != '\0' && lf_curve_add_meta(h->c, text, v) != 0)
            return lf_fail_at(err, LF_ENOMEM, h->name, line, 0, "out of memory");
    }
    return LF_OK;
}

/* Segments from the header's blocks of points; 0 when they do not add up. */
static int
hld_segments(const hld_reader *h, lf_curve *c)
{
    size_t s, m = 0, total = 0;
    if (h->nseg_points == 0 || h->nseg_begin != h->nseg_points || h->nseg_end != h->nseg_points)
        return 0;
    for (s = 0; s < h->nseg_points; s++) {
        if (h->seg_points[s] < 0)
            return 0;
        total += (size_t) h->seg_points[s];
    }
    if (total != c->n)
        return 0;
    for (s = 0; s < h->nseg_points; s++) {
        int kind = h->seg_end[s] > h->seg_begin[s] ? LF_SEG_LOAD
                 : h->seg_end[s] < h->seg_begin[s] ? LF_SEG_UNLOAD : LF_SEG_HOLD;
        long k;
        for (k = 0; k < h->seg_points[s]; k++)
            c->segment[m++] = (unsigned char) kind;
    }
    return 1;
}

static int
hld_read(const lf_source *in, const lf_read_opts *o, lf_curve *c, lf_warnings *warn,
         lf_error *err)
{
    lf_csv_handler hd = { 0 };
    hld_reader h;
    int status;
    (void) o;

    memset(&h, 0, sizeof h);
    h.c = c;
    h.name = in->name;
    hd.ctx = &h;
    hd.line = hld_line;
    if ((status = lf_csv_read_input(in, &hd, err)) != LF_OK)
        return status;
    if (!h.done && c->n == 0)
        return lf_fail_at(err, LF_EFORMAT, in->name, 0, 0, "no load-displacement table (a "
                          "table with displacement and force columns after its 'Data Points' "
                          "line)%s%s", h.others[0] ? "; tables: " : "", h.others);
    if (c->time != NULL && h.jt < 0) {
        free(c->time);
        c->time = NULL;
    }
    lf_warn(&c->info, "table: '%s' (%zu rows)%s%s%s", h.read_name, c->n,
            h.others[0] ? "; not used: " : "", h.others, "");
    lf_warn(&c->info, "depth: column '%s', x %.6g to m", h.cd, h.fd);
    lf_warn(&c->info, "force: column '%s', x %.6g to N", h.cf, h.ff);
    if (hld_segments(&h, c))
        lf_warn(&c->info, "segments: from the header's %zu segments (load where the demand "
                "rises, unload where it falls, hold where it stays: load %zu, hold %zu, "
                "unload %zu points)", h.nseg_points, lf_curve_segment(c, LF_SEG_LOAD, NULL, NULL),
                lf_curve_segment(c, LF_SEG_HOLD, NULL, NULL),
                lf_curve_segment(c, LF_SEG_UNLOAD, NULL, NULL));
    else
        lf_segments_from_profile(c, c->depth, c->force, "depth");
    return lf_curve_finish(c, warn, err);
}

static int
hysitron_read(const lf_source *in, const lf_read_opts *o, lf_curve *c, lf_warnings *warn,
              lf_error *err)
{
    char buf[64];
    lf_sniff_text(in->buf, in->len, buf, sizeof buf);
    if (strncmp(buf, "File Version: Hysitron", 22) == 0)
        return hld_read(in, o, c, warn, err);
    return lf_text_read(in, o, c, warn, err);
}

const lf_reader_type lf_reader_hysitron = {
    "hysitron", "Hysitron nanoindenter: text export (Depth (nm), Load (uN), Time (s), raw "
    "voltages ignored) or .hld file (the test's table of its tables)",
    hysitron_sniff, hysitron_read
};
