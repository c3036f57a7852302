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
    s.each = 0;
    s.group = NULL;
    return s;
}

/* 0: every bias from its own decomposition, as bias_fast's check (tests). */
int lf_fit_choose_fast = 1;

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
    double *rows;           /* max n x (FIT_MMAX + FIT_QMAX): a curve's rows */
    double *g, *step, *work;    /* np */
    double *D;              /* np: the columns' norms where S was summed */
    fit_decomp dec;         /* of the Jacobian at the origin */
    /* every parameter determined at the origin: the biases from the
     * material's Schur complement (bias_fast) */
    int fast;
    double S[FIT_MMAX * FIT_MMAX];  /* sum of the curves' shares (and the prior's) */
    double *sj, *tj;        /* per curve: its share of S, of the reduced J^T d */
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
    free(c->rows);
    free(c->g);
    free(c->sj);
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
    c->rows = calloc(nmax * (FIT_MMAX + FIT_QMAX), sizeof *c->rows);
    c->g = calloc(4 * f->np, sizeof *c->g);
    c->sj = calloc(nc * (FIT_MMAX * FIT_MMAX + FIT_MMAX), sizeof *c->sj);
    c->thin = calloc(nc, sizeof *c->thin);
    c->half_b = calloc(nc, sizeof *c->half_b);
    c->cur = calloc(nc, sizeof *c->cur);
    c->ab_lo = calloc(nc, sizeof *c->ab_lo);
    c->ab_hi = calloc(nc, sizeof *c->ab_hi);
    if (!c->rung || !c->fixed || !c->k || !c->P_exact || !c->exact_ok || !c->ev || !c->rows
        || !c->g || !c->sj || !c->thin || !c->half_b || !c->cur || !c->ab_lo || !c->ab_hi)
        return LF_ENOMEM;
    c->step = c->g + f->np;
    c->work = c->step + f->np;
    c->D = c->work + f->np;
    c->tj = c->sj + nc * FIT_MMAX * FIT_MMAX;
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
    lf_fit_model_changed(f, j);
    return LF_OK;
}

/* The shared decomposition at the origin (decomp.c; in block form beyond
 * FIT_DENSE_P parameters, decomp_block.c). */
static int
decompose(chooser *c)
{
    lf_fit *f = c->f;
    gsl_vector *x = f->ws.x2;

    gsl_vector_set_all(x, 1.0);
    lf_fit_decomp_free(&c->dec);
    if (f->np > FIT_DENSE_P)
        return lf_fit_decomp_block_run(&c->dec, f, x->data, 0, f->set.rcond);
    if (lf_fit_decomp_alloc(&c->dec, f->nres, f->np) != LF_OK)
        return LF_ENOMEM;
    return lf_fit_decomp_run(&c->dec, f, x->data, f->set.rcond);
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

/* What curve j's rows say at the origin, its columns scaled by D, with its
 * own model (model NULL: the evaluations
 * of the fit) or another: the rows' Gram in blocks (H, m x m; C, q x m; B,
 * q x q) and the rows times d = (P_exact - P_model) / sigma (gm, gj). */
typedef struct {
    size_t m, q;
    double H[FIT_MMAX * FIT_MMAX], C[FIT_QMAX * FIT_MMAX], B[FIT_QMAX * FIT_QMAX];
    double gm[FIT_MMAX], gj[FIT_QMAX];
} curve_parts;

static int
parts_of(chooser *c, size_t j, lf_model *model, const double *D, curve_parts *pt)
{
    lf_fit *f = c->f;
    const fit_curve *fc = &f->c[j];
    const size_t at = f->ws.lm.A.at[j];
    double inv[FIT_MMAX + FIT_QMAX];
    size_t mc, i, k, l, kc;

    memset(pt, 0, sizeof *pt);
    if (lf_fit_curve_rows(f, f->ws.x2->data, j, model, c->ev, 0, c->rows, &mc) != GSL_SUCCESS)
        return LF_ENUMERIC;
    pt->m = mc;
    pt->q = f->ws.lm.A.q[j];
    kc = pt->m + pt->q;
    for (k = 0; k < kc; k++) {
        const double dk = D[k < pt->m ? k : at + k - pt->m];
        inv[k] = dk > 0 ? 1.0 / dk : 0.0;
    }
    for (i = 0; i < fc->data.n; i++) {
        const double P = model != NULL ? c->ev[i].P : f->ws.ev[fc->row + i].P;
        const double d = (c->P_exact[fc->row + i] - P) / fc->sigma;
        double v[FIT_MMAX + FIT_QMAX];
        for (k = 0; k < kc; k++)
            v[k] = c->rows[i * kc + k] * inv[k];
        for (k = 0; k < kc; k++) {
            if (k < pt->m)
                pt->gm[k] += v[k] * d;
            else
                pt->gj[k - pt->m] += v[k] * d;
            for (l = 0; l <= k; l++) {
                const double a = v[k] * v[l];
                if (k < pt->m)
                    pt->H[k * FIT_MMAX + l] += a;
                else if (l < pt->m)
                    pt->C[(k - pt->m) * FIT_MMAX + l] += a;
                else
                    pt->B[(k - pt->m) * FIT_QMAX + l - pt->m] += a;
            }
        }
    }
    return LF_OK;
}

/* A curve's share of the material's Schur complement, H - C^T B^-1 C
 * (into sh, stride FIT_MMAX), and of the reduced J^T d, gm - C^T B^-1 gj
 * (into t); 0 when its own block is not positive definite. */
static int
share_of(const curve_parts *pt, double *sh, double *t)
{
    const size_t m = pt->m, q = pt->q;
    double L[FIT_QMAX * FIT_QMAX], W[FIT_QMAX * FIT_MMAX], y[FIT_QMAX];
    size_t r, k, l;

    for (r = 0; r < m; r++) {
        t[r] = pt->gm[r];
        for (k = 0; k <= r; k++)
            sh[r * FIT_MMAX + k] = sh[k * FIT_MMAX + r] = pt->H[r * FIT_MMAX + k];
    }
    if (q == 0)
        return 1;
    if (!lf_small_chol(pt->B, FIT_QMAX, q, 0.0, NULL, L))
        return 0;
    for (k = 0; k < m; k++) {            /* W = B^-1 C, column by column */
        for (r = 0; r < q; r++)
            y[r] = pt->C[r * FIT_MMAX + k];
        lf_small_chol_solve(L, FIT_QMAX, q, y);
        for (r = 0; r < q; r++)
            W[r * FIT_MMAX + k] = y[r];
    }
    for (r = 0; r < q; r++)
        y[r] = pt->gj[r];
    lf_small_chol_solve(L, FIT_QMAX, q, y);
    for (k = 0; k < m; k++) {
        for (r = 0; r < q; r++)
            t[k] -= pt->C[r * FIT_MMAX + k] * y[r];
        for (l = 0; l < m; l++) {
            double v = 0.0;
            for (r = 0; r < q; r++)
                v += pt->C[r * FIT_MMAX + k] * W[r * FIT_MMAX + l];
            sh[k * FIT_MMAX + l] -= v;
        }
    }
    return 1;
}

/* The Schur complement of the current models at the origin, summed from
 * every curve's share, when the decomposition determines every parameter:
 * then a curve's bias with any model costs its own rows (bias_fast). */
static void
prepare_fast(chooser *c)
{
    lf_fit *f = c->f;
    const size_t mm = FIT_MMAX * FIT_MMAX;
    size_t j, r, k;

    c->fast = 0;
    if (c->dec.rank != f->np || !lf_fit_choose_fast)
        return;
    for (k = 0; k < f->np; k++)
        c->D[k] = lf_fit_decomp_norm(&c->dec, k);
    memset(c->S, 0, sizeof c->S);
    for (j = 0; j < f->ncurves; j++) {
        curve_parts pt;
        if (parts_of(c, j, NULL, c->D, &pt) != LF_OK
            || !share_of(&pt, c->sj + j * mm, c->tj + j * FIT_MMAX))
            return;
        for (r = 0; r < pt.m; r++)
            for (k = 0; k < pt.m; k++)
                c->S[r * FIT_MMAX + k] += c->sj[j * mm + r * FIT_MMAX + k];
    }
    if (f->nu_prior) {      /* the prior's row, in nu's column */
        const size_t inu = (size_t) f->imat[FIT_NU];
        const double v = lf_fit_prior_entry(f, f->ws.x2->data, 1) / c->D[inu];
        c->S[inu * FIT_MMAX + inu] += v * v;
    }
    c->fast = 1;
}

/* Curve j's bias with model (NULL: its own) from the Schur complement with
 * its share replaced, S' = S - s_j + s'_j: the material's Gauss-Newton step
 * S'^-1 t'_j over its standard errors sqrt(diag S'^-1) (bias and standard
 * error of the fit that would be made, as decomp.c's; the ratio does not
 * depend on the columns' scales).  0 when S' is not well conditioned
 * (then the whole decomposition decides). */
static int
bias_fast(chooser *c, size_t j, lf_model *model, judge_bias *b)
{
    lf_fit *f = c->f;
    const size_t mm = FIT_MMAX * FIT_MMAX;
    double S[FIT_MMAX * FIT_MMAX], L[FIT_MMAX * FIT_MMAX], sh[FIT_MMAX * FIT_MMAX];
    double t[FIT_MMAX], h[FIT_MMAX];
    size_t r, k, nm = 0;
    int col;

    for (col = 0; col < FIT_NMAT; col++)
        nm += f->imat[col] >= 0;
    memcpy(S, c->S, sizeof S);
    if (model == NULL) {
        memcpy(t, c->tj + j * FIT_MMAX, sizeof t);
    } else {
        curve_parts pt;
        if (parts_of(c, j, model, c->D, &pt) != LF_OK || !share_of(&pt, sh, t))
            return 0;
        for (r = 0; r < nm; r++)
            for (k = 0; k < nm; k++)
                S[r * FIT_MMAX + k] += sh[r * FIT_MMAX + k] - c->sj[j * mm + r * FIT_MMAX + k];
    }
    if (!lf_small_chol(S, FIT_MMAX, nm, 1e-14, NULL, L))
        return 0;
    memcpy(h, t, sizeof h);
    lf_small_chol_solve(L, FIT_MMAX, nm, h);
    for (col = 0; col < FIT_NMAT; col++) {
        const int i = f->imat[col];
        double e[FIT_MMAX] = { 0 }, se;
        b->r[col] = 0.0;
        if (i < 0)
            continue;
        e[i] = 1.0;
        lf_small_chol_solve(L, FIT_MMAX, nm, e);
        se = sqrt(e[i]);
        b->r[col] = se > 0 ? h[i] / se : 0.0;
    }
    b->ok = 1;
    return 1;
}

/* Bias over se of curve j from the decomposition at hand (that of the
 * models being judged): the step pinv(J D^-1) d from D^-1 J_j^T d, curve
 * j's rows being the only ones d touches. */
static int
bias_decomposed(chooser *c, size_t j, judge_bias *b)
{
    lf_fit *f = c->f;
    const size_t at = f->ws.lm.A.at[j];
    curve_parts pt;
    size_t k;

    for (k = 0; k < f->np; k++)
        c->work[k] = lf_fit_decomp_norm(&c->dec, k);
    if (parts_of(c, j, NULL, c->work, &pt) != LF_OK)
        return LF_ENUMERIC;
    memset(c->g, 0, f->np * sizeof *c->g);
    for (k = 0; k < pt.m; k++)
        c->g[k] = pt.gm[k];
    for (k = 0; k < pt.q; k++)
        c->g[at + k] = pt.gj[k];
    lf_fit_decomp_pinv(&c->dec, c->g, c->step, c->work);
    lf_judge_bias(&c->dec, f->imat, c->step, b->r);
    b->ok = 1;
    return LF_OK;
}

/* Bias of curve j when it uses model `rung` instead of exact, the other
 * curves keeping theirs.  The Jacobian is that of the model being judged
 * (the fit that would be made): where every parameter is determined, curve
 * j's share of the material's Schur complement is swapped (bias_fast);
 * else its model is swapped in for a decomposition of its own. */
static int
curve_bias(chooser *c, size_t j, int rung, judge_bias *b)
{
    lf_fit *f = c->f;
    fit_curve *fc = &f->c[j];
    lf_model *saved = fc->model, *m = NULL;
    int swapped = rung != c->rung[j], status = LF_OK;

    memset(b, 0, sizeof *b);
    if (!c->exact_ok[j])
        return LF_OK;           /* ok = 0: not assessed */
    if (rung == FIT_RUNG_EXACT) {
        b->ok = 1;
        return LF_OK;
    }
    if (swapped && (m = instance(c, j, rung)) == NULL)
        return LF_OK;
    if (c->fast && bias_fast(c, j, m, b))
        return LF_OK;
    memset(b, 0, sizeof *b);
    if (swapped) {
        fc->model = m;
        lf_fit_invalidate(f);
        c->base_ok = 0;
    }
    if (!c->base_ok || swapped)
        status = decompose(c);  /* evaluates the models at the origin into f->ev */
    if (status == LF_OK) {
        status = bias_decomposed(c, j, b);
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
    const size_t mm = FIT_MMAX * FIT_MMAX;

    c->base_ok = 0;
    if (c->fast) {
        /* the curve's share of S with its new model */
        lf_model *m = instance(c, j, rung);
        double sh[FIT_MMAX * FIT_MMAX], t[FIT_MMAX];
        curve_parts pt;
        size_t r, k;
        if (m != NULL && parts_of(c, j, m, c->D, &pt) == LF_OK && share_of(&pt, sh, t)) {
            for (r = 0; r < pt.m; r++)
                for (k = 0; k < pt.m; k++)
                    c->S[r * FIT_MMAX + k] += sh[r * FIT_MMAX + k] - c->sj[j * mm + r * FIT_MMAX + k];
            memcpy(c->sj + j * mm, sh, sizeof sh);
            memcpy(c->tj + j * FIT_MMAX, t, sizeof t);
        } else {
            c->fast = 0;
        }
    }
    return set_model(c->f, j, lf_fit_rung_type(rung), c->err);
}

/* a/b in contact at the origin (f->ws.ev evaluated there) into c. */
static void
ab_range(chooser *c, size_t j)
{
    const fit_curve *fc = &c->f->c[j];
    size_t i;

    c->ab_lo[j] = HUGE_VAL;
    c->ab_hi[j] = 0.0;
    for (i = 0; i < fc->data.n; i++) {
        double a = c->f->ws.ev[fc->row + i].a;
        if (a > 0) {
            c->ab_lo[j] = lf_fmin(c->ab_lo[j], a / fc->data.probe.b);
            c->ab_hi[j] = lf_fmax(c->ab_hi[j], a / fc->data.probe.b);
        }
    }
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
    c->fast = 0;
    status = decompose(c);
    if (status != LF_OK)
        return lf_fail(err, status, "model choice: the Jacobian at the solution cannot be decomposed");
    c->base_ok = 1;
    /* a/b ranges and the exact model's forces at the current indentations */
    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *fc = &f->c[j];
        lf_model *ex;
        ab_range(c, j);
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
     * not the current model; where everything is determined, from the
     * material's Schur complement, curve by curve */
    prepare_fast(c);
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

/* --model auto once per probe and layer (lf_choose_settings.group).
 *
 * Some curves of a batch's group of one probe and layer (src/batch.c says
 * which) choose by their own rule, and what their first assessment found
 * is recorded: the thin-layer (and half-space) model's largest bias over se
 * at the thin fit, the thin fit's w and E*, the curve's signal
 * sqrt(n) Fs / sigma (n points, largest |force| Fs, noise sd sigma) and
 * the a/b where its contact starts.  A bias over se is a Gauss-Newton step
 * over se: the model difference over sigma projected on the Jacobian's
 * columns, so that at one shape of the difference it grows as the signal
 * (n points alike: as sqrt(n); sigma halved: twice).  Its shape follows the
 * material and where the contact starts against b: the thin-layer model is
 * least accurate where the contact is small against b, and a curve whose
 * contact starts at a larger a/b is biased more (the 1 024-curve map's
 * thin bias rises from 0.09-0.24 se where a/b starts below 2 to 0.46-1.26
 * se where it starts above 6).  So another curve of the group is predicted
 * from the records of material within GROUP_MATERIAL of its own (w and E*
 * each), from their bias per unit of signal times its own signal: biased
 * at least the smallest of those whose contact starts at an a/b no larger
 * than its own, at most the largest of those whose contact starts at an
 * a/b no smaller.  It is decided by its group where that prediction clears
 * the rule's own tolerance by GROUP_MARGIN (exact: biased at least
 * GROUP_MARGIN tol by the thin-layer model and, where the half-space model
 * is a candidate, by that too; thin: at most tol / GROUP_MARGIN); any other
 * curve, or one without a record to go by, decides by its own rule.  A
 * curve decided so is fitted as its own rule would (the thin fit first,
 * the exact model's refit from it, the final assessment) without the first
 * assessment.  On the 1 024-curve map the realised bias of every curve the
 * group decided was at least 0.81 of its prediction; without the material
 * window, records at E* 0.5 GPa decided curves at 2-2.5 GPa exact that
 * their own rule keeps thin (the 16 384-curve map). */
#define GROUP_MARGIN 2.0
#define GROUP_MATERIAL 0.2231435513142098   /* ln 1.25 */

static int
same_probe(const lf_probe *a, const lf_probe *b)
{
    const double x[5] = { a->k, a->R, a->b, a->angle, a->B };
    const double y[5] = { b->k, b->R, b->b, b->angle, b->B };
    size_t i;

    for (i = 0; i < 5; i++)
        if (!(x[i] == y[i] || (isnan(x[i]) && isnan(y[i]))))
            return 0;
    return a->base == b->base && a->tip == b->tip;
}

/* The signal of curve 0: sqrt(n) Fs / sigma. */
static double
signal_of(const lf_fit *f)
{
    const fit_curve *fc = &f->c[0];
    return sqrt((double) fc->data.n) * fc->Fs / fc->sigma;
}

/* What the first assessment of one of the group's first curves found. */
static void
group_record(const chooser *c, lf_group_ref *q)
{
    q->probe = c->f->c[0].data.probe;
    q->ok = c->thin[0].ok;
    q->thin = lf_judge_bias_max(c->thin[0].r, NULL);
    q->half_ok = c->half_b[0].ok;
    q->half = lf_judge_bias_max(c->half_b[0].r, NULL);
    q->snr = signal_of(c->f);
    q->ab_lo = c->ab_lo[0];
    q->w = c->f->mat.w;
    q->Estar = c->f->mat.Estar;
}

/* The model the group decides for the curve at the origin (its thin fit),
 * with the bias predicted (*pred); -1 where it decides nothing. */
static int
group_decide(chooser *c, const lf_model_group *g, double *pred)
{
    lf_fit *f = c->f;
    const fit_curve *fc = &f->c[0];
    const double tol = c->cs->tol;
    const int half = c->cs->halfspace
                     && fc->data.probe.k > lf_fit_rung_type(FIT_RUNG_HALFSPACE)->k_above;
    double snr, lo = HUGE_VAL, hi = 0.0, hlo = HUGE_VAL;
    size_t r, nlo = 0, nhi = 0, nh = 0;

    /* the fit's state as the first assessment leaves it: the models
     * evaluated at the origin */
    gsl_vector_set_all(f->ws.x2, 1.0);
    if (lf_fit_eval_at(f, f->ws.x2->data) != LF_OK || !(fc->sigma > 0))
        return -1;
    ab_range(c, 0);
    snr = signal_of(f);
    if (!(c->ab_hi[0] > 0) || !isfinite(snr))
        return -1;
    for (r = 0; r < g->nref; r++) {
        const lf_group_ref *q = &g->ref[r];
        if (!q->ok || !(q->snr > 0) || !same_probe(&q->probe, &fc->data.probe)
            || !(fabs(log(q->w / f->mat.w)) <= GROUP_MATERIAL)
            || !(fabs(log(q->Estar / f->mat.Estar)) <= GROUP_MATERIAL))
            continue;
        if (q->ab_lo <= c->ab_lo[0]) {
            lo = lf_fmin(lo, q->thin / q->snr);
            nlo++;
            if (q->half_ok) {
                hlo = lf_fmin(hlo, q->half / q->snr);
                nh++;
            }
        }
        if (q->ab_lo >= c->ab_lo[0]) {
            hi = lf_fmax(hi, q->thin / q->snr);
            nhi++;
        }
    }
    if (nlo > 0 && lo * snr >= GROUP_MARGIN * tol
        && (!half || (nh > 0 && hlo * snr >= GROUP_MARGIN * tol))) {
        *pred = lo * snr;
        return FIT_RUNG_EXACT;
    }
    if (nhi > 0 && hi * snr <= tol / GROUP_MARGIN) {
        *pred = hi * snr;
        return FIT_RUNG_THIN;
    }
    return -1;
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
    int status, fit_status, changed, all_thin = 1, first_all_thin = 1, m, by_group = -1;
    double total = 0.0, predicted = NAN;
    lf_model_group *group;

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
    group = ncurves == 1 && !ch.fixed[0] ? cs->group : NULL;
    for (;;) {
        lf_fit_result next;
        origin_at(f, cur.curves ? &cur : &first);
        if (rounds == 1 && group != NULL && group->record == NULL
            && (by_group = group_decide(&ch, group, &predicted)) >= 0) {
            changed = by_group != FIT_RUNG_THIN;
            ch.rung[0] = by_group;
            if (changed && (status = set_model(f, 0, lf_fit_rung_type(by_group), err)) != LF_OK)
                goto done;
        } else {
            status = assess(&ch, rounds <= cs->max_rounds, &changed, &total, err);
            if (status != LF_OK)
                goto done;
            if (rounds == 1 && group != NULL && group->record != NULL)
                group_record(&ch, group->record);
        }
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
        if (by_group >= 0) {
            size_t len = strlen(cr->model_reason);
            cr->model_by_group = 1;
            if (by_group == FIT_RUNG_THIN)
                snprintf(cr->model_reason, sizeof cr->model_reason, "the thin-layer model, "
                         "decided with its group of one probe and layer: its bias predicted "
                         "at most %.2g se over a/b %.3g-%.3g (tolerance %.2g se)", predicted,
                         ch.ab_lo[j], ch.ab_hi[j], cs->tol);
            else
                snprintf(cr->model_reason + len, sizeof cr->model_reason - len, "; decided "
                         "with its group of one probe and layer (predicted %.2g se)", predicted);
        }
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
