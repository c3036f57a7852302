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

const char *
cli_probe_given(const lf_fit_options *o)
{
    static const char *const names[] = { "k", "R", "b", "interface", "tip", "half-angle", "B" };
    static const char *const flags[] = { "--k", "--R", "--b", "--interface", "--tip",
                                         "--half-angle", "--B" };
    size_t i;

    for (i = 0; i < sizeof names / sizeof names[0]; i++)
        if (lf_fit_options_get(o, names[i]) != NULL)
            return flags[i];
    return NULL;
}

void
cli_probe_state(const char *cmd, const lf_probe_statement *a, lf_probe *p)
{
    lf_error err;

    if (lf_probe_state(a, p, &err) != LF_OK)
        cli_die(CLI_EXIT_USAGE, "%s: %s", cmd, err.msg);
}

lf_plan *
cli_files_plan(const lf_fit_options *o, const lf_fit_request *req, size_t n, char *const *files)
{
    const char *sample = lf_fit_options_get(o, "sample");
    const char *group_by = lf_fit_options_get(o, "group-by");
    const lf_input_settings *is = &req->input;
    lf_probe_statement pa;
    char file[4096];
    lf_plan *plan;
    lf_probe p;
    lf_error err;
    long index;
    size_t i;

    lf_fit_options_statement(o, &pa);
    if (!lf_probe_shape_stated(&pa))
        cli_die(CLI_EXIT_USAGE, "fit: %s is a curve file, not a plan: state the probe of its "
                "curves, e.g. --k 2 --model halfspace (R from the file's header, or --R; --b and "
                "--interface for a layer), or --tip sphere, cone, berkovich or pyramid",
                files[0]);
    cli_probe_state("fit", &pa, &p);
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
