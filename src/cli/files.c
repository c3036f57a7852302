/* cli/files.c: curves named on the command line -- `layerfit fit FILE...`
 * and `layerfit fit --batch FILE...`: their probe, stated once for all by
 * the options as labs state it (--k with --R or --B, --tip, --half-angle;
 * R from each file's header where --R is absent), and the files as a plan
 * of one row each, with their samples from --sample or --group-by.  Every
 * message asks only for what is missing. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

void
cli_probe_args_init(cli_probe_args *a)
{
    a->k = a->R = a->b = a->half_angle = a->B = NAN;
    a->interface = a->tip = NULL;
}

size_t
cli_probe_opts(cli_probe_args *a, cli_opt *opts)
{
    const cli_opt table[CLI_PROBE_NOPTS] = {
        { "k", CLI_NUMBER, &a->k }, { "R", CLI_LENGTH, &a->R }, { "b", CLI_LENGTH, &a->b },
        { "interface", CLI_STRING, &a->interface }, { "tip", CLI_STRING, &a->tip },
        { "half-angle", CLI_ANGLE, &a->half_angle }, { "B", CLI_NUMBER, &a->B },
    };
    memcpy(opts, table, sizeof table);
    return CLI_PROBE_NOPTS;
}

const char *
cli_probe_given(const cli_probe_args *a)
{
    return !isnan(a->k) ? "--k" : !isnan(a->R) ? "--R" : !isnan(a->b) ? "--b"
         : a->interface != NULL ? "--interface" : a->tip != NULL ? "--tip"
         : !isnan(a->half_angle) ? "--half-angle" : !isnan(a->B) ? "--B" : NULL;
}

int
cli_probe_shape_given(const cli_probe_args *a)
{
    return !isnan(a->k) || a->tip != NULL || !isnan(a->half_angle) || !isnan(a->B);
}

/* The layer of the options: b and interface together, or neither for a
 * half-space; *base filled.  Dies naming what is missing. */
static void
layer_of(const char *cmd, const char *model, const cli_probe_args *a, lf_base *base)
{
    const int halfspace = cli_model_ignores_b(model);
    int bb;

    *base = LF_BASE_FRICTIONLESS;
    if (!isnan(a->b) && a->interface == NULL)
        cli_die(CLI_EXIT_USAGE, "%s: --b needs --interface (frictionless or bonded)%s", cmd,
                halfspace ? "; the half-space model uses neither: leave both out" : "");
    if (isnan(a->b) && a->interface != NULL)
        cli_die(CLI_EXIT_USAGE, "%s: --interface needs --b (the layer's thickness, e.g. "
                "--b 1um)%s", cmd, halfspace ? "; the half-space model uses neither: leave both out"
                : "");
    if (isnan(a->b)) {
        if (!halfspace)
            cli_die(CLI_EXIT_USAGE, "%s: the %s model needs the layer: --b and --interface "
                    "(e.g. --b 1um --interface frictionless), or fit the curves as a half-space "
                    "with --model halfspace (no layer)", cmd, model);
        return;
    }
    if ((bb = cli_base(a->interface)) < 0)
        cli_die(CLI_EXIT_USAGE, "%s: unknown interface '%s' (frictionless or bonded)", cmd,
                a->interface);
    *base = (lf_base) bb;
}

void
cli_fit_probe(const char *cmd, const char *model, const cli_probe_args *a, lf_probe *p)
{
    double k = a->k, kt = NAN;
    int tip = LF_TIP_POWER;
    lf_probe chk;
    lf_error err;

    memset(p, 0, sizeof *p);
    if (a->tip != NULL) {
        if ((tip = lf_tip_find(a->tip, &kt)) < 0)
            cli_die(CLI_EXIT_USAGE, "%s: unknown --tip '%s' (paraboloid, sphere, cone, "
                    "berkovich, pyramid, or power with --k)", cmd, a->tip);
        if (!isnan(kt) && !isnan(k) && k != kt)
            cli_die(CLI_EXIT_USAGE, "%s: --tip %s is k = %g: leave --k out (got --k %g)", cmd,
                    a->tip, kt, k);
        if (!isnan(kt))
            k = kt;
    } else if (!isnan(a->half_angle)) {
        tip = LF_TIP_CONE;        /* a half-angle alone states a cone */
        if (isnan(k))
            k = 1.0;
    }
    if (isnan(k))
        cli_die(CLI_EXIT_USAGE, "%s: state the probe's shape: --k K (with --R, or R from the "
                "file's header, or --B), or --tip paraboloid, sphere, cone, berkovich or pyramid", cmd);
    if ((tip == LF_TIP_CONE || tip == LF_TIP_PYRAMID) && isnan(a->half_angle))
        cli_die(CLI_EXIT_USAGE, "%s: --tip %s needs its %shalf-angle (e.g. --half-angle 35deg)", cmd,
                lf_tip_name((lf_tip) tip), tip == LF_TIP_PYRAMID ? "faces' " : "");
    if (!isnan(a->half_angle) && tip != LF_TIP_CONE && tip != LF_TIP_PYRAMID)
        cli_die(CLI_EXIT_USAGE, "%s: --half-angle states a cone or a four-sided pyramid "
                "(--tip cone, --tip pyramid); %s", cmd, tip == LF_TIP_BERKOVICH
                ? "a Berkovich tip has its own equivalent cone (70.3 deg): leave it out"
                : "this probe is stated by --R or --B");
    if (!isnan(a->B) && tip != LF_TIP_POWER)
        cli_die(CLI_EXIT_USAGE, "%s: --B is the prefactor of a power law f = B r^k (with --k); "
                "a %s is stated by %s", cmd, lf_tip_name((lf_tip) tip),
                tip == LF_TIP_SPHERE ? "--R" : "its half-angle");
    if (!isnan(a->B) && !isnan(a->R))
        cli_die(CLI_EXIT_USAGE, "%s: --R and --B both state the profile (B = 1/(k R^(k-1))): "
                "give one", cmd);
    if (!isnan(a->R) && (tip == LF_TIP_CONE || tip == LF_TIP_BERKOVICH || tip == LF_TIP_PYRAMID))
        cli_die(CLI_EXIT_USAGE, "%s: R does not shape a %s (f = r cot(alpha)): leave --R out", cmd,
                lf_tip_name((lf_tip) tip));
    if (tip == LF_TIP_POWER && k == 1.0 && isnan(a->B))
        cli_die(CLI_EXIT_USAGE, "%s: k = 1 is a cone, and R does not shape a cone (f = r "
                "whatever R): state its half-angle (--half-angle 35deg, --tip berkovich, or "
                "--tip pyramid --half-angle THETA of its faces) or its prefactor --B (f = B r)", cmd);
    layer_of(cmd, model, a, &p->base);
    p->k = k;
    p->tip = (lf_tip) tip;
    p->angle = tip == LF_TIP_CONE || tip == LF_TIP_PYRAMID ? a->half_angle : 0.0;
    p->B = isnan(a->B) ? 0.0 : a->B;
    p->R = a->R;              /* NaN: from each file's header, where it is used */
    p->b = a->b;              /* NaN: no layer (a half-space) */
    chk = *p;
    if (isnan(chk.R) && lf_probe_uses_R(&chk))
        chk.R = 1.0;          /* checked with the file's R once it is read */
    if (isnan(chk.b))
        chk.b = 1.0;
    if (lf_probe_check(&chk, &err) != LF_OK)
        cli_die(CLI_EXIT_USAGE, "%s: %s", cmd, err.msg);
}

lf_plan *
cli_files_plan(const char *model, size_t n, char *const *files, const cli_probe_args *pa,
               const lf_input_settings *is, const char *sample, const char *group_by)
{
    char file[4096];
    lf_plan *plan;
    lf_probe p;
    lf_error err;
    long index;
    size_t i;

    if (!cli_probe_shape_given(pa))
        cli_die(CLI_EXIT_USAGE, "fit: %s is a curve file, not a plan: state the probe of its "
                "curves, e.g. --k 2 --model halfspace (R from the file's header, or --R; --b and "
                "--interface for a layer), or --tip sphere, cone, berkovich or pyramid",
                files[0]);
    cli_fit_probe("fit", model, pa, &p);
    if (sample != NULL && group_by != NULL)
        cli_die(CLI_EXIT_USAGE, "fit: --sample names one sample for all the files, --group-by "
                "forms several: give one");
    if (sample != NULL && sample[0] == '\0')
        cli_die(CLI_EXIT_USAGE, "fit: --sample needs a name (e.g. --sample PEG10)");
    for (i = 0; i < n; i++) {
        if (lf_curve_path_split(files[i], file, sizeof file, &index) != LF_OK)
            cli_die(CLI_EXIT_USAGE, "fit: %s: path too long", files[i]);
        if (n > 1 && index < 0 && cli_reads_as_plan(file))
            cli_die(CLI_EXIT_USAGE, "fit: %s is a plan: fit a plan on its own (layerfit fit "
                    "PLAN.csv), or name curve files only", files[i]);
        cli_input_guard("fit", file);
    }
    if (lf_plan_of_files(n, (const char *const *) files, &p,
                         is->segment >= 0 ? (lf_segment) is->segment : LF_SEG_UNLOAD, &plan,
                         &err) != LF_OK)
        cli_die_error(err.status == LF_ENOMEM ? CLI_EXIT_FAIL : CLI_EXIT_USAGE, &err);
    for (i = 0; i < plan->n && sample != NULL; i++) {
        char *s = malloc(strlen(sample) + 1);
        if (s == NULL) {
            lf_plan_free(plan);
            cli_die(CLI_EXIT_FAIL, "out of memory");
        }
        strcpy(s, sample);
        free(plan->rows[i].sample);
        plan->rows[i].sample = s;
    }
    if (group_by != NULL && lf_plan_group(plan, group_by, is->read, &err) != LF_OK) {
        lf_plan_free(plan);
        cli_die(err.status == LF_ENOMEM ? CLI_EXIT_FAIL : CLI_EXIT_USAGE, "fit: --group-by: %s",
                err.msg);
    }
    return plan;
}

int
cli_plan_one_sample(const lf_plan *plan, const char **a, const char **b)
{
    size_t i;

    *a = *b = NULL;
    for (i = 1; i < plan->n; i++)
        if (strcmp(plan->rows[i].sample, plan->rows[0].sample) != 0) {
            *a = plan->rows[0].sample;
            *b = plan->rows[i].sample;
            return 0;
        }
    return 1;
}
