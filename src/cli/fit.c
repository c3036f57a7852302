/* cli/fit.c: `layerfit fit PLAN.csv` and `layerfit fit CURVE.csv --k K
 * --R R --b B --interface I`: read the curves (src/csv_curve.c, src/plan.c),
 * fit them jointly (fit/), print the report and write --json / --curves. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "report.h"

static const char usage_text[] =
    "usage: layerfit fit PLAN.csv [options]\n"
    "       layerfit fit CURVE.csv --k K --R LENGTH --b LENGTH --interface I [options]\n"
    "       layerfit fit EXPORT.txt --model halfspace --k 2 [--R LENGTH] [options]\n"
    "\n"
    "Fits w, E* and (where the plan determines it) nu jointly to every curve,\n"
    "with each curve's contact point z0 and force offset F0 free unless fixed.\n"
    "\n"
    "options:\n"
    "  --json FILE          the result in SI as JSON\n"
    "  --curves FILE        per point: depth, force, fitted force, residual, contact radius\n"
    "  --method M           lm (default), lmaccel, dogleg, ddogleg, subspace2D\n"
    "  --jacobian J         analytic (default), forward, central\n"
    "  --model NAME         auto (default), thin, exact or halfspace; auto picks per curve\n"
    "                       the cheapest model whose bias on w, E*, nu is below --model-tol\n"
    "  --model-tol X        bias allowed to a cheaper model, in standard errors (0.2)\n"
    "  --fix-nu NU          hold nu (also --nu); a plan's nu column does the same\n"
    "  --fix-z0 LENGTH      hold every curve's contact point\n"
    "  --fix-F0 FORCE       hold every curve's force offset\n"
    "  --slope              fit a baseline slope per curve\n"
    "  --max-iter N         iterations allowed (200)\n"
    "  --max-b-over-a X     warn where b/a exceeds X (0.1)\n"
    "  --segment S          unload (default) or load\n"
    "  --guess-w ADH        start the iteration at this w (e.g. 10mJ/m2) instead of\n"
    "                       the automatic guess\n"
    "  --guess-E PRESSURE   start at this E* (e.g. 1GPa)\n"
    "  --guess-nu NU        start at this nu, where nu is fitted\n"
    "  --loss L             linear (least squares, default), huber or cauchy: robust\n"
    "                       losses down-weight outliers (iteratively reweighted)\n"
    "  --loss-scale X       where the robust loss bends, in noise sd (1.345 huber,\n"
    "                       2.385 cauchy)\n"
    "  --plot DIR           figures (PNG, SVG) with their gnuplot scripts and data\n"
    "  --report FILE.html   one self-contained page: tables, warnings, figures\n"
    "  --batch PLAN.csv     every curve or sample an independent fit (see --batch --help)\n"
    "  --format NAME        the curve files' format instead of sniffing (csv, chiaro, jpk,\n"
    "                       workshop, ntmdt, hysitron, text; see layerfit check)\n"
    "  --spring-constant K  cantilever spring constant where a file states none (0.032N/m)\n"
    "  --sensitivity S      deflection sensitivity where a file states none (61nm/nA)\n"
    "  a single curve takes R from its file's header when --R is absent; with\n"
    "  --model halfspace it needs no --b (not used) and no --interface\n"
    "exit status: 0 converged, 3 not converged (report still written), 1 failure, 2 bad input\n";

typedef struct {
    const char *json, *curves, *method, *jacobian, *model, *interface, *segment;
    double k, R, b, nu, fix_nu, fix_z0, fix_F0, max_ba, model_tol;
    long max_iter;
    int slope;
    double guess_w, guess_E, guess_nu;
    const char *loss;
    double loss_scale;
    lf_read_opts read;          /* --format, --spring-constant, --sensitivity */
} fit_args;

/* The data of the run: curves as read, and the arrays handed to the fit. */
typedef struct {
    size_t n;
    lf_fit_curve *fc;
    double **depth, **force;
    char **names;
} fit_data;

/* R from the curve file's header where neither option nor plan gives one
 * (probe R NaN); says where it came from. */
static void
probe_from_file(lf_probe *p, const lf_curve *c, const char *path)
{
    char buf[48];
    lf_error err;
    if (!isnan(p->R))
        return;
    if (!(c->R > 0))
        cli_die(CLI_EXIT_USAGE, "fit: %s: no probe radius: the file states none (give --R, "
                "e.g. --R 8um, or an R in the plan)", path);
    p->R = c->R;
    if (lf_probe_check(p, &err) != LF_OK && !isnan(p->b))
        cli_die(CLI_EXIT_USAGE, "fit: %s: %s", path, err.msg);
    printf("%s: R = %s from the file header (%s export)\n", path,
           cli_human(buf, sizeof buf, p->R, "m"), c->format ? c->format : "?");
}

static void
add_curve(fit_data *d, const char *path, lf_segment seg, const lf_probe *probe_in,
          double z0, double F0, const lf_read_opts *ro)
{
    lf_curve *c = NULL;
    lf_warnings warn = { 0, NULL };
    lf_error err;
    size_t n, j = d->n;
    lf_probe pr = *probe_in, *probe = &pr;

    if (lf_curve_read(path, ro, &c, &warn, &err) != LF_OK)
        cli_die_error(CLI_EXIT_USAGE, &err);
    probe_from_file(probe, c, path);
    if (isnan(probe->b)) {
        /* the half-space model uses no thickness; the automatic start
         * (thin-layer profiling, fit/guess.c) needs a length scale */
        probe->b = probe->R;
        printf("%s: half-space model: no layer thickness or interface used (b shown = R, "
               "only a length scale for the automatic start)\n", path);
    }
    cli_print_warnings(&warn);
    lf_warnings_free(&warn);
    if (lf_curve_check_fit(c, seg, 5, &err) != LF_OK)
        cli_die_error(CLI_EXIT_USAGE, &err);
    n = lf_curve_segment(c, seg, NULL, NULL);
    d->depth[j] = malloc(n * sizeof **d->depth);
    d->force[j] = malloc(n * sizeof **d->force);
    d->names[j] = malloc(strlen(path) + 1);
    if (!d->depth[j] || !d->force[j] || !d->names[j])
        cli_die(CLI_EXIT_FAIL, "fit: out of memory");
    strcpy(d->names[j], path);
    lf_curve_segment(c, seg, d->depth[j], d->force[j]);
    lf_curve_free(c);
    d->fc[j].name = d->names[j];
    d->fc[j].n = n;
    d->fc[j].depth = d->depth[j];
    d->fc[j].force = d->force[j];
    d->fc[j].probe = *probe;
    d->fc[j].branch = seg == LF_SEG_LOAD ? LF_BRANCH_LOAD : LF_BRANCH_UNLOAD;
    d->fc[j].z0 = z0;
    d->fc[j].F0 = F0;
    d->n++;
}

static void
data_alloc(fit_data *d, size_t n)
{
    d->n = 0;
    d->fc = calloc(n, sizeof *d->fc);
    d->depth = calloc(n, sizeof *d->depth);
    d->force = calloc(n, sizeof *d->force);
    d->names = calloc(n, sizeof *d->names);
    if (!d->fc || !d->depth || !d->force || !d->names)
        cli_die(CLI_EXIT_FAIL, "fit: out of memory");
}

/* Read the plan (or the single curve) into d; sets the nu held by the plan. */
static void
read_input(const char *path, const fit_args *a, lf_segment seg_opt, int seg_given,
           fit_data *d, double *plan_nu)
{
    *plan_nu = NAN;
    if (!isnan(a->k)) {
        lf_probe p;
        lf_error err;
        int base;
        /* a half-space has no thickness and no interface: b is a stand-in
         * that no half-space formula uses */
        int halfspace = strcmp(a->model, "halfspace") == 0;
        if (isnan(a->b) && halfspace && a->interface == NULL) {
            p.b = 1.0;             /* NaN after the check: R, see add_curve */
            base = LF_BASE_FRICTIONLESS;
        } else {
            if (isnan(a->b) || a->interface == NULL)
                cli_die(CLI_EXIT_USAGE, "fit: a single curve needs --k, --R, --b and --interface "
                        "(e.g. --k 2 --R 1mm --b 1um --interface frictionless)");
            base = cli_base(a->interface);
            if (base < 0)
                cli_die(CLI_EXIT_USAGE, "fit: unknown interface '%s' (frictionless or bonded)",
                        a->interface);
            p.b = a->b;
        }
        p.k = a->k;
        p.R = isnan(a->R) ? 1.0 : a->R;    /* checked with the file's R below */
        p.base = (lf_base) base;
        if (lf_probe_check(&p, &err) != LF_OK)
            cli_die(CLI_EXIT_USAGE, "fit: %s", err.msg);
        p.R = a->R;
        if (isnan(a->b) && halfspace && a->interface == NULL)
            p.b = NAN;
        data_alloc(d, 1);
        add_curve(d, path, seg_opt, &p, a->fix_z0, a->fix_F0, &a->read);
    } else {
        lf_plan *plan = NULL;
        lf_warnings warn = { 0, NULL };
        lf_error err;
        size_t i;
        if (lf_plan_read(path, &plan, &warn, &err) != LF_OK)
            cli_die_error(CLI_EXIT_USAGE, &err);
        cli_print_warnings(&warn);
        lf_warnings_free(&warn);
        data_alloc(d, plan->n);
        for (i = 0; i < plan->n; i++) {
            const lf_plan_row *row = &plan->rows[i];
            if (!isnan(row->nu) && row->probe.base == LF_BASE_BONDED) {
                if (!isnan(*plan_nu) && *plan_nu != row->nu)
                    cli_die(CLI_EXIT_USAGE, "fit: %s:%ld: nu %g differs from an earlier row's %g "
                            "(one material, one nu)", plan->path, row->line, row->nu, *plan_nu);
                *plan_nu = row->nu;
            }
            {
                lf_read_opts ro = a->read;
                if (ro.format == NULL && row->format != NULL && row->format[0] != '\0')
                    ro.format = row->format;
                add_curve(d, row->file, seg_given ? seg_opt : row->segment, &row->probe,
                          isnan(a->fix_z0) ? row->z0 : a->fix_z0,
                          isnan(a->fix_F0) ? row->F0 : a->fix_F0, &ro);
            }
        }
        lf_plan_free(plan);
    }
}

static void
write_file(const char *path, void (*writer)(FILE *, const report_input *, const lf_fit_result *),
           const report_input *in, const lf_fit_result *r)
{
    FILE *f = fopen(path, "w");
    if (f == NULL)
        cli_die(CLI_EXIT_FAIL, "fit: cannot write %s: %s", path, strerror(errno));
    writer(f, in, r);
    if (ferror(f) | fclose(f))
        cli_die(CLI_EXIT_FAIL, "fit: error writing %s", path);
}

int
cli_fit_options(const char *model, const char *method, const char *jacobian,
                double max_ba, lf_fit_settings *s)
{
    int model_auto = strcmp(model, "auto") == 0;
    size_t i;

    s->model = model_auto ? &lf_model_thin : lf_model_type_find(model);
    if (s->model == NULL)
        cli_die(CLI_EXIT_USAGE, "fit: unknown model '%s' (auto, thin, exact, halfspace)", model);
    for (i = 0; lf_fit_methods[i] != NULL; i++)
        if (strcmp(lf_fit_methods[i], method) == 0)
            break;
    if (lf_fit_methods[i] == NULL)
        cli_die(CLI_EXIT_USAGE, "fit: unknown method '%s' (lm, lmaccel, dogleg, ddogleg, subspace2D)",
                method);
    s->method = method;
    if (strcmp(jacobian, "analytic") == 0)
        s->jacobian = LF_JAC_ANALYTIC;
    else if (strcmp(jacobian, "forward") == 0)
        s->jacobian = LF_JAC_FORWARD;
    else if (strcmp(jacobian, "central") == 0)
        s->jacobian = LF_JAC_CENTRAL;
    else
        cli_die(CLI_EXIT_USAGE, "fit: --jacobian must be analytic, forward or central (got '%s')",
                jacobian);
    if (!isnan(max_ba)) {
        if (!(max_ba > 0))
            cli_die(CLI_EXIT_USAGE, "fit: --max-b-over-a must be > 0 (e.g. --max-b-over-a 0.1)");
        s->max_b_over_a = max_ba;
    }
    return model_auto;
}

int
cli_fit(int argc, char **argv)
{
    fit_args a = { NULL, NULL, "lm", "analytic", "auto", NULL, NULL,
                   NAN, NAN, NAN, NAN, NAN, NAN, NAN, NAN, NAN, -1, 0, NAN, NAN, NAN,
                   "linear", NAN, { NULL, NULL, 0, NULL, NAN, NAN, 0 } };
    const char *plot_dir = NULL, *report_html = NULL, *kc = NULL, *sens = NULL;
    const cli_opt opts[] = {
        { "json", CLI_STRING, &a.json }, { "curves", CLI_STRING, &a.curves },
        { "method", CLI_STRING, &a.method }, { "jacobian", CLI_STRING, &a.jacobian },
        { "model", CLI_STRING, &a.model }, { "interface", CLI_STRING, &a.interface },
        { "segment", CLI_STRING, &a.segment }, { "k", CLI_NUMBER, &a.k },
        { "R", CLI_LENGTH, &a.R }, { "b", CLI_LENGTH, &a.b }, { "nu", CLI_NUMBER, &a.nu },
        { "fix-nu", CLI_NUMBER, &a.fix_nu }, { "fix-z0", CLI_LENGTH, &a.fix_z0 },
        { "fix-F0", CLI_FORCE, &a.fix_F0 }, { "max-b-over-a", CLI_NUMBER, &a.max_ba },
        { "model-tol", CLI_NUMBER, &a.model_tol },
        { "slope", CLI_FLAG, &a.slope }, { "max-iter", CLI_COUNT, &a.max_iter },
        { "guess-w", CLI_ADHESION, &a.guess_w }, { "guess-E", CLI_PRESSURE, &a.guess_E },
        { "guess-nu", CLI_NUMBER, &a.guess_nu }, { "loss", CLI_STRING, &a.loss },
        { "loss-scale", CLI_NUMBER, &a.loss_scale },
        { "plot", CLI_STRING, &plot_dir }, { "report", CLI_STRING, &report_html },
        { "format", CLI_STRING, &a.read.format }, { "spring-constant", CLI_STRING, &kc },
        { "sensitivity", CLI_STRING, &sens },
        { NULL, CLI_FLAG, NULL }
    };
    int npos, help, status, seg_given = 0;
    lf_segment seg = LF_SEG_UNLOAD;
    lf_fit_settings set = lf_fit_settings_default();
    lf_choose_settings choose = lf_choose_settings_default();
    int model_auto;
    fit_data d = { 0, NULL, NULL, NULL, NULL };
    lf_fit_result r;
    lf_error err;
    report_input in;
    double plan_nu, nu;
    size_t i;

    lf_read_opts_default(&a.read);
    cli_parse("fit", argc, argv, opts, &npos, &help);
    if (help) {
        fputs(usage_text, stdout);
        return CLI_EXIT_OK;
    }
    if (lf_read_opts_constants(&a.read, kc, sens, &err) != LF_OK)
        cli_die(CLI_EXIT_USAGE, "fit: %s", err.msg);
    if (npos != 1)
        cli_die(CLI_EXIT_USAGE, "fit: give one plan or curve file (see 'layerfit fit --help')");
    cli_fit_figures_check(plot_dir, report_html);
    if (a.segment != NULL) {
        seg_given = 1;
        if (strcmp(a.segment, "unload") == 0)
            seg = LF_SEG_UNLOAD;
        else if (strcmp(a.segment, "load") == 0)
            seg = LF_SEG_LOAD;
        else
            cli_die(CLI_EXIT_USAGE, "fit: --segment must be unload or load (got '%s')", a.segment);
    }
    model_auto = cli_fit_options(a.model, a.method, a.jacobian, a.max_ba, &set);
    if (!isnan(a.model_tol)) {
        if (!(a.model_tol > 0) || !isfinite(a.model_tol))
            cli_die(CLI_EXIT_USAGE, "fit: --model-tol must be a number > 0 (e.g. --model-tol 0.2)");
        if (!model_auto)
            cli_die(CLI_EXIT_USAGE, "fit: --model-tol applies to --model auto only");
        choose.tol = a.model_tol;
    }
    set.fit_slope = a.slope;
    if (!isnan(a.guess_w) && !(a.guess_w > 0))
        cli_die(CLI_EXIT_USAGE, "fit: --guess-w must be > 0 (e.g. --guess-w 10mJ/m2)");
    if (!isnan(a.guess_E) && !(a.guess_E > 0))
        cli_die(CLI_EXIT_USAGE, "fit: --guess-E must be > 0 (e.g. --guess-E 1GPa)");
    if (!isnan(a.guess_nu) && !(a.guess_nu > 0 && a.guess_nu < 0.5))
        cli_die(CLI_EXIT_USAGE, "fit: --guess-nu must lie in (0, 0.5) (e.g. --guess-nu 0.3)");
    if (lf_loss_find(a.loss) < 0)
        cli_die(CLI_EXIT_USAGE, "fit: --loss must be linear, huber or cauchy (got '%s')", a.loss);
    set.loss = (lf_loss) lf_loss_find(a.loss);
    if (!isnan(a.loss_scale) && !(a.loss_scale > 0))
        cli_die(CLI_EXIT_USAGE, "fit: --loss-scale must be > 0 (e.g. --loss-scale 1.345)");
    set.loss_scale = a.loss_scale;
    set.w.guess = a.guess_w;
    set.Estar.guess = a.guess_E;
    set.nu.guess = a.guess_nu;
    if (a.max_iter == 0)
        cli_die(CLI_EXIT_USAGE, "fit: --max-iter must be >= 1");
    if (a.max_iter > 0)
        set.max_iter = (size_t) a.max_iter;
    read_input(argv[0], &a, seg, seg_given, &d, &plan_nu);
    nu = !isnan(a.fix_nu) ? a.fix_nu : !isnan(a.nu) ? a.nu : plan_nu;
    if (!isnan(nu)) {
        if (!(nu >= 0 && nu < 0.5))
            cli_die(CLI_EXIT_USAGE, "fit: nu must lie in [0, 0.5) (got %g)", nu);
        set.nu.mode = LF_PARAM_FIXED;
        set.nu.value = nu;
    }
    if (model_auto)
        status = lf_fit_choose_driver(&set, &choose, d.n, d.fc, &r, &err);
    else
        status = lf_fit_driver(&set, d.n, d.fc, &r, &err);
    if (status != LF_OK && status != LF_ENOCONV)
        cli_die(status == LF_EDATA || status == LF_EINVAL ? CLI_EXIT_USAGE : CLI_EXIT_FAIL,
                "fit: %s", err.msg);
    if (!model_auto && set.model != &lf_model_thin) {
        lf_error terr;
        int st = lf_fit_compare_thin(&set, d.n, d.fc, &r, &terr);
        if (st != LF_OK)
            fprintf(stderr, "layerfit: warning: the thin-layer comparison fit failed: %s\n",
                    terr.msg);
    }
    in.settings = &set;
    in.model_request = a.model;
    in.model_tol = model_auto ? choose.tol : NAN;
    in.curves = d.fc;
    report_text(stdout, &in, &r);
    if (a.json != NULL)
        write_file(a.json, report_json, &in, &r);
    if (a.curves != NULL)
        write_file(a.curves, report_curves, &in, &r);
    cli_fit_figures(plot_dir, report_html, d.n, d.fc, &r);
    if (status == LF_ENOCONV)
        fprintf(stderr, "layerfit: fit: %s\n", r.stop_reason);
    lf_fit_result_free(&r);
    for (i = 0; i < d.n; i++) {
        free(d.depth[i]);
        free(d.force[i]);
        free(d.names[i]);
    }
    free(d.fc);
    free(d.depth);
    free(d.force);
    free(d.names);
    return status == LF_OK ? CLI_EXIT_OK : CLI_EXIT_NOCONV;
}
