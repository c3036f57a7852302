/* cli/figure.c: the data of the seed paper's figures 2-5 (Papangelo), with
 * the paper's parameters w = 10 mJ/m^2, E* = 1 GPa, b = 1 um, R = 1 mm,
 * frictionless base, as CSV on stdout, and optionally drawn with gnuplot. */
#include <math.h>
#include <stdlib.h>

#include "cli.h"
#include "plot.h"

#define PAPER_W 10e-3     /* J/m^2 */
#define PAPER_E 1e9       /* Pa */
#define PAPER_B 1e-6      /* m */
#define PAPER_R 1e-3      /* m */
#define PAPER_SIGMA 10e6  /* Pa, theoretical strength of Section 3 */

#define MAXSER 8
#define MAXPTS 512

typedef struct {
    plot_series s[MAXSER];
    double x[MAXSER][MAXPTS], y[MAXSER][MAXPTS];
    char title[MAXSER][64];
    size_t n;
} figure_data;

static plot_series *
add_series(figure_data *d, const char *title, int color, int dashed)
{
    plot_series *s = &d->s[d->n];
    snprintf(d->title[d->n], sizeof d->title[0], "%s", title);
    s->title = d->title[d->n];
    s->x = d->x[d->n];
    s->y = d->y[d->n];
    s->n = 0;
    s->color = color;
    s->dashed = dashed;
    d->n++;
    return s;
}

static void
push(figure_data *d, plot_series *s, double x, double y)
{
    size_t i = (size_t) (s - d->s);
    if (s->n < MAXPTS) {
        d->x[i][s->n] = x;
        d->y[i][s->n] = y;
        s->n++;
    }
}

static void
thin_pulloff(double k, double R, double b, lf_pulloff *po)
{
    /* the paper's profile r^k/(k R^(k-1)); at k = 1, where R cancels, its
     * prefactor (f = r) is stated */
    lf_probe p = { k, R, b, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, k == 1.0 ? 1.0 : 0.0 };
    lf_material m = { PAPER_W, PAPER_E, 0.0 };
    lf_error err;
    lf_model *model = lf_model_alloc(&lf_model_thin, &p, &err);

    if (model == NULL || lf_model_pulloff(model, &m, po, &err) != LF_OK)
        cli_die_error(CLI_EXIT_FAIL, &err);
    lf_model_free(model);
}

/* Fig. 2: exponent (2-k)/(2k) of b in the pull-off force. */
static void
figure2(figure_data *d)
{
    plot_series *s = add_series(d, "(2-k)/(2k)", 0, 0);
    int i;
    printf("k,exponent\n");
    for (i = 0; i <= 180; i++) {
        double k = 1.0 + 0.05 * i;
        printf("%.6g,%.17g\n", k, (2 - k) / (2 * k));
        push(d, s, k, (2 - k) / (2 * k));
    }
}

/* Fig. 3: dimensionless force P/(2 pi R w) against delta/c (Eq. 15-16),
 * stable (force control) and unstable parts as separate series. */
static void
figure3(figure_data *d)
{
    static const double ks[] = { 1.9, 2.0, 2.1 };
    const lf_material mat = { PAPER_W, PAPER_E, 0.0 };
    size_t j;
    int i;

    printf("k,delta_bar,P_bar,depth_m,force_N,stable\n");
    for (j = 0; j < 3; j++) {
        lf_probe p = { ks[j], PAPER_R, PAPER_B, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 };
        lf_error err;
        lf_model *model = lf_model_alloc(&lf_model_thin, &p, &err);
        lf_pulloff po;
        char t[64];
        plot_series *st, *un;

        if (model == NULL || lf_model_pulloff(model, &mat, &po, &err) != LF_OK)
            cli_die_error(CLI_EXIT_FAIL, &err);
        snprintf(t, sizeof t, "k = %g stable", ks[j]);
        st = add_series(d, t, (int) j, 0);
        snprintf(t, sizeof t, "k = %g unstable", ks[j]);
        un = add_series(d, t, (int) j, 1);
        for (i = 0; i <= 400; i++) {
            double dbar = -1.0 + 4.0 * i / 400.0, delta = dbar * po.c;
            lf_eval e;
            double pbar;
            if (lf_model_eval(model, &mat, LF_BRANCH_UNLOAD, 1, &delta, &e, &err) != LF_OK)
                cli_die_error(CLI_EXIT_FAIL, &err);
            pbar = e.P / (2 * M_PI * PAPER_R * PAPER_W);
            printf("%g,%.17g,%.17g,%.17g,%.17g,%d\n", ks[j], dbar, pbar, delta, e.P,
                   e.dP_ddelta > 0);
            push(d, e.dP_ddelta > 0 ? st : un, dbar, pbar);
            if (e.dP_ddelta > 0 && un->n > 0 && st->n == 1)
                push(d, un, dbar, pbar);   /* join the two parts */
        }
        lf_model_free(model);
    }
}

/* Figures 4 and 5 share their layout: one series per R/b in {1e2, 1e3,
 * 1e4} (b = 1 um), 301 values of k in [k_lo, k_hi]; point() prints one CSV
 * row and returns the plotted value. */
typedef double (*rb_point)(double R_over_b, double k, double R);

static void
rb_figure(figure_data *d, double k_lo, double k_hi, const char *header, rb_point point)
{
    static const double rb[] = { 1e2, 1e3, 1e4 };
    size_t j;
    int i;

    printf("%s\n", header);
    for (j = 0; j < 3; j++) {
        char t[64];
        plot_series *s;
        snprintf(t, sizeof t, "R/b = 10^%g", log10(rb[j]));
        s = add_series(d, t, (int) j, 0);
        for (i = 0; i <= 300; i++) {
            double k = k_lo + (k_hi - k_lo) * i / 300.0;
            push(d, s, k, point(rb[j], k, rb[j] * PAPER_B));
        }
    }
}

/* Fig. 4: -P_po/(2 pi R w) against k. */
static double
fig4_point(double rb, double k, double R)
{
    lf_pulloff po;
    thin_pulloff(k, R, PAPER_B, &po);
    printf("%g,%.6g,%.17g,%.17g\n", rb, k, po.P_po / (2 * M_PI * R * PAPER_W), po.P_po);
    return -po.P_po / (2 * M_PI * R * PAPER_W);
}

static void
figure4(figure_data *d)
{
    rb_figure(d, 1.0, 4.0, "R_over_b,k,P_po_bar,P_po_N", fig4_point);
}

/* Fig. 5: b_cr/a_po at b = b_cr (Eq. 19-20) against k, sigma_th = 10 MPa,
 * R = (R/b) x 1 um as in the paper.  Eq. (19) gives b_cr = 50 nm at k = 2,
 * not the 1 um the paper's text states (b_cr = 2 (k/(k+2))^2 E* w /
 * sigma_th^2, with w = 10 mJ/m^2, E* = 1 GPa, sigma_th = 10 MPa). */
static double
fig5_point(double rb, double k, double R)
{
    double bcr = lf_thin_b_critical(k, PAPER_W, PAPER_E, PAPER_SIGMA);
    lf_pulloff po;
    thin_pulloff(k, R, bcr, &po);
    printf("%g,%.6g,%.17g,%.17g,%.17g,%.17g\n", rb, k, R, bcr, po.a_po, bcr / po.a_po);
    return bcr / po.a_po;
}

static void
figure5(figure_data *d)
{
    rb_figure(d, 2.0, 10.0, "R_over_b,k,R_m,b_cr_m,a_po_cr_m,b_cr_over_a_po", fig5_point);
}

/* Figure 6 (not the paper's): the thin-layer closed form against the exact
 * layer model, adhesiveless force P1 at the same contact radius, over a/b. */
static void
figure6(figure_data *d)
{
    static const struct { double k; lf_base base; double nu; const char *title; } cases[] = {
        { 2, LF_BASE_FRICTIONLESS, 0.0, "k = 2 frictionless" },
        { 3, LF_BASE_FRICTIONLESS, 0.0, "k = 3 frictionless" },
        { 2, LF_BASE_BONDED, 0.3, "k = 2 bonded nu = 0.3" },
        { 2, LF_BASE_BONDED, 0.45, "k = 2 bonded nu = 0.45" },
        { 2, LF_BASE_BONDED, 0.49, "k = 2 bonded nu = 0.49" },
    };
    size_t j;
    int i;

    printf("k,interface,nu,a_over_b,exact_over_thin_P1\n");
    for (j = 0; j < sizeof cases / sizeof cases[0]; j++) {
        plot_series *s = add_series(d, cases[j].title, (int) j, 0);
        for (i = 0; i <= 120; i++) {
            double tau = pow(10.0, -0.5 + 2.5 * i / 120.0), ratio;
            lf_error err;
            if (lf_exact_thin_ratio(cases[j].k, cases[j].base, cases[j].nu, tau, &ratio, &err) != LF_OK)
                cli_die_error(CLI_EXIT_FAIL, &err);
            printf("%g,%s,%g,%.17g,%.17g\n", cases[j].k, cli_base_name(cases[j].base),
                   cases[j].nu, tau, ratio);
            push(d, s, tau, ratio);
        }
    }
}

int
cli_figure(int figure, const char *plot)
{
    static const struct {
        void (*make)(figure_data *);
        const char *title, *xlabel, *ylabel;
        int logy, logx;
    } figs[] = {
        [2] = { figure2, "Fig. 2: pull-off force scales as b^{(2-k)/(2k)}", "k",
                "exponent (2-k)/(2k)", 0, 0 },
        [3] = { figure3, "Fig. 3: force-indentation, w = 10 mJ/m^2, E* = 1 GPa, b = 1 {/Symbol m}m, R = 1 mm",
                "{/Symbol d}/c", "P/(2{/Symbol p}Rw)", 0, 0 },
        [4] = { figure4, "Fig. 4: pull-off force against profile exponent", "k",
                "-P_{PO}/(2{/Symbol p}Rw)", 1, 0 },
        [5] = { figure5, "Fig. 5: thin-layer validity at the critical thickness (Eq. 20)", "k",
                "b_{cr}/a_{PO,cr}", 1, 0 },
        [6] = { figure6, "Thin-layer closed form against the exact layer model (adhesiveless, same a)",
                "a/b", "P_1 exact / P_1 thin", 1, 1 },
    };
    figure_data *d;
    char msg[512];

    if (figure < 2 || figure > 6)
        cli_die(CLI_EXIT_USAGE, "model: --figure: no figure %d (the paper's figures 2 to 5, "
                "or 6: thin-layer error against a/b)", figure);
    if (plot != NULL && !plot_have_gnuplot())
        cli_die(CLI_EXIT_FAIL, "model: --plot: gnuplot is not installed: %s", PLOT_INSTALL_HINT);
    if (plot != NULL && plot_terminal(plot) == NULL)
        cli_die(CLI_EXIT_USAGE, "model: --plot %s: the file must end in .svg or .png", plot);
    cli_output_note("model", plot);
    cli_output_folder_check("model", plot);
    d = calloc(1, sizeof *d);
    if (d == NULL)
        cli_die(CLI_EXIT_FAIL, "model: out of memory");
    figs[figure].make(d);
    if (plot != NULL) {
        plot_figure f = { figs[figure].title, figs[figure].xlabel, figs[figure].ylabel,
                          figs[figure].logx, figs[figure].logy, d->n, d->s };
        if (plot_draw(&f, plot, msg, sizeof msg) != 0) {
            free(d);
            cli_die(CLI_EXIT_FAIL, "model: --plot: %s", msg);
        }
        cli_say("figure %d drawn in %s", figure, plot);
    }
    free(d);
    return CLI_EXIT_OK;
}
