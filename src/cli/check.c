/* cli/check.c: `layerfit check FILE`: load a fit plan and every curve it
 * lists, or a single curve file, and say what was found.  Everything is
 * read and checked before anything is printed, so that a bad input gives
 * one error message (exit status 2) and no partial report. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"

static void
usage(FILE *f)
{
    fprintf(f,
        "usage: layerfit check [OPTIONS] FILE\n\n"
        "Read a fit plan (a CSV whose header has a 'file' column) and every curve\n"
        "it lists, or one curve file, and report points, ranges, segments and\n"
        "metadata.  A file of many curves (a force map, QI data, a force volume)\n"
        "is listed: each curve's index, position, grid place, points and segments;\n"
        "FILE#N shows its curve N.  Errors go to stderr as FILE:LINE:COLUMN:\n"
        "message (exit 2).\n\n"
        "options:\n"
        "  --depth-unit UNIT   unit of the depth column when the header has none (nm)\n"
        "  --force-unit UNIT   unit of the force column when the header has none (uN)\n"
        "  --skip-bad-rows     skip rows with missing cells, with a warning\n"
        "  --format NAME       the file's format instead of sniffing it (csv, chiaro,\n"
        "                      jpk, workshop, ntmdt, hysitron, text, tab, jpk-force,\n"
        "                      workshop-map, nanoscope, igor)\n"
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
    if (isfinite(c->x)) {
        char x[48], y[48];
        printf("  %-9s x %s, y %s", "position", cli_human(x, sizeof x, c->x, "m"),
               cli_human(y, sizeof y, c->y, "m"));
        if (c->grid_i >= 0)
            printf(" (grid column %ld, row %ld)", c->grid_i, c->grid_j);
        printf("\n");
    }
    for (i = 0; i < c->nmeta; i++)
        printf("  %-9s %s: %s\n", "metadata", c->meta[i].key, meta_value(c->meta[i].value));
}

static void
print_probe(const lf_plan_row *r, const lf_curve *c)
{
    char shape[160], b[48];
    lf_probe p = r->probe;
    const int from_header = isnan(p.R) && lf_probe_uses_R(&p);
    if (isnan(r->probe.b))          /* no layer: a half-space fit only */
        snprintf(b, sizeof b, "none");
    if (from_header)
        p.R = c ? c->R : NAN;
    printf("  %-9s %s%s, b = %s, %s\n", "probe", cli_probe_words(shape, sizeof shape, &p),
           from_header ? " (file header)" : "",
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

/* What check found in one curve file: its curve, or, for a file of many
 * curves named without an index, the listing of its curves. */
typedef struct {
    lf_curve *curve;
    lf_file *file;              /* the file listed (its name and format) */
    lf_curve_info *info;        /* its curves, as their headers state them */
} entry;

static void
entry_free(entry *e)
{
    lf_curve_free(e->curve);
    lf_file_close(e->file);
    free(e->info);
    memset(e, 0, sizeof *e);
}

/* The entry of file f: curve index (-1: its only one, or all listed). */
static int
entry_from(lf_file *f, long index, lf_segment seg, entry *e, lf_warnings *warn, lf_error *err)
{
    size_t n = lf_file_count(f), i;
    int status;

    memset(e, 0, sizeof *e);
    if (index < 0 && n > 1) {
        e->file = f;
        if ((e->info = calloc(n, sizeof *e->info)) == NULL)
            return LF_ENOMEM;
        for (i = 0; i < n; i++)
            if ((status = lf_file_info(f, i, &e->info[i], err)) != LF_OK)
                return status;
        return LF_OK;
    }
    status = lf_file_curve(f, index < 0 ? 0 : (size_t) index, &e->curve, warn, err);
    lf_file_close(f);
    if (status == LF_OK && (status = lf_curve_check_fit(e->curve, seg, CLI_MIN_POINTS, err)) != LF_OK) {
        lf_curve_free(e->curve);
        e->curve = NULL;
    }
    return status;
}

/* The curves of a file of many, one line each. */
static void
print_listing(const entry *e, const char *path)
{
    size_t n = lf_file_count(e->file), i;
    printf("  %-9s %s\n", "format", lf_file_format(e->file));
    printf("  %-9s %zu: a fit takes one (%s#0 .. #%zu, or a plan's index column); "
           "layerfit fit --batch fits each\n", "curves", n, path, n - 1);
    printf("  %-6s %-12s %-12s %-10s %-7s %s\n", "index", "x", "y", "grid", "points",
           "segments (load, hold, unload)");
    for (i = 0; i < n; i++) {
        const lf_curve_info *c = &e->info[i];
        char x[48] = "-", y[48] = "-", g[32] = "-";
        if (isfinite(c->x)) {
            cli_human(x, sizeof x, c->x, "m");
            cli_human(y, sizeof y, c->y, "m");
        }
        if (c->grid_i >= 0)
            snprintf(g, sizeof g, "%ld,%ld", c->grid_i, c->grid_j);
        printf("  %-6zu %-12s %-12s %-10s %-7zu %zu, %zu, %zu\n", i, x, y, g, c->points,
               c->segment_points[LF_SEG_LOAD], c->segment_points[LF_SEG_HOLD],
               c->segment_points[LF_SEG_UNLOAD]);
    }
}

int
cli_check(int argc, char **argv, const char *command_line)
{
    lf_read_opts o;
    lf_error err;
    lf_warnings warn = { 0, NULL };
    lf_file_kind kind = LF_FILE_CURVE;
    lf_input in;
    lf_plan *plan = NULL;
    lf_file *f = NULL;
    entry *curves = NULL;
    size_t i, ncurves = 0;
    int npos, help, status = LF_OK;
    long index;
    const char *kc = NULL, *sens = NULL;
    char file[4096];
    struct stat st;
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
    if (lf_curve_path_split(argv[0], file, sizeof file, &index) != LF_OK)
        cli_die(CLI_EXIT_USAGE, "check: %s: path too long", argv[0]);
    /* a text file named here is read once, whole (it may be a pipe or a
     * FIFO, read as a stream), then parsed as a plan or a curve; a binary
     * file of many curves by random access, never whole.  The curves a
     * plan names must be regular files.  The same checks as a fit.  A
     * forced format, or "FILE#N", reads a curve. */
    memset(&in, 0, sizeof in);
    if (index < 0 && o.format == NULL
        && !(stat(file, &st) == 0 && S_ISREG(st.st_mode)
             && lf_file_kind_of(file, &kind, &err) == LF_OK && kind == LF_FILE_CURVE)) {
        status = lf_input_read_sniffed(file, LF_INPUT_STREAM, &in, &err);
        if (status == LF_OK)
            status = lf_file_kind_parse(in.data, in.len, file, &kind, &err);
        if (status == LF_OK && kind == LF_FILE_PLAN) {
            status = cli_plan_from(&in, file, &plan, &warn, &err);
            ncurves = status == LF_OK ? plan->n : 0;
        } else if (status == LF_OK) {
            status = lf_file_open_memory(in.data, in.len, file, &o, &f, &warn, &err);
            ncurves = 1;
        }
    } else {
        status = lf_file_open(file, LF_INPUT_STREAM, &o, &f, &warn, &err);
        ncurves = 1;
    }
    if (status == LF_OK && (curves = calloc(ncurves, sizeof *curves)) == NULL)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    if (status == LF_OK && plan == NULL) {
        status = entry_from(f, index, LF_SEG_UNLOAD, &curves[0], &warn, &err);
        f = NULL;           /* the entry's now */
    }
    for (i = 0; plan != NULL && i < ncurves && status == LF_OK; i++) {
        lf_read_opts ro = o;
        lf_plan_row *row = &plan->rows[i];
        lf_file *rf;
        if (ro.format == NULL && row->format[0] != '\0')
            ro.format = row->format;
        status = lf_file_open(row->file, 0, &ro, &rf, &warn, &err);
        if (status == LF_OK)
            status = entry_from(rf, row->index, row->segment, &curves[i], &warn, &err);
        if (status != LF_OK && err.line == 0) {
            /* a file that cannot be read: say which row names it */
            char m[sizeof err.msg];
            snprintf(m, sizeof m, "curve file %.200s: %.220s (paths are relative to the "
                     "plan's folder)", err.file, err.msg);
            snprintf(err.msg, sizeof err.msg, "%s", m);
            snprintf(err.file, sizeof err.file, "%s", plan->path);
            err.line = row->line;
        }
        if (status == LF_OK && isnan(row->probe.R) && lf_probe_uses_R(&row->probe)
            && curves[i].curve != NULL
            && !(curves[i].curve->R > 0)) {
            snprintf(err.file, sizeof err.file, "%s", plan->path);
            err.line = row->line;
            err.column = 0;
            snprintf(err.msg, sizeof err.msg, "R 'header', but %s states no probe radius "
                     "(give R in the plan)", row->file);
            status = err.status = LF_EDATA;
        }
    }
    if (status == LF_OK) {
        cli_print_warnings(&warn);
        if (plan != NULL)
            printf("plan %s: %zu curve%s\n", plan->path, plan->n, plan->n == 1 ? "" : "s");
        for (i = 0; i < ncurves; i++) {
            if (plan != NULL) {
                if (plan->rows[i].index >= 0)
                    printf("%s#%ld (plan line %ld)\n", plan->rows[i].file, plan->rows[i].index,
                           plan->rows[i].line);
                else
                    printf("%s (plan line %ld)\n", plan->rows[i].file, plan->rows[i].line);
                print_probe(&plan->rows[i], curves[i].curve);
            } else if (curves[i].curve != NULL) {
                printf("curve %s\n", curves[i].curve->file);
            } else {
                printf("file %s\n", file);
            }
            if (curves[i].curve != NULL)
                print_curve(curves[i].curve, plan ? plan->rows[i].segment : LF_SEG_UNLOAD);
            else
                print_listing(&curves[i], plan != NULL ? plan->rows[i].file : file);
        }
    }
    for (i = 0; i < ncurves && curves != NULL; i++)
        entry_free(&curves[i]);
    lf_file_close(f);
    free(curves);
    lf_input_free(&in);
    lf_plan_free(plan);
    lf_warnings_free(&warn);
    if (status == LF_ENOMEM)
        cli_die(CLI_EXIT_FAIL, "out of memory");
    if (status != LF_OK)
        cli_die_error(CLI_EXIT_USAGE, &err);
    return CLI_EXIT_OK;
}
