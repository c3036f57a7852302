/* cli/map.c: `layerfit map`, force maps.
 *
 *   layerfit map RESULT.csv --plot map.png   heat maps of w and E* from the
 *                                             output of `fit --batch`
 *   layerfit map --synthetic DIR             write a synthetic force map with
 *                                             a known pattern (datasets/forcemap)
 *
 * A map pixel is placed by the x_m, y_m columns of the batch result, which
 * come from "# x: ..." and "# y: ..." lines of each curve file.  The figure is
 * drawn by a gnuplot script written next to the image (map.gp, map.dat for
 * map.png), so that it can be restyled and redrawn with `gnuplot map.gp`. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "cli.h"
#include "plot.h"

/* ------------------------------------------------------------------------
 * The synthetic map: the truth pattern, stated in datasets/forcemap/README.md.
 * --------------------------------------------------------------------- */

#define SYN_K 3.0           /* probe exponent */
#define SYN_R 1e-3          /* m */
#define SYN_B 1e-6          /* m, layer thickness, frictionless base */
#define SYN_PITCH 1e-6      /* m between pixels */
#define SYN_DEPTH 20e-9     /* m, deepest indentation */
#define SYN_PAST_C 1.5      /* shallowest indentation: -1.5 c (baseline) */

/* Work of adhesion at (x, y) in m: 25 mJ/m^2 inside a disc of radius 14
 * pitches centred at (40, 24) pitches, 10 mJ/m^2 outside. */
static double
syn_w(double x, double y)
{
    double dx = x / SYN_PITCH - 40.0, dy = y / SYN_PITCH - 24.0;
    return dx * dx + dy * dy < 14.0 * 14.0 ? 25e-3 : 10e-3;
}

/* E* rises linearly with x from 0.5 GPa (x = 0) to 1.5 GPa (x = 63 pitches). */
static double
syn_E(double x)
{
    return 0.5e9 + 1e9 * (x / SYN_PITCH) / 63.0;
}

/* The contact point follows a tilted surface: 30 nm + 0.25 nm per pitch in x
 * + 0.125 nm per pitch in y. */
static double
syn_z0(double x, double y)
{
    return 30e-9 + 0.25e-9 * x / SYN_PITCH + 0.125e-9 * y / SYN_PITCH;
}

static void
make_dir(const char *path)
{
    if (mkdir(path, 0777) != 0 && errno != EEXIST)
        cli_die(CLI_EXIT_FAIL, "map: cannot create %s: %s", path, strerror(errno));
}

/* Curve of pixel (ix, iy): unloading from SYN_DEPTH to -SYN_PAST_C c, with
 * Gaussian noise of sd noise * max|P| from a generator seeded by the pixel,
 * so that any subset of the map is the same data as the full map. */
static void
syn_curve(const char *dir, long size, long ix, long iy, long points, double noise,
          unsigned long seed)
{
    const lf_probe probe = { SYN_K, SYN_R, SYN_B, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 };
    double x = (double) ix * SYN_PITCH, y = (double) iy * SYN_PITCH;
    lf_material mat;
    lf_model *model;
    lf_pulloff po;
    lf_error err;
    double *delta = malloc((size_t) points * sizeof *delta), pmax = 0.0, sd, z0;
    lf_eval *ev = malloc((size_t) points * sizeof *ev);
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    char path[4096], msg[4400];
    cli_out out;
    FILE *f;
    long i;

    if (delta == NULL || ev == NULL || rng == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    mat.w = syn_w(x, y);
    mat.Estar = syn_E(x);
    mat.nu = 0.3;
    z0 = syn_z0(x, y);
    gsl_rng_set(rng, seed * 1000003UL + (unsigned long) (iy * size + ix));
    model = lf_model_alloc(&lf_model_thin, &probe, &err);
    if (model == NULL || lf_model_pulloff(model, &mat, &po, &err) != LF_OK)
        cli_die_error(CLI_EXIT_FAIL, &err);
    for (i = 0; i < points; i++)
        delta[i] = SYN_DEPTH - (SYN_DEPTH + SYN_PAST_C * po.c) * (double) i / (double) (points - 1);
    if (lf_model_eval(model, &mat, LF_BRANCH_UNLOAD, (size_t) points, delta, ev, &err) != LF_OK)
        cli_die_error(CLI_EXIT_FAIL, &err);
    for (i = 0; i < points; i++)
        pmax = fmax(pmax, fabs(ev[i].P));
    sd = noise * pmax;
    snprintf(path, sizeof path, "%s/curves/x%02ld_y%02ld.csv", dir, ix, iy);
    if ((f = cli_out_open(&out, path, msg, sizeof msg)) == NULL)
        cli_die(CLI_EXIT_FAIL, "map: %s", msg);
    fprintf(f, "# layerfit synthetic force map, pixel (%ld, %ld)\n", ix, iy);
    fprintf(f, "# x: %g um\n# y: %g um\n", x * 1e6, y * 1e6);
    fprintf(f, "# true_w: %.6g J/m2\n# true_Estar: %.6g Pa\n# true_z0: %.6g nm\n",
            mat.w, mat.Estar, z0 * 1e9);
    fprintf(f, "# noise_sd: %.6g mN\n", sd * 1e3);
    fprintf(f, "depth_nm,force_mN,segment\n");
    for (i = 0; i < points; i++) {
        double F = ev[i].P + (sd > 0 ? gsl_ran_gaussian(rng, sd) : 0.0);
        fprintf(f, "%.4f,%.6g,unload\n", (delta[i] + z0) * 1e9, F * 1e3);
    }
    if (cli_out_commit(&out, msg, sizeof msg) != 0)
        cli_die(CLI_EXIT_FAIL, "map: %s", msg);
    lf_model_free(model);
    gsl_rng_free(rng);
    free(delta);
    free(ev);
}

static int
synthetic(const char *dir, long size, long every, long points, double noise,
          unsigned long seed, int force)
{
    char path[4096], msg[4400];
    cli_out out;
    FILE *plan;
    long ix, iy, n = 0;

    if (size < 1 || size > 1000 || every < 1 || points < 10 || points > 100000)
        cli_die(CLI_EXIT_USAGE, "map: --size must be 1..1000, --every >= 1, --points 10..100000");
    if (!(noise >= 0.0 && noise < 1.0))
        cli_die(CLI_EXIT_USAGE, "map: --noise is relative to the largest force, in [0, 1)");
    make_dir(dir);
    snprintf(path, sizeof path, "%s/curves", dir);
    make_dir(path);
    /* no file of an earlier map is replaced unless asked */
    snprintf(path, sizeof path, "%s/plan.csv", dir);
    cli_refuse_existing("map", path, force);
    for (iy = 0; iy < size; iy += every)
        for (ix = 0; ix < size; ix += every) {
            snprintf(path, sizeof path, "%s/curves/x%02ld_y%02ld.csv", dir, ix, iy);
            cli_refuse_existing("map", path, force);
        }
    snprintf(path, sizeof path, "%s/plan.csv", dir);
    if ((plan = cli_out_open(&out, path, msg, sizeof msg)) == NULL)
        cli_die(CLI_EXIT_FAIL, "map: %s", msg);
    fprintf(plan, "# synthetic force map: %ld x %ld pixels (every %ld), %ld points per curve,\n"
                  "# noise %g of the largest force, seed %lu (layerfit map --synthetic)\n",
            size, size, every, points, noise, seed);
    fprintf(plan, "file,k,R,b,interface\n");
    for (iy = 0; iy < size; iy += every)
        for (ix = 0; ix < size; ix += every) {
            syn_curve(dir, size, ix, iy, points, noise, seed);
            fprintf(plan, "curves/x%02ld_y%02ld.csv,%g,%gmm,%gum,frictionless\n", ix, iy,
                    SYN_K, SYN_R * 1e3, SYN_B * 1e6);
            n++;
        }
    if (cli_out_commit(&out, msg, sizeof msg) != 0)
        cli_die(CLI_EXIT_FAIL, "map: %s", msg);
    cli_say("map: wrote %ld curves and %s", n, path);
    return CLI_EXIT_OK;
}

/* ------------------------------------------------------------------------
 * Heat maps from a batch result.
 * --------------------------------------------------------------------- */

enum { MC_X, MC_Y, MC_W, MC_E, MC_STATUS, NMCOL };
static const char *const mcol_name[NMCOL] = { "x_m", "y_m", "w_J_m2", "Estar_Pa", "status" };

typedef struct {
    const char *path;
    size_t n;
    double (*v)[6];        /* x, y, w, E* (NaN where the fit failed), grid
                              column and row (NaN where not stated) */
    size_t skipped;        /* rows without a position */
    int grid;              /* every row states its place on a grid */
} map_reader;

/* The positions and estimates of a batch result (lf_table_read). */
static void
map_read(map_reader *m)
{
    lf_table *t = NULL;
    lf_error err;
    long col[NMCOL], gcol[2];
    size_t i, r;

    if (lf_table_read(m->path, &t, &err) != LF_OK)
        cli_die_error(CLI_EXIT_USAGE, &err);
    for (i = 0; i < NMCOL; i++)
        if ((col[i] = lf_table_column(t, mcol_name[i])) < 0)
            cli_die(CLI_EXIT_USAGE, "%s:%ld: no column '%s': expected the CSV output of "
                    "'layerfit fit --batch PLAN --out RESULT.csv'", m->path, t->header_line,
                    mcol_name[i]);
    m->v = malloc((t->nrows ? t->nrows : 1) * sizeof *m->v);
    if (m->v == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    gcol[0] = lf_table_column(t, "grid_i");
    gcol[1] = lf_table_column(t, "grid_j");
    m->grid = gcol[0] >= 0 && gcol[1] >= 0;
    for (r = 0; r < t->nrows; r++) {
        char *const *row = t->cells + r * t->ncols;
        double v[6];
        for (i = 0; i < 6; i++) {
            /* the scale of each column in the map (um, mJ/m^2, at most
             * Pa; grid places): a value must stay finite there and in the
             * differences of the axes' ranges */
            static const double scale[6] = { 2e6, 2e6, 1e3, 1.0, 1.0, 1.0 };
            long c = i < 4 ? col[i] : gcol[i - 4];
            v[i] = NAN;
            if (c < 0)
                continue;
            if (lf_table_number(row[c], &v[i]) != LF_OK)
                cli_die(CLI_EXIT_USAGE, "%s:%ld:%ld: '%s' is not a number", m->path,
                        t->line[r], t->col[r * t->ncols + (size_t) c], row[c]);
            if (row[c][0] != '\0' && !isfinite(v[i] * scale[i]))
                cli_die(CLI_EXIT_USAGE, "%s:%ld:%ld: %s '%s' is not a finite number a map can "
                        "show (an empty cell is a fit without a value)", m->path, t->line[r],
                        t->col[r * t->ncols + (size_t) c], i < 4 ? mcol_name[i]
                        : i == 4 ? "grid_i" : "grid_j", row[c]);
        }
        if (!isfinite(v[0]) || !isfinite(v[1])) {
            m->skipped++;
            continue;
        }
        if (strcmp(row[col[MC_STATUS]], "ok") != 0)
            v[2] = v[3] = NAN;
        if (!(v[4] >= 0 && v[5] >= 0 && v[4] < 65536 && v[5] < 65536))
            m->grid = 0;
        memcpy(m->v[m->n++], v, sizeof v);
    }
    lf_table_free(t);
}

static int
cmp_double(const void *a, const void *b)
{
    double x = *(const double *) a, y = *(const double *) b;
    return x < y ? -1 : x > y;
}

/* The grid's coordinates along axis c (0 x, 1 y) for its n places: the
 * line through (place, position) of the rows (least squares), so that
 * places no row fills still get theirs.  Returns n. */
static size_t
grid_axis(const map_reader *m, int c, size_t n, double *u)
{
    double si = 0, sx = 0, sii = 0, six = 0, a, b, k = (double) m->n;
    size_t i;
    for (i = 0; i < m->n; i++) {
        double g = m->v[i][4 + c], x = m->v[i][c];
        si += g;
        sx += x;
        sii += g * g;
        six += g * x;
    }
    b = k * sii - si * si > 0 ? (k * six - si * sx) / (k * sii - si * si) : 0.0;
    if (!(fabs(b) > 0))
        b = 1e-6;       /* one place only: any pitch draws it */
    a = (sx - b * si) / k;
    for (i = 0; i < n; i++)
        u[i] = a + b * (double) i;
    return n;
}

/* Sorted distinct values of column c of the points, into u; returns how many. */
static size_t
distinct(const map_reader *m, int c, double *u)
{
    size_t i, k = 0;
    for (i = 0; i < m->n; i++)
        u[i] = m->v[i][c];
    qsort(u, m->n, sizeof *u, cmp_double);
    for (i = 0; i < m->n; i++)
        if (k == 0 || u[i] - u[k - 1] > 1e-9 * fmax(fabs(u[i]), 1e-12))
            u[k++] = u[i];
    return k;
}

static size_t
index_of(const double *u, size_t n, double x)
{
    size_t lo = 0, hi = n;
    while (hi - lo > 1) {
        size_t mid = (lo + hi) / 2;
        if (u[mid] <= x * (1 + 1e-9) + 1e-21)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* Split "dir/name.ext" into dir and "name" (no extension). */
static void
split_path(const char *file, char *dir, size_t nd, char *base, size_t nb)
{
    const char *slash = strrchr(file, '/'), *name = slash ? slash + 1 : file, *dot;
    size_t len;
    if (slash == NULL)
        snprintf(dir, nd, ".");
    else if (slash == file)
        snprintf(dir, nd, "/");
    else
        snprintf(dir, nd, "%.*s", (int) (slash - file), file);
    dot = strrchr(name, '.');
    len = dot ? (size_t) (dot - name) : strlen(name);
    snprintf(base, nb, "%.*s", (int) len, name);
}

/* dir/name through the atomic writer (output.c); dies on failure. */
static FILE *
open_in_dir(cli_out *o, const char *dir, const char *name)
{
    char path[4096], msg[4400];
    FILE *f;
    if (plot_path(path, sizeof path, dir, name) != 0)
        cli_die(CLI_EXIT_FAIL, "map: %s/%s: path too long", dir, name);
    if ((f = cli_out_open(o, path, msg, sizeof msg)) == NULL)
        cli_die(CLI_EXIT_FAIL, "map: %s", msg);
    return f;
}

/* A tic step of 1, 2 or 5 times a power of ten that puts at most one tic
 * per `room` pixels along `px` pixels of an axis spanning `span`. */
static double
tic_step(double span, double px, double room)
{
    double n = fmax(1.0, floor(px / room)), raw = span / n;
    double p = pow(10.0, floor(log10(raw))), m = raw / p;
    return (m <= 1.0 ? 1.0 : m <= 2.0 ? 2.0 : m <= 5.0 ? 5.0 : 10.0) * p;
}

/* Tics that do not overlap: the panel (about 480 x 480 pixels of plot area
 * in the PNG, 380 x 380 in the SVG) keeps the map's aspect (size ratio -1),
 * so a map much taller than wide has a narrow x axis, and the reverse. */
static void
map_tics(FILE *f, const double *lo, const double *hi, int svg)
{
    double side = svg ? 380.0 : 480.0, a = (hi[1] - lo[1]) / (hi[0] - lo[0]);
    double w = a > 1.0 ? side / a : side, h = a > 1.0 ? side : side * a;
    double sx = tic_step(hi[0] - lo[0], w, 70.0), sy = tic_step(hi[1] - lo[1], h, 50.0);
    if (sx > 0.0 && sy > 0.0 && isfinite(sx) && isfinite(sy))   /* else gnuplot's own */
        fprintf(f, "set xtics %.6g\nset ytics %.6g\n", sx, sy);
}

/* One heat map: column 3 + q of the .dat file (q = 0 w, 1 E*), values of
 * grid[2 i + q] times `scale`.  Its colour range is the span of the values
 * (a single value, or values equal to 6 digits, gets a span of its own,
 * +-5%); a panel without a value
 * says so in words.  `with image` needs two cells along each axis to size
 * its pixels, so a one-row or one-column map draws its cells as boxes of
 * half-widths hx, hy (um). */
static void
map_panel(FILE *f, const char *dat, const double *grid, size_t cells, int q, double scale,
          const char *name, const char *title, size_t nx, size_t ny, double hx, double hy)
{
    double vmin = INFINITY, vmax = -INFINITY, s;
    size_t i, n = 0;
    for (i = 0; i < cells; i++) {
        double v = grid[2 * i + q] * scale;
        if (isfinite(v)) {
            vmin = fmin(vmin, v);
            vmax = fmax(vmax, v);
            n++;
        }
    }
    fputs("set title ", f);
    cli_gnuplot_string(f, title);
    fputc('\n', f);
    if (n == 0) {
        fprintf(f, "unset colorbox\nset label 1 '%s not determined at any point of the map' "
                   "at graph 0.5, 0.5 center front\nplot 1/0 notitle\n"
                   "unset label 1\nset colorbox\n", name);
        return;
    }
    /* values equal to the 6 digits written are one value */
    if (vmax - vmin <= 1e-5 * fmax(fabs(vmin), fabs(vmax))) {
        s = vmin != 0.0 ? 0.05 * fabs(vmin) : 1.0;
        vmin = vmax = 0.5 * (vmin + vmax);
        vmin -= s;
        vmax += s;
    }
    fprintf(f, "set cbrange [%.6g:%.6g]\nplot ", vmin, vmax);
    cli_gnuplot_string(f, dat);
    /* a "-" cell is a blank pixel: an undefined value keeps its place in the
     * image's grid (a missing one would be dropped and break the grid) */
    if (nx > 1 && ny > 1)
        fprintf(f, " using 1:2:(strcol(%d) eq '-' ? NaN : $%d) with image notitle\n",
                3 + q, 3 + q);
    else
        fprintf(f, " using 1:2:(%.6g):(%.6g):(strcol(%d) eq '-' ? NaN : $%d) "
                   "with boxxyerror fs solid 1.0 noborder fc palette notitle\n",
                hx, hy, 3 + q, 3 + q);
}

static int
draw_map(const char *result, const char *image)
{
    map_reader m;
    double *ux, *uy, *grid, Escale, cx, cy, lo[2], hi[2];
    const char *Eunit;
    size_t nx, ny, i;
    char dir[4096], base[1024], path[4096], msg[600], gp[1100], dat[1100];
    const char *term = plot_terminal(image), *ext = strrchr(image, '.'), *ext_word;
    cli_out out;
    FILE *f;

    if (term == NULL)
        cli_die(CLI_EXIT_USAGE, "map: --plot %s: the image must end in .png or .svg", image);
    ext_word = ext + 1;
    split_path(image, dir, sizeof dir, base, sizeof base);
    snprintf(dat, sizeof dat, "%s.dat", base);
    snprintf(gp, sizeof gp, "%s.gp", base);
    cli_output_note("map", image);
    if (plot_path(path, sizeof path, dir, dat) == 0)
        cli_output_note("map", path);
    if (plot_path(path, sizeof path, dir, gp) == 0)
        cli_output_note("map", path);
    cli_input_guard("map", result);
    cli_input_note(result, NULL);
    memset(&m, 0, sizeof m);
    m.path = result;
    map_read(&m);
    if (m.n == 0)
        cli_die(CLI_EXIT_USAGE, "map: %s has no rows with a position (x_m, y_m): none of "
                "its curve files states one (in the header of a force map or QI file, a "
                "force volume, a Chiaro or AFM Workshop export, or '# x: ...' and '# y: ...' "
                "lines of a CSV)", result);
    if (m.grid) {
        /* the files state each curve's place on the grid (a JPK map, a
         * force volume): pixels by place, at the grid's positions */
        nx = ny = 0;
        for (i = 0; i < m.n; i++) {
            nx = (size_t) fmax((double) nx, m.v[i][4] + 1);
            ny = (size_t) fmax((double) ny, m.v[i][5] + 1);
        }
        if ((double) nx * (double) ny > 16e6)
            m.grid = 0;         /* a sparse sample of a huge grid: by position */
    }
    if (!m.grid) {
        nx = ny = m.n;
    }
    ux = malloc(nx * sizeof *ux);
    uy = malloc(ny * sizeof *uy);
    if (ux == NULL || uy == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    if (m.grid) {
        grid_axis(&m, 0, nx, ux);
        grid_axis(&m, 1, ny, uy);
        if (ux[nx - 1] < ux[0] || uy[ny - 1] < uy[0])
            m.grid = 0;         /* a grid against its positions: by position */
    }
    if (!m.grid) {
        nx = distinct(&m, 0, ux);
        ny = distinct(&m, 1, uy);
        if (nx * ny > 4 * m.n + 16)
            cli_die(CLI_EXIT_USAGE, "map: the %zu positions of %s do not lie on a grid", m.n,
                    result);
    }
    grid = malloc(2 * nx * ny * sizeof *grid);
    if (grid == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    for (i = 0; i < 2 * nx * ny; i++)
        grid[i] = NAN;
    Escale = 0.0;
    for (i = 0; i < m.n; i++) {
        size_t at = m.grid ? (size_t) m.v[i][5] * nx + (size_t) m.v[i][4]
                           : index_of(uy, ny, m.v[i][1]) * nx + index_of(ux, nx, m.v[i][0]);
        grid[2 * at] = m.v[i][2];
        grid[2 * at + 1] = m.v[i][3];
        if (isfinite(m.v[i][3]))
            Escale = fmax(Escale, m.v[i][3]);
    }
    if (Escale >= 1e9) {
        Escale = 1e9;
        Eunit = "GPa";
    } else if (Escale >= 1e6) {
        Escale = 1e6;
        Eunit = "MPa";
    } else {
        Escale = 1e3;
        Eunit = "kPa";
    }
    f = open_in_dir(&out, dir, dat);
    fputs("# layerfit map of ", f);
    cli_put_clean(f, result);
    fprintf(f, ": x_um y_um w_mJ_m2 Estar_%s (-: fit failed, no curve, or not "
            "determined)\n", Eunit);
    for (i = 0; i < ny; i++) {
        size_t j;
        for (j = 0; j < nx; j++) {
            double w = grid[2 * (i * nx + j)], E = grid[2 * (i * nx + j) + 1];
            fprintf(f, "%.6g %.6g ", ux[j] * 1e6, uy[i] * 1e6);
            if (isfinite(w))
                fprintf(f, "%.6g ", w * 1e3);
            else
                fprintf(f, "- ");
            if (isfinite(E))
                fprintf(f, "%.6g\n", E / Escale);
            else
                fprintf(f, "-\n");
        }
        fputc('\n', f);
    }
    if (cli_out_commit(&out, msg, sizeof msg) != 0)
        cli_die(CLI_EXIT_FAIL, "map: %s", msg);
    f = open_in_dir(&out, dir, gp);
    /* names from the command line are data too: comments on one line,
     * strings quoted by gnuplot's rules */
    fputs("# ", f);
    cli_put_clean(f, gp);
    fprintf(f, ": heat maps of w and E* made by layerfit %s from ", LF_VERSION);
    cli_put_clean(f, result);
    fputs(".\n# Redraw with: gnuplot ", f);
    cli_put_clean(f, gp);
    fputs(" (in its folder)\n", f);
    fprintf(f, "set terminal %s\n", strcmp(ext, ".svg") == 0
            ? "svg size 1100,520 dynamic enhanced font 'Helvetica,13'"
            : "pngcairo size 1400,640 enhanced font 'Helvetica,13'");
    fputs("if (!exists('out')) out = ", f);
    cli_gnuplot_string(f, base);
    fprintf(f, "\nset output out.'%s'\n", ext);
    fprintf(f, "set multiplot layout 1,2 title '%zu x %zu map, %zu fits'\n", nx, ny, m.n);
    /* a cell's size: the grid's spacing; along an axis of one cell, the
     * other axis' spacing (square cells), 1 um for a single cell */
    cx = nx > 1 ? ux[1] - ux[0] : ny > 1 ? uy[1] - uy[0] : 1e-6;
    cy = ny > 1 ? uy[1] - uy[0] : cx;
    lo[0] = (ux[0] - 0.5 * cx) * 1e6;
    hi[0] = (ux[nx - 1] + 0.5 * cx) * 1e6;
    lo[1] = (uy[0] - 0.5 * cy) * 1e6;
    hi[1] = (uy[ny - 1] + 0.5 * cy) * 1e6;
    fprintf(f, "set size ratio -1\nset xlabel 'x (µm)'\nset ylabel 'y (µm)'\n"
               "set palette defined (0 '#440154', 1 '#3b528b', 2 '#21918c', 3 '#5ec962', 4 '#fde725')\n"
               "set xrange [%.6g:%.6g]\nset yrange [%.6g:%.6g]\nset tics out\n",
            lo[0], hi[0], lo[1], hi[1]);
    map_tics(f, lo, hi, strcmp(ext, ".svg") == 0);
    map_panel(f, dat, grid, nx * ny, 0, 1e3, "w", "work of adhesion w (mJ/m^2)",
              nx, ny, 0.5 * cx * 1e6, 0.5 * cy * 1e6);
    snprintf(msg, sizeof msg, "effective modulus E* (%s)", Eunit);
    map_panel(f, dat, grid, nx * ny, 1, 1.0 / Escale, "E*", msg,
              nx, ny, 0.5 * cx * 1e6, 0.5 * cy * 1e6);
    fputs("unset multiplot\n", f);
    if (cli_out_commit(&out, msg, sizeof msg) != 0)
        cli_die(CLI_EXIT_FAIL, "map: %s", msg);
    if (cli_draw_script(dir, gp, base, &ext_word, 1, msg, sizeof msg) != 0)
        cli_die(CLI_EXIT_FAIL, "map: %s (the script and data are in %s/%s and %s/%s)",
                msg, dir, gp, dir, dat);
    if (m.skipped > 0)
        cli_say("map: %zu rows of %s have no position and are not shown",
                m.skipped, result);
    free(ux);
    free(uy);
    free(grid);
    free(m.v);
    return CLI_EXIT_OK;
}

int
cli_map(int argc, char **argv, const char *command_line)
{
    const char *plot = NULL, *syn = NULL, *report = NULL;
    long size = 64, every = 1, points = 150, seed = 1;
    double noise = NAN;
    int npos, help, force = 0;
    const cli_opt opts[] = {
        { "plot", CLI_STRING, &plot },
        { "report", CLI_STRING, &report },
        { "synthetic", CLI_STRING, &syn },
        { "size", CLI_COUNT, &size },
        { "every", CLI_COUNT, &every },
        { "points", CLI_COUNT, &points },
        { "noise", CLI_NUMBER, &noise },
        { "seed", CLI_COUNT, &seed },
        { "force", CLI_FLAG, &force },
        { NULL, 0, NULL }
    };

    cli_parse("map", argc, argv, opts, &npos, &help);
    if (help) {
        printf("usage: layerfit map RESULT.csv [--plot MAP.png|MAP.svg] [--report MAP.html]\n"
               "       layerfit map --synthetic DIR [--size 64] [--every 1] [--points 150]\n"
               "                    [--noise 0.01] [--seed 1] [--force]\n\n"
               "The first form draws heat maps of w and E* from the CSV output of\n"
               "'layerfit fit --batch', keeping the gnuplot script and data next to the\n"
               "image (MAP.gp, MAP.dat); --report writes one interactive page of the results\n"
               "(heat maps, histograms, a filter, a selection exported as a plan, and each\n"
               "fit of one curve redrawn from its file where its SHA-256 is the results').\n"
               "The second\n"
               "writes a synthetic force map with a known pattern: DIR/plan.csv and DIR/curves/xXX_yYY.csv (every N-th pixel);\n"
               "files of an earlier map are replaced only with --force.\n");
        return CLI_EXIT_OK;
    }
    if (syn != NULL) {
        if (*syn == '\0')
            cli_die(CLI_EXIT_USAGE, "map: --synthetic needs a folder name (got an empty one)");
        if (npos > 0)
            cli_die(CLI_EXIT_USAGE, "map: --synthetic takes no other file ('%s')", argv[0]);
        return synthetic(syn, size, every, points, isfinite(noise) ? noise : 0.01,
                         (unsigned long) seed, force);
    }
    if (npos != 1)
        cli_die(CLI_EXIT_USAGE, "map: give one batch result (layerfit map RESULT.csv --plot map.png)");
    if (plot == NULL && report == NULL)
        cli_die(CLI_EXIT_USAGE, "map: say where to draw the map (--plot map.png or --plot map.svg, "
                "or --report map.html)");
    if (report != NULL) {
        char msg[1200];
        size_t len = strlen(report);
        if (len < 5 || strcmp(report + len - 5, ".html") != 0)
            cli_die(CLI_EXIT_USAGE, "map: --report %s: the report is a web page, FILE.html", report);
        cli_output_note("map", report);
        cli_output_folder_check("map", report);
        cli_input_guard("map", argv[0]);
        if (cli_page_map(report, argv[0], NULL, command_line, msg, sizeof msg) != 0)
            cli_die(CLI_EXIT_USAGE, "map: %s", msg);
    }
    return plot != NULL ? draw_map(argv[0], plot) : CLI_EXIT_OK;
}
