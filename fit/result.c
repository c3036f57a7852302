/* result.c: the lifetime of a fit's result -- its arrays sized from the
 * fit's layout (lf_fit_result_alloc), its release (lf_fit_result_free) --
 * and the two edits every later verdict makes to it: an estimate dropped
 * as not determined, and the pull-off following w. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit.h"

int
lf_fit_result_alloc(const lf_fit *f, lf_fit_result *r)
{
    size_t j, p = f->np;

    r->npar = p;
    r->names = calloc(p, sizeof *r->names);
    r->value = calloc(p, sizeof *r->value);
    r->cov = calloc(p * p, sizeof *r->cov);
    r->corr = calloc(p * p, sizeof *r->corr);
    r->singular = calloc(p, sizeof *r->singular);
    r->ncurves = f->ncurves;
    r->curves = calloc(f->ncurves, sizeof *r->curves);
    if (!r->names || !r->value || !r->cov || !r->corr || !r->singular || !r->curves)
        return LF_ENOMEM;
    for (j = 0; j < f->ncurves; j++) {
        size_t n = f->c[j].data.n;
        r->curves[j].fitted = calloc(n, sizeof *r->curves[j].fitted);
        r->curves[j].contact_radius = calloc(n, sizeof *r->curves[j].contact_radius);
        if (!r->curves[j].fitted || !r->curves[j].contact_radius)
            return LF_ENOMEM;
    }
    return LF_OK;
}

void
lf_fit_result_free(lf_fit_result *r)
{
    size_t j;

    if (r == NULL)
        return;
    free(r->names);
    free(r->value);
    free(r->cov);
    free(r->corr);
    free(r->singular);
    if (r->curves != NULL)
        for (j = 0; j < r->ncurves; j++) {
            free(r->curves[j].fitted);
            free(r->curves[j].contact_radius);
            lf_warnings_free(&r->curves[j].warnings);
        }
    free(r->curves);
    lf_warnings_free(&r->identifiability);
    lf_warnings_free(&r->warnings);
    memset(r, 0, sizeof *r);
}

void
lf_fit_estimate_drop(lf_fit_estimate *e, const char *why)
{
    e->why = why;
    e->value = e->se = e->ci95[0] = e->ci95[1] = NAN;
    e->determined = 0;
    e->upper_bound_only = 0;
}

void
lf_fit_pulloff_follows(lf_fit_result *r)
{
    size_t j;

    for (j = 0; j < r->ncurves; j++)
        r->curves[j].pulloff_determined = r->w.determined;
}
