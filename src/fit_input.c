/* fit_input.c: the one step from a plan (or one curve file) to the curves
 * a fit takes -- read each curve file, keep the points of its segment in
 * SI, attach the row's probe, branch and held offsets, and apply the one
 * nu rule of layerfit.h.  The input owns everything it points to. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"

lf_input_settings
lf_input_settings_default(void)
{
    lf_input_settings s;
    s.segment = -1;
    s.z0 = s.F0 = NAN;
    s.read = NULL;
    s.min_points = 5;
    s.window = lf_window_all();
    s.open_flags = 0;
    return s;
}

void
lf_fit_input_free(lf_fit_input *in)
{
    size_t j;

    if (in == NULL)
        return;
    if (in->points != NULL)
        for (j = 0; j < 2 * in->n; j++)
            free(in->points[j]);
    if (in->names != NULL)
        for (j = 0; j < in->n; j++)
            free(in->names[j]);
    free(in->points);
    free(in->names);
    free(in->sha256);
    free(in->R_source);
    free(in->format);
    free(in->origin);
    free(in->index);
    free(in->observed);
    free(in->window);
    free(in->curves);
    memset(in, 0, sizeof *in);
}

static int
input_alloc(lf_fit_input *in, size_t n)
{
    memset(in, 0, sizeof *in);
    in->nu = in->x = in->y = NAN;
    in->grid_i = in->grid_j = -1;
    in->n = n;
    in->curves = calloc(n ? n : 1, sizeof *in->curves);
    in->points = calloc(2 * n + 1, sizeof *in->points);
    in->names = calloc(n ? n : 1, sizeof *in->names);
    in->sha256 = calloc(n ? n : 1, sizeof *in->sha256);
    in->R_source = calloc(n ? n : 1, sizeof *in->R_source);
    in->format = calloc(n ? n : 1, sizeof *in->format);
    in->origin = calloc(n ? n : 1, sizeof *in->origin);
    in->index = calloc(n ? n : 1, sizeof *in->index);
    in->observed = calloc(n ? n : 1, sizeof *in->observed);
    in->window = calloc(n ? n : 1, sizeof *in->window);
    return in->curves && in->points && in->names && in->sha256 && in->R_source && in->format
           && in->origin && in->index && in->observed && in->window ? LF_OK : LF_ENOMEM;
}

/* The probe of a curve: R from the file's header where the caller gives
 * none (NaN), b = R as a stand-in where the caller gives no thickness (NaN:
 * a half-space, which uses none), then checked. */
static int
resolve_probe(lf_probe *p, const lf_curve *c, const char *path, const char *given,
              const char **R_source, lf_warnings *warn, lf_error *err)
{
    lf_error e;
    *R_source = given;
    if (!lf_probe_uses_R(p)) {
        /* a cone, a pyramid or a stated prefactor: no R, none from the file */
        *R_source = "not used";
        if (isnan(p->b))
            p->b = lf_probe_length(p);
        if (lf_probe_check(p, &e) != LF_OK)
            return lf_fail(err, e.status, "%s: %s", path, e.msg);
        return LF_OK;
    }
    if (!isnan(p->R) && c->R > 0 && isfinite(c->R) && fabs(p->R - c->R) > 1e-9 * c->R)
        lf_warn(warn, "%s: R = %.4g m from the %s, where the file header states %.4g m",
                path, p->R, strcmp(given, "plan") == 0 ? "plan" : "--R option", c->R);
    if (isnan(p->R)) {
        if (!(c->R > 0 && isfinite(c->R)))
            return lf_fail(err, LF_EDATA, strcmp(given, "plan") == 0
                           ? "%s: no probe radius: the plan's row says R = header and the file "
                             "states none (give the radius in the plan's R column, e.g. R_um 8)"
                           : "%s: no probe radius: the file states none (give --R, e.g. --R 8um)",
                           path);
        p->R = c->R;
        *R_source = "file header";
    }
    if (isnan(p->b))
        p->b = p->R;
    if (lf_probe_check(p, &e) != LF_OK)
        return lf_fail(err, e.status, "%s: %s", path, e.msg);
    return LF_OK;
}

/* The curve of a plan row or a command line: curve index of the file at
 * path (-1: its only one), from source when the file is open already
 * (lf_plan_expand), else opened here.  sha256 gets the file's. */
static int
read_one(const char *path, long index, lf_file *source, const lf_read_opts *ro,
         unsigned flags, lf_curve **out, char sha256[65], lf_warnings *warn, lf_error *err)
{
    lf_file *f = source;
    int status = LF_OK;
    size_t n;

    if (f == NULL && (status = lf_file_open(path, flags, ro, &f, warn, err)) != LF_OK)
        return status;
    n = lf_file_count(f);
    if (index < 0 && n > 1)
        status = lf_fail_at(err, LF_EDATA, path, 0, 0, "holds %zu curves: a fit of one "
                            "material takes one curve per row: name one as %s#0 .. %s#%zu (or "
                            "in the plan's index column), or fit each on its own with "
                            "layerfit fit --batch", n, path, path, n - 1);
    else
        status = lf_file_curve(f, index < 0 ? 0 : (size_t) index, out, warn, err);
    memcpy(sha256, lf_file_sha256(f), 65);
    if (f != source)
        lf_file_close(f);
    return status;
}

/* Keep the points of curve j within its placed window (in->window[j]),
 * in order; LF_EDATA when fewer than min_points remain. */
static int
apply_window(lf_fit_input *in, size_t j, size_t *n, size_t min_points, lf_error *err)
{
    lf_window_placed *w = &in->window[j];
    double *z = in->points[2 * j], *F = in->points[2 * j + 1];
    size_t i, m = 0;

    w->n_in = *n;
    for (i = 0; i < *n; i++)
        if (!w->active || lf_window_keeps(w, z[i], F[i])) {
            z[m] = z[i];
            F[m++] = F[i];
        }
    w->n_kept = *n = m;
    if (m < min_points)
        return lf_fail(err, LF_EDATA, "%s: the fit window keeps %zu of its %zu points (at "
                       "least %zu are needed)", in->names[j], m, w->n_in, min_points);
    return LF_OK;
}

/* Curve j of in from the file at path (curve index of it, -1 its only
 * one; source: the file already open, or NULL); format is the plan's
 * format column ("" or NULL: the settings' format, else sniffed); win the
 * row's fit window (the settings' wins where it is not all). */
static int
add_curve(lf_fit_input *in, size_t j, const char *path, long index, lf_file *source,
          lf_segment seg, const lf_probe *probe, const char *given, const char *format,
          double z0, double F0, const lf_window *win, const lf_input_settings *s,
          lf_warnings *warn, lf_error *err)
{
    lf_curve *c = NULL;
    lf_fit_curve *fc = &in->curves[j];
    lf_read_opts ro;
    lf_probe p = *probe;
    char split[4096];
    size_t n;
    int status;
    lf_error e;

    if (s->read != NULL)
        ro = *s->read;
    else
        lf_read_opts_default(&ro);
    if (ro.format == NULL && format != NULL && format[0] != '\0')
        ro.format = format;
    /* "FILE#N" names curve N of FILE */
    if (index < 0 && source == NULL) {
        if (lf_curve_path_split(path, split, sizeof split, &index) != LF_OK)
            return lf_fail_at(err, LF_EINVAL, path, 0, 0, "path too long");
        path = split;
    }
    /* a text export is read once, whole, from a checked descriptor (what is
     * parsed is what is hashed); an archive by random access, hashed whole
     * when it is opened */
    status = read_one(path, index, source, &ro, s->open_flags, &c, in->sha256[j], warn, err);
    if (status != LF_OK)
        return status;
    if ((status = lf_curve_check_fit(c, seg, s->min_points, err)) != LF_OK
        || (status = resolve_probe(&p, c, c->file, given, &in->R_source[j], warn, err)) != LF_OK) {
        lf_curve_free(c);
        return status;
    }
    if (j == 0) {
        in->x = c->x;
        in->y = c->y;
        in->grid_i = c->grid_i;
        in->grid_j = c->grid_j;
    }
    n = lf_curve_segment(c, seg, NULL, NULL);
    in->points[2 * j] = malloc(n * sizeof(double));
    in->points[2 * j + 1] = malloc(n * sizeof(double));
    in->names[j] = lf_strdup(c->file);
    if (!in->points[2 * j] || !in->points[2 * j + 1] || !in->names[j]
        || lf_observe(c, &in->observed[j], NULL) != LF_OK) {
        lf_curve_free(c);
        return lf_fail(err, LF_ENOMEM, "out of memory reading %s", path);
    }
    if (!lf_window_is_all(&s->window))
        win = &s->window;
    if ((status = lf_window_place(win, &in->observed[j], &in->window[j], &e)) != LF_OK) {
        lf_curve_free(c);
        return lf_fail(err, status, "%s: %s", in->names[j], e.msg);
    }
    in->index[j] = c->index;
    in->format[j] = c->format;
    in->origin[j].R = in->R_source[j];
    in->origin[j].b = isnan(probe->b) ? NULL : given;
    in->origin[j].spring_constant = c->spring_constant;
    in->origin[j].spring_constant_source = c->spring_constant_source;
    in->origin[j].sensitivity = c->sensitivity;
    in->origin[j].sensitivity_unit = c->sensitivity_unit;
    in->origin[j].sensitivity_source = c->sensitivity_source;
    lf_curve_segment(c, seg, in->points[2 * j], in->points[2 * j + 1]);
    lf_curve_free(c);
    if ((status = apply_window(in, j, &n, s->min_points, err)) != LF_OK)
        return status;
    fc->name = in->names[j];
    fc->n = n;
    fc->depth = in->points[2 * j];
    fc->force = in->points[2 * j + 1];
    fc->probe = p;
    fc->branch = seg;
    fc->z0 = isnan(s->z0) ? z0 : s->z0;
    fc->F0 = isnan(s->F0) ? F0 : s->F0;
    fc->model = NULL;
    return LF_OK;
}

/* Curve j's file holds the same bytes (SHA-256) as an earlier row's with the
 * same segment: the same measurement under two names would count its
 * evidence twice (the plan refuses one name listed twice itself). */
static int
same_data_before(const lf_plan *plan, const size_t *rows, const lf_fit_input *in, size_t j,
                 lf_error *err)
{
    const lf_plan_row *row = &plan->rows[rows ? rows[j] : j];
    size_t i;

    for (i = 0; i < j; i++) {
        if (in->curves[i].branch != in->curves[j].branch || in->index[i] != in->index[j]
            || strcmp(in->sha256[i], in->sha256[j]) != 0)
            continue;
        if (plan->of_files)         /* files named by the caller, no plan lines */
            return lf_fail(err, LF_EDATA, "%s holds the same data as %s (SHA-256 %.12s...): one "
                           "measurement given twice would count twice (give it once)",
                           row->file, in->names[i], in->sha256[j]);
        return lf_fail_at(err, LF_EDATA, plan->path, row->line, 0,
                          "%s holds the same data as %s (line %ld; SHA-256 %.12s...): one "
                          "measurement listed twice would count twice (list it once)",
                          row->file, in->names[i], plan->rows[rows ? rows[i] : i].line,
                          in->sha256[j]);
    }
    return LF_OK;
}

/* An error about a row's curve that names no place in a file (no radius
 * where the row says R = header, a probe the model refuses) is put at the
 * row's line of the plan: the message names the curve's file, the place
 * says which row asked for it.  One inside the curve file (a bad cell, a
 * segment too short) keeps the file's own place. */
static void
at_row(lf_error *err, const lf_plan *plan, const lf_plan_row *row)
{
    char msg[sizeof err->msg];

    memcpy(msg, err->msg, sizeof msg);
    lf_fail_at(err, err->status, plan->path, row->line, 0, "%s", msg);
}

/* One joint fit is of one material: the rows' non-empty samples must agree
 * (checked before any file is read; the nu rule is its twin, below). */
static int
one_sample(const lf_plan *plan, const size_t *rows, size_t n, lf_error *err)
{
    const char *first = NULL;
    size_t j;

    for (j = 0; j < n; j++) {
        const lf_plan_row *row = &plan->rows[rows ? rows[j] : j];
        if (row->sample == NULL || row->sample[0] == '\0')
            continue;
        if (first == NULL)
            first = row->sample;
        else if (strcmp(first, row->sample) != 0)
            return lf_fail_at(err, LF_EDATA, plan->path, row->line, 0,
                              "sample '%s', where an earlier row's is '%s': a joint fit is of "
                              "one material (give each sample a plan of its own, or run "
                              "'layerfit fit --batch', which fits each sample on its own)",
                              row->sample, first);
    }
    return LF_OK;
}

int
lf_fit_input_from_plan(const lf_plan *plan, const size_t *rows, size_t nrows,
                       const lf_input_settings *s, lf_fit_input *in, lf_warnings *warn,
                       lf_error *err)
{
    lf_input_settings def = lf_input_settings_default();
    size_t j, n = rows ? nrows : plan->n;
    int status;

    if (s == NULL)
        s = &def;
    if (input_alloc(in, n) != LF_OK) {
        lf_fit_input_free(in);
        return lf_fail(err, LF_ENOMEM, "out of memory");
    }
    if ((status = one_sample(plan, rows, n, err)) != LF_OK) {
        lf_fit_input_free(in);
        return status;
    }
    for (j = 0; j < n; j++) {
        const lf_plan_row *row = &plan->rows[rows ? rows[j] : j];
        if (!isnan(row->nu)) {
            if (!isnan(in->nu) && in->nu != row->nu) {
                double earlier = in->nu;
                lf_fit_input_free(in);
                return lf_fail_at(err, LF_EDATA, plan->path, row->line, 0,
                                  "nu %g differs from an earlier row's %g (one material, "
                                  "one nu)", row->nu, earlier);
            }
            in->nu = row->nu;
        }
        status = add_curve(in, j, row->file, row->index, row->source,
                           s->segment >= 0 ? (lf_segment) s->segment : row->segment,
                           &row->probe, plan->of_files ? "option" : "plan", row->format,
                           row->z0, row->F0, &row->window, s, warn, err);
        if (status != LF_OK && err != NULL && err->file[0] == '\0' && !plan->of_files)
            at_row(err, plan, row);
        if (status == LF_OK)
            status = same_data_before(plan, rows, in, j, err);
        if (status != LF_OK) {
            lf_fit_input_free(in);
            return status;
        }
    }
    return LF_OK;
}

int
lf_fit_input_from_curve(const char *path, const lf_probe *probe, const lf_input_settings *s,
                        lf_fit_input *in, lf_warnings *warn, lf_error *err)
{
    lf_input_settings def = lf_input_settings_default();
    int status;

    if (s == NULL)
        s = &def;
    if ((!isnan(probe->R) || !lf_probe_uses_R(probe)) && !isnan(probe->b)
        && (status = lf_probe_check(probe, err)) != LF_OK)
        return status;
    if (input_alloc(in, 1) != LF_OK) {
        lf_fit_input_free(in);
        return lf_fail(err, LF_ENOMEM, "out of memory");
    }
    status = add_curve(in, 0, path, -1, NULL,
                       s->segment >= 0 ? (lf_segment) s->segment : LF_SEG_UNLOAD,
                       probe, "option", NULL, NAN, NAN, &s->window, s, warn, err);
    if (status != LF_OK)
        lf_fit_input_free(in);
    return status;
}

void
lf_fit_input_apply_nu(const lf_fit_input *in, lf_fit_settings *settings)
{
    if (!isnan(in->nu) && settings->nu.mode != LF_PARAM_FIXED) {
        settings->nu.mode = LF_PARAM_FIXED;
        settings->nu.value = in->nu;
    }
}
