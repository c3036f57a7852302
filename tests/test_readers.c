/* test_readers.c: the instrument readers (src/reader.c, src/read_*.c).
 *
 * datasets/vendors/ holds one small synthetic file per vendor layout (made
 * by datasets/vendors/make_vendors.py from a known half-space JKR curve):
 * each is sniffed to its format, parsed with every chunk size from 1 to its
 * length with the same result, spot-checked against its raw bytes, and,
 * where the conversion is exact, fitted back to the truth it was made from.
 * ../shared/realdata holds real exports: each is read as exported, its
 * format, columns, segments and metadata asserted, its first and last point
 * checked against the raw line converted here by hand, and the two PEG
 * hydrogel curves are fitted with the half-space JKR model. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "layerfit.h"
#include "testlib.h"
#include "testdata.h"

static char vendors[1200], real[1200];

static int
same_curve(const lf_curve *a, const lf_curve *b)
{
    size_t i;
    if (a->n != b->n || a->nmeta != b->nmeta || a->info.n != b->info.n
        || strcmp(a->format, b->format) != 0
        || memcmp(&a->R, &b->R, sizeof a->R) != 0
        || memcmp(&a->spring_constant, &b->spring_constant, sizeof a->R) != 0
        || memcmp(&a->sensitivity, &b->sensitivity, sizeof a->R) != 0
        || (a->time == NULL) != (b->time == NULL))
        return 0;
    for (i = 0; i < a->nmeta; i++)
        if (strcmp(a->meta[i].key, b->meta[i].key) || strcmp(a->meta[i].value, b->meta[i].value))
            return 0;
    for (i = 0; i < a->info.n; i++)
        if (strcmp(a->info.msg[i], b->info.msg[i]) != 0)
            return 0;
    return memcmp(a->depth, b->depth, a->n * sizeof *a->depth) == 0
        && memcmp(a->force, b->force, a->n * sizeof *a->force) == 0
        && (a->time == NULL || memcmp(a->time, b->time, a->n * sizeof *a->time) == 0)
        && memcmp(a->segment, b->segment, a->n) == 0
        && memcmp(a->line, b->line, a->n * sizeof *a->line) == 0;
}

typedef struct {
    const char *path;
    const lf_read_opts *o;
    int status;
    const lf_curve *ref;
    const lf_error *err;
} reference;

static int
differs(void *ctx, const char *buf, size_t len, size_t chunk)
{
    const reference *r = ctx;
    lf_curve *c = NULL;
    lf_error e;
    int status = lf_curve_parse(buf, len, chunk, r->path, r->o, &c, NULL, &e);
    int bad = status != r->status
        || (status == LF_OK ? !same_curve(r->ref, c) : !same_error(r->err, &e));
    lf_curve_free(c);
    return bad;
}

/* Read path from its file, then from memory in chunks: every size from 1
 * to the length (all_sizes), or 1..13 and a few large ones. */
static lf_curve *
read_all_ways(const char *path, const lf_read_opts *o, int all_sizes, lf_warnings *warn,
              lf_error *err)
{
    lf_curve *ref = NULL;
    reference r;
    size_t len = 0;
    long bad = 0;

    r.path = path;
    r.o = o;
    r.status = lf_curve_read(path, o, &ref, warn, err);
    r.ref = ref;
    r.err = err;
    if (all_sizes) {
        bad = every_chunk(path, &len, differs, &r);
        t_int(bad, 0, "%s: the same %s with each of %zu chunk sizes", path,
              r.status == LF_OK ? "curve" : "error", len + 1);
    } else {
        static const size_t sizes[] = { 1, 2, 3, 5, 7, 11, 13, 4093, 65536, 0 };
        char *buf = slurp(path, &len);
        size_t i;
        if (t_true(buf != NULL, "%s readable", path))
            for (i = 0; i < sizeof sizes / sizeof sizes[0]; i++)
                bad += differs(&r, buf, len, sizes[i]) != 0;
        free(buf);
        t_int(bad, 0, "%s: the same %s with chunk sizes 0-13, 4093, 65536", path,
              r.status == LF_OK ? "curve" : "error");
    }
    return ref;
}

/* Line number lineno (1-based, counted as the readers count: CRLF, LF or
 * CR each end a line) of the file, into buf. */
static int
raw_line(const char *path, long lineno, char *buf, size_t n)
{
    size_t len = 0, i, w = 0;
    long line = 1;
    char *text = slurp(path, &len);
    int found = 0;
    if (text == NULL)
        return 0;
    for (i = 0; i < len && line <= lineno; i++) {
        char ch = text[i];
        if (ch == '\r' || ch == '\n') {
            if (ch == '\r' && i + 1 < len && text[i + 1] == '\n')
                i++;
            if (line == lineno)
                found = 1;
            line++;
            continue;
        }
        if (line == lineno && w + 1 < n)
            buf[w++] = ch;
    }
    if (line == lineno && w > 0)
        found = 1;          /* the last line, without an end */
    buf[w] = '\0';
    free(text);
    return found;
}

/* The numbers of a raw line, any of tab, space, comma as separators when
 * comma_decimal is 0; with comma_decimal, ',' is the decimal point. */
static size_t
numbers(char *line, int comma_decimal, double *v, size_t max)
{
    size_t n = 0;
    char *p = line, *end;
    if (comma_decimal)
        for (end = line; *end; end++)
            if (*end == ',')
                *end = '.';
    while (*p && n < max) {
        while (*p == ' ' || *p == '\t' || (!comma_decimal && *p == ','))
            p++;
        if (!*p)
            break;
        v[n] = strtod(p, &end);
        if (end == p)
            break;
        n++;
        p = end;
    }
    return n;
}

static size_t
count_seg(const lf_curve *c, lf_segment s)
{
    return lf_curve_segment(c, s, NULL, NULL);
}

static int
has_warning(const lf_warnings *w, const char *text)
{
    size_t i;
    for (i = 0; i < w->n; i++)
        if (strstr(w->msg[i], text) != NULL)
            return 1;
    return 0;
}

/* ---- synthetic files -------------------------------------------------- */

typedef struct {
    const char *file, *format;
    const char *k, *sens;      /* options, or NULL */
    int exact;                 /* the conversion is exact: fit back to the truth */
    long load, hold, unload;
} vendor_case;

static void
check_spot(const lf_curve *c, const char *path, size_t i, const char *how)
{
    char line[512];
    double v[8], depth = NAN, force = NAN;
    size_t n;
    if (!t_true(raw_line(path, c->line[i], line, sizeof line), "%s: line %ld read back",
                path, c->line[i]))
        return;
    if (strcmp(how, "chiaro") == 0) {
        n = numbers(line, 0, v, 8);
        if (n >= 5) {
            depth = (v[4] - v[3]) * 1e-9;       /* Piezo - Cantilever, nm */
            force = v[1] * 1e-6;                /* Load, uN */
        }
    } else if (strcmp(how, "hysitron") == 0 || strcmp(how, "text_space_comma") == 0) {
        int comma = strcmp(how, "text_space_comma") == 0;
        n = numbers(line, comma, v, 8);
        if (n >= 3) {
            depth = (comma ? v[1] : v[0]) * 1e-9;
            force = comma ? v[2] * 1e-9 : v[1] * 1e-6;
        }
    }
    if (isnan(depth))
        return;
    t_rel(c->depth[i], depth, 1e-12, "%s: point %zu depth from line %ld by hand", path, i,
          c->line[i]);
    t_rel(c->force[i], force, 1e-12, "%s: point %zu force from line %ld by hand", path, i,
          c->line[i]);
}

static void
test_vendor(const vendor_case *vc)
{
    char path[1400];
    lf_read_opts o;
    lf_warnings w = { 0, NULL };
    lf_error err;
    lf_curve *c, *forced = NULL;
    const lf_reader_type *sniffed;
    char *buf, how[64];
    size_t len = 0;

    snprintf(path, sizeof path, "%s/%s", vendors, vc->file);
    lf_read_opts_default(&o);
    if (lf_read_opts_constants(&o, vc->k, vc->sens, &err) != LF_OK)
        t_true(0, "%s: options (%s)", vc->file, err.msg);
    buf = slurp(path, &len);
    if (!t_true(buf != NULL, "%s readable", path))
        return;
    sniffed = lf_reader_sniff(buf, len);
    t_str(sniffed->name, vc->format, "%s: sniffed as %s", vc->file, vc->format);
    free(buf);
    c = read_all_ways(path, &o, 1, &w, &err);
    if (!t_true(c != NULL, "%s reads (%s)", vc->file, err.msg))
        return;
    t_str(c->format, vc->format, "%s: format", vc->file);
    t_int((long) count_seg(c, LF_SEG_LOAD), vc->load, "%s: loading points", vc->file);
    t_int((long) count_seg(c, LF_SEG_HOLD), vc->hold, "%s: hold points", vc->file);
    t_int((long) count_seg(c, LF_SEG_UNLOAD), vc->unload, "%s: unloading points", vc->file);
    snprintf(how, sizeof how, "%s", vc->file);
    *strchr(how, '.') = '\0';
    check_spot(c, path, 0, how);
    check_spot(c, path, c->n - 1, how);
    o.format = vc->format;
    if (lf_curve_read(path, &o, &forced, NULL, &err) == LF_OK)
        t_true(same_curve(c, forced), "%s: --format %s gives the sniffed curve", vc->file,
               vc->format);
    else
        t_true(0, "%s: --format %s reads (%s)", vc->file, vc->format, err.msg);
    lf_curve_free(forced);
    if (vc->exact) {
        lf_fit_result res;
        int st = fit_halfspace(c, 8e-6, &res);
        if (t_true(st == LF_OK, "%s: fit converges", vc->file)) {
            t_rel(res.w.value, 1e-3, 1e-4, "%s: w back to the truth 1 mJ/m^2", vc->file);
            t_rel(res.Estar.value, 25e3, 1e-4, "%s: E* back to the truth 25 kPa", vc->file);
        }
        if (st == LF_OK || st == LF_ENOCONV)
            lf_fit_result_free(&res);
    }
    lf_curve_free(c);
    lf_warnings_free(&w);
}

static void
test_vendors(void)
{
    static const vendor_case cases[] = {
        { "chiaro.txt", "chiaro", NULL, NULL, 1, 39, 14, 39 },
        { "jpk_force.txt", "jpk", NULL, NULL, 1, 40, 12, 40 },
        { "jpk_volts.txt", "jpk", NULL, NULL, 1, 40, 12, 40 },
        { "workshop_tb.csv", "workshop", NULL, NULL, 1, 40, 0, 40 },
        { "workshop_force.csv", "workshop", "0.032N/m", NULL, 1, 40, 0, 40 },
        { "ntmdt.txt", "ntmdt", "1N/m", "61nm/nA", 0, 38, 0, 38 },
        { "hysitron.txt", "hysitron", NULL, NULL, 0, 29, 14, 29 },
        { "text_space_comma.txt", "text", NULL, NULL, 1, 39, 0, 41 },
    };
    size_t i;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++)
        test_vendor(&cases[i]);
}

/* What the synthetic files' conversions must give, checked by hand. */
static void
test_vendor_details(void)
{
    char path[1400], line[512];
    lf_read_opts o;
    lf_error err;
    lf_curve *c = NULL;
    double v[8];
    size_t n;

    /* JPK in volts: F = k x sensitivity x V, separation -(height + F/k) */
    snprintf(path, sizeof path, "%s/jpk_volts.txt", vendors);
    if (t_int(lf_curve_read(path, NULL, &c, NULL, &err), LF_OK, "jpk volts reads")) {
        t_rel(c->spring_constant, 0.032, 1e-15, "jpk: k from the header");
        t_rel(c->sensitivity, 5e-8, 1e-15, "jpk: sensitivity from the header");
        t_str(c->spring_constant_source ? c->spring_constant_source : "(null)", "file header",
              "jpk: the spring constant's source");
        t_str(c->sensitivity_source ? c->sensitivity_source : "(null)", "file header",
              "jpk: the sensitivity's source");
        t_str(c->sensitivity_unit ? c->sensitivity_unit : "(null)", "m/V", "jpk: per volt");
        if (raw_line(path, c->line[c->n - 1], line, sizeof line)
            && (n = numbers(line, 0, v, 8)) == 5) {
            double d = v[2] * 5e-8;       /* columns: height measuredHeight vDeflection ... */
            t_rel(c->force[c->n - 1], 0.032 * d, 1e-12, "jpk volts: last force by hand");
            t_rel(c->depth[c->n - 1], -(v[1] + d), 1e-12, "jpk volts: last depth by hand");
        } else {
            t_true(0, "jpk volts: last line has 5 numbers");
        }
        t_true(c->time != NULL && c->time[0] > 0, "jpk: seriesTime kept");
    }
    lf_curve_free(c);
    c = NULL;

    /* AFM Workshop T-B: sensitivity 1e-6 / gain(mV/nm), F = k d, depth Z - d */
    snprintf(path, sizeof path, "%s/workshop_tb.csv", vendors);
    if (t_int(lf_curve_read(path, NULL, &c, NULL, &err), LF_OK, "workshop T-B reads")) {
        t_rel(c->sensitivity, 1e-6 / 2.5, 1e-12, "workshop: sensitivity from the gain");
        t_rel(c->spring_constant, 0.032, 1e-12, "workshop: k from 'Force Constant, nN/nm'");
        if (raw_line(path, c->line[c->n - 1], line, sizeof line)
            && numbers(line, 0, v, 8) == 4) {
            double d = v[3] * 1e-6 / 2.5;
            t_rel(c->force[c->n - 1], 0.032 * d, 1e-12, "workshop: last retract force by hand");
            t_rel(c->depth[c->n - 1], v[2] * 1e-9 - d, 1e-12,
                  "workshop: last retract depth by hand");
        }
        t_int(c->line[0], c->line[c->n / 2], "workshop: extend and retract side by side");
    }
    lf_curve_free(c);
    c = NULL;

    /* NT-MDT: no constants in the file */
    snprintf(path, sizeof path, "%s/ntmdt.txt", vendors);
    t_int(lf_curve_read(path, NULL, &c, NULL, &err), LF_EDATA, "ntmdt without k: refused");
    t_contains(err.msg, "--spring-constant 0.032N/m", "ntmdt: the message names the option");
    lf_read_opts_default(&o);
    lf_read_opts_constants(&o, "1N/m", NULL, &err);
    t_int(lf_curve_read(path, &o, &c, NULL, &err), LF_EDATA, "ntmdt without sensitivity");
    t_contains(err.msg, "--sensitivity 61nm/nA", "ntmdt: names --sensitivity");
    lf_read_opts_constants(&o, NULL, "50nm/V", &err);
    t_int(lf_curve_read(path, &o, &c, NULL, &err), LF_EUNIT, "ntmdt: a sensitivity per volt");
    t_contains(err.msg, "per volt", "ntmdt: says the sensitivity is of the wrong kind");
    lf_read_opts_constants(&o, NULL, "61nm/nA", &err);
    if (t_int(lf_curve_read(path, &o, &c, NULL, &err), LF_OK, "ntmdt with both reads")) {
        t_str(c->spring_constant_source ? c->spring_constant_source : "(null)", "option",
              "ntmdt: the spring constant from the option, said");
        t_str(c->sensitivity_source ? c->sensitivity_source : "(null)", "option",
              "ntmdt: the sensitivity from the option, said");
        t_str(c->sensitivity_unit ? c->sensitivity_unit : "(null)", "m/A", "ntmdt: per ampere");
        /* approach: the last row first; retract: the last row last */
        if (raw_line(path, c->line[0], line, sizeof line) && numbers(line, 1, v, 8) == 3) {
            double d = v[1] * 1e-9 * 61.0;
            t_rel(c->depth[0], -(v[0] * 1e-9 + d), 1e-12, "ntmdt: first approach depth");
            t_rel(c->force[0], 1.0 * d, 1e-12, "ntmdt: first approach force");
        }
        t_int(c->line[0], c->line[c->n - 1], "ntmdt: approach starts, retract ends, at the "
              "last row");
        t_true(has_info(c, "dropped padded rows"), "ntmdt: padding dropped and said");
    }
    lf_curve_free(c);
    c = NULL;

    /* an unknown --format */
    lf_read_opts_default(&o);
    o.format = "bruker-nanoscope";
    t_int(lf_curve_read(path, &o, &c, NULL, &err), LF_EINVAL, "unknown format refused");
    t_contains(err.msg, "unknown format 'bruker-nanoscope' (one of: csv, chiaro", "names them");
    t_true(lf_reader_find("jpk") != NULL && lf_reader_find("JPK") != NULL,
           "reader lookup by name, any case");

    /* bad options */
    t_int(lf_read_opts_constants(&o, "0.032", NULL, &err), LF_EUNIT, "k without a unit");
    t_contains(err.msg, "--spring-constant", "k message names the option");
    t_int(lf_read_opts_constants(&o, NULL, "61nm", &err), LF_EUNIT, "sensitivity as a length");
}

/* A text held in memory, parsed at every chunk size the same way. */
static lf_curve *
parse_all_ways(const char *text, const lf_read_opts *o, lf_error *err)
{
    lf_curve *c = NULL;
    reference r;
    size_t len = strlen(text), chunk;
    long bad = 0;
    r.path = "mem.txt";
    r.o = o;
    r.status = lf_curve_parse(text, len, 0, "mem.txt", o, &c, NULL, err);
    r.ref = c;
    r.err = err;
    for (chunk = 1; chunk <= len; chunk++)
        bad += differs(&r, text, len, chunk) != 0;
    t_int(bad, 0, "the same result with each of %zu chunk sizes", len);
    return c;
}

/* The generic text reader and the sniffing that sends text to it. */
static void
test_generic_text(void)
{
    static const char tab_comma[] =
        "Instrument X export\r\nDate: 2024-02-01\r\n\r\n"
        "Depth (nm)\tForce (nN)\tTime (s)\r\n"
        "0\t0,5\t0\r\n10,5\t2,25\t0,1\r\n20\t7\t0,2\r\n15\t4\t0,3\r\n5\t-1,5\t0,4\r\n";
    static const char semi[] =
        "operator = nobody\nindentation [um];load [mN]\n0,1;0,2\n0,3;0,4\n0,2;0,1\n";
    static const char plain[] = "depth_nm,force_uN\n1,2\n3,4\n2,1\n";
    static const char numbers_first[] = "1\t2\n3\t4\n";
    lf_read_opts o;
    lf_error err;
    lf_curve *c;

    t_str(lf_reader_sniff(tab_comma, strlen(tab_comma))->name, "text", "sniff: header on line 4");
    t_str(lf_reader_sniff(semi, strlen(semi))->name, "text", "sniff: header on line 2");
    t_str(lf_reader_sniff(plain, strlen(plain))->name, "csv", "sniff: plain CSV stays csv");
    c = parse_all_ways(tab_comma, NULL, &err);
    if (t_true(c != NULL, "tab, decimal comma reads (%s)", err.msg)) {
        t_str(c->format, "text", "tab comma: format");
        t_int((long) c->n, 5, "tab comma: points");
        t_rel(c->depth[1], 10.5e-9, 1e-15, "tab comma: 10,5 nm");
        t_rel(c->force[4], -1.5e-9, 1e-15, "tab comma: -1,5 nN");
        t_rel(c->time[3], 0.3, 1e-15, "tab comma: time");
        t_int(c->line[0], 5, "tab comma: first point's line");
        t_str(meta(c, "Date"), "2024-02-01", "tab comma: 'Key: value' metadata");
        t_true(has_info(c, "header on line 4, delimiter tab, decimal comma"), "tab comma: info");
        t_int((long) count_seg(c, LF_SEG_LOAD), 2, "tab comma: load before the deepest");
    }
    lf_curve_free(c);
    c = parse_all_ways(semi, NULL, &err);
    if (t_true(c != NULL, "semicolon, decimal comma reads (%s)", err.msg)) {
        t_rel(c->depth[1], 0.3e-6, 1e-15, "semicolon: um");
        t_rel(c->force[0], 0.2e-3, 1e-15, "semicolon: mN");
        t_str(meta(c, "operator"), "nobody", "semicolon: 'Key = value' metadata");
    }
    lf_curve_free(c);
    lf_read_opts_default(&o);
    o.format = "text";
    c = parse_all_ways(numbers_first, &o, &err);
    t_true(c == NULL, "text: numbers before a header refused");
    t_contains(err.msg, "a row of numbers before any row naming the columns", "text: message");
    t_int(err.line, 1, "text: message line");
    lf_curve_free(c);
}

/* Plans: a format column, and R taken from the curve's header. */
static void
test_plan_columns(void)
{
    static const char good[] = "file,k,R,b,interface,format\n"
                               "chiaro.txt,2,header,8um,frictionless,\n"
                               "jpk_volts.txt,2,8um,8um,frictionless,JPK\n";
    static const char bad[] = "file,k,R,b,interface,format\nchiaro.txt,2,1um,8um,frictionless,x\n";
    lf_plan *p = NULL;
    lf_error err;
    if (t_int(lf_plan_parse(good, strlen(good), 0, "p.csv", vendors, &p, NULL, &err), LF_OK,
              "plan with format and R header parses (%s)", err.msg)) {
        t_true(isnan(p->rows[0].probe.R), "plan: R 'header' is NaN in the row");
        t_str(p->rows[0].format, "", "plan: empty format = sniffed");
        t_str(p->rows[1].format, "JPK", "plan: format kept");
        t_rel(p->rows[1].probe.R, 8e-6, 1e-15, "plan: R given");
    }
    lf_plan_free(p);
    p = NULL;
    t_int(lf_plan_parse(bad, strlen(bad), 0, "p.csv", vendors, &p, NULL, &err), LF_EFORMAT,
          "plan: unknown format refused");
    t_int(err.column, 35, "plan: the message points at the format cell");
    lf_plan_free(p);
}

/* ---- the real exports ------------------------------------------------- */

static int
real_present(void)
{
    struct stat st;
    return stat(real, &st) == 0 && S_ISDIR(st.st_mode);
}

static lf_curve *
read_real(const char *name, const lf_read_opts *o, lf_warnings *w, char *path, size_t n)
{
    lf_error err;
    lf_curve *c;
    snprintf(path, n, "%s/%s", real, name);
    c = read_all_ways(path, o, 0, w, &err);
    t_true(c != NULL, "%s reads as exported (%s)", name, c ? "" : err.msg);
    return c;
}

static void
test_real_chiaro(void)
{
    static const struct {
        const char *file;
        double R, k, Eeff;
        long hold_min;
    } cases[] = {
        { "fmt-chiaro-txt_AEBP1_Indentation_002.txt", 27.5e-6, 0.019, 156.009, 0 },
        { "10 wv pc PEGFN S-1 X-1 Y-1 I-1.txt", 8e-6, 0.032, 26567.836, 900 },
        { "10 wv pc PEGFN S-1 X-1 Y-2 I-1.txt", 8e-6, 0.032, 26482.110, 900 },
    };
    size_t i;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char path[1400], line[512];
        lf_warnings w = { 0, NULL };
        lf_curve *c = read_real(cases[i].file, NULL, &w, path, sizeof path);
        const char *e;
        double v[8];
        if (c == NULL)
            continue;
        t_str(c->format, "chiaro", "%s: format", cases[i].file);
        t_rel(c->R, cases[i].R, 1e-12, "%s: R from 'Tip radius (um)'", cases[i].file);
        t_rel(c->spring_constant, cases[i].k, 1e-12, "%s: k from 'k (N/m)'", cases[i].file);
        e = meta(c, "E[eff] (Pa)");
        t_true(e != NULL && fabs(atof(e) - cases[i].Eeff) < 1e-3, "%s: E[eff] kept as metadata",
               cases[i].file);
        t_true(meta(c, "Max load (µN)") != NULL || i > 0, "%s: Latin-1 µ key in UTF-8",
               cases[i].file);
        t_true(has_info(c, "'Piezo (nm)' - 'Cantilever (nm)'"), "%s: separation used",
               cases[i].file);
        t_true(has_warning(&w, "column 'Indentation (nm)' is clamped"), "%s: clamp warned",
               cases[i].file);
        t_true(c->time != NULL, "%s: time kept", cases[i].file);
        if (cases[i].hold_min > 0) {
            t_true((long) count_seg(c, LF_SEG_HOLD) >= cases[i].hold_min,
                   "%s: the 1 s hold at 10 um is found (%zu points)", cases[i].file,
                   count_seg(c, LF_SEG_HOLD));
            /* the header's sweep holds D[Z3] for t[3] = 1 s */
            {
                size_t j, first = c->n, last = 0;
                for (j = 0; j < c->n; j++)
                    if (c->segment[j] == LF_SEG_HOLD) {
                        first = j < first ? j : first;
                        last = j;
                    }
                t_true(first < c->n && fabs(c->time[last] - c->time[first] - 1.0) < 0.05,
                       "%s: hold from %.3f s to %.3f s, 1 s as the header's t[3]",
                       cases[i].file, first < c->n ? c->time[first] : -1.0, c->time[last]);
            }
        } else {
            t_int((long) count_seg(c, LF_SEG_HOLD), 0, "%s: no hold", cases[i].file);
        }
        if (raw_line(path, c->line[0], line, sizeof line) && numbers(line, 0, v, 8) == 6) {
            t_rel(c->depth[0], (v[4] - v[3]) * 1e-9, 1e-12, "%s: first depth by hand",
                  cases[i].file);
            t_rel(c->force[0], v[1] * 1e-6, 1e-12, "%s: first force by hand", cases[i].file);
        } else {
            t_true(0, "%s: first data line has 6 numbers", cases[i].file);
        }
        if (raw_line(path, c->line[c->n - 1], line, sizeof line) && numbers(line, 0, v, 8) == 6) {
            t_rel(c->depth[c->n - 1], (v[4] - v[3]) * 1e-9, 1e-12, "%s: last depth by hand",
                  cases[i].file);
            t_rel(c->time[c->n - 1], v[0], 1e-12, "%s: last time by hand", cases[i].file);
        }
        lf_curve_free(c);
        lf_warnings_free(&w);
    }
}

static void
test_real_others(void)
{
    char path[1400], line[1024];
    lf_warnings w = { 0, NULL };
    lf_read_opts o;
    lf_error err;
    lf_curve *c;
    double v[12];

    /* JPK: three segments of 3000 points, vDeflection in N */
    c = read_real("force-save-2021.06.30-13.48.08.425.txt", NULL, &w, path, sizeof path);
    if (c != NULL) {
        t_str(c->format, "jpk", "jpk: format");
        t_int((long) count_seg(c, LF_SEG_LOAD), 3000, "jpk: extend 3000");
        t_int((long) count_seg(c, LF_SEG_HOLD), 3000, "jpk: pause 3000, a hold");
        t_int((long) count_seg(c, LF_SEG_UNLOAD), 3000, "jpk: retract 3000");
        t_rel(c->spring_constant, 0.061, 1e-12, "jpk: springConstant from the header");
        t_true(has_info(c, "measuredHeight"), "jpk: measuredHeight used");
        t_str(meta(c, "data-description.instrument"), "JPK01466-CellHesion-200",
              "jpk: metadata kept");
        if (raw_line(path, c->line[0], line, sizeof line) && numbers(line, 0, v, 12) == 9) {
            t_rel(c->force[0], v[1], 1e-12, "jpk: first force = vDeflection (N)");
            t_rel(c->depth[0], -(v[6] + v[1] / 0.061000000000000006), 1e-12,
                  "jpk: first depth = -(measuredHeight + F/k)");
            t_rel(c->time[0], v[7], 1e-12, "jpk: seriesTime");
        } else {
            t_true(0, "jpk: first data line has 9 numbers");
        }
        if (raw_line(path, c->line[c->n - 1], line, sizeof line) && numbers(line, 0, v, 12) == 9)
            t_rel(c->depth[c->n - 1], -(v[6] + v[1] / 0.061000000000000006), 1e-12,
                  "jpk: last depth by hand");
        {   /* the pull-off: about -11 nN on retract */
            size_t j;
            double fmin = 0;
            for (j = 0; j < c->n; j++)
                if (c->segment[j] == LF_SEG_UNLOAD && c->force[j] < fmin)
                    fmin = c->force[j];
            t_true(fmin < -9e-9 && fmin > -13e-9, "jpk: retract minimum %g N near -11 nN", fmin);
        }
        lf_curve_free(c);
    }
    lf_warnings_free(&w);

    /* Hysitron: raw voltages ignored, a load-controlled hold */
    c = read_real("RobinSteel0000LC.txt", NULL, &w, path, sizeof path);
    if (c != NULL) {
        t_str(c->format, "hysitron", "hysitron: format");
        t_int((long) c->n, 5304, "hysitron: 'Number of Points = 5304'");
        t_str(meta(c, "Number of Points"), "5304", "hysitron: metadata");
        t_true(has_info(c, "ignored: column 4 'Depth (V)'"), "hysitron: voltages ignored");
        t_true(has_info(c, "'Load (µN)'"), "hysitron: Latin-1 µ in the column name");
        t_true(count_seg(c, LF_SEG_HOLD) > 700, "hysitron: the hold at 3000 uN (%zu points)",
               count_seg(c, LF_SEG_HOLD));
        if (raw_line(path, c->line[0], line, sizeof line) && numbers(line, 0, v, 12) == 5) {
            t_rel(c->depth[0], v[0] * 1e-9, 1e-12, "hysitron: first depth by hand");
            t_rel(c->force[0], v[1] * 1e-6, 1e-12, "hysitron: first load by hand");
        }
        if (raw_line(path, c->line[c->n - 1], line, sizeof line) && numbers(line, 0, v, 12) == 5)
            t_rel(c->time[c->n - 1], v[2], 1e-12, "hysitron: last time by hand");
        lf_curve_free(c);
    }
    lf_warnings_free(&w);

    /* NT-MDT: constants from the options (afmformats' test values) */
    lf_read_opts_default(&o);
    c = NULL;
    snprintf(path, sizeof path, "%s/%s", real,
             "fmt-ntmdt-txt-fd_2015_01_17_gel4-0,1_mQ_adh_6B_Curve_DFL_Height_51.txt");
    t_int(lf_curve_read(path, &o, &c, NULL, &err), LF_EDATA, "ntmdt: no k, refused");
    t_contains(err.msg, "--spring-constant", "ntmdt: names the option");
    lf_read_opts_constants(&o, "0.055N/m", "61nm/nA", &err);
    c = read_real("fmt-ntmdt-txt-fd_2015_01_17_gel4-0,1_mQ_adh_6B_Curve_DFL_Height_51.txt",
                  &o, &w, path, sizeof path);
    if (c != NULL) {
        t_str(c->format, "ntmdt", "ntmdt: format");
        t_int((long) (count_seg(c, LF_SEG_LOAD) + count_seg(c, LF_SEG_UNLOAD)), (long) c->n,
              "ntmdt: approach and retract");
        t_true(count_seg(c, LF_SEG_LOAD) < 1000 && count_seg(c, LF_SEG_LOAD) > 500,
               "ntmdt: padding dropped (%zu approach points of 1000 rows)",
               count_seg(c, LF_SEG_LOAD));
        if (raw_line(path, c->line[c->n - 1], line, sizeof line) && numbers(line, 1, v, 12) == 3) {
            double d = v[2] * 1e-9 * 61.0;
            t_rel(c->depth[c->n - 1], -(v[0] * 1e-9 + d), 1e-12, "ntmdt: last depth by hand");
            t_rel(c->force[c->n - 1], 0.055 * d, 1e-12, "ntmdt: last force by hand");
        }
        lf_curve_free(c);
    }
    lf_warnings_free(&w);

    /* AFM Workshop: three files, T-B or Force; no usable constants */
    {
        static const char *const ws[] = {
            "fmt-afm-workshop-fd_single_2018-08-01_13.06.09.csv",
            "fmt-afm-workshop-fd_single_2020-02-14_13.41.25.csv",
            "fmt-afm-workshop-fd_single_2021-01-15.csv",
        };
        static const long rows[] = { 570, 1015, 3369 };
        size_t i;
        for (i = 0; i < 3; i++) {
            int force = i == 1;
            lf_read_opts_default(&o);
            snprintf(path, sizeof path, "%s/%s", real, ws[i]);
            c = NULL;
            t_int(lf_curve_read(path, &o, &c, NULL, &err), LF_EDATA, "%s: no k, refused", ws[i]);
            t_contains(err.msg, "--spring-constant", "%s: names the option", ws[i]);
            lf_read_opts_constants(&o, "0.1N/m", force ? NULL : "50nm/V", &err);
            c = read_real(ws[i], &o, &w, path, sizeof path);
            if (c == NULL)
                continue;
            t_str(c->format, "workshop", "%s: format", ws[i]);
            t_int((long) count_seg(c, LF_SEG_LOAD), rows[i], "%s: extend rows", ws[i]);
            t_int((long) count_seg(c, LF_SEG_UNLOAD), rows[i], "%s: retract rows", ws[i]);
            if (i == 2)
                t_true(has_info(c, "'Force Constant, nN/nm' = 1 is the software's unset default"),
                       "%s: default constants ignored, said", ws[i]);
            if (raw_line(path, c->line[0], line, sizeof line) && numbers(line, 0, v, 12) == 4) {
                double d = force ? v[1] * 1e-9 / 0.1 : v[1] * 50e-9;
                t_rel(c->depth[0], v[0] * 1e-9 - d, 1e-12, "%s: first depth by hand", ws[i]);
                t_rel(c->force[0], force ? v[1] * 1e-9 : 0.1 * d, 1e-12,
                      "%s: first force by hand", ws[i]);
            } else {
                t_true(0, "%s: first data row has 4 numbers", ws[i]);
            }
            if (raw_line(path, c->line[c->n - 1], line, sizeof line)
                && numbers(line, 0, v, 12) == 4) {
                double d = force ? v[3] * 1e-9 / 0.1 : v[3] * 50e-9;
                t_rel(c->depth[c->n - 1], v[2] * 1e-9 - d, 1e-12, "%s: last retract depth",
                      ws[i]);
            }
            lf_curve_free(c);
            lf_warnings_free(&w);
        }
    }
}

/* The PEG hydrogel curves, fitted with the half-space JKR model from the
 * export: E* against the instrument's Hertz E[eff], and w against the
 * measured pull-off force, |P_po| = 1.5 pi R w. */
static void
test_real_peg(void)
{
    static const char *const files[] = { "10 wv pc PEGFN S-1 X-1 Y-1 I-1.txt",
                                         "10 wv pc PEGFN S-1 X-1 Y-2 I-1.txt" };
    size_t i;
    for (i = 0; i < 2; i++) {
        char path[1400];
        lf_curve *c;
        lf_error err;
        lf_fit_result res;
        int st;
        snprintf(path, sizeof path, "%s/%s", real, files[i]);
        if (!t_int(lf_curve_read(path, NULL, &c, NULL, &err), LF_OK, "%s reads", files[i]))
            continue;
        st = fit_halfspace(c, c->R, &res);
        if (t_true(st == LF_OK, "%s: half-space JKR fit converges", files[i])) {
            double Eeff = atof(meta(c, "E[eff] (Pa)")), fmin = INFINITY, po, wpo;
            size_t j;
            for (j = 0; j < c->n; j++)
                if (c->segment[j] == LF_SEG_UNLOAD)
                    fmin = fmin < c->force[j] ? fmin : c->force[j];
            po = fmin - res.curves[0].F0;         /* pull-off above the baseline */
            wpo = fabs(po) / (1.5 * M_PI * c->R);
            printf("  %s: E* %.4g Pa (header E[eff] %.4g Pa, %+.1f%%), w %.4g J/m^2, "
                   "pull-off %.4g N -> w %.4g J/m^2 (%+.1f%%)\n", files[i], res.Estar.value,
                   Eeff, 100 * (res.Estar.value / Eeff - 1), res.w.value, po, wpo,
                   100 * (res.w.value / wpo - 1));
            t_rel(res.Estar.value, Eeff, 0.10, "%s: E* within 10%% of the instrument's Hertz "
                  "E[eff]", files[i]);
            t_rel(res.w.value, wpo, 0.10, "%s: w within 10%% of |P_po|/(1.5 pi R)", files[i]);
            t_true(po < -35e-9 && po > -45e-9, "%s: pull-off %g N near -41 nN", files[i], po);
        }
        if (st == LF_OK || st == LF_ENOCONV)
            lf_fit_result_free(&res);
        lf_curve_free(c);
    }
}

int
main(int argc, char **argv)
{
    (void) argc;
    find_data(argv[0]);
    snprintf(vendors, sizeof vendors, "%s/../../datasets/vendors", data);
    snprintf(real, sizeof real, "%s/../../../shared/realdata", data);
    test_vendors();
    test_vendor_details();
    test_plan_columns();
    test_generic_text();
    if (real_present()) {
        test_real_chiaro();
        test_real_others();
        test_real_peg();
    } else {
        printf("skipped: ../shared/realdata not found\n");
    }
    return t_summary();
}
