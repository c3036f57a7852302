/* report.h: writers of a fit result for the layerfit command: the readable
 * report, the JSON file and the per-point curves CSV. */
#ifndef LF_REPORT_H
#define LF_REPORT_H

#include <stdio.h>

#include "layerfit.h"

/* What the fit was asked, for the report's "free / fixed" lines. */
typedef struct {
    const lf_fit_settings *settings;
    const lf_fit_curve *curves;    /* the data, for the curves CSV */
    const char *model_request;     /* --model as given ("auto", "exact", ...) */
    double model_tol;              /* --model-tol of auto, NaN otherwise */
    const lf_curve_origin *origin; /* where each curve's probe R, b and AFM
                                      constants came from, or NULL */
    const char *command_line;      /* as main() passed it, for provenance */
    const char *const *format;     /* each curve's reader ("chiaro", ...), or NULL */
    const char *nu_source;         /* where a held nu came from ("--nu", "the
                                      plan's nu column"), or NULL */
    const char *z0_source, *F0_source; /* "--fix-z0" / "--fix-F0" when an
                                      option holds every curve's, else NULL
                                      (a held one is then the plan's) */
} report_input;

/* A value the fit assumed rather than fitted (held, or a probe radius
 * read from a file's header): parameter, its value in SI and unit, the
 * curves it concerns (first..last, 1-based; 0, 0: every curve) and where
 * it came from. */
typedef struct {
    const char *name;
    double value;
    const char *unit;
    size_t first, last;
    char source[96];
} report_assumption;

/* The assumptions of a fit into out[0..max-1]; returns how many. */
size_t report_assumptions(const report_input *in, const lf_fit_result *r,
                          report_assumption *out, size_t max);
/* One assumption in words: "nu = 0.45 (--nu)", "R = 8 µm, curves 1-11
 * (file headers, chiaro exports)". */
const char *report_assumption_text(char *buf, size_t n, const report_assumption *a,
                                   const lf_fit_result *r);
/* The heterogeneity of a fit as a JSON object (the fit's JSON, a batch's
 * summary); indent is the current indentation. */
void report_json_heterogeneity(FILE *f, const lf_heterogeneity *h, const char *indent);

/* People: values with units (cli_human), errors, intervals, correlations,
 * per-probe predictions, warnings in words. */
void report_text(FILE *f, const report_input *in, const lf_fit_result *r);
/* SI, numbers that read back exactly, NaN as null. */
void report_json(FILE *f, const report_input *in, const lf_fit_result *r);
/* depth_m,force_N,fitted_N,residual_N,contact_radius_m,curve */
void report_curves(FILE *f, const report_input *in, const lf_fit_result *r);
/* JSON pieces for other reports: a number (NaN and Inf as null) and a
 * string with quotes and control characters escaped. */
void report_json_number(FILE *f, double x);
void report_json_string(FILE *f, const char *s);

#endif
