/* test_input.c: from a plan to a fit's input (lf_fit_input_from_plan,
 * lf_fit_input_from_curve: points of the chosen segment, probe, held
 * offsets, the one nu rule), and tables (lf_table_read). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "command.h"      /* layerfit.h and what the command shares */
#include "testlib.h"

static char dir[64];

static void
write_text(const char *name, const char *text)
{
    char path[256];
    FILE *f;

    snprintf(path, sizeof path, "%s/%s", dir, name);
    f = fopen(path, "w");
    if (f == NULL || fputs(text, f) < 0 || fclose(f) != 0) {
        fprintf(stderr, "cannot write %s\n", path);
        exit(1);
    }
}

static lf_plan *
plan_of(const char *text, lf_error *err)
{
    lf_plan *p = NULL;
    if (lf_plan_parse(text, strlen(text), 0, "plan.csv", dir, &p, NULL, err) != LF_OK)
        return NULL;
    return p;
}

/* A curve of 6 loading points (depth rising) and 7 unloading ones. */
static const char curve_text[] =
    "depth_m,force_N,segment\n"
    "-2e-9,0.0,load\n-1e-9,0.0,load\n0.0,0.0,load\n1e-9,1e-6,load\n2e-9,3e-6,load\n"
    "3e-9,6e-6,load\n"
    "2.5e-9,5e-6,unload\n2e-9,3e-6,unload\n1e-9,1e-6,unload\n0.0,-1e-6,unload\n"
    "-1e-9,-2e-6,unload\n-2e-9,0.0,unload\n-3e-9,0.0,unload\n";

/* The plan `text` is refused by lf_fit_input_from_plan: LF_EDATA naming
 * line `line`, with `words` in the message, nothing left in the input. */
static void
refused(const char *what, const char *text, long line, const char *words)
{
    lf_error err;
    lf_fit_input in;
    lf_plan *p = plan_of(text, &err);

    t_true(p != NULL, "%s: plan parses: %s", what, p ? "" : err.msg);
    if (p == NULL)
        return;
    t_int(lf_fit_input_from_plan(p, NULL, 0, NULL, &in, NULL, &err), LF_EDATA, "%s: error", what);
    t_int(err.line, line, "%s: names the row's line", what);
    t_contains(err.msg, words, "%s: says why", what);
    t_true(in.curves == NULL && in.n == 0, "%s: nothing left in the input", what);
    lf_plan_free(p);
}

static void
test_plan_input(void)
{
    lf_error err;
    lf_plan *p;
    lf_fit_input in;
    lf_input_settings s = lf_input_settings_default();
    lf_fit_settings fs = lf_fit_settings_default();
    size_t rows[1] = { 1 };

    /* nu on a frictionless row counts like any other: one material, one nu */
    p = plan_of("file,k,R_m,b_m,interface,nu,z0_m\n"
                "a.csv,2,1e-3,1e-6,frictionless,0.25,\n"
                "b.csv,3,1e-3,1e-6,bonded,,1e-9\n", &err);
    t_true(p != NULL, "plan parses: %s", p ? "" : err.msg);
    if (p == NULL)
        return;
    t_int(lf_fit_input_from_plan(p, NULL, 0, NULL, &in, NULL, &err), LF_OK, "input: %s", err.msg);
    t_int((long) in.n, 2, "input: two curves");
    t_int((long) in.curves[0].n, 7, "input: unloading points by default");
    t_int(in.curves[0].branch, LF_BRANCH_UNLOAD, "input: the row's segment is the branch");
    t_abs(in.curves[0].depth[0], 2.5e-9, 0.0, "input: points in file order, SI");
    t_true(isnan(in.curves[0].z0) && in.curves[1].z0 == 1e-9, "input: the row's z0 held, else free");
    t_abs(in.nu, 0.25, 0.0, "input: nu from the frictionless row");
    t_str(in.curves[1].name, p->rows[1].file, "input: names the file");
    t_true(isnan(in.x) && isnan(in.y), "input: no position without '# x:' lines");
    lf_fit_input_apply_nu(&in, &fs);
    t_true(fs.nu.mode == LF_PARAM_FIXED && fs.nu.value == 0.25, "apply_nu: the plan holds nu");
    fs.nu.value = 0.4;
    lf_fit_input_apply_nu(&in, &fs);
    t_abs(fs.nu.value, 0.4, 0.0, "apply_nu: a value already held wins");
    lf_fit_input_free(&in);
    lf_plan_free(p);

    /* the input owns its arrays: the plan is freed first */
    p = plan_of("file,k,R_m,b_m,interface\na.csv,2,1e-3,1e-6,frictionless\n"
                "b.csv,2,1e-3,1e-6,frictionless\n", &err);
    s.segment = LF_SEG_LOAD;
    s.z0 = 2e-9;
    s.F0 = -1e-7;
    t_int(lf_fit_input_from_plan(p, rows, 1, &s, &in, NULL, &err), LF_OK, "subset: %s", err.msg);
    lf_plan_free(p);
    t_int((long) in.n, 1, "subset: one row");
    t_int((long) in.curves[0].n, 6, "segment override: loading points");
    t_int(in.curves[0].branch, LF_BRANCH_LOAD, "segment override: loading branch");
    t_true(strstr(in.curves[0].name, "b.csv") != NULL, "subset: the row asked for");
    t_true(in.curves[0].z0 == 2e-9 && in.curves[0].F0 == -1e-7, "offsets override");
    t_true(isnan(in.nu), "no nu column: NaN");
    lf_fit_input_free(&in);
    lf_fit_input_free(&in);     /* twice: harmless */

    /* one input, one material: two values of nu, two samples (an unnamed
     * row joins either; found before any file is read: c.csv holds a.csv's
     * bytes, the later error), or the same data under two names with the
     * same segment are each an error naming the row */
    refused("two nu", "file,k,R_m,b_m,interface,nu\na.csv,2,1e-3,1e-6,bonded,0.3\n"
            "b.csv,2,1e-3,1e-6,frictionless,0.35\n", 3, "one nu");
    refused("two samples", "file,k,R_m,b_m,interface,sample\n"
            "a.csv,2,1e-3,1e-6,frictionless,film-A\nb.csv,2,1e-3,1e-6,frictionless,\n"
            "c.csv,3,1e-3,1e-6,frictionless,film-B\n", 4, "a joint fit is of one material");
    /* an error about a row's curve is put at the row's line */
    refused("no radius", "file,k,R_m,b_m,interface\na.csv,2,1e-3,1e-6,frictionless\n"
            "c.csv,2,header,1e-6,frictionless\n", 3, "no probe radius");
    refused("same data", "file,k,R_m,b_m,interface\na.csv,2,1e-3,1e-6,frictionless\n"
            "c.csv,3,1e-3,1e-6,frictionless\n", 3, "holds the same data as");
    /* the same data as another segment is another curve */
    p = plan_of("file,k,R_m,b_m,interface,segment\na.csv,2,1e-3,1e-6,frictionless,load\n"
                "c.csv,2,1e-3,1e-6,frictionless,unload\n", &err);
    t_int(lf_fit_input_from_plan(p, NULL, 0, NULL, &in, NULL, &err), LF_OK,
          "same data, other segment: %s", err.msg);
    lf_fit_input_free(&in);
    lf_plan_free(p);

    /* a segment with too few points */
    p = plan_of("file,k,R_m,b_m,interface,segment\na.csv,2,1e-3,1e-6,frictionless,load\n", &err);
    s = lf_input_settings_default();
    s.min_points = 7;
    t_int(lf_fit_input_from_plan(p, NULL, 0, &s, &in, NULL, &err), LF_EDATA,
          "too few points: error");
    lf_plan_free(p);
}

static void
test_curve_input(void)
{
    lf_probe probe = { 2.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 }, bad = probe;
    lf_fit_input in;
    lf_error err;
    char path[256];

    snprintf(path, sizeof path, "%s/a.csv", dir);
    t_int(lf_fit_input_from_curve(path, &probe, NULL, &in, NULL, &err), LF_OK, "curve: %s", err.msg);
    t_int((long) in.n, 1, "curve: one");
    t_int((long) in.curves[0].n, 7, "curve: unloading by default");
    t_true(isnan(in.nu), "curve: no nu");
    lf_fit_input_free(&in);
    bad.R = -1.0;
    t_true(lf_fit_input_from_curve(path, &bad, NULL, &in, NULL, &err) != LF_OK, "curve: bad probe");
}

static void
test_table(void)
{
    lf_table *t = NULL;
    lf_error err;
    char path[256];
    double v;

    write_text("t.csv", "# a comment\nfit,status,w_J_m2\n1,ok,0.01\n2,error,\n3,ok,abc\n");
    snprintf(path, sizeof path, "%s/t.csv", dir);
    t_int(lf_table_read(path, &t, &err), LF_OK, "table: %s", err.msg);
    if (t == NULL)
        return;
    t_int((long) t->nrows, 3, "table: rows");
    t_int((long) t->ncols, 3, "table: columns");
    t_int(t->header_line, 2, "table: header line after the comment");
    t_int(lf_table_column(t, "w_J_m2"), 2, "table: column by name");
    t_int(lf_table_column(t, "nope"), -1, "table: unknown column");
    t_int(lf_table_number(t->cells[0 * 3 + 2], &v), LF_OK, "table: a number");
    t_abs(v, 0.01, 0.0, "table: its value");
    t_int(lf_table_number(t->cells[1 * 3 + 2], &v), LF_OK, "table: empty cell");
    t_true(isnan(v), "table: empty is NaN");
    t_int(lf_table_number(t->cells[2 * 3 + 2], &v), LF_EFORMAT, "table: not a number");
    t_int(t->line[2], 5, "table: line of a row");
    lf_table_free(t);
    lf_table_free(NULL);
}

int
main(void)
{
    char cmd[128];

    snprintf(dir, sizeof dir, "/tmp/lf-test-input-XXXXXX");
    if (mkdtemp(dir) == NULL) {
        perror("mkdtemp");
        return 1;
    }
    write_text("a.csv", curve_text);
    write_text("c.csv", curve_text);        /* a's data under another name */
    {   /* b: another measurement (one force differs) */
        char b[sizeof curve_text + 8], *at;
        memcpy(b, curve_text, sizeof curve_text);
        at = strstr(b, "0.0,-1e-6,unload");
        t_true(at != NULL, "b.csv made");
        if (at != NULL)
            at[5] = '2';     /* -1e-6 -> -2e-6 */
        write_text("b.csv", b);
    }
    test_plan_input();
    test_curve_input();
    test_table();
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
    return t_summary();
}
