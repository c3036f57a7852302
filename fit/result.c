/* result.c: the lifetime of a fit's result -- its arrays sized from the
 * fit's layout (lf_fit_result_alloc), its release (lf_fit_result_free) --
 * and the two edits every later verdict makes to it: an estimate dropped
 * as not determined, and the pull-off following w. */
#include <math.h>
#include <stdio.h>
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
    if (p <= FIT_DENSE_P) {     /* else the covariance in block form */
        r->cov = calloc(p * p, sizeof *r->cov);
        r->corr = calloc(p * p, sizeof *r->corr);
        if (!r->cov || !r->corr)
            return LF_ENOMEM;
    }
    r->singular = calloc(p, sizeof *r->singular);
    r->ncurves = f->ncurves;
    r->curves = calloc(f->ncurves, sizeof *r->curves);
    if (!r->names || !r->value || !r->singular || !r->curves)
        return LF_ENOMEM;
    for (j = 0; j < f->ncurves; j++) {
        size_t n = f->c[j].data.n;
        r->curves[j].fitted = calloc(n, sizeof *r->curves[j].fitted);
        r->curves[j].contact_radius = calloc(n, sizeof *r->curves[j].contact_radius);
        if (!r->curves[j].fitted || !r->curves[j].contact_radius)
            return LF_ENOMEM;
        lf_curve_estimate_none(&r->curves[j].alone, &f->c[j].data.probe);
    }
    lf_heterogeneity_of(0, NULL, &r->heterogeneity, NULL);
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
    if (r->covariance != NULL) {
        lf_fit_bdec_free(&r->covariance->b);
        free(r->covariance->det);
        free(r->covariance);
    }
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

void
lf_fit_keep_choice(lf_fit_result *nr, const lf_fit_result *res)
{
    size_t j;

    nr->model_rounds = res->model_rounds;
    nr->thin = res->thin;
    nr->iterations += res->iterations;
    nr->evaluations += res->evaluations;
    for (j = 0; j < res->ncurves && j < nr->ncurves; j++) {
        memcpy(nr->curves[j].model_reason, res->curves[j].model_reason,
               sizeof nr->curves[j].model_reason);
        nr->curves[j].thin_bias = res->curves[j].thin_bias;
        nr->curves[j].model_by_group = res->curves[j].model_by_group;
        memcpy(nr->curves[j].thin_bias_se, res->curves[j].thin_bias_se,
               sizeof nr->curves[j].thin_bias_se);
        nr->curves[j].alone = res->curves[j].alone;
    }
    nr->heterogeneity = res->heterogeneity;
}

void
lf_fit_bound_words(lf_fit_result *r)
{
    lf_warnings *w = &r->identifiability;
    size_t i, k = 0;

    for (i = 0; i < w->n; i++) {
        char *m = w->msg[i];
        if (strncmp(m, FIT_W_BOUND_PREFIX, strlen(FIT_W_BOUND_PREFIX)) == 0) {
            if (!r->w.upper_bound_only || !isfinite(r->w.ci95[1])) {
                free(m);        /* no longer an upper bound only */
                continue;
            }
            {
                int len = snprintf(NULL, 0, FIT_W_BOUND_WORDS, r->w.ci95[1]);
                char *t = len >= 0 ? malloc((size_t) len + 1) : NULL;
                if (t != NULL) {
                    snprintf(t, (size_t) len + 1, FIT_W_BOUND_WORDS, r->w.ci95[1]);
                    free(m);
                    m = t;
                }
            }
        }
        w->msg[k++] = m;
    }
    w->n = k;
}
