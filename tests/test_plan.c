/* test_plan.c: the fit-plan reader.  Every plan under tests/data is parsed
 * with every chunk size and must give the same plan or error as when read
 * from its file; then values, units, defaults and each rejection. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "command.h"      /* layerfit.h and what the command shares */
#include "testlib.h"
#include "testdata.h"

static int
same_plan(const lf_plan *a, const lf_plan *b)
{
    size_t i;
    if (a->n != b->n || strcmp(a->path, b->path) != 0)
        return 0;
    for (i = 0; i < a->n; i++) {
        const lf_plan_row *x = &a->rows[i], *y = &b->rows[i];
        if (strcmp(x->file, y->file) || strcmp(x->sample, y->sample) || x->line != y->line
            || memcmp(&x->probe, &y->probe, sizeof x->probe) || x->segment != y->segment
            || memcmp(&x->nu, &y->nu, sizeof x->nu) || memcmp(&x->z0, &y->z0, sizeof x->z0)
            || memcmp(&x->F0, &y->F0, sizeof x->F0))
            return 0;
    }
    return 1;
}

/* What a chunked parse is compared with. */
typedef struct {
    const char *path, *dir;
    int status;
    const lf_plan *ref;
    const lf_error *err;
} reference;

static int
plan_differs(void *ctx, const char *buf, size_t len, size_t chunk)
{
    const reference *r = ctx;
    lf_plan *p;
    lf_error e;
    int status = lf_plan_parse(buf, len, chunk, r->path, r->dir, &p, NULL, &e);
    int differs = status != r->status
        || (status == LF_OK ? !same_plan(r->ref, p) : !same_error(r->err, &e));
    lf_plan_free(p);
    return differs;
}

/* Read name (under tests/data) from its file, then from memory at every
 * chunk size; all must agree.  Returns the plan from the file or NULL. */
static lf_plan *
read_all_ways(const char *name, lf_error *err)
{
    char path[1200], dir[1200];
    lf_plan *ref = NULL;
    reference r;
    size_t len = 0;
    long bad;

    snprintf(path, sizeof path, "%s/%s", data, name);
    snprintf(dir, sizeof dir, "%s", path);
    *strrchr(dir, '/') = '\0';
    r.path = path;
    r.dir = dir;
    r.status = lf_plan_read(path, &ref, NULL, err);
    r.ref = ref;
    r.err = err;
    bad = every_chunk(path, &len, plan_differs, &r);
    t_int(bad, 0, "%s: the same %s with each of %zu chunk sizes", name,
          r.status == LF_OK ? "plan" : "error", len + 1);
    return ref;
}

static void
test_good(void)
{
    char want[1200];
    lf_error err;
    lf_plan *p = read_all_ways("plan_good.csv", &err);
    const lf_plan_row *r;

    if (!t_true(p != NULL, "plan_good.csv reads (%s)", err.msg))
        return;
    t_int((long) p->n, 4, "good: rows");
    r = &p->rows[0];
    snprintf(want, sizeof want, "%s/curve_comma.csv", data);
    t_str(r->file, want, "good: path relative to the plan's folder");
    t_int(r->line, 3, "good: line after a comment");
    t_rel(r->probe.k, 2, 0, "good: k");
    t_rel(r->probe.R, 1e-3, 1e-15, "good: R from the header unit");
    t_rel(r->probe.b, 1e-6, 1e-15, "good: b from the cell unit");
    t_int(r->probe.base, LF_BASE_FRICTIONLESS, "good: frictionless");
    t_true(isnan(r->nu) && isnan(r->z0) && isnan(r->F0), "good: empty cells are free (NaN)");
    t_int(r->segment, LF_SEG_UNLOAD, "good: unload by default");
    t_str(r->sample, "film-A", "good: sample");
    r = &p->rows[1];
    t_rel(r->probe.k, 3, 0, "good: k row 2");
    t_rel(r->probe.R, 1.5e-3, 1e-15, "good: R row 2");
    t_rel(r->probe.b, 1e-6, 1e-15, "good: '1 um' with a space");
    t_rel(r->z0, 15e-9, 1e-15, "good: z0 fixed");
    t_true(isnan(r->F0), "good: 'NaN' F0 is free");
    r = &p->rows[2];
    t_int(r->probe.base, LF_BASE_BONDED, "good: bonded");
    t_rel(r->nu, 0.35, 0, "good: nu");
    t_int(r->segment, LF_SEG_LOAD, "good: load segment");
    t_rel(r->F0, -2e-6, 1e-15, "good: F0 fixed");
    t_rel(r->probe.b, 1e-6, 1e-12, "good: 1000nm");
    t_int(p->rows[3].probe.base, LF_BASE_BONDED, "good: interface word in any case");
    t_str(p->rows[3].sample, "film-B", "good: sample row 4");
    lf_plan_free(p);
}

static void
test_memory(void)
{
    static const char semi[] = "File;k;R;b;Interface\n"
                               "curve_comma.csv;2,5;1,5 mm;0,5um;frictionless\n";
    char abs[1400];
    lf_plan *p = NULL;
    lf_error err;

    t_int(lf_plan_parse(semi, sizeof semi - 1, 0, "semi.csv", data, &p, NULL, &err), LF_OK,
          "semicolon plan with decimal commas (%s)", err.msg);
    if (p != NULL) {
        t_rel(p->rows[0].probe.k, 2.5, 0, "semicolon: k");
        t_rel(p->rows[0].probe.R, 1.5e-3, 1e-15, "semicolon: R with a cell unit");
        t_rel(p->rows[0].probe.b, 0.5e-6, 1e-15, "semicolon: b");
        t_str(p->rows[0].sample, "", "no sample column: empty");
        t_str(p->path, "semi.csv", "plan path is its name");
    }
    lf_plan_free(p);
    {
        char *full = realpath(data, NULL);
        snprintf(abs, sizeof abs, "file,k,R_m,b_m,interface\n%s/curve_comma.csv,2,1e-3,"
                 "1e-6,frictionless\n", full ? full : "/");
        free(full);
    }
    t_int(lf_plan_parse(abs, strlen(abs), 0, "abs.csv", "/nowhere", &p, NULL, &err), LF_OK,
          "a path from / is not resolved (%s)", err.msg);
    lf_plan_free(p);
}

/* Empty b and interface cells: no layer (b NaN), for half-space fits; a
 * row with a layer beside it keeps its own. */
static void
test_no_layer(void)
{
    static const char no_layer[] = "file,k,R,b,interface\n"
                                   "curve_comma.csv,2,8um,,\n"
                                   "curve_bracket.tsv,2,8um,1um,bonded\n";
    lf_plan *p = NULL;
    lf_error err;

    t_int(lf_plan_parse(no_layer, sizeof no_layer - 1, 0, "nl.csv", data, &p, NULL, &err),
          LF_OK, "empty b and interface cells are read (%s)", err.msg);
    if (p != NULL && p->n == 2) {
        t_true(isnan(p->rows[0].probe.b), "no layer: b is NaN");
        t_rel(p->rows[0].probe.R, 8e-6, 1e-15, "no layer: R kept");
        t_rel(p->rows[1].probe.b, 1e-6, 1e-15, "the next row keeps its b");
        t_int(p->rows[1].probe.base, LF_BASE_BONDED, "the next row keeps its interface");
    }
    lf_plan_free(p);
}

static void
test_bad_memory(void)
{
    static const struct {
        const char *in;
        int status;
        long line, col;
        const char *msg;
    } cases[] = {
        { "", LF_EFORMAT, 0, 0, "empty plan (expected a header such as file,k,R_mm,b_um,interface and one row per curve)" },
        { "file,k,R_mm,b_um,interface\n", LF_EDATA, 1, 0, "header but no rows (list one curve per row below it)" },
        { "file,k_mm,R_mm,b_um,interface\n", LF_EUNIT, 1, 6, "column k takes no unit in its header (name it 'k')" },
        { "file,k,R_s,b_um,interface\n", LF_EUNIT, 1, 8, "column R: unit 's' is a time, not a length (e.g. 1um)" },
        { "file,k,R,b,interface,k\n", LF_EFORMAT, 1, 22, "second k column (keep one)" },
        { "file,k,R,b,interface\ncurve_comma.csv,2,1,1um,frictionless\n", LF_EUNIT, 2, 19, "R: '1' has no unit (e.g. 1um)" },
        { "file,k,R,b,interface\ncurve_comma.csv,2,,1um,frictionless\n", LF_EFORMAT, 2, 19, "empty R cell (every row needs R)" },
        { "file,k,R,b,interface\ncurve_comma.csv,two,1mm,1um,frictionless\n", LF_EFORMAT, 2, 17, "k 'two' is not a number (e.g. 2)" },
        { "file,k,R,b,interface\ncurve_comma.csv,-2,1mm,1um,frictionless\n", LF_EINVAL, 2, 17, "k must be a finite number > 0 (got -2)" },
        { "file,k,R,b,interface\ncurve_comma.csv,2,1mm,0um,frictionless\n", LF_EINVAL, 2, 23, "b must be a finite length > 0 (got 0 m)" },
        { "file,k,R,b,interface,nu\ncurve_comma.csv,2,1mm,1um,bonded,0.7\n", LF_EINVAL, 2, 34, "nu must lie in [0, 0.5) for a bonded layer (got 0.7) (leave nu empty to fit it)" },
        { "file,k,R,b,interface,nu\ncurve_comma.csv,2,1mm,1um,frictionless,0.7\n", LF_EINVAL, 2, 40, "nu must lie in (-1, 0.5] (got 0.7)" },
        { "file,k,R,b,interface,segment\ncurve_comma.csv,2,1mm,1um,bonded,hold\n", LF_EFORMAT, 2, 34, "segment 'hold' is a hold, which is never fitted (expected unload or load)" },
        { "file,k,R,b,interface,segment\ncurve_comma.csv,2,1mm,1um,bonded,Dwell\n", LF_EFORMAT, 2, 34, "segment 'Dwell' is a hold, which is never fitted (expected unload or load)" },
        { "file,k,R,b,interface\ncurve_comma.csv,2,1mm,1um,\n", LF_EFORMAT, 2, 27, "b and interface go together: give both for a layer, or leave both empty for a half-space (fit with --model halfspace)" },
        { "file,k,R,b,interface\ncurve_comma.csv,2,1mm,,frictionless\n", LF_EFORMAT, 2, 24, "b and interface go together: give both for a layer, or leave both empty for a half-space (fit with --model halfspace)" },
        { "file,k,R,b,interface,segment\ncurve_comma.csv,2,1mm,1um,bonded,sideways\n", LF_EFORMAT, 2, 34, "unknown segment 'sideways' (expected unload or load)" },
        { "file,k,R,b,interface\ncurve_comma.csv,2,1mm,1um\n", LF_EFORMAT, 2, 1, "row has 4 cells, the header 5 (give each column a cell; leave optional ones empty)" },
        { "file,k,R,b,interface\n,2,1mm,1um,bonded\n", LF_EFORMAT, 2, 1, "empty file cell (name the curve's CSV file, relative to the plan's folder)" },
        { "file,k,R,b,interface,segment\ncurve_comma.csv,2,1mm,1um,bonded,unload\n"
          "curve_comma.csv,2,1mm,1um,bonded,load\ncurve_comma.csv,3,1mm,1um,bonded,retract\n",
          LF_EFORMAT, 4, 1, "duplicate row: curve 'curve_comma.csv' and segment unload are listed at line 2 already (list each once)" },
        { "file,k,R,b,interface,F0\ncurve_comma.csv,2,1mm,1um,bonded,1m\n", LF_EUNIT, 2, 34, "F0: unit 'm' is a length, not a force (e.g. 10uN)" },
    };
    size_t i, chunk;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        size_t len = strlen(cases[i].in);
        lf_plan *p = NULL;
        lf_error err, e2;
        int same = 1;
        t_int(lf_plan_parse(cases[i].in, len, 0, "p.csv", data, &p, NULL, &err),
              cases[i].status, "plan case %zu: status", i);
        t_true(p == NULL, "plan case %zu: no plan", i);
        t_int(err.line, cases[i].line, "plan case %zu: line", i);
        t_int(err.column, cases[i].col, "plan case %zu: column", i);
        t_str(err.msg, cases[i].msg, "plan case %zu: message", i);
        for (chunk = 1; chunk <= len; chunk++) {
            lf_plan_parse(cases[i].in, len, chunk, "p.csv", data, &p, NULL, &e2);
            same &= same_error(&err, &e2);
        }
        t_true(same, "plan case %zu: same error at every chunk size", i);
    }
}

static void
test_bad_files(void)
{
    static const char *const files[] = {
        "plan_k_zero.csv", "plan_negative_R.csv",
        "plan_negative_b.csv", "plan_nu_bonded.csv", "plan_interface.csv",
        "plan_duplicate.csv", "plan_unknown_column.csv", "plan_no_b.csv",
        "plan_cell_unit.csv"
    };
    char name[256];
    size_t i;
    for (i = 0; i < sizeof files / sizeof files[0]; i++) {
        lf_error err;
        lf_plan *p;
        snprintf(name, sizeof name, "bad/%s", files[i]);
        p = read_all_ways(name, &err);
        t_true(p == NULL && err.msg[0] != '\0' && err.line > 0, "%s rejected at a line", files[i]);
        lf_plan_free(p);
    }
}

/* A curve file that is missing, a folder or a FIFO does not stop the plan
 * from being read (a batch makes it that curve's row): it is refused when
 * it is read, on the open descriptor, without blocking. */
static void
test_curve_checked_when_read(void)
{
    static const char folder_row[] = "file,k,R,b,interface\nbad,2,1mm,1um,bonded\n";
    char path[1200], fifo[64];
    lf_plan *p = NULL;
    lf_curve *c = NULL;
    lf_input in;
    lf_error err;
    int fd;

    snprintf(path, sizeof path, "%s/bad/plan_missing_curve.csv", data);
    t_int(lf_plan_read(path, &p, NULL, &err), LF_OK, "plan naming a missing curve is read (%s)",
          err.msg);
    if (p != NULL) {
        t_int(lf_curve_read(p->rows[p->n - 1].file, NULL, &c, NULL, &err), LF_EIO,
              "the missing curve is refused when read");
        t_true(strstr(err.msg, "No such file") != NULL, "and says so (%s)", err.msg);
    }
    lf_plan_free(p);
    t_int(lf_plan_parse(folder_row, strlen(folder_row), 0, "p.csv", data,
                        &p, NULL, &err), LF_OK, "plan naming a folder is read (%s)", err.msg);
    if (p != NULL) {
        t_int(lf_input_open(p->rows[0].file, 0, &fd, &err), LF_EIO, "a folder is refused");
        t_str(err.msg, "is a directory (expected a CSV file)", "a folder: message");
    }
    lf_plan_free(p);
    snprintf(fifo, sizeof fifo, "/tmp/lf_test_fifo_%ld", (long) getpid());
    unlink(fifo);
    if (mkfifo(fifo, 0600) == 0) {
        t_int(lf_input_read(fifo, 0, &in, &err), LF_EIO, "a FIFO is refused at once");
        t_str(err.msg, "is not a regular file (a FIFO or pipe; name a CSV file)", "a FIFO: message");
        t_int(lf_curve_read(fifo, NULL, &c, NULL, &err), LF_EIO, "a FIFO curve is refused");
        unlink(fifo);
    } else {
        t_true(0, "mkfifo %s", fifo);
    }
    snprintf(path, sizeof path, "%s/curve_comma.csv", data);
    t_int(lf_input_read(path, 0, &in, &err), LF_OK, "a regular file is read (%s)", err.msg);
    t_true(in.len > 0 && strlen(in.sha256) == 64, "whole, with its SHA-256");
    lf_input_free(&in);
    t_int(lf_input_read("/dev/null", LF_INPUT_STREAM, &in, &err), LF_OK, "a device as a stream");
    t_int((long) in.len, 0, "/dev/null is empty");
    t_str(in.sha256, "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855",
          "SHA-256 of nothing (FIPS 180-4 example)");
    lf_input_free(&in);
}

/* A long cell is parsed whole: '1' + 200 spaces + 'mm' is 1 mm, not 1 m. */
static void
test_long_cell(void)
{
    char buf[600];
    lf_plan *p = NULL;
    lf_error err;
    int n = snprintf(buf, sizeof buf, "file,k,R,b,interface\ncurve_comma.csv,2,1%200smm,1um,"
                     "frictionless\n", "");
    t_int(lf_plan_parse(buf, (size_t) n, 0, "p.csv", data, &p, NULL, &err), LF_OK,
          "long cell: read (%s)", err.msg);
    if (p != NULL)
        t_rel(p->rows[0].probe.R, 1e-3, 1e-12, "long cell: R = 1 mm");
    lf_plan_free(p);
}

static void
test_kind(void)
{
    char path[1200];
    lf_file_kind kind = LF_FILE_PLAN;
    lf_error err;

    snprintf(path, sizeof path, "%s/plan_good.csv", data);
    t_int(lf_file_kind_of(path, &kind, &err), LF_OK, "kind of a plan: ok");
    t_int(kind, LF_FILE_PLAN, "kind of a plan");
    snprintf(path, sizeof path, "%s/curve_paren_crlf.csv", data);
    t_int(lf_file_kind_of(path, &kind, &err), LF_OK, "kind of a curve: ok");
    t_int(kind, LF_FILE_CURVE, "kind of a curve");
    snprintf(path, sizeof path, "%s/bad/curve_empty.csv", data);
    t_int(lf_file_kind_of(path, &kind, &err), LF_OK, "kind of an empty file: ok");
    t_int(kind, LF_FILE_CURVE, "an empty file is left to the curve reader");
    snprintf(path, sizeof path, "%s/none.csv", data);
    t_int(lf_file_kind_of(path, &kind, &err), LF_EIO, "kind of a missing file");
    lf_plan_free(NULL);
}

int
main(int argc, char **argv)
{
    (void) argc;
    find_data(argv[0]);
    test_good();
    test_memory();
    test_no_layer();
    test_bad_memory();
    test_bad_files();
    test_curve_checked_when_read();
    test_long_cell();
    test_kind();
    return t_summary();
}
