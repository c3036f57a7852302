/* cli/html.c: `layerfit fit ... --report FILE.html`, one self-contained page.
 *
 * The page holds the material parameters with their errors and intervals,
 * the correlation matrix, what the data determine (identifiability) and
 * what to be wary of (validity warnings), fit statistics, a table of the
 * curves (the library's tables, lf_fit_result_html, with its style sheet)
 * and every figure of cli/plotfit.c inlined as SVG (element ids are
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

static void
put_file(void *ctx, const char *s, size_t n)
{
    fwrite(s, 1, n, (FILE *) ctx);
}

/* Text as HTML: markup characters escaped, invalid UTF-8 as U+FFFD. */
static void
esc(FILE *f, const char *s)
{
    lf_html_text(s, put_file, f);
}

static void
td_text(FILE *f, const char *s)
{
    fputs("<td>", f);
    esc(f, s);
    fputs("</td>", f);
}

/* What the fit assumed rather than fitted, at the top. */
static void
assumptions(FILE *f, const lf_assumption *assumed, size_t n, size_t ncurves)
{
    char buf[200];
    size_t i;

    if (n == 0)
        return;
    fputs("<section id=\"assumed\">\n<h2>Assumed, not fitted</h2>\n<ul>\n", f);
    for (i = 0; i < n; i++) {
        fputs("<li>", f);
        esc(f, lf_assumption_text(buf, sizeof buf, &assumed[i], ncurves));
        fputs("</li>\n", f);
    }
    fputs("</ul>\n</section>\n", f);
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
                const lf_fit_curve *curves, const lf_fit_result *r, const char *command_line,
                const lf_assumption *assumed, size_t nassumed, char *msg, size_t n)
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
    if (cli_plot_fit(dir, ncurves, curves, r, command_line, &figs, note, sizeof note) != 0)
        have_note = 1;
    if ((f = cli_out_open(&out, file, msg, n)) == NULL) {
        status = -1;
        goto done;
    }
    fputs("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
          "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n", f);
    fprintf(f, "<meta name=\"generator\" content=\"layerfit %s\">\n<title>layerfit fit: %zu curve%s</title>\n",
            LF_VERSION, r->ncurves, r->ncurves == 1 ? "" : "s");
    fprintf(f, "<style>\n%s</style>\n</head>\n<body>\n", lf_report_css());
    fputs("<header>\n<h1>layerfit fit report</h1>\n", f);
    fprintf(f, "<p id=\"version\">layerfit %s &middot; model ", LF_VERSION);
    esc(f, r->model);
    fputs(" &middot; method ", f);
    esc(f, r->method);
    fprintf(f, " &middot; %zu curve%s</p>\n<p>Command line:</p>\n<code class=\"cmd\" id=\"command-line\">",
            r->ncurves, r->ncurves == 1 ? "" : "s");
    esc(f, command_line);
    fputs("</code>\n</header>\n", f);
    assumptions(f, assumed, nassumed, r->ncurves);
    {
        /* the tables: the library's, as a notebook shows them */
        lf_error err;
        char *tables;
        if (lf_fit_result_html(r, NULL, &tables, &err) != LF_OK)
            cli_die(CLI_EXIT_FAIL, "fit: %s", err.msg);
        fputs(tables, f);
        lf_free(tables);
    }
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
