/* cli/html.c: `layerfit fit ... --report FILE.html`, one self-contained page.
 *
 * The page holds the material parameters with their errors and intervals,
 * the correlation matrix, what the data determine (identifiability) and
 * what to be wary of (validity warnings), fit statistics, a table of the
 * curves and every figure of cli/plotfit.c inlined as SVG (element ids are
 * prefixed per figure so that several gnuplot SVGs can share one page).  The
 * command line and version that produced it are at the top.  Without
 * gnuplot the page is written all the same, with a note where the figures
 * would be. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"
#include "plot.h"

/* ------------------------------------------------------------------------
 * HTML helpers.
 * --------------------------------------------------------------------- */

/* Text as HTML: markup characters escaped, invalid UTF-8 as U+FFFD. */
static void
esc_put(void *ctx, const char *s, size_t n)
{
    FILE *f = ctx;
    size_t i;
    for (i = 0; i < n; i++) {
        switch (s[i]) {
        case '&': fputs("&amp;", f); break;
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '"': fputs("&quot;", f); break;
        case '\'': fputs("&#39;", f); break;
        default: fputc(s[i], f);
        }
    }
}

static void
esc(FILE *f, const char *s)
{
    cli_text_clean(s, 1, esc_put, f);
}

static void
td_text(FILE *f, const char *s)
{
    fputs("<td>", f);
    esc(f, s);
    fputs("</td>", f);
}

static void
td_human(FILE *f, double x, const char *unit)
{
    char buf[64];
    if (!isfinite(x)) {
        fputs("<td class=\"na\">&ndash;</td>", f);
        return;
    }
    fputs("<td class=\"num\">", f);
    esc(f, cli_human(buf, sizeof buf, x, unit));
    fputs("</td>", f);
}

/* x with prec significant digits and a suffix ("" or " %"). */
static void
td_num(FILE *f, double x, int prec, const char *suffix)
{
    if (!isfinite(x)) {
        fputs("<td class=\"na\">&ndash;</td>", f);
        return;
    }
    fprintf(f, "<td class=\"num\">%.*g%s</td>", prec, x, suffix);
}

static void
warning_list(FILE *f, const lf_warnings *w, const char *cls, const char *prefix)
{
    size_t i;
    for (i = 0; i < w->n; i++) {
        fprintf(f, "<li class=\"%s\">", cls);
        if (prefix != NULL)
            esc(f, prefix);
        esc(f, w->msg[i]);
        fputs("</li>\n", f);
    }
}

static const char style[] =
    "body{font-family:Helvetica,Arial,sans-serif;max-width:1100px;margin:2em auto;"
    "padding:0 1em;color:#222;line-height:1.4}\n"
    "h1{font-size:1.6em;margin-bottom:.2em}h2{font-size:1.25em;border-bottom:1px solid #ccc;"
    "padding-bottom:.2em;margin-top:1.6em}\n"
    "code.cmd{display:block;background:#f4f4f4;padding:.6em;border-radius:4px;"
    "white-space:pre-wrap;word-break:break-all}\n"
    "table{border-collapse:collapse;margin:.5em 0;font-size:.92em}\n"
    "th,td{border:1px solid #ccc;padding:.25em .6em;text-align:left}\n"
    "th{background:#eef2f6}td.num{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}\n"
    "td.na{text-align:center;color:#999}div.wide{overflow-x:auto}\n"
    "li.ident{color:#1b4f72}li.warn{color:#9a3c00}\n"
    "figure{margin:1.2em 0;border:1px solid #ddd;padding:.5em}\n"
    "figure svg{width:100%;height:auto;display:block}\n"
    "figcaption{font-size:.9em;color:#555;margin-top:.3em}\n"
    "p.note{background:#fff4e0;border-left:4px solid #e67e22;padding:.5em}\n"
    "span.ok{color:#1e8449}span.bad{color:#b03a2e;font-weight:bold}\n";

/* ------------------------------------------------------------------------
 * Sections.
 * --------------------------------------------------------------------- */

static void
parameter_row(FILE *f, const char *name, const lf_fit_estimate *e, const char *unit)
{
    char buf[64], bound[128], why[256];
    const char *status, *words, *bounded = cli_bound_text(e, name, unit, bound, sizeof bound);

    if (e->upper_bound_only)
        status = "upper bound only (adhesion below the noise)";
    else if (bounded != NULL)
        status = bounded[0] == '\0' ? "not determined: the data do not bound it"
                 : isfinite(e->ci95[0]) ? "not determined: bounded only from below"
                                        : "not determined: bounded only from above";
    else if (!e->free && e->determined)
        status = "fixed";
    else if (!e->determined && e->why != NULL) {
        snprintf(why, sizeof why, "not determined: %s", e->why);
        status = why;
    }
    else if (!e->determined)
        status = "not determined by the data";
    else
        status = "fitted";
    fprintf(f, "<tr><th>%s</th>", name);
    if (unit[0] != '\0') {
        td_human(f, e->upper_bound_only ? NAN : e->value, unit);
        td_human(f, e->se, unit);
    } else {
        td_num(f, e->upper_bound_only ? NAN : e->value, 4, "");
        td_num(f, e->se, 2, "");
    }
    td_num(f, e->free && e->determined && e->value != 0 ? 100.0 * e->se / fabs(e->value) : NAN,
           2, " %");
    if (isfinite(e->ci95[0]) && isfinite(e->ci95[1]) && (e->free || e->upper_bound_only)) {
        fputs("<td class=\"num\">", f);
        if (unit[0] != '\0') {
            esc(f, cli_human(buf, sizeof buf, e->ci95[0], unit));
            fputs(" &ndash; ", f);
            esc(f, cli_human(buf, sizeof buf, e->ci95[1], unit));
        } else {
            fprintf(f, "%.4f &ndash; %.4f", e->ci95[0], e->ci95[1]);
        }
        if ((words = cli_interval_words(e, 1)) != NULL)
            fprintf(f, " (%s)", words);
        fputs("</td>", f);
    } else if (bounded != NULL && bounded[0] != '\0') {
        fputs("<td class=\"num\">", f);
        esc(f, bounded);
        fputs(" (profile likelihood)</td>", f);
    } else {
        fputs("<td class=\"na\">&ndash;</td>", f);
    }
    td_text(f, status);
    fputs("</tr>\n", f);
}

static void
parameters(FILE *f, const lf_fit_result *r)
{
    fputs("<section id=\"parameters\">\n<h2>Material parameters</h2>\n"
          "<table id=\"parameter-table\">\n<tr><th>parameter</th><th>value</th>"
          "<th>standard error</th><th>relative</th><th>95 % interval</th><th>status</th></tr>\n", f);
    parameter_row(f, "w (work of adhesion)", &r->w, "J/m²");
    parameter_row(f, "E* (effective modulus)", &r->Estar, "Pa");
    parameter_row(f, "nu (Poisson&#39;s ratio)", &r->nu, "");
    if (isfinite(r->M.value))
        parameter_row(f, "M = Z E* (bonded curves)", &r->M, "Pa");
    if (r->corr_time > 1.5)
        fprintf(f, "</table>\n<p>Standard errors are scaled by sqrt(chi²/dof &times; "
                   "correlation time %.3g) = %.3g: neighbouring residuals are correlated.</p>\n"
                   "</section>\n", r->corr_time, r->se_scale);
    else
        fprintf(f, "</table>\n<p>Standard errors are scaled by sqrt(chi²/dof) = %.3g.</p>\n"
                   "</section>\n", r->se_scale);
}

static void
correlations(FILE *f, const lf_fit_result *r)
{
    size_t i, j;

    fputs("<section id=\"correlations\">\n<h2>Correlations</h2>\n", f);
    if (r->npar == 0 || r->corr == NULL) {
        fputs("<p>No free parameters.</p>\n</section>\n", f);
        return;
    }
    fputs("<div class=\"wide\"><table id=\"correlation-table\">\n<tr><th></th>", f);
    for (j = 0; j < r->npar; j++) {
        fputs("<th>", f);
        esc(f, r->names[j]);
        fputs("</th>", f);
    }
    fputs("</tr>\n", f);
    for (i = 0; i < r->npar; i++) {
        fputs("<tr><th>", f);
        esc(f, r->names[i]);
        fputs("</th>", f);
        for (j = 0; j < r->npar; j++) {
            double c = r->corr[i * r->npar + j];
            if (!isfinite(c)) {
                fputs("<td class=\"na\">&ndash;</td>", f);
                continue;
            }
            /* red for positive, blue for negative, paler when weaker */
            fprintf(f, "<td class=\"num\" style=\"background:rgba(%s,%.2f)\">%.3f</td>",
                    c >= 0 ? "192,57,43" : "27,108,168", 0.6 * fabs(c), c);
        }
        fputs("</tr>\n", f);
    }
    fputs("</table></div>\n</section>\n", f);
}

static void
assessment(FILE *f, const lf_fit_result *r)
{
    size_t j, nw = r->warnings.n;

    fputs("<section id=\"identifiability\">\n<h2>What the data determine</h2>\n<ul>\n", f);
    warning_list(f, &r->identifiability, "ident", NULL);
    fputs("</ul>\n</section>\n", f);
    for (j = 0; j < r->ncurves; j++)
        nw += r->curves[j].warnings.n;
    fputs("<section id=\"warnings\">\n<h2>Validity warnings</h2>\n", f);
    if (nw == 0) {
        fputs("<p><span class=\"ok\">none</span></p>\n</section>\n", f);
        return;
    }
    fputs("<ul>\n", f);
    warning_list(f, &r->warnings, "warn", NULL);
    for (j = 0; j < r->ncurves; j++) {
        char prefix[64];
        snprintf(prefix, sizeof prefix, "curve %zu: ", j + 1);
        warning_list(f, &r->curves[j].warnings, "warn", prefix);
    }
    fputs("</ul>\n</section>\n", f);
}

static void
statistics(FILE *f, const lf_fit_result *r)
{
    fputs("<section id=\"statistics\">\n<h2>Fit</h2>\n<table id=\"fit-table\">\n", f);
    fputs("<tr><th>model</th>", f);
    td_text(f, r->model);
    fputs("</tr>\n<tr><th>method</th>", f);
    td_text(f, r->method);
    fprintf(f, "</tr>\n<tr><th>converged</th><td><span class=\"%s\">%s</span></td></tr>\n",
            r->converged ? "ok" : "bad", r->converged ? "yes" : "no");
    fputs("<tr><th>stop reason</th>", f);
    td_text(f, r->stop_reason);
    fprintf(f, "</tr>\n<tr><th>iterations / evaluations</th><td class=\"num\">%zu / %zu</td></tr>\n",
            r->iterations, r->evaluations);
    fprintf(f, "<tr><th>chi² / dof</th><td class=\"num\">%.4g / %zu = %.4g</td></tr>\n",
            r->chi2, r->dof, r->dof ? r->chi2 / (double) r->dof : NAN);
    fprintf(f, "<tr><th>free parameters</th><td class=\"num\">%zu</td></tr>\n", r->npar);
    fputs("</table>\n</section>\n", f);
}

/* "value ± se", or "value (fixed)". */
static void
td_estimate(FILE *f, double x, double se, int free, const char *unit)
{
    char a[64], b[64];
    fputs("<td class=\"num\">", f);
    if (isnan(x)) {            /* a free offset the data do not determine */
        fputs("not determined</td>", f);
        return;
    }
    esc(f, cli_human(a, sizeof a, x, unit));
    if (!free)
        fputs(" (fixed)", f);
    else if (isfinite(se)) {
        fputs(" &plusmn; ", f);
        esc(f, cli_human(b, sizeof b, se, unit));
    }
    fputs("</td>", f);
}

static void
curves_table(FILE *f, const lf_fit_result *r, const lf_fit_input *in)
{
    size_t j;
    char shape[160];

    fputs("<section id=\"curves\">\n<h2>Curves</h2>\n<div class=\"wide\"><table id=\"curve-table\">\n"
          "<tr><th>#</th><th>file</th><th>probe</th><th>b</th><th>interface</th>"
          "<th>branch</th><th>points</th><th>z0</th><th>F0</th>"
          "<th>noise &sigma;</th><th>rms residual</th><th>rms/&sigma;</th><th>pull-off force</th>"
          "<th>pull-off radius</th><th>b/a at pull-off</th><th>measured adhesion force</th>"
          "<th>detachment work</th><th>contact point (no model)</th>"
          "<th>instrument's E[eff]</th><th>fit window</th></tr>\n", f);
    for (j = 0; j < r->ncurves; j++) {
        const lf_fit_curve_result *c = &r->curves[j];
        fprintf(f, "<tr><td class=\"num\">%zu</td>", j + 1);
        td_text(f, c->name ? c->name : "");
        td_text(f, cli_probe_words(shape, sizeof shape, &c->probe));
        if (cli_model_ignores_b(c->model)) {   /* b inside is only a stand-in */
            td_text(f, "none");
            td_text(f, "half-space");
        } else {
            td_human(f, c->probe.b, "m");
            td_text(f, cli_base_name(c->probe.base));
        }
        td_text(f, c->branch == LF_BRANCH_LOAD ? "load" : "unload");
        fprintf(f, "<td class=\"num\">%zu</td>", c->n);
        td_estimate(f, c->z0, c->z0_se, c->z0_free, "m");
        td_estimate(f, c->F0, c->F0_se, c->F0_free, "N");
        td_human(f, c->sigma, "N");
        td_human(f, c->rms, "N");
        td_num(f, c->sigma > 0 ? c->rms / c->sigma : NAN, 3, "");
        if (c->pulloff_determined) {
            td_human(f, c->pulloff.P_po, "N");
            td_human(f, c->pulloff.a_po, "m");
        } else {
            td_text(f, "not determined (w is not)");
            td_text(f, "not determined");
        }
        if (cli_model_ignores_b(c->model))
            td_text(f, "none");
        else if (c->pulloff_determined)
            td_num(f, c->b_over_a_pulloff, 3, "");
        else
            td_text(f, "not determined");
        if (in != NULL) {   /* what the curve shows without a model */
            const lf_observables *o = &in->observed[j];
            char kept[64];
            td_human(f, o->adhesion_force, "N");
            td_human(f, o->detachment_work, "J");
            td_human(f, o->contact_point, "m");
            if (isfinite(o->instrument_Eeff))
                td_human(f, o->instrument_Eeff, "Pa");
            else
                td_text(f, "not stated");
            snprintf(kept, sizeof kept, "%zu of %zu points", in->window[j].n_kept,
                     in->window[j].n_in);
            td_text(f, in->window[j].active ? kept : "all points");
        }
        fputs("</tr>\n", f);
    }
    fputs("</table></div>\n</section>\n", f);
}

/* Copy an SVG file into the page from its <svg element on, prefixing every
 * id and every reference to one with "fN-". */
static int
inline_svg(FILE *f, const char *path, size_t fig)
{
    lf_input in;
    lf_error err;
    char *buf, *p, *q;
    char prefix[32];
    size_t seq = 0;

    /* opened as every input is: without blocking, a regular file only */
    if (lf_input_read(path, 0, &in, &err) != LF_OK)
        return -1;
    buf = realloc(in.data, in.len + 1);
    if (buf == NULL) {
        lf_input_free(&in);
        return -1;
    }
    buf[in.len] = '\0';
    p = strstr(buf, "<svg");
    if (p == NULL) {
        free(buf);
        return -1;
    }
    snprintf(prefix, sizeof prefix, "f%zu-", fig);
    while (*p) {
        static const char *const pats[] = { "id='", "id=\"", "href='#", "href=\"#", "url(#" };
        size_t k, best = 0;
        char *at = NULL;
        for (k = 0; k < sizeof pats / sizeof pats[0]; k++) {
            q = strstr(p, pats[k]);
            if (q != NULL && (at == NULL || q < at)) {
                at = q;
                best = k;
            }
        }
        if (at == NULL) {
            fputs(p, f);
            break;
        }
        at += strlen(pats[best]);
        fwrite(p, 1, (size_t) (at - p), f);
        fputs(prefix, f);
        /* gnuplot repeats its group ids in every panel of a multiplot;
         * nothing refers to them, so they are numbered apart */
        if (best < 2 && strncmp(at, "gnuplot_", 8) == 0)
            fprintf(f, "%zu-", ++seq);
        p = at;
    }
    free(buf);
    return 0;
}

static void
figures(FILE *f, const char *dir, const cli_figures *figs, const char *note)
{
    size_t k;

    fputs("<section id=\"figures\">\n<h2>Figures</h2>\n", f);
    if (note != NULL) {
        fputs("<p class=\"note\">", f);
        esc(f, note);
        fputs("</p>\n", f);
    }
    for (k = 0; k < figs->n; k++) {
        char path[4096], name[80];
        snprintf(name, sizeof name, "%s.svg", figs->base[k]);
        if (plot_path(path, sizeof path, dir, name) != 0)
            continue;
        if (access(path, R_OK) != 0)
            continue;
        fprintf(f, "<figure class=\"fit-figure\" id=\"figure-%s\">\n", figs->base[k]);
        if (inline_svg(f, path, k + 1) != 0)
            fputs("<p class=\"note\">figure could not be read</p>\n", f);
        fputs("\n<figcaption>", f);
        esc(f, figs->caption[k]);
        fputs("</figcaption>\n</figure>\n", f);
    }
    fputs("</section>\n", f);
}

/* Where the numbers came from: version, command line, inputs and hashes. */
static void
provenance(FILE *f)
{
    size_t i;
    fprintf(f, "<section id=\"provenance\">\n<h2>Provenance</h2>\n<p>layerfit %s</p>\n"
               "<table id=\"input-table\">\n<tr><th>input</th><th>SHA-256</th></tr>\n",
            LF_VERSION);
    for (i = 0; i < cli_inputs_count(); i++) {
        fputs("<tr>", f);
        td_text(f, cli_input_path(i));
        fputs("<td><code>", f);
        esc(f, cli_input_sha256(i));
        fputs("</code></td></tr>\n", f);
    }
    fputs("</table>\n</section>\n", f);
}

static void
unlink_file(const char *path)
{
    (void) unlink(path);
}

/* Remove what cli_plot_fit wrote into a temporary folder, then the folder. */
static void
remove_figures(const char *dir, size_t ncurves)
{
    cli_plot_files(dir, ncurves, unlink_file);
    rmdir(dir);
}

int
cli_html_report(const char *file, const char *plotdir, size_t ncurves,
                const lf_fit_curve *curves, const lf_fit_result *r, const lf_fit_input *in,
                const char *command_line, char *msg, size_t n)
{
    cli_figures figs = { 0, NULL, NULL };
    char tmpdir[4096], note[1200];
    const char *dir = plotdir;
    int have_note = 0, status = 0, slot = -1;
    cli_out out;
    FILE *f;

    if (dir == NULL) {
        const char *t = getenv("TMPDIR");
        snprintf(tmpdir, sizeof tmpdir, "%s/layerfit-report-XXXXXX", t && *t ? t : "/tmp");
        if (mkdtemp(tmpdir) == NULL) {
            snprintf(msg, n, "cannot create a temporary folder for the figures: %s", strerror(errno));
            return -1;
        }
        slot = cli_temp_add(tmpdir, 1);     /* removed, whatever stops the run */
        dir = tmpdir;
    }
    if (cli_plot_fit(dir, ncurves, curves, r, in, command_line, &figs, note, sizeof note) != 0)
        have_note = 1;
    if ((f = cli_out_open(&out, file, msg, n)) == NULL) {
        status = -1;
        goto done;
    }
    fputs("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
          "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n", f);
    fprintf(f, "<meta name=\"generator\" content=\"layerfit %s\">\n<title>layerfit fit: %zu curve%s</title>\n",
            LF_VERSION, r->ncurves, r->ncurves == 1 ? "" : "s");
    fprintf(f, "<style>\n%s</style>\n</head>\n<body>\n", style);
    fputs("<header>\n<h1>layerfit fit report</h1>\n", f);
    fprintf(f, "<p id=\"version\">layerfit %s &middot; model ", LF_VERSION);
    esc(f, r->model);
    fputs(" &middot; method ", f);
    esc(f, r->method);
    fprintf(f, " &middot; %zu curve%s</p>\n<p>Command line:</p>\n<code class=\"cmd\" id=\"command-line\">",
            r->ncurves, r->ncurves == 1 ? "" : "s");
    esc(f, command_line);
    fputs("</code>\n</header>\n", f);
    if (!r->converged) {
        fputs("<p class=\"note\">The fit did not converge: the numbers are where it stopped (", f);
        esc(f, r->stop_reason);
        fputs(").</p>\n", f);
    }
    parameters(f, r);
    assessment(f, r);
    correlations(f, r);
    statistics(f, r);
    curves_table(f, r, in);
    figures(f, dir, &figs, have_note ? note : NULL);
    provenance(f);
    fputs("</body>\n</html>\n", f);
    if (cli_out_commit(&out, msg, n) != 0)
        status = -1;
    if (status == 0 && have_note) {
        snprintf(msg, n, "%s", note);
        status = 1;
    }
done:
    if (plotdir == NULL) {
        remove_figures(dir, ncurves);
        cli_temp_forget(slot);
    }
    cli_figures_free(&figs);
    return status;
}
