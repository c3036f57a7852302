/* assumed.c: what a fit assumed rather than fitted -- a held w, E* or nu,
 * held offsets, a probe radius read from a file's header -- for the top of
 * every report (text, HTML, JSON), so that nothing is assumed without
 * saying so.  See lf_fit_assumptions in layerfit.h. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "internal.h"

/* Some curve of the fit depends on nu: a bonded layer under a model that
 * has one (the half-space ignores the interface). */
static int
uses_nu(const lf_fit_result *r)
{
    size_t j;
    for (j = 0; j < r->ncurves; j++) {
        const lf_model_type *t = r->curves[j].model != NULL
                                 ? lf_model_type_find(r->curves[j].model) : NULL;
        if (r->curves[j].probe.base == LF_BASE_BONDED
            && (t == NULL || t->scope != LF_SCOPE_HALFSPACE))
            return 1;
    }
    return 0;
}

static void
assume(lf_assumption *out, size_t max, size_t *n, const char *name, double value,
       const char *unit, size_t first, size_t last, const char *source)
{
    if (*n >= max)
        return;
    out[*n].name = name;
    out[*n].value = value;
    out[*n].unit = unit;
    out[*n].first = first;
    out[*n].last = last;
    snprintf(out[*n].source, sizeof out[*n].source, "%s", source);
    (*n)++;
}

/* Curve j's radius came from its file's header. */
static int
R_from_header(const lf_fit_input *in, size_t j)
{
    return in->origin != NULL && in->origin[j].R != NULL
           && strcmp(in->origin[j].R, "file header") == 0;
}

/* Runs of curves whose value of one kind (held z0 or F0, R from a file
 * header of one reader) is the same, each one assumption; every curve in
 * one run held by an option (or R): one assumption for every curve
 * (first = last = 0). */
static void
assume_runs(const lf_fit_request *req, const lf_fit_input *in, int kind, lf_assumption *out,
            size_t max, size_t *n)
{
    static const char *const name[3] = { "z0", "F0", "R" };
    static const char *const unit[3] = { "m", "N", "m" };
    const double held[2] = { req->input.z0, req->input.F0 };
    size_t j = 0, nc = in->n;

    while (j < nc) {
        double v;
        const char *src, *fmt = NULL;
        char buf[96];
        size_t k;
        if (kind == 2) {
            if (!R_from_header(in, j)) {
                j++;
                continue;
            }
            v = in->curves[j].probe.R;
            fmt = in->format != NULL ? in->format[j] : NULL;
        } else {
            v = kind == 0 ? in->curves[j].z0 : in->curves[j].F0;
            if (isnan(v)) {
                j++;
                continue;
            }
        }
        for (k = j + 1; k < nc; k++) {
            double u = kind == 2 ? (R_from_header(in, k)
                                    && (fmt == NULL || (in->format[k] != NULL
                                                        && strcmp(in->format[k], fmt) == 0))
                                    ? in->curves[k].probe.R : NAN)
                       : kind == 0 ? in->curves[k].z0 : in->curves[k].F0;
            if (!(u == v))
                break;
        }
        if (kind == 2) {
            snprintf(buf, sizeof buf, "the file header%s%s%s", k - j > 1 ? "s" : "",
                     fmt != NULL ? ", " : "", fmt != NULL ? fmt : "");
            if (fmt != NULL)
                snprintf(buf + strlen(buf), sizeof buf - strlen(buf), " export%s",
                         k - j > 1 ? "s" : "");
            src = buf;
        } else {
            src = !isnan(held[kind]) ? (kind == 0 ? "--fix-z0" : "--fix-F0") : "the plan";
        }
        if (j == 0 && k == nc && (kind == 2 || !isnan(held[kind])))
            assume(out, max, n, name[kind], v, unit[kind], 0, 0, src);
        else
            assume(out, max, n, name[kind], v, unit[kind], j + 1, k, src);
        j = k;
    }
}

size_t
lf_fit_assumptions(const lf_fit_request *req, const lf_fit_input *in, const lf_fit_result *r,
                   lf_assumption *out, size_t max)
{
    const lf_fit_settings *s = &req->fit;
    size_t n = 0;
    int k;

    if (s->w.mode == LF_PARAM_FIXED)
        assume(out, max, &n, "w", s->w.value, "J/m^2", 0, 0, "held as given");
    if (s->Estar.mode == LF_PARAM_FIXED)
        assume(out, max, &n, "E*", s->Estar.value, "Pa", 0, 0, "held as given");
    if (s->nu.mode == LF_PARAM_FIXED || !isnan(in->nu)) {
        /* an option wins over the plan's column (lf_fit_input_apply_nu) */
        int opt = s->nu.mode == LF_PARAM_FIXED;
        char src[96];
        snprintf(src, sizeof src, "%s%s",
                 !opt ? "the plan's nu column" : req->nu_option ? req->nu_option : "held as given",
                 uses_nu(r) ? "" : "; no curve here depends on nu");
        assume(out, max, &n, "nu", opt ? s->nu.value : in->nu, "", 0, 0, src);
    }
    for (k = 0; k < 3; k++)
        assume_runs(req, in, k, out, max, &n);
    return n;
}

const char *
lf_assumption_text(char *buf, size_t n, const lf_assumption *a, size_t ncurves)
{
    char v[48], who[48];

    if (a->unit[0] != '\0')
        lf_human(v, sizeof v, a->value, a->unit);
    else
        snprintf(v, sizeof v, "%.4g", a->value);
    if (a->first == 0)
        snprintf(who, sizeof who, "%s", ncurves > 1 ? ", every curve" : "");
    else if (a->first == a->last)
        snprintf(who, sizeof who, ", curve %zu", a->first);
    else
        snprintf(who, sizeof who, ", curves %zu-%zu", a->first, a->last);
    if (strcmp(a->name, "w") == 0 || strcmp(a->name, "E*") == 0 || strcmp(a->name, "nu") == 0)
        who[0] = '\0';
    snprintf(buf, n, "%s = %s%s (%s)", a->name, v, who, a->source);
    return buf;
}
