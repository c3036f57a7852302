/* cli/batch.c: `layerfit fit --batch PLAN.csv`, many independent fits: the
 * options, the plan, the output file and the progress bar.  The fits are
 * the library's batch (lf_batch_run, src/batch.c): worker threads, rows
 * handed over in plan order as they are done, each written here.
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

#include "cli.h"

/* ------------------------------------------------------------------------
 * Summaries: per sample and for all curves, from each curve's own fit
 * (lf_heterogeneity_of: n, mean, SD, median, quartiles, and the random-
 * effects population mean with its interval and the spot-to-spot SD).
 * --------------------------------------------------------------------- */

typedef struct {
    char *sample;           /* NULL: every curve of the batch (or shard) */
    lf_heterogeneity h;
} summary_group;

/* Each curve's own estimates as the rows come (a curve that could not be
 * fitted: NaN), and a group per sample; the last group, all the curves,
 * is made at the end (summary_add_group(sm, NULL, 0)). */
typedef struct {
    lf_curve_estimate *est;
    size_t nest, cap;
    size_t n, ncap;
    summary_group *g;
    size_t misfits;         /* curves of misfit rows, left out */
} summary;

/* A group of the curves est[first..nest-1]. */
static void
summary_add_group(summary *sm, const char *sample, size_t first)
{
    lf_error err;
    summary_group *g;

    if (sm->n == sm->ncap) {
        sm->ncap = sm->ncap ? 2 * sm->ncap : 16;
        if ((sm->g = realloc(sm->g, sm->ncap * sizeof *sm->g)) == NULL)
            cli_die(CLI_EXIT_FAIL, "out of memory");
    }
    g = &sm->g[sm->n++];
    g->sample = NULL;
    if (sample != NULL && (g->sample = strdup(sample)) == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    if (lf_heterogeneity_of(sm->nest - first, sm->est + first, &g->h, &err) != LF_OK)
        cli_die(CLI_EXIT_FAIL, "fit: summary: %s", err.msg);
}

/* A row's curves into the summary (136 bytes a curve), and its sample's
 * group. */
static void
summary_row(summary *sm, const lf_batch_row *row)
{
    /* a misfit's values are those of a model that does not describe its
     * curve, not measurements: left out as a failed fit's are */
    const lf_fit_result *r = row->outcome == LF_BATCH_OK ? row->result : NULL;
    size_t n = row->result != NULL ? row->result->ncurves : row->input != NULL ? row->input->n : 0;
    size_t first = sm->nest, j;

    if (sm->nest + n > sm->cap) {
        sm->cap = sm->nest + n > 2 * sm->cap ? sm->nest + n : 2 * sm->cap;
        if ((sm->est = realloc(sm->est, sm->cap * sizeof *sm->est)) == NULL)
            cli_die(CLI_EXIT_FAIL, "out of memory");
    }
    for (j = 0; j < n; j++) {
        lf_curve_estimate *e = &sm->est[sm->nest++];
        if (r != NULL) {
            *e = r->curves[j].alone;
            e->probe = r->curves[j].probe;
            continue;
        }
        if (row->outcome == LF_BATCH_MISFIT)
            sm->misfits++;
        memset(e, 0, sizeof *e);
        e->value[0] = e->value[1] = e->value[2] = NAN;
        e->se[0] = e->se[1] = e->se[2] = e->corr_wE = NAN;
        e->ci95[0][0] = e->ci95[0][1] = e->ci95[1][0] = NAN;
        e->ci95[1][1] = e->ci95[2][0] = e->ci95[2][1] = NAN;
        e->probe = row->input != NULL ? row->input->curves[j].probe
                                       : row->result->curves[j].probe;
    }
    if (row->sample[0] != '\0')
        summary_add_group(sm, row->sample, first);
}

static void
summary_free(summary *sm)
{
    size_t i;
    for (i = 0; i < sm->n; i++)
        free(sm->g[i].sample);
    free(sm->g);
    free(sm->est);
}

static const char *const summary_param[3] = { "w", "Estar", "nu" };
static const char *const summary_unit[3] = { "J/m^2", "Pa", "" };

static const lf_population_estimate *
summary_estimate(const lf_heterogeneity *h, int m)
{
    return m == LF_MAT_W ? &h->w : m == LF_MAT_E ? &h->Estar : &h->nu;
}

static void
csv_num(FILE *f, double x)
{
    fputc(',', f);
    if (isfinite(x))
        cli_print_double(f, x);
}

/* One row per group and parameter (nu only where some curve determines it). */
static void
summary_csv(FILE *f, const void *ctx)
{
    const summary *sm = ctx;
    size_t i;
    int m;

    fputs("scope,sample,curves,parameter,unit,n,mean,sd,median,q1,q3,population_mean,"
          "population_ci95_lo,population_ci95_hi,tau,tau_ci95_lo,tau_ci95_hi,tau_rel,I2,"
          "p_homogeneous\n", f);
    for (i = 0; i < sm->n; i++) {
        const summary_group *g = &sm->g[i];
        for (m = 0; m < 3; m++) {
            const lf_population_estimate *e = summary_estimate(&g->h, m);
            /* the columns after n, in the header's order */
            const double v[] = { e->mean, e->sd, e->median, e->q1, e->q3, e->population_mean,
                                 e->population_ci95[0], e->population_ci95[1], e->tau,
                                 e->tau_ci95[0], e->tau_ci95[1], e->tau_rel, e->I2,
                                 e->p_homogeneous };
            size_t k;
            if (m == LF_MAT_NU && e->n == 0)
                continue;
            fprintf(f, "%s,", g->sample ? "sample" : "all");
            cli_put_csv_cell(f, g->sample ? g->sample : "");
            fprintf(f, ",%zu,%s,%s,%zu", g->h.curves, summary_param[m], summary_unit[m], e->n);
            for (k = 0; k < sizeof v / sizeof v[0]; k++)
                csv_num(f, v[k]);
            fputc('\n', f);
        }
    }
}

typedef struct {
    const summary *sm;
    const char *command_line;
} summary_json_ctx;

/* One group's "heterogeneity" (the fit JSON's object). */
static void
json_heterogeneity(FILE *f, const lf_heterogeneity *h, const char *indent)
{
    char *json = lf_heterogeneity_json(h, indent);
    if (json == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    fputs(json, f);
    lf_free(json);
}

static void
summary_json(FILE *f, const void *ctx)
{
    const summary_json_ctx *c = ctx;
    size_t i, k = 0;

    fputs("{\n  \"groups\": [", f);
    for (i = 0; i < c->sm->n; i++) {
        const summary_group *g = &c->sm->g[i];
        if (g->sample == NULL)
            continue;
        fprintf(f, "%s\n    {\"sample\": ", k++ ? "," : "");
        cli_json_string(f, g->sample);
        fprintf(f, ", \"curves\": %zu, \"heterogeneity\": ", g->h.curves);
        json_heterogeneity(f, &g->h, "    ");
        fputc('}', f);
    }
    fprintf(f, "%s],\n  \"all\": {\"curves\": %zu, \"heterogeneity\": ", k ? "\n  " : "",
            c->sm->g[c->sm->n - 1].h.curves);
    json_heterogeneity(f, &c->sm->g[c->sm->n - 1].h, "  ");
    fputs("},\n  \"provenance\": ", f);
    cli_provenance_json(f, "  ", c->command_line);
    fputs("\n}\n", f);
}

/* The summary for people: one line per group and parameter. */
static void
summary_text(FILE *f, const summary *sm)
{
    static const char *const name[3] = { "w", "E*", "nu" };
    char a[48], b[48], c[48];
    size_t i;
    int m;

    fputs("summary (each curve fitted alone; population mean and spot-to-spot SD by random "
          "effects, 95% intervals):\n", f);
    if (sm->misfits > 0)
        fprintf(f, "  %zu curve%s of misfit fits left out (the model does not describe %s: "
                "%s values are not measurements)\n", sm->misfits, sm->misfits == 1 ? "" : "s",
                sm->misfits == 1 ? "it" : "them", sm->misfits == 1 ? "its" : "their");
    for (i = 0; i < sm->n; i++) {
        const summary_group *g = &sm->g[i];
        for (m = 0; m < 3; m++) {
            const lf_population_estimate *e = summary_estimate(&g->h, m);
            int rel = m != LF_MAT_NU;
            if (m == LF_MAT_NU && e->n == 0)
                continue;
            if (g->sample != NULL) {
                fputs("  sample ", f);
                cli_put_clean(f, g->sample);
            } else {
                fputs("  all", f);
            }
            fprintf(f, " (%zu curve%s), %s: ", g->h.curves, g->h.curves == 1 ? "" : "s", name[m]);
            if (e->n == 0) {
                fputs("no curve determines it alone\n", f);
                continue;
            }
            fprintf(f, "%zu determined; mean %s", e->n, cli_param_text(a, sizeof a, e->mean, m));
            if (isfinite(e->sd))
                fprintf(f, ", SD %s", cli_spread_text(a, sizeof a, rel ? e->sd / e->mean : e->sd,
                                                      rel));
            fprintf(f, ", median %s", cli_param_text(a, sizeof a, e->median, m));
            fprintf(f, ", quartiles %s to %s", cli_param_text(a, sizeof a, e->q1, m),
                    cli_param_text(b, sizeof b, e->q3, m));
            if (isfinite(e->population_mean)) {
                fprintf(f, "; population mean %s (%s to %s)",
                        cli_param_text(a, sizeof a, e->population_mean, m),
                        cli_param_text(b, sizeof b, e->population_ci95[0], m),
                        cli_param_text(c, sizeof c, e->population_ci95[1], m));
                fprintf(f, ", spot-to-spot SD %s", cli_spread_text(a, sizeof a, e->tau_rel, rel));
                fprintf(f, " (%s to %s)", cli_spread_text(a, sizeof a, e->tau_rel_ci95[0], rel),
                        cli_spread_text(b, sizeof b, e->tau_rel_ci95[1], rel));
                fprintf(f, ", I^2 %.3g%%, %s", 100.0 * e->I2,
                        cli_p_text(a, sizeof a, e->p_homogeneous));
            }
            fputc('\n', f);
        }
    }
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

/* One cause of failures: its key (lf_batch_row.cause), how many, the
 * first message. */
typedef struct {
    char *key, *why;
    size_t count, first;
} cause;

static int
cmp_cause(const void *a, const void *b)
{
    const cause *x = a, *y = b;
    return x->count != y->count ? (x->count < y->count) - (x->count > y->count)
                                : (x->first > y->first) - (x->first < y->first);
}

/* Where the rows go, the progress bar, the causes of the failed fits and
 * the report's curves. */
typedef struct {
    FILE *out;
    int io_error;
    int progress;
    double t0, last;
    cli_page_store *page;  /* --report, or NULL */
    summary sm;             /* each curve's own fit, for the summaries */
    cause *causes;
    size_t ncauses, cap, nfailed;
    int lost;              /* out of memory counting them */
} batch_sink;

/* Count a failed row's cause. */
static void
cause_count(batch_sink *k, const lf_batch_row *row)
{
    size_t j;

    if (row->why == NULL || row->cause == NULL) {
        k->lost |= row->why != NULL;
        return;
    }
    k->nfailed++;
    for (j = 0; j < k->ncauses && strcmp(k->causes[j].key, row->cause) != 0; j++)
        ;
    if (j == k->ncauses) {
        cause *grown = k->ncauses < k->cap ? k->causes
                       : realloc(k->causes, (k->cap = 2 * k->cap + 16) * sizeof *grown);
        char *key = grown != NULL ? strdup(row->cause) : NULL;
        char *why = key != NULL ? strdup(row->why) : NULL;
        if (grown != NULL)
            k->causes = grown;
        if (why == NULL) {
            free(key);
            k->lost = 1;
            return;
        }
        k->causes[j].key = key;
        k->causes[j].why = why;
        k->causes[j].count = 0;
        k->causes[j].first = k->nfailed;
        k->ncauses++;
    }
    k->causes[j].count++;
}

/* The most common causes of the failures, with their counts, on stderr;
 * then released. */
#define CAUSES_SHOWN 3
static void
causes_print(batch_sink *k)
{
    size_t i, nc = k->ncauses;

    qsort(k->causes, nc, sizeof *k->causes, cmp_cause);
    for (i = 0; i < nc && i < CAUSES_SHOWN; i++) {
        fprintf(stderr, "  %zu fit%s: ", k->causes[i].count, k->causes[i].count == 1 ? "" : "s");
        cli_put_clean(stderr, k->causes[i].why);
        if (k->causes[i].count > 1)
            fprintf(stderr, " (and %zu more like it)", k->causes[i].count - 1);
        fputc('\n', stderr);
    }
    if (nc > CAUSES_SHOWN)
        fprintf(stderr, "  and %zu other reason%s\n", nc - CAUSES_SHOWN,
                nc - CAUSES_SHOWN == 1 ? "" : "s");
}

static void
causes_free(batch_sink *k)
{
    size_t i;

    for (i = 0; i < k->ncauses; i++) {
        free(k->causes[i].key);
        free(k->causes[i].why);
    }
    free(k->causes);
}

static int
write_row(void *ctx, const lf_batch_row *row)
{
    batch_sink *k = ctx;

    /* rows come in plan order: the row's place in the output */
    cli_page_store_fit(k->page, row->done - 1, row->input, row->result, row->sample);

    if (fwrite(row->text, 1, row->len, k->out) != row->len)
        k->io_error = 1;
    summary_row(&k->sm, row);
    cause_count(k, row);
    if (k->progress && (cli_now() - k->last > 0.2 || row->done == row->total)) {
        k->last = cli_now();
        progress_show(row->done, row->total, row->failed, k->t0, 0);
    }
    return 0;
}

int
cli_batch_run(const cli_batch_opts *o)
{
    lf_plan *plan = NULL;
    lf_batch_settings bs = lf_batch_settings_default();
    lf_batch_summary sum;
    batch_sink sink;
    cli_out atomic;
    lf_error err;
    char msg[4400];
    size_t i;
    int beside;
    struct stat st;

    memset(&sink, 0, sizeof sink);
    sink.out = stdout;
    sink.t0 = cli_now();
    bs.results = 1;             /* each curve's own fit, for the summaries */
    if (o->out != NULL) {
        if (ends_with(o->out, ".jsonl"))
            bs.json = 1;
        else if (!ends_with(o->out, ".csv")) {
            lf_plan_free(o->files);
            cli_die(CLI_EXIT_USAGE, "fit: --out %s: the batch output must end in .csv or .jsonl",
                    o->out);
        }
    }
    if (o->shard != NULL && cli_shard_parse(o->shard, &bs.shard_index, &bs.shard_count) != 0) {
        lf_plan_free(o->files);
        cli_die(CLI_EXIT_USAGE, "fit: --shard '%s' is not I/N with 1 <= I <= N (e.g. --shard 3/8)",
                o->shard);
    }
    if (o->threads != 0 && (o->threads < 1 || o->threads > CLI_MAX_THREADS)) {
        lf_plan_free(o->files);
        cli_die(CLI_EXIT_USAGE, "fit: --threads must be 1..%d (got %ld)", CLI_MAX_THREADS,
                o->threads);
    }
    bs.threads = o->threads;
    bs.csv_raw = cli_csv_raw;
    if (o->report != NULL) {
        /* the page is made from the results file and each fit's curves */
        if (o->out == NULL || !ends_with(o->out, ".csv"))
            cli_die(CLI_EXIT_USAGE, "fit: --report %s: the page is made from the results; give "
                    "them as --out FILE.csv", o->report);
        if ((sink.page = cli_page_store_new()) == NULL)     /* rows carry their fits */
            cli_die(CLI_EXIT_FAIL, "out of memory");
    }
    cli_output_note("fit", o->out);
    cli_output_note_sidecar("fit", o->out);
    cli_output_note("fit", o->report);
    cli_output_folder_check("fit", o->report);
    /* the summaries beside a results file (none beside an output written
     * in place: a pipe, a device, as no sidecar) */
    beside = o->out != NULL && strcmp(o->out, "-") != 0
             && (stat(o->out, &st) != 0 || S_ISREG(st.st_mode));
    if (beside) {
        char *sc = cli_summary_path(o->out, "csv"), *sj = cli_summary_path(o->out, "json");
        cli_output_note("fit", sc);
        cli_output_note("fit", sj);
        free(sc);
        free(sj);
    }
    if (o->files != NULL)
        plan = o->files;      /* curve files (force maps among them), one probe for all */
    else
        plan = cli_plan_load("fit", o->plan);
    cli_plan_need_layers(plan, o->req->model);
    for (i = 0; i < plan->n; i++)      /* no output may replace a curve */
        if (i == 0 || strcmp(plan->rows[i].file, plan->rows[i - 1].file) != 0)
            cli_input_guard("fit", plan->rows[i].file);
    /* a file of many curves named without an index: each curve a fit (its
     * file opened once here, for the provenance of a map fitted whole) */
    if (lf_plan_open_files(plan, o->req->input.read, &err) != LF_OK)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    for (i = 0; o->files != NULL && i < plan->n; i++) {
        /* provenance: the files named on the command line (a file of many
         * curves by its digest, taken when it was opened) */
        const char *sha = NULL;
        size_t f;
        for (f = 0; f < plan->nfiles; f++)
            if (plan->rows[i].source == plan->files[f])
                sha = lf_file_sha256(plan->files[f]);
        cli_input_note(plan->rows[i].file, sha);
    }
    if (o->out != NULL && (sink.out = cli_out_open(&atomic, o->out, msg, sizeof msg)) == NULL)
        cli_die(CLI_EXIT_FAIL, "fit: %s", msg);
    if (!bs.json)
        fputs(lf_batch_csv_header(), sink.out);
    sink.progress = o->progress >= 0 ? o->progress : isatty(STDERR_FILENO);
    if (lf_batch_run(plan, o->req, &bs, write_row, &sink, &sum, &err) != LF_OK)
        cli_die(err.status == LF_ENOMEM ? CLI_EXIT_FAIL : CLI_EXIT_USAGE, "fit: %s", err.msg);
    if (sink.progress)
        progress_show(sum.done, sum.total, sum.failed, sink.t0, 1);
    if (sink.out == stdout && (fflush(stdout) != 0 || ferror(stdout)))
        sink.io_error = 1;
    lf_plan_free(plan);
    summary_add_group(&sink.sm, NULL, 0);      /* all the curves */
    if (sink.io_error)
        cli_die(CLI_EXIT_FAIL, "fit: error writing %s", o->out ? o->out : "standard output");
    if (sink.out != stdout) {
        /* the results and their sidecar replace earlier ones only now,
         * whole and together */
        if (cli_out_commit_sidecar(&atomic, o->command_line, msg, sizeof msg) != 0)
            cli_die(CLI_EXIT_FAIL, "fit: %s", msg);
    }
    if (beside) {               /* the summaries beside them */
        summary_json_ctx jc;
        char *sc = cli_summary_path(o->out, "csv"), *sj = cli_summary_path(o->out, "json");
        cli_write_file("fit", sc, summary_csv, &sink.sm);
        jc.sm = &sink.sm;
        jc.command_line = o->command_line;
        cli_write_file("fit", sj, summary_json, &jc);
        free(sc);
        free(sj);
    }
    /* the summary for people: on standard output beside a results file,
     * else on stderr (standard output then carries the rows) */
    if (sink.sm.nest >= 2)
        summary_text(sink.out != stdout ? stdout : stderr, &sink.sm);
    summary_free(&sink.sm);
    if (sink.page != NULL) {    /* the page, from the results and their summary */
        if (cli_page_map(o->report, o->out, sink.page, o->command_line, msg, sizeof msg) != 0)
            cli_die(CLI_EXIT_FAIL, "fit: %s", msg);
        cli_page_store_free(sink.page);
    }
    if (sum.failed > 0) {
        cli_say("fit: %zu of %zu fits failed (status 'error' or 'noconv' in %s); the most "
                "common reasons:", sum.failed, sum.total, o->out ? o->out : "the output");
        causes_print(&sink);
        if (sink.lost)
            fputs("  (out of memory counting the rest)\n", stderr);
    }
    causes_free(&sink);
    if (sum.failed > 0)
        return CLI_EXIT_SOME_FAILED;
    if (sum.misfits > 0) {
        cli_say("fit: %zu of %zu fits converged, but the model does not "
                "describe a curve of theirs (status 'misfit' in %s)", sum.misfits, sum.total,
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
    const char *plan = NULL, *out = NULL, *shard = NULL, *report = NULL;
    long threads_opt = -1;
    int npos, help = 0, quiet = 0, progress = 0, curves_file, status;
    lf_fit_options *fo = lf_fit_options_alloc();
    cli_opt opts[7 + CLI_FIT_NOPTS + 1] = {
        { "batch", CLI_STRING, &plan }, { "out", CLI_STRING, &out },
        { "threads", CLI_COUNT, &threads_opt }, { "shard", CLI_STRING, &shard },
        { "progress", CLI_FLAG, &progress }, { "quiet", CLI_FLAG, &quiet },
        { "report", CLI_STRING, &report },
    };
    lf_fit_request req;
    cli_batch_opts o;
    size_t no;

    if (fo == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    no = 7 + cli_fit_opts(fo, opts + 7);
    opts[no].name = NULL;
    curves_file = batch_of_curves(argc, argv);
    {
        /* a single fit's outputs, and the probe of curve files for a plan,
         * asked of a batch: say where they belong */
        static const char *const single[] = { "--json", "--curves", "--plot" };
        static const char *const probes[] = { "--k", "--R", "--b", "--interface", "--tip",
                                              "--half-angle", "--B", "--sample", "--group-by" };
        cli_refuse_options(argc, argv, single, sizeof single / sizeof single[0],
                           "a single fit; a batch writes one row per fit to --out FILE.csv or "
                           "--out FILE.jsonl");
        if (!curves_file)
            cli_refuse_options(argc, argv, probes, sizeof probes / sizeof probes[0],
                               "curve files; a batch of a plan takes each curve's probe and "
                               "sample from its row (columns k, R, b, interface, tip, "
                               "half_angle, prefactor, sample)");
    }
    cli_parse("fit", argc, argv, opts, &npos, &help);
    /* `fit --batch --help`: the help, not a plan called --help */
    if (plan != NULL && (strcmp(plan, "--help") == 0 || strcmp(plan, "-h") == 0))
        help = 1;
    if (help) {
        printf("usage: layerfit fit --batch PLAN.csv [--out FILE.csv|FILE.jsonl] [--threads N]\n"
               "                    [--shard I/N] [--progress|--quiet] [--report MAP.html]\n"
               "                    [fit options]\n"
               "       layerfit fit --batch FILE... PROBE [--sample NAME | --group-by RULE]\n"
               "                    [options as above]\n\n"
               "Fits every curve of the plan, or every group of curves with the same\n"
               "'sample', on its own, in parallel; one output row per fit, in plan order,\n"
               "with its status (ok, misfit, noconv, error) and message.  A plan row that\n"
               "names a file of many curves (a force map, QI data, a force volume) without\n"
               "an index stands for each of its curves.  Curve files given instead of a\n"
               "plan (as the shell expands *.txt) are fitted with the probe of the options:\n"
               "--k with --R (else each file's header) or --B, or --tip, --half-angle; and\n"
               "--b with --interface for a layer.  --sample NAME makes them one sample,\n"
               "fitted jointly; --group-by RULE forms samples by a header field\n"
               "(field:KEY), a pattern in the file names (name:REGEX, its first group) or\n"
               "their folders (dir).  Each row carries the curve's position (x_m, y_m) and\n"
               "grid place (grid_i, grid_j) where its file states them, and what the first\n"
               "curve shows without a model (adhesion_force_N, ...).\n\n"
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
        lf_fit_options_free(fo);
        printf("\nEvery problem with one curve (a missing or unreadable file included) is\n"
               "that fit's row; the batch goes on, and stderr says the most common reasons\n"
               "of the fits that failed, with their counts.  --out FILE gets\n"
               "FILE.provenance.json.\n\n"
               "exit status: 0 every fit ok; 3 some fits failed (rows with status error or\n"
               "noconv; stderr says how many); 4 none failed, but some converged where the\n"
               "model does not describe a curve (status misfit); 2 bad command line or plan\n"
               "(nothing fitted); 1 a failure of the run itself (e.g. the output could not be\n"
               "written)\n");
        return CLI_EXIT_OK;
    }
    if (plan == NULL || *plan == '\0')
        cli_die(CLI_EXIT_USAGE, "fit: --batch needs a plan or curve files (e.g. --batch plan.csv, "
                "--batch *.txt --k 2 --model halfspace)");
    if (npos > 0 && !curves_file)
        cli_die(CLI_EXIT_USAGE, "fit: --batch %s is a plan: fit it alone (unexpected '%s'; curve "
                "files are named after --batch with their probe)", plan, argv[0]);
    cli_fit_request(fo, &req);
    o.req = &req;
    o.files = NULL;
    if (curves_file) {
        /* curve files: every curve with the probe of the options */
        char **files = malloc(((size_t) npos + 1) * sizeof *files);
        int i;
        if (files == NULL)
            cli_die(CLI_EXIT_FAIL, "out of memory");
        files[0] = (char *) plan;
        for (i = 0; i < npos; i++)
            files[i + 1] = argv[i];
        o.files = cli_files_plan(fo, &req, (size_t) npos + 1, files);
        free(files);
    } else if (lf_fit_options_get(fo, "sample") != NULL
               || lf_fit_options_get(fo, "group-by") != NULL) {
        cli_die(CLI_EXIT_USAGE, "fit: --%s forms the samples of curve files; a plan's sample "
                "column names its samples",
                lf_fit_options_get(fo, "sample") != NULL ? "sample" : "group-by");
    }
    o.plan = plan;
    o.out = out;
    o.report = report;
    o.command_line = command_line;
    o.shard = shard;
    if (threads_opt == 0)
        cli_die(CLI_EXIT_USAGE, "fit: --threads must be 1..%d (got 0)", CLI_MAX_THREADS);
    o.threads = threads_opt < 0 ? 0 : threads_opt;
    o.progress = quiet ? 0 : progress ? 1 : -1;
    status = cli_batch_run(&o);
    lf_fit_options_free(fo);
    return status;
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
