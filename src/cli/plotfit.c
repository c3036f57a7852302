/* cli/plotfit.c: the figures of a fit (`layerfit fit --plot DIR`).
 *
 * Per curve, after the seed paper's Fig. 3: the measured points, the fitted
 * model with its force-controlled stable part (dP/ddelta > 0) solid and its
 * unstable part dashed, the baseline out of contact, the pull-off point, and
 * the residuals in a panel below.  One overview puts every curve of a joint
 * fit on shared axes (indentation delta = z - z0 in nm, force in a unit
 * chosen for the data).  Each figure is drawn by a gnuplot script kept next
 * to it with its data: DIR/NAME.gp reads DIR/NAME.dat and writes NAME.png
 * and NAME.svg, so `cd DIR && gnuplot NAME.gp` redraws it after restyling. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"
#include "plot.h"

#define GRID 400   /* points of a model curve */

static const char *const palette[] = { "#1b6ca8", "#c0392b", "#27ae60", "#8e44ad",
                                       "#d35400", "#2c3e50", "#16a085", "#7f8c8d" };
#define NPAL (sizeof palette / sizeof palette[0])

/* A force unit for values up to fmax: scale (N per unit) and name. */
static void
force_unit(double fmax, double *scale, const char **name)
{
    static const struct { double s; const char *n; } u[] = {
        { 1.0, "N" }, { 1e-3, "mN" }, { 1e-6, "µN" }, { 1e-9, "nN" }, { 1e-12, "pN" }
    };
    size_t i;
    for (i = 0; i < sizeof u / sizeof u[0] - 1; i++)
        if (fmax >= u[i].s)
            break;
    *scale = u[i].s;
    *name = u[i].n;
}

static const char *
base_name(const char *path)
{
    const char *s;
    if (path == NULL || *path == '\0')
        return "curve";
    s = strrchr(path, '/');
    return s ? s + 1 : path;
}

/* A value for a title: "not determined" for NaN (no NaN ever reaches a
 * figure's text). */
static const char *
value_text(char *buf, size_t n, double x, const char *unit)
{
    if (!isfinite(x)) {
        snprintf(buf, n, "not determined");
        return buf;
    }
    return cli_human(buf, n, x, unit);
}

/* A data block with nothing to draw still needs a line, or gnuplot would
 * not count it as an index: "- -", which gnuplot reads as no point (and no
 * NaN reaches any output). */
#define NO_POINT "- -\n"

/* One curve's model on a grid of indentations, in instrument coordinates
 * (the library's lf_fit_figure_curve). */
typedef struct {
    double z[GRID], F[GRID];
    int cls[GRID];          /* 0 baseline (no contact), 1 stable, 2 unstable */
    int have;               /* 0 when the model could not be evaluated */
    double z_po, F_po;      /* pull-off point, NaN if none */
} model_curve;

static void
model_for(const lf_fit_curve *c, size_t j, const lf_fit_result *res, model_curve *mc)
{
    lf_fit_figure fig;
    lf_error err;

    mc->have = 0;
    mc->z_po = mc->F_po = NAN;
    if (lf_fit_figure_curve(res, j, c, GRID, mc->z, mc->F, mc->cls, &fig, &err) != LF_OK)
        return;
    mc->have = fig.have;
    mc->z_po = fig.z_po;
    mc->F_po = fig.F_po;
}

/* Write the model points of class cls as one data set, contiguous runs
 * separated by a blank line; the boundary points are shared so that the
 * parts join.  xshift is subtracted from z.  Returns the points written. */
static size_t
put_class(FILE *f, const model_curve *mc, int cls, double xshift, double fscale)
{
    size_t i, n = 0;
    int in = 0;
    for (i = 0; i < GRID; i++) {
        int here = mc->cls[i] == cls
                   || (i > 0 && mc->cls[i - 1] == cls)
                   || (i + 1 < GRID && mc->cls[i + 1] == cls);
        if (here) {
            fprintf(f, "%.9g %.9g\n", (mc->z[i] - xshift) * 1e9, mc->F[i] / fscale);
            n++;
            in = 1;
        } else if (in) {
            fputc('\n', f);
            in = 0;
        }
    }
    if (n == 0)
        fputs(NO_POINT, f);
    return n;
}

/* dir/name through the atomic writer (output.c). */
static FILE *
open_in(cli_out *o, const char *dir, const char *name, char *msg, size_t n)
{
    char path[4096];
    if (plot_path(path, sizeof path, dir, name) != 0) {
        snprintf(msg, n, "%s/%s: path too long", dir, name);
        return NULL;
    }
    return cli_out_open(o, path, msg, n);
}

/* The lines every script starts with: a loop over both terminals.  The
 * images go to OUT.png and OUT.svg, OUT being the figure's name unless the
 * caller sets it (gnuplot -e "out='...'"): layerfit draws into a temporary
 * name and renames the images once gnuplot has succeeded. */
static void
script_head(FILE *g, const char *base, const char *what, int w_png, int h_png)
{
    fprintf(g, "# %s.gp: %s, made by layerfit %s.\n"
               "# Data in %s.dat (blocks selected with 'index', described in its header).\n"
               "# Redraw after restyling with: gnuplot %s.gp\n",
            base, what, LF_VERSION, base, base);
    fprintf(g, "if (!exists('out')) out = '%s'\n"
               "do for [fmt in 'png svg'] {\n"
               "if (fmt eq 'png') {\n"
               "    set terminal pngcairo size %d,%d enhanced font 'Helvetica,12'\n"
               "    set output out.'.png'\n"
               "} else {\n"
               "    set terminal svg size %d,%d dynamic enhanced font 'Helvetica,13'\n"
               "    set output out.'.svg'\n"
               "}\n", base, w_png, h_png, w_png * 4 / 5, h_png * 4 / 5);
    fprintf(g, "set grid lc rgb '#e0e0e0'\nset tics out nomirror\nset border 3\n");
}

/* Commit both files (or discard both after an error). */
static int
close_both(cli_out *g, cli_out *d, char *msg, size_t n)
{
    int bad = 0;
    if (cli_out_commit(g, msg, n) != 0)
        bad = 1;
    if (bad)
        cli_out_discard(d);
    else if (cli_out_commit(d, msg, n) != 0)
        bad = 1;
    return bad ? -1 : 0;
}

/* The plot command of data, model parts and pull-off from NAME.dat. */
static void
curve_layers(FILE *g, const char *base, size_t nst, size_t nun, size_t nbase, int have,
             int po, int titles, const char *po_text)
{
    fprintf(g, "plot '%s.dat' index 0 using 1:2 with points pt 6 ps 0.6 lc rgb '#7f8c8d' %s",
            base, titles ? "title 'data'" : "notitle");
    if (nst > 0)
        fprintf(g, ", \\\n     '' index 1 using 1:2 with lines lw 2.5 lc rgb '%s' %s",
                palette[0], titles ? "title 'fit, stable'" : "notitle");
    if (nun > 0)
        fprintf(g, ", \\\n     '' index 2 using 1:2 with lines lw 2.5 dt 2 lc rgb '%s' %s",
                palette[0], titles ? "title 'fit, unstable'" : "notitle");
    if (nbase > 0)
        fprintf(g, ", \\\n     '' index 3 using 1:2 with lines lw 1.5 lc rgb '#95a5a6' %s",
                titles ? "title 'out of contact'" : "notitle");
    if (!have)
        fprintf(g, ", \\\n     '' index 0 using 1:3 with lines lw 2 lc rgb '%s' %s", palette[0],
                titles ? "title 'fit'" : "notitle");
    if (po) {
        fprintf(g, ", \\\n     '' index 4 using 1:2 with points pt 7 ps 1.6 lc rgb '%s' ", palette[1]);
        if (titles)
            fprintf(g, "title 'pull-off %s'", po_text);
        else
            fprintf(g, "notitle");
    }
    fprintf(g, "\n");
}

/* One curve: data + model over the residuals, and the part around pull-off. */
static int
curve_figure(const char *dir, const char *base, size_t j, const lf_fit_curve *c,
             const lf_fit_result *res, const lf_window_placed *win, char *msg, size_t n)
{
    const lf_fit_curve_result *cr = &res->curves[j];
    model_curve *mc = malloc(sizeof *mc);
    char name[1100], buf[64], wb[64], Eb[64];
    const char *fu;
    double fs, fpeak = 0.0;
    size_t i, nst = 0, nun = 0, nbase = 0;
    cli_out od, og;
    FILE *d, *g;

    if (mc == NULL) {
        snprintf(msg, n, "out of memory");
        return -1;
    }
    model_for(c, j, res, mc);
    for (i = 0; i < c->n; i++)
        fpeak = fmax(fpeak, fabs(c->force[i]));
    force_unit(fpeak, &fs, &fu);
    snprintf(name, sizeof name, "%s.dat", base);
    if ((d = open_in(&od, dir, name, msg, n)) == NULL) {
        free(mc);
        return -1;
    }
    fprintf(d, "# %s: curve %zu of the fit, ", base, j + 1);
    cli_put_clean(d, c->name);   /* one line whatever the name holds */
    fprintf(d, " (%s branch)\n", cr->branch == LF_BRANCH_LOAD ? "loading" : "unloading");
    fprintf(d, "# index 0: measured points: depth_nm force_%s fitted_%s residual_%s\n", fu, fu, fu);
    for (i = 0; i < c->n; i++)
        fprintf(d, "%.9g %.9g %.9g %.9g\n", c->depth[i] * 1e9, c->force[i] / fs,
                cr->fitted[i] / fs, (c->force[i] - cr->fitted[i]) / fs);
    fprintf(d, "\n\n# index 1: model, stable under force control (dP/ddelta > 0): depth_nm force_%s\n", fu);
    nst = mc->have ? put_class(d, mc, 1, 0.0, fs) : (fputs(NO_POINT, d), 0);
    fprintf(d, "\n\n# index 2: model, unstable under force control (dP/ddelta <= 0)\n");
    nun = mc->have ? put_class(d, mc, 2, 0.0, fs) : (fputs(NO_POINT, d), 0);
    fprintf(d, "\n\n# index 3: model out of contact (baseline)\n");
    nbase = mc->have ? put_class(d, mc, 0, 0.0, fs) : (fputs(NO_POINT, d), 0);
    fprintf(d, "\n\n# index 4: force-controlled pull-off: depth_nm force_%s\n", fu);
    if (isfinite(mc->F_po))
        fprintf(d, "%.9g %.9g\n", mc->z_po * 1e9, mc->F_po / fs);
    else
        fputs(NO_POINT, d);

    snprintf(name, sizeof name, "%s.gp", base);
    if ((g = open_in(&og, dir, name, msg, n)) == NULL) {
        cli_out_discard(&od);
        free(mc);
        return -1;
    }
    script_head(g, base, "one curve of a fit with its residuals", 1200, 760);
    /* left: the whole curve over its residuals; right: the adhesive part
     * around pull-off, where the paper's Fig. 3 draws the branches.  The
     * title holds the file name: a gnuplot string, never script text. */
    {
        char pb[64], title[1400], layer[160], shape[160];
        if (cli_model_ignores_b(cr->model))
            snprintf(layer, sizeof layer, "half-space");
        else
            snprintf(layer, sizeof layer, "b = %s, %s",
                     cli_human(pb, sizeof pb, c->probe.b, "m"), cli_base_name(c->probe.base));
        snprintf(title, sizeof title, "%s: %s, %s;  w = %s, E* = %s",
                 base_name(c->name), cli_probe_words(shape, sizeof shape, &c->probe),
                 layer, value_text(wb, sizeof wb, res->w.value, "J/m²"),
                 value_text(Eb, sizeof Eb, res->Estar.value, "Pa"));
        fputs("set multiplot title ", g);
        cli_gnuplot_string(g, title);
        fputs(" noenhanced\n", g);
    }
    /* the main and residual panels share one x axis: the data's depths
     * and the model's */
    {
        double xlo = HUGE_VAL, xhi = -HUGE_VAL;
        for (i = 0; i < c->n; i++) {
            xlo = fmin(xlo, c->depth[i]);
            xhi = fmax(xhi, c->depth[i]);
        }
        if (mc->have)
            for (i = 0; i < GRID; i++) {
                xlo = fmin(xlo, mc->z[i]);
                xhi = fmax(xhi, mc->z[i]);
            }
        if (!(xhi > xlo)) {
            double h = fabs(xlo) > 0 ? 1e-3 * fabs(xlo) : 1e-9;
            xlo -= h;
            xhi += h;
        }
        fprintf(g, "set xrange [%.9g:%.9g]\n", xlo * 1e9, xhi * 1e9);
    }
    fprintf(g, "set lmargin at screen 0.09\nset rmargin at screen 0.60\n"
               "set tmargin at screen 0.90\nset bmargin at screen 0.36\n"
               "set format x ''\nunset xlabel\nset ylabel 'force (%s)'\n"
               "set key top left Left reverse box opaque\n", fu);
    if (win != NULL && win->active) {
        /* the fit window's bounds, where it has them: dashed grey lines */
        const double at[4] = { win->depth_lo * 1e9, win->depth_hi * 1e9, win->force_lo / fs,
                               win->force_hi / fs };
        int a;
        for (a = 0; a < 4; a++) {
            if (!isfinite(at[a]))
                continue;
            if (a < 2)
                fprintf(g, "set arrow %d from %.9g, graph 0 to %.9g, graph 1 nohead dt 2 "
                           "lc rgb '#888888'\n", a + 1, at[a], at[a]);
            else
                fprintf(g, "set arrow %d from graph 0, first %.9g to graph 1, first %.9g "
                           "nohead dt 2 lc rgb '#888888'\n", a + 1, at[a], at[a]);
        }
    }
    curve_layers(g, base, nst, nun, nbase, mc->have, isfinite(mc->F_po), 1,
                 cli_human(buf, sizeof buf, cr->pulloff.P_po, "N"));
    fputs("unset arrow\n", g);
    fprintf(g, "set tmargin at screen 0.34\nset bmargin at screen 0.09\n"
               "set format x '%%g'\nset xlabel 'depth z (nm)'\nset ylabel 'residual (%s)'\n"
               "unset key\n", fu);
    fprintf(g, "plot '%s.dat' index 0 using 1:4 with points pt 7 ps 0.4 lc rgb '%s', "
               "0 with lines lc rgb '#444444' dt 3\n", base, palette[0]);
    if (isfinite(mc->F_po) && isfinite(cr->pulloff.delta_detach)
        && cr->pulloff.delta_po >= cr->pulloff.delta_detach) {
        /* from just past detachment to a few pull-off widths into contact,
         * at least a twentieth of the data's depth span (w -> 0 shrinks
         * the pull-off to a point); the force range from the data and the
         * model inside that window */
        double s = isfinite(cr->slope) ? cr->slope : 0.0, dlo = HUGE_VAL, dhi = -HUGE_VAL;
        double span, x0, x1, y0 = HUGE_VAL, y1 = -HUGE_VAL, pad;
        for (i = 0; i < c->n; i++) {
            dlo = fmin(dlo, c->depth[i] - cr->z0);
            dhi = fmax(dhi, c->depth[i] - cr->z0);
        }
        span = fmax(cr->pulloff.delta_po - cr->pulloff.delta_detach, 0.05 * (dhi - dlo));
        x0 = cr->pulloff.delta_detach - 0.4 * span;
        x1 = cr->pulloff.delta_po + 3.0 * span;
        for (i = 0; i < c->n; i++) {
            double dd = c->depth[i] - cr->z0;
            if (dd >= x0 && dd <= x1) {
                y0 = fmin(y0, c->force[i]);
                y1 = fmax(y1, c->force[i]);
            }
        }
        y0 = fmin(y0, mc->F_po);
        y1 = fmax(y1, cr->F0 + s * x1);
        pad = 0.1 * (y1 - y0);
        if (!(pad > 0))
            pad = fabs(y0) > 0 ? 0.1 * fabs(y0) : 1e-12;
        y0 -= pad;
        y1 += pad;
        fprintf(g, "set lmargin at screen 0.70\nset rmargin at screen 0.98\n"
                   "set tmargin at screen 0.90\nset bmargin at screen 0.36\n"
                   "set title 'around pull-off'\nset xlabel 'depth z (nm)'\n"
                   "set ylabel 'force (%s)'\n", fu);
        fprintf(g, "set xrange [%.9g:%.9g]\nset yrange [%.9g:%.9g]\n",
                (x0 + cr->z0) * 1e9, (x1 + cr->z0) * 1e9, y0 / fs, y1 / fs);
        curve_layers(g, base, nst, nun, nbase, mc->have, 1, 0, "");
        fprintf(g, "unset title\nset autoscale\n");
    }
    fprintf(g, "unset multiplot\n}\n");
    free(mc);
    return close_both(&og, &od, msg, n);
}

/* Every curve on shared axes: delta = z - z0 so that the curves meet at
 * contact. */
static int
overview_figure(const char *dir, const char *base, size_t nc, const lf_fit_curve *c,
                const lf_fit_result *res, char *msg, size_t n)
{
    model_curve *mc = malloc(sizeof *mc);
    size_t j, i, *cnt = calloc(4 * (nc ? nc : 1), sizeof *cnt);
    double fs, fpeak = 0.0;
    const char *fu;
    char name[1100], buf[160], wb[64], Eb[64];
    cli_out od, og;
    FILE *d, *g;
    int first = 1;

    if (mc == NULL || cnt == NULL) {
        free(mc);
        free(cnt);
        snprintf(msg, n, "out of memory");
        return -1;
    }
    for (j = 0; j < nc; j++)
        for (i = 0; i < c[j].n; i++)
            fpeak = fmax(fpeak, fabs(c[j].force[i] - res->curves[j].F0));
    force_unit(fpeak, &fs, &fu);
    snprintf(name, sizeof name, "%s.dat", base);
    if ((d = open_in(&od, dir, name, msg, n)) == NULL) {
        free(mc);
        free(cnt);
        return -1;
    }
    fprintf(d, "# %s: every curve of the fit, indentation delta = z - z0 (nm) and force\n"
               "# minus the fitted offset F0 (%s).  Curve j (1-based) has index 4(j-1)+0:\n"
               "# data, +1: model stable, +2: model unstable, +3: pull-off point.\n", base, fu);
    for (j = 0; j < nc; j++) {
        const lf_fit_curve_result *cr = &res->curves[j];
        model_for(&c[j], j, res, mc);
        if (j > 0)
            fprintf(d, "\n\n");
        fprintf(d, "# curve %zu: ", j + 1);
        cli_put_clean(d, c[j].name);   /* a line break would start a data line */
        fputc('\n', d);
        for (i = 0; i < c[j].n; i++)
            fprintf(d, "%.9g %.9g\n", (c[j].depth[i] - cr->z0) * 1e9, (c[j].force[i] - cr->F0) / fs);
        cnt[4 * j] = c[j].n;
        if (mc->have) {
            for (i = 0; i < GRID; i++)
                mc->F[i] -= cr->F0;
            fprintf(d, "\n\n");
            cnt[4 * j + 1] = put_class(d, mc, 1, cr->z0, fs);
            fprintf(d, "\n\n");
            cnt[4 * j + 2] = put_class(d, mc, 2, cr->z0, fs);
        } else {
            fprintf(d, "\n\n# no model\n" NO_POINT "\n\n# no model\n" NO_POINT);
        }
        fprintf(d, "\n\n# pull-off\n");
        if (isfinite(mc->F_po)) {
            fprintf(d, "%.9g %.9g\n", (mc->z_po - cr->z0) * 1e9, (mc->F_po - cr->F0) / fs);
            cnt[4 * j + 3] = 1;
        } else {
            fputs(NO_POINT, d);
        }
    }
    snprintf(name, sizeof name, "%s.gp", base);
    if ((g = open_in(&og, dir, name, msg, n)) == NULL) {
        cli_out_discard(&od);
        free(mc);
        free(cnt);
        return -1;
    }
    script_head(g, base, "every curve of a joint fit on shared axes", 1000, 700);
    fprintf(g, "set title \"%zu curve%s, w = %s, E* = %s, %s model\" noenhanced\n", nc,
            nc == 1 ? "" : "s", value_text(wb, sizeof wb, res->w.value, "J/m²"),
            value_text(Eb, sizeof Eb, res->Estar.value, "Pa"), res->model ? res->model : "");
    fprintf(g, "set xlabel 'indentation δ = z - z_0 (nm)'\nset ylabel 'force - F_0 (%s)'\n"
               "set key outside right top noenhanced\n", fu);
    fprintf(g, "plot ");
    for (j = 0; j < nc; j++) {
        const char *col = palette[j % NPAL];
        char label[200];
        snprintf(label, sizeof label, "%zu: %s", j + 1,
                 cli_probe_words(buf, sizeof buf, &c[j].probe));
        fprintf(g, "%s'%s.dat' index %zu with points pt 6 ps 0.5 lc rgb '%s' title '%s'",
                first ? "" : ", \\\n     ", base, 4 * j, col, label);
        first = 0;
        if (cnt[4 * j + 1] > 0)
            fprintf(g, ", \\\n     '' index %zu with lines lw 2.5 lc rgb '%s' notitle", 4 * j + 1, col);
        if (cnt[4 * j + 2] > 0)
            fprintf(g, ", \\\n     '' index %zu with lines lw 2.5 dt 2 lc rgb '%s' notitle", 4 * j + 2, col);
        if (cnt[4 * j + 3] > 0)
            fprintf(g, ", \\\n     '' index %zu with points pt 7 ps 1.4 lc rgb '%s' notitle", 4 * j + 3, col);
    }
    fprintf(g, "\n}\n");
    free(mc);
    free(cnt);
    return close_both(&og, &od, msg, n);
}

/* Figure k's name: the overview (k = 0), then curve k. */
static void
figure_base(char *buf, size_t n, size_t k)
{
    if (k == 0)
        snprintf(buf, n, "overview");
    else
        snprintf(buf, n, "curve%zu", k);
}

void
cli_plot_files(const char *dir, size_t ncurves, void (*each)(const char *path))
{
    static const char *const ext[] = { "gp", "dat", "png", "svg" };
    char path[4096], base[64], name[80];
    size_t k, e;

    for (k = 0; k <= ncurves; k++) {
        figure_base(base, sizeof base, k);
        for (e = 0; e < sizeof ext / sizeof ext[0]; e++) {
            snprintf(name, sizeof name, "%s.%s", base, ext[e]);
            if (plot_path(path, sizeof path, dir, name) == 0)
                each(path);
        }
    }
    if (plot_path(path, sizeof path, dir, "provenance.json") == 0)
        each(path);
}

static void
provenance_writer(FILE *f, const void *ctx)
{
    cli_provenance_json(f, "", ctx);
    fputc('\n', f);
}

int
cli_draw_script(const char *dir, const char *script, const char *base,
                const char *const *ext, size_t next, char *msg, size_t n)
{
    char tmp[4096], out[4200], *leaf;
    size_t e;
    int status, slot;

    if (plot_path(tmp, sizeof tmp, dir, ".layerfit-XXXXXX") != 0 || mkdtemp(tmp) == NULL) {
        snprintf(msg, n, "cannot create a temporary folder in %s: %s", dir, strerror(errno));
        return -1;
    }
    slot = cli_temp_add(tmp, 1);
    leaf = strrchr(tmp, '/') + 1;
    snprintf(out, sizeof out, "%s/img", leaf);
    status = plot_run_script(dir, script, out, msg, n);
    for (e = 0; e < next; e++) {
        char from[4400], to[4400], name[4200];
        snprintf(name, sizeof name, "img.%s", ext[e]);
        if (plot_path(from, sizeof from, tmp, name) != 0)
            continue;
        snprintf(name, sizeof name, "%s.%s", base, ext[e]);
        if (status == 0 && plot_path(to, sizeof to, dir, name) != 0) {
            snprintf(msg, n, "cannot put %s/%s in place: %s", dir, name, strerror(ENAMETOOLONG));
            status = -1;
        } else if (status == 0) {
            /* written through a symbolic link there, as every output is */
            status = cli_put_in_place(from, to, msg, n);
        }
        unlink(from);     /* what a failed run left */
    }
    rmdir(tmp);
    cli_temp_forget(slot);
    return status;
}

static int
draw_all(const char *dir, const cli_figures *figs, char *msg, size_t n)
{
    static const char *const ext[] = { "png", "svg" };
    size_t k;
    int status = 0;

    for (k = 0; k < figs->n && status == 0; k++) {
        char script[80];
        snprintf(script, sizeof script, "%s.gp", figs->base[k]);
        status = cli_draw_script(dir, script, figs->base[k], ext, 2, msg, n);
    }
    return status;
}

void
cli_figures_free(cli_figures *f)
{
    if (f == NULL)
        return;
    free(f->base);
    free(f->caption);
    f->base = NULL;
    f->caption = NULL;
    f->n = 0;
}

int
cli_plot_fit(const char *dir, size_t ncurves, const lf_fit_curve *curves,
             const lf_fit_result *res, const lf_fit_input *in, const char *command_line,
             cli_figures *figs, char *msg, size_t n)
{
    lf_fit_result draw;
    size_t j, k = 0;
    int status;

    figs->n = 0;
    figs->base = calloc(ncurves + 1, sizeof *figs->base);
    figs->caption = calloc(ncurves + 1, sizeof *figs->caption);
    if (figs->base == NULL || figs->caption == NULL) {
        snprintf(msg, n, "out of memory");
        return -1;
    }
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        snprintf(msg, n, "cannot create %s: %s", dir, strerror(errno));
        return -1;
    }
    figure_base(figs->base[k], sizeof figs->base[0], k);
    snprintf(figs->caption[k], sizeof figs->caption[0],
             "Every curve of the fit against indentation; fitted model solid where stable "
             "under force control, dashed where unstable; dots: pull-off.");
    figs->n = ++k;
    /* drawn with every curve's offsets where the fit ended, also those the
     * data do not determine (the report gives no number for them) */
    draw = *res;
    draw.curves = malloc((ncurves ? ncurves : 1) * sizeof *draw.curves);
    if (draw.curves == NULL) {
        snprintf(msg, n, "out of memory");
        return -1;
    }
    for (j = 0; j < ncurves; j++) {
        lf_fit_curve_result *cr = &draw.curves[j];
        lf_fit_figure fig;
        lf_error err;
        *cr = res->curves[j];
        if (lf_fit_figure_curve(res, j, &curves[j], 0, NULL, NULL, NULL, &fig, &err) == LF_OK) {
            cr->z0 = fig.z0;
            cr->F0 = fig.F0;
            cr->slope = fig.slope;
        }
    }
    status = overview_figure(dir, figs->base[0], ncurves, curves, &draw, msg, n);
    for (j = 0; status == 0 && j < ncurves; j++, k++) {
        figure_base(figs->base[k], sizeof figs->base[0], k);
        snprintf(figs->caption[k], sizeof figs->caption[0], "Curve %zu: %s, with residuals.",
                 j + 1, curves[j].name ? curves[j].name : "");
        figs->n = k + 1;
        if (in != NULL && in->window[j].active)
            snprintf(figs->caption[k] + strlen(figs->caption[k]),
                     sizeof figs->caption[0] - strlen(figs->caption[k]),
                     " Dashed grey lines: the fit window (%zu of %zu points fitted).",
                     in->window[j].n_kept, in->window[j].n_in);
        status = curve_figure(dir, figs->base[k], j, &curves[j], &draw,
                              in != NULL ? &in->window[j] : NULL, msg, n);
    }
    free(draw.curves);
    if (status != 0)
        return -1;
    {
        char path[4096];
        if (plot_path(path, sizeof path, dir, "provenance.json") == 0)
            cli_write_file("fit", path, provenance_writer, command_line);
    }
    if (!plot_have_gnuplot()) {
        snprintf(msg, n, "gnuplot is not installed, so the figures were not drawn (their "
                 "scripts and data are in %s): %s", dir, PLOT_INSTALL_HINT);
        return 1;
    }
    return draw_all(dir, figs, msg, n);
}
