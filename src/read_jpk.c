/* read_jpk.c: JPK (Bruker) force-save text exports.
 *
 * Layout, as JPK's software writes it: a block of "# key: value" lines
 * before each segment (extend, pause, retract, ...), each block naming the
 * segment ("# segment: extend"), its columns ("# columns: height
 * vDeflection ...") and their units ("# units: m N ..."), the cantilever's
 * "springConstant" (N/m) and "sensitivity" (m/V); then rows of numbers
 * separated by spaces.  Segments may have different columns.
 *
 * Conventions: heights grow away from the sample (the piezo extends
 * downwards as the height falls), and vDeflection is positive when the
 * cantilever bends up, i.e. when it pushes.  With the deflection d in m
 * (vDeflection / k when exported as a force, x sensitivity when in V), the
 * tip position is height + d, so the tip-sample separation positive into
 * the sample is -(height + d); the force is k d (vDeflection itself when
 * exported in N).  Height column, by preference: measuredHeight,
 * capacitiveSensorHeight, strainGaugeHeight, height, head-height,
 * smoothedMeasuredHeight. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "readers.h"

#define JPK_MAX_COLS 64

static const char *const height_names[] = {
    "measuredHeight", "capacitiveSensorHeight", "strainGaugeHeight", "height",
    "head-height", "smoothedMeasuredHeight", "smoothedCapacitiveSensorHeight", NULL
};

typedef struct {
    const lf_read_opts *o;
    lf_warnings *warn;
    lf_curve *c;
    const char *name;
    size_t cap;
    /* the segment being read */
    char cols[512], units[512];
    char segname[64];
    int seg;                     /* lf_segment */
    int resolved;                /* columns looked up for this segment */
    size_t ncol;
    int jh, jd, jt;
    double fh, ft;               /* SI factors of height and time */
    int defl_kind;               /* 0 m, 1 N, 2 V */
    char hname[64], dunit[16];
    double k, sens;              /* from the current header, or NaN */
    int have_time;
    long nseg[3];
    char used_heights[256];
} jpk;

static int
jpk_sniff(const char *head, size_t len)
{
    char buf[8192];
    lf_sniff_text(head, len, buf, sizeof buf);
    if (strncmp(buf, "# TEXT EXPORT", 13) == 0)
        return 90;
    if (strstr(buf, "\n# columns: ") != NULL && strstr(buf, "\n# units: ") != NULL)
        return 80;
    return 0;
}

static int
segment_kind(const char *s)
{
    if (strstr(s, "pause") || strstr(s, "hold") || strstr(s, "dwell"))
        return LF_SEG_HOLD;
    if (strstr(s, "extend") || strstr(s, "approach") || strstr(s, "trace"))
        return LF_SEG_LOAD;
    if (strstr(s, "retract") || strstr(s, "withdraw"))
        return LF_SEG_UNLOAD;
    return -1;
}

static int
header_line(jpk *j, long line, char *text, lf_error *err)
{
    char *colon, *key, *value;
    size_t n;

    key = text + 1;
    key += strspn(key, " \t");
    n = strlen(key);
    while (n > 0 && (key[n - 1] == ' ' || key[n - 1] == '\t'))
        key[--n] = '\0';
    colon = strchr(key, ':');
    if (colon == NULL)
        return LF_OK;
    *colon = '\0';
    value = colon + 1 + strspn(colon + 1, " \t");
    if (strcmp(key, "segmentIndex") == 0 && strcmp(value, "0") == 0 && j->c->n > 0)
        return lf_fail_at(err, LF_EFORMAT, j->name, line, 0,
                          "a second curve begins here (segmentIndex 0 again): one curve per "
                          "file (export the curves of a force map one by one)");
    if (strcmp(key, "columns") == 0) {
        snprintf(j->cols, sizeof j->cols, "%s", value);
        j->resolved = 0;
    } else if (strcmp(key, "units") == 0) {
        snprintf(j->units, sizeof j->units, "%s", value);
        j->resolved = 0;
    } else if (strcmp(key, "segment") == 0) {
        int kind = segment_kind(value);
        snprintf(j->segname, sizeof j->segname, "%s", value);
        if (kind < 0) {
            lf_warn(j->warn, "%s:%ld: unknown segment '%s', kept as a hold (not fitted)",
                    j->name, line, j->segname);
            kind = LF_SEG_HOLD;
        }
        j->seg = kind;
        j->resolved = 0;
    } else if (strcmp(key, "springConstant") == 0) {
        double v;
        j->k = lf_csv_number(value, 0, &v) == LF_NUM_OK && v > 0 ? v : NAN;
    } else if (strcmp(key, "sensitivity") == 0) {
        double v;
        j->sens = lf_csv_number(value, 0, &v) == LF_NUM_OK && v > 0 ? v : NAN;
    } else if (key[0] != '\0' && lf_curve_add_meta(j->c, key, value) != 0) {
        return lf_fail_at(err, LF_ENOMEM, j->name, line, 0, "out of memory");
    }
    return LF_OK;
}

/* Find this segment's height, deflection and time columns, their units,
 * and the constants the conversion needs. */
static int
resolve(jpk *j, long line, lf_error *err)
{
    char cols[512], units[512], *cn[JPK_MAX_COLS + 1], *un[JPK_MAX_COLS + 1];
    size_t nc, nu, i, h;
    lf_error e;
    int hi = -1;

    if (j->cols[0] == '\0')
        return lf_fail_at(err, LF_EFORMAT, j->name, line, 1,
                          "data before any '# columns:' line (a JPK export names its "
                          "columns in the header of each segment)");
    strcpy(cols, j->cols);
    strcpy(units, j->units);
    nc = lf_split_cells(cols, ' ', cn, NULL, JPK_MAX_COLS + 1);
    nu = lf_split_cells(units, ' ', un, NULL, JPK_MAX_COLS + 1);
    if (nc > JPK_MAX_COLS || nu != nc)
        return lf_fail_at(err, LF_EFORMAT, j->name, line, 0,
                          "the segment's '# units:' line names %zu units for %zu columns",
                          nu, nc);
    j->ncol = nc;
    j->jh = j->jd = j->jt = -1;
    for (h = 0; height_names[h] != NULL && hi < 0; h++)
        for (i = 0; i < nc; i++)
            if (strcmp(cn[i], height_names[h]) == 0) {
                hi = (int) i;
                break;
            }
    j->jh = hi;
    for (i = 0; i < nc; i++) {
        if (strcmp(cn[i], "vDeflection") == 0)
            j->jd = (int) i;
        if (strcmp(cn[i], "seriesTime") == 0 || (j->jt < 0 && strcmp(cn[i], "time") == 0))
            j->jt = (int) i;
    }
    if (j->jh < 0 || j->jd < 0)
        return lf_fail_at(err, LF_EFORMAT, j->name, line, 0,
                          "segment '%s' has no %s column (expected vDeflection and one of "
                          "measuredHeight, capacitiveSensorHeight, height)", j->segname,
                          j->jh < 0 ? "height" : "vDeflection");
    snprintf(j->hname, sizeof j->hname, "%s", cn[j->jh]);
    if (strstr(j->used_heights, j->hname) == NULL) {
        size_t len = strlen(j->used_heights);
        snprintf(j->used_heights + len, sizeof j->used_heights - len, "%s%s",
                 len ? ", " : "", j->hname);
    }
    if (lf_units_factor(un[j->jh], LF_Q_LENGTH, &j->fh, &e) != LF_OK)
        return lf_fail_at(err, LF_EUNIT, j->name, line, 0, "%s: %s", cn[j->jh], e.msg);
    if (j->jt >= 0 && lf_units_factor(un[j->jt], LF_Q_TIME, &j->ft, &e) != LF_OK)
        j->jt = -1;
    snprintf(j->dunit, sizeof j->dunit, "%s", un[j->jd]);
    if (strcmp(un[j->jd], "N") == 0)
        j->defl_kind = 1;
    else if (strcmp(un[j->jd], "m") == 0)
        j->defl_kind = 0;
    else if (strcmp(un[j->jd], "V") == 0)
        j->defl_kind = 2;
    else
        return lf_fail_at(err, LF_EUNIT, j->name, line, 0,
                          "vDeflection in '%s' (expected N, m or V)", un[j->jd]);
    if (isnan(j->c->spring_constant)) {
        int st = lf_afm_spring_constant(j->c, j->k, "springConstant", j->o,
                                        "to convert the deflection", err);
        if (st != LF_OK)
            return st;
    }
    if (j->defl_kind == 2 && isnan(j->c->sensitivity)) {
        int st = lf_afm_sensitivity(j->c, j->sens, "sensitivity", 0, j->o, err);
        if (st != LF_OK)
            return st;
    }
    j->resolved = 1;
    return LF_OK;
}

static int
data_line(jpk *j, long line, char *text, lf_error *err)
{
    char *cells[JPK_MAX_COLS + 1], buf[64];
    long cols[JPK_MAX_COLS + 1];
    double h = 0, d = 0, force, t = 0, k;
    size_t n, i;
    int st;

    if (!j->resolved && (st = resolve(j, line, err)) != LF_OK)
        return st;
    n = lf_split_cells(text, ' ', cells, cols, JPK_MAX_COLS + 1);
    if (n != j->ncol) {
        if (j->o->skip_bad_rows && n < j->ncol)
            return LF_OK;
        return lf_fail_at(err, LF_EFORMAT, j->name, line, 1,
                          "row has %zu values, the segment's '# columns:' line names %zu",
                          n, j->ncol);
    }
    for (i = 0; i < n; i++) {
        double v;
        if ((int) i != j->jh && (int) i != j->jd && (int) i != j->jt)
            continue;
        if (lf_csv_number(cells[i], 0, &v) != LF_NUM_OK)
            return lf_fail_at(err, LF_EFORMAT, j->name, line, cols[i],
                              "'%s' is not a number (expected e.g. 5.5659595E-5)",
                              lf_csv_excerpt(cells[i], buf, sizeof buf));
        if ((int) i == j->jh)
            h = v * j->fh;
        else if ((int) i == j->jd)
            d = v;
        else
            t = v * j->ft;
    }
    k = j->c->spring_constant;
    if (j->defl_kind == 1) {          /* a force */
        force = d;
        d /= k;
    } else {
        if (j->defl_kind == 2)
            d *= j->c->sensitivity;
        force = k * d;
    }
    if (j->c->n == j->cap) {
        size_t cap = j->cap ? 2 * j->cap : 1024;
        if (lf_curve_reserve(j->c, cap, 1) != 0)
            return lf_fail_at(err, LF_ENOMEM, j->name, line, 0, "out of memory");
        j->cap = cap;
    }
    i = j->c->n++;
    j->c->depth[i] = -(h + d);
    j->c->force[i] = force;
    j->c->time[i] = j->jt >= 0 ? t : NAN;
    j->c->segment[i] = (unsigned char) j->seg;
    j->c->line[i] = line;
    j->nseg[j->seg]++;
    return LF_OK;
}

static int
on_line(void *ctx, long line, char *text, size_t len, lf_error *err)
{
    jpk *j = ctx;
    size_t b = strspn(text, " \t");
    if (b == len)
        return LF_OK;
    if (text[b] == '#')
        return header_line(j, line, text + b, err);
    return data_line(j, line, text + b, err);
}

static int
jpk_read(const lf_source *in, const lf_read_opts *o, lf_curve *c, lf_warnings *warn,
         lf_error *err)
{
    lf_csv_handler h = { 0 };   /* callbacks not set stay NULL */
    jpk j;
    int status;
    size_t i;

    memset(&j, 0, sizeof j);
    j.o = o;
    j.warn = warn;
    j.c = c;
    j.name = in->name;
    j.seg = LF_SEG_LOAD;
    j.k = j.sens = NAN;
    strcpy(j.segname, "(unnamed)");
    h.ctx = &j;
    h.record = NULL;
    h.comment = NULL;
    h.line = on_line;
    status = lf_csv_read_input(in, &h, err);
    if (status != LF_OK)
        return status;
    if (c->n > 0) {
        int any_time = 0;
        for (i = 0; i < c->n; i++)
            any_time |= !isnan(c->time[i]);
        if (!any_time) {
            free(c->time);
            c->time = NULL;
        }
    }
    lf_warn(&c->info, "force: vDeflection (%s)%s", j.dunit,
            strcmp(j.dunit, "N") == 0 ? "" : " x sensitivity x k");
    lf_warn(&c->info, "depth: tip-sample separation = -(%s + vDeflection / k) (into the "
            "sample positive)", j.used_heights);
    lf_warn(&c->info, "segments: from the file's '# segment:' headers (extend %ld, "
            "pause/hold %ld, retract %ld points)", j.nseg[LF_SEG_LOAD], j.nseg[LF_SEG_HOLD],
            j.nseg[LF_SEG_UNLOAD]);
    return lf_curve_finish(c, warn, err);
}

const lf_reader_type lf_reader_jpk = {
    "jpk", "JPK force-save text export ('# columns:' / '# units:' headers, segments "
    "extend, pause, retract)",
    jpk_sniff, jpk_read
};
