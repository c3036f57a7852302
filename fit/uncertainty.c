/* uncertainty.c: covariance, confidence intervals and identifiability at
 * the solution of a fit.
 *
 * J is the weighted Jacobian with respect to the physical parameters (w,
 * E*, nu, then z0, F0, s of each curve).  Its columns are scaled to unit
 * norm, Js = J D^-1, and decomposed, Js = U S V^T (decomp.c, shared with
 * the model choice).
 * Rule: a singular value below rcond * S_max (settings, default 1e-7)
 * marks a direction the data do not determine; a parameter whose squared
 * components along those directions sum to more than 0.01 is "not
 * determined" and gets no value or error.  The covariance is the
 * pseudo-inverse over the remaining directions,
 *     C = s^2 D^-1 V S^-2 V^T D^-1,   s^2 = chi2 / dof,
 * i.e. the relative weights come from each curve's noise estimate and the
 * overall scale from the residuals (so errors stay honest when the noise
 * estimate is off, and chi2/dof near 1 says the model fits).  Intervals:
 * w and E* log-normal, exp(ln x +- 1.96 se/x); nu normal, clipped to
 * [0, 0.5].  w counts as "below the noise" when w < 2 se: then only the
 * one-sided bound w + 1.645 se is reported. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_linalg.h>

#include "fit.h"


/* Standard error of free parameter i, or NaN. */
static double
se_of(const lf_fit_result *r, int i)
{
    return i < 0 ? NAN : sqrt(lf_fit_result_cov(r, (size_t) i, (size_t) i));
}

static void
estimate_fixed(lf_fit_estimate *e, double value)
{
    e->why = NULL;
    e->value = value;
    e->se = NAN;
    e->ci95[0] = e->ci95[1] = value;
    e->free = 0;
    e->determined = 1;
    e->upper_bound_only = 0;
}

static void
estimate_undetermined(lf_fit_estimate *e, int free)
{
    e->free = free;
    lf_fit_estimate_drop(e, NULL);
}

/* A positive parameter with a log-normal interval. */
static void
estimate_positive(lf_fit_estimate *e, double value, double se)
{
    e->why = NULL;
    e->value = value;
    e->se = se;
    e->ci95[0] = value * exp(-FIT_Z95 * se / value);
    e->ci95[1] = value * exp(FIT_Z95 * se / value);
    e->free = 1;
    e->determined = 1;
    e->upper_bound_only = 0;
}

static void
name_parameters(const lf_fit *f, lf_fit_result *r)
{
    size_t j;
    static const char *const mat[FIT_NMAT] = { "w", "E*", "nu" };
    int i;

    for (i = 0; i < FIT_NMAT; i++)
        if (f->imat[i] >= 0)
            snprintf(r->names[f->imat[i]], sizeof r->names[0], "%s", mat[i]);
    for (j = 0; j < f->ncurves; j++) {
        if (f->c[j].iz0 >= 0)
            snprintf(r->names[f->c[j].iz0], sizeof r->names[0], "z0[%zu]", j + 1);
        if (f->c[j].iF0 >= 0)
            snprintf(r->names[f->c[j].iF0], sizeof r->names[0], "F0[%zu]", j + 1);
        if (f->c[j].islope >= 0)
            snprintf(r->names[f->c[j].islope], sizeof r->names[0], "s[%zu]", j + 1);
    }
}

/* The shared decomposition (decomp.c) at x: the covariance, singular
 * values and V, D and the rank. */
static int
normal_decompose(lf_fit *f, const double *x, const gsl_vector *res, fit_decomp *d)
{
    const size_t p = f->np;
    const fit_lm *lm = &f->ws.lm;
    gsl_vector_const_view xv = gsl_vector_const_view_array(x, p);
    double *G, *g, *c;
    int status;

    if (lf_fit_decomp_alloc(d, 0, p) != LF_OK)
        return LF_ENOMEM;
    if ((G = malloc((p * p + 2 * p) * sizeof *G)) == NULL)
        return LF_ENOMEM;
    g = G + p * p;
    c = g + p;
    /* J^T J at x: lm.c's own when its last look at the Jacobian was at x
     * (the same origin and weights), else summed again (no evaluation: the
     * model's at x are cached) */
    if (f->ws.own && lf_fit_gn_at(f, &xv.vector)
        && memcmp(lm->x->data, x, p * sizeof *x) == 0)
        lf_arrow_dense(&lm->A, G);
    else {
        fit_arrow A;
        int st = lf_arrow_copy_layout(&A, &lm->A);
        if (st == LF_OK && lf_fit_normal_sums(f, x, res->data, &A, g, c) != GSL_SUCCESS)
            st = LF_ENUMERIC;
        if (st == LF_OK)
            lf_arrow_dense(&A, G);
        lf_arrow_free(&A);
        if (st != LF_OK) {
            free(G);
            return st;
        }
    }
    lf_fit_internal_scale(f, x, c);
    status = lf_fit_decomp_normal(d, G, c, f->set.rcond);
    free(G);
    return status;
}

/* The decomposition at x into d (the caller frees it): r's singular
 * values and covariance.  Beyond FIT_DENSE_P parameters in block form
 * (decomp_block.c): the covariance stays in it, r->covariance sharing its
 * blocks (the caller hands them over at the end, assess). */
static int
decompose(lf_fit *f, const double *x, const gsl_vector *res, lf_fit_result *r, fit_decomp *d)
{
    size_t p = f->np, i, k;
    double s2 = r->se_scale * r->se_scale;
    int status;

    if (p > FIT_DENSE_P) {
        struct lf_fit_covariance *c = calloc(1, sizeof *c);
        memset(d, 0, sizeof *d);
        if (c == NULL || (c->det = malloc(p)) == NULL) {
            free(c);
            return LF_ENOMEM;
        }
        r->covariance = c;
        status = lf_fit_decomp_block_run(d, f, x, 0, f->set.rcond);
        c->b = d->blk;          /* shared until assess hands it over */
        c->scale = s2;
        memset(c->det, 1, p);
        if (status != LF_OK)
            return status;
        for (k = 0; k < p; k++)
            r->singular[k] = NAN;
        r->singular[0] = 1.0;
        r->singular[p - 1] = lf_fit_decomp_smin_ratio(d);
        return LF_OK;
    }
    status = normal_decompose(f, x, res, d);
    if (status == LF_ENUMERIC) {
        /* not well conditioned enough for J^T J: the QR of J */
        lf_fit_decomp_free(d);
        if (lf_fit_decomp_alloc(d, f->nres, p) != LF_OK)
            return LF_ENOMEM;
        status = lf_fit_decomp_run(d, f, x, f->set.rcond);
    }
    if (status != LF_OK)
        return status;
    for (k = 0; k < p; k++)
        r->singular[k] = gsl_vector_get(d->S, k) / gsl_vector_get(d->S, 0);
    for (i = 0; i < p; i++)
        for (k = 0; k < p; k++)
            r->cov[i * p + k] = lf_fit_decomp_cov(d, (int) i, (int) k, s2);
    return LF_OK;
}

/* The residuals' autocorrelation time, pooled over the curves by their
 * points (noise.c); each curve's own, and its noise sd, go into r's curve
 * records (the noise model of consistency() starts from them). */
static double
pooled_corr_time(lf_fit *f, lf_fit_result *r, const gsl_vector *res)
{
    double sum = 0.0;
    size_t j, n = 0;
    for (j = 0; j < f->ncurves; j++) {
        lf_fit_curve_result *cr = &r->curves[j];
        lf_fit_curve_noise(f, j, res, &cr->corr_time, &cr->noise_sd);
        sum += cr->corr_time * (double) f->c[j].data.n;
        n += f->c[j].data.n;
    }
    return n > 0 ? sum / (double) n : 1.0;
}

/* The variance of M = Z(nu) E* of the bonded curves from the covariance
 * (before undetermined rows are blanked: M can be determined when E* and
 * nu are not). */
static double
M_variance(const lf_fit *f, const lf_fit_result *r, const lf_material *mat)
{
    const int idx[2] = { f->imat[FIT_E], f->imat[FIT_NU] };
    double Z = lf_thin_Z(LF_BASE_BONDED, mat->nu), dlnZ = lf_thin_dlogZ_dnu(LF_BASE_BONDED, mat->nu);
    double g[2], var = 0.0;
    int a, b;

    g[0] = Z;                       /* dM/dE* */
    g[1] = mat->Estar * Z * dlnZ;   /* dM/dnu */
    for (a = 0; a < 2; a++)
        for (b = 0; b < 2; b++)
            if (idx[a] >= 0 && idx[b] >= 0)
                var += g[a] * g[b] * lf_fit_result_cov(r, (size_t) idx[a], (size_t) idx[b]);
    return var;
}

/* M and its error; whether it is free and determined is the judgement's. */
static void
estimate_M(const lf_fit *f, const lf_fit_result *r, const lf_material *mat,
           const judge_out *o, lf_fit_estimate *M)
{
    double Z = lf_thin_Z(LF_BASE_BONDED, mat->nu), var;

    if (!o->M_free) {
        if (f->any_bonded && f->imat[FIT_E] < 0 && f->imat[FIT_NU] < 0)
            estimate_fixed(M, Z * mat->Estar);
        else
            estimate_undetermined(M, 0);
        return;
    }
    var = M_variance(f, r, mat);
    if (!o->M_det || !(var >= 0)) {
        estimate_undetermined(M, 1);
        M->why = o->M_why;
        return;
    }
    estimate_positive(M, Z * mat->Estar, sqrt(var));
}

/* Does curve j agree with the material fitted to all curves?  Its
 * residuals over its own noise sd (estimated from the data, not the model;
 * robust weights included): chi2 per point and its chi-square tail, and
 * the Wald-Wolfowitz runs test of their signs in order of depth, which a
 * misfit in shape (a wrong k, R, b or interface) drives far below 0 while
 * the noise level does not matter to it. */
static void
consistency(const lf_fit *f, size_t j, const gsl_vector *res, lf_fit_curve_result *cr)
{
    const fit_curve *c = &f->c[j];
    size_t i, own;
    double chi2 = 0.0;

    for (i = 0; i < c->data.n; i++) {
        double u = gsl_vector_get(res, c->row + i);
        chi2 += u * u;
    }
    cr->downweighted = 0;
    for (i = 0; i < c->data.n; i++)
        cr->downweighted += f->ws.sqrtw[c->row + i] * f->ws.sqrtw[c->row + i] < 0.5;
    own = (size_t) (c->iz0 >= 0) + (size_t) (c->iF0 >= 0) + (size_t) (c->islope >= 0);
    (void) chi2;
    /* chi2 per point and the runs test against the noise model of the data
     * (noise.c: correlated noise, its own sd and independent points); the
     * noise sd is itself estimated (to some 10% for 300 points), so chi2
     * alone flags only a gross excess; the runs test does not depend on it */
    lf_fit_noise_model(f, j, res, cr);
    cr->p_value = cr->n_eff > (double) own + 1.0
                  ? gsl_cdf_chisq_Q(cr->chi2_per_point * (double) c->data.n / cr->corr_time,
                                    cr->n_eff - (double) own)
                  : NAN;
}

/* k = 2 stands for a sphere of radius R, a paraboloid only where a << R: the
 * sphere's height at radius a, R - sqrt(R^2 - a^2), exceeds the
 * paraboloid's a^2 / (2 R) by 2.4% at a = 0.3 R and 7% at 0.5 R, and no
 * sphere reaches a = R.  Past SPHERE_A_OVER_R (5% in height) the largest
 * contact radius of the curve is a warning. */
#define SPHERE_A_OVER_R 0.43
static void
sphere_check(const lf_probe *p, const lf_model_type *t, double amax, lf_warnings *w)
{
    double q = amax / lf_probe_length(p);

    /* a true sphere (LF_TIP_SPHERE) is modelled as one: exactly on a
     * half-space; on a thin layer up to its equator; by the exact model
     * through a correction of its paraboloid (src/exact_sphere.c) */
    if (p->tip == LF_TIP_SPHERE && t->scope == LF_SCOPE_THIN && q >= 1.0 - 1e-9)
        lf_warn(w, "the contact reaches the sphere's equator (a = R): past it the thin-layer "
                "model takes a flat punch of radius R");
    if (p->tip == LF_TIP_SPHERE && t->scope == LF_SCOPE_ANY && q > 0.5)
        lf_warn(w, "the contact radius reaches a = %.2g R: the exact model's sphere is a "
                "correction of its paraboloid, within 0.7%% of the force up to a = 0.5 R, 2%% up "
                "to 0.7 R, 7%% up to 0.9 R", q);
    if (p->tip != LF_TIP_POWER || fabs(p->k - 2.0) > 1e-9 || !(q > SPHERE_A_OVER_R))
        return;
    if (q < 1.0)
        lf_warn(w, "the contact radius reaches a = %.3g m, %.2g R: a sphere of radius R departs "
                "there from the paraboloid of k = 2 by %.2g%% in height (the model takes a << R; "
                "tip sphere models the sphere itself)",
                amax, q, 100.0 * ((1.0 - sqrt(1.0 - q * q)) / (0.5 * q * q) - 1.0));
    else
        lf_warn(w, "the contact radius reaches a = %.3g m, %.2g R: no sphere of radius R makes "
                "such a contact (k = 2 is a paraboloid, a sphere only where a << R; check R and "
                "the depth's units)", amax, q);
}

/* Contact is made at indentation 0 (on approach, and the unloading branch
 * starts where loading turned), so a curve's deepest point lies at or
 * past its contact point.  A free contact point fitted deeper than that by
 * more than Z0_PAST_SE standard errors has the probe never reach the
 * undeformed surface: the whole curve would be adhesive pull.  The rule
 * for an offset far outside the data (verdict.c, two spans) calls such a
 * fit ran away; nearer, it is a converged fit that says so. */
#define Z0_PAST_SE 2.0
static void
contact_point_check(const fit_curve *c, const lf_fit_curve_result *cr, lf_warnings *w)
{
    const double past = cr->z0 - c->zhi;

    if (!cr->z0_free || !(past > 0) || !(past > Z0_PAST_SE * cr->z0_se))
        return;
    lf_warn(w, "the contact point z0 = %.4g m lies %.3g m (%.2g se) past the deepest point of "
            "the curve: the fit has the probe never reach the undeformed surface (contact is made "
            "at indentation 0), so every point would be adhesive pull (check the depth's sign and "
            "origin, the segment, or fix z0)", cr->z0, past, past / cr->z0_se);
}

static void
assess_curve(lf_fit *f, const double *x, size_t j, lf_fit_result *r, const fit_decomp *d,
             const judge_out *o, const gsl_vector *res)
{
    const fit_curve *c = &f->c[j];
    lf_fit_curve_result *cr = &r->curves[j];
    lf_material mat;
    double z0, F0, slope, ss = 0.0, amin = HUGE_VAL, amax = 0.0, b = c->data.probe.b;
    size_t i;

    lf_fit_unpack(f, x, &mat, &z0, &F0, &slope, j);
    cr->name = c->data.name;
    cr->probe = c->data.probe;
    cr->branch = c->data.branch;
    cr->n = c->data.n;
    cr->z0 = z0;
    cr->F0 = F0;
    cr->slope = slope;
    cr->z0_free = c->iz0 >= 0;
    cr->F0_free = c->iF0 >= 0;
    cr->slope_free = c->islope >= 0;
    cr->z0_se = se_of(r, c->iz0);
    cr->F0_se = se_of(r, c->iF0);
    cr->slope_se = se_of(r, c->islope);
    if (c->iz0 >= 0 && !lf_judge_col_determined(d, c->iz0))
        cr->z0 = cr->z0_se = NAN;
    if (c->iF0 >= 0 && (!lf_judge_col_determined(d, c->iF0) || o->k2))
        cr->F0 = cr->F0_se = NAN;
    cr->sigma = c->sigma;
    cr->quantum = c->quantum;
    if (c->quantum > 0 && !(c->sigma > c->quantum / sqrt(12.0)))
        lf_warn(&cr->warnings, "the force is quantized in steps of %.3g N and varies less "
                "from point to point than that: its noise is taken as the step's own rounding, "
                "step / sqrt(12) = %.3g N", c->quantum, c->sigma);
    for (i = 0; i < c->data.n; i++) {
        size_t k = c->row + i;
        double e = lf_fit_unweighted(gsl_vector_get(res, k), c->sigma, f->ws.sqrtw[k]);
        ss += e * e;
        cr->fitted[i] = c->data.force[i] + e;
        cr->contact_radius[i] = f->ws.ev[k].a;
        if (f->ws.ev[k].a > 0)
            amin = lf_fmin(amin, f->ws.ev[k].a);
        amax = lf_fmax(amax, f->ws.ev[k].a);
    }
    cr->rms = sqrt(ss / (double) c->data.n);
    if (lf_model_pulloff(c->model, &mat, &cr->pulloff, NULL) != LF_OK)
        memset(&cr->pulloff, 0, sizeof cr->pulloff);
    cr->b_over_a_min_contact = amin < HUGE_VAL ? b / amin : NAN;
    cr->b_over_a_pulloff = cr->pulloff.a_po > 0 ? b / cr->pulloff.a_po : NAN;
    cr->pulloff_determined = r->w.determined;
    /* the b << a warnings concern the thin-layer model only */
    if (lf_model_get_type(c->model)->scope == LF_SCOPE_THIN) {
        lf_judge_thin_strain(&cr->warnings, NULL, cr->b_over_a_min_contact,
                             "at the shallowest point in contact", f->set.max_b_over_a);
        if (cr->pulloff_determined)
            lf_judge_thin_strain(&cr->warnings, NULL, cr->b_over_a_pulloff, "at pull-off",
                                 f->set.max_b_over_a);
    }
    sphere_check(&c->data.probe, lf_model_get_type(c->model), amax, &cr->warnings);
    lf_fit_plausible_curve(f, j, z0, amax, &cr->warnings);
    contact_point_check(c, cr, &cr->warnings);
    consistency(f, j, res, cr);
    if (cr->downweighted > 0)
        lf_warn(&cr->warnings, "%zu points weigh less than half under the %s loss (outliers)",
                cr->downweighted, lf_loss_name(f->set.loss));
    if (cr->shape > FIT_SHAPE_MAX && cr->chi2_per_point <= 4.0 && !(cr->runs_z < FIT_RUNS_Z_BAD))
        lf_warn(&cr->warnings, "its residuals follow a shape %.2g times the noise (the rms of "
                "their means over sixteenths of the curve, against the noise sd): a systematic "
                "misfit, which the correlation of neighbouring residuals does not explain",
                cr->shape);
    /* against the noise model's sd (noise.c: = sigma for white noise) */
    if (cr->rms > 1.5 * cr->noise_sd && cr->agreement == 1)
        lf_warn(&cr->warnings, "residuals are %.2g times the noise estimated from the data: "
                "the model describes the shape, not every feature of this curve",
                cr->rms / cr->noise_sd);
    else if (cr->rms > 1.5 * cr->noise_sd)
        lf_warn(&cr->warnings, "residuals are %.2g times the noise estimated from the data: "
                "the model does not describe this curve well", cr->rms / cr->noise_sd);
}

/* Name the curves that disagree with the material fitted to all of them. */
static void
agreement(const lf_fit *f, lf_fit_result *r)
{
    size_t j, bad = 0;

    for (j = 0; j < f->ncurves; j++)
        bad += !r->curves[j].consistent;
    /* when all of three or more disagree, one bad curve may be dragging the
     * material: the driver refits without each (leave_one_out) */
    if (bad == 0 || (bad == f->ncurves && f->ncurves >= 3))
        return;
    for (j = 0; j < f->ncurves; j++) {
        const lf_fit_curve_result *cr = &r->curves[j];
        if (cr->consistent)
            continue;
        if (bad < f->ncurves)
            lf_warn(&r->warnings, "curve %zu (%s) disagrees with the others: its residuals are "
                    "%.3g times its noise (chi2/point %.3g, p = %.2g; runs test z = %.3g): check "
                    "its k, R, b, interface and segment", j + 1, cr->name ? cr->name : "",
                    sqrt(cr->chi2_per_point), cr->chi2_per_point, cr->p_value, cr->runs_z);
        else if (cr->agreement == 1)
            /* the verdict of noise.c, the shape followed within 5% of the
             * force range but not to the noise: the curve's own warning
             * (assess_curve) says so, once */
            continue;
        else
            lf_warn(&r->warnings, "curve %zu (%s) is not described by the model: its residuals are "
                    "%.3g times its noise (chi2/point %.3g, p = %.2g; runs test z = %.3g)",
                    j + 1, cr->name ? cr->name : "", sqrt(cr->chi2_per_point),
                    cr->chi2_per_point, cr->p_value, cr->runs_z);
    }
}

/* The judgement's measures at a fit's solution (judge.c asks for them
 * only where it needs them). */
typedef struct {
    lf_fit *f;
    const double *x;
    const lf_fit_result *r;
    const fit_decomp *d;    /* at x */
    int refitted;           /* the k = 2 refit moved f's evaluations */
} assess_ctx;

/* k = 2: chi2 with w held e^FIT_K2_W_HIGH times higher (every point then
 * in contact) against its threshold, by a refit (hold.c). */
static int
w_open_above(void *ctx)
{
    assess_ctx *a = ctx;
    if (a->f->k2_waits) {       /* leave-one-out's refits (loo.c) */
        a->f->k2_waited = 1;
        return 0;
    }
    a->refitted = 1;
    return lf_fit_w_open_above(a->f, a->r, exp(FIT_K2_W_HIGH));
}

/* E* with nu's column (nu held) added to the Jacobian at x: 1 when still
 * determined, with the regression of ln E* on nu. */
static int
E_with_nu(void *ctx, double *dlnE_dnu)
{
    assess_ctx *a = ctx;
    lf_fit *f = a->f;
    const int e = f->imat[FIT_E];
    int nu = (int) f->np, ok = 0, st;
    fit_decomp d;

    if (f->np + 1 > FIT_DENSE_P) {
        /* in block form nu's column follows the material's */
        memset(&d, 0, sizeof d);
        st = lf_fit_decomp_block_run(&d, f, a->x, 1, f->set.rcond);
        nu = (int) d.blk.m - 1;
    } else {
        if (lf_fit_decomp_alloc(&d, f->nres, f->np + 1) != LF_OK)
            return 0;
        st = lf_fit_jacobian_physical_nu(f, a->x, d.QR) == GSL_SUCCESS
             ? lf_fit_decomp_factor(&d, f->set.rcond, 1) : LF_ENUMERIC;
    }
    if (st == LF_OK && lf_judge_col_determined(&d, e)
        && lf_fit_decomp_cov(&d, nu, nu, 1.0) > 0) {
        *dlnE_dnu = lf_fit_decomp_cov(&d, e, nu, 1.0) / lf_fit_decomp_cov(&d, nu, nu, 1.0) / f->mat.Estar;
        ok = 1;
    }
    lf_fit_decomp_free(&d);
    return ok;
}

/* The judgement of what the data determine at x (judge.c), its words into
 * r->identifiability. */
static int
judge_at(lf_fit *f, const double *x, const fit_run *run, const fit_decomp *d, lf_fit_result *r,
         const lf_material *mat, judge_out *o)
{
    judge_curve *jc = calloc(f->ncurves, sizeof *jc);
    assess_ctx a = { f, x, r, d, 0 };
    judge_in in;
    size_t j, i;
    int m;

    if (jc == NULL)
        return -1;
    memset(&in, 0, sizeof in);
    in.d = d;
    for (m = 0; m < FIT_NMAT; m++)
        in.col[m] = f->imat[m];
    in.held_by_user[FIT_W] = f->set.w.mode == LF_PARAM_FIXED;
    in.held_by_user[FIT_E] = f->set.Estar.mode == LF_PARAM_FIXED;
    in.held_by_user[FIT_NU] = f->set.nu.mode == LF_PARAM_FIXED;
    in.w = mat->w;
    in.w_se = se_of(r, f->imat[FIT_W]);
    in.nu = mat->nu;
    in.M = lf_thin_Z(LF_BASE_BONDED, mat->nu) * mat->Estar;
    in.M_se = sqrt(M_variance(f, r, mat));
    in.dM[0] = lf_thin_Z(LF_BASE_BONDED, mat->nu);
    in.dM[1] = in.M * lf_thin_dlogZ_dnu(LF_BASE_BONDED, mat->nu);
    in.ncurves = f->ncurves;
    in.c = jc;
    in.ran_away = run->stop == LF_STOP_RAN_AWAY;
    in.ran_col = in.ran_away ? run->ran_col : -1;
    for (j = 0; j < f->ncurves; j++)
        in.ran_force |= in.ran_col >= 0 && f->c[j].iF0 == in.ran_col;
    in.ctx = &a;
    in.w_open_above = w_open_above;
    in.E_with_nu = E_with_nu;
    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        snprintf(jc[j].label, sizeof jc[j].label, "%zu", j + 1);
        jc[j].k = c->data.probe.k;
        jc[j].base = c->data.probe.base;
        jc[j].branch = c->data.branch;
        jc[j].model = lf_model_get_type(c->model);
        for (i = 0; i < c->data.n; i++)
            jc[j].n_out += f->ws.ev[c->row + i].a == 0.0;
        jc[j].col_z0 = c->iz0;
        jc[j].col_F0 = c->iF0;
        jc[j].col_slope = c->islope;
    }
    lf_judge(&in, o, &r->identifiability);
    free(jc);
    return a.refitted;
}

int
lf_fit_assess(lf_fit *f, const double *x, const fit_run *run, lf_fit_result *r, lf_error *err)
{
    size_t p = f->np, i, k, j;
    gsl_vector *res = gsl_vector_alloc(f->nres);
    gsl_vector_const_view xv = gsl_vector_const_view_array(x, p);
    double z0, F0, slope;
    lf_material mat;
    fit_decomp d;
    judge_out o;
    int status, refitted;

    memset(&d, 0, sizeof d);
    if (res == NULL || lf_fit_result_alloc(f, r) != LF_OK) {
        status = lf_fail(err, LF_ENOMEM, "out of memory assessing a fit");
        goto done;
    }
    if (lf_fit_residuals(&xv.vector, f, res) != GSL_SUCCESS) {
        status = lf_fail(err, LF_ENUMERIC, "the model cannot be evaluated at the solution");
        goto done;
    }
    r->chi2 = 0.0;          /* the residuals are finite (lf_fit_residuals checks) */
    for (i = 0; i < f->nres; i++)
        r->chi2 += res->data[i] * res->data[i];
    r->dof = f->nres - p;
    /* correlated noise: errors grow by the residuals' autocorrelation time
     * (noise.c), pooled over the curves by their points */
    r->corr_time = pooled_corr_time(f, r, res);
    r->se_scale = sqrt(r->chi2 / (double) r->dof * r->corr_time);
    status = decompose(f, x, res, r, &d);
    if (status != LF_OK) {
        status = lf_fail(err, status, "the Jacobian at the solution cannot be decomposed");
        goto done;
    }
    name_parameters(f, r);
    lf_fit_unpack(f, x, &mat, &z0, &F0, &slope, f->ncurves);
    f->mat = mat;
    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        lf_fit_unpack(f, x, &mat, &z0, &F0, &slope, j);
        if (c->iz0 >= 0) r->value[c->iz0] = z0;
        if (c->iF0 >= 0) r->value[c->iF0] = F0;
        if (c->islope >= 0) r->value[c->islope] = slope;
    }
    mat = f->mat;
    if (f->imat[FIT_W] >= 0) r->value[f->imat[FIT_W]] = mat.w;
    if (f->imat[FIT_E] >= 0) r->value[f->imat[FIT_E]] = mat.Estar;
    if (f->imat[FIT_NU] >= 0) r->value[f->imat[FIT_NU]] = mat.nu;
    /* what the data determine (judge.c; the k = 2 check refits from these
     * values, hold.c: the model's evaluations ev[] are those at x again
     * after) */
    refitted = judge_at(f, x, run, &d, r, &mat, &o);
    if (refitted < 0) {
        status = lf_fail(err, LF_ENOMEM, "out of memory assessing a fit");
        goto done;
    }
    if (refitted && lf_fit_residuals(&xv.vector, f, res) != GSL_SUCCESS) {
        status = lf_fail(err, LF_ENUMERIC, "the model cannot be evaluated at the solution");
        goto done;
    }
    estimate_M(f, r, &mat, &o, &r->M);

    /* w */
    if (f->imat[FIT_W] < 0)
        estimate_fixed(&r->w, mat.w);
    else if (o.w_upper) {
        estimate_undetermined(&r->w, 1);
        r->w.upper_bound_only = 1;
        r->w.ci95[0] = 0.0;
        r->w.ci95[1] = o.w_bound;
    } else if (!o.det[FIT_W]) {
        estimate_undetermined(&r->w, 1);
        r->w.why = o.why[FIT_W];
    } else {
        estimate_positive(&r->w, mat.w, se_of(r, f->imat[FIT_W]));
    }
    /* nu */
    if (o.det[FIT_NU]) {
        double se = se_of(r, f->imat[FIT_NU]);
        r->nu.value = mat.nu;
        r->nu.se = se;
        r->nu.ci95[0] = lf_fmax(mat.nu - FIT_Z95 * se, 0.0);
        r->nu.ci95[1] = lf_fmin(mat.nu + FIT_Z95 * se, 0.5);
        r->nu.free = 1;
        r->nu.determined = 1;
        r->nu.why = NULL;
    } else if (f->imat[FIT_NU] >= 0 || f->set.nu.mode != LF_PARAM_FIXED) {
        estimate_undetermined(&r->nu, f->imat[FIT_NU] >= 0);
        r->nu.why = o.why[FIT_NU];
    } else {
        estimate_fixed(&r->nu, mat.nu);
    }
    /* E* */
    if (f->imat[FIT_E] < 0)
        estimate_fixed(&r->Estar, mat.Estar);
    else if (!o.det[FIT_E]) {
        estimate_undetermined(&r->Estar, 1);
        r->Estar.why = o.why[FIT_E];
    } else
        estimate_positive(&r->Estar, mat.Estar, se_of(r, f->imat[FIT_E]));

    /* blank what is not determined, then correlations (in block form the
     * accessor reads the mask) */
    for (k = 0; k < p; k++)
        if (!lf_judge_col_determined(&d, (int) k)) {
            if (r->covariance != NULL)
                r->covariance->det[k] = 0;
            else
                for (i = 0; i < p; i++)
                    r->cov[k * p + i] = r->cov[i * p + k] = NAN;
        }
    if (r->corr != NULL)
        for (i = 0; i < p; i++)
            for (k = 0; k < p; k++)
                r->corr[i * p + k] = r->cov[i * p + k]
                                     / sqrt(r->cov[i * p + i] * r->cov[k * p + k]);
    for (j = 0; j < f->ncurves; j++)
        assess_curve(f, x, j, r, &d, &o, res);
    agreement(f, r);
    lf_fit_plausible(r);
    if (r->corr_time > 1.5)
        lf_warn(&r->warnings, "neighbouring residuals are correlated (filtered or oversampled "
                "data): about one independent point in %.3g; standard errors include that "
                "factor (scaled by %.3g in all)", r->corr_time, r->se_scale);
    else if (r->chi2 / (double) r->dof > 2.0)
        lf_warn(&r->warnings, "chi2/dof = %.3g: the residuals exceed the point-to-point noise "
                "(model misfit or correlated noise); standard errors are scaled by %.3g",
                r->chi2 / (double) r->dof, r->se_scale);
    status = LF_OK;
done:
    gsl_vector_free(res);
    if (r->covariance != NULL && d.block) {
        /* the blocks are the result's now; their scratch goes */
        memset(&d.blk, 0, sizeof d.blk);
        lf_fit_bdec_trim(&r->covariance->b);
    }
    lf_fit_decomp_free(&d);
    return status;
}
