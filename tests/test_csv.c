/* test_csv.c: the curve reader.  Every file under tests/data is parsed
 * with every chunk size from 1 to its length and must give the same curve
 * (or the same error) as when read at once, as libcsv's own tests do; then
 * values, segments, metadata, warnings and each rejection are checked. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "layerfit.h"
#include "testlib.h"
#include "testdata.h"

static int
same_array(const void *a, const void *b, size_t n)
{
    return (a == NULL) == (b == NULL) && (a == NULL || memcmp(a, b, n) == 0);
}

static int
same_curve(const lf_curve *a, const lf_curve *b)
{
    size_t i;
    if (a->n != b->n || a->nmeta != b->nmeta || strcmp(a->file, b->file) != 0)
        return 0;
    for (i = 0; i < a->nmeta; i++)
        if (strcmp(a->meta[i].key, b->meta[i].key) || strcmp(a->meta[i].value, b->meta[i].value))
            return 0;
    return same_array(a->depth, b->depth, a->n * sizeof *a->depth)
        && same_array(a->force, b->force, a->n * sizeof *a->force)
        && same_array(a->time, b->time, a->n * sizeof *a->time)
        && same_array(a->segment, b->segment, a->n)
        && same_array(a->line, b->line, a->n * sizeof *a->line);
}

/* What a chunked parse is compared with. */
typedef struct {
    const char *path;
    const lf_read_opts *o;
    int status;
    const lf_curve *ref;
    const lf_error *err;
} reference;

static int
curve_differs(void *ctx, const char *buf, size_t len, size_t chunk)
{
    const reference *r = ctx;
    lf_curve *c;
    lf_error e;
    int status = lf_curve_parse(buf, len, chunk, r->path, r->o, &c, NULL, &e);
    int differs = status != r->status
        || (status == LF_OK ? !same_curve(r->ref, c) : !same_error(r->err, &e));
    lf_curve_free(c);
    return differs;
}

/* Read name (under tests/data) from its file, then from memory at every
 * chunk size; all must agree.  Returns the curve read from the file (or
 * NULL and *err). */
static lf_curve *
read_all_ways(const char *name, const lf_read_opts *o, lf_warnings *warn, lf_error *err)
{
    char path[1200];
    lf_curve *ref = NULL;
    reference r;
    size_t len = 0;
    long bad;

    snprintf(path, sizeof path, "%s/%s", data, name);
    r.path = path;
    r.o = o;
    r.status = lf_curve_read(path, o, &ref, warn, err);
    r.ref = ref;
    r.err = err;
    bad = every_chunk(path, &len, curve_differs, &r);
    t_int(bad, 0, "%s: the same %s with each of %zu chunk sizes", name,
          r.status == LF_OK ? "curve" : "error", len + 1);
    return ref;
}

static void
test_comma(void)
{
    lf_warnings w = { 0, NULL };
    lf_error err;
    lf_curve *c = read_all_ways("curve_comma.csv", NULL, &w, &err);
    double d[10], f[10];
    static const double load[] = { -5, 0, 10, 20 }, unload[] = { 30, 25, 15, 5, -1, -6 };
    size_t i, n;

    if (!t_true(c != NULL, "curve_comma.csv reads (%s)", err.msg))
        return;
    t_int((long) c->n, 10, "comma: points");
    t_rel(c->depth[0], -5e-9, 1e-15, "comma: depth in m");
    t_rel(c->force[4], 85.25e-6, 1e-15, "comma: force in N");
    t_true(c->time == NULL, "comma: no time column");
    t_int(c->line[0], 4, "comma: first point's line");
    t_int((long) c->nmeta, 2, "comma: metadata lines");
    t_str(c->meta[0].key, "instrument", "comma: metadata key");
    t_str(c->meta[1].value, "sphere, R = 1 mm", "comma: metadata value keeps commas");
    n = lf_curve_segment(c, LF_SEG_LOAD, d, f);
    t_int((long) n, 4, "comma: loading points before the deepest");
    for (i = 0; i < n && i < 4; i++)
        t_rel(d[i], load[i] * 1e-9, 1e-15, "comma: load depth %zu", i);
    n = lf_curve_segment(c, LF_SEG_UNLOAD, d, f);
    t_int((long) n, 6, "comma: unloading points from the deepest");
    for (i = 0; i < n && i < 6; i++)
        t_rel(d[i], unload[i] * 1e-9, 1e-15, "comma: unload depth %zu", i);
    t_rel(f[3], -3.5e-6, 1e-15, "comma: unload force");
    t_int((long) lf_curve_segment(c, LF_SEG_UNLOAD, NULL, NULL), 6, "comma: count only");
    t_int((long) w.n, 0, "comma: no warnings");
    t_int(lf_curve_check_fit(c, LF_SEG_UNLOAD, 6, &err), LF_OK, "comma: unload fits");
    t_int(lf_curve_check_fit(c, LF_SEG_LOAD, 6, &err), LF_EDATA, "comma: load too short");
    t_str(err.msg, "the loading segment has 4 points (a fit needs at least 6)", "comma: message");
    t_int(err.line, 4, "comma: message points at the segment");
    lf_curve_free(c);
    lf_warnings_free(&w);
}

static void
test_paren_crlf(void)
{
    lf_warnings w = { 0, NULL };
    lf_error err;
    lf_curve *c = read_all_ways("curve_paren_crlf.csv", NULL, &w, &err);

    if (!t_true(c != NULL, "curve_paren_crlf.csv reads (%s)", err.msg))
        return;
    t_int((long) c->n, 9, "paren: points (blank and comment lines skipped)");
    t_rel(c->depth[1], 10e-9, 1e-15, "paren: quoted depth, BOM dropped");
    t_rel(c->force[1], 1.5e-6, 1e-15, "paren: µN understood");
    t_true(c->time != NULL && c->time[8] == 8.0, "paren: time in s");
    t_int(c->line[2], 6, "paren: line of a row after a comment");
    t_int(c->line[3], 8, "paren: a quoted line break counts as a line");
    t_int(c->line[8], 13, "paren: last line without a newline");
    t_int(c->segment[3], LF_SEG_UNLOAD, "paren: split at the deepest point");
    t_int((long) w.n, 1, "paren: one warning");
    if (w.n > 0)
        t_contains(w.msg[0], "/curve_paren_crlf.csv:5: dropped 1 comment line (first here; "
                   "only '# key: value' lines above the header are kept, as metadata)",
                   "paren: dropped comment warning");
    lf_curve_free(c);
    lf_warnings_free(&w);
}

static void
test_tab_segments(void)
{
    lf_warnings w = { 0, NULL };
    lf_error err;
    lf_curve *c = read_all_ways("curve_bracket.tsv", NULL, &w, &err);

    if (!t_true(c != NULL, "curve_bracket.tsv reads (%s)", err.msg))
        return;
    t_int((long) c->n, 13, "tab: points");
    t_rel(c->depth[5], 20e-9, 1e-12, "tab: um");
    t_rel(c->force[6], 0.31e-3, 1e-12, "tab: mN");
    t_int((long) lf_curve_segment(c, LF_SEG_LOAD, NULL, NULL), 6, "tab: segment column, load words");
    t_int(c->segment[6], LF_SEG_UNLOAD, "tab: 'retract' unloads");
    t_int(c->segment[5], LF_SEG_LOAD, "tab: 'Extend' loads, any case");
    t_str(c->meta[0].value, "PDMS 1 um", "tab: metadata");
    t_int((long) w.n, 1, "tab: one warning");
    if (w.n > 0)
        t_contains(w.msg[0], "curve_bracket.tsv:12: depth increases at 1 point of the "
                   "unloading segment", "tab: non-monotonic depth warned");
    lf_curve_free(c);
    lf_warnings_free(&w);
}

/* Hold words in a segment column mark a hold: kept, counted, never fitted. */
static void
test_hold_column(void)
{
    lf_warnings w = { 0, NULL };
    lf_error err;
    double d[16], f[16];
    size_t n;
    lf_curve *c = read_all_ways("curve_hold_column.csv", NULL, &w, &err);

    if (!t_true(c != NULL, "curve_hold_column.csv reads (%s)", err.msg))
        return;
    t_int((long) c->n, 15, "hold column: every point kept");
    t_int((long) lf_curve_segment(c, LF_SEG_LOAD, NULL, NULL), 5, "hold column: load points");
    t_int((long) lf_curve_segment(c, LF_SEG_HOLD, NULL, NULL), 4,
          "hold column: hold, Pause, DWELL, holding are holds");
    n = lf_curve_segment(c, LF_SEG_UNLOAD, d, f);
    t_int((long) n, 6, "hold column: unload points");
    t_rel(d[0], 16e-9, 1e-12, "hold column: unloading starts after the hold");
    t_rel(f[0], 7.5e-6, 1e-12, "hold column: force of the first unloading point");
    t_int(c->segment[5], LF_SEG_HOLD, "hold column: line 7 is a hold");
    t_int(c->segment[9], LF_SEG_UNLOAD, "hold column: 'retract' after the hold unloads");
    t_int((long) w.n, 0, "hold column: no warning (the hold's constant depth is not "
          "a backwards step)");
    t_true(lf_curve_check_fit(c, LF_SEG_UNLOAD, 5, &err) == LF_OK,
           "hold column: the unloading segment can be fitted");
    lf_curve_free(c);
    lf_warnings_free(&w);
}

static void
test_semicolon(void)
{
    lf_error err;
    lf_curve *c = read_all_ways("curve_semicolon.csv", NULL, NULL, &err);
    if (!t_true(c != NULL, "curve_semicolon.csv reads (%s)", err.msg))
        return;
    t_int((long) c->n, 8, "semicolon: points");
    t_rel(c->depth[1], 1.5e-8, 1e-15, "semicolon: decimal comma");
    t_rel(c->force[1], 2.5e-6, 1e-15, "semicolon: decimal comma in force");
    lf_curve_free(c);
}

static void
test_options(void)
{
    lf_read_opts o;
    lf_warnings w = { 0, NULL };
    lf_error err;
    lf_curve *c;

    lf_read_opts_default(&o);
    t_true(o.depth_unit == NULL && o.force_unit == NULL && !o.skip_bad_rows, "default options");
    c = read_all_ways("curve_nounit.csv", &o, NULL, &err);
    t_true(c == NULL, "no units: rejected");
    t_str(err.msg, "depth column 'Depth' has no unit (name it in the header, e.g. "
          "Depth_nm or Depth (nm), or give --depth-unit)", "no units: message");
    t_int(err.status, LF_EUNIT, "no units: status");
    o.depth_unit = "nm";
    o.force_unit = "uN";
    c = read_all_ways("curve_nounit.csv", &o, NULL, &err);
    if (t_true(c != NULL, "units from options (%s)", err.msg)) {
        t_rel(c->depth[3], 3e-9, 1e-15, "option depth unit");
        t_rel(c->force[3], 9e-6, 1e-15, "option force unit");
    }
    lf_curve_free(c);
    o.depth_unit = "um";
    c = read_all_ways("curve_comma.csv", &o, &w, &err);
    if (t_true(c != NULL, "option over a header unit (%s)", err.msg))
        t_rel(c->depth[0], -5e-6, 1e-15, "option wins over the header");
    t_true(w.n == 1 && strstr(w.msg[0], "the header gives 'nm' for depth") != NULL,
           "option over a header unit: warned");
    lf_curve_free(c);
    lf_warnings_free(&w);
    o.depth_unit = "kg";
    t_int(lf_curve_parse("depth_nm,force_uN\n", 18, 0, "x", &o, &c, NULL, &err), LF_EUNIT,
          "bad option unit: status");
    t_str(err.msg, "--depth-unit: unit 'kg' is another kind of quantity, not a length "
          "(e.g. 1um)", "bad option unit: message");
    lf_read_opts_default(&o);
    c = read_all_ways("curve_skip.csv", &o, NULL, &err);
    t_true(c == NULL, "missing cell rejected by default");
    t_int(err.line * 100 + err.column, 303, "missing cell: line 3 column 3");
    o.skip_bad_rows = 1;
    c = read_all_ways("curve_skip.csv", &o, &w, &err);
    if (t_true(c != NULL, "skip bad rows (%s)", err.msg)) {
        t_int((long) c->n, 7, "skip bad rows: points kept");
        t_int(c->line[1], 5, "skip bad rows: rows 3 and 4 gone");
        t_true(w.n == 1 && strstr(w.msg[0], ":3: skipped 2 rows with missing cells") != NULL,
               "skip bad rows: warned");
    }
    lf_curve_free(c);
    lf_warnings_free(&w);
}

/* Every file under tests/data/bad whose name starts with "curve_" is
 * rejected the same way at every chunk size; the messages themselves are
 * compared by tests/cli/check.sh. */
static void
test_bad_files(void)
{
    static const char *const files[] = {
        "curve_empty.csv", "curve_header_only.csv", "curve_binary.csv",
        "curve_no_depth.csv", "curve_no_force.csv", "curve_two_depth.csv",
        "curve_unknown_unit.csv", "curve_wrong_unit.csv", "curve_no_unit.csv",
        "curve_not_number.csv", "curve_nan.csv", "curve_inf.csv",
        "curve_ragged.csv", "curve_ragged_long.csv", "curve_quote.csv",
        "curve_bad_quote.csv", "curve_segment_word.csv", "curve_utf16.csv",
        "curve_data_first.csv"
    };
    char name[256];
    size_t i;
    for (i = 0; i < sizeof files / sizeof files[0]; i++) {
        lf_error err;
        lf_curve *c;
        snprintf(name, sizeof name, "bad/%s", files[i]);
        c = read_all_ways(name, NULL, NULL, &err);
        t_true(c == NULL && err.msg[0] != '\0', "%s rejected", files[i]);
        lf_curve_free(c);
    }
}

/* Rejections from memory: status, line, column and message. */
static void
test_bad_memory(void)
{
    static const struct {
        const char *in;
        int status;
        long line, col;
        const char *msg;
    } cases[] = {
        { "", LF_EFORMAT, 0, 0, "empty file (expected a header such as depth_nm,force_uN and one row per point)" },
        { "# a: b\n\n# c\n", LF_EFORMAT, 0, 0, "no header row, only comments (the first line that is not a comment names the columns, e.g. depth_nm,force_uN)" },
        { "depth_nm,force_uN\r\n", LF_EDATA, 1, 0, "header but no data rows (expected one row of depth_nm and force_uN per point below it)" },
        { "depth_nm,force_uN\n1,2\x01\n", LF_EFORMAT, 2, 4, "binary data: control byte 0x01 (expected a text CSV file)" },
        { "d\xff\xfe_nm,\x80\n", LF_EFORMAT, 1, 1, "binary data or text that is not UTF-8 (expected a CSV text file)" },
        { "delta_nm,P_nN,delta (um)\n", LF_EFORMAT, 1, 15, "second depth column 'delta (um)' (column 'delta_nm' is the depth already; keep one, or rename the other)" },
        { "load_uN,force_uN\n", LF_EFORMAT, 1, 9, "second force column 'force_uN' (column 'load_uN' is the force already; keep one, or rename the other)" },
        { "depth_nm,force_kg\n", LF_EUNIT, 1, 10, "force column 'force_kg': unit 'kg' is another kind of quantity, not a force (e.g. 10uN)" },
        { "depth_nm,force_uN\n1,2\n3,0x10\n", LF_EFORMAT, 3, 3, "force_uN '0x10' is not a number (expected a decimal number such as 12.5)" },
        { "depth_nm;force_uN\n1;2\n3;1.000,5\n", LF_EFORMAT, 3, 3, "force_uN '1.000,5' is not a number (expected a decimal number such as 12,5 or 12.5)" },
        { "depth_nm,force_uN\n1e400,2\n", LF_EFORMAT, 2, 1, "depth_nm '1e400' is not a finite number (give a measured value, or delete the row)" },
        { "depth_nm,force_uN\n1, inf \n", LF_EFORMAT, 2, 3, "force_uN 'inf' is not a finite number (give a measured value, or delete the row)" },
        { "depth_nm,force_uN\n1\n", LF_EFORMAT, 2, 2, "row has 1 cell, the header 2 (every row needs a cell in each column; --skip-bad-rows skips such rows)" },
        { "depth_nm,force_uN\n1,\n", LF_EFORMAT, 2, 3, "empty force cell (every row needs a cell in each column; --skip-bad-rows skips such rows)" },
        { "depth_nm\tforce_uN\n1\t2\t3\n", LF_EFORMAT, 2, 5, "row has 3 cells, the header 2 (is the delimiter '\\t' used inside a number? quote such cells)" },
        { "depth_nm,force_uN\n1,\"2\n\n3,4\n", LF_EFORMAT, 2, 3, "quote opened here is never closed (end the field with \")" },
        { "depth_nm,force_uN\n1,\"2\"x\n", LF_EFORMAT, 2, 6, "malformed quotes (quote a whole field, and double the quotes inside it: \"a \"\"b\"\"\")" },
        { "depth_nm,force_uN,Segment\n1,2,creep\n", LF_EFORMAT, 2, 5, "unknown segment 'creep' (expected load, approach, extend, hold, pause, dwell, unload, retract or withdraw)" },
        { "1.5,2\n", LF_EFORMAT, 1, 1, "the first row is data, not a header (start with a header naming the columns, e.g. depth_nm,force_uN)" },
        { "x,y\n", LF_EFORMAT, 1, 1, "no depth column in the header (name one depth, indentation, displacement or delta, with its unit, e.g. depth_nm)" },
        { "\xff\xfe" "d\0", LF_EFORMAT, 1, 1, "UTF-16 text (save the file as UTF-8 CSV)" },
    };
    size_t i, chunk;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        size_t len = strlen(cases[i].in) + (cases[i].in[0] == '\xff' ? 2 : 0);
        lf_curve *c = NULL;
        lf_error err, e2;
        int status = lf_curve_parse(cases[i].in, len, 0, "m.csv", NULL, &c, NULL, &err);
        int same = 1;
        t_int(status, cases[i].status, "case %zu: status", i);
        t_true(c == NULL, "case %zu: no curve", i);
        t_int(err.line, cases[i].line, "case %zu: line", i);
        t_int(err.column, cases[i].col, "case %zu: column", i);
        t_str(err.msg, cases[i].msg, "case %zu: message", i);
        t_str(err.file, "m.csv", "case %zu: file", i);
        for (chunk = 1; chunk <= len; chunk++) {
            lf_curve_parse(cases[i].in, len, chunk, "m.csv", NULL, &c, NULL, &e2);
            same &= same_error(&err, &e2);
        }
        t_true(same, "case %zu: same error at every chunk size", i);
    }
}

/* A line of exactly 1 MiB is read; one byte more is refused. */
static void
test_long_line(void)
{
    const char *head = "depth_nm,force_uN\n";
    size_t h = strlen(head), max = 1024 * 1024, chunks[] = { 0, 1, 7, 4096, 65536 }, k;
    char *buf = malloc(h + max + 8);
    lf_curve *c = NULL;
    lf_error err;

    if (!t_true(buf != NULL, "long line: memory"))
        return;
    memcpy(buf, head, h);
    for (k = 0; k < sizeof chunks / sizeof chunks[0]; k++) {
        memset(buf + h, ' ', max + 1);
        memcpy(buf + h, "1,2", 3);
        buf[h + max] = '\n';
        t_int(lf_curve_parse(buf, h + max + 1, chunks[k], "big.csv", NULL, &c, NULL, &err),
              LF_OK, "1 MiB line read (chunk %zu)", chunks[k]);
        lf_curve_free(c);
        buf[h + max] = ' ';
        buf[h + max + 1] = '\n';
        t_int(lf_curve_parse(buf, h + max + 2, chunks[k], "big.csv", NULL, &c, NULL, &err),
              LF_EFORMAT, "1 MiB + 1 refused (chunk %zu)", chunks[k]);
        t_str(err.msg, "line longer than 1 MiB (lines must end within 1048576 bytes; "
              "is this a CSV file?)", "long line: message");
        t_int(err.line, 2, "long line: line");
    }
    /* a quote left open swallows lines until the record passes 1 MiB */
    memset(buf + h, '\n', max + 4);
    memcpy(buf + h, "1,\"", 3);
    t_int(lf_curve_parse(buf, h + max + 4, 4096, "big.csv", NULL, &c, NULL, &err),
          LF_EFORMAT, "open quote over many lines refused");
    t_str(err.msg, "row longer than 1 MiB (is a quote left open here?)", "open quote: message");
    t_int(err.line * 10 + err.column, 23, "open quote: where the field starts");
    free(buf);
}

static void
test_check_fit(void)
{
    static const char few[] = "depth_nm,force_uN\n0,0\n10,5\n20,9\n10,4\n0,0\n";
    static const char zero[] = "depth_nm,force_uN\n0,0\n20,0\n10,0\n0,0\n";
    static const char flat[] = "depth_nm,force_uN\n5,0\n5,1\n5,2\n5,1\n";
    lf_curve *c;
    lf_error err;

    lf_curve_parse(few, sizeof few - 1, 0, "few.csv", NULL, &c, NULL, &err);
    t_int(lf_curve_check_fit(c, LF_SEG_UNLOAD, 4, &err), LF_EDATA, "few points: refused");
    t_str(err.msg, "the unloading segment has 3 points (a fit needs at least 4)", "few points: message");
    t_int(lf_curve_check_fit(c, LF_SEG_UNLOAD, 3, &err), LF_OK, "few points: enough for 3");
    lf_curve_free(c);
    lf_curve_parse(zero, sizeof zero - 1, 0, "zero.csv", NULL, &c, NULL, &err);
    t_int(lf_curve_check_fit(c, LF_SEG_UNLOAD, 2, &err), LF_EDATA, "zero force: refused");
    t_str(err.msg, "force is 0 at every point of the unloading segment (is the force "
          "column the right one?)", "zero force: message");
    t_str(err.file, "zero.csv", "zero force: file named");
    lf_curve_free(c);
    lf_curve_parse(flat, sizeof flat - 1, 0, "flat.csv", NULL, &c, NULL, &err);
    t_int(lf_curve_check_fit(c, LF_SEG_UNLOAD, 2, &err), LF_EDATA, "flat depth: refused");
    t_str(err.msg, "depth is 5e-09 m at every point of the unloading segment (is the "
          "depth column the right one?)", "flat depth: message");
    lf_curve_free(c);
}

static void
test_files(void)
{
    char path[1200];
    lf_curve *c = (lf_curve *) &c;
    lf_error err;

    snprintf(path, sizeof path, "%s/no-such-file.csv", data);
    t_int(lf_curve_read(path, NULL, &c, NULL, &err), LF_EIO, "missing file: status");
    t_true(c == NULL, "missing file: no curve");
    t_str(err.msg, "cannot open: No such file or directory", "missing file: message");
    t_int(lf_curve_read(data, NULL, &c, NULL, &err), LF_EIO, "directory: status");
    t_str(err.msg, "is a directory (expected a CSV file)", "directory: message");
    lf_curve_free(NULL);
}

int
main(int argc, char **argv)
{
    (void) argc;
    find_data(argv[0]);
    test_comma();
    test_paren_crlf();
    test_tab_segments();
    test_hold_column();
    test_semicolon();
    test_options();
    test_bad_files();
    test_bad_memory();
    test_long_line();
    test_check_fit();
    test_files();
    return t_summary();
}
