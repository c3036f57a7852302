/* command.h: what the layerfit command (src/cli/) shares with the library
 * beyond its public interface (layerfit.h): helpers for the command's own
 * reading and writing and words the library's warnings share with it.
 * They are compiled into the library's objects, which the command links,
 * but the installed libraries do not export them and `make install` does
 * not install this header: programs see layerfit.h alone. */
#ifndef LF_COMMAND_H
#define LF_COMMAND_H

#include "layerfit.h"

/* A deflection sensitivity in SI (si_unit "m/A", else m/V) as instruments
 * show it: the number into *shown, its unit returned ("nm/nA", the same
 * number; "nm/V", 1e9 times). */
const char *lf_sensitivity_shown(double si, const char *si_unit, double *shown);

/* What a thin-layer model's result is worth at b/a (thickness over contact
 * radius) in words: NULL up to `limit` (a fit's max_b_over_a, 0.1 by
 * default); "strained" below b = a; from b = a on, the model does not apply
 * (there its force is off by a quarter to a factor 5 against the exact
 * model's, `layerfit model --figure 6`). */
const char *lf_thin_scope(double b_over_a, double limit);

/* A number of option opt's kind from text (LF_OPTION_NUMBER, _COUNT,
 * _QUANTITY in SI) with the fit options' messages ("--NAME: ..."); the
 * command parses every option's number through it. */
int lf_option_number(const lf_option *opt, const char *text, double *x, lf_error *err);

/* A probe as a lab states it, in the options' words (`fit` and `model`):
 * NaN and NULL where not given.  k, tip, half_angle and B state its shape
 * (R from each file's header where R is NaN and the shape uses it); b and
 * interface its layer, neither for a half-space. */
typedef struct {
    double k, R, B, half_angle, b;
    const char *tip, *interface;
    const char *model;        /* the model's name, for messages */
    int halfspace;            /* 1: the model needs no layer */
} lf_probe_statement;
/* 1 when a statement gives the shape (k, tip, half-angle or B). */
int lf_probe_shape_stated(const lf_probe_statement *a);
/* The probe of a statement into *p (R NaN: from the file's header; b NaN:
 * no layer); LF_EINVAL naming only what is missing or contradicts. */
int lf_probe_state(const lf_probe_statement *a, lf_probe *p, lf_error *err);
/* The statement of the fit options (k, R, B, half-angle, b, tip,
 * interface, and the model asked for). */
void lf_fit_options_statement(const lf_fit_options *o, lf_probe_statement *a);

/* A probe's shape as it was stated, in words: "cone, half-angle 35°",
 * "Berkovich tip as its equivalent cone, ...", "sphere, R = 8 µm", "k = 2,
 * R = 8 µm", "k = 1.5, B = 2000 m^-0.5 (f = B r^k)".  Returns buf. */
const char *lf_probe_words(char *buf, size_t n, const lf_probe *p);
/* The model-free observables' column and key names (adhesion_force_N,
 * detachment_work_J, contact_point_m, max_indentation_m, max_force_N,
 * instrument_Eeff_Pa) and their values, in that order. */
#define LF_NOBSERVED 6
extern const char *const lf_observed_keys[LF_NOBSERVED];
void lf_observed_values(const lf_observables *o, double v[LF_NOBSERVED]);

/* A plan already in memory (lf_input_read of path), its curves resolved
 * against path's folder. */
int lf_plan_from_input(const lf_input *in, const char *path, lf_plan **out, lf_warnings *warn,
                       lf_error *err);
/* LF_EDATA at the first row of plan without b and interface (no layer),
 * unless the fit's model (its name, "auto" included) is the half-space. */
int lf_plan_need_layers(const lf_plan *plan, const char *model, lf_error *err);

/* ------------------------------------------------------------------------
 * Text for reports (src/text.c, src/words.c), shared by the library's
 * writers and the command's own.
 * --------------------------------------------------------------------- */

/* A number that reads back exactly ("%.15g", "%.17g" where that is needed)
 * into buf; NaN and Inf as printf writes them.  Returns buf. */
const char *lf_number_text(char buf[40], double x);
/* A number for people with an SI prefix chosen for it:
 * lf_human(buf, n, 1.2e-8, "m") -> "12 nm"; NaN as "undefined".  Returns buf. */
char *lf_human(char *buf, size_t n, double x, const char *unit);
/* 1 when s is valid UTF-8 (lf_utf8_len). */
int lf_utf8_valid(const char *s);
/* Text from data handed to put in pieces: lf_text_clean as one line of
 * valid UTF-8 (control characters as spaces, line breaks kept when
 * keep_newlines, invalid bytes as U+FFFD); lf_json_escape as a JSON string,
 * always valid UTF-8 (invalid bytes become \ufffd); lf_percent_escape as a
 * JSON string of the raw bytes, every byte outside printable ASCII and
 * % " \ as %XX.  NULL is "". */
void lf_text_clean(const char *s, int keep_newlines, void (*put)(void *, const char *, size_t),
                   void *ctx);
void lf_json_escape(const char *s, void (*put)(void *, const char *, size_t), void *ctx);
void lf_percent_escape(const char *s, void (*put)(void *, const char *, size_t), void *ctx);
/* Text as a CSV cell (RFC 4180: quoted when it holds a comma, quote or
 * line break, or starts or ends with a blank; quotes doubled).  Unless raw,
 * text that a spreadsheet would run as a formula (a cell starting with =,
 * +, -, @, tab or CR) gets a leading ' (OWASP, "CSV injection").  Numbers
 * are not written through this: a negative number stays a number. */
void lf_csv_cell(const char *s, int raw, void (*put)(void *, const char *, size_t), void *ctx);
/* The provenance record {"layerfit", "command_line", "inputs"} with indent
 * before each line after the first, into *json (lf_free). */
int lf_provenance_json(const lf_provenance *p, const char *indent, char **json, lf_error *err);

/* Text as HTML (markup characters escaped, control characters as spaces
 * but line breaks, invalid UTF-8 as U+FFFD), handed to put in pieces. */
void lf_html_text(const char *s, void (*put)(void *, const char *, size_t), void *ctx);
/* The HTML report's style sheet (static). */
const char *lf_report_css(void);

/* The value where the fit ended of the free parameter NAME ("w", "E*",
 * "nu", "z0[1]", ...: lf_fit_result.names), NaN when it was not free. */
double lf_fit_result_value(const lf_fit_result *res, const char *name);

/* The words a report puts after an interval for how it was found (NULL: a
 * checked linear interval, nothing said); brief: the HTML table's. */
const char *lf_interval_words(const lf_fit_estimate *e, int brief);
/* How a free estimate's 95% interval was found (JSON ci95_method, the
 * batch's *_ci95_method): "linear (Wald)" or e->interval_method; with no
 * interval, the method that looked for one (a profile that found no
 * bound), else NULL, as for a held parameter. */
const char *lf_interval_method(const lf_fit_estimate *e);
/* What a free estimate that the data do not determine is bounded by, from
 * its profile (text and HTML say the same): into buf "LO < NAME" (bounded
 * only from below), "NAME < HI" (only from above) or "" (not bounded at
 * all, the profile open on both sides); NULL when it is not such an
 * estimate (determined, fixed, an upper bound of w, or never profiled). */
const char *lf_bound_text(const lf_fit_estimate *e, const char *name, const char *unit,
                          char *buf, size_t n);
/* 1 when the reports call curve cr DISAGREES: it is not described by the
 * model (misfit beyond 5% of its force range) or, in a joint fit, it
 * disagrees with the others. */
int lf_curve_disagrees(const lf_fit_curve_result *cr);
/* The curves of a converged r that disagree, as "1, 3" into buf (at most n
 * bytes); their count (0: none, or r did not converge). */
size_t lf_disagreeing(const lf_fit_result *r, char *buf, size_t n);
/* Numbers of the heterogeneity in words: a spread, relative ("12%") or
 * absolute ("0.012", nu); a value of parameter m (LF_MAT_*) in its unit; a
 * p-value ("p = 0.41", "p < 1e-16").  Each returns buf. */
const char *lf_spread_text(char *buf, size_t n, double x, int relative);
const char *lf_param_text(char *buf, size_t n, double x, int m);
const char *lf_p_text(char *buf, size_t n, double p);
/* How the curves of one material differ, in words, one line per call of
 * put: first whether they agree within their errors, then each
 * parameter's spread and population, then the probes (nothing for fewer
 * than two curves).  The text report, the HTML tables and a batch's
 * summary say the same. */
void lf_hetero_lines(const lf_heterogeneity *h, void (*put)(void *, const char *), void *ctx);
/* One assumption in words: "nu = 0.45 (--nu)", "R = 8 µm, curves 1-11
 * (the file headers, chiaro exports)"; ncurves those of the fit. */
const char *lf_assumption_text(char *buf, size_t n, const lf_assumption *a, size_t ncurves);
/* The object "heterogeneity" of the fit's JSON (report_json.c), indent
 * before each line after the first, for a batch's summary; NULL when out
 * of memory (lf_free). */
char *lf_heterogeneity_json(const lf_heterogeneity *h, const char *indent);

/* Length of the valid UTF-8 sequence that starts at s (1..4), or 0 when
 * the bytes there are not UTF-8 (overlong forms and surrogates included). */
size_t lf_utf8_len(const unsigned char *s);
/* lf_input_read (flags: LF_INPUT_STREAM or 0) of a file that may be a text
 * export, a plan or a binary format read as a stream: checked as text as
 * it arrives (LF_INPUT_TEXT) unless its first LF_SNIFF_BYTES are a binary
 * format's (file.c). */
int lf_input_read_sniffed(const char *path, unsigned flags, lf_input *in, lf_error *err);
/* lf_file_kind_of for a file already in memory (name for messages). */
int lf_file_kind_parse(const char *buf, size_t len, const char *name, lf_file_kind *kind,
                       lf_error *err);

/* ------------------------------------------------------------------------
 * Tables (src/table.c): a CSV file read whole, every cell as text -- e.g.
 * the output of `layerfit fit --batch`.  The same line layer as the curve
 * and plan readers (delimiter from the header, '#' comments, quotes).
 * Ownership: *out is the caller's, released by lf_table_free.
 * --------------------------------------------------------------------- */

typedef struct {
    size_t nrows, ncols;
    long header_line;     /* the line of the header */
    char **names;         /* ncols header cells */
    char **cells;         /* nrows x ncols, row-major; "" where a row is short */
    long *line;           /* nrows: the line where each row starts */
    long *col;            /* nrows x ncols: the character column of each cell
                             (0 where a row is short) */
} lf_table;

int lf_table_read(const char *path, lf_table **out, lf_error *err);
void lf_table_free(lf_table *t);
/* The index of the column named name, or -1. */
long lf_table_column(const lf_table *t, const char *name);
/* A number in a cell: LF_OK with *v, or LF_OK with *v = NaN for an empty
 * cell; LF_EFORMAT (and *v = NaN) when the cell is not a number. */
int lf_table_number(const char *cell, double *v);

#endif
