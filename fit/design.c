/* design.c: what a planned set of indentation curves would measure, before
 * the lab records them (the contract is in layerfit.h above
 * lf_design_candidate).
 *
 * Each candidate is prepared once: its indentations, its noise sd and, for
 * each forward model a fit could use (thin, half-space, exact), the QR
 * factor R_m of its weighted gradient rows
 *     g_i = (dP/dln w, dP/dln E*, dP/dnu, -dP/ddelta L, Fs) / sigma
 * (z0 in units of the depth span L, F0 in units of the largest force Fs)
 * and Q_m^T d_m with d_m = (P_exact - P_m) / sigma.  Because J_j = Q_j R_j,
 * the Jacobian of any set has the same singular values and right singular
 * vectors as the stack of the R_j (5 rows per curve, columns picked for
 * the parameters that set frees), and J^T d = sum R_j^T (Q_j^T d_j).  So a
 * set is evaluated from a matrix of 5 rows per curve, without the models.
 *
 * The stack is decomposed as the fitter decomposes its Jacobian (decomp.c:
 * columns scaled to unit norm, A = U S V^T) and judged by the fitter's own
 * judgement (judge.c: what is determined and why, the model choice, each
 * curve's model bias); the covariance is the pseudo-inverse over the
 * determined directions, the Cramer-Rao bound of that fit (no
 * sqrt(chi2/dof): the truth is known).  All of it at the truth, where a
 * fit of noise-free data of the chosen model would land. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_vector.h>

#include "fit.h"

#define NL 5                    /* local columns: ln w, ln E*, nu, z0, F0 */
enum { C_W = 0, C_E, C_NU, C_Z0, C_F0 };
#define NO_BASELINE_END 0.9     /* a curve without baseline ends at 0.9 of the
                                   detachment indentation (the two-probe
                                   Cramer-Rao scene of tests/test_crb.c) */

/* ------------------------------------------------------------ settings */

lf_design_settings
lf_design_settings_default(void)
{
    lf_design_settings s;

    memset(&s, 0, sizeof s);
    s.truth.w = NAN;
    s.truth.Estar = NAN;
    s.truth.nu = 0.3;
    s.fix_nu = 0;
    s.noise_rel = 0.01;
    s.noise_abs = NAN;
    s.delta_max = 50e-9;
    s.points = 200;
    s.baseline_fraction = 0.25;
    s.model = NULL;
    s.choose = lf_choose_settings_default();
    s.rcond = 1e-7;
    return s;
}

/* ------------------------------------------------------- preparation */

/* One model's view of one candidate. */
typedef struct {
    int ok;                 /* 0: the model cannot describe this curve */
    double R[NL * NL];      /* upper triangular, row-major */
    double qd[NL];          /* Q^T d */
    size_t n_past;          /* points out of contact */
} model_part;

typedef struct {
    lf_design_candidate c;  /* defaults resolved */
    double delta_lo, delta_hi, delta_detach, sigma, fmax;
    double ba_min, ba_max, ba_pulloff;
    model_part m[FIT_NRUNG];
} prepared;

struct lf_design {
    lf_design_settings s;
    size_t n;
    prepared *p;
};

/* R and Q^T d of one model from its evaluations ev[0..n-1]. */
static int
factor_part(const prepared *pp, const lf_eval *ev, const double *P_exact, size_t n,
            gsl_matrix *G, gsl_vector *tau, gsl_vector *d, model_part *mp)
{
    double L = pp->delta_hi - pp->delta_lo, s = pp->sigma;
    size_t i, r, c;

    mp->n_past = 0;
    for (i = 0; i < n; i++) {
        double g[NL];
        g[C_W] = ev[i].dP_dlogw;
        g[C_E] = ev[i].dP_dlogE;
        g[C_NU] = ev[i].dP_dnu;
        g[C_Z0] = -ev[i].dP_ddelta * L;
        g[C_F0] = pp->fmax;
        for (c = 0; c < NL; c++)
            gsl_matrix_set(G, i, c, g[c] / s);
        gsl_vector_set(d, i, (P_exact[i] - ev[i].P) / s);
        mp->n_past += ev[i].a == 0.0;
    }
    if (gsl_linalg_QR_decomp(G, tau) != GSL_SUCCESS
        || gsl_linalg_QR_QTvec(G, tau, d) != GSL_SUCCESS)
        return LF_ENUMERIC;
    for (r = 0; r < NL; r++) {
        for (c = 0; c < NL; c++)
            mp->R[r * NL + c] = c >= r ? gsl_matrix_get(G, r, c) : 0.0;
        mp->qd[r] = gsl_vector_get(d, r);
    }
    for (r = 0; r < NL * NL; r++)
        if (!isfinite(mp->R[r]))
            return LF_ENUMERIC;
    mp->ok = 1;
    return LF_OK;
}

static int
prepare(const lf_design_settings *s, const lf_design_candidate *in, prepared *pp,
        lf_error *err)
{
    lf_design_candidate *c = &pp->c;
    lf_model *m = NULL;
    lf_eval *ev = NULL, *evx = NULL;
    double *delta = NULL, *P = NULL;
    gsl_matrix *G = NULL;
    gsl_vector *tau = NULL, *d = NULL;
    lf_pulloff po;
    size_t i, n;
    int st, rung;
    double amin = HUGE_VAL, amax = 0.0;

    *c = *in;
    if (isnan(c->delta_max))
        c->delta_max = s->delta_max;
    if (c->points == 0)
        c->points = s->points;
    n = c->points;
    if (n < NL)
        return lf_fail(err, LF_EINVAL, "%s: at least %d points per curve", c->name, NL);
    if (lf_probe_check(&c->probe, err) != LF_OK)
        return LF_EINVAL;
    if (!(c->delta_max > 0) || !isfinite(c->delta_max))
        return lf_fail(err, LF_EINVAL, "%s: the deepest indentation must be > 0", c->name);
    m = lf_model_alloc(lf_fit_rung_type(FIT_RUNG_EXACT), &c->probe, err);
    if (m == NULL)
        return err ? err->status : LF_EINVAL;
    /* a probe the model cannot evaluate would give numbers of no meaning */
    if ((st = lf_model_check_region(m, &s->truth, err)) != LF_OK) {
        if (err != NULL) {
            char why[sizeof err->msg];
            snprintf(why, sizeof why, "%s", err->msg);
            lf_fail(err, st, "%s: %s", c->name, why);
        }
        goto done;
    }
    st = lf_model_pulloff(m, &s->truth, &po, err);
    if (st != LF_OK)
        goto done;
    pp->delta_detach = c->branch == LF_BRANCH_LOAD ? 0.0 : po.delta_detach;
    pp->ba_pulloff = po.a_po > 0 ? c->probe.b / po.a_po : NAN;
    pp->delta_hi = c->delta_max;
    if (!isnan(c->delta_min))
        pp->delta_lo = c->delta_min;
    else if (c->baseline == 0.0)
        pp->delta_lo = NO_BASELINE_END * pp->delta_detach;
    else
        pp->delta_lo = pp->delta_detach
                       - (isnan(c->baseline) ? s->baseline_fraction * (c->delta_max - pp->delta_detach)
                                             : c->baseline);
    if (!(pp->delta_lo < pp->delta_hi)) {
        st = lf_fail(err, LF_EINVAL, "%s: the shallowest indentation (%g m) must lie above "
                     "the deepest (%g m)", c->name, pp->delta_lo, pp->delta_hi);
        goto done;
    }
    delta = malloc(n * sizeof *delta);
    P = malloc(n * sizeof *P);
    ev = malloc(n * sizeof *ev);
    evx = malloc(n * sizeof *evx);
    G = gsl_matrix_alloc(n, NL);
    tau = gsl_vector_alloc(NL);
    d = gsl_vector_alloc(n);
    if (!delta || !P || !ev || !evx || !G || !tau || !d) {
        st = lf_fail(err, LF_ENOMEM, "out of memory preparing a design");
        goto done;
    }
    /* the indentations as lf_simulate writes them */
    for (i = 0; i < n; i++) {
        double t = (double) i / (double) (n - 1);
        delta[i] = c->branch == LF_BRANCH_UNLOAD ? pp->delta_hi - t * (pp->delta_hi - pp->delta_lo)
                                                 : pp->delta_lo + t * (pp->delta_hi - pp->delta_lo);
    }
    st = lf_model_eval(m, &s->truth, c->branch, n, delta, evx, err);
    if (st != LF_OK)
        goto done;
    pp->fmax = 0.0;
    for (i = 0; i < n; i++) {
        P[i] = evx[i].P;
        pp->fmax = lf_fmax(pp->fmax, fabs(P[i]));
        if (evx[i].a > 0) {
            amin = lf_fmin(amin, evx[i].a);
            amax = lf_fmax(amax, evx[i].a);
        }
    }
    if (!(pp->fmax > 0) || !isfinite(pp->fmax)) {
        st = lf_fail(err, LF_EDATA, "%s: the curve has no force (no contact in its range)", c->name);
        goto done;
    }
    pp->ba_min = amax > 0 ? c->probe.b / amax : NAN;
    pp->ba_max = amax > 0 ? c->probe.b / amin : NAN;
    pp->sigma = isfinite(c->noise_abs) ? c->noise_abs
                : isfinite(c->noise_rel) ? c->noise_rel * pp->fmax
                : isfinite(s->noise_abs) ? s->noise_abs : s->noise_rel * pp->fmax;
    if (!(pp->sigma > 0) || !isfinite(pp->sigma)) {
        st = lf_fail(err, LF_EINVAL, "%s: the noise must be > 0", c->name);
        goto done;
    }
    for (rung = 0; rung < FIT_NRUNG; rung++) {
        lf_model *mr = m;
        const lf_eval *e = evx;
        memset(&pp->m[rung], 0, sizeof pp->m[rung]);
        if (rung != FIT_RUNG_EXACT) {
            if (!(c->probe.k > lf_fit_rung_type(rung)->k_above))
                continue;
            if ((mr = lf_model_alloc(lf_fit_rung_type(rung), &c->probe, NULL)) == NULL)
                continue;
            st = lf_model_eval(mr, &s->truth, c->branch, n, delta, ev, NULL);
            lf_model_free(mr);
            if (st != LF_OK) {
                st = LF_OK;     /* this model cannot be used here */
                continue;
            }
            e = ev;
        }
        st = factor_part(pp, e, P, n, G, tau, d, &pp->m[rung]);
        if (st != LF_OK) {
            if (rung == FIT_RUNG_EXACT) {
                st = lf_fail(err, st, "%s: the exact model's derivatives are not finite", c->name);
                goto done;
            }
            memset(&pp->m[rung], 0, sizeof pp->m[rung]);
            st = LF_OK;
        }
    }
done:
    lf_model_free(m);
    free(delta);
    free(P);
    free(ev);
    free(evx);
    gsl_matrix_free(G);
    gsl_vector_free(tau);
    gsl_vector_free(d);
    return st;
}

lf_design *
lf_design_alloc(const lf_design_settings *s, size_t n, const lf_design_candidate *cand,
                lf_error *err)
{
    lf_design *d;
    size_t i;

    if (n == 0) {
        lf_fail(err, LF_EINVAL, "no candidate curves");
        return NULL;
    }
    if (!(s->truth.w > 0) || !isfinite(s->truth.w)) {
        lf_fail(err, LF_EINVAL, "the true w must be > 0 (e.g. 10mJ/m2): its error is relative");
        return NULL;
    }
    if (lf_material_check(&s->truth, LF_BASE_BONDED, err) != LF_OK)
        return NULL;
    if (!(s->rcond > 0 && s->rcond < 1) || !(s->choose.tol > 0)
        || !(s->baseline_fraction > 0) || !isfinite(s->baseline_fraction)) {
        lf_fail(err, LF_EINVAL, "design settings out of range (rcond in (0, 1), tolerance and "
                "baseline fraction > 0)");
        return NULL;
    }
    d = calloc(1, sizeof *d);
    if (d == NULL || (d->p = calloc(n, sizeof *d->p)) == NULL) {
        free(d);
        lf_fail(err, LF_ENOMEM, "out of memory");
        return NULL;
    }
    d->s = *s;
    d->n = n;
    for (i = 0; i < n; i++)
        if (prepare(s, &cand[i], &d->p[i], err) != LF_OK) {
            lf_design_free(d);
            return NULL;
        }
    return d;
}

void
lf_design_free(lf_design *d)
{
    if (d == NULL)
        return;
    free(d->p);
    free(d);
}

/* ------------------------------------------------------- one set */

/* The decomposition of one set with given models. */
typedef struct {
    const lf_design *d;
    size_t ns;              /* curves */
    const size_t *idx;      /* their candidate indices */
    int *rung;              /* their models */
    int nu_free;
    size_t p;               /* columns */
    int col[FIT_NMAT];      /* ln w, ln E*, nu columns (nu -1 when held) */
    int *cz0, *cF0;         /* per curve, -1 when held */
    fit_decomp dec;         /* of the stack of the curves' R blocks */
    double *g;              /* p: D^-1 R^T Q^T d of one curve */
    double *coef;           /* p: its projection on the determined directions */
} setwork;

static void
setwork_free(setwork *w)
{
    free(w->rung);
    free(w->cz0);
    free(w->cF0);
    free(w->g);
    free(w->coef);
    lf_fit_decomp_free(&w->dec);
}

/* The set's layout: nu free as the fitter frees it (fit/problem.c: bonded
 * curves with frictionless ones, unless held), or forced free (nu_free >
 * 0: the judgement of E* apart from nu). */
static int
setwork_alloc(setwork *w, const lf_design *d, size_t ns, const size_t *idx, int force_nu)
{
    size_t j, p;
    int any_b = 0, any_f = 0;

    memset(w, 0, sizeof *w);
    w->d = d;
    w->ns = ns;
    w->idx = idx;
    for (j = 0; j < ns; j++) {
        if (d->p[idx[j]].c.probe.base == LF_BASE_BONDED)
            any_b = 1;
        else
            any_f = 1;
    }
    w->nu_free = force_nu || (!d->s.fix_nu && any_b && any_f);
    p = 0;
    w->col[FIT_W] = (int) p++;
    w->col[FIT_E] = (int) p++;
    w->col[FIT_NU] = w->nu_free ? (int) p++ : -1;
    w->rung = calloc(ns, sizeof *w->rung);
    w->cz0 = calloc(ns, sizeof *w->cz0);
    w->cF0 = calloc(ns, sizeof *w->cF0);
    if (!w->rung || !w->cz0 || !w->cF0)
        return LF_ENOMEM;
    for (j = 0; j < ns; j++) {
        const lf_design_candidate *c = &d->p[idx[j]].c;
        w->cz0[j] = c->free_z0 ? (int) p++ : -1;
        w->cF0[j] = c->free_F0 ? (int) p++ : -1;
    }
    w->p = p;
    w->g = calloc(p, sizeof *w->g);
    w->coef = calloc(p, sizeof *w->coef);
    if (!w->g || !w->coef || lf_fit_decomp_alloc(&w->dec, NL * ns, p) != LF_OK)
        return LF_ENOMEM;
    return LF_OK;
}

/* Global column of local column c of set curve j, or -1. */
static int
column_of(const setwork *w, size_t j, int c)
{
    switch (c) {
    case C_W: return w->col[FIT_W];
    case C_E: return w->col[FIT_E];
    case C_NU: return w->col[FIT_NU];
    case C_Z0: return w->cz0[j];
    default: return w->cF0[j];
    }
}

/* Stack the curves' R blocks with the current models and decompose them
 * as the fitter decomposes its Jacobian (decomp.c). */
static int
decompose(setwork *w)
{
    gsl_matrix *A = w->dec.QR;
    size_t j, r;
    int c;

    gsl_matrix_set_zero(A);
    for (j = 0; j < w->ns; j++) {
        const model_part *mp = &w->d->p[w->idx[j]].m[w->rung[j]];
        for (c = 0; c < NL; c++) {
            int g = column_of(w, j, c);
            if (g < 0)
                continue;
            for (r = 0; r < NL; r++)
                gsl_matrix_set(A, NL * j + r, (size_t) g, mp->R[r * NL + (size_t) c]);
        }
    }
    return lf_fit_decomp_factor(&w->dec, w->d->s.rcond, 1);
}

/* Covariance of global columns a, b in the parameters' own units (ln w,
 * ln E*, nu, z0/L, F0/Fs): the Cramer-Rao bound. */
static double
covariance(const setwork *w, int a, int b)
{
    return lf_fit_decomp_cov(&w->dec, a, b, 1.0);
}

/* Bias over se of w, E*, nu (judge.c) when set curve j uses model `rung`'s
 * forces in place of the exact ones, with the current decomposition
 * (which must be that of the models being judged): J^T d = R^T Q^T d. */
static void
project_bias(setwork *w, size_t j, int rung, double r[FIT_NMAT])
{
    const fit_decomp *d = &w->dec;
    const model_part *mp = &w->d->p[w->idx[j]].m[rung];
    size_t k, l;
    int c, q;

    for (k = 0; k < w->p; k++)
        w->g[k] = 0.0;
    for (c = 0; c < NL; c++) {        /* D^-1 R^T Q^T d */
        int gc = column_of(w, j, c);
        double s = 0.0;
        if (gc < 0)
            continue;
        for (q = 0; q <= c; q++)
            s += mp->R[q * NL + c] * mp->qd[q];
        if (gsl_vector_get(d->D, (size_t) gc) > 0)
            w->g[gc] = s / gsl_vector_get(d->D, (size_t) gc);
    }
    for (l = 0; l < d->rank; l++) {
        double vg = 0.0, sl = gsl_vector_get(d->S, l);
        for (k = 0; k < w->p; k++)
            vg += gsl_matrix_get(d->V, k, l) * w->g[k];
        w->coef[l] = vg / (sl * sl);
    }
    lf_judge_bias(d, w->col, w->coef, r);
}

/* The bias of set curve j with model `rung`, the others keeping theirs;
 * decomposes with j swapped and restores (b->ok = 0 when that model is not
 * available for the curve). */
static int
curve_bias(setwork *w, size_t j, int rung, judge_bias *b)
{
    int saved = w->rung[j], st;

    memset(b, 0, sizeof *b);
    b->ok = w->d->p[w->idx[j]].m[rung].ok;
    if (!b->ok || rung == FIT_RUNG_EXACT)
        return LF_OK;
    w->rung[j] = rung;
    st = decompose(w);
    if (st == LF_OK)
        project_bias(w, j, rung, b->r);
    w->rung[j] = saved;
    return st;
}

/* The model choice's callbacks (judge_models). */
static int
models_bias(void *ctx, size_t j, int rung, judge_bias *b)
{
    return curve_bias(ctx, j, rung, b);
}

static int
models_move(void *ctx, size_t j, int rung)
{
    setwork *w = ctx;
    w->rung[j] = rung;
    return decompose(w);    /* the models being judged */
}

/* The auto rule of lf_fit_choose_driver (judge.c) at the truth: start
 * thin; each round assesses every curve's bias and moves curves up until
 * the summed bias is within the tolerance; rounds until nothing moves.
 * Fills each curve's model, reason and thin bias.  With settings.model set
 * every curve keeps that model. */
static int
choose_models(setwork *w, lf_design_curve_info *info)
{
    const lf_design_settings *s = &w->d->s;
    judge_bias *cur = calloc(w->ns, sizeof *cur), *thin = calloc(w->ns, sizeof *thin);
    judge_bias *half = calloc(w->ns, sizeof *half);
    int *fixed = calloc(w->ns, sizeof *fixed), st = LF_OK, changed = 1;
    double *k = calloc(w->ns, sizeof *k), total;
    judge_models jm;
    size_t j, round;

    if (!cur || !thin || !half || !fixed || !k) {
        st = LF_ENOMEM;
        goto done;
    }
    for (j = 0; j < w->ns; j++) {
        int r = s->model != NULL ? lf_fit_rung_of(s->model) : FIT_RUNG_THIN;
        if (!w->d->p[w->idx[j]].m[r].ok)
            r = FIT_RUNG_EXACT;
        w->rung[j] = r;
        fixed[j] = s->model != NULL;
        k[j] = w->d->p[w->idx[j]].c.probe.k;
    }
    memset(&jm, 0, sizeof jm);
    jm.n = w->ns;
    jm.rung = w->rung;
    jm.fixed = fixed;
    jm.k = k;
    jm.cur = cur;
    jm.half = half;
    jm.tol = s->choose.tol;
    jm.halfspace = s->choose.halfspace;
    jm.allow_change = s->model == NULL;
    jm.ctx = w;
    jm.bias = models_bias;
    jm.move = models_move;
    for (round = 0; jm.allow_change && changed && round <= s->choose.max_rounds; round++) {
        if ((st = decompose(w)) != LF_OK)
            goto done;
        for (j = 0; j < w->ns; j++) {
            memset(&cur[j], 0, sizeof cur[j]);
            cur[j].ok = 1;
            if (w->rung[j] != FIT_RUNG_EXACT)
                project_bias(w, j, w->rung[j], cur[j].r);
            memset(&half[j], 0, sizeof half[j]);
        }
        if ((st = lf_judge_models(&jm, &total, &changed)) != LF_OK)
            goto done;
    }
    /* the final assessment: each curve's thin and half-space biases */
    for (j = 0; j < w->ns && st == LF_OK; j++) {
        st = curve_bias(w, j, FIT_RUNG_THIN, &thin[j]);
        if (st == LF_OK && w->rung[j] == FIT_RUNG_HALFSPACE)
            st = curve_bias(w, j, FIT_RUNG_HALFSPACE, &half[j]);
        info[j].thin_bias = thin[j].ok ? lf_judge_bias_max(thin[j].r, NULL) : NAN;
    }
    if (st != LF_OK)
        goto done;
    st = decompose(w);
    for (j = 0; j < w->ns && st == LF_OK; j++) {
        const prepared *pp = &w->d->p[w->idx[j]];
        info[j].model = lf_fit_rung_type(w->rung[j]);
        if (w->rung[j] != FIT_RUNG_HALFSPACE)
            memset(&half[j], 0, sizeof half[j]);
        lf_judge_model_reason(info[j].model_reason, sizeof info[j].model_reason, w->rung[j],
                              fixed[j], &thin[j], &half[j], 1.0 / pp->ba_max, 1.0 / pp->ba_min,
                              s->choose.tol);
    }
done:
    free(cur);
    free(thin);
    free(half);
    free(fixed);
    free(k);
    return st;
}

void
lf_design_result_free(lf_design_result *r)
{
    if (r == NULL)
        return;
    free(r->curves);
    lf_warnings_free(&r->identifiability);
    lf_warnings_free(&r->notes);
    memset(r, 0, sizeof *r);
}

static void
estimate_set(lf_design_estimate *e, int free_, int determined, double se, double rel,
             const char *why)
{
    e->free = free_;
    e->determined = free_ && determined;
    e->se = e->determined ? se : NAN;
    e->rel = e->determined ? rel : NAN;
    e->upper_bound_only = 0;
    e->why = e->determined ? NULL : why;
}

/* The judgement's measures at the truth (judge.c asks for them only where
 * it needs them). */
typedef struct {
    setwork *w;
    int *rung;              /* the set's models */
} design_ctx;

/* k = 2: whether the data bound w from above, predicted from the
 * linearised model: chi2 with ln w held FIT_K2_W_HIGH higher rises by
 * (FIT_K2_W_HIGH / sd(ln w))^2 in units of the noise, against the 95%
 * threshold 1.96^2. */
static int
design_w_open_above(void *ctx)
{
    const design_ctx *c = ctx;
    double v = covariance(c->w, c->w->col[FIT_W], c->w->col[FIT_W]);
    return !(FIT_K2_W_HIGH * FIT_K2_W_HIGH / v >= FIT_Z95 * FIT_Z95);
}

/* E* with nu's column (nu held) added: 1 when still determined, with the
 * regression of ln E* on nu. */
static int
design_E_with_nu(void *ctx, double *dlnE_dnu)
{
    const design_ctx *c = ctx;
    setwork x;
    int ok = 0;

    if (setwork_alloc(&x, c->w->d, c->w->ns, c->w->idx, 1) == LF_OK) {
        const int e = x.col[FIT_E], nu = x.col[FIT_NU];
        memcpy(x.rung, c->rung, c->w->ns * sizeof *x.rung);
        if (decompose(&x) == LF_OK && lf_judge_col_determined(&x.dec, e)
            && covariance(&x, nu, nu) > 0) {
            *dlnE_dnu = covariance(&x, e, nu) / covariance(&x, nu, nu);
            ok = 1;
        }
    }
    setwork_free(&x);
    return ok;
}

/* Notes a design adds to the judgement's words. */
static void
notes(const setwork *w, lf_design_result *r)
{
    const double limit = lf_fit_settings_default().max_b_over_a;
    size_t j;

    for (j = 0; j < w->ns; j++) {
        const prepared *pp = &w->d->p[w->idx[j]];
        const lf_design_curve_info *ci = &r->curves[j];
        if (ci->model->scope == LF_SCOPE_THIN)
            lf_judge_thin_strain(&r->notes, pp->c.name, ci->ba_max,
                                 "at the shallowest point in contact", limit);
        if (pp->c.probe.k > 2.0 + 1e-9 && ci->n_past > 0)
            lf_warn(&r->notes, "%s: k > 2 recorded through detachment, where the force's slope "
                    "diverges: the predicted errors (w above all) depend on where the points fall "
                    "next to detachment and may be optimistic (Monte Carlo fits of such curves "
                    "scattered up to 25%% more than predicted)", pp->c.name);
    }
}

static int
eval_set(lf_design *d, size_t ns, const size_t *idx, lf_design_result *r)
{
    const lf_material *t = &d->s.truth;
    const double Z = lf_thin_Z(LF_BASE_BONDED, t->nu);
    const double dl = lf_thin_dlogZ_dnu(LF_BASE_BONDED, t->nu);
    setwork w;
    judge_curve *jc = NULL;
    judge_in in;
    judge_out o;
    design_ctx ctx;
    size_t j;
    int st, c, a, cols[FIT_NMAT];
    double cov[FIT_NMAT][FIT_NMAT], M_var;

    memset(r, 0, sizeof *r);
    st = setwork_alloc(&w, d, ns, idx, 0);
    if (st == LF_OK && ((r->curves = calloc(ns, sizeof *r->curves)) == NULL
                        || (jc = calloc(ns, sizeof *jc)) == NULL))
        st = LF_ENOMEM;
    if (st != LF_OK)
        goto done;
    r->ncurves = ns;
    if ((st = choose_models(&w, r->curves)) != LF_OK)
        goto done;
    for (j = 0; j < ns; j++) {
        const prepared *pp = &d->p[idx[j]];
        lf_design_curve_info *ci = &r->curves[j];
        ci->index = idx[j];
        ci->delta_lo = pp->delta_lo;
        ci->delta_hi = pp->delta_hi;
        ci->delta_detach = pp->delta_detach;
        ci->n = pp->c.points;
        ci->n_past = pp->m[w.rung[j]].n_past;
        ci->sigma = pp->sigma;
        ci->fmax = pp->fmax;
        ci->ba_min = pp->ba_min;
        ci->ba_max = pp->ba_max;
        ci->ba_pulloff = pp->ba_pulloff;
        ci->free_z0 = pp->c.free_z0;
        ci->free_F0 = pp->c.free_F0;
        snprintf(jc[j].label, sizeof jc[j].label, "%s", pp->c.name);
        jc[j].k = pp->c.probe.k;
        jc[j].base = pp->c.probe.base;
        jc[j].branch = pp->c.branch;
        jc[j].model = ci->model;
        jc[j].n_out = ci->n_past;
        jc[j].col_z0 = w.cz0[j];
        jc[j].col_F0 = w.cF0[j];
        jc[j].col_slope = -1;
    }
    r->npar = w.p;
    for (c = 0; c < FIT_NMAT; c++) {
        cols[c] = w.col[c];
        for (a = 0; a < FIT_NMAT; a++)
            cov[c][a] = w.col[c] >= 0 && w.col[a] >= 0 ? covariance(&w, w.col[c], w.col[a]) : 0.0;
    }
    /* the relative variance of M = Z(nu) E* */
    M_var = cov[FIT_E][FIT_E] + (cols[FIT_NU] >= 0 ? 2 * dl * cov[FIT_E][FIT_NU]
                                                   + dl * dl * cov[FIT_NU][FIT_NU] : 0.0);
    /* the judgement at the truth (judge.c), as a fit's at its solution */
    memset(&in, 0, sizeof in);
    in.d = &w.dec;
    memcpy(in.col, w.col, sizeof in.col);
    in.held_by_user[FIT_NU] = d->s.fix_nu;
    in.ran_col = -1;
    in.w = t->w;
    in.w_se = t->w * sqrt(lf_fmax(cov[FIT_W][FIT_W], 0.0));
    in.nu = t->nu;
    in.M = Z * t->Estar;
    in.M_se = in.M * sqrt(lf_fmax(M_var, 0.0));
    in.dM[0] = in.M;            /* dM/dln E* */
    in.dM[1] = in.M * dl;       /* dM/dnu */
    in.ncurves = ns;
    in.c = jc;
    ctx.w = &w;
    ctx.rung = w.rung;
    in.ctx = &ctx;
    in.w_open_above = design_w_open_above;
    in.E_with_nu = design_E_with_nu;
    lf_judge(&in, &o, &r->identifiability);
    estimate_set(&r->w, 1, o.det[FIT_W], t->w * sqrt(cov[FIT_W][FIT_W]), sqrt(cov[FIT_W][FIT_W]),
                 o.why[FIT_W]);
    r->w.upper_bound_only = o.w_upper;
    estimate_set(&r->nu, w.nu_free, o.det[FIT_NU], sqrt(cov[FIT_NU][FIT_NU]),
                 sqrt(cov[FIT_NU][FIT_NU]), o.why[FIT_NU]);
    if (!w.nu_free)
        r->nu.why = d->s.fix_nu ? "held at the given value" : o.why[FIT_NU];
    estimate_set(&r->Estar, 1, o.det[FIT_E], t->Estar * sqrt(cov[FIT_E][FIT_E]),
                 sqrt(cov[FIT_E][FIT_E]), o.why[FIT_E]);
    /* M = Z(nu) E* of the bonded curves */
    estimate_set(&r->M, o.M_free, o.M_det && M_var >= 0, in.M * sqrt(lf_fmax(M_var, 0)),
                 sqrt(lf_fmax(M_var, 0)), NULL);
    r->corr_wE = o.det[FIT_W] && o.det[FIT_E]
                 ? cov[FIT_W][FIT_E] / sqrt(cov[FIT_W][FIT_W] * cov[FIT_E][FIT_E]) : NAN;
    /* the information of the determined material parameters, nuisance
     * profiled: the inverse of their covariance block */
    {
        double blk[9];
        int map[3], m = 0, b;
        for (c = 0; c < FIT_NMAT; c++)
            if (o.det[c] && cols[c] >= 0)
                map[m++] = c;
        r->ndetermined = (size_t) m;
        r->logdet = -HUGE_VAL;
        if (m > 0) {
            gsl_matrix_view B = gsl_matrix_view_array(blk, (size_t) m, (size_t) m);
            double ld = 0.0;
            for (a = 0; a < m; a++)
                for (b = 0; b < m; b++)
                    blk[a * m + b] = cov[map[a]][map[b]];
            if (gsl_linalg_cholesky_decomp1(&B.matrix) == GSL_SUCCESS) {
                for (a = 0; a < m; a++)
                    ld += 2.0 * log(blk[a * m + a]);
                r->logdet = -ld;
            }
        }
    }
    notes(&w, r);
done:
    free(jc);
    setwork_free(&w);
    if (st != LF_OK)
        lf_design_result_free(r);
    return st;
}

int
lf_design_eval(lf_design *d, const int *use, lf_design_result *out, lf_error *err)
{
    size_t *idx = malloc(d->n * sizeof *idx), ns = 0, i;
    int st;

    memset(out, 0, sizeof *out);
    if (idx == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory");
    for (i = 0; i < d->n; i++)
        if (use == NULL || use[i])
            idx[ns++] = i;
    if (ns == 0) {
        free(idx);
        return lf_fail(err, LF_EDATA, "no candidate in the set");
    }
    st = eval_set(d, ns, idx, out);
    free(idx);
    if (st != LF_OK)
        return lf_fail(err, st, "the design cannot be evaluated (%s)", lf_strerror(st));
    return LF_OK;
}

/* ------------------------------------------------------- choosing */

static const char *const target_names[] = { "w", "E", "nu", "all" };

const char *
lf_design_target_name(lf_design_target t)
{
    return (unsigned) t < 4 ? target_names[t] : "?";
}

int
lf_design_target_find(const char *name)
{
    int i;
    for (i = 0; i < 4; i++)
        if (strcmp(name, target_names[i]) == 0)
            return i;
    return -1;
}

lf_design_score
lf_design_score_of(const lf_design_result *r, lf_design_target t)
{
    lf_design_score s;
    const lf_design_estimate *e = t == LF_TARGET_W ? &r->w : t == LF_TARGET_E ? &r->Estar : &r->nu;

    s.target = t;
    s.ndetermined = r->ndetermined;
    s.logdet = r->logdet;
    if (t == LF_TARGET_ALL) {
        s.target_determined = r->ndetermined > 0;
        s.value = r->logdet;
    } else {
        s.target_determined = e->determined;
        s.value = e->determined ? -e->rel : -HUGE_VAL;
    }
    return s;
}

int
lf_design_score_cmp(const lf_design_score *a, const lf_design_score *b)
{
    if (a->target_determined != b->target_determined)
        return a->target_determined ? 1 : -1;
    if ((a->target == LF_TARGET_ALL || !a->target_determined) && a->ndetermined != b->ndetermined)
        return a->ndetermined > b->ndetermined ? 1 : -1;
    if (a->value != b->value)
        return a->value > b->value ? 1 : -1;
    if (a->logdet != b->logdet)
        return a->logdet > b->logdet ? 1 : -1;
    return 0;
}

void
lf_design_choice_free(lf_design_choice *c)
{
    if (c == NULL)
        return;
    free(c->steps);
    free(c->chosen);
    memset(c, 0, sizeof *c);
}

/* Score of the set `use` (n flags). */
static int
score_set(lf_design *d, const int *use, lf_design_target t, lf_design_result *r,
          lf_design_score *s, lf_error *err)
{
    int st = lf_design_eval(d, use, r, err);
    if (st == LF_OK)
        *s = lf_design_score_of(r, t);
    return st;
}

int
lf_design_choose(lf_design *d, size_t nchoose, lf_design_target target,
                 lf_design_choice *out, lf_error *err)
{
    size_t step, i;
    int st = LF_OK;

    memset(out, 0, sizeof *out);
    if (nchoose == 0 || nchoose > d->n)
        return lf_fail(err, LF_EINVAL, "choose between 1 and %zu candidates (got %zu)", d->n,
                       nchoose);
    if ((unsigned) target > LF_TARGET_ALL)
        return lf_fail(err, LF_EINVAL, "unknown target");
    out->steps = calloc(nchoose, sizeof *out->steps);
    out->chosen = calloc(d->n, sizeof *out->chosen);
    if (!out->steps || !out->chosen) {
        lf_design_choice_free(out);
        return lf_fail(err, LF_ENOMEM, "out of memory");
    }
    for (step = 0; step < nchoose; step++) {
        lf_design_step *sp = &out->steps[step];
        lf_design_result best_r;
        int have = 0, have2 = 0;
        memset(&best_r, 0, sizeof best_r);
        sp->runner_up = (size_t) -1;
        for (i = 0; i < d->n; i++) {
            lf_design_result r;
            lf_design_score s;
            if (out->chosen[i])
                continue;
            out->chosen[i] = 1;
            st = score_set(d, out->chosen, target, &r, &s, err);
            out->chosen[i] = 0;
            if (st != LF_OK)
                break;
            if (!have || lf_design_score_cmp(&s, &sp->score) > 0) {
                if (have) {
                    sp->runner_up = sp->added;
                    sp->runner_score = sp->score;
                    have2 = 1;
                }
                lf_design_result_free(&best_r);
                best_r = r;
                sp->added = i;
                sp->score = s;
                have = 1;
            } else {
                if (!have2 || lf_design_score_cmp(&s, &sp->runner_score) > 0) {
                    sp->runner_up = i;
                    sp->runner_score = s;
                    have2 = 1;
                }
                lf_design_result_free(&r);
            }
        }
        if (st != LF_OK) {
            lf_design_result_free(&best_r);
            lf_design_choice_free(out);
            return st;
        }
        out->chosen[sp->added] = 1;
        sp->w = best_r.w;
        sp->Estar = best_r.Estar;
        sp->nu = best_r.nu;
        lf_design_result_free(&best_r);
        out->nsteps = step + 1;
    }
    return LF_OK;
}

int
lf_design_exhaustive(lf_design *d, size_t nchoose, lf_design_target target, size_t max_sets,
                     int *best, lf_design_score *score, lf_error *err)
{
    size_t *comb, i, k = nchoose, n = d->n, nsets = 1;
    int *use, have = 0, st = LF_OK;

    if (nchoose == 0 || nchoose > n)
        return lf_fail(err, LF_EINVAL, "choose between 1 and %zu candidates (got %zu)", n, nchoose);
    for (i = 0; i < k; i++) {       /* C(n, k), capped */
        nsets = nsets * (n - i) / (i + 1);
        if (nsets > max_sets)
            return lf_fail(err, LF_EINVAL, "more than %zu sets of %zu among %zu candidates "
                           "to search", max_sets, k, n);
    }
    comb = malloc(k * sizeof *comb);
    use = calloc(n, sizeof *use);
    if (!comb || !use) {
        free(comb);
        free(use);
        return lf_fail(err, LF_ENOMEM, "out of memory");
    }
    for (i = 0; i < k; i++)
        comb[i] = i;
    for (;;) {
        lf_design_result r;
        lf_design_score s;
        memset(use, 0, n * sizeof *use);
        for (i = 0; i < k; i++)
            use[comb[i]] = 1;
        if ((st = score_set(d, use, target, &r, &s, err)) != LF_OK)
            break;
        lf_design_result_free(&r);
        if (!have || lf_design_score_cmp(&s, score) > 0) {
            *score = s;
            memcpy(best, use, n * sizeof *use);
            have = 1;
        }
        /* next combination in lexicographic order */
        i = k;
        while (i > 0 && comb[i - 1] == n - k + i - 1)
            i--;
        if (i == 0)
            break;
        comb[i - 1]++;
        for (; i < k; i++)
            comb[i] = comb[i - 1] + 1;
    }
    free(comb);
    free(use);
    return st;
}

/* ------------------------------------------------------- sweeping */

static const char *const factor_names[] = { "k", "delta_max", "points", "b", "R", "baseline" };
#define NFACTOR ((int) (sizeof factor_names / sizeof factor_names[0]))

const char *
lf_design_factor_name(lf_design_factor f)
{
    return (int) f >= 0 && (int) f < NFACTOR ? factor_names[f] : "?";
}

int
lf_design_factor_find(const char *name)
{
    int i;
    if (strcmp(name, "depth") == 0)
        return LF_FACTOR_DELTA_MAX;
    for (i = 0; i < NFACTOR; i++)
        if (strcmp(name, factor_names[i]) == 0)
            return i;
    return -1;
}

lf_quantity
lf_design_factor_quantity(lf_design_factor f)
{
    return f == LF_FACTOR_K || f == LF_FACTOR_POINTS ? LF_Q_DIMENSIONLESS : LF_Q_LENGTH;
}

static int
apply_factor(lf_design_candidate *c, lf_design_factor f, double v, lf_error *err)
{
    switch (f) {
    case LF_FACTOR_K: c->probe.k = v; break;
    case LF_FACTOR_DELTA_MAX: c->delta_max = v; break;
    case LF_FACTOR_B: c->probe.b = v; break;
    case LF_FACTOR_R: c->probe.R = v; break;
    case LF_FACTOR_BASELINE:
        if (!(v >= 0) || !isfinite(v))
            return lf_fail(err, LF_EINVAL, "baseline must be >= 0 (got %g)", v);
        c->baseline = v;
        c->delta_min = NAN;
        break;
    case LF_FACTOR_POINTS:
        if (!(v >= NL && v <= 1e7) || v != floor(v))
            return lf_fail(err, LF_EINVAL, "points must be a whole number from %d (got %g)", NL, v);
        c->points = (size_t) v;
        break;
    default:
        return lf_fail(err, LF_EINVAL, "unknown factor");
    }
    return LF_OK;
}

int
lf_design_sweep(const lf_design_settings *s, size_t n, const lf_design_candidate *cand,
                lf_design_factor factor, size_t which, size_t nv, const double *values,
                lf_design_result *out, lf_error *err)
{
    lf_design_candidate *c = malloc((n ? n : 1) * sizeof *c);
    size_t v, i;
    int st = LF_OK;

    if (c == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory");
    if (which != (size_t) -1 && which >= n) {
        free(c);
        return lf_fail(err, LF_EINVAL, "candidate %zu does not exist", which + 1);
    }
    for (v = 0; v < nv; v++)
        memset(&out[v], 0, sizeof out[v]);
    for (v = 0; v < nv && st == LF_OK; v++) {
        lf_design *d;
        memcpy(c, cand, n * sizeof *c);
        for (i = 0; i < n && st == LF_OK; i++)
            if (which == (size_t) -1 || which == i)
                st = apply_factor(&c[i], factor, values[v], err);
        if (st != LF_OK)
            break;
        d = lf_design_alloc(s, n, c, err);
        if (d == NULL) {
            st = err ? err->status : LF_EINVAL;
            break;
        }
        st = lf_design_eval(d, NULL, &out[v], err);
        lf_design_free(d);
    }
    if (st != LF_OK)
        for (v = 0; v < nv; v++)
            lf_design_result_free(&out[v]);
    free(c);
    return st;
}
