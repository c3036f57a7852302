/* cli/simulate.c: `layerfit simulate`, synthetic lab data from probes,
 * true parameters and a noise model, written in the lab-data formats
 * (curve CSV `depth_m,force_N,segment`, plan CSV `file,k,R_m,b_m,interface,nu`)
 * with a truth file beside them. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"

static const char usage_text[] =
    "usage: layerfit simulate --out DIR --w W --E E [--nu NU] [options] PROBE...\n"
    "\n"
    "PROBE is k=K,R=LENGTH,b=LENGTH,interface=frictionless|bonded, e.g.\n"
    "  k=2,R=1mm,b=1um,interface=frictionless\n"
    "Writes DIR/plan.csv, DIR/curveN.csv (one per probe) and DIR/truth.csv.\n"
    "\n"
    "options:\n"
    "  --nu NU          Poisson's ratio (needed by bonded probes)\n"
    "  --noise F        Gaussian noise sd as a fraction of each curve's largest |force| (0)\n"
    "  --seed N         seed of GSL's mt19937 generator (1)\n"
    "  --force          replace files of an earlier run in DIR (refused otherwise)\n"
    "  --z0 LENGTH      contact point offset added to depth (0)\n"
    "  --F0 FORCE       force offset (0)\n"
    "  --points N       points per curve (300)\n"
    "  --delta-max L    deepest indentation (50nm)\n"
    "  --delta-min L    shallowest indentation (default -past_c * c)\n"
    "  --past-c F       shallowest indentation as a multiple of -c (1.2)\n"
    "  --branch B       unload (default, written deep to shallow) or load\n"
    "  --model NAME     forward model (thin)\n";

/* Parse "k=2,R=1mm,b=1um,interface=bonded". */
static void
parse_probe(const char *text, lf_probe *p)
{
    char buf[256], *tok, *save = NULL;
    lf_error err;
    int have = 0;

    if (strlen(text) >= sizeof buf)
        cli_die(CLI_EXIT_USAGE, "simulate: probe '%s' is too long", text);
    strcpy(buf, text);
    p->k = p->R = p->b = NAN;
    p->base = LF_BASE_FRICTIONLESS;
    for (tok = strtok_r(buf, ",", &save); tok != NULL; tok = strtok_r(NULL, ",", &save)) {
        char *eq = strchr(tok, '='), *end;
        if (eq == NULL)
            cli_die(CLI_EXIT_USAGE, "simulate: probe '%s': '%s' is not key=value "
                    "(e.g. k=2,R=1mm,b=1um,interface=frictionless)", text, tok);
        *eq++ = '\0';
        if (strcmp(tok, "k") == 0) {
            errno = 0;
            p->k = strtod(eq, &end);
            if (end == eq || *end != '\0' || errno == ERANGE)
                cli_die(CLI_EXIT_USAGE, "simulate: probe '%s': k '%s' is not a number", text, eq);
            have |= 1;
        } else if (strcmp(tok, "R") == 0 || strcmp(tok, "b") == 0) {
            if (lf_units_parse(eq, LF_Q_LENGTH, tok[0] == 'R' ? &p->R : &p->b, &err) != LF_OK)
                cli_die(CLI_EXIT_USAGE, "simulate: probe '%s': %s: %s", text, tok, err.msg);
            have |= tok[0] == 'R' ? 2 : 4;
        } else if (strcmp(tok, "interface") == 0) {
            int base = cli_base(eq);
            if (base < 0)
                cli_die(CLI_EXIT_USAGE, "simulate: probe '%s': unknown interface '%s' "
                        "(frictionless or bonded)", text, eq);
            p->base = (lf_base) base;
        } else {
            cli_die(CLI_EXIT_USAGE, "simulate: probe '%s': unknown key '%s' (k, R, b, interface)",
                    text, tok);
        }
    }
    if (have != 7)
        cli_die(CLI_EXIT_USAGE, "simulate: probe '%s' needs k, R and b "
                "(e.g. k=2,R=1mm,b=1um,interface=frictionless)", text);
    if (lf_probe_check(p, &err) != LF_OK)
        cli_die(CLI_EXIT_USAGE, "simulate: probe '%s': %s", text, err.msg);
}

/* Every file through the atomic writer (output.c). */
static FILE *
open_out(cli_out *o, const char *dir, const char *name, char *path, size_t n)
{
    char msg[4400];
    FILE *f;
    snprintf(path, n, "%s/%s", dir, name);
    if ((f = cli_out_open(o, path, msg, sizeof msg)) == NULL)
        cli_die(CLI_EXIT_FAIL, "simulate: %s", msg);
    return f;
}

static void
close_out(cli_out *o)
{
    char msg[4400];
    if (cli_out_commit(o, msg, sizeof msg) != 0)
        cli_die(CLI_EXIT_FAIL, "simulate: %s", msg);
}

int
cli_simulate(int argc, char **argv, const char *command_line)
{
    const char *out = NULL, *branch = "unload", *model = "thin";
    double w = NAN, E = NAN, nu = NAN, noise = NAN, z0 = NAN, F0 = NAN;
    double dmax = NAN, dmin = NAN, past_c = NAN;
    long seed = -1, points = -1;
    int force_replace = 0;
    const cli_opt opts[] = {
        { "out", CLI_STRING, &out }, { "w", CLI_ADHESION, &w }, { "E", CLI_PRESSURE, &E },
        { "nu", CLI_NUMBER, &nu }, { "noise", CLI_NUMBER, &noise }, { "seed", CLI_COUNT, &seed },
        { "z0", CLI_LENGTH, &z0 }, { "F0", CLI_FORCE, &F0 }, { "points", CLI_COUNT, &points },
        { "delta-max", CLI_LENGTH, &dmax }, { "delta-min", CLI_LENGTH, &dmin },
        { "past-c", CLI_NUMBER, &past_c }, { "branch", CLI_STRING, &branch },
        { "model", CLI_STRING, &model }, { "force", CLI_FLAG, &force_replace },
        { NULL, CLI_FLAG, NULL }
    };
    int npos, help, i, all_bonded = 1;
    cli_out oplan, otruth, ocurve;
    lf_sim_settings s = lf_sim_settings_default();
    const lf_model_type *type;
    lf_material mat;
    lf_probe *probes;
    double **depth, **force, *sigma;
    lf_error err;
    char path[4096];
    FILE *plan, *truth;
    size_t j, k;
    static const char *const fixed_names[] = { "plan.csv", "truth.csv" };

    (void) command_line;    /* no provenance record */
    cli_parse("simulate", argc, argv, opts, &npos, &help);
    if (help) {
        fputs(usage_text, stdout);
        return CLI_EXIT_OK;
    }
    if (out == NULL || *out == '\0')
        cli_die(CLI_EXIT_USAGE, "simulate: --out %s (e.g. --out datasets/demo)",
                out == NULL ? "is required" : "needs a folder name (got an empty one)");
    if (isnan(w) || isnan(E))
        cli_die(CLI_EXIT_USAGE, "simulate: --w and --E are required (e.g. --w 10mJ/m2 --E 1GPa)");
    if (npos == 0)
        cli_die(CLI_EXIT_USAGE, "simulate: give at least one probe "
                "(e.g. k=2,R=1mm,b=1um,interface=frictionless)");
    type = lf_model_type_find(model);
    if (type == NULL)
        cli_die(CLI_EXIT_USAGE, "simulate: unknown model '%s'", model);
    if (strcmp(branch, "unload") == 0)
        s.branch = LF_BRANCH_UNLOAD;
    else if (strcmp(branch, "load") == 0)
        s.branch = LF_BRANCH_LOAD;
    else
        cli_die(CLI_EXIT_USAGE, "simulate: --branch must be unload or load (got '%s')", branch);
    if (!isnan(noise)) s.noise = noise;
    if (seed >= 0) s.seed = (unsigned long) seed;
    if (!isnan(z0)) s.z0 = z0;
    if (!isnan(F0)) s.F0 = F0;
    if (points >= 0) s.points = (size_t) points;
    if (!isnan(dmax)) s.delta_max = dmax;
    if (!isnan(dmin)) s.delta_min = dmin;
    if (!isnan(past_c)) s.past_c = past_c;
    probes = calloc((size_t) npos, sizeof *probes);
    depth = calloc((size_t) npos, sizeof *depth);
    force = calloc((size_t) npos, sizeof *force);
    sigma = calloc((size_t) npos, sizeof *sigma);
    if (!probes || !depth || !force || !sigma)
        cli_die(CLI_EXIT_FAIL, "simulate: out of memory");
    for (i = 0; i < npos; i++) {
        parse_probe(argv[i], &probes[i]);
        if (probes[i].base == LF_BASE_BONDED && isnan(nu))
            cli_die(CLI_EXIT_USAGE, "simulate: --nu is required for a bonded probe (e.g. --nu 0.3)");
        depth[i] = malloc((s.points ? s.points : 1) * sizeof **depth);
        force[i] = malloc((s.points ? s.points : 1) * sizeof **force);
        if (!depth[i] || !force[i])
            cli_die(CLI_EXIT_FAIL, "simulate: out of memory");
    }
    mat.w = w;
    mat.Estar = E;
    mat.nu = isnan(nu) ? 0.3 : nu;
    if (lf_simulate(&s, type, &mat, (size_t) npos, probes, depth, force, sigma, &err) != LF_OK)
        cli_die(CLI_EXIT_USAGE, "simulate: %s", err.msg);
    if (mkdir(out, 0777) != 0 && errno != EEXIST)
        cli_die(CLI_EXIT_FAIL, "simulate: cannot create %s: %s", out, strerror(errno));
    /* no file of an earlier run is replaced unless asked */
    for (j = 0; j < 2 + (size_t) npos; j++) {
        if (j < 2)
            snprintf(path, sizeof path, "%s/%s", out, fixed_names[j]);
        else
            snprintf(path, sizeof path, "%s/curve%zu.csv", out, j - 1);
        cli_refuse_existing("simulate", path, force_replace);
    }

    for (j = 0; j < (size_t) npos; j++)
        all_bonded &= probes[j].base == LF_BASE_BONDED;
    plan = open_out(&oplan, out, "plan.csv", path, sizeof path);
    fputs("file,k,R_m,b_m,interface,nu\n", plan);
    for (j = 0; j < (size_t) npos; j++) {
        char name[64], cpath[4096];
        FILE *c;

        snprintf(name, sizeof name, "curve%zu.csv", j + 1);
        fprintf(plan, "%s,", name);
        cli_print_double(plan, probes[j].k);
        fputc(',', plan);
        cli_print_double(plan, probes[j].R);
        fputc(',', plan);
        cli_print_double(plan, probes[j].b);
        fprintf(plan, ",%s,", cli_base_name(probes[j].base));
        /* nu where the fit needs it given: bonded curves alone do not
         * determine it (with a frictionless one they do, and it is left
         * to the fit) */
        if (probes[j].base == LF_BASE_BONDED && all_bonded)
            cli_print_double(plan, nu);
        fputc('\n', plan);
        c = open_out(&ocurve, out, name, cpath, sizeof cpath);
        fputs("depth_m,force_N,segment\n", c);
        for (k = 0; k < s.points; k++) {
            cli_print_double(c, depth[j][k]);
            fputc(',', c);
            cli_print_double(c, force[j][k]);
            fprintf(c, ",%s\n", s.branch == LF_BRANCH_LOAD ? "load" : "unload");
        }
        close_out(&ocurve);
    }
    close_out(&oplan);

    truth = open_out(&otruth, out, "truth.csv", path, sizeof path);
    fputs("file,k,R_m,b_m,interface,w_J_m2,Estar_Pa,nu,z0_m,F0_N,noise_sd_N,seed,model\n", truth);
    for (j = 0; j < (size_t) npos; j++) {
        const double v[] = { probes[j].k, probes[j].R, probes[j].b };
        const double m[] = { mat.w, mat.Estar, nu, s.z0, s.F0, sigma[j] };
        fprintf(truth, "curve%zu.csv", j + 1);
        for (k = 0; k < 3; k++) {
            fputc(',', truth);
            cli_print_double(truth, v[k]);
        }
        fprintf(truth, ",%s", cli_base_name(probes[j].base));
        for (k = 0; k < 6; k++) {
            fputc(',', truth);
            if (isfinite(m[k]))
                cli_print_double(truth, m[k]);
        }
        fprintf(truth, ",%lu,%s\n", s.seed, type->name);
    }
    close_out(&otruth);
    for (i = 0; i < npos; i++) {
        free(depth[i]);
        free(force[i]);
    }
    free(depth);
    free(force);
    free(sigma);
    free(probes);
    return CLI_EXIT_OK;
}
