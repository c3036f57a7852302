/* batch.c: many independent fits, the engine of `layerfit fit --batch`
 * (lf_batch_run in layerfit.h).
 *
 * Every curve of the plan, or every group of curves that share a non-empty
 * `sample`, is one fit of its own.  Worker threads take the fits in plan
 * order, one at a time; each reads its curves, fits them as the command
 * does (lf_fit_request_run, LF_RUN_BATCH) and formats its own row.  A row
 * is handed to the caller as soon as it may be: in plan order (the rows
 * of later fits wait for the earlier ones, and no worker starts a fit more
 * than 128 per thread ahead of the first one not handed over), or as the
 * fits finish.  Memory is therefore bounded by that window, not by the
 * number of curves, and rows in plan order do not depend on the thread
 * count: every fit sees only its own data and the fitter keeps no global
 * state.
 *
 * A shard keeps the I-th of N contiguous shares of the fits, so that the
 * rows of shards 1..N, concatenated in order, are those of the whole plan.
 * A bad curve (a missing file included) gives a row with status "error"
 * and its message. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "internal.h"

/* Text as a CSV cell (lf_csv_cell: quoted where needed, a formula made
 * text unless raw) or as a JSON string. */
static void
sb_text(lf_str *b, const char *s, int json, int raw)
{
    if (json)
        lf_str_json(b, s);   /* valid UTF-8 whatever the bytes */
    else
        lf_csv_cell(s, raw, lf_str_put_cb, b);
}

/* ------------------------------------------------------------------------
 * The fits of a plan: units of one or more rows.
 * --------------------------------------------------------------------- */

typedef struct {
    const lf_plan *plan;
    size_t nunits;
    size_t *start;      /* unit u has items row[start[u] .. start[u+1]-1] */
    size_t *row;
    size_t nitems;      /* a curve each: a plan row, or one curve of a row */
    size_t *item_row;   /* that names a file of many without an index */
    long *item_index;
} unit_list;

typedef struct {
    const char *sample;
    size_t row;
} sample_key;

static int
cmp_sample(const void *a, const void *b)
{
    const sample_key *x = a, *y = b;
    int c = strcmp(x->sample, y->sample);
    if (c != 0)
        return c;
    return x->row < y->row ? -1 : x->row > y->row;
}

typedef struct {
    size_t first, n, at;   /* first row, rows, offset into the sorted keys */
} group;

static int
cmp_group(const void *a, const void *b)
{
    const group *x = a, *y = b;
    return x->first < y->first ? -1 : x->first > y->first;
}

/* The curves of the plan, one item each: a row, or each curve of a row
 * that names a file of many without an index (its file opened once by
 * lf_plan_open_files; the curves are not copied into rows of their own,
 * so a map of any size costs two numbers per curve here). */
static int
items_make(const lf_plan *plan, unit_list *u)
{
    size_t i, k, n = 0, w = 0;
    for (i = 0; i < plan->n; i++)
        n += plan->rows[i].source != NULL && plan->rows[i].index < 0
             ? lf_file_count(plan->rows[i].source) : 1;
    u->item_row = malloc((n ? n : 1) * sizeof *u->item_row);
    u->item_index = malloc((n ? n : 1) * sizeof *u->item_index);
    if (u->item_row == NULL || u->item_index == NULL)
        return -1;
    for (i = 0; i < plan->n; i++) {
        const lf_plan_row *r = &plan->rows[i];
        size_t m = r->source != NULL && r->index < 0 ? lf_file_count(r->source) : 0;
        if (m == 0) {
            u->item_row[w] = i;
            u->item_index[w++] = r->index;
        }
        for (k = 0; k < m; k++) {
            u->item_row[w] = i;
            u->item_index[w++] = (long) k;
        }
    }
    u->nitems = n;
    return 0;
}

/* Group the plan's curves into fits, in the order of each fit's first one:
 * a curve of a row with an empty sample alone, those of one sample
 * together. */
static int
units_make(const lf_plan *plan, unit_list *u)
{
    size_t n, i, ng = 0, k = 0;
    sample_key *key;
    group *g;

    u->plan = plan;
    if (items_make(plan, u) != 0)
        return -1;
    n = u->nitems;
    key = malloc((n ? n : 1) * sizeof *key);
    g = malloc((n ? n : 1) * sizeof *g);
    u->start = malloc((n + 1) * sizeof *u->start);
    u->row = malloc((n ? n : 1) * sizeof *u->row);
    if (key == NULL || g == NULL || u->start == NULL || u->row == NULL) {
        free(key);
        free(g);
        return -1;
    }
    for (i = 0; i < n; i++) {
        const char *sample = plan->rows[u->item_row[i]].sample;
        key[i].sample = sample ? sample : "";
        key[i].row = i;
    }
    qsort(key, n, sizeof *key, cmp_sample);
    for (i = 0; i < n; i++) {
        if (key[i].sample[0] != '\0' && ng > 0 && g[ng - 1].n > 0
            && strcmp(key[g[ng - 1].at].sample, key[i].sample) == 0) {
            g[ng - 1].n++;
            continue;
        }
        g[ng].first = key[i].row;
        g[ng].n = 1;
        g[ng].at = i;
        ng++;
    }
    qsort(g, ng, sizeof *g, cmp_group);
    for (i = 0; i < ng; i++) {
        size_t j;
        u->start[i] = k;
        for (j = 0; j < g[i].n; j++)
            u->row[k++] = key[g[i].at + j].row;
    }
    u->start[ng] = k;
    u->nunits = ng;
    free(key);
    free(g);
    return 0;
}

static void
units_free(unit_list *u)
{
    free(u->start);
    free(u->row);
    free(u->item_row);
    free(u->item_index);
}

/* ------------------------------------------------------------------------
 * One fit.
 * --------------------------------------------------------------------- */

typedef struct {
    const lf_fit_request *req;
    int json;
    int csv_raw;           /* CSV text cells as they are (no ' before =) */
    int keep;              /* rows keep their fit's result and input */
} batch_config;

/* A fit done: its row and what the caller may see of it. */
typedef struct {
    lf_str text;           /* the row, CSV or JSON line */
    int ready;             /* done, not yet handed over */
    lf_batch_outcome outcome;
    const char *status;    /* "ok", "misfit", "noconv", "error" */
    const char *sample;    /* the plan's */
    int have_res, have_in; /* res and in hold a fit (kept: cfg->keep) */
    lf_fit_result res;
    lf_fit_input in;
    char *why, *cause;     /* a failed fit: why, and its cause (cause_of) */
} unit_out;

static void
format_error(char *buf, size_t n, const lf_error *err)
{
    size_t len = 0;
    buf[0] = '\0';
    if (err->file[0] != '\0') {
        len = (size_t) snprintf(buf, n, "%s:", err->file);
        if (err->line > 0 && len < n)
            len += (size_t) snprintf(buf + len, n - len, "%ld:", err->line);
        if (err->column > 0 && len < n)
            len += (size_t) snprintf(buf + len, n - len, "%ld:", err->column);
        if (len < n)
            len += (size_t) snprintf(buf + len, n - len, " ");
    }
    if (len < n)
        snprintf(buf + len, n - len, "%s", err->msg[0] ? err->msg : lf_strerror(err->status));
}

static void
join_warnings(lf_str *b, const lf_warnings *w, int *first)
{
    size_t i;
    for (i = 0; i < w->n; i++) {
        lf_str_printf(b, "%s%s", *first ? "" : " | ", w->msg[i]);
        *first = 0;
    }
}

/* The column names, in the order put_row writes them. */
static const char *const columns[] = {
    "fit", "sample", "file", "curves", "status", "model", "x_m", "y_m",
    "w_J_m2", "w_se_J_m2", "w_upper_bound", "Estar_Pa", "Estar_se_Pa",
    "nu", "nu_se", "M_Pa", "M_se_Pa", "corr_w_Estar", "chi2_dof",
    "rms_N", "P_po_N", "iterations",
    "w_ci95_lo_J_m2", "w_ci95_hi_J_m2", "Estar_ci95_lo_Pa", "Estar_ci95_hi_Pa",
    "nu_ci95_lo", "nu_ci95_hi", "w_ci95_method", "Estar_ci95_method", "nu_ci95_method",
    "identifiability", "message", "grid_i", "grid_j", "sha256",
    /* what the first curve shows without a model (lf_observe) */
    "adhesion_force_N", "detachment_work_J", "contact_point_m", "max_indentation_m",
    "max_force_N", "instrument_Eeff_Pa", "instrument_model",
    /* what redraws a fit of one curve (`map RESULTS --report`): its probe,
     * segment, the offsets the figures draw with and a nu that was held */
    "k", "R_m", "b_m", "interface", "tip", "half_angle_rad", "B", "segment",
    "z0_m", "F0_N", "slope_N_m", "nu_held",
    /* --model auto: "group" where the curve's group of one probe and layer
     * decided its model, "curve" where its own rule did */
    "model_by", NULL
};

/* The cells of a fit of one curve that redraw it; NULL for a joint fit. */
typedef struct {
    const lf_probe *probe;
    int layer;                  /* the plan gave b and interface */
    lf_segment segment;
    double z0, F0, slope;       /* as the figures draw it (NaN: no fit) */
    double nu_held;             /* nu where the fit held it, else NaN */
} curve_cells;

/* Sum of squared residuals relative to the points, over all curves. */
static double
rms_all(const lf_fit_result *r)
{
    double ss = 0.0;
    size_t j, n = 0;
    for (j = 0; j < r->ncurves; j++) {
        ss += r->curves[j].rms * r->curves[j].rms * (double) r->curves[j].n;
        n += r->curves[j].n;
    }
    return n ? sqrt(ss / (double) n) : NAN;
}

static double
corr_w_E(const lf_fit_result *r)
{
    int iw = -1, iE = -1;
    size_t i;
    for (i = 0; i < r->npar; i++) {
        if (strcmp(r->names[i], "w") == 0)
            iw = (int) i;
        else if (strcmp(r->names[i], "E*") == 0)
            iE = (int) i;
    }
    if (iw < 0 || iE < 0)
        return NAN;
    return lf_fit_result_corr(r, (size_t) iw, (size_t) iE);
}

typedef struct {
    const char *key;
    double value;
} num_field;

/* The text columns between the numbers and identifiability. */
#define NTEXT 3
static const char *const text_keys[NTEXT] = {
    "w_ci95_method", "Estar_ci95_method", "nu_ci95_method"
};

/* How an estimate's 95% interval was found ("" for none). */
static const char *
ci_method(const lf_fit_estimate *e)
{
    const char *m = lf_interval_method(e);
    return m != NULL ? m : "";
}

/* The curves of one fit: names and SHA-256 of what was read ("" if not). */
typedef struct {
    size_t n;
    const char **name;
    char (*sha)[65];
} unit_files;

/* The file names of a joint fit in one cell: joined by ';', a name that
 * holds ';', '"' or starts or ends with a space in double quotes (quotes
 * doubled), so that the names can be told apart again. */
static void
join_names(lf_str *b, const unit_files *uf)
{
    size_t i;
    for (i = 0; i < uf->n; i++) {
        const char *p = uf->name[i];
        size_t len = strlen(p);
        lf_str_printf(b, i ? ";" : "");
        if (uf->n > 1 && (strpbrk(p, ";\"") != NULL || (len > 0 && (p[0] == ' ' || p[len - 1] == ' ')))) {
            lf_str_printf(b, "\"");
            for (; *p; p++)
                lf_str_printf(b, *p == '"' ? "\"\"" : "%c", *p);
            lf_str_printf(b, "\"");
        } else {
            lf_str_printf(b, "%s", p);
        }
    }
}

/* Write one row: key/value pairs for JSON Lines, cells for CSV. */
static void
put_row(lf_str *b, const batch_config *cfg, size_t fit_no, const char *sample,
        const char *files, const unit_files *uf, size_t ncurves, const char *status,
        const char *model, const num_field *num, size_t nnum, const char *const *text,
        const char *ident, const char *msg, const double grid[2], const lf_observables *obs,
        const curve_cells *cc, const char *model_by)
{
    int json = cfg->json;
    double ov[LF_NOBSERVED];
    size_t i;

    if (json)
        lf_str_printf(b, "{\"fit\": %zu, \"sample\": ", fit_no);
    else
        lf_str_printf(b, "%zu,", fit_no);
    sb_text(b, sample, json, cfg->csv_raw);
    lf_str_printf(b, json ? ", \"file\": " : ",");
    sb_text(b, files, json, cfg->csv_raw);
    lf_str_printf(b, json ? ", \"curves\": %zu, \"status\": " : ",%zu,", ncurves);
    sb_text(b, status, json, cfg->csv_raw);
    lf_str_printf(b, json ? ", \"model\": " : ",");
    sb_text(b, model, json, cfg->csv_raw);
    for (i = 0; i < nnum; i++) {
        lf_str_printf(b, json ? ", \"%s\": " : ",", num[i].key);
        lf_str_number(b, num[i].value, json ? "null" : "");
    }
    for (i = 0; i < NTEXT; i++) {
        lf_str_printf(b, json ? ", \"%s\": " : ",", text_keys[i]);
        sb_text(b, text[i], json, cfg->csv_raw);
    }
    lf_str_printf(b, json ? ", \"identifiability\": " : ",");
    sb_text(b, ident, json, cfg->csv_raw);
    lf_str_printf(b, json ? ", \"message\": " : ",");
    sb_text(b, msg, json, cfg->csv_raw);
    for (i = 0; i < 2; i++) {   /* the curve's place on a map's grid */
        lf_str_printf(b, json ? ", \"%s\": " : ",", i ? "grid_j" : "grid_i");
        lf_str_number(b, grid[i], json ? "null" : "");
    }
    if (json) {
        int raw = 0;
        lf_str_printf(b, ", \"files\": [");
        for (i = 0; i < uf->n; i++) {
            lf_str_printf(b, i ? ", " : "");
            lf_str_json(b, uf->name[i]);
            raw |= !lf_utf8_valid(uf->name[i]);
        }
        if (raw) {   /* the bytes of names that are not UTF-8, percent-escaped */
            lf_str_printf(b, "], \"files_raw\": [");
            for (i = 0; i < uf->n; i++) {
                lf_str_printf(b, i ? ", " : "");
                lf_percent_escape(uf->name[i], lf_str_put_cb, b);
            }
        }
        lf_str_printf(b, "], \"sha256\": [");
        for (i = 0; i < uf->n; i++)
            lf_str_printf(b, uf->sha[i][0] ? "%s\"%s\"" : "%snull", i ? ", " : "", uf->sha[i]);
        lf_str_printf(b, "]");
    } else {
        lf_str_printf(b, ",");
        for (i = 0; i < uf->n; i++)
            lf_str_printf(b, "%s%s", i ? ";" : "", uf->sha[i]);
    }
    /* the first curve's observables (as P_po_N is its pull-off) */
    for (i = 0; i < LF_NOBSERVED; i++)
        ov[i] = NAN;
    if (obs != NULL)
        lf_observed_values(obs, ov);
    for (i = 0; i < LF_NOBSERVED; i++) {
        lf_str_printf(b, json ? ", \"%s\": " : ",", lf_observed_keys[i]);
        lf_str_number(b, ov[i], json ? "null" : "");
    }
    lf_str_printf(b, json ? ", \"instrument_model\": " : ",");
    if (json && (obs == NULL || obs->instrument_model[0] == '\0'))
        lf_str_printf(b, "null");
    else
        sb_text(b, obs != NULL ? obs->instrument_model : "", json, cfg->csv_raw);
    {
        const lf_probe *p = cc != NULL ? cc->probe : NULL;
        int shaped = p != NULL && (p->tip == LF_TIP_CONE || p->tip == LF_TIP_PYRAMID);
        const num_field pn[] = {
            { "k", p ? p->k : NAN }, { "R_m", p ? p->R : NAN },
            { "b_m", p && cc->layer ? p->b : NAN }, { "interface", NAN },
            { "tip", NAN }, { "half_angle_rad", shaped ? p->angle : NAN },
            { "B", p && p->tip == LF_TIP_POWER && p->B > 0.0 ? p->B : NAN },
            { "segment", NAN }, { "z0_m", p ? cc->z0 : NAN }, { "F0_N", p ? cc->F0 : NAN },
            { "slope_N_m", p ? cc->slope : NAN }, { "nu_held", p ? cc->nu_held : NAN },
        };
        const char *tv[sizeof pn / sizeof pn[0]] = { NULL };
        tv[3] = p && cc->layer ? (p->base == LF_BASE_BONDED ? "bonded" : "frictionless") : "";
        tv[4] = p ? lf_tip_name(p->tip) : "";
        tv[7] = p ? lf_segment_name(cc->segment) : "";
        for (i = 0; i < sizeof pn / sizeof pn[0]; i++) {
            lf_str_printf(b, json ? ", \"%s\": " : ",", pn[i].key);
            if (tv[i] == NULL)
                lf_str_number(b, pn[i].value, json ? "null" : "");
            else if (json && tv[i][0] == '\0')
                lf_str_printf(b, "null");
            else
                sb_text(b, tv[i], json, cfg->csv_raw);
        }
    }
    lf_str_printf(b, json ? ", \"model_by\": " : ",");
    if (json && model_by[0] == '\0')
        lf_str_printf(b, "null");
    else
        sb_text(b, model_by, json, cfg->csv_raw);
    lf_str_printf(b, json ? "}\n" : "\n");
}

/* A failure's cause: its message with its files' names (@) and every
 * number (#) blanked out, so that the failures of one cause count
 * together; NULL when out of memory. */
static char *
cause_of(const char *why, const unit_files *uf)
{
    size_t i = 0, k = 0, j;
    char *key = malloc(strlen(why) + 1);

    if (key == NULL)
        return NULL;
    while (why[i] != '\0') {
        size_t len = 0;
        for (j = 0; j < uf->n && len == 0; j++)
            if (uf->name[j] != NULL && strncmp(why + i, uf->name[j], strlen(uf->name[j])) == 0)
                len = strlen(uf->name[j]);
        if (len > 0) {                  /* a file's name */
            key[k++] = '@';
            i += len;
        } else if (why[i] >= '0' && why[i] <= '9') {   /* a number */
            key[k++] = '#';
            while ((why[i] >= '0' && why[i] <= '9') || why[i] == '.' || why[i] == 'e'
                   || ((why[i] == '-' || why[i] == '+') && i > 0 && why[i - 1] == 'e'))
                i++;
        } else {
            key[k++] = why[i++];
        }
    }
    key[k] = '\0';
    return key;
}

/* Read, fit and format fit number u (0-based) of the plan into o: its
 * outcome LF_BATCH_FAILED when the fit failed (error or no convergence),
 * LF_BATCH_MISFIT when it converged but the model does not describe a
 * curve (status misfit), LF_BATCH_OK when it succeeded.  What goes wrong
 * is written into the row; o->text.failed when the row could not be. */
static void
fit_unit(const unit_list *ul, size_t u, const batch_config *cfg, lf_model_group *mg,
         unit_out *o)
{
    lf_str *out = &o->text;
    const lf_plan *plan = ul->plan;
    size_t first = ul->start[u], n = ul->start[u + 1] - first, j;
    lf_fit_input in;
    lf_fit_result res;
    lf_error err;
    lf_plan one = *plan;        /* the unit's curves as rows of a plan of their own */
    lf_plan_row *rows = malloc((n ? n : 1) * sizeof *rows);
    unit_files uf = { n, calloc(n, sizeof(const char *)), calloc(n, sizeof(char[65])) };
    lf_str files = { NULL, 0, 0, 0 }, ident = { NULL, 0, 0, 0 }, msg = { NULL, 0, 0, 0 };
    char ebuf[1200];
    const char *sample = plan->rows[ul->item_row[ul->row[first]]].sample;
    const char *status = "error";
    double x = NAN, y = NAN, grid[2] = { NAN, NAN };
    int st = LF_EINVAL, have_res = 0, failed = 1, firstw = 1;
    curve_cells cc;

    lf_error_clear(&err);
    o->status = status;
    o->sample = sample;
    o->outcome = LF_BATCH_FAILED;
    o->have_res = o->have_in = 0;
    if (uf.name == NULL || uf.sha == NULL || rows == NULL) {
        free(uf.name);
        free(uf.sha);
        free(rows);
        out->failed = 1;
        return;
    }
    memset(&in, 0, sizeof in);
    for (j = 0; j < n; j++) {
        /* a curve of a file of many is named FILE#N */
        size_t item = ul->row[first + j];
        const lf_plan_row *r = &rows[j];
        rows[j] = plan->rows[ul->item_row[item]];   /* shallow: the plan owns its strings */
        rows[j].index = ul->item_index[item];
        uf.name[j] = r->file;
        if (r->index >= 0) {
            size_t len = strlen(r->file) + 24;
            char *name = malloc(len);
            if (name != NULL) {
                snprintf(name, len, "%s#%ld", r->file, r->index);
                uf.name[j] = name;
            }
        }
    }
    join_names(&files, &uf);
    /* the one step from a plan to a fit's input, the one rule for nu: each
     * curve a regular file checked when it is opened, the same checks as
     * `layerfit check`; whatever goes wrong is this fit's row */
    one.n = n;
    one.rows = rows;
    if (lf_fit_input_from_plan(&one, NULL, n, &cfg->req->input, &in, NULL, &err) != LF_OK) {
        format_error(ebuf, sizeof ebuf, &err);
        goto row;
    }
    for (j = 0; j < n; j++)
        memcpy(uf.sha[j], in.sha256[j], sizeof uf.sha[j]);
    x = in.x;
    y = in.y;
    grid[0] = in.grid_i >= 0 ? (double) in.grid_i : NAN;
    grid[1] = in.grid_j >= 0 ? (double) in.grid_j : NAN;
    /* as a single fit is made, after the profile's cheap screen */
    if (mg != NULL) {       /* the model chosen with the curve's group */
        lf_fit_request rq = *cfg->req;
        rq.choose.group = mg;
        st = lf_fit_request_run(&rq, &in, LF_RUN_BATCH, &res, NULL, &err);
    } else {
        st = lf_fit_request_run(cfg->req, &in, LF_RUN_BATCH, &res, NULL, &err);
    }
    if (st == LF_OK || st == LF_ENOCONV) {
        have_res = 1;
        /* the profile may find the minimum was a local one (noconv) */
        status = st == LF_OK ? "ok" : "noconv";
        failed = st != LF_OK;
        if (!failed && lf_disagreeing(&res, ebuf, sizeof ebuf) > 0) {
            status = "misfit";      /* the report's DISAGREES: no measurement */
            failed = 2;
        }
    } else {
        format_error(ebuf, sizeof ebuf, &err);
    }
row:
    if (n == 1) {       /* a fit of one curve: what redraws it */
        lf_fit_figure fig;
        cc.probe = in.n == 1 ? &in.curves[0].probe : &rows[0].probe;
        cc.layer = in.n == 1 ? in.origin == NULL || in.origin[0].b != NULL : !isnan(rows[0].probe.b);
        cc.segment = in.n == 1 ? in.curves[0].branch : rows[0].segment;
        cc.z0 = cc.F0 = cc.slope = cc.nu_held = NAN;
        if (have_res && in.n == 1
            && lf_fit_figure_curve(&res, 0, &in.curves[0], 0, NULL, NULL, NULL, &fig, &err) == LF_OK) {
            cc.z0 = fig.z0;
            cc.F0 = fig.F0;
            cc.slope = fig.slope;
            cc.nu_held = res.nu.free ? NAN : res.nu.value;
        }
    }
    if (have_res) {
        num_field num[] = {
            { "x_m", x }, { "y_m", y },
            { "w_J_m2", res.w.value }, { "w_se_J_m2", res.w.se },
            { "w_upper_bound", res.w.upper_bound_only ? 1.0 : 0.0 },
            { "Estar_Pa", res.Estar.value }, { "Estar_se_Pa", res.Estar.se },
            { "nu", res.nu.free || res.nu.determined ? res.nu.value : NAN },
            { "nu_se", res.nu.se },
            { "M_Pa", res.M.value }, { "M_se_Pa", res.M.se },
            { "corr_w_Estar", corr_w_E(&res) },
            /* as the single fit's report: chi2 / dof (se_scale^2 also
             * holds the correlation time of the noise) */
            { "chi2_dof", res.dof > 0 ? res.chi2 / (double) res.dof : NAN },
            { "rms_N", rms_all(&res) },
            { "P_po_N", res.ncurves && res.curves[0].pulloff_determined
                        ? res.curves[0].pulloff.P_po : NAN },
            { "iterations", (double) res.iterations },
            { "w_ci95_lo_J_m2", res.w.free ? res.w.ci95[0] : NAN },
            { "w_ci95_hi_J_m2", res.w.free ? res.w.ci95[1] : NAN },
            { "Estar_ci95_lo_Pa", res.Estar.free ? res.Estar.ci95[0] : NAN },
            { "Estar_ci95_hi_Pa", res.Estar.free ? res.Estar.ci95[1] : NAN },
            { "nu_ci95_lo", res.nu.free ? res.nu.ci95[0] : NAN },
            { "nu_ci95_hi", res.nu.free ? res.nu.ci95[1] : NAN },
        };
        const char *text[NTEXT] = { ci_method(&res.w), ci_method(&res.Estar),
                                    ci_method(&res.nu) };
        firstw = 1;
        join_warnings(&ident, &res.identifiability, &firstw);
        firstw = 1;
        join_warnings(&msg, &res.warnings, &firstw);
        for (j = 0; j < res.ncurves; j++)
            join_warnings(&msg, &res.curves[j].warnings, &firstw);
        put_row(out, cfg, u + 1, sample, files.s ? files.s : "", &uf, n, status,
                res.model ? res.model : "", num,
                sizeof num / sizeof num[0], text, ident.s ? ident.s : "", msg.s ? msg.s : "",
                grid, in.n > 0 ? &in.observed[0] : NULL, n == 1 ? &cc : NULL,
                !cfg->req->model_auto || res.ncurves != 1 ? ""
                : res.curves[0].model_by_group ? "group" : "curve");
        if (failed == 1)
            o->why = lf_strdup(res.stop_reason);
        if (cfg->keep) {
            o->res = res;
            o->have_res = 1;
        } else {
            lf_fit_result_free(&res);
        }
    } else {
        num_field num[] = {
            { "x_m", x }, { "y_m", y },
            { "w_J_m2", NAN }, { "w_se_J_m2", NAN }, { "w_upper_bound", NAN },
            { "Estar_Pa", NAN }, { "Estar_se_Pa", NAN }, { "nu", NAN }, { "nu_se", NAN },
            { "M_Pa", NAN }, { "M_se_Pa", NAN }, { "corr_w_Estar", NAN },
            { "chi2_dof", NAN }, { "rms_N", NAN }, { "P_po_N", NAN }, { "iterations", NAN },
            { "w_ci95_lo_J_m2", NAN }, { "w_ci95_hi_J_m2", NAN }, { "Estar_ci95_lo_Pa", NAN },
            { "Estar_ci95_hi_Pa", NAN }, { "nu_ci95_lo", NAN }, { "nu_ci95_hi", NAN },
        };
        const char *text[NTEXT] = { "", "", "" };
        put_row(out, cfg, u + 1, sample, files.s ? files.s : "", &uf, n, status, "", num,
                sizeof num / sizeof num[0], text, "", ebuf, grid,
                in.n > 0 ? &in.observed[0] : NULL, n == 1 ? &cc : NULL, "");
        o->why = lf_strdup(ebuf);
    }
    if (cfg->keep && in.n > 0) {
        o->in = in;
        o->have_in = 1;
    } else {
        lf_fit_input_free(&in);
    }
    o->status = status;
    o->outcome = (lf_batch_outcome) failed;
    if (o->why != NULL)
        o->cause = cause_of(o->why, &uf);
    free(files.s);
    free(ident.s);
    free(msg.s);
    for (j = 0; j < n; j++)
        if (uf.name[j] != rows[j].file)
            free((char *) uf.name[j]);
    free(uf.name);
    free(uf.sha);
    free(rows);
}


/* ------------------------------------------------------------------------
 * --model auto once per probe and layer: the plan's fits of one curve
 * grouped by what shapes the model choice (the row's probe and layer, nu,
 * segment, which offsets it holds).  The fits of a group that choose by
 * their own rule and record it (lf_model_group, the rule in fit/choose.c)
 * are its first LF_GROUP_REFS, in plan order, and every GROUP_EVERY-th
 * after them; every other fit's choice is made from the LF_GROUP_REFS
 * records made last before it, where they settle it.  Which fits record,
 * and which records a fit goes by, follow from the plan alone, whatever
 * the threads or the shard (a shard first fits, without their rows, the
 * records its share needs from before it), so the rows do too.
 * --------------------------------------------------------------------- */

#define GROUP_KEY 11
#define GROUP_EVERY 16

typedef struct {
    double key[GROUP_KEY];
    size_t nunits, last;    /* its fits, the last one's index */
    size_t nref;            /* its fits that record */
    size_t *ref_unit;       /* nref: which */
    unsigned char *done;    /* nref: recorded */
    lf_group_ref *rec;      /* nref: what they recorded */
} batch_group;

typedef struct {
    size_t n, cap;
    batch_group *g;
    size_t *of;             /* per fit: its group, or SIZE_MAX */
    size_t *rank;           /* per fit: its place in its group, in plan order */
    size_t *table, tsize;   /* open addressing: group index + 1, 0 empty */
} group_list;

/* The fit of rank r records; how many of the ranks before r do. */
static int
records(size_t r)
{
    return r < LF_GROUP_REFS || r % GROUP_EVERY == 0;
}

static size_t
records_before(size_t r)
{
    return r <= LF_GROUP_REFS ? r
           : LF_GROUP_REFS + (r - 1) / GROUP_EVERY - (LF_GROUP_REFS - 1) / GROUP_EVERY;
}

static void
group_key(const lf_plan_row *r, double *key)
{
    const double v[GROUP_KEY] = {
        r->probe.k, r->probe.R, r->probe.b, (double) r->probe.base, (double) r->probe.tip,
        r->probe.angle, r->probe.B, r->nu, (double) r->segment, isnan(r->z0), isnan(r->F0)
    };
    size_t i;

    for (i = 0; i < GROUP_KEY; i++)     /* one bit pattern per value */
        key[i] = isnan(v[i]) ? -HUGE_VAL : v[i] == 0.0 ? 0.0 : v[i];
}

static size_t
key_hash(const double *key)
{
    const unsigned char *p = (const unsigned char *) key;
    size_t i, h = 14695981039346656037ULL & SIZE_MAX;

    for (i = 0; i < GROUP_KEY * sizeof *key; i++)
        h = (h ^ p[i]) * (1099511628211ULL & SIZE_MAX);
    return h;
}

static void
groups_free(group_list *gl)
{
    size_t i;

    for (i = 0; i < gl->n; i++) {
        free(gl->g[i].ref_unit);
        free(gl->g[i].done);
        free(gl->g[i].rec);
    }
    free(gl->g);
    free(gl->of);
    free(gl->rank);
    free(gl->table);
}

/* The groups of the plan's fits of one curve; -1 when out of memory. */
static int
groups_make(const unit_list *ul, group_list *gl)
{
    size_t u, i, n = ul->nunits;

    memset(gl, 0, sizeof *gl);
    for (gl->tsize = 16; gl->tsize < 2 * n; gl->tsize *= 2)
        ;
    gl->of = malloc((n ? n : 1) * sizeof *gl->of);
    gl->rank = malloc((n ? n : 1) * sizeof *gl->rank);
    gl->table = calloc(gl->tsize, sizeof *gl->table);
    if (gl->of == NULL || gl->rank == NULL || gl->table == NULL)
        return -1;
    for (u = 0; u < n; u++) {
        double key[GROUP_KEY];
        size_t h;
        batch_group *g;
        gl->of[u] = SIZE_MAX;
        if (ul->start[u + 1] - ul->start[u] != 1)
            continue;       /* a joint fit chooses its own models */
        group_key(&ul->plan->rows[ul->item_row[ul->row[ul->start[u]]]], key);
        for (h = key_hash(key) & (gl->tsize - 1); gl->table[h] != 0; h = (h + 1) & (gl->tsize - 1))
            if (memcmp(gl->g[gl->table[h] - 1].key, key, sizeof key) == 0)
                break;
        if (gl->table[h] == 0) {
            if (gl->n == gl->cap) {
                size_t cap = gl->cap ? 2 * gl->cap : 16;
                batch_group *ng = realloc(gl->g, cap * sizeof *ng);
                if (ng == NULL)
                    return -1;
                gl->g = ng;
                gl->cap = cap;
            }
            g = &gl->g[gl->n];
            memset(g, 0, sizeof *g);
            memcpy(g->key, key, sizeof key);
            gl->table[h] = ++gl->n;
        }
        g = &gl->g[gl->table[h] - 1];
        gl->of[u] = gl->table[h] - 1;
        gl->rank[u] = g->nunits++;
        g->last = u;
    }
    for (i = 0; i < gl->n; i++) {
        batch_group *g = &gl->g[i];
        if (g->nunits <= LF_GROUP_REFS)
            continue;       /* no fit of the group is decided by it */
        g->nref = records_before(g->nunits);
        g->ref_unit = malloc(g->nref * sizeof *g->ref_unit);
        g->done = calloc(g->nref, 1);
        g->rec = calloc(g->nref, sizeof *g->rec);
        if (g->ref_unit == NULL || g->done == NULL || g->rec == NULL)
            return -1;
    }
    for (u = 0; u < n; u++)
        if (gl->of[u] != SIZE_MAX && gl->g[gl->of[u]].nref > 0 && records(gl->rank[u]))
            gl->g[gl->of[u]].ref_unit[records_before(gl->rank[u])] = u;
    return 0;
}

/* The group context of fit u (into mg), or NULL when it has none; *wait:
 * the records it needs are not all made yet. */
static lf_model_group *
unit_group(group_list *gl, size_t u, lf_model_group *mg, int *wait)
{
    batch_group *g;
    size_t r, k;

    *wait = 0;
    if (gl == NULL || gl->of[u] == SIZE_MAX || gl->g[gl->of[u]].nref == 0)
        return NULL;
    g = &gl->g[gl->of[u]];
    r = gl->rank[u];
    memset(mg, 0, sizeof *mg);
    if (records(r)) {
        mg->record = &g->rec[records_before(r)];
    } else {
        k = records_before(r);      /* at least LF_GROUP_REFS */
        mg->ref = &g->rec[k - LF_GROUP_REFS];
        mg->nref = LF_GROUP_REFS;
        for (; k > records_before(r) - LF_GROUP_REFS; k--)
            *wait |= !g->done[k - 1];
    }
    return mg;
}

/* ------------------------------------------------------------------------
 * The engine.
 * --------------------------------------------------------------------- */

lf_batch_settings
lf_batch_settings_default(void)
{
    lf_batch_settings s;
    s.json = 0;
    s.threads = 0;
    s.shard_index = s.shard_count = 1;
    s.ordered = 1;
    s.results = 0;
    s.csv_raw = 0;
    return s;
}

static char csv_header[1024];

static void
make_header(void)
{
    size_t i, len = 0;

    for (i = 0; columns[i] != NULL; i++)
        len += (size_t) snprintf(csv_header + len, sizeof csv_header - len, "%s%s", i ? "," : "",
                                 columns[i]);
    snprintf(csv_header + len, sizeof csv_header - len, "\n");
}

const char *
lf_batch_csv_header(void)
{
    static pthread_once_t once = PTHREAD_ONCE_INIT;

    pthread_once(&once, make_header);
    return csv_header;
}

typedef struct {
    const unit_list *ul;
    const batch_config *cfg;
    lf_batch_fn each;
    void *ctx;
    size_t lo, hi;          /* the shard's fits */
    size_t window;          /* ordered: fits in flight ahead of `deliver` */
    int ordered;
    pthread_mutex_t lock;
    pthread_cond_t moved;   /* `deliver` moved on, or the batch stopped */
    size_t next;            /* the next fit to start */
    size_t deliver;         /* ordered: the next fit to hand over */
    unit_out *slot;         /* ordered: window slots, fit u in u % window */
    size_t done, failed, misfits;
    int stop;               /* the caller stopped it, or a row was lost */
    int status;
    lf_error err;
    group_list *gl;         /* --model auto: the fits' groups, or NULL */
} engine;

static void
unit_release(unit_out *o)
{
    if (o->have_res)
        lf_fit_result_free(&o->res);
    if (o->have_in)
        lf_fit_input_free(&o->in);
    o->have_res = o->have_in = 0;
    free(o->why);
    free(o->cause);
    o->why = o->cause = NULL;
    o->ready = 0;
    o->text.len = 0;
    o->text.failed = 0;
    if (o->text.s != NULL)
        o->text.s[0] = '\0';
}

/* Hand fit u's row to the caller (the lock held). */
static void
hand_over(engine *e, size_t u, unit_out *o)
{
    lf_batch_row row;

    if (e->stop)
        return;
    if (o->text.failed || o->text.s == NULL) {
        e->status = lf_fail(&e->err, LF_ENOMEM, "out of memory writing fit %zu", u + 1);
        e->stop = 1;
        return;
    }
    e->done++;
    e->failed += o->outcome == LF_BATCH_FAILED;
    e->misfits += o->outcome == LF_BATCH_MISFIT;
    row.fit = u + 1;
    row.sample = o->sample != NULL ? o->sample : "";
    row.status = o->status;
    row.outcome = o->outcome;
    row.text = o->text.s;
    row.len = o->text.len;
    row.result = o->have_res ? &o->res : NULL;
    row.input = o->have_in ? &o->in : NULL;
    row.why = o->why;
    row.cause = o->cause;
    row.done = e->done;
    row.total = e->hi - e->lo;
    row.failed = e->failed;
    row.misfits = e->misfits;
    if (e->each != NULL && e->each(e->ctx, &row) != 0)
        e->stop = 1;
}

static void *
worker(void *arg)
{
    engine *e = arg;
    unit_out own;
    lf_model_group mg, *mgp;
    int wait;

    memset(&own, 0, sizeof own);
    pthread_mutex_lock(&e->lock);
    for (;;) {
        size_t u;
        unit_out *o;
        if (e->stop || e->next >= e->hi)
            break;
        if (e->ordered && e->next >= e->deliver + e->window) {
            pthread_cond_wait(&e->moved, &e->lock);
            continue;
        }
        u = e->next++;
        o = e->ordered ? &e->slot[u % e->window] : &own;
        /* a fit whose group decides waits for the records it goes by (of
         * fits taken before it, in plan order) */
        while ((mgp = unit_group(e->gl, u, &mg, &wait)) != NULL && wait && !e->stop)
            pthread_cond_wait(&e->moved, &e->lock);
        pthread_mutex_unlock(&e->lock);
        /* the slot is this worker's alone until it is marked ready */
        fit_unit(e->ul, u, e->cfg, mgp, o);
        pthread_mutex_lock(&e->lock);
        if (mgp != NULL && mgp->record != NULL) {
            e->gl->g[e->gl->of[u]].done[records_before(e->gl->rank[u])] = 1;
            pthread_cond_broadcast(&e->moved);
        }
        if (!e->ordered) {
            hand_over(e, u, o);
            unit_release(o);
            continue;
        }
        o->ready = 1;
        while (e->deliver < e->hi && e->slot[e->deliver % e->window].ready) {
            unit_out *d = &e->slot[e->deliver % e->window];
            hand_over(e, e->deliver, d);
            unit_release(d);
            e->deliver++;
        }
        pthread_cond_broadcast(&e->moved);
    }
    pthread_cond_broadcast(&e->moved);
    pthread_mutex_unlock(&e->lock);
    unit_release(&own);
    lf_str_free(&own.text);
    return NULL;
}

/* A shard's share goes by records of fits before it (at most the
 * LF_GROUP_REFS made last before its first fit, in each group): made here,
 * without their rows. */
static void
pre_fit(engine *e)
{
    group_list *gl = e->gl;
    size_t i, k, r;

    for (i = 0; i < gl->n; i++) {
        batch_group *g = &gl->g[i];
        if (g->nref == 0 || g->last < e->lo)
            continue;
        for (k = 0; k < g->nref && g->ref_unit[k] < e->lo; k++)
            ;
        for (r = k > LF_GROUP_REFS ? k - LF_GROUP_REFS : 0; r < k; r++) {
            unit_out o;
            lf_model_group mg;
            int wait;
            memset(&o, 0, sizeof o);
            fit_unit(e->ul, g->ref_unit[r], e->cfg, unit_group(gl, g->ref_unit[r], &mg, &wait),
                     &o);
            unit_release(&o);
            lf_str_free(&o.text);
            g->done[r] = 1;
        }
    }
}

/* Processors to run on: the threads asked for, or one per processor. */
static size_t
thread_count(long asked)
{
    long n = asked > 0 ? asked : sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (size_t) n : 1;
}

int
lf_batch_run(lf_plan *plan, const lf_fit_request *req, const lf_batch_settings *bs,
             lf_batch_fn each, void *ctx, lf_batch_summary *sum, lf_error *err)
{
    lf_batch_settings def = lf_batch_settings_default();
    batch_config cfg;
    unit_list ul;
    group_list gl;
    engine e;
    pthread_t *tid = NULL;
    size_t nthreads, started = 0, i;
    int status;

    if (bs == NULL)
        bs = &def;
    if (sum != NULL)
        memset(sum, 0, sizeof *sum);
    if (bs->shard_count < 1 || bs->shard_index < 1 || bs->shard_index > bs->shard_count)
        return lf_fail(err, LF_EINVAL, "shard %ld of %ld: it must be I of N with 1 <= I <= N",
                       bs->shard_index, bs->shard_count);
    if (bs->threads < 0)
        return lf_fail(err, LF_EINVAL, "threads %ld: it must be 0 (one per processor) or more",
                       bs->threads);
    /* a file of many curves named without an index: each curve a fit (its
     * file opened once, its curves read from it one at a time) */
    if ((status = lf_plan_open_files(plan, req->input.read, err)) != LF_OK
        || (status = lf_plan_need_layers(plan, req->model, err)) != LF_OK)
        return status;
    memset(&ul, 0, sizeof ul);
    memset(&gl, 0, sizeof gl);
    if (units_make(plan, &ul) != 0) {
        units_free(&ul);
        return lf_fail(err, LF_ENOMEM, "out of memory");
    }
    cfg.req = req;
    cfg.json = bs->json;
    cfg.csv_raw = bs->csv_raw;
    cfg.keep = bs->results;
    memset(&e, 0, sizeof e);
    e.ul = &ul;
    e.cfg = &cfg;
    e.each = each;
    e.ctx = ctx;
    e.lo = (size_t) ((double) ul.nunits * (double) (bs->shard_index - 1) / (double) bs->shard_count);
    e.hi = (size_t) ((double) ul.nunits * (double) bs->shard_index / (double) bs->shard_count);
    e.next = e.deliver = e.lo;
    e.ordered = bs->ordered;
    nthreads = thread_count(bs->threads);
    if (nthreads > e.hi - e.lo)
        nthreads = e.hi - e.lo > 0 ? e.hi - e.lo : 1;
    /* large enough that slow fits average out across threads */
    e.window = 128 * nthreads;
    e.status = LF_OK;
    pthread_mutex_init(&e.lock, NULL);
    pthread_cond_init(&e.moved, NULL);
    if (e.ordered && (e.slot = calloc(e.window, sizeof *e.slot)) == NULL) {
        e.status = lf_fail(&e.err, LF_ENOMEM, "out of memory");
        e.stop = 1;
    }
    if (!e.stop && req->model_auto && !req->choose.each && req->choose.group == NULL) {
        if (groups_make(&ul, &gl) != 0) {
            e.status = lf_fail(&e.err, LF_ENOMEM, "out of memory");
            e.stop = 1;
        } else {
            e.gl = &gl;
            pre_fit(&e);
        }
    }
    if (!e.stop && nthreads > 1 && (tid = malloc(nthreads * sizeof *tid)) == NULL)
        nthreads = 1;
    /* the caller's thread is one of the workers */
    for (i = 1; !e.stop && i < nthreads; i++)
        if (pthread_create(&tid[started], NULL, worker, &e) == 0)
            started++;
    if (!e.stop)
        worker(&e);
    for (i = 0; i < started; i++)
        pthread_join(tid[i], NULL);
    free(tid);
    if (e.slot != NULL) {
        for (i = 0; i < e.window; i++) {
            unit_release(&e.slot[i]);
            lf_str_free(&e.slot[i].text);
        }
        free(e.slot);
    }
    pthread_cond_destroy(&e.moved);
    pthread_mutex_destroy(&e.lock);
    if (sum != NULL) {
        sum->fits = ul.nunits;
        sum->total = e.hi - e.lo;
        sum->done = e.done;
        sum->failed = e.failed;
        sum->misfits = e.misfits;
        sum->stopped = e.stop && e.status == LF_OK && e.done < e.hi - e.lo;
    }
    units_free(&ul);
    groups_free(&gl);
    if (e.status != LF_OK && err != NULL)
        *err = e.err;
    return e.status;
}

int
lf_batch_row_json(const lf_batch_row *row, const lf_fit_request *req, const char *command_line,
                  char **json, lf_error *err)
{
    const lf_fit_input *in = row->input;
    lf_provenance prov;
    lf_report_info info;
    lf_assumption assumed[16];

    *json = NULL;
    if (row->result == NULL || in == NULL)
        return lf_fail(err, LF_EINVAL, "fit %zu has no result (status %s%s)", row->fit,
                       row->status, row->result == NULL ? "" : "; rows keep results only "
                       "with lf_batch_settings.results");
    prov.command_line = command_line;
    prov.ninputs = in->n;
    prov.input = (const char *const *) in->names;
    prov.sha256 = NULL;
    info.model_request = req->model;
    info.model_tol = req->model_auto ? req->choose.tol : NAN;
    info.origin = in->origin;
    info.provenance = &prov;
    info.assumed = assumed;
    info.nassumed = lf_fit_assumptions(req, in, row->result, assumed,
                                       sizeof assumed / sizeof assumed[0]);
    info.observed = in->observed;
    info.window = in->window;
    {
        /* the digests as strings */
        const char **sha = malloc((in->n ? in->n : 1) * sizeof *sha);
        size_t i;
        int status;
        if (sha == NULL)
            return lf_fail(err, LF_ENOMEM, "out of memory");
        for (i = 0; i < in->n; i++)
            sha[i] = in->sha256[i];
        prov.sha256 = sha;
        status = lf_fit_result_json(row->result, &info, json, err);
        free((void *) sha);
        return status;
    }
}
