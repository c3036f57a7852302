/* judge.c: one judgement of what a set of curves determines, and why, in
 * words.  The fitter asks it at its solution (uncertainty.c, choose.c), a
 * design at the truth (design.c); both hand it the decomposition of the
 * column-scaled Jacobian of the model in use (decomp.c) and what it needs
 * to know of each curve, so that no rule exists twice.
 *
 * The rules, in order:
 *  - a parameter whose weight in the undetermined directions (singular
 *    values below rcond S_0) exceeds FIT_NULL_WEIGHT is not determined;
 *    so is a derived quantity (M = Z E*) whose gradient has that weight;
 *  - k = 2 with z0 and F0 free: in contact the force is nearly a parabola
 *    in depth (exactly one for the thin layer, Eq. 10 of the seed paper:
 *    P = M K ((z - z0)^2 - c^2) + F0), three coefficients for four
 *    unknowns, so w is told from F0 only by the points past detachment,
 *    where the force is F0 alone (other models' curves are parabolas only
 *    nearly, the exact model's where the layer is thin, or not at all, the
 *    half-space's).  When every curve is such a curve, w is not separable
 *    from the force offsets when no curve under the thin-layer model has
 *    FIT_K2_MIN_OUT points out of contact (the contact edge moves over
 *    fewer), when the Jacobian leaves w undetermined, or when the data do
 *    not bound w from above (chi2 with w held e^FIT_K2_W_HIGH times higher
 *    rises by less than its threshold: measured by a refit at a fit's
 *    solution, predicted from the linearised model for a design);
 *  - w below two standard errors is bounded from above only;
 *  - bonded curves alone with nu neither held by the user nor determined:
 *    where the layer is thin the force depends on E* and nu through
 *    M = Z(nu) E* only (the seed paper, Eq. 22), so E* is not determined
 *    and M is; a thicker layer, under the exact model, acts more and more
 *    like a half-space, whose force fixes E* itself (Lebedev & Ufliand
 *    1958; Dimitriadis et al. 2002).  Which of the two the data are is the
 *    Jacobian's to say: with nu's column added, the data fix E* when E*
 *    moves less with nu (the regression of ln E* on nu) than M does;
 *  - a fit that ran away (an offset far outside its curve's data): the
 *    material parameters that moved with that offset (correlation of
 *    FIT_RAN_CORR or more) have no estimate and no bound.
 * And the model choice's rule (lf_judge_models) with its words. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fit.h"

static const char *const mat_names[FIT_NMAT] = { "w", "E*", "nu" };

const lf_model_type *
lf_fit_rung_type(int rung)
{
    return lf_model_type_cheapest(rung == FIT_RUNG_THIN ? LF_SCOPE_THIN
                                  : rung == FIT_RUNG_HALFSPACE ? LF_SCOPE_HALFSPACE
                                                               : LF_SCOPE_ANY);
}

int
lf_fit_rung_of(const lf_model_type *t)
{
    return t->scope == LF_SCOPE_THIN ? FIT_RUNG_THIN
           : t->scope == LF_SCOPE_HALFSPACE ? FIT_RUNG_HALFSPACE : FIT_RUNG_EXACT;
}

int
lf_judge_col_determined(const fit_decomp *d, int col)
{
    return col >= 0 && lf_fit_decomp_nullw(d, (size_t) col) <= FIT_NULL_WEIGHT;
}

/* The weight in the undetermined directions of the linear combination
 * sum_i g[i] * (parameter of column cols[i]) (g in the parameters' own
 * units; columns -1 skipped): its gradient in the scaled coordinates,
 * normalised.  1 when it has no gradient. */
static double
combination_nullw(const fit_decomp *d, const int *cols, const double *g, size_t m)
{
    double norm = 0.0, null = 0.0;
    size_t i, l;

    for (i = 0; i < m; i++)
        if (cols[i] >= 0) {
            double dk = gsl_vector_get(d->D, (size_t) cols[i]);
            if (!(dk > 0))
                return 1.0;
            norm += g[i] * g[i] / (dk * dk);
        }
    if (!(norm > 0))
        return 1.0;
    for (l = d->rank; l < d->p; l++) {
        double s = 0.0;
        for (i = 0; i < m; i++)
            if (cols[i] >= 0)
                s += gsl_matrix_get(d->V, (size_t) cols[i], l) * g[i]
                     / gsl_vector_get(d->D, (size_t) cols[i]);
        null += s * s;
    }
    return null / norm;
}

/* k = 2 alone with free z0 and F0: every curve so. */
static int
k2_alone(const judge_in *in)
{
    size_t j;

    for (j = 0; j < in->ncurves; j++) {
        const judge_curve *c = &in->c[j];
        if (fabs(c->k - 2.0) > 1e-9 || c->col_z0 < 0 || c->col_F0 < 0)
            return 0;
    }
    return in->ncurves > 0;
}

/* The k = 2 verdict: w not separable from the force offsets. */
static int
k2_verdict(const judge_in *in)
{
    size_t j;
    int enough = 0;

    if (in->col[FIT_W] < 0 || !k2_alone(in))
        return 0;
    /* the baseline: under the thin-layer model the curve in contact is a
     * parabola exactly, and fewer points out of contact than
     * FIT_K2_MIN_OUT the contact edge moves over; other models' curves
     * are not parabolas, and the Jacobian and the refit with w held higher
     * judge them.  At a point the fit ran away to, what is in contact says
     * nothing of the data's baseline. */
    for (j = 0; j < in->ncurves; j++)
        enough |= in->c[j].n_out >= FIT_K2_MIN_OUT || in->c[j].model->scope != LF_SCOPE_THIN
                  || in->ran_away;
    if (!enough || !lf_judge_col_determined(in->d, in->col[FIT_W]))
        return 1;
    return in->w_open_above != NULL && in->w_open_above(in->ctx);
}

/* Some curve's free force offset is not determined (w then moves with
 * it). */
static int
w_with_offsets(const judge_in *in)
{
    size_t j;

    for (j = 0; j < in->ncurves; j++)
        if (in->c[j].col_F0 >= 0 && !lf_judge_col_determined(in->d, in->c[j].col_F0))
            return 1;
    return 0;
}

void
lf_judge_thin_strain(lf_warnings *w, const char *who, double ba, const char *where,
                     double limit)
{
    const char *words = lf_thin_scope(ba, limit);

    if (words == NULL)
        return;
    if (who != NULL)
        lf_warn(w, "%s: b/a = %.3g %s: %s (limit %g)", who, ba, where, words, limit);
    else
        lf_warn(w, "b/a = %.3g %s: %s (limit %g)", ba, where, words, limit);
}

/* The plain words of what is not determined and why (into words), from
 * the verdicts in o. */
static void
say(const judge_in *in, const judge_out *o, int any_bonded, lf_warnings *words)
{
    char buf[800];
    size_t j, len = 0;
    int all_k2 = 1, all_load = 1, all_halfspace = 1, other = 0, c;
    int F0_null = o->k2;

    F0_null |= w_with_offsets(in);
    for (j = 0; j < in->ncurves; j++) {
        const judge_curve *cv = &in->c[j];
        all_k2 &= fabs(cv->k - 2.0) <= 1e-9;
        all_load &= cv->branch == LF_BRANCH_LOAD;
        all_halfspace &= cv->model->scope == LF_SCOPE_HALFSPACE;
    }
    switch (o->bonded) {
    case FIT_BONDED_ONLY_M:
        lf_warn(words, "only bonded curves: the data fix M = Z*E* = %.4g Pa (se %.2g Pa)%s; nu "
                "is not determined (fix nu or add a frictionless curve)", in->M, in->M_se,
                o->det[FIT_W] ? " and w" : "");
        break;
    case FIT_BONDED_NOTHING:
        lf_warn(words, "only bonded curves: nu is not determined (fix nu or add a frictionless "
                "curve)");
        break;
    case FIT_BONDED_E:
        lf_warn(words, "only bonded curves: nu is not determined and is held at %.4g; the layer "
                "is not thin for these curves, so the data fix E* rather than M = Z*E*, and E* "
                "moves by %+.2g%% per +0.1 of nu (fix nu or add a frictionless curve to measure "
                "it)", in->nu, 10.0 * o->dlnE_dnu);
        break;
    default:
        break;
    }
    if (!any_bonded && !in->held_by_user[FIT_NU])
        lf_warn(words, "%s curves do not depend on nu: nu is not determined (add a bonded curve "
                "of the same material to measure it)",
                all_halfspace ? "half-space" : "frictionless");
    if (o->k2 && all_k2 && all_load)
        /* the baseline before contact is there: on loading, the curve's
         * shape does not fix w, and the jump into contact that shows it is
         * not resolved */
        lf_warn(words, "k = 2 alone with free F0 and z0 cannot separate w from the force offset "
                "on loading: the curve's shape does not fix w, and the jump into contact that "
                "shows it is not resolved (fit the unload segment, whose pull-off and baseline "
                "past detachment measure it, add a probe with k != 2, or fix F0)");
    else if (o->k2)
        lf_warn(words, "k = 2 alone with free F0 and z0 cannot separate w from the force offset "
                "(record the baseline past detachment, add a probe with k != 2, or fix F0)");
    else if (!o->det[FIT_W] && in->col[FIT_W] >= 0 && F0_null && !o->w_upper)
        lf_warn(words, "w cannot be separated from the force offsets (record the baseline past "
                "detachment or fix F0)");
    if (o->w_upper)
        lf_warn(words, FIT_W_BOUND_WORDS, o->w_bound);
    /* the rest, in column order, that no sentence above explains */
    buf[0] = '\0';
    for (c = 0; c < FIT_NMAT; c++) {
        int explained = (c == FIT_W && (F0_null || o->w_upper))
                        || (o->bonded != FIT_BONDED_NONE && c != FIT_W);
        if (in->col[c] < 0 || lf_judge_col_determined(in->d, in->col[c]) || explained)
            continue;
        len += (size_t) snprintf(buf + len, len < sizeof buf ? sizeof buf - len : 0, "%s%s",
                                 other ? ", " : "", mat_names[c]);
        other = 1;
    }
    for (j = 0; j < in->ncurves && !F0_null; j++) {
        const judge_curve *cv = &in->c[j];
        const int cols[3] = { cv->col_z0, cv->col_F0, cv->col_slope };
        static const char *const what[3] = { "z0", "F0", "s" };
        int q;
        for (q = 0; q < 3; q++) {
            if (cols[q] < 0 || lf_judge_col_determined(in->d, cols[q]))
                continue;
            len += (size_t) snprintf(buf + len, len < sizeof buf ? sizeof buf - len : 0,
                                     "%s%s[%s]", other ? ", " : "", what[q], cv->label);
            other = 1;
        }
    }
    if (other && len < sizeof buf)
        lf_warn(words, "not determined by the data: %s (fix some of them or add curves)", buf);
    if (words->n == 0)
        lf_warn(words, "every free parameter is determined (smallest scaled singular value %.2g)",
                in->d->p > 0 ? gsl_vector_get(in->d->S, in->d->p - 1) / gsl_vector_get(in->d->S, 0)
                             : 1.0);
}

void
lf_judge(const judge_in *in, judge_out *o, lf_warnings *words)
{
    const fit_decomp *d = in->d;
    size_t j;
    int any_bonded = 0, any_frictionless = 0, c;

    memset(o, 0, sizeof *o);
    for (c = 0; c < FIT_NMAT; c++)
        o->det[c] = lf_judge_col_determined(d, in->col[c]);
    /* which curves see nu: bonded layers under a model with a layer */
    for (j = 0; j < in->ncurves; j++) {
        const judge_curve *cv = &in->c[j];
        if (cv->model->scope == LF_SCOPE_HALFSPACE)
            continue;
        if (cv->base == LF_BASE_BONDED)
            any_bonded = 1;
        else
            any_frictionless = 1;
    }
    /* k = 2 */
    o->k2 = k2_verdict(in);
    if (o->k2)
        o->det[FIT_W] = 0;
    /* w below two standard errors: an upper bound */
    if (o->det[FIT_W] && in->w < 2.0 * in->w_se) {
        o->det[FIT_W] = 0;
        o->w_upper = 1;
        o->w_bound = in->w + FIT_Z95_ONE_SIDED * in->w_se;
    }
    /* M = Z(nu) E* of the bonded curves: where its gradient is determined */
    o->M_free = any_bonded && (in->col[FIT_E] >= 0 || in->col[FIT_NU] >= 0);
    if (o->M_free) {
        const int cols[2] = { in->col[FIT_E], in->col[FIT_NU] };
        const double g[2] = { in->dM[0], in->dM[1] };
        o->M_det = combination_nullw(d, cols, g, 2) <= FIT_NULL_WEIGHT;
    }
    /* E* of bonded curves alone, nu neither given nor determined: does E*
     * hinge on nu?  With nu free, when the Jacobian leaves E* undetermined;
     * with nu held (the fitter's rule), when, nu's column added, E* is not
     * determined or moves with nu more than M = Z(nu) E* does: the data
     * then fix M rather than E* */
    o->bonded = FIT_BONDED_NONE;
    if (any_bonded && !any_frictionless && in->col[FIT_E] >= 0 && !in->held_by_user[FIT_NU]
        && !o->det[FIT_NU]) {
        int hinges;
        if (in->col[FIT_NU] >= 0)
            hinges = !o->det[FIT_E];
        else {
            const double z = in->dM[1] / in->M;      /* dln Z / dnu */
            double s = NAN;
            hinges = in->E_with_nu == NULL || !in->E_with_nu(in->ctx, &s)
                     || !(fabs(s) < fabs(s + z));
            o->dlnE_dnu = s;
        }
        if (hinges) {
            o->det[FIT_E] = 0;
            o->why[FIT_E] = o->M_det ? "only M = Z*E* is" : NULL;
            o->bonded = o->M_det ? FIT_BONDED_ONLY_M : FIT_BONDED_NOTHING;
        } else if (in->col[FIT_NU] < 0 && o->det[FIT_E]) {
            o->bonded = FIT_BONDED_E;
            o->M_det = 0;       /* M is then what hinges on the nu assumed */
        }
    }
    /* a run that ran away (an offset far outside its curve's data)
     * stopped where a material parameter that moved with that offset
     * (FIT_RAN_CORR) has no meaning: no estimate, no interval, no bound;
     * M follows E* and nu (an offset the data do not determine has no
     * correlation to go by) */
    if (in->ran_col >= 0 && lf_judge_col_determined(d, in->ran_col)) {
        const char *why = in->ran_force
                          ? "the fit ran away: it moved with a force offset that went far "
                            "outside its curve's forces, and where that stopped is no estimate"
                          : "the fit ran away: it moved with a contact point that went far "
                            "outside its curve's depths, and where that stopped is no estimate";
        const double vr = lf_fit_decomp_cov(d, in->ran_col, in->ran_col, 1.0);
        for (c = 0; c < FIT_NMAT; c++) {
            double vc;
            if (in->col[c] < 0 || !(o->det[c] || (c == FIT_W && o->w_upper)))
                continue;
            vc = lf_fit_decomp_cov(d, in->col[c], in->col[c], 1.0);
            if (!(fabs(lf_fit_decomp_cov(d, in->col[c], in->ran_col, 1.0) / sqrt(vc * vr))
                  >= FIT_RAN_CORR))
                continue;
            o->det[c] = 0;
            o->why[c] = why;
            if (c == FIT_W)
                o->w_upper = 0;
            else if (o->M_det) {
                o->M_det = 0;
                o->M_why = why;
            }
        }
    }
    /* the reasons in words of what is not determined (the notes say more) */
    for (c = 0; c < FIT_NMAT; c++)
        if (in->col[c] >= 0 && !o->det[c] && o->why[c] == NULL && o->bonded == FIT_BONDED_NONE)
            o->why[c] = "the data do not separate it from the other parameters (see what the "
                        "data determine)";
    if (in->col[FIT_W] >= 0 && !o->det[FIT_W] && (o->k2 || w_with_offsets(in)))
        o->why[FIT_W] = "it cannot be told from the force offset";
    if (o->w_upper)
        o->why[FIT_W] = NULL;   /* its upper bound says it */
    if (in->col[FIT_NU] < 0 && !in->held_by_user[FIT_NU])
        o->why[FIT_NU] = "the plan does not determine it";
    say(in, o, any_bonded, words);
}

void
lf_judge_bias(const fit_decomp *d, const int col[FIT_NMAT], const double *coef,
              double r[FIT_NMAT])
{
    size_t l;
    int m;

    for (m = 0; m < FIT_NMAT; m++) {
        double se = 0.0, s = 0.0;
        r[m] = 0.0;
        if (!lf_judge_col_determined(d, col[m]))
            continue;
        for (l = 0; l < d->rank; l++) {
            double v = gsl_matrix_get(d->V, (size_t) col[m], l), sl = gsl_vector_get(d->S, l);
            se += v * v / (sl * sl);
            s += v * coef[l];
        }
        r[m] = se > 0 ? s / sqrt(se) : 0.0;
    }
}

double
lf_judge_bias_max(const double r[FIT_NMAT], int *which)
{
    double m = 0.0;
    int i;

    if (which)
        *which = FIT_W;
    for (i = 0; i < FIT_NMAT; i++)
        if (fabs(r[i]) > m) {
            m = fabs(r[i]);
            if (which)
                *which = i;
        }
    return m;
}

int
lf_judge_models(judge_models *jm, double *total_max, int *changed)
{
    double total[FIT_NMAT] = { 0, 0, 0 };
    size_t j;
    int m, st = LF_OK;

    *changed = 0;
    for (j = 0; j < jm->n; j++)
        for (m = 0; m < FIT_NMAT; m++)
            total[m] += jm->cur[j].r[m];
    while (st == LF_OK) {
        size_t jw = jm->n;
        double worst = 0.0;
        *total_max = lf_judge_bias_max(total, NULL);
        if (!jm->allow_change || *total_max < jm->tol)
            break;
        for (j = 0; j < jm->n; j++) {
            double bm = lf_judge_bias_max(jm->cur[j].r, NULL);
            if (!jm->fixed[j] && jm->rung[j] != FIT_RUNG_EXACT && jm->cur[j].ok && bm > worst) {
                worst = bm;
                jw = j;
            }
        }
        if (jw == jm->n)
            break;      /* nothing left to move */
        for (m = 0; m < FIT_NMAT; m++)
            total[m] -= jm->cur[jw].r[m];
        if (jm->rung[jw] == FIT_RUNG_THIN && jm->halfspace
            && jm->k[jw] > lf_fit_rung_type(FIT_RUNG_HALFSPACE)->k_above)
            st = jm->bias(jm->ctx, jw, FIT_RUNG_HALFSPACE, &jm->half[jw]);
        if (st == LF_OK && jm->rung[jw] == FIT_RUNG_THIN && jm->half[jw].ok
            && lf_judge_bias_max(jm->half[jw].r, NULL) < lf_fmin(jm->tol, worst)) {
            jm->rung[jw] = FIT_RUNG_HALFSPACE;
            jm->cur[jw] = jm->half[jw];
        } else {
            jm->rung[jw] = FIT_RUNG_EXACT;
            memset(jm->cur[jw].r, 0, sizeof jm->cur[jw].r);
        }
        for (m = 0; m < FIT_NMAT; m++)
            total[m] += jm->cur[jw].r[m];
        if (st == LF_OK)
            st = jm->move(jm->ctx, jw, jm->rung[jw]);
        *changed = 1;
    }
    return st;
}

void
lf_judge_model_reason(char *buf, size_t n, int rung, int fixed, const judge_bias *thin,
                      const judge_bias *half, double ab_lo, double ab_hi, double tol)
{
    char range[80] = "";
    int wt, wh;
    double bt = lf_judge_bias_max(thin->r, &wt), bh = lf_judge_bias_max(half->r, &wh);

    if (ab_hi > 0)
        snprintf(range, sizeof range, " over a/b %.3g-%.3g", ab_lo, ab_hi);
    if (fixed) {
        if (thin->ok)
            snprintf(buf, n, "as requested; the thin-layer model would bias %s by %.2g se%s",
                     mat_names[wt], bt, range);
        else
            snprintf(buf, n, "as requested");
        return;
    }
    if (!thin->ok) {
        snprintf(buf, n, "the exact model cannot be evaluated at the fitted parameters, "
                 "so the choice was not checked");
        return;
    }
    switch (rung) {
    case FIT_RUNG_THIN:
        snprintf(buf, n, "the thin-layer model biases %s by at most %.2g se%s "
                 "(tolerance %.2g se)", mat_names[wt], bt, range, tol);
        break;
    case FIT_RUNG_HALFSPACE:
        snprintf(buf, n, "the thin-layer model would bias %s by %.2g se%s, the half-space "
                 "model only %s by %.2g se (tolerance %.2g se)", mat_names[wt], bt, range,
                 mat_names[wh], bh, tol);
        break;
    default:
        snprintf(buf, n, "the thin-layer model would bias %s by %.2g se%s "
                 "(tolerance %.2g se, with the other curves' biases added)",
                 mat_names[wt], bt, range, tol);
        break;
    }
}
