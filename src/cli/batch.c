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

/* Where the rows go, the progress bar and the report's curves. */
typedef struct {
    FILE *out;
    int io_error;
    int progress;
    double t0, last;
    cli_page_store *page;  /* --report, or NULL */
} batch_sink;

static int
write_row(void *ctx, const lf_batch_row *row)
{
    batch_sink *k = ctx;

    /* rows come in plan order: the row's place in the output */
    cli_page_store_fit(k->page, row->done - 1, row->input, row->result, row->sample);

    if (fwrite(row->text, 1, row->len, k->out) != row->len)
        k->io_error = 1;
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
    batch_sink sink = { stdout, 0, 0, 0.0, 0.0, NULL };
    cli_out atomic;
    lf_error err;
    char msg[4400];
    size_t i;

    sink.t0 = cli_now();
    if (o->out != NULL) {
        if (ends_with(o->out, ".jsonl"))
            bs.json = 1;
        else if (!ends_with(o->out, ".csv"))
            cli_die(CLI_EXIT_USAGE, "fit: --out %s: the batch output must end in .csv or .jsonl",
                    o->out);
    }
    if (o->shard != NULL && cli_shard_parse(o->shard, &bs.shard_index, &bs.shard_count) != 0)
        cli_die(CLI_EXIT_USAGE, "fit: --shard '%s' is not I/N with 1 <= I <= N (e.g. --shard 3/8)",
                o->shard);
    if (o->threads != 0 && (o->threads < 1 || o->threads > CLI_MAX_THREADS))
        cli_die(CLI_EXIT_USAGE, "fit: --threads must be 1..%d (got %ld)", CLI_MAX_THREADS,
                o->threads);
    bs.threads = o->threads;
    bs.csv_raw = cli_csv_raw;
    if (o->report != NULL) {
        /* the page is made from the results file and each fit's curves */
        if (o->out == NULL || !ends_with(o->out, ".csv"))
            cli_die(CLI_EXIT_USAGE, "fit: --report %s: the page is made from the results; give "
                    "them as --out FILE.csv", o->report);
        if ((sink.page = cli_page_store_new()) == NULL)
            cli_die(CLI_EXIT_FAIL, "out of memory");
        bs.results = 1;
    }
    cli_output_note("fit", o->out);
    cli_output_note_sidecar("fit", o->out);
    cli_output_note("fit", o->report);
    cli_output_folder_check("fit", o->report);
    if (o->probe != NULL) {
        /* a file of curves (a force map): each curve with the one probe */
        cli_input_guard("fit", o->plan);
        if (lf_plan_of_file(o->plan, o->probe, LF_SEG_UNLOAD, &plan, &err) != LF_OK)
            cli_die_error(err.status == LF_ENOMEM ? CLI_EXIT_FAIL : CLI_EXIT_USAGE, &err);
    } else {
        plan = cli_plan_load("fit", o->plan);
    }
    cli_plan_need_layers(plan, o->req->model);
    for (i = 0; i < plan->n; i++)      /* no output may replace a curve */
        if (i == 0 || strcmp(plan->rows[i].file, plan->rows[i - 1].file) != 0)
            cli_input_guard("fit", plan->rows[i].file);
    /* a file of many curves named without an index: each curve a fit (its
     * file opened once here, for the provenance of a map fitted whole) */
    if (lf_plan_open_files(plan, o->req->input.read, &err) != LF_OK)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    if (o->probe != NULL)
        cli_input_note(o->plan, plan->nfiles > 0 ? lf_file_sha256(plan->files[0]) : NULL);
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
    if (sink.io_error)
        cli_die(CLI_EXIT_FAIL, "fit: error writing %s", o->out ? o->out : "standard output");
    if (sink.out != stdout) {
        /* the results and their sidecar replace earlier ones only now,
         * whole and together */
        if (cli_out_commit_sidecar(&atomic, o->command_line, msg, sizeof msg) != 0)
            cli_die(CLI_EXIT_FAIL, "fit: %s", msg);
    }
    if (sink.page != NULL) {
        if (cli_page_map(o->report, o->out, sink.page, o->command_line, msg, sizeof msg) != 0)
            cli_die(CLI_EXIT_FAIL, "fit: %s", msg);
        cli_page_store_free(sink.page);
    }
    if (sum.failed > 0) {
        cli_say("fit: %zu of %zu fits failed (status 'error' or 'noconv' in %s)",
                sum.failed, sum.total, o->out ? o->out : "the output");
        return CLI_EXIT_SOME_FAILED;
    }
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
    int npos, help = 0, quiet = 0, progress = 0, curves_file, one_curve, status;
    lf_fit_options *fo = lf_fit_options_alloc();
    cli_opt opts[7 + CLI_FIT_NOPTS + 1] = {
        { "batch", CLI_STRING, &plan }, { "out", CLI_STRING, &out },
        { "threads", CLI_COUNT, &threads_opt }, { "shard", CLI_STRING, &shard },
        { "progress", CLI_FLAG, &progress }, { "quiet", CLI_FLAG, &quiet },
        { "report", CLI_STRING, &report },
    };
    lf_fit_request req;
    cli_batch_opts o;
    lf_probe probe;
    size_t no;

    if (fo == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    no = 7 + cli_fit_opts(fo, opts + 7);
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
        lf_fit_options_free(fo);
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
    cli_fit_request(fo, &req);
    o.req = &req;
    o.probe = NULL;
    if (curves_file) {
        /* a file of curves: every curve with the probe of the options */
        if (lf_fit_options_get(fo, "k") == NULL)
            cli_die(CLI_EXIT_USAGE, "fit: %s is a curve file, not a plan: give the probe of its "
                    "curves, e.g. --batch %s --k 2 --R 5um --model halfspace (or --b and "
                    "--interface for a layer)", plan, plan);
        cli_fit_probe(fo, &probe, &one_curve);
        o.probe = &probe;
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
