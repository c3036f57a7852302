/* cli/model.c: `layerfit model`, forward curves, derived quantities and the
 * data of the seed paper's figures 2-5. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"


static const char model_help[] =
    "usage: layerfit model --k K --R LEN --b LEN --w ADH --E PRESSURE [options]\n"
    "       layerfit model --figure N [--plot FILE.svg|FILE.png]\n"
    "\n"
    "Force against indentation of a power-law probe f(r) = r^k/(k R^(k-1)) on an\n"
    "adhesive elastic layer of thickness b on a rigid base, as CSV on stdout\n"
    "(depth_m,force_N,radius_m,b_over_a,stable: SI units, stable = 1 where the\n"
    "curve is stable under force control).\n"
    "\n"
    "  --k K              profile exponent (2 paraboloid, large k flat punch)\n"
    "  --R LEN            reference length of the profile, e.g. 1mm\n"
    "  --B PREFACTOR      the profile as f = B r^k, B in SI (m^(1-k)), instead of --R\n"
    "  --tip T            paraboloid, sphere (true sphere of radius --R), cone,\n"
    "                     berkovich, pyramid (their equivalent cones)\n"
    "  --half-angle ANGLE a cone's half-angle (35deg), a pyramid's faces'\n"
    "  --b LEN            layer thickness, e.g. 1um (not for --model halfspace)\n"
    "  --w ADH            work of adhesion, e.g. 10mJ/m2 (also J/m^2, N/m)\n"
    "  --E PRESSURE       effective modulus E* = E/(1-nu^2), e.g. 1GPa\n"
    "  --interface WORD   frictionless (default) or bonded\n"
    "  --nu NU            Poisson's ratio in [0, 0.5), needed for bonded layers\n"
    "  --model NAME       forward model (default thin)\n"
    "  --branch WORD      unload (default: contact down to detachment) or load\n"
    "  --from LEN --to LEN --points N   indentation range and points\n"
    "                     (default: from detachment over ten pull-off widths, 200)\n"
    "  --summary          print pull-off and validity figures for people\n"
    "  --json             print the same in SI as JSON\n"
    "  --sigma-th P       theoretical strength: adds the critical thickness (Eq. 19)\n"
    "  --figure N         data of the paper's figure N (2..5) with its parameters,\n"
    "                     or 6: thin-layer error against a/b (exact layer model)\n"
    "  --plot FILE        with --figure, draw it with gnuplot (.svg or .png)\n";

typedef struct {
    double k, R, b, w, E, nu, from, to, sigma_th;
    long points;
    const char *interface, *model, *branch, *plot;
    int summary, json;
    long figure;
    const char *tip;
    double half_angle, B;
} model_args;

/* Everything the summary and JSON report (the library's). */
typedef lf_model_summary model_summary;

static void
need(const char *name, double v, const char *example)
{
    if (isnan(v))
        cli_die(CLI_EXIT_USAGE, "model: --%s is required (e.g. --%s %s)", name, name, example);
}

static lf_model *
make_model(const model_args *a, lf_probe *probe, lf_material *mat)
{
    lf_error err;
    lf_model *m;
    const lf_model_type *type = lf_model_type_find(a->model);
    int base = cli_base(a->interface);

    if (type == NULL)
        cli_die(CLI_EXIT_USAGE, "model: --model: unknown model '%s' (e.g. --model thin)", a->model);
    if (base < 0)
        cli_die(CLI_EXIT_USAGE, "model: --interface: unknown interface '%s' "
                "(frictionless or bonded)", a->interface);
    if (a->tip == NULL && isnan(a->half_angle))
        need("k", a->k, "2");
    if (type->scope != LF_SCOPE_HALFSPACE)   /* a half-space has no thickness */
        need("b", a->b, "1um");
    need("w", a->w, "10mJ/m2");
    need("E", a->E, "1GPa");
    if (base == LF_BASE_BONDED && isnan(a->nu))
        cli_die(CLI_EXIT_USAGE, "model: --nu is required for a bonded layer (e.g. --nu 0.3)");
    {
        /* the shape as fit states it: --k with --R or --B, --tip, --half-angle */
        lf_probe_statement pa;
        pa.k = a->k;
        pa.R = a->R;
        pa.tip = a->tip;
        pa.half_angle = a->half_angle;
        pa.B = a->B;
        pa.b = type->scope == LF_SCOPE_HALFSPACE ? NAN : a->b;
        pa.interface = isnan(pa.b) ? NULL : a->interface;
        pa.model = type->name;
        pa.halfspace = type->scope == LF_SCOPE_HALFSPACE;
        cli_probe_state("model", &pa, probe);
    }
    if (lf_probe_uses_R(probe))
        need("R", a->R, "1mm");
    /* a half-space's b is only a stand-in that no formula of it uses */
    if (isnan(probe->b))
        probe->b = isfinite(probe->R) ? probe->R : 1.0;
    mat->w = a->w;
    mat->Estar = a->E;
    mat->nu = isnan(a->nu) ? 0.0 : a->nu;
    m = lf_model_alloc(type, probe, &err);
    if (m == NULL || lf_material_check(mat, probe->base, &err) != LF_OK) {
        lf_model_free(m);
        cli_die(CLI_EXIT_USAGE, "model: %s", err.msg);
    }
    /* parameters the model cannot evaluate: refused before a number is
     * written (the message names the model and the parameters) */
    if (lf_model_check_region(m, mat, &err) != LF_OK)
        cli_die_error(CLI_EXIT_USAGE, &err);
    return m;
}

static void
summarise(const lf_model *m, const model_args *a, model_summary *s)
{
    lf_material mat;
    lf_error err;

    mat.w = a->w;
    mat.Estar = a->E;
    mat.nu = isnan(a->nu) ? 0.0 : a->nu;
    if (lf_model_summarise(m, &mat, a->sigma_th, s, &err) != LF_OK)
        cli_die_error(err.status == LF_EINVAL ? CLI_EXIT_USAGE : CLI_EXIT_FAIL, &err);
}

/* The thin-layer model at b/a (at pull-off): "" where b << a holds (up to
 * the fit's default limit 0.1), else what it means (lf_thin_scope).  At
 * b = a its force is off by a quarter (bonded, nu = 0.45) to a factor 2
 * (frictionless) or 5 (bonded, nu = 0.49): `layerfit model --figure 6`. */
static const char *
thin_scope(const model_summary *s, double ba)
{
    const char *words = lf_thin_scope(ba, lf_fit_settings_default().max_b_over_a);

    return s->type->scope == LF_SCOPE_THIN && words != NULL ? words : "";
}

static void
print_summary(const model_summary *s)
{
    char b1[64], b2[64], shape[160];
    const int has_R = lf_probe_uses_R(&s->probe);
    const lf_pulloff *po = &s->pulloff;

    printf("model            %s: %s\n", s->type->name, s->type->description);
    if (s->type->scope == LF_SCOPE_HALFSPACE)
        printf("probe            %s, half-space (no layer)",
               cli_probe_words(shape, sizeof shape, &s->probe));
    else
        printf("probe            %s, b = %s, %s base",
               cli_probe_words(shape, sizeof shape, &s->probe),
               cli_human(b2, sizeof b2, s->probe.b, "m"), cli_base_name(s->probe.base));
    if (s->probe.base == LF_BASE_BONDED)
        printf(", nu = %g (Z = %.6g)", s->mat.nu, s->Z);
    printf("\nmaterial         w = %s, E* = %s\n",
           cli_human(b1, sizeof b1, s->mat.w, "J/m^2"),
           cli_human(b2, sizeof b2, s->mat.Estar, "Pa"));
    if (po->c > 0)
        printf("offset c         %s  (sqrt(2 b w / (Z E*)))\n", cli_human(b1, sizeof b1, po->c, "m"));
    printf("detachment       delta = %s, P = %s, a = %s  (displacement control)\n",
           cli_human(b1, sizeof b1, po->delta_detach, "m"),
           cli_human(b2, sizeof b2, po->P_detach, "N"),
           cli_human((char[64]){ 0 }, 64, po->a_detach, "m"));
    printf("pull-off         delta = %s, P = %s, a = %s  (force control)\n",
           cli_human(b1, sizeof b1, po->delta_po, "m"),
           cli_human(b2, sizeof b2, po->P_po, "N"),
           cli_human((char[64]){ 0 }, 64, po->a_po, "m"));
    if (!has_R)
        ;                       /* no R: no pull-off in units of R */
    else if (s->mat.w > 0 && isfinite(po->P_po))
        printf("P_po/(2 pi R w)  %.6g\n", po->P_po / (2 * M_PI * s->probe.R * s->mat.w));
    else
        printf("P_po/(2 pi R w)  undefined (no adhesion: w = 0)\n");
    printf("mean tension     |sigma_po| = %s  (Eq. 18)\n", cli_human(b1, sizeof b1, po->sigma_po, "Pa"));
    printf("jump-in force    %s  (loading, at contact)\n", cli_human(b1, sizeof b1, po->P_jump, "N"));
    if (s->type->scope == LF_SCOPE_HALFSPACE)
        ;                       /* no layer: no b/a */
    else if (po->a_po > 0 && isfinite(s->probe.b / po->a_po)) {
        const char *scope = thin_scope(s, s->probe.b / po->a_po);
        printf("b/a at pull-off  %.4g%s%s%s\n", s->probe.b / po->a_po, *scope ? "  (" : "", scope,
               *scope ? ")" : "");
    }
    else
        printf("b/a at pull-off  undefined (no contact left at pull-off)\n");
    if (has_R)
        printf("JKR sphere a_po  %s  (half-space, (9 pi R^2 w/(8 E*))^(1/3), for comparison)\n",
               cli_human(b1, sizeof b1, lf_jkr_sphere_a_po(s->probe.R, s->mat.w, s->mat.Estar),
                         "m"));
    if (isfinite(s->b_cr) && isfinite(s->b_cr_over_a)) {
        printf("critical b       %s  (Eq. 19: |sigma_po| reaches sigma_th)\n",
               cli_human(b1, sizeof b1, s->b_cr, "m"));
        printf("b_cr/a_po at b_cr %.4g  (Eq. 20)\n", s->b_cr_over_a);
    } else if (!isnan(s->sigma_th)) {
        printf("critical b       undefined (no adhesion: w = 0, so no pull-off stress)\n");
    }
}

static void
print_json(const model_summary *s)
{
    lf_error err;
    char *json;

    if (lf_model_summary_json(s, &json, &err) != LF_OK)
        cli_die(CLI_EXIT_FAIL, "model: %s", err.msg);
    fputs(json, stdout);
    lf_free(json);
}

static void
print_curve(const lf_model *m, const lf_material *mat, lf_branch branch,
            double from, double to, long points)
{
    lf_error err;
    lf_eval *e = malloc((size_t) points * sizeof *e);
    double *delta = malloc((size_t) points * sizeof *delta);
    const double b = lf_model_get_probe(m)->b;
    /* a half-space has no layer: its b_over_a is left empty */
    const int layer = lf_model_get_type(m)->scope != LF_SCOPE_HALFSPACE;
    long i;

    if (e == NULL || delta == NULL)
        cli_die(CLI_EXIT_FAIL, "model: out of memory");
    for (i = 0; i < points; i++)
        delta[i] = points == 1 ? from : from + (to - from) * (double) i / (double) (points - 1);
    if (lf_model_eval(m, mat, branch, (size_t) points, delta, e, &err) != LF_OK)
        cli_die(CLI_EXIT_FAIL, "model: %s", err.msg);
    for (i = 0; i < points; i++)      /* no NaN or inf is ever written */
        if (!isfinite(delta[i]) || !isfinite(e[i].P) || !isfinite(e[i].a)
            || (layer && e[i].a > 0 && !isfinite(b / e[i].a)))
            cli_die(CLI_EXIT_USAGE, "model: the model cannot be evaluated at an indentation of "
                    "%g m (its force or contact radius is not a finite number there): give "
                    "--from and --to within the curve", delta[i]);
    printf("depth_m,force_N,radius_m,b_over_a,stable\n");
    for (i = 0; i < points; i++) {
        cli_print_double(stdout, delta[i]);
        putchar(',');
        cli_print_double(stdout, e[i].P);
        putchar(',');
        cli_print_double(stdout, e[i].a);
        putchar(',');
        if (layer && e[i].a > 0)
            cli_print_double(stdout, b / e[i].a);
        printf(",%d\n", e[i].a > 0 && e[i].dP_ddelta > 0);
    }
    free(e);
    free(delta);
}

int
cli_model(int argc, char **argv, const char *command_line)
{
    model_args a = { NAN, NAN, NAN, NAN, NAN, NAN, NAN, NAN, NAN, 200,
                     "frictionless", "thin", "unload", NULL, 0, 0, 0, NULL, NAN, NAN };
    const cli_opt opts[] = {
        { "k", CLI_NUMBER, &a.k }, { "R", CLI_LENGTH, &a.R }, { "b", CLI_LENGTH, &a.b },
        { "w", CLI_ADHESION, &a.w }, { "E", CLI_PRESSURE, &a.E }, { "nu", CLI_NUMBER, &a.nu },
        { "interface", CLI_STRING, &a.interface }, { "model", CLI_STRING, &a.model },
        { "branch", CLI_STRING, &a.branch }, { "from", CLI_LENGTH, &a.from },
        { "to", CLI_LENGTH, &a.to }, { "points", CLI_COUNT, &a.points },
        { "summary", CLI_FLAG, &a.summary }, { "json", CLI_FLAG, &a.json },
        { "sigma-th", CLI_PRESSURE, &a.sigma_th }, { "figure", CLI_COUNT, &a.figure },
        { "tip", CLI_STRING, &a.tip }, { "half-angle", CLI_ANGLE, &a.half_angle },
        { "B", CLI_NUMBER, &a.B },
        { "plot", CLI_STRING, &a.plot }, { NULL, CLI_FLAG, NULL }
    };
    int npos, help;
    lf_probe probe = { 0 };
    lf_material mat;
    lf_model *m;
    model_summary s;
    lf_branch branch;

    (void) command_line;    /* no provenance record */
    cli_parse("model", argc, argv, opts, &npos, &help);
    if (help) {
        const lf_model_type *const *t;
        int cost, top = 0;
        fputs(model_help, stdout);
        printf("\nmodels (--model NAME), from the cheapest:\n");
        for (t = lf_model_types; *t != NULL; t++)
            top = (*t)->cost > top ? (*t)->cost : top;
        for (cost = 0; cost <= top; cost++)
            for (t = lf_model_types; *t != NULL; t++)
                if ((*t)->cost == cost)
                    printf("  %-10s %s%s\n", (*t)->name, (*t)->description,
                           (*t)->scope == LF_SCOPE_THIN ? "; assumes b << a"
                           : (*t)->scope == LF_SCOPE_HALFSPACE ? "; assumes b >> a" : "");
        return CLI_EXIT_OK;
    }
    if (npos > 0)
        cli_die(CLI_EXIT_USAGE, "model: unexpected argument '%s' (see 'layerfit model --help')", argv[0]);
    if (a.figure != 0)
        return cli_figure((int) a.figure, a.plot);
    if (a.plot != NULL)
        cli_die(CLI_EXIT_USAGE, "model: --plot goes with --figure N");
    if (strcmp(a.branch, "unload") == 0)
        branch = LF_BRANCH_UNLOAD;
    else if (strcmp(a.branch, "load") == 0)
        branch = LF_BRANCH_LOAD;
    else
        cli_die(CLI_EXIT_USAGE, "model: --branch: unknown branch '%s' (unload or load)", a.branch);
    if (a.points < 1 || a.points > 100000000L)
        cli_die(CLI_EXIT_USAGE, "model: --points must be between 1 and 100000000");

    m = make_model(&a, &probe, &mat);
    summarise(m, &a, &s);
    if (!a.summary && s.pulloff.a_po > 0 && s.probe.b / s.pulloff.a_po >= 1.0) {
        /* numbers without the summary's words: the warning goes beside them */
        const char *scope = thin_scope(&s, s.probe.b / s.pulloff.a_po);
        if (*scope)
            cli_say("model: warning: b/a = %.4g at pull-off: %s",
                    s.probe.b / s.pulloff.a_po, scope);
    }
    if (a.summary)
        print_summary(&s);
    else if (a.json)
        print_json(&s);
    else {
        if (isnan(a.from))
            a.from = s.from;
        if (isnan(a.to))
            a.to = a.from + s.width;
        if (!(a.to > a.from) && a.points > 1)
            cli_die(CLI_EXIT_USAGE, "model: the range is empty: give --from and --to with --to > --from");
        print_curve(m, &mat, branch, a.from, a.to, a.points);
    }
    lf_model_free(m);
    return CLI_EXIT_OK;
}
