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
 * are the output of the whole plan.  A bad curve gives a row with status
 * "error" and its message; the exit status counts the failed fits. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
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

/* Text as a CSV cell (quoted when it holds a comma, quote or line break) or
 * as a JSON string. */
static void
sb_text(sbuf *b, const char *s, int json)
{
    const char *p;
    if (json) {
        sb_printf(b, "\"");
        for (p = s; *p; p++) {
            unsigned char ch = (unsigned char) *p;
            if (ch == '"' || ch == '\\')
                sb_printf(b, "\\%c", ch);
            else if (ch == '\n')
                sb_printf(b, "\\n");
            else if (ch < 0x20)
                sb_printf(b, "\\u%04x", ch);
            else
                sb_printf(b, "%c", ch);
        }
        sb_printf(b, "\"");
        return;
    }
    if (strpbrk(s, ",\"\r\n") == NULL) {
        sb_printf(b, "%s", s);
        return;
    }
    sb_printf(b, "\"");
    for (p = s; *p; p++)
        sb_printf(b, *p == '"' ? "\"\"" : "%c", *p);
    sb_printf(b, "\"");
}

/* ------------------------------------------------------------------------
 * The fits of a plan: units of one or more rows.
 * --------------------------------------------------------------------- */

typedef struct {
    const lf_plan *plan;
    size_t nunits;
    size_t *start;      /* unit u has rows row[start[u] .. start[u+1]-1] */
    size_t *row;
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

/* Group the plan's rows into fits, in the order of each fit's first row:
 * a row with an empty sample alone, rows of one sample together. */
static int
units_make(const lf_plan *plan, unit_list *u)
{
    size_t n = plan->n, i, ng = 0, k = 0;
    sample_key *key = malloc((n ? n : 1) * sizeof *key);
    group *g = malloc((n ? n : 1) * sizeof *g);

    u->plan = plan;
    u->start = malloc((n + 1) * sizeof *u->start);
    u->row = malloc((n ? n : 1) * sizeof *u->row);
    if (key == NULL || g == NULL || u->start == NULL || u->row == NULL) {
        free(key);
        free(g);
        return -1;
    }
    for (i = 0; i < n; i++) {
        key[i].sample = plan->rows[i].sample ? plan->rows[i].sample : "";
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
}

/* ------------------------------------------------------------------------
 * One fit.
 * --------------------------------------------------------------------- */

typedef struct {
    const lf_fit_settings *settings;
    int json;
    int auto_model;        /* lf_fit_choose_driver instead of lf_fit_driver */
} batch_config;

/* How curve files are read (--format, --spring-constant, --sensitivity):
 * set once before the fits start, then only read by the threads. */
static lf_read_opts batch_read_opts;

/* Where a curve sits on a force map: "# x: 10 um" and "# y: ..." lines of
 * its file, NaN when absent or unreadable. */
static double
meta_length(const lf_curve *c, const char *key)
{
    size_t i;
    for (i = 0; i < c->nmeta; i++)
        if (strcmp(c->meta[i].key, key) == 0) {
            double v;
            lf_error err;
            if (lf_units_parse(c->meta[i].value, LF_Q_LENGTH, &v, &err) == LF_OK)
                return v;
        }
    return NAN;
}

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
    "rms_N", "P_po_N", "iterations", "identifiability", "message", NULL
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

/* Write one row: key/value pairs for JSON Lines, cells for CSV. */
static void
put_row(sbuf *b, const batch_config *cfg, size_t fit_no, const char *sample,
        const char *files, size_t ncurves, const char *status, const char *model,
        const num_field *num, size_t nnum, const char *ident, const char *msg)
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
    sb_printf(b, json ? ", \"identifiability\": " : ",");
    sb_text(b, ident, json);
    sb_printf(b, json ? ", \"message\": " : ",");
    sb_text(b, msg, json);
    sb_printf(b, json ? "}\n" : "\n");
}

/* Read, fit and format fit number u (0-based) of the plan.  Returns 1 when
 * the fit failed (error or no convergence), 0 when it succeeded.  Never
 * exits: what goes wrong is written into the row. */
static int
fit_unit(const unit_list *ul, size_t u, const batch_config *cfg, sbuf *out)
{
    const lf_plan *plan = ul->plan;
    size_t first = ul->start[u], n = ul->start[u + 1] - first, j;
    lf_curve **curve = calloc(n, sizeof *curve);
    lf_fit_curve *fc = calloc(n, sizeof *fc);
    double **data = calloc(2 * n, sizeof *data);
    lf_fit_settings s = *cfg->settings;
    lf_fit_result res;
    lf_error err;
    sbuf files = { NULL, 0, 0, 0 }, ident = { NULL, 0, 0, 0 }, msg = { NULL, 0, 0, 0 };
    char ebuf[1200];
    const char *sample = plan->rows[ul->row[first]].sample;
    const char *status = "error";
    double x = NAN, y = NAN, nu_row = NAN;
    int st = LF_EINVAL, have_res = 0, failed = 1, firstw = 1;

    lf_error_clear(&err);
    for (j = 0; j < n; j++)
        sb_printf(&files, "%s%s", j ? ";" : "", plan->rows[ul->row[first + j]].file);
    if (curve == NULL || fc == NULL || data == NULL) {
        snprintf(ebuf, sizeof ebuf, "out of memory");
        goto row;
    }
    for (j = 0; j < n; j++) {
        const lf_plan_row *pr = &plan->rows[ul->row[first + j]];
        size_t m;

        lf_read_opts ro = batch_read_opts;
        if (ro.format == NULL && pr->format != NULL && pr->format[0] != '\0')
            ro.format = pr->format;
        if (lf_curve_read(pr->file, &ro, &curve[j], NULL, &err) != LF_OK
            || lf_curve_check_fit(curve[j], pr->segment, 5, &err) != LF_OK) {
            format_error(ebuf, sizeof ebuf, &err);
            goto row;
        }
        if (j == 0) {
            x = meta_length(curve[j], "x");
            y = meta_length(curve[j], "y");
        }
        if (isfinite(pr->nu)) {
            if (isfinite(nu_row) && nu_row != pr->nu) {
                snprintf(ebuf, sizeof ebuf, "%s:%ld: sample '%s' gives two values of nu",
                         plan->path, pr->line, sample);
                goto row;
            }
            nu_row = pr->nu;
        }
        m = lf_curve_segment(curve[j], pr->segment, NULL, NULL);
        data[2 * j] = malloc(m * sizeof(double));
        data[2 * j + 1] = malloc(m * sizeof(double));
        if (data[2 * j] == NULL || data[2 * j + 1] == NULL) {
            snprintf(ebuf, sizeof ebuf, "out of memory");
            goto row;
        }
        lf_curve_segment(curve[j], pr->segment, data[2 * j], data[2 * j + 1]);
        fc[j].name = pr->file;
        fc[j].n = m;
        fc[j].depth = data[2 * j];
        fc[j].force = data[2 * j + 1];
        fc[j].probe = pr->probe;
        if (isnan(fc[j].probe.R)) {       /* R "header" in the plan */
            if (!(curve[j]->R > 0)) {
                snprintf(ebuf, sizeof ebuf, "%s:%ld: R 'header', but %s states no probe "
                         "radius", plan->path, pr->line, pr->file);
                goto row;
            }
            fc[j].probe.R = curve[j]->R;
        }
        fc[j].branch = pr->segment == LF_SEG_LOAD ? LF_BRANCH_LOAD : LF_BRANCH_UNLOAD;
        fc[j].z0 = pr->z0;
        fc[j].F0 = pr->F0;
    }
    if (isfinite(nu_row) && s.nu.mode != LF_PARAM_FIXED) {
        s.nu.mode = LF_PARAM_FIXED;
        s.nu.value = nu_row;
    }
    if (cfg->auto_model) {
        lf_choose_settings choose = lf_choose_settings_default();
        st = lf_fit_choose_driver(&s, &choose, n, fc, &res, &err);
    } else {
        st = lf_fit_driver(&s, n, fc, &res, &err);
    }
    if (st == LF_OK || st == LF_ENOCONV) {
        have_res = 1;
        status = st == LF_OK ? "ok" : "noconv";
        failed = st != LF_OK;
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
            { "chi2_dof", res.se_scale * res.se_scale },
            { "rms_N", rms_all(&res) },
            { "P_po_N", res.ncurves ? res.curves[0].pulloff.P_po : NAN },
            { "iterations", (double) res.iterations },
        };
        firstw = 1;
        join_warnings(&ident, &res.identifiability, &firstw);
        firstw = 1;
        join_warnings(&msg, &res.warnings, &firstw);
        for (j = 0; j < res.ncurves; j++)
            join_warnings(&msg, &res.curves[j].warnings, &firstw);
        put_row(out, cfg, u + 1, sample, files.s ? files.s : "", n, status,
                res.model ? res.model : "", num,
                sizeof num / sizeof num[0], ident.s ? ident.s : "", msg.s ? msg.s : "");
        lf_fit_result_free(&res);
    } else {
        num_field num[] = {
            { "x_m", x }, { "y_m", y },
            { "w_J_m2", NAN }, { "w_se_J_m2", NAN }, { "w_upper_bound", NAN },
            { "Estar_Pa", NAN }, { "Estar_se_Pa", NAN }, { "nu", NAN }, { "nu_se", NAN },
            { "M_Pa", NAN }, { "M_se_Pa", NAN }, { "corr_w_Estar", NAN },
            { "chi2_dof", NAN }, { "rms_N", NAN }, { "P_po_N", NAN }, { "iterations", NAN },
        };
        put_row(out, cfg, u + 1, sample, files.s ? files.s : "", n, status, "", num,
                sizeof num / sizeof num[0], "", ebuf);
    }
    for (j = 0; curve != NULL && j < n; j++)
        lf_curve_free(curve[j]);
    for (j = 0; data != NULL && j < 2 * n; j++)
        free(data[j]);
    free(curve);
    free(fc);
    free(data);
    free(files.s);
    free(ident.s);
    free(msg.s);
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
    lf_warnings warn = { 0, NULL };
    lf_error err;
    unit_list ul;
    batch_config cfg;
    FILE *out = stdout;
    sbuf *rows;
    size_t lo, hi, u, block, total, done = 0, failed = 0, i;
    long shard_i = 1, shard_n = 1, threads = o->threads;
    int progress, io_error = 0;
    double t0 = cli_now(), last = 0.0;

    cfg.settings = settings;
    cfg.json = 0;
    cfg.auto_model = o->auto_model;
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
#ifdef _OPENMP
    if (threads <= 0)
        threads = omp_get_num_procs();
#else
    threads = 1;
#endif
    if (lf_plan_read(o->plan, &plan, &warn, &err) != LF_OK)
        cli_die_error(CLI_EXIT_USAGE, &err);
    cli_print_warnings(&warn);
    lf_warnings_free(&warn);
    if (units_make(plan, &ul) != 0)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    lo = (size_t) ((double) ul.nunits * (double) (shard_i - 1) / (double) shard_n);
    hi = (size_t) ((double) ul.nunits * (double) shard_i / (double) shard_n);
    total = hi - lo;
    if (o->out != NULL && (out = fopen(o->out, "w")) == NULL)
        cli_die(CLI_EXIT_USAGE, "fit: cannot write %s: %s", o->out, strerror(errno));
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
        size_t nb = hi - u < block ? hi - u : block, bad = 0;
        long b;
#pragma omp parallel for schedule(dynamic, 1) num_threads((int) threads) reduction(+ : bad)
        for (b = 0; b < (long) nb; b++) {
            rows[b].len = 0;
            rows[b].failed = 0;
            bad += (size_t) fit_unit(&ul, u + (size_t) b, &cfg, &rows[b]);
        }
        for (i = 0; i < nb; i++) {
            if (rows[i].failed || rows[i].s == NULL)
                cli_die(CLI_EXIT_FAIL, "out of memory writing fit %zu", u + i + 1);
            if (fwrite(rows[i].s, 1, rows[i].len, out) != rows[i].len)
                io_error = 1;
        }
        failed += bad;
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
    if (fflush(out) != 0 || ferror(out))
        io_error = 1;
    if (out != stdout && fclose(out) != 0)
        io_error = 1;
    units_free(&ul);
    lf_plan_free(plan);
    if (io_error)
        cli_die(CLI_EXIT_FAIL, "fit: error writing %s", o->out ? o->out : "standard output");
    if (failed > 0)
        fprintf(stderr, "layerfit: fit: %zu of %zu fits failed (status 'error' or 'noconv' in %s)\n",
                failed, total, o->out ? o->out : "the output");
    return failed > CLI_BATCH_MAX_FAILED ? CLI_BATCH_MAX_FAILED : (int) failed;
}

/* `layerfit fit --batch PLAN.csv [options]`: reached from main.c before the
 * single-fit command sees the arguments.  The fit settings take the same
 * options as a single fit (cli/fit.c). */
int
cli_fit_batch(int argc, char **argv)
{
    const char *plan = NULL, *out = NULL, *shard = NULL, *model = "thin", *method = "lm",
               *jacobian = "analytic";
    long threads = 0, max_iter = -1;
    int npos, help = 0, slope = 0, quiet = 0, progress = 0;
    double nu = NAN, fix_nu = NAN, max_ba = NAN;
    const char *format = NULL, *kc = NULL, *sens = NULL;
    lf_error err;
    const cli_opt opts[] = {
        { "batch", CLI_STRING, &plan }, { "out", CLI_STRING, &out },
        { "threads", CLI_COUNT, &threads }, { "shard", CLI_STRING, &shard },
        { "progress", CLI_FLAG, &progress }, { "quiet", CLI_FLAG, &quiet },
        { "model", CLI_STRING, &model }, { "method", CLI_STRING, &method },
        { "jacobian", CLI_STRING, &jacobian }, { "slope", CLI_FLAG, &slope },
        { "nu", CLI_NUMBER, &nu }, { "fix-nu", CLI_NUMBER, &fix_nu },
        { "max-b-over-a", CLI_NUMBER, &max_ba }, { "max-iter", CLI_COUNT, &max_iter },
        { "format", CLI_STRING, &format }, { "spring-constant", CLI_STRING, &kc },
        { "sensitivity", CLI_STRING, &sens },
        { NULL, 0, NULL }
    };
    lf_fit_settings s = lf_fit_settings_default();
    cli_batch_opts o;

    cli_parse("fit", argc, argv, opts, &npos, &help);
    if (help) {
        printf("usage: layerfit fit --batch PLAN.csv [--out FILE.csv|FILE.jsonl] [--threads N]\n"
               "                    [--shard I/N] [--progress|--quiet] [fit options]\n\n"
               "Fits every curve of the plan, or every group of curves with the same\n"
               "'sample', on its own, in parallel; one output row per fit, in plan order,\n"
               "with its status (ok, noconv, error) and message.\n\n"
               "  --out FILE        .csv or .jsonl (default: CSV on standard output)\n"
               "  --threads N       parallel fits (default: all cores); the output does\n"
               "                    not depend on N\n"
               "  --shard I/N       only the I-th of N contiguous shares of the fits; the\n"
               "                    outputs of 1..N concatenated (one CSV header) are the\n"
               "                    output of the whole plan\n"
               "  --progress        progress bar on stderr even when it is not a terminal\n"
               "  --quiet           no progress bar\n"
               "fit options as for a single fit: --model, --method, --jacobian, --slope,\n"
               "  --nu/--fix-nu NU, --max-b-over-a X, --max-iter N; how curves are read:\n"
               "  --format NAME, --spring-constant K, --sensitivity S\n\n"
               "exit status: 0 every fit ok; N (1..%d) the number of fits that failed;\n"
               "2 also for a bad command line or plan (then nothing is fitted)\n",
               CLI_BATCH_MAX_FAILED);
        return CLI_EXIT_OK;
    }
    if (npos > 0)
        cli_die(CLI_EXIT_USAGE, "fit: --batch takes the plan as its value; unexpected '%s'", argv[0]);
    if (plan == NULL || *plan == '\0')
        cli_die(CLI_EXIT_USAGE, "fit: --batch needs a plan (e.g. --batch plan.csv)");
    lf_read_opts_default(&batch_read_opts);
    batch_read_opts.format = format;
    if (lf_read_opts_constants(&batch_read_opts, kc, sens, &err) != LF_OK)
        cli_die(CLI_EXIT_USAGE, "fit: %s", err.msg);
    o.auto_model = cli_fit_options(model, method, jacobian, max_ba, &s);
    s.fit_slope = slope;
    if (max_iter == 0)
        cli_die(CLI_EXIT_USAGE, "fit: --max-iter must be at least 1");
    if (max_iter > 0)
        s.max_iter = (size_t) max_iter;
    if (!isnan(fix_nu))
        nu = fix_nu;
    if (!isnan(nu)) {
        if (!(nu >= 0.0 && nu < 0.5))
            cli_die(CLI_EXIT_USAGE, "fit: nu must lie in [0, 0.5) (got %g)", nu);
        s.nu.mode = LF_PARAM_FIXED;
        s.nu.value = nu;
    }
    o.plan = plan;
    o.out = out;
    o.shard = shard;
    o.threads = threads;
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
