/* cli/page.c: the interactive report, one self-contained HTML page.
 *
 *   layerfit fit PLAN --report fit.html                  a single or joint fit
 *   layerfit fit --batch PLAN --out r.csv --report map.html   every fit of a batch
 *   layerfit map r.csv --report map.html                 a batch result
 *
 * The page is the project's own script and style (page.js, page.css,
 * embedded into the command at build time as page_assets.c) and the data
 * as JSON inside <script type="application/json">.  Every '<', '>', '&',
 * U+2028 and U+2029 of that JSON is written as a \u escape, so no file name
 * or metadata can close the script element or become code; the script
 * shows names through textContent only.  A fit's tables are the library's
 * (lf_fit_result_html), in the page as HTML; the script draws the figures.
 *
 * A curve is drawn from its points quantized to `levels` steps of its own
 * depth, force and residual ranges (integers: a third of the bytes of
 * decimal numbers).  A map's curves keep at most MAP_POINTS points: every
 * point near contact and near the lowest force (pull-off), and the lowest
 * and highest force of each stretch elsewhere (the envelope the eye sees);
 * the full data are in the curve files, named in the results. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "report.h"

/* page_assets.c, made by the Makefile from page.js and page.css */
extern const unsigned char cli_page_js[], cli_page_css[];
extern const size_t cli_page_js_len, cli_page_css_len;

#define FIT_POINTS 20000    /* a single fit's curves: all points up to this */
#define FIT_GRID 400        /* its model curves */
#define FIT_LEVELS 1000000L
#define MAP_POINTS 64       /* a map's curves */
#define MAP_GRID 48
#define MAP_LEVELS 1000L

/* ------------------------------------------------------------------------
 * JSON into the page.
 * --------------------------------------------------------------------- */

/* JSON text as it may stand inside a script element: '<', '>', '&' and
 * the line separators U+2028, U+2029 (JavaScript line ends in old engines)
 * as \u escapes.  Outside strings JSON holds none of them, so the text
 * parses to the same value. */
static void
json_safe(FILE *f, const char *s, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++) {
        unsigned char c = (unsigned char) s[i];
        if (c == '<' || c == '>' || c == '&')
            fprintf(f, "\\u%04x", c);
        else if (c == 0xE2 && i + 2 < n && (unsigned char) s[i + 1] == 0x80
                 && ((unsigned char) s[i + 2] == 0xA8 || (unsigned char) s[i + 2] == 0xA9)) {
            fprintf(f, "\\u%04x", (unsigned char) s[i + 2] == 0xA8 ? 0x2028 : 0x2029);
            i += 2;
        } else
            fputc(c, f);
    }
}

static void
jnum(FILE *f, double x)
{
    if (isfinite(x))
        fprintf(f, "%.9g", x);
    else
        fputs("null", f);
}

static void
jstr(FILE *f, const char *s)
{
    cli_json_string(f, s != NULL ? s : "");
}

/* ------------------------------------------------------------------------
 * One curve for drawing.
 * --------------------------------------------------------------------- */

static int
cmp_size(const void *a, const void *b)
{
    size_t x = *(const size_t *) a, y = *(const size_t *) b;
    return x < y ? -1 : x > y;
}

/* Indices (file order) of at most maxpts points of c to draw: all when
 * there are no more; else every point within 2% of the depth range of the
 * contact point z0 and of the lowest force (pull-off), every n-th where
 * those are more than two thirds of maxpts, and the lowest and highest
 * force of each stretch of the rest.  Returns how many, into keep (room
 * for maxpts + 2). */
static size_t
pick(const lf_fit_curve *c, double z0, size_t maxpts, size_t *keep)
{
    double lo = INFINITY, hi = -INFINITY, zmin, near;
    size_t i, k = 0, imin = 0, nnear = 0, stride, nb, b;
    unsigned char *mark;

    if (c->n <= maxpts) {
        for (i = 0; i < c->n; i++)
            keep[i] = i;
        return c->n;
    }
    for (i = 0; i < c->n; i++) {
        lo = fmin(lo, c->depth[i]);
        hi = fmax(hi, c->depth[i]);
        if (c->force[i] < c->force[imin])
            imin = i;
    }
    zmin = c->depth[imin];
    near = 0.02 * (hi - lo);
    if ((mark = calloc(c->n, 1)) == NULL) {
        keep[0] = 0;
        return 1;
    }
    for (i = 0; i < c->n; i++)
        if ((isfinite(z0) && fabs(c->depth[i] - z0) <= near) || fabs(c->depth[i] - zmin) <= near) {
            mark[i] = 1;
            nnear++;
        }
    stride = nnear > 2 * maxpts / 3 ? (nnear + 2 * maxpts / 3 - 1) / (2 * maxpts / 3) : 1;
    for (i = 0, b = 0; i < c->n; i++)
        if (mark[i] && b++ % stride == 0)
            keep[k++] = i;
    keep[k++] = imin;
    nb = (maxpts - k) / 2;
    for (b = 0; b < nb; b++) {
        size_t from = c->n * b / nb, to = c->n * (b + 1) / nb, jlo = SIZE_MAX, jhi = SIZE_MAX;
        for (i = from; i < to; i++) {
            if (mark[i])
                continue;
            if (jlo == SIZE_MAX || c->force[i] < c->force[jlo])
                jlo = i;
            if (jhi == SIZE_MAX || c->force[i] > c->force[jhi])
                jhi = i;
        }
        if (jlo != SIZE_MAX)
            keep[k++] = jlo;
        if (jhi != SIZE_MAX && jhi != jlo)
            keep[k++] = jhi;
    }
    free(mark);
    qsort(keep, k, sizeof *keep, cmp_size);
    for (i = 0, b = 0; i < k; i++)      /* imin may be there twice */
        if (b == 0 || keep[i] != keep[b - 1])
            keep[b++] = keep[i];
    return b;
}

/* "[lo,hi]" and x[idx[i]] (or x[i] without idx) as integers 0..levels
 * over [lo, hi]. */
static void
quantized(FILE *f, const char *key, const double *x, const size_t *idx, size_t n, double lo,
          double hi, long levels)
{
    double scale = hi > lo ? (double) levels / (hi - lo) : 0.0;
    size_t i;
    fprintf(f, "\"%s\":[", key);
    for (i = 0; i < n; i++) {
        double v = x[idx ? idx[i] : i];
        fprintf(f, i ? ",%ld" : "%ld", isfinite(v) ? lround((v - lo) * scale) : -1L);
    }
    fputc(']', f);
}

static void
pair_json(FILE *f, double a, double b)
{
    fputc('[', f);
    jnum(f, a);
    fputc(',', f);
    jnum(f, b);
    fputc(']', f);
}

/* The start of a drawn set of points: {"q": levels, "z": [lo, hi], "f":
 * [lo, hi] (its brace left open). */
static void
scale_json(FILE *f, long levels, double zlo, double zhi, double flo, double fhi)
{
    fprintf(f, "{\"q\":%ld,\"z\":", levels);
    pair_json(f, zlo, zhi);
    fputs(",\"f\":", f);
    pair_json(f, flo, fhi);
}

static void
widen(double *lo, double *hi, const double *x, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        if (isfinite(x[i])) {
            *lo = fmin(*lo, x[i]);
            *hi = fmax(*hi, x[i]);
        }
}

/* Curve j of a fit for the page's script: {"q": levels, "z": [lo, hi],
 * "f": [lo, hi], "r": [lo, hi] (SI: m, N, N), "n": points in the fit,
 * "z0", "F0": the offsets it is drawn with (lf_fit_figure_curve),
 * "pz", "pf", "pr": the drawn points' depth, force and residual, "mz":
 * the model's first and last depth (SI; its depths are evenly spaced),
 * "mf": its forces, "mc": its classes (a digit per point: 0 out of contact,
 * 1 stable, 2 unstable under force control), "po": the model's pull-off
 * point [z, F] or null}, the closing brace the caller's (others_json may
 * add to it); {"q": 0 without memory. */
static void
plot_json(FILE *f, const lf_fit_result *res, size_t j, const lf_fit_curve *c, size_t maxpts,
          size_t grid, long levels)
{
    const lf_fit_curve_result *cr = &res->curves[j];
    lf_fit_figure fig;
    lf_error err;
    size_t *keep = malloc((maxpts + 2) * sizeof *keep), nk, i;
    double *z = malloc(grid * sizeof *z), *F = malloc(grid * sizeof *F);
    double *resid = malloc((c->n ? c->n : 1) * sizeof *resid);
    int *cls = malloc(grid * sizeof *cls), have = 0;
    double zpo = NAN, Fpo = NAN, zlo = INFINITY, zhi = -INFINITY, flo = INFINITY, fhi = -INFINITY;
    double rlo = INFINITY, rhi = -INFINITY;

    if (keep == NULL || z == NULL || F == NULL || resid == NULL || cls == NULL) {
        fputs("{\"q\":0", f);   /* out of memory: an empty plot */
        goto done;
    }
    /* the model where the fit ended, with the offsets it is drawn with */
    if (lf_fit_figure_curve(res, j, c, grid, z, F, cls, &fig, &err) == LF_OK) {
        have = fig.have;
        zpo = fig.z_po;
        Fpo = fig.F_po;
    } else
        fig.z0 = fig.F0 = NAN;
    nk = pick(c, fig.z0, maxpts, keep);
    for (i = 0; i < c->n; i++)
        resid[i] = cr->fitted != NULL ? c->force[i] - cr->fitted[i] : NAN;
    widen(&zlo, &zhi, c->depth, c->n);
    widen(&flo, &fhi, c->force, c->n);
    widen(&rlo, &rhi, resid, c->n);
    if (have) {
        widen(&zlo, &zhi, z, grid);
        widen(&flo, &fhi, F, grid);
    }
    scale_json(f, levels, zlo, zhi, flo, fhi);
    fputs(",\"r\":", f);
    pair_json(f, rlo, rhi);
    fprintf(f, ",\"n\":%zu,\"z0\":", c->n);
    jnum(f, fig.z0);
    fputs(",\"F0\":", f);
    jnum(f, fig.F0);
    fputc(',', f);
    quantized(f, "pz", c->depth, keep, nk, zlo, zhi, levels);
    fputc(',', f);
    quantized(f, "pf", c->force, keep, nk, flo, fhi, levels);
    fputc(',', f);
    quantized(f, "pr", resid, keep, nk, rlo, rhi, levels);
    if (have) {
        fputs(",\"mz\":", f);       /* the grid is even in depth: its ends */
        pair_json(f, z[0], z[grid - 1]);
        fputc(',', f);
        quantized(f, "mf", F, NULL, grid, flo, fhi, levels);
        fputs(",\"mc\":\"", f);
        for (i = 0; i < grid; i++)
            fputc('0' + cls[i], f);
        fputc('"', f);
    }
    fputs(",\"po\":", f);
    if (isfinite(zpo) && isfinite(Fpo))
        pair_json(f, zpo, Fpo);
    else
        fputs("null", f);
done:
    free(keep);
    free(z);
    free(F);
    free(resid);
    free(cls);
}

/* Point i of c is one the fit left out: of another segment, or of the
 * fitted one outside its window w (NULL: none). */
static int
left_out(const lf_curve *c, size_t i, lf_branch fitted, const lf_window_placed *w)
{
    if (!isfinite(c->depth[i]) || !isfinite(c->force[i]))
        return 0;
    if (c->segment[i] != fitted)
        return 1;
    return w != NULL && w->active
           && !(c->depth[i] >= w->depth_lo && c->depth[i] <= w->depth_hi
                && c->force[i] >= w->force_lo && c->force[i] <= w->force_hi);
}

/* The points of curve j's file that the fit left out (the approach, hold,
 * or retract when the approach was fitted, and the fitted segment's points
 * outside its window), read again from the file with the fit's read
 * options and drawn greyed: ,"o": {"q", "z", "f" as above, "pz", "pf",
 * "s": a digit per point, its lf_segment, or 3 outside the window}.
 * Nothing when the file cannot be read again as it was (a pipe, or changed
 * since: its SHA-256 differs) or no point was left out. */
static void
others_json(FILE *f, const lf_fit_input *d, size_t j, const lf_read_opts *ro, lf_branch fitted,
            size_t maxpts, long levels)
{
    const lf_window_placed *w = d->window != NULL ? &d->window[j] : NULL;
    lf_read_opts o;
    lf_file *file = NULL;
    lf_curve *c = NULL;
    lf_error err;
    double zlo = INFINITY, zhi = -INFINITY, flo = INFINITY, fhi = -INFINITY;
    size_t i, n = 0, stride, *keep = NULL, k = 0;

    if (d->names == NULL || d->names[j] == NULL)
        return;
    if (ro != NULL)
        o = *ro;
    else
        memset(&o, 0, sizeof o);
    if (d->format != NULL)
        o.format = d->format[j];
    if (lf_file_open(d->names[j], 0, &o, &file, NULL, &err) != LF_OK)
        return;
    if (strcmp(lf_file_sha256(file), d->sha256[j]) != 0
        || lf_file_curve(file, d->index != NULL && d->index[j] > 0 ? (size_t) d->index[j] : 0, &c,
                         NULL, &err) != LF_OK
        || c->segment == NULL)
        goto done;
    for (i = 0; i < c->n; i++)
        if (left_out(c, i, fitted, w)) {
            n++;
            zlo = fmin(zlo, c->depth[i]);
            zhi = fmax(zhi, c->depth[i]);
            flo = fmin(flo, c->force[i]);
            fhi = fmax(fhi, c->force[i]);
        }
    if (n == 0 || (keep = malloc(n * sizeof *keep)) == NULL)
        goto done;
    stride = (n + maxpts - 1) / maxpts;
    for (i = 0, n = 0; i < c->n; i++)
        if (left_out(c, i, fitted, w) && n++ % stride == 0)
            keep[k++] = i;
    fputs(",\"o\":", f);
    scale_json(f, levels, zlo, zhi, flo, fhi);
    fputc(',', f);
    quantized(f, "pz", c->depth, keep, k, zlo, zhi, levels);
    fputc(',', f);
    quantized(f, "pf", c->force, keep, k, flo, fhi, levels);
    fputs(",\"s\":\"", f);
    for (i = 0; i < k; i++)     /* 3: the fitted segment, outside the window */
        fputc(c->segment[keep[i]] == fitted ? '3'
              : '0' + (c->segment[keep[i]] <= 2 ? c->segment[keep[i]] : 2), f);
    fputs("\"}", f);
done:
    free(keep);
    lf_curve_free(c);
    lf_file_close(file);
}

/* ------------------------------------------------------------------------
 * The page.
 * --------------------------------------------------------------------- */

static void
put_file(void *ctx, const char *s, size_t n)
{
    fwrite(s, 1, n, (FILE *) ctx);
}

/* A number with its unit as a table cell ("–" when there is none). */
static void
td_human(FILE *f, double x, const char *unit)
{
    char buf[64];
    if (!isfinite(x)) {
        fputs("<td class=\"na\">&ndash;</td>", f);
        return;
    }
    fprintf(f, "<td class=\"num\">%s</td>", cli_human(buf, sizeof buf, x, unit));
}

/* What each curve shows without a model, beside the fit's tables: the
 * measured adhesion force, detachment work and contact point, the
 * instrument's own E[eff], and the fit window. */
static void
observed_table(FILE *f, const lf_fit_input *in)
{
    size_t j;

    fputs("<section id=\"observed\">\n<h2>Measured without a model</h2>\n<div class=\"wide\">"
          "<table id=\"observed-table\">\n<tr><th>#</th><th>file</th>"
          "<th>measured adhesion force</th><th>detachment work</th>"
          "<th>contact point (no model)</th><th>deepest indentation</th><th>largest force</th>"
          "<th>instrument's E[eff]</th><th>fit window</th></tr>\n", f);
    for (j = 0; j < in->n; j++) {
        const lf_observables *o = &in->observed[j];
        fprintf(f, "<tr><td class=\"num\">%zu</td><td>", j + 1);
        lf_html_text(in->names[j] ? in->names[j] : "", put_file, f);
        fputs("</td>", f);
        td_human(f, o->adhesion_force, "N");
        td_human(f, o->detachment_work, "J");
        td_human(f, o->contact_point, "m");
        td_human(f, o->max_indentation, "m");
        td_human(f, o->max_force, "N");
        if (isfinite(o->instrument_Eeff))
            td_human(f, o->instrument_Eeff, "Pa");
        else
            fputs("<td>not stated</td>", f);
        if (in->window != NULL && in->window[j].active)
            fprintf(f, "<td>%zu of %zu points</td>", in->window[j].n_kept, in->window[j].n_in);
        else
            fputs("<td>all points</td>", f);
        fputs("</tr>\n", f);
    }
    fputs("</table></div>\n</section>\n", f);
}

/* A memory stream for the page's data (page_write closes it). */
static FILE *
data_open(char **buf, size_t *len, char *msg, size_t n)
{
    FILE *f = open_memstream(buf, len);
    if (f == NULL)
        snprintf(msg, n, "out of memory");
    return f;
}

/* The page around the data, the JSON text in *json (n bytes) written to
 * the memory stream d, closed and freed here: its style, the header
 * (title, version, command line), body (HTML or NULL), the data and the
 * script. */
static int
page_write(const char *file, const char *title, const char *command_line, const char *body,
           const char *after, FILE *d, char **json, size_t *n, char *msg, size_t nmsg)
{
    cli_out out;
    FILE *f;

    if (fclose(d) != 0 || *json == NULL) {
        free(*json);
        snprintf(msg, nmsg, "out of memory");
        return -1;
    }
    if ((f = cli_out_open(&out, file, msg, nmsg)) == NULL) {
        free(*json);
        return -1;
    }
    fprintf(f, "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
               "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
               "<meta name=\"generator\" content=\"layerfit %s\">\n<title>%s</title>\n<style>\n%s",
            LF_VERSION, title, lf_report_css());
    fwrite(cli_page_css, 1, cli_page_css_len, f);
    fprintf(f, "</style>\n</head>\n<body>\n<main id=\"page\">\n<header>\n<h1>%s</h1>\n"
               "<p id=\"version\">layerfit %s</p>\n<code class=\"cmd\" id=\"command-line\">",
            title, LF_VERSION);
    lf_html_text(command_line != NULL ? command_line : "", put_file, f);
    fputs("</code>\n<noscript><p class=\"note\">The figures, maps and the choice of a curve "
          "need JavaScript.</p></noscript>\n</header>\n", f);
    if (body != NULL)       /* a fit's tables, and its figures after them */
        fprintf(f, "%s<section id=\"figures\">\n<h2>Figures</h2>\n</section>\n", body);
    if (after != NULL)
        fputs(after, f);
    fputs("</main>\n<script type=\"application/json\" id=\"lf-data\">", f);
    json_safe(f, *json, *n);
    free(*json);
    fputs("</script>\n<script>\n", f);
    fwrite(cli_page_js, 1, cli_page_js_len, f);
    fputs("</script>\n</body>\n</html>\n", f);
    return cli_out_commit(&out, msg, nmsg);
}

int
cli_page_fit(const char *file, const report_input *in, const lf_fit_result *r,
             const lf_fit_input *d, const lf_read_opts *ro, char *msg, size_t n)
{
    char *buf = NULL, *tables = NULL, *body = NULL, *after = NULL, text[200];
    size_t len = 0, blen = 0, alen = 0, i, j;
    lf_error err;
    FILE *f, *h;
    int st;

    /* what the fit assumed rather than fitted, then the tables: the
     * library's, as every report of a fit says them */
    if (lf_fit_result_html(r, NULL, &tables, &err) != LF_OK) {
        snprintf(msg, n, "%s", err.msg);
        return -1;
    }
    if ((h = open_memstream(&body, &blen)) != NULL) {
        if (in->nassumed > 0) {
            fputs("<section id=\"assumed\">\n<h2>Assumed, not fitted</h2>\n<ul>\n", h);
            for (i = 0; i < in->nassumed; i++) {
                fputs("<li>", h);
                lf_html_text(lf_assumption_text(text, sizeof text, &in->assumed[i], r->ncurves),
                             put_file, h);
                fputs("</li>\n", h);
            }
            fputs("</ul>\n</section>\n", h);
        }
        fputs(tables, h);
        if (fclose(h) != 0) {
            free(body);
            body = NULL;
        }
    }
    lf_free(tables);
    if (body == NULL || (f = data_open(&buf, &len, msg, n)) == NULL) {
        free(body);
        snprintf(msg, n, "out of memory");
        return -1;
    }
    fputs("{\"kind\":\"fit\",\"result\":", f);
    report_json(f, in, r);
    fputs(",\"plots\":[", f);
    for (j = 0; j < r->ncurves; j++) {
        fputs(j ? ",\n" : "\n", f);
        plot_json(f, r, j, &in->curves[j], FIT_POINTS, FIT_GRID, FIT_LEVELS);
        if (d != NULL && j < d->n)
            others_json(f, d, j, ro, r->curves[j].branch, FIT_POINTS, FIT_LEVELS);
        fputc('}', f);
    }
    fputs("]}", f);
    if (d != NULL && d->observed != NULL && (h = open_memstream(&after, &alen)) != NULL) {
        observed_table(h, d);
        if (fclose(h) != 0) {
            free(after);
            after = NULL;
        }
    }
    st = page_write(file, "layerfit fit report", in->command_line, body, after, f, &buf, &len,
                    msg, n);
    free(body);
    free(after);
    return st;
}

/* ------------------------------------------------------------------------
 * Maps: the curves of a batch, kept as each row is handed over.
 * --------------------------------------------------------------------- */

struct cli_page_store {
    size_t n, cap;
    char **fit;         /* per row: {"c": [curves], "p": [plan rows]}, or NULL */
};

cli_page_store *
cli_page_store_new(void)
{
    return calloc(1, sizeof(cli_page_store));
}

void
cli_page_store_free(cli_page_store *s)
{
    size_t i;
    if (s == NULL)
        return;
    for (i = 0; i < s->n; i++)
        free(s->fit[i]);
    free(s->fit);
    free(s);
}

/* A curve as a row of a plan: [file, index, sample, k, R, b, interface,
 * nu, segment] (SI; b and interface empty without a layer). */
static void
plan_row_json(FILE *f, const char *file, long index, const char *sample, const lf_probe *p,
              int layer, double nu, lf_segment seg)
{
    fputc('[', f);
    jstr(f, file);
    fprintf(f, ",%ld,", index);
    jstr(f, sample);
    fputc(',', f);
    jnum(f, p->k);
    fputc(',', f);
    jnum(f, p->R);
    fputc(',', f);
    jnum(f, layer ? p->b : NAN);
    fputc(',', f);
    jstr(f, layer ? cli_base_name(p->base) : "");
    fputc(',', f);
    jnum(f, nu);
    fputc(',', f);
    jstr(f, lf_segment_name(seg));
    fputc(']', f);
}

/* A fit's curves for the page: {"c": [curves], "p": [plan rows] (its
 * closing brace the caller's). */
static void
fit_json(FILE *f, const lf_fit_input *in, const lf_fit_result *res, const char *sample)
{
    size_t j;

    fputs("{\"c\":[", f);
    for (j = 0; in != NULL && res != NULL && j < in->n && j < res->ncurves; j++) {
        fputs(j ? "," : "", f);
        plot_json(f, res, j, &in->curves[j], MAP_POINTS, MAP_GRID, MAP_LEVELS);
        fputc('}', f);
    }
    /* each curve as a row of a plan: file, index, sample, k, R, b,
     * interface, nu, segment (SI; an index names the only curve of a file
     * as well) */
    fputs("],\"p\":[", f);
    for (j = 0; in != NULL && j < in->n; j++) {
        fputs(j ? "," : "", f);
        plan_row_json(f, in->names[j], in->index != NULL ? in->index[j] : 0L, sample,
                      &in->curves[j].probe, in->origin == NULL || in->origin[j].b != NULL, in->nu,
                      in->curves[j].branch);
    }
    fputc(']', f);
}

void
cli_page_store_fit(cli_page_store *s, size_t i, const lf_fit_input *in, const lf_fit_result *res,
                   const char *sample)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f;

    if (s == NULL)
        return;
    if (i >= s->cap) {      /* rows come one at a time: the store grows */
        size_t cap = s->cap ? 2 * s->cap : 1024, k;
        char **fit;
        while (cap <= i)
            cap *= 2;
        if ((fit = realloc(s->fit, cap * sizeof *fit)) == NULL)
            return;
        for (k = s->cap; k < cap; k++)
            fit[k] = NULL;
        s->fit = fit;
        s->cap = cap;
    }
    if (i >= s->n)
        s->n = i + 1;
    if ((f = open_memstream(&buf, &len)) == NULL)
        return;
    fit_json(f, in, res, sample);
    fputc('}', f);
    if (fclose(f) != 0) {
        free(buf);
        return;
    }
    s->fit[i] = buf;
}

/* The results' columns the page shows, where the file has them. */
static const char *const map_columns[] = {
    "fit", "sample", "file", "curves", "status", "model", "x_m", "y_m", "grid_i", "grid_j",
    "w_J_m2", "w_se_J_m2", "w_upper_bound", "Estar_Pa", "Estar_se_Pa", "nu", "nu_se", "M_Pa",
    "chi2_dof", "rms_N", "P_po_N", "adhesion_force_N", "iterations", "message", NULL
};
static const char *const text_columns[] = { "sample", "file", "status", "model", "message", NULL };

static int
is_text(const char *name)
{
    size_t i;
    for (i = 0; text_columns[i] != NULL; i++)
        if (strcmp(name, text_columns[i]) == 0)
            return 1;
    return 0;
}

/* ------------------------------------------------------------------------
 * Maps from a results file alone (`layerfit map RESULTS --report`): each
 * fit of one curve redrawn from its file and the row's probe, offsets and
 * material, the model evaluated by the library as the fit's figures do.
 * --------------------------------------------------------------------- */

/* The results' columns a curve is redrawn from. */
enum {
    RC_FILE, RC_SAMPLE, RC_CURVES, RC_MODEL, RC_W, RC_WUB, RC_E, RC_NU, RC_M, RC_PPO, RC_SHA,
    RC_K, RC_R, RC_B, RC_IFACE, RC_TIP, RC_ANGLE, RC_PREF, RC_SEG, RC_Z0, RC_F0, RC_SLOPE,
    RC_NUH, RC_STATUS, NRC
};
static const char *const rc_name[NRC] = {
    "file", "sample", "curves", "model", "w_J_m2", "w_upper_bound", "Estar_Pa", "nu", "M_Pa",
    "P_po_N", "sha256", "k", "R_m", "b_m", "interface", "tip", "half_angle_rad", "B", "segment",
    "z0_m", "F0_N", "slope_N_m", "nu_held", "status"
};

static double
cell_num(char *const *row, const long *rc, int c)
{
    double v;
    if (rc[c] < 0 || row[rc[c]][0] == '\0' || lf_table_number(row[rc[c]], &v) != LF_OK)
        return NAN;
    return v;
}

/* Row r's fit as the batch's page holds it, with ,"note": why it is not
 * drawn where it is not; the closing brace the caller's.  The material is
 * the one the fit's figures draw with (lf_fit_figure_curve): E* = M with
 * nu = 0 where only M is determined, w = 0 where only its upper bound is. */
static void
row_fit_json(FILE *f, char *const *row, const long *rc)
{
    char path[4096], why[600];
    const char *cell = rc[RC_FILE] >= 0 ? row[rc[RC_FILE]] : "";
    const char *sha = rc[RC_SHA] >= 0 ? row[rc[RC_SHA]] : "";
    const char *model = rc[RC_MODEL] >= 0 ? row[rc[RC_MODEL]] : "";
    lf_probe probe = { 0 };
    lf_plan *plan = NULL;
    lf_fit_input in;
    lf_fit_result res;
    lf_fit_curve_result cr;
    lf_material mat;
    lf_model *m = NULL;
    lf_eval *ev = NULL;
    lf_error err;
    double *delta = NULL, *fitted = NULL, s;
    long index = -1;
    int seg = rc[RC_SEG] >= 0 ? lf_segment_find(row[rc[RC_SEG]]) : -1;
    int tip = rc[RC_TIP] >= 0 ? lf_tip_find(row[rc[RC_TIP]], NULL) : -1;
    size_t i;

    memset(&in, 0, sizeof in);
    why[0] = '\0';
    if (cell_num(row, rc, RC_CURVES) != 1.0) {
        fputs("{\"c\":[],\"p\":[],\"note\":", f);
        jstr(f, "A joint fit of several curves: its curves are not drawn from the results, "
                "nor in the exported plan (the page of `layerfit fit --batch ... --report` "
                "holds them).");
        return;
    }
    probe.k = cell_num(row, rc, RC_K);
    probe.R = cell_num(row, rc, RC_R);
    probe.b = cell_num(row, rc, RC_B);
    probe.base = rc[RC_IFACE] >= 0 && strcmp(row[rc[RC_IFACE]], "bonded") == 0
                 ? LF_BASE_BONDED : LF_BASE_FRICTIONLESS;
    probe.tip = tip >= 0 ? (lf_tip) tip : LF_TIP_POWER;
    probe.angle = cell_num(row, rc, RC_ANGLE);
    probe.B = isfinite(cell_num(row, rc, RC_PREF)) ? cell_num(row, rc, RC_PREF) : 0.0;
    if (!isfinite(probe.k) || seg < 0) {
        fputs("{\"c\":[],\"p\":[],\"note\":", f);
        jstr(f, "No curve to draw: these results do not name the probe (results of an older "
                "layerfit); `layerfit fit --batch ... --report` draws it.");
        return;
    }
    snprintf(path, sizeof path, "%s", cell);
    if (lf_curve_path_split(cell, path, sizeof path, &index) != LF_OK
        || lf_plan_of_file(path, &probe, (lf_segment) seg, &plan, &err) != LF_OK)
        snprintf(why, sizeof why, "cannot read %.300s", cell);
    else {
        lf_input_settings is = lf_input_settings_default();
        plan->rows[0].index = index;
        plan->rows[0].nu = cell_num(row, rc, RC_NUH);
        if (lf_fit_input_from_plan(plan, NULL, 1, &is, &in, NULL, &err) != LF_OK)
            snprintf(why, sizeof why, "%.300s%s%.280s", strstr(err.msg, path) ? "" : path,
                     strstr(err.msg, path) ? "" : ": ", err.msg);
        else if (strcmp(in.sha256[0], sha) != 0)
            snprintf(why, sizeof why, "%.300s has changed since it was fitted (its SHA-256 differs "
                     "from the results')", cell);
    }
    lf_plan_free(plan);
    if (why[0] == '\0' && rc[RC_STATUS] >= 0 && strcmp(row[rc[RC_STATUS]], "error") == 0)
        snprintf(why, sizeof why, "the fit failed before a result");
    if (why[0] != '\0') {
        /* the plan row stays: the curve may still be refitted */
        lf_fit_input_free(&in);
        fputs("{\"c\":[],\"p\":[", f);
        plan_row_json(f, path, index >= 0 ? index : 0L, rc[RC_SAMPLE] >= 0 ? row[rc[RC_SAMPLE]] : "",
                      &probe, isfinite(probe.b), cell_num(row, rc, RC_NUH), (lf_segment) seg);
        fputs("],\"note\":", f);
        snprintf(path, sizeof path, "Not drawn: %s.", why);
        jstr(f, path);
        return;
    }
    /* the fit as its figures need it */
    memset(&res, 0, sizeof res);
    memset(&cr, 0, sizeof cr);
    res.w.value = cell_num(row, rc, RC_W);
    res.w.upper_bound_only = cell_num(row, rc, RC_WUB) == 1.0;
    res.Estar.value = cell_num(row, rc, RC_E);
    res.nu.value = isfinite(cell_num(row, rc, RC_NU)) ? cell_num(row, rc, RC_NU)
                                                     : cell_num(row, rc, RC_NUH);
    res.M.value = cell_num(row, rc, RC_M);
    res.model = model;
    res.ncurves = 1;
    res.curves = &cr;
    cr.probe = in.curves[0].probe;
    cr.branch = in.curves[0].branch;
    cr.n = in.curves[0].n;
    cr.model = model;
    cr.z0 = cell_num(row, rc, RC_Z0);
    cr.F0 = cell_num(row, rc, RC_F0);
    cr.slope = cell_num(row, rc, RC_SLOPE);
    cr.pulloff_determined = isfinite(cell_num(row, rc, RC_PPO));
    cr.pulloff.delta_po = cr.pulloff.delta_detach = cr.pulloff.P_po = NAN;
    s = isfinite(cr.slope) ? cr.slope : 0.0;
    mat.w = isfinite(res.w.value) ? res.w.value : res.w.upper_bound_only ? 0.0 : NAN;
    mat.Estar = res.Estar.value;
    mat.nu = isfinite(res.nu.value) ? res.nu.value : 0.3;
    if (!isfinite(mat.Estar) && isfinite(res.M.value)) {
        mat.Estar = res.M.value;
        mat.nu = 0.0;
    }
    if (isfinite(mat.w) && isfinite(mat.Estar) && isfinite(cr.z0) && isfinite(cr.F0)
        && lf_model_type_find(model) != NULL
        && (m = lf_model_alloc(lf_model_type_find(model), &in.curves[0].probe, &err)) != NULL
        && (delta = malloc((cr.n ? cr.n : 1) * sizeof *delta)) != NULL
        && (fitted = malloc((cr.n ? cr.n : 1) * sizeof *fitted)) != NULL
        && (ev = malloc((cr.n ? cr.n : 1) * sizeof *ev)) != NULL) {
        lf_pulloff po;
        if (lf_model_pulloff(m, &mat, &po, &err) == LF_OK)
            cr.pulloff = po;
        for (i = 0; i < cr.n; i++)
            delta[i] = in.curves[0].depth[i] - cr.z0;
        if (lf_model_eval(m, &mat, cr.branch, cr.n, delta, ev, &err) == LF_OK) {
            for (i = 0; i < cr.n; i++)
                fitted[i] = ev[i].P + cr.F0 + s * delta[i];
            cr.fitted = fitted;
        }
    }
    fit_json(f, &in, &res, rc[RC_SAMPLE] >= 0 ? row[rc[RC_SAMPLE]] : "");
    lf_model_free(m);
    free(delta);
    free(fitted);
    free(ev);
    lf_fit_input_free(&in);
}

int
cli_page_map(const char *file, const char *results, const cli_page_store *s,
             const char *command_line, char *msg, size_t n)
{
    lf_table *t = NULL;
    lf_error err;
    long col[sizeof map_columns / sizeof map_columns[0]], rc[NRC];
    char *buf = NULL;
    size_t len = 0, r, i, ncol = 0;
    FILE *f;

    if (lf_table_read(results, &t, &err) != LF_OK) {
        snprintf(msg, n, "%s", err.msg);
        return -1;
    }
    if ((f = data_open(&buf, &len, msg, n)) == NULL) {
        lf_table_free(t);
        return -1;
    }
    fputs("{\"kind\":\"map\",\"results\":", f);
    jstr(f, results);
    fputs(",\"columns\":[", f);
    for (i = 0; map_columns[i] != NULL; i++)
        if ((col[i] = lf_table_column(t, map_columns[i])) >= 0) {
            fputs(ncol++ ? "," : "", f);
            jstr(f, map_columns[i]);
        }
    fputs("],\"rows\":[", f);
    for (r = 0; r < t->nrows; r++) {
        char *const *row = t->cells + r * t->ncols;
        size_t k = 0;
        fputs(r ? ",\n[" : "\n[", f);
        for (i = 0; map_columns[i] != NULL; i++) {
            double v;
            if (col[i] < 0)
                continue;
            fputs(k++ ? "," : "", f);
            if (is_text(map_columns[i]))
                jstr(f, row[col[i]]);
            else if (row[col[i]][0] != '\0' && lf_table_number(row[col[i]], &v) == LF_OK)
                jnum(f, v);
            else
                fputs("null", f);
        }
        fputc(']', f);
    }
    fputs("],\"summary\":", f);
    {
        /* the batch's population summary beside the results: its JSON as
         * a string, which the script reads where it parses */
        char *path = cli_summary_path(results, "json"), *text = NULL;
        lf_input sj;
        int got = lf_input_read(path, LF_INPUT_TEXT, &sj, &err) == LF_OK;
        if (got && (text = realloc(sj.data, sj.len + 1)) != NULL) {
            text[sj.len] = '\0';
            jstr(f, text);
            free(text);
        } else {
            if (got)
                lf_input_free(&sj);
            fputs("null", f);
        }
        free(path);
    }
    fputs(",\"fits\":[", f);
    for (i = 0; s == NULL && i < NRC; i++)
        rc[i] = lf_table_column(t, rc_name[i]);
    for (r = 0; r < t->nrows; r++) {
        fputs(r ? ",\n" : "\n", f);
        if (s == NULL) {        /* the results alone: each curve from its file */
            row_fit_json(f, t->cells + r * t->ncols, rc);
            fputc('}', f);
        } else
            fputs(r < s->n && s->fit[r] != NULL ? s->fit[r] : "null", f);
    }
    fputs("]}", f);
    lf_table_free(t);
    return page_write(file, "layerfit batch and map report", command_line, NULL, NULL, f, &buf, &len,
                      msg, n);
}
