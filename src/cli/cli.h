/* cli.h: what the layerfit command's files share.  Only this layer prints,
 * picks exit codes and adds file:line:column context to library errors. */
#ifndef LF_CLI_H
#define LF_CLI_H

#include <stdio.h>

#include "command.h"     /* layerfit.h and what the library shares with
                            the command (not installed) */

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
    CLI_EXIT_FAIL = 1,      /* a failure of the run itself (I/O, memory, a computation) */
    CLI_EXIT_USAGE = 2,     /* bad command line or bad input file or plan */
    CLI_EXIT_NOCONV = 3,    /* a fit did not converge (single fit) */
    CLI_EXIT_SOME_FAILED = 3, /* some fits of a batch failed (error or noconv) */
    CLI_EXIT_MISFIT = 4     /* converged, but the model does not describe a curve
                               (single fit), or a batch row has status misfit */
};

/* A subcommand: one entry of the table in main.c. */
typedef struct {
    const char *name;
    const char *summary;
    /* argv[0] is the subcommand name; command_line is the whole line as
     * typed, shell-quoted (main.c), for the provenance records */
    int (*run)(int argc, char **argv, const char *command_line);
} cli_command;

/* Print "layerfit: MESSAGE" on stderr and exit with code. */
CLI_NORETURN void cli_die(int code, const char *fmt, ...) CLI_PRINTF(2, 3);
/* Print a library error as "layerfit: FILE:LINE:COLUMN: message" (the parts
 * that are known) and exit with code. */
CLI_NORETURN void cli_die_error(int code, const lf_error *err);
/* Print warnings as "layerfit: warning: ..." on stderr; of warnings that
 * differ only in their place and numbers, the first 3 are printed and the
 * rest counted, "... and N more like it (...)" at the end of the run (or
 * when cli_warnings_flush is called). */
void cli_print_warnings(const lf_warnings *w);
void cli_warnings_flush(void);
/* Print "layerfit: MESSAGE" on stderr and go on.  Every message of the
 * command goes through these: control characters and bytes that are not
 * UTF-8 (from a file name, say) are written escaped (\n, \xHH), so that a
 * message stays one line and cannot drive the terminal. */
void cli_say(const char *fmt, ...) CLI_PRINTF(1, 2);

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
    CLI_PRESSURE,
    CLI_ANGLE,       /* double *, rad ("35deg") */
    CLI_FIT,         /* lf_fit_options *: the library's fit option of this name */
    CLI_FIT_FLAG,    /* the same, a flag */
    CLI_DESIGN,      /* lf_design_options *: the library's design option */
    CLI_DESIGN_FLAG  /* the same, a flag */
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
/* 1 when the named model uses no layer thickness or interface (its
 * scope in the model table is the half-space). */
int cli_model_ignores_b(const char *model);

/* A size in bytes: a number >= 1 with an optional unit (B, kB, MB, GB, TB;
 * K or KiB, M or MiB, G or GiB, T or TiB).  0, or -1 when it is not one. */
int cli_parse_size(const char *text, double *bytes);

/* Monotonic wall-clock time in seconds, for progress and benchmarks. */
double cli_now(void);

/* Write a number that reads back exactly ("%.17g"); NaN and inf write
 * nothing (an empty CSV cell; JSON writers write null themselves). */
void cli_print_double(FILE *f, double x);
/* A number for people with an SI prefix (lf_human, command.h). */
#define cli_human lf_human
/* Options of the other mode of `fit` (single or --batch): the first of
 * argv that is one of names[0..n-1] ("--json" or "--json=...") stops the
 * command with exit 2, "fit: --json is for WHY". */
void cli_refuse_options(int argc, char **argv, const char *const *names, size_t n,
                        const char *why);
/* The report's DISAGREES and the curves of a converged fit that do
 * (lf_curve_disagrees, lf_disagreeing: command.h). */
#define cli_curve_disagrees lf_curve_disagrees
#define cli_disagreeing lf_disagreeing
/* The value where the fit ended of a free parameter (lf_fit_result_value). */
#define cli_fitted_value lf_fit_result_value



/* The subcommands, one file each (src/cli/NAME.c). */
int cli_model(int argc, char **argv, const char *command_line);
int cli_fit(int argc, char **argv, const char *command_line);
int cli_simulate(int argc, char **argv, const char *command_line);
/* `layerfit bench`: speed against error (bench.c). */
int cli_bench(int argc, char **argv, const char *command_line);
int cli_cache(int argc, char **argv, const char *command_line);
/* `layerfit bench --coverage`: interval coverage over seeds (coverage.c). */
int cli_coverage(size_t nseeds, const char *scene_name, int calibrate);
/* bench_many.c: `layerfit bench --scene many-curves` (seeds_max 0: its own) */
int cli_bench_many(size_t seeds_max, int quick);
/* 1 when the probes are frictionless and bonded together: nu is fitted. */
int cli_probes_free_nu(const lf_probe *p, size_t n);
/* `layerfit model --figure N [--plot FILE]` (figure.c). */
int cli_figure(int figure, const char *plot);
int cli_check(int argc, char **argv, const char *command_line);
int cli_map(int argc, char **argv, const char *command_line);
/* `layerfit design`: what a planned test would measure (design.c). */
int cli_design(int argc, char **argv, const char *command_line);

/* The fit options a single fit and a batch share: the library's table
 * (lf_fit_option_table), one set of defaults.  cli_fit_opts puts one entry
 * per option into opts (room for CLI_FIT_NOPTS), each setting o by name
 * (lf_fit_options_set), and returns how many; cli_fit_request checks them
 * and fills req (lf_fit_options_request); cli_fit_probe the probe of a
 * single curve or a file of many (lf_fit_options_probe; *single 0 for a
 * plan).  Bad values exit 2. */
#define CLI_FIT_NOPTS 40
size_t cli_fit_opts(lf_fit_options *o, cli_opt *opts);
void cli_fit_request(lf_fit_options *o, lf_fit_request *req);
void cli_fit_probe(const lf_fit_options *o, lf_probe *p, int *single);
/* The fit options' help lines, shared by both usage texts. */
extern const char cli_fit_help[];

/* The words for intervals and bounds (the library's words.c, command.h),
 * so that every report says the same. */
#define cli_interval_words lf_interval_words
#define cli_interval_method lf_interval_method
#define cli_bound_text lf_bound_text
/* How the curves of one material differ, in words (words.c, command.h) */
#define cli_spread_text lf_spread_text
#define cli_param_text lf_param_text
#define cli_p_text lf_p_text
#define cli_hetero_lines lf_hetero_lines
/* Curves named on the command line (files.c): the first probe option
 * given ("--k", ...), or NULL. */
const char *cli_probe_given(const lf_fit_options *o);
/* The probe of a statement (lf_probe_state); dies with status 2 naming
 * only what is missing or contradicts, the command's name first. */
void cli_probe_state(const char *cmd, const lf_probe_statement *a, lf_probe *p);
/* Curve files files[0..n-1] as a plan of one row each (lf_plan_of_files)
 * with the probe of the options, on the request's segment, each file's
 * sample --sample or formed by --group-by, or none; dies with status 2 on
 * a plan among them, a missing probe or a grouping that fails.  The plan
 * is the caller's. */
lf_plan *cli_files_plan(const lf_fit_options *o, const lf_fit_request *req, size_t n,
                        char *const *files);
/* 1 when every row of the plan has the same sample; else 0 with two that
 * differ in *a, *b. */
int cli_plan_one_sample(const lf_plan *plan, const char **a, const char **b);

/* Batch fitting (batch.c). */
#define CLI_MAX_THREADS 1024      /* --threads is 1..CLI_MAX_THREADS */
typedef struct {
    const char *plan;      /* the plan */
    const char *out;       /* FILE.csv or FILE.jsonl; NULL: CSV on stdout */
    const char *report;    /* --report MAP.html (page.c), or NULL */
    const char *shard;     /* "I/N" or NULL for all */
    long threads;          /* 0: all cores */
    int progress;          /* 1 on, 0 off, -1 when stderr is a terminal */
    const lf_fit_request *req;  /* the fit options' settings */
    const char *command_line;   /* for the provenance record */
    lf_plan *files;             /* not NULL: curve files named on the command line
                                   (cli_files_plan), fitted instead of `plan`;
                                   freed by cli_batch_run */
} cli_batch_opts;
/* Fit every fit of the plan with the settings; returns the exit status
 * (CLI_EXIT_OK, or CLI_EXIT_SOME_FAILED with a summary line on stderr). */
int cli_batch_run(const cli_batch_opts *o);
/* "OUT.summary.EXT" beside a batch's results OUT (util.c; OUT without its
 * .csv or .jsonl; the caller frees it; dies without memory). */
char *cli_summary_path(const char *out, const char *ext);
/* "I/N" with 1 <= I <= N; -1 when malformed. */
int cli_shard_parse(const char *text, long *index, long *count);
/* `layerfit fit --batch ...` and whether argv asks for it. */
int cli_fit_batch(int argc, char **argv, const char *command_line);
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
 * gnuplot on them; in (may be NULL) gives each curve's shape words and fit
 * window, drawn as dashed lines.  Returns 0, -1 with a message (a folder or file not
 * made, gnuplot failed), or 1 with a message when gnuplot is not installed
 * (the scripts and data are still written and figs filled). */
int cli_plot_fit(const char *dir, size_t ncurves, const lf_fit_curve *curves,
                 const lf_fit_result *res, const lf_fit_input *in, const char *command_line,
                 cli_figures *figs, char *msg, size_t n);
void cli_figures_free(cli_figures *f);
/* Run dir/script (cwd dir) with its images going to a temporary folder in
 * dir (gnuplot -e "out='.layerfit-XXXXXX/img'"; the script writes
 * out.'.EXT'), then rename each img.EXT to dir/base.EXT: an image is
 * replaced only by one gnuplot finished.  0, or -1 with msg. */
int cli_draw_script(const char *dir, const char *script, const char *base,
                    const char *const *ext, size_t next, char *msg, size_t n);

/* Every file cli_plot_fit writes into dir for ncurves curves (the figures
 * overview and curve1..curveN, each NAME.gp, .dat, .png and .svg, and
 * provenance.json), each path handed to each(). */
void cli_plot_files(const char *dir, size_t ncurves, void (*each)(const char *path));

/* The interactive report of many fits (page.c): the curves of a batch
 * kept as each row is handed over, one at a time (cli_page_store_fit: row
 * i of the results, its fit's input and result, either NULL when it failed
 * before, and its sample), then the page written from the results CSV, the
 * population summary beside it (cli_summary_path, where there is one) and
 * the store (NULL: the results alone).  0, or -1 with msg. */
typedef struct cli_page_store cli_page_store;
cli_page_store *cli_page_store_new(void);
void cli_page_store_fit(cli_page_store *s, size_t i, const lf_fit_input *in,
                        const lf_fit_result *res, const char *sample);
void cli_page_store_free(cli_page_store *s);
int cli_page_map(const char *file, const char *results, const cli_page_store *s,
                 const char *command_line, char *msg, size_t n);

/* ---- Outputs and inputs (output.c, read.c) -------------------------------
 * Every output file goes through cli_out: a temporary file in the same
 * folder (registered for removal on exit or a signal: cli_temp_add),
 * renamed into place by cli_out_commit after fflush, fsync and a check of
 * every write; cli_out_discard (or exit) removes it. */
typedef struct cli_out {
    FILE *f;
    char *path;             /* the file replaced (a link's target) */
    char *name;             /* the output as named (for its sidecar) */
    char *tmp;
    int slot;               /* cli_temp_add's, or -1 */
    int direct;             /* written in place: standard output ("-"), a
                               pipe or a device (nothing there to keep) */
} cli_out;
/* Open path for writing (NULL with msg when not possible, or when path is
 * a noted input).  "-" is standard output; a symbolic link is followed (its
 * target replaced, the link kept); a pipe or device is written in place,
 * opened without blocking (a FIFO with no reader is waited for at most
 * LF_STREAM_WAIT seconds, then refused). */
FILE *cli_out_open(cli_out *o, const char *path, char *msg, size_t n);
/* Exit 1 (before any work) when the folder path would be written in does
 * not exist ("-" and a bare name need none). */
void cli_output_folder_check(const char *cmd, const char *path);
/* Finish and rename into place: 0, or -1 with msg (the temp is removed). */
int cli_out_commit(cli_out *o, char *msg, size_t n);
/* Commit o together with its provenance sidecar NAME.provenance.json (for
 * CSV and JSON Lines outputs; command_line for its record): both temporaries are written and checked
 * before either is renamed, both renames happen under a lock on the
 * folder with signals held, and a second rename that fails undoes the
 * first, so the two always describe each other.  An output written in
 * place (standard output, a pipe, a device) gets no sidecar.  0, or -1
 * with msg (nothing replaced). */
int cli_out_commit_sidecar(cli_out *o, const char *command_line, char *msg, size_t n);
void cli_out_discard(cli_out *o);
/* Put the finished file from in place as to (a symbolic link to: its
 * target, as cli_out_open does; across file systems by a copy): 0, or -1
 * with msg.  For files another program wrote (gnuplot's images). */
int cli_put_in_place(const char *from, const char *to, char *msg, size_t n);
/* PATH's temporary name ".NAME.XXXXXX" in its folder (NAME cut so that
 * it fits in NAME_MAX), malloc'ed. */
int cli_tmp_name(const char *path, char **tmp);
/* cli_out_open + writer + commit; dies with status 1 on failure.  The
 * _sidecar form commits with the provenance sidecar (cli_out_commit_sidecar). */
void cli_write_file(const char *cmd, const char *path, void (*writer)(FILE *, const void *),
                    const void *ctx);
void cli_write_file_sidecar(const char *cmd, const char *path, const char *command_line,
                            void (*writer)(FILE *, const void *), const void *ctx);
/* Die (status 2) when path exists and force is 0, or when it is an input:
 * for commands that make a folder of new files (simulate, map --synthetic),
 * called for every file before the first is written. */
void cli_refuse_existing(const char *cmd, const char *path, int force);
/* Flush and close stdout at the end of a run: 0, or -1 after a message. */
int cli_stdout_close(void);

/* Outputs declared before anything is read, inputs noted as they are read:
 * an output that is the same file (device and inode) as an input is refused
 * with exit status 2 from whichever call comes second, and so is an output
 * that is the same file as an earlier output of the run (by device and
 * inode, or by the real path of its folder and its name).  What can be
 * known about writing it is checked too, before any work: an empty name or
 * one longer than NAME_MAX (exit 2); a link to nothing, a folder, an
 * immutable file, a folder that cannot be written, a FIFO that no reader
 * opens (exit 1). */
void cli_output_note(const char *cmd, const char *path);
/* The same for the provenance sidecar PATH.provenance.json of an output
 * (cli_out_commit_sidecar); nothing for NULL, "-", a pipe or a device. */
void cli_output_note_sidecar(const char *cmd, const char *path);
void cli_input_guard(const char *cmd, const char *path);
/* 1 when paths a and b (which need not exist) name the same place: the
 * same name in the same real folder. */
int cli_same_place(const char *a, const char *b);
/* 1 when path is the same file as a noted input (for files that are put in
 * place by rename, such as gnuplot's images: checked again just before). */
int cli_is_input(const char *path);
/* Record an input (and its SHA-256, or NULL) for provenance and the guard. */
void cli_input_note(const char *path, const char *sha256);
size_t cli_inputs_count(void);
const char *cli_input_path(size_t i);
const char *cli_input_sha256(size_t i);
/* {"layerfit": VERSION, "command_line": ..., "inputs": [{"file", "sha256"}]}
 * with indent before each line after the first; command_line as main()
 * passed it to the subcommand. */
void cli_provenance_json(FILE *f, const char *indent, const char *command_line);
/* A CSV cell as lf_csv_cell writes it (quoted where needed, a cell a
 * spreadsheet would run as a formula made text) unless cli_csv_raw
 * (--csv-raw) is set. */
extern int cli_csv_raw;
void cli_csv_cell(const char *s, void (*put)(void *, const char *, size_t), void *ctx);
/* The same into f. */
void cli_put_csv_cell(FILE *f, const char *s);
/* The run's provenance record for the library's writers: its arrays
 * point at the noted inputs (cli_provenance_free releases the arrays). */
void cli_provenance_of(const char *command_line, lf_provenance *p);
void cli_provenance_free(lf_provenance *p);

/* Text from data (the library's escapes, command.h: lf_json_escape,
 * lf_text_clean, ...).  cli_json_string: a JSON string, always valid UTF-8
 * (invalid bytes become U+FFFD).  cli_gnuplot_string: a single-quoted
 * gnuplot string ('' for ', control characters as spaces, invalid UTF-8
 * as ?).  cli_put_clean / cli_text_clean: one line of valid UTF-8 (control
 * characters as spaces, invalid bytes as U+FFFD). */
#define cli_text_clean lf_text_clean
#define cli_json_escape lf_json_escape
void cli_put_clean(FILE *f, const char *s);
void cli_json_string(FILE *f, const char *s);
void cli_gnuplot_string(FILE *g, const char *s);

/* ---- Other programs and temporaries (spawn.c, temps.c) ------------------
 * No shell ever runs: cli_spawn starts argv[0] (looked up along PATH) with
 * argv as its arguments (posix_spawnp), in folder dir (NULL: here), with
 * how: CLI_SPAWN_STDIN (c->in: a pipe to its standard input),
 * CLI_SPAWN_STDOUT (c->out: a pipe from its standard output),
 * CLI_SPAWN_STDERR_TO_OUT (its standard error there too), CLI_SPAWN_QUIET
 * (its output to /dev/null).  0, or -1 with errno.  cli_child_wait closes
 * the pipes and returns the program's exit status (-1: it did not exit
 * normally, or could not be waited for).  cli_have_program: 1 when name
 * is an executable file along PATH. */
#define CLI_SPAWN_STDIN 1u
#define CLI_SPAWN_STDOUT 2u
#define CLI_SPAWN_STDERR_TO_OUT 4u
#define CLI_SPAWN_QUIET 8u
typedef struct {
    long pid;
    FILE *in, *out;
} cli_child;
int cli_spawn(cli_child *c, const char *const *argv, const char *dir, unsigned how);
int cli_child_wait(cli_child *c);
int cli_have_program(const char *name);
/* Temporaries of the run (files, or folders with what they hold), removed
 * at exit and on SIGINT, SIGTERM, SIGHUP, SIGQUIT or SIGPIPE (then the
 * signal is raised again), unless forgotten first (committed or removed by
 * their owner).  cli_temp_add returns a slot for cli_temp_forget (-1 when
 * the table is full: the path is then only the caller's to remove).
 * cli_temp_child names a program to stop with the run (0: none).
 * cli_signals_hold / _release bracket what a signal must not cut in two
 * (the renames of an output and its sidecar). */
void cli_signals_install(void);
int cli_temp_add(const char *path, int is_dir);
void cli_temp_forget(int slot);
void cli_temp_child(long pid);
void cli_signals_hold(void);
void cli_signals_release(void);
/* Remove a folder and everything in it, without a shell (nftw): 0, or -1
 * when something is left. */
int cli_remove_tree(const char *dir);

/* Reading (read.c).  The fewest points of a segment worth fitting: one more
 * than the most parameters a fit can have (w, E*, nu, z0, F0); `check` and
 * every fit refuse a curve with fewer. */
#define CLI_MIN_POINTS LF_FIT_MIN_POINTS
/* A plan already in memory, its curves resolved against path's folder. */
int cli_plan_from(const lf_input *in, const char *path, lf_plan **out, lf_warnings *warn,
                  lf_error *err);
/* Read a plan (stream allowed), note it as an input; dies with status 2. */
lf_plan *cli_plan_load(const char *cmd, const char *path);
/* 1 when path is a regular file that reads as a plan (for a hint when it
 * was given as a curve). */
int cli_reads_as_plan(const char *path);
/* Exit with status 2 naming the first row of plan without b and interface
 * (no layer) unless the fit's model is the half-space (model: its name). */
void cli_plan_need_layers(const lf_plan *plan, const char *model);
/* ---- cli/observed.c: model-free observables and fit windows in words ---- */

/* The library's words (command.h). */
#define cli_probe_words lf_probe_words
#define CLI_NOBSERVED LF_NOBSERVED
#define cli_observed_keys lf_observed_keys
#define cli_observed_values lf_observed_values
/* The report's lines of a curve's observables and its instrument's own
 * result, beside the fit's pull-off (cr may be NULL). */
void cli_observed_text(FILE *f, const lf_observables *o, const lf_fit_curve_result *cr);
/* The report's line of a curve's fit window as stated and what it kept
 * (nothing when the window keeps everything). */
void cli_window_text(FILE *f, const lf_window_placed *w, const lf_observables *o);

#endif
