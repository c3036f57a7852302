/* cli.h: what the layerfit command's files share.  Only this layer prints,
 * picks exit codes and adds file:line:column context to library errors. */
#ifndef LF_CLI_H
#define LF_CLI_H

#include <stdio.h>

#include "layerfit.h"

#if defined(__GNUC__)
#define CLI_NORETURN __attribute__((noreturn))
#define CLI_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define CLI_NORETURN
#define CLI_PRINTF(a, b)
#endif

/* Exit statuses of the command. */
enum {
    CLI_EXIT_OK = 0,
    CLI_EXIT_FAIL = 1,      /* a computation failed */
    CLI_EXIT_USAGE = 2,     /* bad command line or bad input file */
    CLI_EXIT_NOCONV = 3     /* a fit did not converge */
};

/* A subcommand: one entry of the table in main.c. */
typedef struct {
    const char *name;
    const char *summary;
    int (*run)(int argc, char **argv);  /* argv[0] is the subcommand name */
} cli_command;

/* Print "layerfit: MESSAGE" on stderr and exit with code. */
CLI_NORETURN void cli_die(int code, const char *fmt, ...) CLI_PRINTF(2, 3);
/* Print a library error as "layerfit: FILE:LINE:COLUMN: message" (the parts
 * that are known) and exit with code. */
CLI_NORETURN void cli_die_error(int code, const lf_error *err);
/* Print warnings as "layerfit: warning: ..." on stderr. */
void cli_print_warnings(const lf_warnings *w);

/* Options.  A value option is "--name VALUE" or "--name=VALUE".  A double
 * target starts as NaN, meaning "not given". */
typedef enum {
    CLI_FLAG,        /* int *, set to 1 */
    CLI_STRING,      /* const char ** */
    CLI_NUMBER,      /* double *, bare number */
    CLI_COUNT,       /* long *, integer >= 0 */
    CLI_LENGTH,      /* double *, SI, through udunits2 */
    CLI_FORCE,
    CLI_ADHESION,
    CLI_PRESSURE
} cli_kind;

typedef struct {
    const char *name;     /* without the leading "--" */
    cli_kind kind;
    void *target;
} cli_opt;

/* Parse argv[1..argc-1] (argv[0] is the subcommand) against opts (ended
 * by a {NULL} entry).  Non-option words are moved to the front of argv
 * and counted in *npos.  "--help" sets *help.  Errors exit with status 2
 * and name the option and an example of a good value. */
void cli_parse(const char *cmd, int argc, char **argv, const cli_opt *opts,
               int *npos, int *help);

/* Parse an interface word ("frictionless", "bonded"); -1 if unknown. */
int cli_base(const char *word);
const char *cli_base_name(lf_base base);

/* Monotonic wall-clock time in seconds, for progress and benchmarks. */
double cli_now(void);

/* Write a number that reads back exactly ("%.17g"); NaN/Inf as given. */
void cli_print_double(FILE *f, double x);
/* Write a number for people with an SI prefix chosen for it:
 * cli_human(buf, n, 1.2e-8, "m") -> "12 nm".  Returns buf. */
char *cli_human(char *buf, size_t n, double x, const char *unit);



/* The subcommands, one file each (src/cli/NAME.c). */
int cli_model(int argc, char **argv);
int cli_fit(int argc, char **argv);
int cli_simulate(int argc, char **argv);
/* `layerfit bench`: speed against error (bench.c). */
int cli_bench(int argc, char **argv);
/* `layerfit bench --coverage`: interval coverage over seeds (coverage.c). */
int cli_coverage(size_t nseeds, const char *scene_name);
/* 1 when the probes are frictionless and bonded together: nu is fitted. */
int cli_probes_free_nu(const lf_probe *p, size_t n);
/* `layerfit model --figure N [--plot FILE]` (figure.c). */
int cli_figure(int figure, const char *plot);
int cli_check(int argc, char **argv);
int cli_map(int argc, char **argv);

/* The fit options a single fit and a batch share: one table, one set of
 * defaults (fit.c).  cli_fit_args_init sets the defaults; cli_fit_opts puts
 * the table's entries into opts (room for CLI_FIT_NOPTS) and returns how
 * many; cli_fit_settings checks the values and fills the fit, model-choice
 * and input settings, returning 1 for --model auto.  Bad values exit 2. */
typedef struct {
    const char *method, *jacobian, *model, *segment, *loss;
    double nu, fix_nu, fix_z0, fix_F0, max_ba, model_tol;
    double guess_w, guess_E, guess_nu, loss_scale;
    long max_iter;
    int slope;
    const char *format, *spring_constant, *sensitivity;  /* how curves are read */
    lf_read_opts read;    /* filled by cli_fit_settings; is->read points here */
} cli_fit_args;
#define CLI_FIT_NOPTS 24
void cli_fit_args_init(cli_fit_args *a);
size_t cli_fit_opts(cli_fit_args *a, cli_opt *opts);
int cli_fit_settings(cli_fit_args *a, lf_fit_settings *s, lf_choose_settings *cs,
                     lf_input_settings *is);
/* The fit options' help lines, shared by both usage texts. */
extern const char cli_fit_help[];

/* Batch fitting (batch.c). */
#define CLI_BATCH_MAX_FAILED 125   /* exit status: failed fits, capped */
typedef struct {
    const char *plan;      /* the plan */
    const char *out;       /* FILE.csv or FILE.jsonl; NULL: CSV on stdout */
    const char *shard;     /* "I/N" or NULL for all */
    long threads;          /* 0: all cores */
    int progress;          /* 1 on, 0 off, -1 when stderr is a terminal */
    int auto_model;        /* 1: choose each fit's models (lf_fit_choose_driver) */
    lf_choose_settings choose;  /* the model choice's settings */
    lf_input_settings input;    /* segment, held offsets */
} cli_batch_opts;
/* Fit every fit of the plan with the settings; returns the exit status
 * (number of failed fits, capped). */
int cli_batch_run(const cli_batch_opts *o, const lf_fit_settings *settings);
/* "I/N" with 1 <= I <= N; -1 when malformed. */
int cli_shard_parse(const char *text, long *index, long *count);
/* `layerfit fit --batch ...` and whether argv asks for it. */
int cli_fit_batch(int argc, char **argv);
int cli_wants_batch(int argc, char **argv);

/* Figures of a fit (plotfit.c): "overview" and "curve1", "curve2", ...
 * each as DIR/NAME.png and DIR/NAME.svg, drawn by DIR/NAME.gp from
 * DIR/NAME.dat.  The names and captions are owned by the struct. */
typedef struct {
    size_t n;
    char (*base)[64];
    char (*caption)[1200];
} cli_figures;
/* Write the scripts and data into dir (created when missing) and run
 * gnuplot on them.  Returns 0, or -1 with a message: when gnuplot is not
 * installed the scripts and data are still written and figs filled. */
int cli_plot_fit(const char *dir, size_t ncurves, const lf_fit_curve *curves,
                 const lf_fit_result *res, cli_figures *figs, char *msg, size_t n);
void cli_figures_free(cli_figures *f);

/* `layerfit fit --plot DIR --report FILE.html` (either may be NULL): draw
 * the figures and write the page; what goes wrong short of an I/O error on
 * the page (gnuplot missing) is said on stderr without failing. */
void cli_fit_figures(const char *plotdir, const char *report, size_t ncurves,
                     const lf_fit_curve *curves, const lf_fit_result *res);
/* Check --plot and --report before fitting (exit 2 on a bad value). */
void cli_fit_figures_check(const char *plotdir, const char *report);

/* The command line as typed (shell-quoted), saved by main() for reports. */
void cli_set_command_line(int argc, char **argv);
const char *cli_get_command_line(void);
/* Write a self-contained HTML report of a fit (html.c) with the figures
 * inlined as SVG; they are drawn into plotdir, or into a temporary folder
 * removed afterwards when plotdir is NULL.  Returns 0; 1 when the page was
 * written without figures (msg says why, e.g. gnuplot missing); -1 with msg
 * when the page could not be written. */
int cli_html_report(const char *file, const char *plotdir, size_t ncurves,
                    const lf_fit_curve *curves, const lf_fit_result *r, char *msg, size_t n);
#endif
