/* design_plan.c: design plans, CSV files that list the curves a lab could
 * record (layerfit design): `k,R,b,interface` and optionally
 * `name,delta_max,delta_min,points,baseline,z0,F0,segment,noise`.  Read by
 * the column code of fit plans (plan.c: units in the header or in each
 * cell, messages with the cell's place); what a design makes of the
 * candidates is fit/design.c's. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csvsplit.h"

enum { D_NAME, D_K, D_R, D_B, D_INTERFACE, D_DMAX, D_DMIN, D_POINTS, D_BASELINE,
       D_Z0, D_F0, D_SEGMENT, D_NOISE, NDCOL };

static const lf_csv_column dcols[NDCOL] = {
    [D_NAME]      = { "name", LF_Q_DIMENSIONLESS, 0, NULL },
    [D_K]         = { "k", LF_Q_DIMENSIONLESS, 1, NULL },
    [D_R]         = { "R", LF_Q_LENGTH, 1, NULL },
    [D_B]         = { "b", LF_Q_LENGTH, 1, NULL },
    [D_INTERFACE] = { "interface", LF_Q_DIMENSIONLESS, 1, NULL },
    [D_DMAX]      = { "delta_max", LF_Q_LENGTH, 0, NULL },
    [D_DMIN]      = { "delta_min", LF_Q_LENGTH, 0, NULL },
    [D_POINTS]    = { "points", LF_Q_DIMENSIONLESS, 0, NULL },
    [D_BASELINE]  = { "baseline", LF_Q_LENGTH, 0, NULL },
    [D_Z0]        = { "z0", LF_Q_DIMENSIONLESS, 0, NULL },
    [D_F0]        = { "F0", LF_Q_DIMENSIONLESS, 0, NULL },
    [D_SEGMENT]   = { "segment", LF_Q_DIMENSIONLESS, 0, NULL },
    [D_NOISE]     = { "noise", LF_Q_FORCE, 0, "give 1% or 2uN in each cell" },
};

#define DCOLUMNS_HINT "a design plan has the columns k,R,b,interface and may add " \
                      "name,delta_max,delta_min,points,baseline,z0,F0,segment,noise"

typedef struct {
    const char *name;
    lf_design_plan *plan;
    size_t cap;
    lf_csv_table t;             /* its columns */
} dplan_reader;

/* "free" (or empty) -> 1, "fixed"/"known" -> 0, else -1. */
static int
free_word(const char *t)
{
    if (t[0] == '\0' || lf_csv_ieq(t, "free"))
        return 1;
    if (lf_csv_ieq(t, "fixed") || lf_csv_ieq(t, "known"))
        return 0;
    return -1;
}

/* noise: "1%", "0.01" (fractions of the largest |force|) or "2uN". */
static int
dplan_noise(dplan_reader *rd, const lf_csv_record *r, lf_design_candidate *row, lf_error *err)
{
    long k = rd->t.col[D_NOISE];
    char text[128], buf[64];
    size_t len;
    double v;
    lf_error e;

    if (k < 0 || r->text[k][0] == '\0')
        return LF_OK;
    snprintf(text, sizeof text, "%s", r->text[k]);
    len = strlen(text);
    if (len > 1 && text[len - 1] == '%') {
        text[len - 1] = '\0';
        if (lf_csv_number(text, rd->t.decimal_comma, &v) == LF_NUM_OK && v > 0) {
            row->noise_rel = v / 100.0;
            return LF_OK;
        }
    } else if (lf_csv_number(text, rd->t.decimal_comma, &v) == LF_NUM_OK) {
        if (v > 0) {
            row->noise_rel = v;
            return LF_OK;
        }
    } else {
        lf_csv_decimal_point(text, rd->t.decimal_comma);
        if (lf_units_parse(text, LF_Q_FORCE, &v, &e) == LF_OK && v > 0) {
            row->noise_abs = v;
            return LF_OK;
        }
    }
    return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                      "noise '%s' is not a positive fraction (1%% or 0.01) or force (2uN)",
                      lf_csv_excerpt(r->text[k], buf, sizeof buf));
}

static int
dplan_row(dplan_reader *rd, const lf_csv_record *r, lf_error *err)
{
    lf_design_plan *p = rd->plan;
    lf_design_candidate *row;
    lf_segment seg;
    char buf[64];
    double pts;
    long k;
    int st;
    lf_error e;

    if ((st = lf_csv_row_cells(rd->name, r, rd->t.ncells, err)) != LF_OK)
        return st;
    if (p->n == rd->cap) {
        size_t cap = rd->cap ? 2 * rd->cap : 16;
        lf_design_candidate *rows = realloc(p->rows, cap * sizeof *rows);
        if (rows == NULL)
            return lf_fail_at(err, LF_ENOMEM, rd->name, r->line, 0, "out of memory");
        p->rows = rows;
        rd->cap = cap;
    }
    row = &p->rows[p->n];
    memset(row, 0, sizeof *row);
    row->line = r->line;
    row->noise_rel = row->noise_abs = NAN;
    k = rd->t.col[D_NAME];
    if (k >= 0 && r->text[k][0] != '\0')
        snprintf(row->name, sizeof row->name, "%s", r->text[k]);
    else
        snprintf(row->name, sizeof row->name, "row %zu", p->n + 1);
    if ((st = lf_csv_cell_interface(rd->name, r, rd->t.col[D_INTERFACE], &row->probe.base, err))
        != LF_OK)
        return st;
    if ((st = lf_csv_table_segment(&rd->t, r, D_SEGMENT, &seg, err)) != LF_OK)
        return st;
    row->branch = seg == LF_SEG_LOAD ? LF_BRANCH_LOAD : LF_BRANCH_UNLOAD;
    row->free_z0 = row->free_F0 = 1;
    if ((k = rd->t.col[D_Z0]) >= 0 && (row->free_z0 = free_word(r->text[k])) < 0)
        return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                          "z0 '%s' must be free or fixed", lf_csv_excerpt(r->text[k], buf, sizeof buf));
    if ((k = rd->t.col[D_F0]) >= 0 && (row->free_F0 = free_word(r->text[k])) < 0)
        return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                          "F0 '%s' must be free or fixed", lf_csv_excerpt(r->text[k], buf, sizeof buf));
    k = rd->t.col[D_BASELINE];
    row->baseline = 0.0;
    if (k >= 0 && (lf_csv_ieq(r->text[k], "yes") || lf_csv_ieq(r->text[k], "y")))
        row->baseline = NAN;
    else if (k >= 0 && !(r->text[k][0] == '\0' || lf_csv_ieq(r->text[k], "no")
                         || lf_csv_ieq(r->text[k], "n"))) {
        if ((st = lf_csv_table_number(&rd->t, r, D_BASELINE, 0, &row->baseline, err)) != LF_OK)
            return st;
        if (!(row->baseline >= 0))
            return lf_fail_at(err, LF_EINVAL, rd->name, r->fline[k], r->fcol[k],
                              "baseline must be yes, no or a length >= 0 (e.g. 20nm)");
    }
    if ((st = lf_csv_table_number(&rd->t, r, D_K, 0, &row->probe.k, err)) != LF_OK
        || (st = lf_csv_table_number(&rd->t, r, D_R, 0, &row->probe.R, err)) != LF_OK
        || (st = lf_csv_table_number(&rd->t, r, D_B, 0, &row->probe.b, err)) != LF_OK
        || (st = lf_csv_table_number(&rd->t, r, D_DMAX, 1, &row->delta_max, err)) != LF_OK
        || (st = lf_csv_table_number(&rd->t, r, D_DMIN, 1, &row->delta_min, err)) != LF_OK
        || (st = lf_csv_table_number(&rd->t, r, D_POINTS, 1, &pts, err)) != LF_OK
        || (st = dplan_noise(rd, r, row, err)) != LF_OK)
        return st;
    p->n++;
    if (lf_probe_check(&row->probe, &e) != LF_OK)
        return lf_fail_at(err, e.status, rd->name, r->line, 0, "%s", e.msg);
    if (!isnan(pts)) {
        k = rd->t.col[D_POINTS];
        if (!(pts >= 5 && pts <= 1e7 && pts == floor(pts)))
            return lf_fail_at(err, LF_EINVAL, rd->name, r->fline[k], r->fcol[k],
                              "points must be a whole number from 5 to 10000000");
        row->points = (size_t) pts;
    }
    if (!isnan(row->delta_min) && row->baseline != 0.0)
        return lf_fail_at(err, LF_EINVAL, rd->name, r->line, 0,
                          "give delta_min or baseline, not both (delta_min sets the whole range)");
    if (!isnan(row->delta_max) && !(row->delta_max > 0))
        return lf_fail_at(err, LF_EINVAL, rd->name, r->fline[rd->t.col[D_DMAX]],
                          r->fcol[rd->t.col[D_DMAX]], "delta_max must be > 0 (e.g. 50nm)");
    return LF_OK;
}

static int
dplan_record(void *ctx, const lf_csv_record *r, lf_error *err)
{
    dplan_reader *rd = ctx;
    return r->index == 0 ? lf_csv_table_header(&rd->t, r, err) : dplan_row(rd, r, err);
}

static int
dplan_load(const char *path, const char *buf, size_t len, const char *name,
           lf_design_plan **out, lf_error *err)
{
    dplan_reader rd;
    int st;

    *out = NULL;
    memset(&rd, 0, sizeof rd);
    rd.name = name ? name : "";
    rd.t.file = rd.name;
    rd.t.cols = dcols;
    rd.t.ncol = NDCOL;
    rd.t.hint = DCOLUMNS_HINT;
    rd.plan = calloc(1, sizeof *rd.plan);
    if (rd.plan == NULL || (rd.plan->path = lf_strdup(rd.name)) == NULL) {
        lf_design_plan_free(rd.plan);
        return lf_fail_at(err, LF_ENOMEM, rd.name, 0, 0, "out of memory");
    }
    st = lf_csv_table_load(&rd.t, path, buf, len, 0, dplan_record, &rd, &rd.plan->n,
                           "design plan", "name,k,R_mm,b_um,interface", "candidate curve", err);
    if (st != LF_OK) {
        lf_design_plan_free(rd.plan);
        return st;
    }
    *out = rd.plan;
    return LF_OK;
}

int
lf_design_plan_read(const char *path, lf_design_plan **out, lf_error *err)
{
    return dplan_load(path, NULL, 0, path, out, err);
}

int
lf_design_plan_parse(const char *buf, size_t len, const char *name, lf_design_plan **out,
                     lf_error *err)
{
    return dplan_load(NULL, buf ? buf : "", len, name, out, err);
}

void
lf_design_plan_free(lf_design_plan *p)
{
    if (p == NULL)
        return;
    free(p->rows);
    free(p->path);
    free(p);
}
