/* cli/check.c: `layerfit check FILE`: load a fit plan and every curve it
 * lists, or a single curve file, and say what was found.  Everything is
 * read and checked before anything is printed, so that a bad input gives
 * one error message (exit status 2) and no partial report. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static void
usage(FILE *f)
{
    fprintf(f,
        "usage: layerfit check [OPTIONS] FILE\n\n"
        "Read a fit plan (a CSV whose header has a 'file' column) and every curve\n"
        "it lists, or one curve file, and report points, ranges, segments and\n"
        "metadata.  Errors go to stderr as FILE:LINE:COLUMN: message (exit 2).\n\n"
        "options:\n"
        "  --depth-unit UNIT   unit of the depth column when the header has none (nm)\n"
        "  --force-unit UNIT   unit of the force column when the header has none (uN)\n"
        "  --skip-bad-rows     skip rows with missing cells, with a warning\n"
        "  --format NAME       the file's format instead of sniffing it (csv, chiaro,\n"
        "                      jpk, workshop, ntmdt, hysitron, text)\n"
        "  --spring-constant K cantilever spring constant when the file has none (0.032N/m)\n"
        "  --sensitivity S     deflection sensitivity when the file has none (61nm/nA, 50nm/V)\n");
}

static void
print_range(const char *label, const double *x, size_t n, const char *unit)
{
    char lo[48], hi[48];
    double a = INFINITY, b = -INFINITY;
    size_t i;
    for (i = 0; i < n; i++) {
        a = fmin(a, x[i]);
        b = fmax(b, x[i]);
    }
    printf("  %-9s %s .. %s\n", label, cli_human(lo, sizeof lo, a, unit),
           cli_human(hi, sizeof hi, b, unit));
}

static void
print_free(const char *label, double v, const char *unit)
{
    char buf[48];
    if (isnan(v))
        printf("  %-9s free\n", label);
    else if (unit[0] == '\0')
        printf("  %-9s %g (fixed)\n", label, v);
    else
        printf("  %-9s %s (fixed)\n", label, cli_human(buf, sizeof buf, v, unit));
}

/* What was found in one curve; seg is the segment a fit would use. */

/* A metadata value as shown: an instrument's "NaN" (a setting it left
 * unset) is said in words, never passed on as a number. */
static const char *
meta_value(const char *v)
{
    const char *t = v + strspn(v, " \t");
    if (*t == '+' || *t == '-')
        t++;
    if ((t[0] == 'n' || t[0] == 'N') && (t[1] == 'a' || t[1] == 'A') && (t[2] == 'n' || t[2] == 'N')
        && t[3 + strspn(t + 3, " \t\r")] == '\0')
        return "not a number (unset in the file)";
    return v;
}
static void
print_curve(const lf_curve *c, lf_segment seg)
{
    size_t i, nload = lf_curve_segment(c, LF_SEG_LOAD, NULL, NULL);
    size_t nhold = lf_curve_segment(c, LF_SEG_HOLD, NULL, NULL);

    /* every file says what was made of it: format, columns and units,
     * conversions, segments */
    if (c->format != NULL) {
        printf("  %-9s %s\n", "format", c->format);
        for (i = 0; i < c->info.n; i++)
            printf("  %-9s %s\n", "found", c->info.msg[i]);
    }
    if (nhold > 0)
        printf("  %-9s %zu (load %zu, hold %zu (not fitted), unload %zu)\n", "points", c->n,
               nload, nhold, c->n - nload - nhold);
    else
        printf("  %-9s %zu (load %zu, unload %zu)\n", "points", c->n, nload, c->n - nload);
    print_range("depth", c->depth, c->n, "m");
    print_range("force", c->force, c->n, "N");
    if (c->time != NULL)
        print_range("time", c->time, c->n, "s");
    printf("  %-9s %s segment, %zu points\n", "fit", lf_segment_name(seg),
           lf_curve_segment(c, seg, NULL, NULL));
    for (i = 0; i < c->nmeta; i++)
        printf("  %-9s %s: %s\n", "metadata", c->meta[i].key, meta_value(c->meta[i].value));
}

static void
print_probe(const lf_plan_row *r, const lf_curve *c)
{
    char R[48], b[48];
    if (isnan(r->probe.b))          /* no layer: a half-space fit only */
        snprintf(b, sizeof b, "none");
    printf("  %-9s k = %g, R = %s%s, b = %s, %s\n", "probe", r->probe.k,
           cli_human(R, sizeof R, isnan(r->probe.R) ? c->R : r->probe.R, "m"),
           isnan(r->probe.R) ? " (file header)" : "",
           isnan(r->probe.b) ? b : cli_human(b, sizeof b, r->probe.b, "m"),
           isnan(r->probe.b) ? "no interface (--model halfspace only)"
                             : cli_base_name(r->probe.base));
    if (r->sample[0] != '\0')
        printf("  %-9s %s\n", "sample", r->sample);
    if (isnan(r->nu) && (isnan(r->probe.b) || r->probe.base == LF_BASE_FRICTIONLESS))
        printf("  %-9s not seen (a %s curve does not depend on it)\n", "nu",
               isnan(r->probe.b) ? "half-space" : "frictionless");
    else
        print_free("nu", r->nu, "");
    print_free("z0", r->z0, "m");
    print_free("F0", r->F0, "N");
}

int
cli_check(int argc, char **argv, const char *command_line)
{
    lf_read_opts o;
    lf_error err;
    lf_warnings warn = { 0, NULL };
    lf_file_kind kind;
    lf_input in;
    lf_plan *plan = NULL;
    lf_curve **curves = NULL;
    size_t i, ncurves = 0;
    int npos, help, status;
    const char *kc = NULL, *sens = NULL;
    cli_opt opts[] = {
        { "depth-unit", CLI_STRING, NULL },
        { "force-unit", CLI_STRING, NULL },
        { "skip-bad-rows", CLI_FLAG, NULL },
        { "format", CLI_STRING, NULL },
        { "spring-constant", CLI_STRING, NULL },
        { "sensitivity", CLI_STRING, NULL },
        { NULL, CLI_FLAG, NULL }
    };

    (void) command_line;    /* no provenance record */
    lf_read_opts_default(&o);
    opts[0].target = &o.depth_unit;
    opts[1].target = &o.force_unit;
    opts[2].target = &o.skip_bad_rows;
    opts[3].target = &o.format;
    opts[4].target = &kc;
    opts[5].target = &sens;
    cli_parse("check", argc, argv, opts, &npos, &help);
    if (help) {
        usage(stdout);
        return CLI_EXIT_OK;
    }
    if (lf_read_opts_constants(&o, kc, sens, &err) != LF_OK)
        cli_die(CLI_EXIT_USAGE, "check: %s", err.msg);
    if (npos != 1)
        cli_die(CLI_EXIT_USAGE, "check: expected one file, a plan or a curve "
                "(e.g. layerfit check plan.csv)");
    /* the file named here is read once, whole (it may be a pipe or a
     * FIFO, read as a stream), then parsed; the curves a plan names must be
     * regular files.  The same checks as a fit (cli_curve_load).  A forced
     * format reads a curve. */
    status = lf_input_read(argv[0], LF_INPUT_STREAM, &in, &err);
    if (status == LF_OK) {
        if (o.format != NULL)
            kind = LF_FILE_CURVE;
        else
            status = lf_file_kind_parse(in.data, in.len, argv[0], &kind, &err);
        if (status == LF_OK && kind == LF_FILE_PLAN) {
            status = cli_plan_from(&in, argv[0], &plan, &warn, &err);
            ncurves = status == LF_OK ? plan->n : 0;
        } else if (status == LF_OK) {
            ncurves = 1;
        }
    }
    if (status == LF_OK && (curves = calloc(ncurves, sizeof *curves)) == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    for (i = 0; i < ncurves && status == LF_OK; i++) {
        lf_read_opts ro = o;
        if (plan && ro.format == NULL && plan->rows[i].format[0] != '\0')
            ro.format = plan->rows[i].format;
        if (plan == NULL)
            status = cli_curve_from(&in, argv[0], &ro, LF_SEG_UNLOAD, &curves[i], &warn, &err);
        else
            status = cli_curve_load(plan->rows[i].file, 0, &ro, plan->rows[i].segment,
                                    &curves[i], NULL, &warn, &err);
        if (status != LF_OK && plan != NULL && err.line == 0) {
            /* a file that cannot be read: say which row names it */
            char m[sizeof err.msg];
            snprintf(m, sizeof m, "curve file %.200s: %.220s (paths are relative to the "
                     "plan's folder)", err.file, err.msg);
            snprintf(err.msg, sizeof err.msg, "%s", m);
            snprintf(err.file, sizeof err.file, "%s", plan->path);
            err.line = plan->rows[i].line;
        }
        if (status == LF_OK && plan && isnan(plan->rows[i].probe.R) && !(curves[i]->R > 0)) {
            snprintf(err.file, sizeof err.file, "%s", plan->path);
            err.line = plan->rows[i].line;
            err.column = 0;
            snprintf(err.msg, sizeof err.msg, "R 'header', but %s states no probe radius "
                     "(give R in the plan)", plan->rows[i].file);
            status = err.status = LF_EDATA;
        }
    }
    lf_input_free(&in);
    if (status == LF_OK) {
        cli_print_warnings(&warn);
        if (plan != NULL)
            printf("plan %s: %zu curve%s\n", plan->path, plan->n, plan->n == 1 ? "" : "s");
        for (i = 0; i < ncurves; i++) {
            if (plan != NULL) {
                printf("%s (plan line %ld)\n", plan->rows[i].file, plan->rows[i].line);
                print_probe(&plan->rows[i], curves[i]);
            } else {
                printf("curve %s\n", curves[i]->file);
            }
            print_curve(curves[i], plan ? plan->rows[i].segment : LF_SEG_UNLOAD);
        }
    }
    for (i = 0; i < ncurves && curves != NULL; i++)
        lf_curve_free(curves[i]);
    free(curves);
    lf_plan_free(plan);
    lf_warnings_free(&warn);
    if (status != LF_OK)
        cli_die_error(status == LF_ENOMEM ? CLI_EXIT_FAIL : CLI_EXIT_USAGE, &err);
    return CLI_EXIT_OK;
}
