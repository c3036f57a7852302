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
    const lf_assumption *assumed;  /* what the fit assumed (lf_fit_assumptions) */
    size_t nassumed;
    const lf_observables *observed; /* what each curve shows without a model
                                      (lf_observe), or NULL */
    const lf_window_placed *window; /* each curve's fit window, or NULL */
} report_input;

/* People: values with units (cli_human), errors, intervals, correlations,
 * per-probe predictions, warnings in words. */
void report_text(FILE *f, const report_input *in, const lf_fit_result *r);
/* SI, numbers that read back exactly, NaN as null. */
void report_json(FILE *f, const report_input *in, const lf_fit_result *r);
/* depth_m,force_N,fitted_N,residual_N,contact_radius_m,curve */
void report_curves(FILE *f, const report_input *in, const lf_fit_result *r);
/* The interactive page of a fit (page.c): the JSON above and each
 * curve's points and model for its figures, with the segments the fit left
 * out read again from the files of d (NULL: none) with the read options
 * ro.  0, or -1 with msg. */
int cli_page_fit(const char *file, const report_input *in, const lf_fit_result *r,
                 const lf_fit_input *d, const lf_read_opts *ro, char *msg, size_t n);
/* JSON pieces for other reports: a number (NaN and Inf as null) and a
 * string with quotes and control characters escaped. */
void report_json_number(FILE *f, double x);
void report_json_string(FILE *f, const char *s);

#endif
