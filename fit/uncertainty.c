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

#define Z95 1.959963984540054
#define Z95_ONE_SIDED 1.6448536269514722

/* Standard error of free parameter i, or NaN. */
static double
se_of(const lf_fit_result *r, int i)
{
    return i < 0 ? NAN : sqrt(r->cov[(size_t) i * r->npar + (size_t) i]);
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
    e->ci95[0] = value * exp(-Z95 * se / value);
    e->ci95[1] = value * exp(Z95 * se / value);
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
 * values and nullw[k], the weight of parameter k in the undetermined
 * directions. */
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
        memcpy(G, lm->A, p * p * sizeof *G);
    else if (lf_fit_normal_sums(f, x, res->data, G, g, c) != GSL_SUCCESS) {
        free(G);
        return LF_ENUMERIC;
    }
    lf_fit_internal_scale(f, x, c);
    status = lf_fit_decomp_normal(d, G, c, f->set.rcond);
    free(G);
    return status;
}

static int
decompose(lf_fit *f, const double *x, const gsl_vector *res, lf_fit_result *r, double *nullw)
{
    size_t p = f->np, i, k, l;
    fit_decomp d;
    double s2 = r->se_scale * r->se_scale;
    int status;

    status = normal_decompose(f, x, res, &d);
    if (status == LF_ENUMERIC) {
        /* not well conditioned enough for J^T J: the QR of J */
        lf_fit_decomp_free(&d);
        if (lf_fit_decomp_alloc(&d, f->nres, p) != LF_OK)
            return LF_ENOMEM;
        status = lf_fit_decomp_run(&d, f, x, f->set.rcond);
    }
    if (status != LF_OK)
        goto done;
    for (k = 0; k < p; k++) {
        r->singular[k] = gsl_vector_get(d.S, k) / gsl_vector_get(d.S, 0);
        nullw[k] = lf_fit_decomp_nullw(&d, k);
    }
    for (i = 0; i < p; i++)
        for (k = 0; k < p; k++) {
            double c = 0.0, di = gsl_vector_get(d.D, i), dk = gsl_vector_get(d.D, k);
            for (l = 0; l < d.rank; l++) {
                double sl = gsl_vector_get(d.S, l);
                c += gsl_matrix_get(d.V, i, l) * gsl_matrix_get(d.V, k, l) / (sl * sl);
            }
            r->cov[i * p + k] = di > 0 && dk > 0 ? s2 * c / (di * dk) : NAN;
        }
done:
    lf_fit_decomp_free(&d);
    return status;
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

/* M = Z(nu) E* of the bonded curves and its error from the covariance
 * (before undetermined rows are blanked: M can be determined when E* and
 * nu are not). */
static void
estimate_M(const lf_fit *f, const lf_fit_result *r, const lf_material *mat,
           const double *nullw, lf_fit_estimate *M)
{
    int iE = f->imat[FIT_E], inu = f->imat[FIT_NU];
    double Z = lf_thin_Z(LF_BASE_BONDED, mat->nu), dlnZ = lf_thin_dlogZ_dnu(LF_BASE_BONDED, mat->nu);
    double g[2], var = 0.0;
    int idx[2] = { iE, inu }, a, b, bad = 0;

    if (!f->any_bonded) {
        estimate_undetermined(M, 0);
        return;
    }
    if (iE < 0 && inu < 0) {
        estimate_fixed(M, Z * mat->Estar);
        return;
    }
    g[0] = Z;                       /* dM/dE* */
    g[1] = mat->Estar * Z * dlnZ;   /* dM/dnu */
    for (a = 0; a < 2; a++)
        for (b = 0; b < 2; b++)
            if (idx[a] >= 0 && idx[b] >= 0)
                var += g[a] * g[b] * r->cov[(size_t) idx[a] * r->npar + (size_t) idx[b]];
    /* E* alone undetermined (not through nu) leaves M undetermined too */
    if (iE >= 0 && nullw[iE] > 0.01 && (inu < 0 || nullw[inu] <= 0.01))
        bad = 1;
    if (bad || !(var >= 0)) {
        estimate_undetermined(M, 1);
        return;
    }
    estimate_positive(M, Z * mat->Estar, sqrt(var));
}

/* physics.md section 2: with k = 2 only and free z0 and F0, the contact
 * part of a curve is a parabola (three coefficients for four unknowns) and
 * w rests on the baseline past detachment alone.  Where every curve is
 * like that and less than 10% of its points lie past detachment at the
 * solution, w is not determined (whatever a noisy edge suggests). */
static int
k2_without_baseline(const lf_fit *f)
{
    return f->k2_degenerate;
}

/* The thin layer's k = 2 force is M K ((z - z0)^2 - c^2) + F0 in contact:
 * w (through c) only shifts it, like F0; a model of finite thickness (the
 * exact one) nearly keeps that form where the layer is thin.  Points past detachment (the
 * baseline) measure F0 and so w.  Decided from the data: with fewer than
 * three points out of contact at the solution, or when chi2 with w held
 * 55 times higher (every point then in contact) rises by less than 3.84
 * s^2 (the profile, profile.c), w and F0 are not separable. */
static int
k2_rule(lf_fit *f, const lf_fit_result *r, int *refitted)
{
    size_t i, j;
    int few = 0;

    int all_thin = 1;

    *refitted = 0;
    if (f->imat[FIT_W] < 0)
        return 0;
    for (j = 0; j < f->ncurves; j++) {
        const fit_curve *c = &f->c[j];
        size_t nout = 0;
        if (fabs(c->data.probe.k - 2.0) > 1e-9 || c->iz0 < 0 || c->iF0 < 0)
            return 0;
        all_thin &= lf_model_get_type(c->model) == &lf_model_thin;
        for (i = 0; i < c->data.n; i++)
            nout += f->ws.ev[c->row + i].a == 0.0;
        few |= nout < 3;
    }
    /* under the thin model the parabola is exact: too few points out of
     * contact settle it; under a model of finite thickness the curve only
     * nearly is one, and the profile decides */
    if (all_thin && few)
        return 1;
    *refitted = 1;      /* the profile's refit moves f's evaluations */
    return lf_fit_w_open_above(f, r, exp(4.0));
}

void
lf_fit_say_undetermined(lf_warnings *out, int bonded_only, const char *nu_unseen_by,
                        int w_with_F0, int all_k2, int all_load)
{
    if (bonded_only)
        lf_warn(out, "only bonded curves: nu is not determined (fix nu or add a frictionless curve)");
    if (nu_unseen_by != NULL)
        lf_warn(out, "%s curves do not depend on nu: nu is not determined "
                "(add a bonded curve of the same material to measure it)", nu_unseen_by);
    if (w_with_F0 && all_k2 && all_load)
        /* the baseline before contact is there: on loading, the curve's
         * shape does not fix w, and the jump into contact that shows it is
         * not resolved */
        lf_warn(out, "k = 2 alone with free F0 and z0 cannot separate w from the force offset "
                "on loading: the curve's shape does not fix w, and the jump into contact that "
                "shows it is not resolved (fit the unload segment, whose pull-off and baseline "
                "past detachment measure it, add a probe with k != 2, or fix F0)");
    else if (w_with_F0 && all_k2)
        lf_warn(out, "k = 2 alone with free F0 and z0 cannot separate w from the force offset "
                "(record the baseline past detachment, add a probe with k != 2, or fix F0)");
    else if (w_with_F0)
        lf_warn(out, "w cannot be separated from the force offsets (record the baseline past "
                "detachment or fix F0)");
}

/* What the data cannot determine, in words. */
static void
explain(const lf_fit *f, lf_fit_result *r, const double *nullw)
{
    char buf[800];
    size_t k, j, len = 0;
    int all_k2 = 1, all_load = 1, w_null = f->imat[FIT_W] >= 0 && nullw[f->imat[FIT_W]] > 0.01;
    int F0_null = 0, other = 0, all_halfspace = 1;

    for (j = 0; j < f->ncurves; j++) {
        if (fabs(f->c[j].data.probe.k - 2.0) > 1e-9)
            all_k2 = 0;
        if (f->c[j].data.branch != LF_BRANCH_LOAD)
            all_load = 0;
        if (lf_model_get_type(f->c[j].model)->scope != LF_SCOPE_HALFSPACE)
            all_halfspace = 0;
        if (f->c[j].iF0 >= 0 && nullw[f->c[j].iF0] > 0.01)
            F0_null = 1;
    }
    if (f->imat[FIT_W] >= 0 && k2_without_baseline(f))
        w_null = F0_null = 1;
    if (f->any_bonded && !f->any_frictionless && !r->nu.determined
        && f->set.Estar.mode != LF_PARAM_FIXED && r->M.determined)
        lf_warn(&r->identifiability,
                "only bonded curves: the data fix M = Z*E* = %.4g Pa (se %.2g Pa) and w; "
                "nu is not determined (fix nu or add a frictionless curve)",
                r->M.value, r->M.se);
    lf_fit_say_undetermined(&r->identifiability,
                            f->any_bonded && !f->any_frictionless && !r->nu.determined
                                && f->set.Estar.mode != LF_PARAM_FIXED && !r->M.determined,
                            !f->any_bonded && f->set.nu.mode != LF_PARAM_FIXED
                                ? (all_halfspace ? "half-space" : "frictionless") : NULL,
                            w_null && F0_null, all_k2, all_load);
    if (r->w.upper_bound_only)
        lf_warn(&r->identifiability, "adhesion below the noise: w < %.4g J/m^2 (95%%)",
                r->w.ci95[1]);
    buf[0] = '\0';
    for (k = 0; k < f->np; k++) {
        int is_mat = (int) k == f->imat[FIT_W] || (int) k == f->imat[FIT_E]
                     || (int) k == f->imat[FIT_NU];
        int explained = ((int) k == f->imat[FIT_W] && F0_null)
                        || (f->any_bonded && !f->any_frictionless
                            && ((int) k == f->imat[FIT_E] || (int) k == f->imat[FIT_NU]));
        if (nullw[k] > 0.01 && !explained && (is_mat || !F0_null)) {
            len += (size_t) snprintf(buf + len, len < sizeof buf ? sizeof buf - len : 0,
                                     "%s%s", other ? ", " : "", r->names[k]);
            other = 1;
        }
    }
    if (other && len < sizeof buf)
        lf_warn(&r->identifiability, "not determined by the data: %s (fix some of them or add curves)", buf);
    if (r->identifiability.n == 0)
        lf_warn(&r->identifiability,
                "every free parameter is determined (smallest scaled singular value %.2g)",
                r->singular[f->np - 1]);
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
/* The thin-layer model past its limit of b/a (at `where`), in the words
 * of lf_thin_scope. */
static void
thin_strain(lf_warnings *w, double ba, const char *where, double limit)
{
    const char *words = lf_thin_scope(ba, limit);

    if (words != NULL)
        lf_warn(w, "b/a = %.3g %s: %s (limit %g)", ba, where, words, limit);
}

static void
sphere_check(const lf_probe *p, double amax, lf_warnings *w)
{
    double q = amax / p->R;

    if (fabs(p->k - 2.0) > 1e-9 || !(q > SPHERE_A_OVER_R))
        return;
    if (q < 1.0)
        lf_warn(w, "the contact radius reaches a = %.3g m, %.2g R: a sphere of radius R departs "
                "there from the paraboloid of k = 2 by %.2g%% in height (the model takes a << R)",
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
assess_curve(lf_fit *f, const double *x, size_t j, lf_fit_result *r,
             const double *nullw, const gsl_vector *res)
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
    if (c->iz0 >= 0 && nullw[c->iz0] > 0.01)
        cr->z0 = cr->z0_se = NAN;
    if (c->iF0 >= 0 && (nullw[c->iF0] > 0.01
                        || (f->imat[FIT_W] >= 0 && k2_without_baseline(f))))
        cr->F0 = cr->F0_se = NAN;
    cr->sigma = c->sigma;
    for (i = 0; i < c->data.n; i++) {
        size_t k = c->row + i;
        double e = gsl_vector_get(res, k) * c->sigma / f->ws.sqrtw[k];
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
        thin_strain(&cr->warnings, cr->b_over_a_min_contact, "at the shallowest point in contact",
                    f->set.max_b_over_a);
        if (cr->pulloff_determined)
            thin_strain(&cr->warnings, cr->b_over_a_pulloff, "at pull-off", f->set.max_b_over_a);
    }
    sphere_check(&c->data.probe, amax, &cr->warnings);
    contact_point_check(c, cr, &cr->warnings);
    consistency(f, j, res, cr);
    if (cr->downweighted > 0)
        lf_warn(&cr->warnings, "%zu points weigh less than half under the %s loss (outliers)",
                cr->downweighted, lf_loss_name(f->set.loss));
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

int
lf_fit_assess(lf_fit *f, const double *x, lf_fit_result *r, lf_error *err)
{
    size_t p = f->np, i, k, j;
    gsl_vector *res = gsl_vector_alloc(f->nres);
    gsl_vector_const_view xv = gsl_vector_const_view_array(x, p);
    double *nullw = NULL, z0, F0, slope;
    lf_material mat;
    int status, refitted;

    if (res == NULL || (nullw = calloc(p, sizeof *nullw)) == NULL
        || lf_fit_result_alloc(f, r) != LF_OK) {
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
    status = decompose(f, x, res, r, nullw);
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
    /* the k = 2 degeneracy, decided from the data (profile.c refits from
     * these values; the model's evaluations ev[] are those at x again after) */
    f->k2_degenerate = 0;
    f->k2_degenerate = k2_rule(f, r, &refitted);
    if (refitted && lf_fit_residuals(&xv.vector, f, res) != GSL_SUCCESS) {
        status = lf_fail(err, LF_ENUMERIC, "the model cannot be evaluated at the solution");
        goto done;
    }
    estimate_M(f, r, &mat, nullw, &r->M);

    /* w */
    if (f->imat[FIT_W] < 0)
        estimate_fixed(&r->w, mat.w);
    else if (nullw[f->imat[FIT_W]] > 0.01 || k2_without_baseline(f))
        estimate_undetermined(&r->w, 1);
    else {
        double se = se_of(r, f->imat[FIT_W]);
        if (mat.w < 2.0 * se) {
            estimate_undetermined(&r->w, 1);
            r->w.upper_bound_only = 1;
            r->w.ci95[0] = 0.0;
            r->w.ci95[1] = mat.w + Z95_ONE_SIDED * se;
        } else {
            estimate_positive(&r->w, mat.w, se);
        }
    }
    /* nu */
    if (f->imat[FIT_NU] >= 0 && nullw[f->imat[FIT_NU]] <= 0.01) {
        double se = se_of(r, f->imat[FIT_NU]);
        r->nu.value = mat.nu;
        r->nu.se = se;
        r->nu.ci95[0] = lf_fmax(mat.nu - Z95 * se, 0.0);
        r->nu.ci95[1] = lf_fmin(mat.nu + Z95 * se, 0.5);
        r->nu.free = 1;
        r->nu.determined = 1;
        r->nu.why = NULL;
    } else if (f->imat[FIT_NU] >= 0) {
        estimate_undetermined(&r->nu, 1);
    } else if (f->set.nu.mode == LF_PARAM_FIXED) {
        estimate_fixed(&r->nu, mat.nu);
    } else {
        estimate_undetermined(&r->nu, 0);
    }
    /* E*: bonded curves alone fix M only, unless nu is known */
    if (f->imat[FIT_E] < 0)
        estimate_fixed(&r->Estar, mat.Estar);
    else if (f->any_bonded && !f->any_frictionless && !r->nu.determined)
        /* bonded curves alone: E* = M / Z(nu) with nu unknown */
        estimate_undetermined(&r->Estar, 1);
    else if (nullw[f->imat[FIT_E]] > 0.01) {
        estimate_undetermined(&r->Estar, 1);
        r->Estar.why = "the data do not separate it from the other parameters (see what the "
                       "data determine)";
    } else
        estimate_positive(&r->Estar, mat.Estar, se_of(r, f->imat[FIT_E]));

    /* blank what is not determined, then correlations */
    for (k = 0; k < p; k++)
        if (nullw[k] > 0.01)
            for (i = 0; i < p; i++)
                r->cov[k * p + i] = r->cov[i * p + k] = NAN;
    for (i = 0; i < p; i++)
        for (k = 0; k < p; k++)
            r->corr[i * p + k] = r->cov[i * p + k]
                                 / sqrt(r->cov[i * p + i] * r->cov[k * p + k]);
    for (j = 0; j < f->ncurves; j++)
        assess_curve(f, x, j, r, nullw, res);
    agreement(f, r);
    explain(f, r, nullw);
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
    free(nullw);
    return status;
}
