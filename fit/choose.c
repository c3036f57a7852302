/* choose.c: the cheapest forward model that is accurate enough, per curve
 * (the rule and the algorithm are in layerfit.h above
 * lf_fit_choose_driver), and the all-thin comparison fit.
 *
 * Why a bias rule and not a residual rule: fitted to curves of the exact
 * layer model, the thin-layer closed form leaves residuals below 1% of the
 * force while w moves by 10-70% (the exact model of Lebedev & Ufliand 1958,
 * noise-free curves at b/a 0.1-4 fitted with the thin form).  What
 * matters is the shift of the parameters against their standard errors.
 * To first order the estimate made with model m from data that follow the
 * exact model moves by
 *     bias = (J^T J)^+ J^T (P_exact - P_m) / sigma,
 * one Gauss-Newton step from the solution, with J the weighted Jacobian.
 * Everything is computed in the column-scaled SVD J D^-1 = U S V^T that
 * uncertainty.c uses, over the same determined directions (rcond), so the
 * ratio bias / se needs no inverse:
 *     bias_p / se_p = (sum_l V_pl (U_l . d) / S_l) / sqrt(sum_l V_pl^2 / S_l^2).
 * Biases of several curves add (the map is linear in d). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_linalg.h>

#include "fit.h"

lf_choose_settings
lf_choose_settings_default(void)
{
    lf_choose_settings s;
    s.tol = 0.2;
    s.max_rounds = 3;
    s.halfspace = 1;
    s.thin_comparison = 1;
    return s;
}

/* The state of a model choice. */
typedef struct {
    lf_fit *f;
    const lf_choose_settings *cs;
    int *rung;              /* current model of each curve */
    int *fixed;             /* 1: the caller named the model */
    double *k;              /* each curve's probe exponent */
    lf_model **inst[FIT_NRUNG]; /* per model and curve, made when first needed */
    int base_ok;            /* the decomposition is that of the current models */
    double *P_exact;        /* ndata: the exact model's forces */
    int *exact_ok;          /* per curve: P_exact could be evaluated */
    lf_eval *ev;            /* max n: scratch evaluations */
    double *d;              /* nres: the difference vector */
    double *coef;           /* np */
    fit_decomp dec;         /* of the Jacobian at the origin */
    judge_bias *thin, *half_b, *cur;  /* per curve */
    lf_error *err;          /* where a model move's failure goes */
    double *ab_lo, *ab_hi;      /* a/b range in contact */
} chooser;

static void
chooser_free(chooser *c)
{
    size_t j;
    int r;

    for (r = 0; r < FIT_NRUNG; r++) {
        if (c->f != NULL && c->inst[r] != NULL)
            for (j = 0; j < c->f->ncurves; j++)
                lf_model_free(c->inst[r][j]);
        free(c->inst[r]);
    }
    free(c->rung);
    free(c->fixed);
    free(c->k);
    free(c->P_exact);
    free(c->exact_ok);
    free(c->ev);
    free(c->d);
    free(c->coef);
    free(c->thin);
    free(c->half_b);
    free(c->cur);
    free(c->ab_lo);
    free(c->ab_hi);
    lf_fit_decomp_free(&c->dec);
}

static int
chooser_alloc(chooser *c, lf_fit *f, const lf_choose_settings *cs)
{
    size_t j, nmax = 0, nc = f->ncurves;
    int r;

    memset(c, 0, sizeof *c);
    for (r = 0; r < FIT_NRUNG; r++)
        if ((c->inst[r] = calloc(nc, sizeof *c->inst[r])) == NULL)
            return LF_ENOMEM;
    c->f = f;
    c->cs = cs;
    for (j = 0; j < nc; j++)
        nmax = f->c[j].data.n > nmax ? f->c[j].data.n : nmax;
    c->rung = calloc(nc, sizeof *c->rung);
    c->fixed = calloc(nc, sizeof *c->fixed);
    c->k = calloc(nc, sizeof *c->k);
    c->P_exact = calloc(f->ndata, sizeof *c->P_exact);
    c->exact_ok = calloc(nc, sizeof *c->exact_ok);
    c->ev = calloc(nmax, sizeof *c->ev);
    c->d = calloc(f->nres, sizeof *c->d);
    c->coef = calloc(f->np, sizeof *c->coef);
    c->thin = calloc(nc, sizeof *c->thin);
    c->half_b = calloc(nc, sizeof *c->half_b);
    c->cur = calloc(nc, sizeof *c->cur);
    c->ab_lo = calloc(nc, sizeof *c->ab_lo);
    c->ab_hi = calloc(nc, sizeof *c->ab_hi);
    if (!c->rung || !c->fixed || !c->k || !c->P_exact || !c->exact_ok || !c->ev || !c->d || !c->coef
        || !c->thin || !c->half_b || !c->cur || !c->ab_lo || !c->ab_hi
        || lf_fit_decomp_alloc(&c->dec, f->nres, f->np) != LF_OK)
        return LF_ENOMEM;
    return LF_OK;
}

/* Put the origin of the fit at the solution in res (warm start, and the
 * point where the Jacobian is taken with x = 1). */
static void
origin_at(lf_fit *f, const lf_fit_result *res)
{
    size_t j;

    if (f->imat[FIT_W] >= 0)
        f->mat.w = res->value[f->imat[FIT_W]];
    if (f->imat[FIT_E] >= 0)
        f->mat.Estar = res->value[f->imat[FIT_E]];
    if (f->imat[FIT_NU] >= 0)
        f->mat.nu = res->value[f->imat[FIT_NU]];
    for (j = 0; j < f->ncurves; j++) {
        fit_curve *c = &f->c[j];
        if (c->iz0 >= 0)
            c->z0 = res->value[c->iz0];
        if (c->iF0 >= 0)
            c->F0 = res->value[c->iF0];
        if (c->islope >= 0)
            c->slope = res->value[c->islope];
    }
    lf_fit_set_origin(f);
}

static int
set_model(lf_fit *f, size_t j, const lf_model_type *t, lf_error *err)
{
    lf_model *m = lf_model_alloc(t, &f->c[j].data.probe, err);

    if (m == NULL)
        return err ? err->status : LF_EINVAL;
    lf_model_free(f->c[j].model);
    f->c[j].model = m;
    f->c[j].data.model = t;
    lf_fit_invalidate(f);
    return LF_OK;
}

/* The shared decomposition (decomp.c) at the origin. */
static int
decompose(chooser *c)
{
    gsl_vector *x = c->f->ws.x2;

    gsl_vector_set_all(x, 1.0);
    return lf_fit_decomp_run(&c->dec, c->f, x->data, c->f->set.rcond);
}

/* Bias over se from c->d (judge.c). */
static void
project(chooser *c, judge_bias *b)
{
    lf_fit_decomp_project(&c->dec, c->d, c->coef);
    lf_judge_bias(&c->dec, c->f->imat, c->coef, b->r);
    b->ok = 1;
}

/* The model instance of curve j for a rung, made when first needed. */
static lf_model *
instance(chooser *c, size_t j, int rung)
{
    lf_model **slot = &c->inst[rung][j];

    if (*slot == NULL) {
        *slot = lf_model_alloc(lf_fit_rung_type(rung), &c->f->c[j].data.probe, NULL);
        /* its tables for the current nu resolved now, not in eval */
        if (*slot != NULL && lf_model_prepare(*slot, c->f->mat.nu, c->f->mat.nu, NULL) != LF_OK) {
            lf_model_free(*slot);
            *slot = NULL;
        }
    }
    return *slot;
}

/* Bias of curve j when it uses model `rung` instead of exact, the other
 * curves keeping theirs.  The Jacobian is that of the model being judged
 * (the fit that would be made), so curve j's model is swapped in for the
 * decomposition when it is not the current one. */
static int
curve_bias(chooser *c, size_t j, int rung, judge_bias *b)
{
    lf_fit *f = c->f;
    fit_curve *fc = &f->c[j];
    lf_model *saved = fc->model, *m;
    int swapped = rung != c->rung[j], status = LF_OK;
    size_t i;

    memset(b, 0, sizeof *b);
    if (!c->exact_ok[j])
        return LF_OK;           /* ok = 0: not assessed */
    if (rung == FIT_RUNG_EXACT) {
        b->ok = 1;
        return LF_OK;
    }
    if (swapped) {
        if ((m = instance(c, j, rung)) == NULL)
            return LF_OK;
        fc->model = m;
        lf_fit_invalidate(f);
        c->base_ok = 0;
    }
    if (!c->base_ok || swapped)
        status = decompose(c);  /* evaluates the models at the origin into f->ev */
    if (status == LF_OK) {
        memset(c->d, 0, f->nres * sizeof *c->d);
        for (i = 0; i < fc->data.n; i++)
            c->d[fc->row + i] = (c->P_exact[fc->row + i] - f->ws.ev[fc->row + i].P) / fc->sigma;
        project(c, b);
        c->base_ok = !swapped;
    }
    if (swapped) {
        fc->model = saved;
        lf_fit_invalidate(f);
    }
    return status;
}

/* The model choice's callbacks (judge_models): a curve's bias with a
 * model, and its move to a model (the fit's own model objects). */
static int
models_bias(void *ctx, size_t j, int rung, judge_bias *b)
{
    return curve_bias(ctx, j, rung, b);
}

static int
models_move(void *ctx, size_t j, int rung)
{
    chooser *c = ctx;
    c->base_ok = 0;
    return set_model(c->f, j, lf_fit_rung_type(rung), c->err);
}

/* Assess every curve at the origin (the last solution): biases of thin,
 * half-space (where needed) and the current model against exact; then,
 * when allowed, move curves up until the summed bias is below tol.
 * *changed tells whether a model moved. */
static int
assess(chooser *c, int allow_change, int *changed, double *total_max, lf_error *err)
{
    lf_fit *f = c->f;
    size_t j, i;
    int status;

    *changed = 0;
    c->base_ok = 0;
    status = decompose(c);
    if (status != LF_OK)
        return lf_fail(err, status, "model choice: the Jacobian at the solution cannot be decomposed");
    c->base_ok = 1;
    /* a/b ranges and the exact model's forces at the current indentations */
    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *fc = &f->c[j];
        double b = fc->data.probe.b;
        lf_model *ex;
        c->ab_lo[j] = HUGE_VAL;
        c->ab_hi[j] = 0.0;
        for (i = 0; i < fc->data.n; i++) {
            double a = f->ws.ev[fc->row + i].a;
            if (a > 0) {
                c->ab_lo[j] = lf_fmin(c->ab_lo[j], a / b);
                c->ab_hi[j] = lf_fmax(c->ab_hi[j], a / b);
            }
        }
        c->exact_ok[j] = 1;
        /* a curve wholly in the thin-layer regime (a/b beyond the exact
         * model's tables) is compared without building any table */
        if (c->rung[j] != FIT_RUNG_EXACT && c->ab_lo[j] < HUGE_VAL
            && lf_exact_far_eval(&fc->data.probe, &f->mat, fc->data.branch, fc->data.n,
                                 f->ws.delta + fc->row, c->P_exact + fc->row, NULL) == LF_OK)
            continue;
        ex = c->rung[j] == FIT_RUNG_EXACT ? NULL : instance(c, j, FIT_RUNG_EXACT);
        if (c->rung[j] == FIT_RUNG_EXACT) {
            for (i = 0; i < fc->data.n; i++)
                c->P_exact[fc->row + i] = f->ws.ev[fc->row + i].P;
        } else if (ex == NULL || lf_model_eval(ex, &f->mat, fc->data.branch, fc->data.n,
                                                f->ws.delta + fc->row, c->ev, NULL) != LF_OK) {
            c->exact_ok[j] = 0;   /* e.g. nu above the exact model's range */
        } else {
            for (i = 0; i < fc->data.n; i++)
                c->P_exact[fc->row + i] = c->ev[i].P;
        }
    }
    /* the current models first (one decomposition), then thin where it is
     * not the current model */
    for (j = 0; j < f->ncurves && status == LF_OK; j++) {
        status = curve_bias(c, j, c->rung[j], &c->cur[j]);
        if (c->rung[j] == FIT_RUNG_THIN)
            c->thin[j] = c->cur[j];
        if (c->rung[j] == FIT_RUNG_HALFSPACE)
            c->half_b[j] = c->cur[j];
        else
            memset(&c->half_b[j], 0, sizeof c->half_b[j]);
    }
    for (j = 0; j < f->ncurves && status == LF_OK; j++)
        if (c->rung[j] != FIT_RUNG_THIN)
            status = curve_bias(c, j, FIT_RUNG_THIN, &c->thin[j]);
    if (status == LF_OK) {
        judge_models jm;
        memset(&jm, 0, sizeof jm);
        jm.n = f->ncurves;
        jm.rung = c->rung;
        jm.fixed = c->fixed;
        jm.k = c->k;
        jm.cur = c->cur;
        jm.half = c->half_b;
        jm.tol = c->cs->tol;
        jm.halfspace = c->cs->halfspace;
        jm.allow_change = allow_change;
        jm.ctx = c;
        jm.bias = models_bias;
        jm.move = models_move;
        c->err = err;
        status = lf_judge_models(&jm, total_max, changed);
    }
    if (status != LF_OK)
        lf_fail(err, status, "model choice: the bias of a cheaper model cannot be computed");
    return status;
}

/* res->thin from an all-thin fit. */
static void
fill_thin(lf_fit_result *res, const lf_fit_result *thin)
{
    lf_fit_thin_comparison *t = &res->thin;

    t->done = 1;
    t->converged = thin->converged;
    t->w = thin->w;
    t->Estar = thin->Estar;
    t->nu = thin->nu;
    t->chi2 = thin->chi2;
    t->w_rel = (thin->w.value - res->w.value) / res->w.value;
    t->Estar_rel = (thin->Estar.value - res->Estar.value) / res->Estar.value;
    t->nu_diff = thin->nu.value - res->nu.value;
    t->w_in_se = (thin->w.value - res->w.value) / res->w.se;
}

int
lf_fit_compare_thin(const lf_fit_settings *settings, size_t ncurves,
                    const lf_fit_curve *curves, lf_fit_result *res, lf_error *err)
{
    lf_fit_settings s = *settings;
    lf_fit_curve *cv = malloc(ncurves * sizeof *cv);
    lf_fit_result thin;
    size_t j;
    int status;

    if (cv == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory");
    for (j = 0; j < ncurves; j++) {
        cv[j] = curves[j];
        cv[j].model = NULL;
    }
    s.model = lf_fit_rung_type(FIT_RUNG_THIN);
    status = lf_fit_driver(&s, ncurves, cv, &thin, err);
    free(cv);
    if (status != LF_OK && status != LF_ENOCONV)
        return status;
    fill_thin(res, &thin);
    lf_fit_result_free(&thin);
    return LF_OK;
}

/* A bonded curve at a held nu of FIT_NU_INCOMPRESSIBLE or more. */
static int
incompressible(const lf_fit_settings *s, const lf_fit_curve *c)
{
    return c->probe.base == LF_BASE_BONDED && s->nu.mode != LF_PARAM_FREE
           && s->nu.value >= FIT_NU_INCOMPRESSIBLE;
}

int
lf_fit_choose_driver(const lf_fit_settings *settings, const lf_choose_settings *cs,
                     size_t ncurves, const lf_fit_curve *curves, lf_fit_result *res,
                     lf_error *err)
{
    lf_fit_curve *cv = NULL;
    lf_fit *f = NULL;
    chooser ch;
    lf_fit_result cur, first;
    size_t j, rounds = 1;
    int status, fit_status, changed, all_thin = 1, first_all_thin = 1, m;
    double total = 0.0;

    memset(res, 0, sizeof *res);
    memset(&cur, 0, sizeof cur);
    memset(&first, 0, sizeof first);
    memset(&ch, 0, sizeof ch);
    if (!(cs->tol > 0) || !isfinite(cs->tol))
        return lf_fail(err, LF_EINVAL, "model choice: tolerance must be > 0 (got %g)", cs->tol);
    cv = malloc((ncurves ? ncurves : 1) * sizeof *cv);
    if (cv == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory");
    for (j = 0; j < ncurves; j++) {
        cv[j] = curves[j];
        /* a nearly incompressible bonded layer: the exact model alone
         * holds there (problem.c) */
        if (cv[j].model == NULL && incompressible(settings, &curves[j]))
            cv[j].model = lf_fit_rung_type(FIT_RUNG_EXACT);
        if (cv[j].model == NULL)
            cv[j].model = lf_fit_rung_type(FIT_RUNG_THIN);
        else if (cv[j].model != lf_fit_rung_type(FIT_RUNG_THIN))
            first_all_thin = 0;
    }
    f = lf_fit_alloc(settings, ncurves, cv, err);
    if (f == NULL) {
        free(cv);
        return err ? err->status : LF_EINVAL;
    }
    if (chooser_alloc(&ch, f, cs) != LF_OK) {
        status = lf_fail(err, LF_ENOMEM, "out of memory choosing models");
        goto done;
    }
    for (j = 0; j < ncurves; j++) {
        ch.fixed[j] = curves[j].model != NULL || incompressible(settings, &curves[j]);
        ch.k[j] = curves[j].probe.k;
        ch.rung[j] = lf_fit_rung_of(cv[j].model);
    }
    fit_status = lf_fit_run(f, &first, err);
    if (fit_status != LF_OK && fit_status != LF_ENOCONV) {
        status = fit_status;
        goto done;
    }
    for (;;) {
        lf_fit_result next;
        origin_at(f, cur.curves ? &cur : &first);
        status = assess(&ch, rounds <= cs->max_rounds, &changed, &total, err);
        if (status != LF_OK)
            goto done;
        if (!changed)
            break;
        fit_status = lf_fit_solve(f, NULL, &next, err);
        if (fit_status != LF_OK && fit_status != LF_ENOCONV) {
            status = fit_status;
            goto done;
        }
        lf_fit_result_free(&cur);
        cur = next;
        rounds++;
    }
    if (cur.curves == NULL) {   /* the first fit stands */
        cur = first;
        memset(&first, 0, sizeof first);
    }
    for (j = 0; j < ncurves; j++) {
        lf_fit_curve_result *cr = &cur.curves[j];
        cr->model = lf_fit_rung_type(ch.rung[j])->name;
        lf_judge_model_reason(cr->model_reason, sizeof cr->model_reason, ch.rung[j], ch.fixed[j],
                              &ch.thin[j], &ch.half_b[j], ch.ab_lo[j], ch.ab_hi[j], cs->tol);
        if (curves[j].model == NULL && incompressible(settings, &curves[j]))
            snprintf(cr->model_reason, sizeof cr->model_reason, "a bonded layer at nu >= %g is "
                     "nearly incompressible, where the thin-layer model does not hold",
                     FIT_NU_INCOMPRESSIBLE);
        cr->thin_bias = ch.thin[j].ok ? lf_judge_bias_max(ch.thin[j].r, NULL) : NAN;
        for (m = 0; m < FIT_NMAT; m++)
            cr->thin_bias_se[m] = ch.thin[j].ok ? ch.thin[j].r[m] : NAN;
        if (ch.rung[j] != FIT_RUNG_THIN)
            all_thin = 0;
    }
    cur.model_rounds = rounds;
    if (total >= cs->tol)
        lf_warn(&cur.warnings, "model choice: after %zu fits the cheaper models still bias the "
                "material by %.2g se (tolerance %.2g se); consider --model exact",
                rounds, total, cs->tol);
    *res = cur;
    memset(&cur, 0, sizeof cur);
    status = fit_status;
    if (!all_thin && cs->thin_comparison) {
        int st;
        if (first_all_thin && first.curves != NULL)
            fill_thin(res, &first);
        else if ((st = lf_fit_compare_thin(settings, ncurves, curves, res, NULL)) != LF_OK)
            lf_warn(&res->warnings, "the all-thin comparison fit failed (%s)", lf_strerror(st));
    }
done:
    lf_fit_result_free(&cur);
    lf_fit_result_free(&first);
    chooser_free(&ch);
    lf_fit_free(f);
    free(cv);
    return status;
}
