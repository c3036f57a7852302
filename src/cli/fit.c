/* cli/fit.c: `layerfit fit PLAN.csv` and `layerfit fit CURVE.csv --k K
 * --R R --b B --interface I`: read the curves (src/csv_curve.c, src/plan.c),
 * fit them jointly (fit/), print the report and write --json / --curves. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"
#include "report.h"

static const char usage_text[] =
    "usage: layerfit fit PLAN.csv [options]\n"
    "       layerfit fit FILE... PROBE [--b LENGTH --interface I] [options]\n"
    "       layerfit fit EXPORT.txt --model halfspace --k 2 [--R LENGTH] [options]\n"
    "       layerfit fit MAP.jpk-force-map#N ...   curve N (from 0) of a file of many\n"
    "\n"
    "Fits w, E* and (where the plan determines it) nu jointly to every curve,\n"
    "with each curve's contact point z0 and force offset F0 free unless fixed.\n"
    "Curve files named on the command line (a.txt b.txt, or *.txt as the shell\n"
    "expands it) are one material, with one probe for all: R from each file's\n"
    "header where --R is absent; with --model halfspace no --b and --interface.\n"
    "\n"
    "the probe (PROBE) of curve files:\n"
    "  --k K --R LENGTH     a power law f = r^k/(k R^(k-1)) (k = 2: a paraboloid)\n"
    "  --k K --B PREFACTOR  the same stated by f = B r^k, B in m^(1-k)\n"
    "  --tip T              paraboloid, sphere (a true sphere of radius --R, contact up\n"
    "                       to R), cone, berkovich (its equivalent cone, 70.3 deg),\n"
    "                       pyramid (four-sided: the cone of equal projected area)\n"
    "  --half-angle ANGLE   a cone's half-angle (35deg), a pyramid's faces'\n"
    "  --b LENGTH --interface frictionless|bonded   the layer under it\n"
    "options:\n"
    "  --json FILE          the result in SI as JSON\n"
    "  --curves FILE        per point: depth, force, fitted force, residual, contact radius\n"
    "  --plot DIR           figures (PNG, SVG) with their gnuplot scripts and data\n"
    "  --report FILE.html   one self-contained interactive page: tables, warnings, figures\n"
    "  --batch PLAN.csv     every curve or sample an independent fit (see --batch --help)\n"
    "fit options (the same, with the same defaults, for --batch):\n";

const char cli_fit_help[] =
    "  --model NAME         auto (default), thin, exact or halfspace; auto picks per curve\n"
    "                       the cheapest model whose bias on w, E*, nu is below --model-tol\n"
    "  --model-tol X        bias allowed to a cheaper model, in standard errors (0.2)\n"
    "  --model-each         a batch's auto decides every curve alone (default: once per\n"
    "                       probe and layer where the group's margin settles it)\n"
    "  --method M           lm (default), lmaccel, dogleg, ddogleg, subspace2D\n"
    "  --jacobian J         analytic (default), forward, central\n"
    "  --no-cache           neither read nor write the exact model's tables on disk\n"
    "  --fix-nu NU          hold nu (also --nu); a plan's nu column does the same (every\n"
    "                       row that gives nu must give the same value; the option wins)\n"
    "  --fix-z0 LENGTH      hold every curve's contact point\n"
    "  --fix-F0 FORCE       hold every curve's force offset\n"
    "  --slope              fit a baseline slope per curve\n"
    "  --max-iter N         iterations allowed (200)\n"
    "  --max-b-over-a X     warn where b/a exceeds X (0.1)\n"
    "  --segment S          unload (retract, withdraw) or load (approach, extend) for\n"
    "                       every curve (default: the plan's, unload)\n"
    "  --depth-range LO:HI  fit only the points whose indentation from the curve's\n"
    "                       contact point lies within: 0:500nm, or 0:30% of its deepest\n"
    "                       indentation; a side left empty is open (:50%)\n"
    "  --force-range LO:HI  fit only the points whose force above the baseline lies\n"
    "                       within: -20nN:2uN, or :80% of its largest force\n"
    "  --sample NAME        curve files on the command line are one sample NAME\n"
    "  --group-by RULE      their samples by a header field (field:KEY), a pattern in\n"
    "                       their names (name:REGEX, its first group) or folder (dir)\n"
    "  --guess-w ADH        start the iteration at this w (e.g. 10mJ/m2) instead of\n"
    "                       the automatic guess\n"
    "  --guess-E PRESSURE   start at this E* (e.g. 1GPa)\n"
    "  --guess-nu NU        start at this nu, where nu is fitted\n"
    "  --loss L             linear (least squares, default), huber or cauchy: robust\n"
    "                       losses down-weight outliers (iteratively reweighted)\n"
    "  --loss-scale X       where the robust loss bends, in noise sd (1.345 huber,\n"
    "                       2.385 cauchy)\n"
    "  --intervals I        auto (default): profile-likelihood intervals where the\n"
    "                       linear ones are unreliable; linear: skip that check (faster\n"
    "                       batches; every interval then says 'not checked')\n"
    "how curve files are read (also for --batch; a plan's format column per row):\n"
    "  --format NAME        the curve files' format instead of sniffing (csv, chiaro, jpk,\n"
    "                       workshop, ntmdt, hysitron, text, tab, jpk-force,\n"
    "                       workshop-map, nanoscope, igor; see layerfit check)\n"
    "  --spring-constant K  cantilever spring constant where a file states none (0.032N/m)\n"
    "  --sensitivity S      deflection sensitivity where a file states none (61nm/nA)\n"
    "  --depth-unit UNIT    unit of a depth column whose header gives none (nm)\n"
    "  --force-unit UNIT    unit of a force column whose header gives none (uN)\n"
    "  --skip-bad-rows      skip rows with missing cells, with a warning\n";

static const char exit_text[] =
    "exit status: 0 converged; 3 not converged or the model cannot be evaluated at\n"
    "the start (report still written when there is one); 4 converged, but the model\n"
    "does not describe a curve (DISAGREES; report still written); 2 bad command line,\n"
    "option value or input file, or a probe the model cannot evaluate (all before the\n"
    "fit); 1 input, output or memory (e.g. an output not written)\n";

typedef struct {
    const char *json, *curves;
    int single;         /* a single curve (--k given), not a plan */
    lf_probe probe;     /* its probe (lf_fit_options_probe) */
} fit_args;

/* The report's notes on its input, once the fit has run (an error exit
 * leaves nothing on standard output): a single curve fitted as a half-space
 * uses no layer, and "FILE: R = 8 um from the file header" for each curve
 * whose probe radius was read from its file. */
static void
print_input_notes(const fit_args *a, const lf_fit_input *in)
{
    char buf[48];
    size_t j;
    if (a->single && isnan(a->probe.b) && in->n == 1)
        printf("%s: half-space model: no layer thickness or interface used\n", in->names[0]);
    for (j = 0; j < in->n; j++)
        if (in->R_source[j] != NULL && strcmp(in->R_source[j], "file header") == 0)
            printf("%s: R = %s from the file header (%s export)\n", in->curves[j].name,
                   cli_human(buf, sizeof buf, in->curves[j].probe.R, "m"),
                   in->format[j] != NULL ? in->format[j] : "?");
}

static int
to_stdout(const char *output)
{
    return output != NULL && strcmp(output, "-") == 0;
}

/* A probe the fit's model cannot evaluate (lf_model_check_probe: k, R or
 * b where its numbers leave double precision) is refused before the fit,
 * naming the curve; --model auto starts from the thin-layer model. */
static void
check_probes(const lf_fit_input *in, const char *model)
{
    const lf_model_type *type = lf_model_type_find(model);
    lf_error err;
    size_t j, i;

    if (type == NULL)
        type = &lf_model_thin;
    for (j = 0; j < in->n; j++) {
        const lf_probe *p = &in->curves[j].probe;
        for (i = 0; i < j; i++)       /* each probe once */
            if (memcmp(&in->curves[i].probe, p, sizeof *p) == 0)
                break;
        if (i == j && lf_model_check_probe(type, p, &err) != LF_OK)
            cli_die(CLI_EXIT_USAGE, "fit: %s: %s", in->names[j], err.msg);
    }
}

void
cli_fit_probe(const lf_fit_options *o, lf_probe *p, int *single)
{
    lf_error err;

    if (lf_fit_options_probe(o, p, single, &err) != LF_OK)
        cli_die(CLI_EXIT_USAGE, "fit: %s", err.msg);
}

void
cli_fit_request(lf_fit_options *o, lf_fit_request *req)
{
    lf_error err;

    if (lf_fit_options_request(o, req, &err) != LF_OK)
        cli_die(CLI_EXIT_USAGE, "fit: %s", err.msg);
}

size_t
cli_fit_opts(lf_fit_options *o, cli_opt *opts)
{
    size_t n;

    for (n = 0; lf_fit_option_table[n].name != NULL; n++) {
        if (n == CLI_FIT_NOPTS)     /* a table that outgrew the room: never silently */
            cli_die(CLI_EXIT_FAIL, "fit: more options than CLI_FIT_NOPTS (%d)", CLI_FIT_NOPTS);
        opts[n].name = lf_fit_option_table[n].name;
        opts[n].kind = lf_fit_option_table[n].kind == LF_OPTION_FLAG ? CLI_FIT_FLAG : CLI_FIT;
        opts[n].target = o;
    }
    return n;
}

/* Read the plan, the single curve or the curve files into in
 * (lf_fit_input_from_plan: the one step from a plan to a fit's input, the
 * one rule for nu). */
static void
read_input(int npos, char **pos, const lf_fit_options *fo, const lf_fit_request *req,
           lf_fit_input *in)
{
    const lf_input_settings *is = &req->input;
    lf_warnings warn = { 0, NULL };
    lf_error err;
    lf_input_settings one = *is;
    const char *path = pos[0];
    size_t j;
    int status;
    if (npos > 1 || !cli_reads_as_plan(path)) {
        /* curve files, each with the probe of the options */
        lf_plan *plan;
        const char *s1, *s2;
        plan = cli_files_plan(fo, req, (size_t) npos, pos);
        if (!cli_plan_one_sample(plan, &s1, &s2)) {
            char msg[600];
            snprintf(msg, sizeof msg, "fit: the files form several samples ('%s', '%s', ...): a "
                     "joint fit is of one material; fit each sample on its own with "
                     "layerfit fit --batch FILE... --group-by ...", s1, s2);
            lf_plan_free(plan);
            cli_die(CLI_EXIT_USAGE, "%s", msg);
        }
        if (npos == 1 && plan->rows[0].index < 0) {
            /* a single curve named on the command line may be a pipe (read once) */
            one.open_flags = LF_INPUT_STREAM;
            status = lf_fit_input_from_curve(path, &plan->rows[0].probe, &one, in, &warn, &err);
        } else {
            status = lf_fit_input_from_plan(plan, NULL, 0, is, in, &warn, &err);
        }
        lf_plan_free(plan);
    } else {
        lf_plan *plan;
        const char *sample = lf_fit_options_get(fo, "sample");
        if (sample != NULL || lf_fit_options_get(fo, "group-by") != NULL)
            cli_die(CLI_EXIT_USAGE, "fit: --%s forms the samples of curve files; %s is a plan, "
                    "whose sample column names them", sample != NULL ? "sample" : "group-by",
                    path);
        plan = cli_plan_load("fit", path);
        cli_plan_need_layers(plan, req->model);
        for (j = 0; j < plan->n; j++)   /* no output may replace a curve */
            cli_input_guard("fit", plan->rows[j].file);
        status = lf_fit_input_from_plan(plan, NULL, 0, is, in, &warn, &err);
        lf_plan_free(plan);
    }
    cli_print_warnings(&warn);
    lf_warnings_free(&warn);
    if (status != LF_OK && err.file[0] == '\0')
        cli_die(status == LF_ENOMEM ? CLI_EXIT_FAIL : CLI_EXIT_USAGE, "fit: %s", err.msg);
    if (status != LF_OK)
        cli_die_error(status == LF_ENOMEM ? CLI_EXIT_FAIL : CLI_EXIT_USAGE, &err);
    for (j = 0; j < in->n; j++)     /* provenance: each curve as it was read */
        cli_input_note(in->names[j], in->sha256[j]);
    check_probes(in, req->model);
}

/* --json and --curves: through the atomic writer (output.c). */
typedef struct {
    void (*writer)(FILE *, const report_input *, const lf_fit_result *);
    const report_input *in;
    const lf_fit_result *r;
} fit_output;

static void
fit_output_write(FILE *f, const void *ctx)
{
    const fit_output *o = ctx;
    o->writer(f, o->in, o->r);
}

/* Write path (with its provenance sidecar when command_line is not NULL). */
static void
write_file(const char *path, void (*writer)(FILE *, const report_input *, const lf_fit_result *),
           const report_input *in, const lf_fit_result *r, const char *command_line)
{
    fit_output o;
    o.writer = writer;
    o.in = in;
    o.r = r;
    if (command_line != NULL)
        cli_write_file_sidecar("fit", path, command_line, fit_output_write, &o);
    else
        cli_write_file("fit", path, fit_output_write, &o);
}

/* Check --plot and --report before fitting (exit 2 on a bad value). */
static void
figures_check(const char *plotdir, const char *report)
{
    struct stat st;
    if (plotdir != NULL && *plotdir == '\0')
        cli_die(CLI_EXIT_USAGE, "fit: --plot needs a folder (e.g. --plot figures)");
    /* a file (not a folder) where the figures would go: said before the fit */
    if (plotdir != NULL && stat(plotdir, &st) == 0 && !S_ISDIR(st.st_mode))
        cli_die(CLI_EXIT_FAIL, "fit: --plot %s: that is a file, not a folder (name a folder "
                "for the figures)", plotdir);
    if (plotdir != NULL && report != NULL && cli_same_place(plotdir, report))
        cli_die(CLI_EXIT_USAGE, "fit: --plot %s and --report %s name the same path: the figures "
                "go into a folder, the report is a file (name them apart)", plotdir, report);
    if (report != NULL) {
        size_t len = strlen(report);
        if (len < 5 || (strcmp(report + len - 5, ".html") != 0 && strcmp(report + len - 4, ".htm") != 0))
            cli_die(CLI_EXIT_USAGE, "fit: --report %s: the report is a web page, FILE.html", report);
    }
}

static void
note_fit_output(const char *path)
{
    cli_output_note("fit", path);
}

/* Note every file that --plot DIR will write for ncurves curves as an
 * output (cli_output_note): once the inputs are read, so that one of them
 * named like a figure (curve1.svg, overview.dat, provenance.json) is
 * refused with exit status 2 before anything is written. */
static void
figures_note(const char *plotdir, size_t ncurves)
{
    if (plotdir != NULL)
        cli_plot_files(plotdir, ncurves, note_fit_output);
}

/* `layerfit fit --plot DIR --report FILE.html` (either may be NULL),
 * checked by figures_check before the fit: draw the figures (plotfit.c)
 * and write the interactive page (page.c); gnuplot missing is said on
 * stderr without failing. */
static void
figures(const char *plotdir, const char *report, const report_input *in, const lf_fit_input *d,
        const lf_read_opts *ro, const lf_fit_result *res, const char *command_line)
{
    char msg[1400];

    if (plotdir != NULL) {
        cli_figures figs = { 0, NULL, NULL };
        int st = cli_plot_fit(plotdir, d->n, d->curves, res, d, command_line, &figs, msg,
                              sizeof msg);
        cli_figures_free(&figs);
        if (st < 0)         /* a folder or file not made, gnuplot failed */
            cli_die(CLI_EXIT_FAIL, "fit: %s", msg);
        if (st > 0)         /* no gnuplot: scripts and data written */
            cli_say("fit: %s", msg);
    }
    if (report != NULL && cli_page_fit(report, in, res, d, ro, msg, sizeof msg) != 0)
        cli_die(CLI_EXIT_FAIL, "fit: %s", msg);
}

int
cli_fit(int argc, char **argv, const char *command_line)
{
    fit_args a = { NULL, NULL, 0, { NAN, NAN, NAN, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 } };
    lf_fit_options *fo = lf_fit_options_alloc();
    const char *plot_dir = NULL, *report_html = NULL;
    cli_opt opts[4 + CLI_FIT_NOPTS + 1] = {
        { "json", CLI_STRING, &a.json }, { "curves", CLI_STRING, &a.curves },
        { "plot", CLI_STRING, &plot_dir }, { "report", CLI_STRING, &report_html },
    };
    int npos, help, status, misfit = 0;
    lf_fit_request req;
    lf_warnings notes = { 0, NULL };
    lf_fit_input d;
    lf_fit_result r;
    lf_error err;
    report_input in;
    lf_assumption assumed[16];
    size_t no;
    char bad[256];

    if (fo == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    no = 4 + cli_fit_opts(fo, opts + 4);
    opts[no].name = NULL;
    {
        /* a batch's options, asked of a single fit: say where they belong */
        static const char *const batch[] = { "--out", "--threads", "--shard", "--progress",
                                             "--quiet" };
        cli_refuse_options(argc, argv, batch, sizeof batch / sizeof batch[0],
                           "fit --batch PLAN; a single fit writes --json, --curves, --plot and "
                           "--report");
    }
    cli_parse("fit", argc, argv, opts, &npos, &help);
    if (help) {
        fputs(usage_text, stdout);
        fputs(cli_fit_help, stdout);
        fputs(exit_text, stdout);
        lf_fit_options_free(fo);
        return CLI_EXIT_OK;
    }
    if (npos < 1)
        cli_die(CLI_EXIT_USAGE, "fit: give a plan, or curve files with their probe (see "
                "'layerfit fit --help')");
    figures_check(plot_dir, report_html);
    cli_output_note("fit", a.json);
    cli_output_note("fit", a.curves);
    cli_output_note_sidecar("fit", a.curves);
    cli_output_note("fit", report_html);
    cli_output_folder_check("fit", a.json);
    cli_output_folder_check("fit", a.curves);
    cli_output_folder_check("fit", report_html);
    cli_output_folder_check("fit", plot_dir);      /* its parent: --plot makes one level */
    cli_fit_request(fo, &req);
    if (npos == 1 && cli_probe_given(fo) != NULL && cli_reads_as_plan(argv[0]))
        cli_die(CLI_EXIT_USAGE, "fit: %s applies to curve files; %s is a plan, which gives each "
                "curve's probe in its row (columns k, R, b, interface, tip, half_angle, prefactor; "
                "R may read 'header'): fit it without the probe options", cli_probe_given(fo),
                argv[0]);
    cli_fit_probe(fo, &a.probe, &a.single);
    read_input(npos, argv, fo, &req, &d);
    figures_note(plot_dir, d.n);
    status = lf_fit_request_run(&req, &d, 0, &r, &notes, &err);
    if (status != LF_OK && status != LF_ENOCONV)
        /* a model that cannot be evaluated (LF_ENUMERIC) is a fit that
         * cannot be made: 3, as one that does not converge */
        cli_die(status == LF_EDATA || status == LF_EINVAL ? CLI_EXIT_USAGE
                : status == LF_ENOMEM || status == LF_EIO ? CLI_EXIT_FAIL : CLI_EXIT_NOCONV,
                "fit: %s", err.msg);
    cli_print_warnings(&notes);
    lf_warnings_free(&notes);
    in.settings = &req.fit;
    in.model_request = req.model;
    in.model_tol = req.model_auto ? req.choose.tol : NAN;
    in.curves = d.curves;
    in.origin = d.origin;
    in.command_line = command_line;
    in.assumed = assumed;
    in.nassumed = lf_fit_assumptions(&req, &d, &r, assumed, sizeof assumed / sizeof assumed[0]);
    in.observed = d.observed;
    in.window = d.window;
    if (!to_stdout(a.json) && !to_stdout(a.curves)) {
        /* standard output carries the report unless it carries an output
         * (--json -, --curves -): then that alone, for the next program */
        print_input_notes(&a, &d);
        report_text(stdout, &in, &r);
    }
    if (a.json != NULL)
        write_file(a.json, report_json, &in, &r, NULL);
    if (a.curves != NULL)
        write_file(a.curves, report_curves, &in, &r, command_line);
    figures(plot_dir, report_html, &in, &d, req.input.read, &r, command_line);
    if (status == LF_OK && cli_disagreeing(&r, bad, sizeof bad) > 0) {
        cli_say("fit: converged, but the model does not describe curve%s %s "
                "(DISAGREES): the values are those of a model that does not fit, not a "
                "measurement (check k, R, b, interface and segment)",
                strchr(bad, ',') != NULL ? "s" : "", bad);
        misfit = 1;
    }
    if (status == LF_ENOCONV)
        cli_say("fit: %s%s", r.stop_reason,
                r.stop == LF_STOP_ITERATIONS
                ? " (--max-iter N allows more; a fit that creeps along a kink of the cost may "
                  "still not settle)" : "");
    lf_fit_result_free(&r);
    lf_fit_input_free(&d);
    lf_fit_options_free(fo);
    return status != LF_OK ? CLI_EXIT_NOCONV : misfit ? CLI_EXIT_MISFIT : CLI_EXIT_OK;
}
