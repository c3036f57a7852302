/* cli/batch.c: `layerfit fit --batch PLAN.csv`, many independent fits.
 *
 * Every curve of the plan, or every group of curves that share a non-empty
 * `sample`, is one fit of its own.  The fits run in parallel with OpenMP and
 * stream: the plan is cut into blocks of 128 fits per thread; a block is
 * read and fitted in parallel, each fit formats its own output row, and the
 * rows are written in plan order before the next block starts.  Memory is
 * therefore bounded by the block (the number of threads), not by the number
 * of curves, and the output does not depend on the thread count: every fit
 * sees only its own data and the fitter keeps no global state.
 *
 * `--shard I/N` keeps the I-th of N contiguous shares of the fits, so that
 * the outputs of shards 1..N, concatenated in order (one CSV header kept),
 * are the output of the whole plan.  A bad curve (a missing file
 * included) gives a row with status "error" and its message; the exit
 * status is 3 when any fit failed. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>
#include <unistd.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "cli.h"

/* ------------------------------------------------------------------------
 * A growable string, for one output row.
 * --------------------------------------------------------------------- */

typedef struct {
    char *s;
    size_t len, cap;
    int failed;        /* an allocation failed: the row is lost */
} sbuf;

static void sb_printf(sbuf *b, const char *fmt, ...) CLI_PRINTF(2, 3);

static void
sb_printf(sbuf *b, const char *fmt, ...)
{
    va_list ap;
    int need;

    if (b->failed)
        return;
    for (;;) {
        size_t room = b->cap - b->len;
        va_start(ap, fmt);
        need = vsnprintf(b->s ? b->s + b->len : NULL, room, fmt, ap);
        va_end(ap);
        if (need < 0) {
            b->failed = 1;
            return;
        }
        if ((size_t) need < room) {
            b->len += (size_t) need;
            return;
        }
        {
            size_t cap = b->cap ? b->cap : 256;
            char *s;
            while (cap <= b->len + (size_t) need)
                cap *= 2;
            s = realloc(b->s, cap);
            if (s == NULL) {
                b->failed = 1;
                return;
            }
            b->s = s;
            b->cap = cap;
        }
    }
}

/* A number that reads back exactly; NaN and Inf as an empty CSV cell or a
 * JSON null (JSON has no Inf). */
static void
sb_number(sbuf *b, double x, int json)
{
    char buf[40];
    if (!isfinite(x)) {
        sb_printf(b, "%s", json ? "null" : "");
        return;
    }
    snprintf(buf, sizeof buf, "%.15g", x);
    if (strtod(buf, NULL) != x)
        snprintf(buf, sizeof buf, "%.17g", x);
    sb_printf(b, "%s", buf);
}

static void
sb_put(void *ctx, const char *s, size_t n)
{
    sb_printf((sbuf *) ctx, "%.*s", (int) n, s);
}

/* Text as a CSV cell (cli_csv_cell: quoted where needed, a formula made
 * text) or as a JSON string. */
static void
sb_text(sbuf *b, const char *s, int json)
{
    if (json)
        cli_json_escape(s, sb_put, b);   /* valid UTF-8 whatever the bytes */
    else
        cli_csv_cell(s, sb_put, b);
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
    const lf_fit_settings *settings;
    const lf_choose_settings *choose;
    const lf_input_settings *input;
    int json;
    int auto_model;        /* lf_fit_choose_driver instead of lf_fit_driver */
    int linear_only;       /* --intervals linear: no profile-likelihood check */
    cli_page_store *page;  /* --report: each fit's curves, by its place in
                              the output (u - first), or NULL */
    size_t first;
} batch_config;

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
join_warnings(sbuf *b, const lf_warnings *w, int *first)
{
    size_t i;
    for (i = 0; i < w->n; i++) {
        sb_printf(b, "%s%s", *first ? "" : " | ", w->msg[i]);
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
    "identifiability", "message", "grid_i", "grid_j", "sha256", NULL
};

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
    if (iw < 0 || iE < 0 || r->corr == NULL)
        return NAN;
    return r->corr[(size_t) iw * r->npar + (size_t) iE];
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
    const char *m = cli_interval_method(e);
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
join_names(sbuf *b, const unit_files *uf)
{
    size_t i;
    for (i = 0; i < uf->n; i++) {
        const char *p = uf->name[i];
        size_t len = strlen(p);
        sb_printf(b, i ? ";" : "");
        if (uf->n > 1 && (strpbrk(p, ";\"") != NULL || (len > 0 && (p[0] == ' ' || p[len - 1] == ' ')))) {
            sb_printf(b, "\"");
            for (; *p; p++)
                sb_printf(b, *p == '"' ? "\"\"" : "%c", *p);
            sb_printf(b, "\"");
        } else {
            sb_printf(b, "%s", p);
        }
    }
}

/* Write one row: key/value pairs for JSON Lines, cells for CSV. */
static void
put_row(sbuf *b, const batch_config *cfg, size_t fit_no, const char *sample,
        const char *files, const unit_files *uf, size_t ncurves, const char *status,
        const char *model, const num_field *num, size_t nnum, const char *const *text,
        const char *ident, const char *msg, const double grid[2])
{
    int json = cfg->json;
    size_t i;

    if (json)
        sb_printf(b, "{\"fit\": %zu, \"sample\": ", fit_no);
    else
        sb_printf(b, "%zu,", fit_no);
    sb_text(b, sample, json);
    sb_printf(b, json ? ", \"file\": " : ",");
    sb_text(b, files, json);
    sb_printf(b, json ? ", \"curves\": %zu, \"status\": " : ",%zu,", ncurves);
    sb_text(b, status, json);
    sb_printf(b, json ? ", \"model\": " : ",");
    sb_text(b, model, json);
    for (i = 0; i < nnum; i++) {
        sb_printf(b, json ? ", \"%s\": " : ",", num[i].key);
        sb_number(b, num[i].value, json);
    }
    for (i = 0; i < NTEXT; i++) {
        sb_printf(b, json ? ", \"%s\": " : ",", text_keys[i]);
        sb_text(b, text[i], json);
    }
    sb_printf(b, json ? ", \"identifiability\": " : ",");
    sb_text(b, ident, json);
    sb_printf(b, json ? ", \"message\": " : ",");
    sb_text(b, msg, json);
    for (i = 0; i < 2; i++) {   /* the curve's place on a map's grid */
        sb_printf(b, json ? ", \"%s\": " : ",", i ? "grid_j" : "grid_i");
        sb_number(b, grid[i], json);
    }
    if (json) {
        int raw = 0;
        sb_printf(b, ", \"files\": [");
        for (i = 0; i < uf->n; i++) {
            sb_printf(b, i ? ", " : "");
            cli_json_escape(uf->name[i], sb_put, b);
            raw |= !cli_utf8_valid(uf->name[i]);
        }
        if (raw) {   /* the bytes of names that are not UTF-8, percent-escaped */
            sb_printf(b, "], \"files_raw\": [");
            for (i = 0; i < uf->n; i++) {
                sb_printf(b, i ? ", " : "");
                cli_percent_escape(uf->name[i], sb_put, b);
            }
        }
        sb_printf(b, "], \"sha256\": [");
        for (i = 0; i < uf->n; i++)
            sb_printf(b, uf->sha[i][0] ? "%s\"%s\"" : "%snull", i ? ", " : "", uf->sha[i]);
        sb_printf(b, "]}\n");
    } else {
        sb_printf(b, ",");
        for (i = 0; i < uf->n; i++)
            sb_printf(b, "%s%s", i ? ";" : "", uf->sha[i]);
        sb_printf(b, "\n");
    }
}

/* Read, fit and format fit number u (0-based) of the plan.  Returns 1 when
 * the fit failed (error or no convergence), 2 when it converged but the
 * model does not describe a curve (status misfit), 0 when it succeeded.
 * Never exits: what goes wrong is written into the row. */
static int
fit_unit(const unit_list *ul, size_t u, const batch_config *cfg, sbuf *out)
{
    const lf_plan *plan = ul->plan;
    size_t first = ul->start[u], n = ul->start[u + 1] - first, j;
    lf_fit_input in;
    lf_fit_settings s = *cfg->settings;
    lf_fit_result res;
    lf_error err;
    lf_plan one = *plan;        /* the unit's curves as rows of a plan of their own */
    lf_plan_row *rows = malloc((n ? n : 1) * sizeof *rows);
    unit_files uf = { n, calloc(n, sizeof(const char *)), calloc(n, sizeof(char[65])) };
    sbuf files = { NULL, 0, 0, 0 }, ident = { NULL, 0, 0, 0 }, msg = { NULL, 0, 0, 0 };
    char ebuf[1200];
    const char *sample = plan->rows[ul->item_row[ul->row[first]]].sample;
    const char *status = "error";
    double x = NAN, y = NAN, grid[2] = { NAN, NAN };
    int st = LF_EINVAL, have_res = 0, failed = 1, firstw = 1;

    lf_error_clear(&err);
    if (uf.name == NULL || uf.sha == NULL || rows == NULL) {
        free(uf.name);
        free(uf.sha);
        free(rows);
        out->failed = 1;
        return 1;
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
    if (lf_fit_input_from_plan(&one, NULL, n, cfg->input, &in, NULL, &err) != LF_OK) {
        format_error(ebuf, sizeof ebuf, &err);
        goto row;
    }
    for (j = 0; j < n; j++)
        memcpy(uf.sha[j], in.sha256[j], sizeof uf.sha[j]);
    x = in.x;
    y = in.y;
    grid[0] = in.grid_i >= 0 ? (double) in.grid_i : NAN;
    grid[1] = in.grid_j >= 0 ? (double) in.grid_j : NAN;
    lf_fit_input_apply_nu(&in, &s);
    if (cfg->auto_model)
        st = lf_fit_choose_driver(&s, cfg->choose, n, in.curves, &res, &err);
    else
        st = lf_fit_driver(&s, n, in.curves, &res, &err);
    if (st == LF_OK || st == LF_ENOCONV) {
        /* profile-likelihood intervals where the linear ones are unreliable,
         * as a single fit makes them, after the cheap screen (a failure keeps
         * the linear ones) */
        lf_error perr;
        (void) lf_fit_profile(&s, n, in.curves, &res,
                              cfg->linear_only ? LF_PROFILE_LINEAR : LF_PROFILE_SCREEN, &perr);
        have_res = 1;
        /* the profile may find the minimum was a local one (res no longer
         * converged) */
        status = st == LF_OK && res.converged ? "ok" : "noconv";
        failed = !(st == LF_OK && res.converged);
        if (!failed && cli_disagreeing(&res, ebuf, sizeof ebuf) > 0) {
            status = "misfit";      /* the report's DISAGREES: no measurement */
            failed = 2;
        }
    } else {
        format_error(ebuf, sizeof ebuf, &err);
    }
row:
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
        cli_page_store_fit(cfg->page, u - cfg->first, n, in.curves, rows, &res);
        put_row(out, cfg, u + 1, sample, files.s ? files.s : "", &uf, n, status,
                res.model ? res.model : "", num,
                sizeof num / sizeof num[0], text, ident.s ? ident.s : "", msg.s ? msg.s : "",
                grid);
        lf_fit_result_free(&res);
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
        cli_page_store_fit(cfg->page, u - cfg->first, n, NULL, rows, NULL);
        put_row(out, cfg, u + 1, sample, files.s ? files.s : "", &uf, n, status, "", num,
                sizeof num / sizeof num[0], text, "", ebuf, grid);
    }
    lf_fit_input_free(&in);
    free(files.s);
    free(ident.s);
    free(msg.s);
    for (j = 0; j < n; j++)
        if (uf.name[j] != rows[j].file)
            free((char *) uf.name[j]);
    free(uf.name);
    free(uf.sha);
    free(rows);
    return failed;
}

/* ------------------------------------------------------------------------
 * Progress on a terminal.
 * --------------------------------------------------------------------- */

static void
progress_show(size_t done, size_t total, size_t failed, double t0, int final)
{
    enum { WIDTH = 30 };
    char bar[WIDTH + 1];
    double el = cli_now() - t0, rate = el > 0 ? (double) done / el : 0.0;
    double left = rate > 0 ? (double) (total - done) / rate : 0.0;
    size_t i, fill = total ? done * WIDTH / total : WIDTH;

    for (i = 0; i < WIDTH; i++)
        bar[i] = i < fill ? '#' : '.';
    bar[WIDTH] = '\0';
    fprintf(stderr, "\r[%s] %zu/%zu fits, %zu failed, %.0f fits/s, %s %d:%02d ",
            bar, done, total, failed, rate, final ? "took" : "left",
            (int) ((final ? el : left) / 60), (int) fmod(final ? el : left, 60.0));
    if (final)
        fputc('\n', stderr);
    fflush(stderr);
}

/* ------------------------------------------------------------------------
 * The command.
 * --------------------------------------------------------------------- */

int
cli_shard_parse(const char *text, long *index, long *count)
{
    char *end;
    long i, n;
    errno = 0;
    i = strtol(text, &end, 10);
    if (end == text || *end != '/' || errno == ERANGE)
        return -1;
    text = end + 1;
    n = strtol(text, &end, 10);
    if (end == text || *end != '\0' || errno == ERANGE)
        return -1;
    if (n < 1 || i < 1 || i > n)
        return -1;
    *index = i;
    *count = n;
    return 0;
}

static int
ends_with(const char *s, const char *suffix)
{
    size_t a = strlen(s), b = strlen(suffix);
    return a >= b && strcmp(s + a - b, suffix) == 0;
}

int
cli_batch_run(const cli_batch_opts *o, const lf_fit_settings *settings)
{
    lf_plan *plan = NULL;
    unit_list ul;
    batch_config cfg;
    cli_out atomic;
    char msg[4400];
    FILE *out = stdout;
    sbuf *rows;
    size_t lo, hi, u, block, total, done = 0, failed = 0, misfits = 0, i;
    long shard_i = 1, shard_n = 1, threads = o->threads;
    int progress, io_error = 0;
    double t0 = cli_now(), last = 0.0;

    cfg.settings = settings;
    cfg.choose = &o->choose;
    cfg.input = &o->input;
    cfg.json = 0;
    cfg.auto_model = o->auto_model;
    cfg.linear_only = o->linear_only;
    cfg.page = NULL;
    if (o->report != NULL && (o->out == NULL || !ends_with(o->out, ".csv")))
        cli_die(CLI_EXIT_USAGE, "fit: --report %s: the page is made from the results; give them "
                "as --out FILE.csv", o->report);
    if (o->out != NULL) {
        if (ends_with(o->out, ".jsonl"))
            cfg.json = 1;
        else if (!ends_with(o->out, ".csv"))
            cli_die(CLI_EXIT_USAGE, "fit: --out %s: the batch output must end in .csv or .jsonl",
                    o->out);
    }
    if (o->shard != NULL && cli_shard_parse(o->shard, &shard_i, &shard_n) != 0)
        cli_die(CLI_EXIT_USAGE, "fit: --shard '%s' is not I/N with 1 <= I <= N (e.g. --shard 3/8)",
                o->shard);
    if (threads != 0 && (threads < 1 || threads > CLI_MAX_THREADS))
        cli_die(CLI_EXIT_USAGE, "fit: --threads must be 1..%d (got %ld)", CLI_MAX_THREADS, threads);
#ifdef _OPENMP
    if (threads <= 0)
        threads = omp_get_num_procs();
    if (threads > CLI_MAX_THREADS)
        threads = CLI_MAX_THREADS;
#else
    threads = 1;
#endif
    cli_output_note("fit", o->out);
    cli_output_note_sidecar("fit", o->out);
    cli_output_note("fit", o->report);
    cli_output_folder_check("fit", o->report);
    if (o->probe != NULL) {
        /* a file of curves (a force map): each curve with the one probe */
        lf_error err;
        cli_input_guard("fit", o->plan);
        if (lf_plan_of_file(o->plan, o->probe, LF_SEG_UNLOAD, &plan, &err) != LF_OK)
            cli_die_error(err.status == LF_ENOMEM ? CLI_EXIT_FAIL : CLI_EXIT_USAGE, &err);
    } else {
        plan = cli_plan_load("fit", o->plan);
    }
    cli_plan_need_layers(plan, o->auto_model ? "auto" : settings->model->name);
    for (i = 0; i < plan->n; i++)      /* no output may replace a curve */
        if (i == 0 || strcmp(plan->rows[i].file, plan->rows[i - 1].file) != 0)
            cli_input_guard("fit", plan->rows[i].file);
    {
        /* a file of many curves named without an index: each curve a row
         * (its file opened once, its curves read from it one at a time) */
        lf_error err;
        if (lf_plan_open_files(plan, o->input.read, &err) != LF_OK)
            cli_die(CLI_EXIT_FAIL, "out of memory");
        if (o->probe != NULL) {
            if (plan->nfiles > 0)
                cli_input_note(o->plan, lf_file_sha256(plan->files[0]));
            else
                cli_input_note(o->plan, NULL);
        }
    }
    if (units_make(plan, &ul) != 0)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    lo = (size_t) ((double) ul.nunits * (double) (shard_i - 1) / (double) shard_n);
    hi = (size_t) ((double) ul.nunits * (double) shard_i / (double) shard_n);
    total = hi - lo;
    cfg.first = lo;
    if (o->report != NULL && (cfg.page = cli_page_store_new(total)) == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    if (o->out != NULL && (out = cli_out_open(&atomic, o->out, msg, sizeof msg)) == NULL)
        cli_die(CLI_EXIT_FAIL, "fit: %s", msg);
    if (!cfg.json) {
        for (i = 0; columns[i] != NULL; i++)
            fprintf(out, "%s%s", i ? "," : "", columns[i]);
        fputc('\n', out);
    }
    progress = o->progress >= 0 ? o->progress : isatty(STDERR_FILENO);
    block = 128 * (size_t) threads;   /* large enough that slow fits average out across threads */
    rows = calloc(block, sizeof *rows);
    if (rows == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    for (u = lo; u < hi; u += block) {
        size_t nb = hi - u < block ? hi - u : block, bad = 0, mis = 0;
        long b;
#pragma omp parallel for schedule(dynamic, 1) num_threads((int) threads) reduction(+ : bad, mis)
        for (b = 0; b < (long) nb; b++) {
            int r;
            rows[b].len = 0;
            rows[b].failed = 0;
            r = fit_unit(&ul, u + (size_t) b, &cfg, &rows[b]);
            bad += r == 1;
            mis += r == 2;
        }
        for (i = 0; i < nb; i++) {
            if (rows[i].failed || rows[i].s == NULL)
                cli_die(CLI_EXIT_FAIL, "out of memory writing fit %zu", u + i + 1);
            if (fwrite(rows[i].s, 1, rows[i].len, out) != rows[i].len)
                io_error = 1;
        }
        failed += bad;
        misfits += mis;
        done += nb;
        if (progress && (cli_now() - last > 0.2 || done == total)) {
            last = cli_now();
            progress_show(done, total, failed, t0, 0);
        }
    }
    if (progress)
        progress_show(done, total, failed, t0, 1);
    for (i = 0; i < block; i++)
        free(rows[i].s);
    free(rows);
    if (out == stdout && (fflush(out) != 0 || ferror(out)))
        io_error = 1;
    units_free(&ul);
    lf_plan_free(plan);
    if (io_error)
        cli_die(CLI_EXIT_FAIL, "fit: error writing %s", o->out ? o->out : "standard output");
    if (out != stdout) {
        /* the results and their sidecar replace earlier ones only now,
         * whole and together */
        if (cli_out_commit_sidecar(&atomic, o->command_line, msg, sizeof msg) != 0)
            cli_die(CLI_EXIT_FAIL, "fit: %s", msg);
    }
    if (cfg.page != NULL) {
        if (cli_page_map(o->report, o->out, cfg.page, o->command_line, msg, sizeof msg) != 0)
            cli_die(CLI_EXIT_FAIL, "fit: %s", msg);
        cli_page_store_free(cfg.page);
    }
    if (failed > 0) {
        cli_say("fit: %zu of %zu fits failed (status 'error' or 'noconv' in %s)",
                failed, total, o->out ? o->out : "the output");
        return CLI_EXIT_SOME_FAILED;
    }
    if (misfits > 0) {
        cli_say("fit: %zu of %zu fits converged, but the model does not "
                "describe a curve of theirs (status 'misfit' in %s)", misfits, total,
                o->out ? o->out : "the output");
        return CLI_EXIT_MISFIT;
    }
    return CLI_EXIT_OK;
}

static int
regular_file(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* 1 when the value of --batch is a file of curves (a force map, or any
 * curve file), not a plan: a regular file that does not read as a plan. */
static int
batch_of_curves(int argc, char **argv)
{
    const char *path = NULL;
    lf_file_kind kind;
    lf_error err;
    char file[4096];
    long index;
    int i;
    for (i = 1; i < argc && path == NULL; i++) {
        if (strcmp(argv[i], "--") == 0)
            break;
        if (strcmp(argv[i], "--batch") == 0 && i + 1 < argc)
            path = argv[i + 1];
        else if (strncmp(argv[i], "--batch=", 8) == 0)
            path = argv[i] + 8;
    }
    if (path == NULL || lf_curve_path_split(path, file, sizeof file, &index) != LF_OK)
        return 0;
    if (index >= 0)
        return 1;
    return regular_file(file) && lf_file_kind_of(file, &kind, &err) == LF_OK
           && kind == LF_FILE_CURVE;
}

/* `layerfit fit --batch PLAN.csv [options]`: reached from main.c before the
 * single-fit command sees the arguments.  The fit settings take the same
 * options as a single fit (cli/fit.c). */
int
cli_fit_batch(int argc, char **argv, const char *command_line)
{
    const char *plan = NULL, *out = NULL, *shard = NULL, *interface = NULL, *report = NULL;
    long threads_opt = -1;
    int npos, help = 0, quiet = 0, progress = 0, curves_file;
    double k = NAN, R = NAN, b = NAN;
    cli_fit_args fa;
    cli_opt opts[11 + CLI_FIT_NOPTS + 1] = {
        { "batch", CLI_STRING, &plan }, { "out", CLI_STRING, &out },
        { "threads", CLI_COUNT, &threads_opt }, { "shard", CLI_STRING, &shard },
        { "progress", CLI_FLAG, &progress }, { "quiet", CLI_FLAG, &quiet },
        { "k", CLI_NUMBER, &k }, { "R", CLI_LENGTH, &R }, { "b", CLI_LENGTH, &b },
        { "interface", CLI_STRING, &interface }, { "report", CLI_STRING, &report },
    };
    lf_fit_settings s = lf_fit_settings_default();
    cli_batch_opts o;
    lf_probe probe;
    size_t no;

    cli_fit_args_init(&fa);
    no = 11 + cli_fit_opts(&fa, opts + 11);
    opts[no].name = NULL;
    curves_file = batch_of_curves(argc, argv);
    {
        /* a single fit's outputs, and a single curve's probe for a plan,
         * asked of a batch: say where they belong */
        static const char *const single[] = { "--json", "--curves", "--plot" };
        static const char *const probes[] = { "--k", "--R", "--b", "--interface" };
        cli_refuse_options(argc, argv, single, sizeof single / sizeof single[0],
                           "a single fit; a batch writes one row per fit to --out FILE.csv or "
                           "--out FILE.jsonl");
        if (!curves_file)
            cli_refuse_options(argc, argv, probes, sizeof probes / sizeof probes[0],
                               "a single curve; a batch takes each curve's probe from its row "
                               "of the plan (columns k, R, b, interface)");
    }
    cli_parse("fit", argc, argv, opts, &npos, &help);
    /* `fit --batch --help`: the help, not a plan called --help */
    if (plan != NULL && (strcmp(plan, "--help") == 0 || strcmp(plan, "-h") == 0))
        help = 1;
    if (help) {
        printf("usage: layerfit fit --batch PLAN.csv [--out FILE.csv|FILE.jsonl] [--threads N]\n"
               "                    [--shard I/N] [--progress|--quiet] [--report MAP.html]\n"
               "                    [fit options]\n"
               "       layerfit fit --batch MAP --k K [--R LENGTH] [--b LENGTH --interface I]\n"
               "                    [options as above]\n\n"
               "Fits every curve of the plan, or every group of curves with the same\n"
               "'sample', on its own, in parallel; one output row per fit, in plan order,\n"
               "with its status (ok, misfit, noconv, error) and message.  A plan row that\n"
               "names a file of many curves (a force map, QI data, a force volume) without\n"
               "an index stands for each of its curves; MAP, a file of curves given instead\n"
               "of a plan, has every curve fitted with the probe of --k, --R, --b and\n"
               "--interface.  Each row carries the curve's position (x_m, y_m) and grid\n"
               "place (grid_i, grid_j) where its file states them.\n\n"
               "  --out FILE        .csv or .jsonl (default: CSV on standard output)\n"
               "  --threads N       parallel fits, 1..%d (default: all cores); the output\n"
               "                    does not depend on N\n"
               "  --shard I/N       only the I-th of N contiguous shares of the fits; the\n"
               "                    outputs of 1..N concatenated (one CSV header) are the\n"
               "                    output of the whole plan\n"
               "  --report MAP.html one interactive page of every fit: heat maps, histograms,\n"
               "                    the results, each curve with its fit (needs --out FILE.csv)\n"
               "  --progress        progress bar on stderr even when it is not a terminal\n"
               "  --quiet           no progress bar\n"
               "fit options, as for a single fit and with the same defaults:\n",
               CLI_MAX_THREADS);
        fputs(cli_fit_help, stdout);
        printf("\nEvery problem with one curve (a missing or unreadable file included) is\n"
               "that fit's row; the batch goes on.  --out FILE gets FILE.provenance.json.\n\n"
               "exit status: 0 every fit ok; 3 some fits failed (rows with status error or\n"
               "noconv; stderr says how many); 4 none failed, but some converged where the\n"
               "model does not describe a curve (status misfit); 2 bad command line or plan\n"
               "(nothing fitted); 1 a failure of the run itself (e.g. the output could not be\n"
               "written)\n");
        return CLI_EXIT_OK;
    }
    if (npos > 0)
        cli_die(CLI_EXIT_USAGE, "fit: --batch takes the plan as its value; unexpected '%s'", argv[0]);
    if (plan == NULL || *plan == '\0')
        cli_die(CLI_EXIT_USAGE, "fit: --batch needs a plan (e.g. --batch plan.csv)");
    o.choose = lf_choose_settings_default();
    o.input = lf_input_settings_default();
    o.auto_model = cli_fit_settings(&fa, &s, &o.choose, &o.input);
    o.probe = NULL;
    if (curves_file) {
        /* a file of curves: every curve with the probe of the options */
        if (isnan(k))
            cli_die(CLI_EXIT_USAGE, "fit: %s is a curve file, not a plan: give the probe of its "
                    "curves, e.g. --batch %s --k 2 --R 5um --model halfspace (or --b and "
                    "--interface for a layer)", plan, plan);
        cli_fit_probe(o.auto_model ? "auto" : s.model->name, k, R, b, interface, &probe);
        o.probe = &probe;
    }
    o.linear_only = fa.linear_only;
    o.plan = plan;
    o.out = out;
    o.report = report;
    o.command_line = command_line;
    o.shard = shard;
    if (threads_opt == 0)
        cli_die(CLI_EXIT_USAGE, "fit: --threads must be 1..%d (got 0)", CLI_MAX_THREADS);
    o.threads = threads_opt < 0 ? 0 : threads_opt;
    o.progress = quiet ? 0 : progress ? 1 : -1;
    return cli_batch_run(&o, &s);
}

/* 1 when argv asks for a batch fit. */
int
cli_wants_batch(int argc, char **argv)
{
    int i;
    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--") == 0)
            break;
        if (strcmp(argv[i], "--batch") == 0 || strncmp(argv[i], "--batch=", 8) == 0)
            return 1;
    }
    return 0;
}
