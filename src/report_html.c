/* report_html.c: a fit result as the tables of the HTML report -- the
 * material parameters with their errors and intervals, what the data
 * determine, the validity warnings, the correlation matrix, the fit's
 * statistics and a table of the curves -- for the page of `layerfit fit
 * --report` and for a binding's notebook display alike
 * (lf_fit_result_html in layerfit.h), with the page's style sheet. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "internal.h"

static const char report_style[] =
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


const char *
lf_report_css(void)
{
    return report_style;
}

/* The style sheet with every rule confined to <div class="scope">: each
 * selector prefixed by ".scope " (body: the div itself). */
static void
scoped_style(lf_str *f, const char *scope)
{
    const char *p = report_style;

    lf_str_puts(f, "<style>\n");
    while (*p) {
        const char *open = strchr(p, '{'), *close = open ? strchr(open, '}') : NULL;
        const char *sel = p;
        if (close == NULL)
            break;
        while (sel < open) {
            const char *comma = memchr(sel, ',', (size_t) (open - sel));
            const char *end = comma ? comma : open;
            while (sel < end && (*sel == '\n' || *sel == ' '))
                sel++;
            if ((size_t) (end - sel) == 4 && strncmp(sel, "body", 4) == 0)
                lf_str_printf(f, ".%s", scope);
            else
                lf_str_printf(f, ".%s %.*s", scope, (int) (end - sel), sel);
            lf_str_puts(f, comma ? "," : "");
            sel = end + (comma != NULL);
        }
        lf_str_put(f, open, (size_t) (close - open) + 1);
        lf_str_puts(f, "\n");
        p = close + 1;
        while (*p == '\n')
            p++;
    }
    lf_str_puts(f, "</style>\n");
}

/* A model that uses no layer (its scope the half-space). */
static int
halfspace_model(const char *name)
{
    const lf_model_type *t = name != NULL ? lf_model_type_find(name) : NULL;
    return t != NULL && t->scope == LF_SCOPE_HALFSPACE;
}

/* ------------------------------------------------------------------------
 * HTML helpers.
 * --------------------------------------------------------------------- */

/* Where escaped text goes. */
typedef struct {
    void (*put)(void *, const char *, size_t);
    void *ctx;
} html_sink;

/* Markup characters escaped. */
static void
esc_put(void *ctx, const char *s, size_t n)
{
    const html_sink *k = ctx;
    size_t i, from = 0;
    for (i = 0; i < n; i++) {
        const char *e;
        switch (s[i]) {
        case '&': e = "&amp;"; break;
        case '<': e = "&lt;"; break;
        case '>': e = "&gt;"; break;
        case '"': e = "&quot;"; break;
        case '\'': e = "&#39;"; break;
        default: continue;
        }
        k->put(k->ctx, s + from, i - from);
        k->put(k->ctx, e, strlen(e));
        from = i + 1;
    }
    k->put(k->ctx, s + from, n - from);
}

void
lf_html_text(const char *s, void (*put)(void *, const char *, size_t), void *ctx)
{
    html_sink k;

    k.put = put;
    k.ctx = ctx;
    lf_text_clean(s, 1, esc_put, &k);
}

static void
esc(lf_str *f, const char *s)
{
    lf_html_text(s, lf_str_put_cb, f);
}

static void
td_text(lf_str *f, const char *s)
{
    lf_str_puts(f, "<td>");
    esc(f, s);
    lf_str_puts(f, "</td>");
}

static void
td_human(lf_str *f, double x, const char *unit)
{
    char buf[64];
    if (!isfinite(x)) {
        lf_str_puts(f, "<td class=\"na\">&ndash;</td>");
        return;
    }
    lf_str_puts(f, "<td class=\"num\">");
    esc(f, lf_human(buf, sizeof buf, x, unit));
    lf_str_puts(f, "</td>");
}

/* x with prec significant digits and a suffix ("" or " %"). */
static void
td_num(lf_str *f, double x, int prec, const char *suffix)
{
    if (!isfinite(x)) {
        lf_str_puts(f, "<td class=\"na\">&ndash;</td>");
        return;
    }
    lf_str_printf(f, "<td class=\"num\">%.*g%s</td>", prec, x, suffix);
}

static void
warning_list(lf_str *f, const lf_warnings *w, const char *cls, const char *prefix)
{
    size_t i;
    for (i = 0; i < w->n; i++) {
        lf_str_printf(f, "<li class=\"%s\">", cls);
        if (prefix != NULL)
            esc(f, prefix);
        esc(f, w->msg[i]);
        lf_str_puts(f, "</li>\n");
    }
}

/* ------------------------------------------------------------------------
 * Sections.
 * --------------------------------------------------------------------- */

static void
parameter_row(lf_str *f, const char *name, const lf_fit_estimate *e, const char *unit)
{
    char buf[64], bound[128], why[256];
    const char *status, *words, *bounded = lf_bound_text(e, name, unit, bound, sizeof bound);

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
    lf_str_printf(f, "<tr><th>%s</th>", name);
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
        lf_str_puts(f, "<td class=\"num\">");
        if (unit[0] != '\0') {
            esc(f, lf_human(buf, sizeof buf, e->ci95[0], unit));
            lf_str_puts(f, " &ndash; ");
            esc(f, lf_human(buf, sizeof buf, e->ci95[1], unit));
        } else {
            lf_str_printf(f, "%.4f &ndash; %.4f", e->ci95[0], e->ci95[1]);
        }
        if ((words = lf_interval_words(e, 1)) != NULL)
            lf_str_printf(f, " (%s)", words);
        lf_str_puts(f, "</td>");
    } else if (bounded != NULL && bounded[0] != '\0') {
        lf_str_puts(f, "<td class=\"num\">");
        esc(f, bounded);
        lf_str_puts(f, " (profile likelihood)</td>");
    } else {
        lf_str_puts(f, "<td class=\"na\">&ndash;</td>");
    }
    td_text(f, status);
    lf_str_puts(f, "</tr>\n");
}

static void
li_line(void *ctx, const char *line)
{
    lf_str *f = ctx;
    lf_str_puts(f, "<li>");
    esc(f, line);
    lf_str_puts(f, "</li>\n");
}

/* A cell of a spread: relative (w, E*) in %, absolute for nu. */
static void
td_spread(lf_str *f, double x, int m)
{
    if (m == LF_MAT_NU)
        td_num(f, x, 3, "");
    else
        td_num(f, 100.0 * x, 2, " %");
}

/* How the curves differ: the words, then per parameter the single fits'
 * spread, tau and the population's mean and interval. */
static void
heterogeneity(lf_str *f, const lf_fit_result *r)
{
    static const char *const name[3] = { "w", "E*", "nu" };
    static const char *const unit[3] = { "J/m²", "Pa", "" };
    const lf_heterogeneity *h = &r->heterogeneity;
    const lf_population_estimate *pe[3] = { &h->w, &h->Estar, &h->nu };
    char buf[64];
    int m;

    if (h->curves < 2)
        return;
    lf_str_printf(f, "<section id=\"heterogeneity\">\n<h2>How the %zu curves differ</h2>\n<ul>\n",
                  h->curves);
    lf_hetero_lines(h, li_line, f);
    lf_str_puts(f, "</ul>\n<table id=\"heterogeneity-table\">\n<tr><th>parameter</th>"
                "<th>curves alone</th><th>their mean</th><th>their SD</th><th>median</th>"
                "<th>spot-to-spot SD (tau)</th><th>tau 95 %</th><th>population mean</th>"
                "<th>population 95 %</th><th>I²</th><th>p (homogeneous)</th></tr>\n");
    for (m = 0; m < 3; m++) {
        const lf_population_estimate *x = pe[m];
        if (x->n == 0)
            continue;
        lf_str_printf(f, "<tr><th>%s</th><td class=\"num\">%zu</td>", name[m], x->n);
        if (m == LF_MAT_NU) {
            td_num(f, x->mean, 4, "");
            td_num(f, x->sd, 3, "");
            td_num(f, x->median, 4, "");
        } else {
            td_human(f, x->mean, unit[m]);
            td_spread(f, x->mean > 0 ? x->sd / x->mean : NAN, m);
            td_human(f, x->median, unit[m]);
        }
        td_spread(f, x->tau_rel, m);
        if (isfinite(x->tau_rel_ci95[0]) && isfinite(x->tau_rel_ci95[1])) {
            if (m == LF_MAT_NU)
                lf_str_printf(f, "<td class=\"num\">%.3g &ndash; %.3g</td>", x->tau_rel_ci95[0],
                              x->tau_rel_ci95[1]);
            else
                lf_str_printf(f, "<td class=\"num\">%.2g %% &ndash; %.2g %%</td>",
                              100.0 * x->tau_rel_ci95[0], 100.0 * x->tau_rel_ci95[1]);
        } else {
            lf_str_puts(f, "<td class=\"na\">&ndash;</td>");
        }
        if (m == LF_MAT_NU)
            td_num(f, x->population_mean, 4, "");
        else
            td_human(f, x->population_mean, unit[m]);
        if (isfinite(x->population_ci95[0]) && isfinite(x->population_ci95[1])) {
            lf_str_puts(f, "<td class=\"num\">");
            if (m == LF_MAT_NU) {
                lf_str_printf(f, "%.4g &ndash; %.4g", x->population_ci95[0],
                              x->population_ci95[1]);
            } else {
                esc(f, lf_human(buf, sizeof buf, x->population_ci95[0], unit[m]));
                lf_str_puts(f, " &ndash; ");
                esc(f, lf_human(buf, sizeof buf, x->population_ci95[1], unit[m]));
            }
            lf_str_puts(f, "</td>");
        } else {
            lf_str_puts(f, "<td class=\"na\">&ndash;</td>");
        }
        td_num(f, 100.0 * x->I2, 3, " %");
        td_num(f, x->p_homogeneous, 2, "");
        lf_str_puts(f, "</tr>\n");
    }
    lf_str_puts(f, "</table>\n</section>\n");
}

static void
parameters(lf_str *f, const lf_fit_result *r)
{
    lf_str_puts(f, "<section id=\"parameters\">\n<h2>Material parameters</h2>\n"
          "<table id=\"parameter-table\">\n<tr><th>parameter</th><th>value</th>"
          "<th>standard error</th><th>relative</th><th>95 % interval</th><th>status</th></tr>\n");
    parameter_row(f, "w (work of adhesion)", &r->w, "J/m²");
    parameter_row(f, "E* (effective modulus)", &r->Estar, "Pa");
    parameter_row(f, "nu (Poisson&#39;s ratio)", &r->nu, "");
    if (isfinite(r->M.value))
        parameter_row(f, "M = Z E* (bonded curves)", &r->M, "Pa");
    if (r->corr_time > 1.5)
        lf_str_printf(f, "</table>\n<p>Standard errors are scaled by sqrt(chi²/dof &times; "
                   "correlation time %.3g) = %.3g: neighbouring residuals are correlated.</p>\n"
                   "</section>\n", r->corr_time, r->se_scale);
    else
        lf_str_printf(f, "</table>\n<p>Standard errors are scaled by sqrt(chi²/dof) = %.3g.</p>\n"
                   "</section>\n", r->se_scale);
}

static void
correlations(lf_str *f, const lf_fit_result *r)
{
    size_t i, j;

    lf_str_puts(f, "<section id=\"correlations\">\n<h2>Correlations</h2>\n");
    if (r->npar == 0 || r->corr == NULL) {
        lf_str_puts(f, "<p>No free parameters.</p>\n</section>\n");
        return;
    }
    lf_str_puts(f, "<div class=\"wide\"><table id=\"correlation-table\">\n<tr><th></th>");
    for (j = 0; j < r->npar; j++) {
        lf_str_puts(f, "<th>");
        esc(f, r->names[j]);
        lf_str_puts(f, "</th>");
    }
    lf_str_puts(f, "</tr>\n");
    for (i = 0; i < r->npar; i++) {
        lf_str_puts(f, "<tr><th>");
        esc(f, r->names[i]);
        lf_str_puts(f, "</th>");
        for (j = 0; j < r->npar; j++) {
            double c = r->corr[i * r->npar + j];
            if (!isfinite(c)) {
                lf_str_puts(f, "<td class=\"na\">&ndash;</td>");
                continue;
            }
            /* red for positive, blue for negative, paler when weaker */
            lf_str_printf(f, "<td class=\"num\" style=\"background:rgba(%s,%.2f)\">%.3f</td>",
                    c >= 0 ? "192,57,43" : "27,108,168", 0.6 * fabs(c), c);
        }
        lf_str_puts(f, "</tr>\n");
    }
    lf_str_puts(f, "</table></div>\n</section>\n");
}

static void
assessment(lf_str *f, const lf_fit_result *r)
{
    size_t j, nw = r->warnings.n;

    lf_str_puts(f, "<section id=\"identifiability\">\n<h2>What the data determine</h2>\n<ul>\n");
    warning_list(f, &r->identifiability, "ident", NULL);
    lf_str_puts(f, "</ul>\n</section>\n");
    for (j = 0; j < r->ncurves; j++)
        nw += r->curves[j].warnings.n;
    lf_str_puts(f, "<section id=\"warnings\">\n<h2>Validity warnings</h2>\n");
    if (nw == 0) {
        lf_str_puts(f, "<p><span class=\"ok\">none</span></p>\n</section>\n");
        return;
    }
    lf_str_puts(f, "<ul>\n");
    warning_list(f, &r->warnings, "warn", NULL);
    for (j = 0; j < r->ncurves; j++) {
        char prefix[64];
        snprintf(prefix, sizeof prefix, "curve %zu: ", j + 1);
        warning_list(f, &r->curves[j].warnings, "warn", prefix);
    }
    lf_str_puts(f, "</ul>\n</section>\n");
}

static void
statistics(lf_str *f, const lf_fit_result *r)
{
    lf_str_puts(f, "<section id=\"statistics\">\n<h2>Fit</h2>\n<table id=\"fit-table\">\n");
    lf_str_puts(f, "<tr><th>model</th>");
    td_text(f, r->model);
    lf_str_puts(f, "</tr>\n<tr><th>method</th>");
    td_text(f, r->method);
    lf_str_printf(f, "</tr>\n<tr><th>converged</th><td><span class=\"%s\">%s</span></td></tr>\n",
            r->converged ? "ok" : "bad", r->converged ? "yes" : "no");
    lf_str_puts(f, "<tr><th>stop reason</th>");
    td_text(f, r->stop_reason);
    lf_str_printf(f, "</tr>\n<tr><th>iterations / evaluations</th><td class=\"num\">%zu / %zu</td></tr>\n",
            r->iterations, r->evaluations);
    lf_str_printf(f, "<tr><th>chi² / dof</th><td class=\"num\">%.4g / %zu = %.4g</td></tr>\n",
            r->chi2, r->dof, r->dof ? r->chi2 / (double) r->dof : NAN);
    lf_str_printf(f, "<tr><th>free parameters</th><td class=\"num\">%zu</td></tr>\n", r->npar);
    lf_str_puts(f, "</table>\n</section>\n");
}

/* "value ± se", or "value (fixed)". */
static void
td_estimate(lf_str *f, double x, double se, int free, const char *unit)
{
    char a[64], b[64];
    lf_str_puts(f, "<td class=\"num\">");
    if (isnan(x)) {            /* a free offset the data do not determine */
        lf_str_puts(f, "not determined</td>");
        return;
    }
    esc(f, lf_human(a, sizeof a, x, unit));
    if (!free)
        lf_str_puts(f, " (fixed)");
    else if (isfinite(se)) {
        lf_str_puts(f, " &plusmn; ");
        esc(f, lf_human(b, sizeof b, se, unit));
    }
    lf_str_puts(f, "</td>");
}

static void
curves_table(lf_str *f, const lf_fit_result *r)
{
    size_t j;
    char shape[160];

    lf_str_puts(f, "<section id=\"curves\">\n<h2>Curves</h2>\n<div class=\"wide\"><table id=\"curve-table\">\n"
          "<tr><th>#</th><th>file</th><th>probe</th><th>b</th><th>interface</th>"
          "<th>branch</th><th>points</th><th>z0</th><th>F0</th>"
          "<th>noise &sigma;</th><th>rms residual</th><th>rms/&sigma;</th><th>pull-off force</th>"
          "<th>pull-off radius</th><th>b/a at pull-off</th></tr>\n");
    for (j = 0; j < r->ncurves; j++) {
        const lf_fit_curve_result *c = &r->curves[j];
        lf_str_printf(f, "<tr><td class=\"num\">%zu</td>", j + 1);
        td_text(f, c->name ? c->name : "");
        td_text(f, lf_probe_words(shape, sizeof shape, &c->probe));
        if (halfspace_model(c->model)) {   /* b inside is only a stand-in */
            td_text(f, "none");
            td_text(f, "half-space");
        } else {
            td_human(f, c->probe.b, "m");
            td_text(f, c->probe.base == LF_BASE_BONDED ? "bonded" : "frictionless");
        }
        td_text(f, c->branch == LF_BRANCH_LOAD ? "load" : "unload");
        lf_str_printf(f, "<td class=\"num\">%zu</td>", c->n);
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
        if (halfspace_model(c->model))
            td_text(f, "none");
        else if (c->pulloff_determined)
            td_num(f, c->b_over_a_pulloff, 3, "");
        else
            td_text(f, "not determined");
        lf_str_puts(f, "</tr>\n");
    }
    lf_str_puts(f, "</table></div>\n</section>\n");
}


int
lf_fit_result_html(const lf_fit_result *r, const char *scope, char **html, lf_error *err)
{
    lf_str b = { NULL, 0, 0, 0 };

    if (scope != NULL && (scope[0] == '\0' || strspn(scope, "abcdefghijklmnopqrstuvwxyz"
                                                       "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_")
                                              != strlen(scope)))
        return lf_fail(err, LF_EINVAL, "'%s' is not a class name (letters, digits, - and _)",
                       scope);
    if (scope != NULL) {
        lf_str_puts(&b, "<div class=\"");
        esc(&b, scope);
        lf_str_puts(&b, "\">\n");
        scoped_style(&b, scope);
    }
    if (!r->converged) {
        lf_str_puts(&b, "<p class=\"note\">The fit did not converge: the numbers are where it "
                    "stopped (");
        esc(&b, r->stop_reason);
        lf_str_puts(&b, ").</p>\n");
    }
    heterogeneity(&b, r);
    parameters(&b, r);
    assessment(&b, r);
    correlations(&b, r);
    statistics(&b, r);
    curves_table(&b, r);
    if (scope != NULL)
        lf_str_puts(&b, "</div>\n");
    return lf_str_take(&b, html, err);
}
