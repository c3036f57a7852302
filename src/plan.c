/* plan.c: fit plans, CSV files that list curves and what is known about
 * each: `file,k,R,b,interface` and optionally `nu,segment,sample,z0,F0`.
 * Dimensional values carry their unit in the header ("R_mm", "b [um]") or
 * in each cell ("1mm").  Each row is checked as it is read: the probe
 * passes lf_probe_check, nu suits the interface, and no curve and segment
 * is listed twice.  The curve files themselves are checked when they are
 * read.  The column code (lf_csv_table_*) is shared with the design plan's
 * reader (design_plan.c). */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "readers.h"

enum { P_FILE, P_K, P_R, P_B, P_INTERFACE, P_NU, P_SEGMENT, P_SAMPLE, P_Z0, P_F0, P_FORMAT,
       P_INDEX, P_TIP, P_HALF_ANGLE, P_PREFACTOR, P_DEPTH_RANGE, P_FORCE_RANGE, NPCOL };

typedef enum { TEXT, NUMBER, FREE_NUMBER } cell_kind;  /* FREE_NUMBER: empty/NaN = free */

static const lf_csv_column pcols[NPCOL] = {
    [P_FILE]      = { "file", LF_Q_DIMENSIONLESS, 1, NULL },
    [P_K]         = { "k", LF_Q_DIMENSIONLESS, 1, NULL },
    [P_R]         = { "R", LF_Q_LENGTH, 1, NULL },
    [P_B]         = { "b", LF_Q_LENGTH, 1, NULL },
    [P_INTERFACE] = { "interface", LF_Q_DIMENSIONLESS, 1, NULL },
    [P_NU]        = { "nu", LF_Q_DIMENSIONLESS, 0, NULL },
    [P_SEGMENT]   = { "segment", LF_Q_DIMENSIONLESS, 0, NULL },
    [P_SAMPLE]    = { "sample", LF_Q_DIMENSIONLESS, 0, NULL },
    [P_Z0]        = { "z0", LF_Q_LENGTH, 0, NULL },
    [P_F0]        = { "F0", LF_Q_FORCE, 0, NULL },
    [P_FORMAT]    = { "format", LF_Q_DIMENSIONLESS, 0, NULL },  /* empty: sniffed */
    [P_INDEX]     = { "index", LF_Q_DIMENSIONLESS, 0, NULL },   /* empty: the file's only
                                                                   curve, or all (batch) */
    [P_TIP]       = { "tip", LF_Q_DIMENSIONLESS, 0, NULL },     /* empty: the power law */
    [P_HALF_ANGLE] = { "half_angle", LF_Q_ANGLE, 0, NULL },
    [P_PREFACTOR] = { "prefactor", LF_Q_DIMENSIONLESS, 0, NULL }, /* B of f = B r^k, SI */
    [P_DEPTH_RANGE] = { "depth_range", LF_Q_DIMENSIONLESS, 0, NULL }, /* "LO:HI" */
    [P_FORCE_RANGE] = { "force_range", LF_Q_DIMENSIONLESS, 0, NULL },
};

/* What each column's cells hold. */
static const cell_kind pkind[NPCOL] = {
    [P_FILE] = TEXT, [P_K] = NUMBER, [P_R] = NUMBER, [P_B] = NUMBER, [P_INTERFACE] = TEXT,
    [P_NU] = FREE_NUMBER, [P_SEGMENT] = TEXT, [P_SAMPLE] = TEXT, [P_Z0] = FREE_NUMBER,
    [P_F0] = FREE_NUMBER, [P_FORMAT] = TEXT, [P_INDEX] = FREE_NUMBER, [P_TIP] = TEXT,
    [P_HALF_ANGLE] = FREE_NUMBER, [P_PREFACTOR] = FREE_NUMBER, [P_DEPTH_RANGE] = TEXT,
    [P_FORCE_RANGE] = TEXT,
};

#define COLUMNS_HINT "a plan has the columns file,k,R,b,interface and may add nu,segment," \
    "sample,z0,F0,format,index,tip,half_angle,prefactor,depth_range,force_range"

typedef struct {
    const char *name;
    const char *dir;
    lf_plan *plan;
    size_t cap;
    char **canon;             /* canonical path of each row, for duplicates */
    size_t *slot;             /* open-addressing set of rows by (canon,
                                 segment): row index + 1, 0 = empty */
    size_t nslot, nused;      /* nslot a power of two, > 2 nused */
    lf_csv_table t;           /* its columns */
} plan_reader;

/* FNV-1a over a row's canonical path and segment. */
static size_t
row_hash(const plan_reader *rd, size_t idx)
{
    const unsigned char *c = (const unsigned char *) rd->canon[idx];
    size_t h = (size_t) 2166136261u;
    for (; *c; c++)
        h = (h ^ *c) * (size_t) 16777619u;
    h = (h ^ (size_t) rd->plan->rows[idx].index) * (size_t) 16777619u;
    return (h ^ (size_t) rd->plan->rows[idx].segment) * (size_t) 16777619u;
}

/* Put row idx into rd's slot table (nslot a power of two). */
static void
slot_put(plan_reader *rd, size_t idx)
{
    size_t h = row_hash(rd, idx) & (rd->nslot - 1);
    while (rd->slot[h] != 0)
        h = (h + 1) & (rd->nslot - 1);
    rd->slot[h] = idx + 1;
}

/* 1 (and *dup) when a row before idx names the same curve and segment,
 * else 0 after adding idx to the set; -1 when out of memory.  Linear time
 * over a plan, where comparing every pair would be quadratic. */
static int
seen_before(plan_reader *rd, size_t idx, size_t *dup)
{
    const lf_plan_row *rows = rd->plan->rows;
    size_t h, i;

    if (2 * (rd->nused + 1) >= rd->nslot) {
        size_t *old = rd->slot, nold = rd->nslot;
        rd->nslot = nold ? 2 * nold : 64;
        rd->slot = calloc(rd->nslot, sizeof *rd->slot);
        if (rd->slot == NULL) {
            rd->slot = old;
            rd->nslot = nold;
            return -1;
        }
        for (i = 0; i < nold; i++)
            if (old[i] != 0)
                slot_put(rd, old[i] - 1);
        free(old);
    }
    for (h = row_hash(rd, idx) & (rd->nslot - 1); rd->slot[h] != 0; h = (h + 1) & (rd->nslot - 1)) {
        i = rd->slot[h] - 1;
        if (rows[i].segment == rows[idx].segment && rows[i].index == rows[idx].index
            && strcmp(rd->canon[i], rd->canon[idx]) == 0) {
            *dup = i;
            return 1;
        }
    }
    rd->slot[h] = idx + 1;
    rd->nused++;
    return 0;
}

/* ---- the column code of tables with a header (plan.c, design_plan.c) ---- */

int
lf_csv_table_header(lf_csv_table *t, const lf_csv_record *r, lf_error *err)
{
    t->have_header = 1;
    t->header_line = r->line;
    t->ncells = r->n;
    t->decimal_comma = r->delim == ';';
    return lf_csv_columns(t->file, r, t->cols, t->ncol, t->hint, t->col, t->factor,
                          t->has_unit, err);
}

int
lf_csv_table_number(const lf_csv_table *t, const lf_csv_record *r, int c, int empty_ok,
                    double *v, lf_error *err)
{
    long k = t->col[c];
    const char *s;

    *v = NAN;
    if (k < 0)
        return LF_OK;
    s = r->text[k];
    if (empty_ok && (s[0] == '\0' || lf_csv_ieq(s, "nan")))
        return LF_OK;
    if (s[0] == '\0')
        return lf_fail_at(err, LF_EFORMAT, t->file, r->fline[k], r->fcol[k],
                          "empty %s cell (every row needs %s)", t->cols[c].name,
                          t->cols[c].name);
    return lf_csv_cell_number(t->file, r, k, &t->cols[c], t->has_unit[c], t->factor[c],
                              t->decimal_comma, v, err);
}

int
lf_csv_table_segment(const lf_csv_table *t, const lf_csv_record *r, int c, lf_segment *seg,
                     lf_error *err)
{
    long k = t->col[c];
    char buf[64];
    int word;

    *seg = LF_SEG_UNLOAD;
    if (k < 0 || r->text[k][0] == '\0')
        return LF_OK;
    word = lf_csv_segment_word(r->text[k]);
    if (word < 0)
        return lf_fail_at(err, LF_EFORMAT, t->file, r->fline[k], r->fcol[k],
                          "unknown segment '%s' (expected unload or load)",
                          lf_csv_excerpt(r->text[k], buf, sizeof buf));
    if (word == LF_SEG_HOLD)
        return lf_fail_at(err, LF_EFORMAT, t->file, r->fline[k], r->fcol[k],
                          "segment '%s' is a hold, which is never fitted "
                          "(expected unload or load)",
                          lf_csv_excerpt(r->text[k], buf, sizeof buf));
    *seg = (lf_segment) word;
    return LF_OK;
}

int
lf_csv_table_load(const lf_csv_table *t, const char *path, const char *buf, size_t len,
                  size_t chunk, int (*record)(void *, const lf_csv_record *, lf_error *),
                  void *ctx, const size_t *nrows, const char *what, const char *example,
                  const char *row, lf_error *err)
{
    lf_csv_handler h = { 0 };   /* callbacks not set stay NULL */
    int status;

    h.ctx = ctx;
    h.record = record;
    status = buf == NULL ? lf_csv_read_file(path, &h, err)
                         : lf_csv_read_buffer(buf, len, chunk, t->file, &h, err);
    if (status == LF_OK && !t->have_header)
        status = lf_fail_at(err, LF_EFORMAT, t->file, 0, 0, "empty %s (expected a header such "
                            "as %s and one row per %s)", what, example, row);
    if (status == LF_OK && *nrows == 0)
        status = lf_fail_at(err, LF_EDATA, t->file, t->header_line, 0,
                            "header but no rows (list one %s per row below it)", row);
    return status;
}

/* ---- fit plans ------------------------------------------------------------ */

/* A numeric cell in SI: a bare number in the header's unit, or a number
 * with its own unit when the header gives none.  NaN when free. */
static int
plan_number(plan_reader *rd, const lf_csv_record *r, int c, double *v, lf_error *err)
{
    return lf_csv_table_number(&rd->t, r, c, pkind[c] == FREE_NUMBER, v, err);
}

/* The curve path of a row, against the plan's folder. */
static char *
resolve(const char *dir, const char *file)
{
    size_t nd, nf = strlen(file);
    char *p;
    if (file[0] == '/' || dir == NULL || dir[0] == '\0')
        return lf_strdup(file);
    nd = strlen(dir);
    p = malloc(nd + nf + 2);
    if (p != NULL)
        sprintf(p, "%s%s%s", dir, dir[nd - 1] == '/' ? "" : "/", file);
    return p;
}

/* Resolve and check the curve of row idx against the rows before it. */
static int
plan_file(plan_reader *rd, const lf_csv_record *r, size_t idx, lf_error *err)
{
    lf_plan_row *row = &rd->plan->rows[idx];
    long k = rd->t.col[P_FILE];
    const char *t = r->text[k];
    char buf[64], *canon;
    size_t i;

    if (t[0] == '\0')
        return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                          "empty file cell (name the curve's CSV file, relative "
                          "to the plan's folder)");
    row->file = resolve(rd->dir, t);
    if (row->file == NULL)
        return lf_fail_at(err, LF_ENOMEM, rd->name, r->line, 0, "out of memory");
    {
        /* "FILE#N": curve N of FILE (when no file has the whole name) */
        char split[4096];
        long index;
        if (lf_curve_path_split(row->file, split, sizeof split, &index) == LF_OK && index >= 0) {
            if (row->index >= 0 && row->index != index)
                return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                                  "the file cell names curve %ld, the index column %ld (give "
                                  "one)", index, row->index);
            row->file[strlen(split)] = '\0';
            row->index = index;
        }
    }
    /* whether the file exists and is a regular file is checked when it is
     * read (lf_input_open), so that a batch can report it as that curve's
     * problem and go on */
    canon = realpath(row->file, NULL);
    if (canon == NULL)
        canon = lf_strdup(row->file);
    if (canon == NULL)
        return lf_fail_at(err, LF_ENOMEM, rd->name, r->line, 0, "out of memory");
    rd->canon[idx] = canon;
    switch (seen_before(rd, idx, &i)) {
    case 1:
        return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                          "duplicate row: curve '%s' and segment %s are "
                          "listed at line %ld already (list each once)",
                          lf_csv_excerpt(t, buf, sizeof buf),
                          lf_segment_name(row->segment), rd->plan->rows[i].line);
    case -1:
        return lf_fail_at(err, LF_ENOMEM, rd->name, r->line, 0, "out of memory");
    default:
        return LF_OK;
    }
}

/* Which column a message of lf_probe_check is about: its first word. */
static long
probe_column(const plan_reader *rd, const char *msg)
{
    static const struct { const char *word; int col; } named[] = {
        { "k", P_K }, { "R", P_R }, { "b", P_B }, { "interface", P_INTERFACE },
        { "tip:", P_TIP }, { "half-angle", P_HALF_ANGLE }, { "B", P_PREFACTOR },
    };
    size_t i, n;
    for (i = 0; i < sizeof named / sizeof named[0]; i++) {
        n = strlen(named[i].word);
        if (strncmp(msg, named[i].word, n) == 0 && msg[n] == ' ')
            return rd->t.col[named[i].col];
    }
    return -1;
}

/* The row's probe shape from its tip, half_angle and prefactor cells
 * (tip empty: a power law; a half-angle alone: a cone), and the k the tip
 * implies (*k_tip, NaN for none). */
static int
plan_shape(plan_reader *rd, const lf_csv_record *r, lf_plan_row *row, double *k_tip,
           lf_error *err)
{
    long k = rd->t.col[P_TIP];
    char buf[64];
    int status, tip = LF_TIP_POWER;
    size_t i;

    *k_tip = NAN;
    if (k >= 0 && r->text[k][0] != '\0') {
        lf_csv_excerpt(r->text[k], buf, sizeof buf);
        for (i = 0; buf[i]; i++)
            buf[i] = (char) (buf[i] >= 'A' && buf[i] <= 'Z' ? buf[i] - 'A' + 'a' : buf[i]);
        if ((tip = lf_tip_find(buf, k_tip)) < 0)
            return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                              "unknown tip '%s' (paraboloid, sphere, cone, berkovich, pyramid "
                              "or power; empty: the power law of k and R)", buf);
    }
    if ((status = plan_number(rd, r, P_HALF_ANGLE, &row->probe.angle, err)) != LF_OK
        || (status = plan_number(rd, r, P_PREFACTOR, &row->probe.B, err)) != LF_OK)
        return status;
    if (!isnan(row->probe.angle) && tip == LF_TIP_POWER && isnan(*k_tip)) {
        tip = LF_TIP_CONE;        /* a half-angle alone states a cone */
        *k_tip = 1.0;
    }
    k = rd->t.col[P_HALF_ANGLE];
    if (!isnan(row->probe.angle) && tip != LF_TIP_CONE && tip != LF_TIP_PYRAMID)
        return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                          "a half-angle states a cone or a pyramid, not a %s (leave it empty)",
                          lf_tip_name((lf_tip) tip));
    if ((tip == LF_TIP_CONE || tip == LF_TIP_PYRAMID) && isnan(row->probe.angle))
        return lf_fail_at(err, LF_EFORMAT, rd->name, r->line, k >= 0 ? r->fcol[k] : 0,
                          "a %s needs its half-angle (a half_angle column, e.g. 35deg)",
                          lf_tip_name((lf_tip) tip));
    k = rd->t.col[P_PREFACTOR];
    if (!isnan(row->probe.B) && tip != LF_TIP_POWER)
        return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                          "a prefactor states a power law f = B r^k, not a %s (leave it empty)",
                          lf_tip_name((lf_tip) tip));
    row->probe.tip = (lf_tip) tip;
    if (isnan(row->probe.angle))
        row->probe.angle = 0.0;
    if (isnan(row->probe.B))
        row->probe.B = 0.0;
    return LF_OK;
}

/* A window cell ("0:500nm", "0:30%"), empty: open. */
static int
plan_range(plan_reader *rd, const lf_csv_record *r, int c, lf_quantity q, lf_range *out,
           lf_error *err)
{
    long k = rd->t.col[c];
    lf_error e;

    if (k < 0 || r->text[k][0] == '\0')
        return LF_OK;
    if (lf_range_parse(r->text[k], q, out, &e) != LF_OK)
        return lf_fail_at(err, e.status, rd->name, r->fline[k], r->fcol[k], "%s: %s",
                          pcols[c].name, e.msg);
    return LF_OK;
}

/* An R cell reading "header": the probe radius stated in the curve file's
 * header (NaN in the plan row). */
static int
R_from_header(const plan_reader *rd, const lf_csv_record *r)
{
    return rd->t.col[P_R] >= 0 && lf_csv_ieq(r->text[rd->t.col[P_R]], "header");
}

/* An empty b cell: no layer (NaN in the plan row), for half-space fits
 * only; the interface cell is then empty too. */
static int
no_layer(const plan_reader *rd, const lf_csv_record *r)
{
    return r->text[rd->t.col[P_B]][0] == '\0';
}

static int plan_row_cells(plan_reader *rd, const lf_csv_record *r, lf_error *err);

/* One row into the plan.  A row with more cells than the header whose
 * extra ones are empty is read (a trailing comma), but when it then fails,
 * the likely cause is said: a cell with an unquoted comma shifted the
 * others one column on. */
static int
plan_row(plan_reader *rd, const lf_csv_record *r, lf_error *err)
{
    int status = plan_row_cells(rd, r, err);
    size_t len;

    if (status != LF_OK && status != LF_ENOMEM && r->n > rd->t.ncells && err != NULL
        && (len = strlen(err->msg)) < sizeof err->msg)
        snprintf(err->msg + len, sizeof err->msg - len, " (this row has %zu cells where the "
                 "header has %zu: a cell that holds a comma, such as a file name, must be in "
                 "double quotes)", r->n, rd->t.ncells);
    return status;
}

static int
plan_row_cells(plan_reader *rd, const lf_csv_record *r, lf_error *err)
{
    lf_plan *p = rd->plan;
    lf_plan_row *row;
    lf_error e;
    char buf[64];
    long k;
    int status;
    double k_tip;

    if ((status = lf_csv_row_cells(rd->name, r, rd->t.ncells, err)) != LF_OK)
        return status;
    if (p->n == rd->cap) {
        size_t cap = rd->cap ? 2 * rd->cap : 16;
        lf_plan_row *rows = realloc(p->rows, cap * sizeof *rows);
        char **canon;
        if (rows == NULL)
            return lf_fail_at(err, LF_ENOMEM, rd->name, r->line, 0, "out of memory");
        p->rows = rows;
        canon = realloc(rd->canon, cap * sizeof *canon);
        if (canon == NULL)
            return lf_fail_at(err, LF_ENOMEM, rd->name, r->line, 0, "out of memory");
        rd->canon = canon;
        rd->cap = cap;
    }
    row = &p->rows[p->n];
    memset(row, 0, sizeof *row);
    rd->canon[p->n] = NULL;
    row->line = r->line;
    if ((status = lf_csv_table_segment(&rd->t, r, P_SEGMENT, &row->segment, err)) != LF_OK)
        return status;
    row->index = -1;
    row->window = lf_window_all();
    k = rd->t.col[P_INTERFACE];
    if (no_layer(rd, r) != (r->text[k][0] == '\0'))
        return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                          "b and interface go together: give both for a layer, or leave "
                          "both empty for a half-space (fit with --model halfspace)");
    if (no_layer(rd, r))
        row->probe.base = LF_BASE_FRICTIONLESS;     /* not used by a half-space */
    else if ((status = lf_csv_cell_interface(rd->name, r, k, &row->probe.base, err)) != LF_OK)
        return status;
    k = rd->t.col[P_FORMAT];
    if (k >= 0 && r->text[k][0] != '\0' && lf_reader_find(r->text[k]) == NULL) {
        char list[256];
        return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                          "unknown format '%s' (%s; or empty to detect it)",
                          lf_csv_excerpt(r->text[k], buf, sizeof buf),
                          lf_reader_names(list, sizeof list));
    }
    k = rd->t.col[P_SAMPLE];
    row->sample = lf_strdup(k >= 0 ? r->text[k] : "");
    row->format = lf_strdup(rd->t.col[P_FORMAT] >= 0 ? r->text[rd->t.col[P_FORMAT]] : "");
    p->n++;          /* from here on the row is owned by the plan */
    if (row->sample == NULL || row->format == NULL)
        return lf_fail_at(err, LF_ENOMEM, rd->name, r->line, 0, "out of memory");
    if ((status = plan_shape(rd, r, row, &k_tip, err)) != LF_OK
        || (status = plan_range(rd, r, P_DEPTH_RANGE, LF_Q_LENGTH, &row->window.depth,
                                err)) != LF_OK
        || (status = plan_range(rd, r, P_FORCE_RANGE, LF_Q_FORCE, &row->window.force,
                                err)) != LF_OK)
        return status;
    k = rd->t.col[P_K];
    if (isnan(k_tip) || r->text[k][0] != '\0')
        status = plan_number(rd, r, P_K, &row->probe.k, err);
    else
        row->probe.k = k_tip;     /* a cone's or a sphere's k, implied */
    if (status == LF_OK && !isnan(k_tip) && row->probe.k != k_tip)
        return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                          "k %g, but a %s is k = %g (leave k empty)", row->probe.k,
                          lf_tip_name(row->probe.tip), k_tip);
    k = rd->t.col[P_R];
    if (status == LF_OK && !lf_probe_uses_R(&row->probe)) {
        /* a cone, a pyramid or a stated prefactor: R is not used */
        if (r->text[k][0] != '\0')
            return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                              "R does not shape a %s: leave R empty",
                              row->probe.tip == LF_TIP_POWER ? "probe stated by its prefactor"
                                                             : lf_tip_name(row->probe.tip));
        row->probe.R = NAN;
    }
    if (status != LF_OK
        || (lf_probe_uses_R(&row->probe) && !R_from_header(rd, r)
            && (status = plan_number(rd, r, P_R, &row->probe.R, err)) != LF_OK)
        || (!no_layer(rd, r)
            && (status = plan_number(rd, r, P_B, &row->probe.b, err)) != LF_OK)
        || (status = plan_number(rd, r, P_NU, &row->nu, err)) != LF_OK
        || (status = plan_number(rd, r, P_Z0, &row->z0, err)) != LF_OK
        || (status = plan_number(rd, r, P_F0, &row->F0, err)) != LF_OK)
        return status;
    if (rd->t.col[P_INDEX] >= 0) {
        double v;
        k = rd->t.col[P_INDEX];
        if ((status = plan_number(rd, r, P_INDEX, &v, err)) != LF_OK)
            return status;
        if (!isnan(v) && !(v >= 0 && v < 1e9 && v == floor(v)))
            return lf_fail_at(err, LF_EFORMAT, rd->name, r->fline[k], r->fcol[k],
                              "index must be a whole number >= 0 (the curve's place in its "
                              "file, from 0), or empty");
        if (!isnan(v))
            row->index = (long) v;
    }
    if (R_from_header(rd, r) && lf_probe_uses_R(&row->probe))
        row->probe.R = 1.0;        /* checked with the curve's R by the fit */
    if (no_layer(rd, r))
        row->probe.b = 1.0;
    status = lf_probe_check(&row->probe, &e);
    if (R_from_header(rd, r) && lf_probe_uses_R(&row->probe))
        row->probe.R = NAN;
    if (no_layer(rd, r))
        row->probe.b = NAN;
    if (status != LF_OK) {
        k = probe_column(rd, e.msg);
        return lf_fail_at(err, e.status, rd->name, r->line, k >= 0 ? r->fcol[k] : 0,
                          "%s", e.msg);
    }
    if (!isnan(row->nu)) {
        lf_material m = { 0.0, 1.0, row->nu };
        k = rd->t.col[P_NU];
        if (lf_material_check(&m, row->probe.base, &e) != LF_OK)
            return lf_fail_at(err, e.status, rd->name, r->fline[k], r->fcol[k],
                              "%s (leave nu empty to fit it)", e.msg);
        if (!(row->nu > -1.0 && row->nu <= 0.5))
            return lf_fail_at(err, LF_EINVAL, rd->name, r->fline[k], r->fcol[k],
                              "nu must lie in (-1, 0.5] (got %g)", row->nu);
    }
    return plan_file(rd, r, p->n - 1, err);
}

static int
plan_record(void *ctx, const lf_csv_record *r, lf_error *err)
{
    plan_reader *rd = ctx;
    return r->index == 0 ? lf_csv_table_header(&rd->t, r, err) : plan_row(rd, r, err);
}

static int
plan_load(const char *path, const char *buf, size_t len, size_t chunk,
          const char *name, const char *dir, lf_plan **out, lf_warnings *warn,
          lf_error *err)
{
    plan_reader rd;
    int status;
    size_t i;

    (void) warn;   /* no warnings yet: plan comments are the user's notes */
    *out = NULL;
    memset(&rd, 0, sizeof rd);
    rd.name = name ? name : "";
    rd.dir = dir;
    rd.t.file = rd.name;
    rd.t.cols = pcols;
    rd.t.ncol = NPCOL;
    rd.t.hint = COLUMNS_HINT;
    rd.plan = calloc(1, sizeof *rd.plan);
    if (rd.plan == NULL || (rd.plan->path = lf_strdup(rd.name)) == NULL) {
        lf_plan_free(rd.plan);
        return lf_fail_at(err, LF_ENOMEM, rd.name, 0, 0, "out of memory");
    }
    status = lf_csv_table_load(&rd.t, path, buf, len, chunk, plan_record, &rd, &rd.plan->n,
                               "plan", "file,k,R_mm,b_um,interface", "curve", err);
    for (i = 0; i < rd.plan->n; i++)
        free(rd.canon[i]);
    free(rd.canon);
    free(rd.slot);
    if (status != LF_OK) {
        lf_plan_free(rd.plan);
        return status;
    }
    *out = rd.plan;
    return LF_OK;
}

int
lf_plan_parse(const char *buf, size_t len, size_t chunk, const char *name,
              const char *dir, lf_plan **out, lf_warnings *warn, lf_error *err)
{
    return plan_load(NULL, buf ? buf : "", len, chunk, name, dir, out, warn, err);
}

int
lf_plan_read(const char *path, lf_plan **out, lf_warnings *warn, lf_error *err)
{
    const char *slash = strrchr(path, '/');
    char *dir = NULL;
    int status;

    if (slash != NULL) {
        size_t n = (size_t) (slash - path);
        dir = malloc(n + 2);
        if (dir == NULL)
            return lf_fail_at(err, LF_ENOMEM, path, 0, 0, "out of memory");
        memcpy(dir, path, n);
        dir[n] = '\0';
        if (n == 0)
            strcpy(dir, "/");
    }
    status = plan_load(path, NULL, 0, 0, path, dir, out, warn, err);
    free(dir);
    return status;
}

void
lf_plan_free(lf_plan *p)
{
    size_t i;
    if (p == NULL)
        return;
    for (i = 0; i < p->n; i++) {
        free(p->rows[i].file);
        free(p->rows[i].sample);
        free(p->rows[i].format);
    }
    for (i = 0; i < p->nfiles; i++)
        lf_file_close(p->files[i]);
    free(p->files);
    free(p->rows);
    free(p->path);
    free(p);
}

/* lf_file_kind_parse: for a CSV (not an instrument export), the header
 * alone decides: a "file" column makes it a plan. */
static int
kind_record(void *ctx, const lf_csv_record *r, lf_error *err)
{
    char name[256], unit[256];
    size_t i;
    (void) err;
    for (i = 0; i < r->n; i++) {
        lf_csv_header_cell(r->text[i], name, sizeof name, unit, sizeof unit);
        if (lf_csv_ieq(name, "file"))
            *(lf_file_kind *) ctx = LF_FILE_PLAN;
    }
    return LF_CSV_STOP;
}

int
lf_file_kind_parse(const char *buf, size_t len, const char *name, lf_file_kind *kind,
                   lf_error *err)
{
    lf_csv_handler h = { 0 };   /* callbacks not set stay NULL */
    *kind = LF_FILE_CURVE;
    buf = buf ? buf : "";
    /* an instrument's export is a curve, whatever its first line holds;
     * so is binary data (the curve readers say what it is) */
    if (strcmp(lf_reader_sniff(buf, len < LF_SNIFF_BYTES ? len : LF_SNIFF_BYTES)->name,
               "csv") != 0)
        return LF_OK;
    {
        char what[1024];
        lf_src src;
        src.mem = (const unsigned char *) buf;
        src.fd = -1;
        src.size = len;
        src.name = name;
        if (lf_describe_binary(&src, buf, len < LF_SNIFF_BYTES ? len : LF_SNIFF_BYTES, what,
                               sizeof what))
            return LF_OK;
    }
    h.ctx = kind;
    h.record = kind_record;
    return lf_csv_read_buffer(buf, len, 0, name, &h, err);
}

int
lf_file_kind_of(const char *path, lf_file_kind *kind, lf_error *err)
{
    lf_input in;
    int status;

    *kind = LF_FILE_CURVE;
    /* a binary file of many curves is a curve file: not read whole */
    if (lf_file_sniff_multi(path, NULL))
        return LF_OK;
    if ((status = lf_input_read(path, LF_INPUT_TEXT, &in, err)) != LF_OK)
        return status;
    status = lf_file_kind_parse(in.data, in.len, path, kind, err);
    lf_input_free(&in);
    return status;
}

/* ---------------------------------------------------------------------- */

int
lf_plan_of_files(size_t n, const char *const *paths, const lf_probe *probe, lf_segment seg,
                 lf_plan **out, lf_error *err)
{
    char split[4096];
    lf_plan *p;
    size_t i;

    *out = NULL;
    if (n == 0)
        return lf_fail(err, LF_EINVAL, "no curve files");
    p = calloc(1, sizeof *p);
    if (p == NULL || (p->path = lf_strdup(paths[0])) == NULL
        || (p->rows = calloc(n, sizeof *p->rows)) == NULL) {
        lf_plan_free(p);
        return lf_fail_at(err, LF_ENOMEM, paths[0], 0, 0, "out of memory");
    }
    for (i = 0; i < n; i++) {
        lf_plan_row *row = &p->rows[i];
        long index;
        if (lf_curve_path_split(paths[i], split, sizeof split, &index) != LF_OK) {
            lf_plan_free(p);
            return lf_fail_at(err, LF_EINVAL, paths[i], 0, 0, "path too long");
        }
        row->file = lf_strdup(split);
        row->sample = lf_strdup("");
        row->format = lf_strdup("");
        p->n = i + 1;
        if (row->file == NULL || row->sample == NULL || row->format == NULL) {
            lf_plan_free(p);
            return lf_fail_at(err, LF_ENOMEM, paths[i], 0, 0, "out of memory");
        }
        row->line = 0;
        row->probe = *probe;
        row->nu = row->z0 = row->F0 = NAN;
        row->segment = seg;
        row->index = index;
        row->window = lf_window_all();
    }
    p->of_files = 1;
    *out = p;
    return LF_OK;
}

int
lf_plan_of_file(const char *path, const lf_probe *probe, lf_segment seg, lf_plan **out,
                lf_error *err)
{
    return lf_plan_of_files(1, &path, probe, seg, out, err);
}

/* The open file of path among the plan's, or NULL. */
static lf_file *
plan_file_open(const lf_plan *plan, const char *path, const char *format)
{
    size_t i;
    for (i = 0; i < plan->nfiles; i++)
        if (strcmp(plan->files[i]->path, path) == 0
            && (format[0] == '\0' || strcmp(lf_file_format(plan->files[i]), format) == 0))
            return plan->files[i];
    return NULL;
}

/* A copy of row r as curve index of its file (strings duplicated). */
static int
row_copy(lf_plan_row *to, const lf_plan_row *r, long index, lf_file *source)
{
    *to = *r;
    to->index = index;
    to->source = source;
    to->file = lf_strdup(r->file);
    to->sample = lf_strdup(r->sample);
    to->format = lf_strdup(r->format);
    return to->file && to->sample && to->format ? LF_OK : LF_ENOMEM;
}

int
lf_plan_open_files(lf_plan *plan, const lf_read_opts *o, lf_error *err)
{
    size_t i;

    /* open each file of many curves once */
    for (i = 0; i < plan->n; i++) {
        lf_plan_row *r = &plan->rows[i];
        lf_read_opts ro;
        lf_file *f;
        lf_file **files;
        lf_error e;
        if (o != NULL)
            ro = *o;
        else
            lf_read_opts_default(&ro);
        if (ro.format == NULL && r->format[0] != '\0')
            ro.format = r->format;
        if (r->source != NULL || r->text_export)
            continue;           /* open already (here before, or the caller's), or text */
        if ((f = plan_file_open(plan, r->file, r->format)) == NULL) {
            if (!lf_file_sniff_multi(r->file, ro.format)) {
                r->text_export = 1;     /* or unreadable: the fit of the row says so */
                continue;
            }
            if (lf_file_open(r->file, 0, &ro, &f, NULL, &e) != LF_OK)
                continue;       /* the fit of the row says what is wrong */
            files = realloc(plan->files, (plan->nfiles + 1) * sizeof *files);
            if (files == NULL) {
                lf_file_close(f);
                return lf_fail(err, LF_ENOMEM, "out of memory");
            }
            plan->files = files;
            plan->files[plan->nfiles++] = f;
        }
        r->source = f;
    }
    return LF_OK;
}

int
lf_plan_expand(lf_plan *plan, const lf_read_opts *o, lf_error *err)
{
    lf_plan_row *rows;
    size_t i, total = 0, w = 0;
    int status;

    if ((status = lf_plan_open_files(plan, o, err)) != LF_OK)
        return status;
    for (i = 0; i < plan->n; i++)
        total += plan->rows[i].source != NULL && plan->rows[i].index < 0
                 ? lf_file_count(plan->rows[i].source) : 1;
    if (total == plan->n)
        return LF_OK;
    if ((rows = calloc(total, sizeof *rows)) == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory");
    /* the copies first: on failure the plan is left as it was */
    for (i = 0; i < plan->n; i++) {
        lf_plan_row *r = &plan->rows[i];
        size_t k, n = r->source != NULL && r->index < 0 ? lf_file_count(r->source) : 0;
        if (n == 0) {
            rows[w++] = *r;
            continue;
        }
        for (k = 0; k < n; k++, w++)
            if (row_copy(&rows[w], r, (long) k, r->source) != LF_OK) {
                size_t j, at = 0;
                for (j = 0, w++; j < plan->n; j++) {
                    size_t m = plan->rows[j].source != NULL && plan->rows[j].index < 0
                               ? lf_file_count(plan->rows[j].source) : 0;
                    if (m == 0) {
                        at++;
                        continue;
                    }
                    for (; m > 0 && at < w; m--, at++) {
                        free(rows[at].file);
                        free(rows[at].sample);
                        free(rows[at].format);
                    }
                }
                free(rows);
                return lf_fail(err, LF_ENOMEM, "out of memory");
            }
    }
    for (i = 0; i < plan->n; i++)
        if (plan->rows[i].source != NULL && plan->rows[i].index < 0) {
            free(plan->rows[i].file);
            free(plan->rows[i].sample);
            free(plan->rows[i].format);
        }
    free(plan->rows);
    plan->rows = rows;
    plan->n = total;
    return LF_OK;
}
