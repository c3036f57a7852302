/* test_plausible.c: no silent assumption and no number no real test gives
 * (issue 35), in the library, each check of a defect the previous build
 * had:
 *  - a quantized force signal: the noise is never below the step's own
 *    rounding (step / sqrt(12)), and the step is found;
 *  - a residual shape larger than the noise is systematic whatever the
 *    correlation of neighbouring residuals (depths 1000 times too small
 *    under filtered noise were "consistent");
 *  - depths 1000 times too large or too small: the indentation past the
 *    layer's thickness, a modulus above any solid's, said with the cause;
 *  - bonded layers: no assumed nu; nearly incompressible ones only under
 *    the exact model, up to its 0.4995;
 *  - one bound of w per report: the words say the estimate's bound. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "testlib.h"
#include "layerfit.h"

#define N 300

static const lf_material mat = { 12.3e-3, 1.85e9, 0.35 };

/* Noise-free thin-layer data of one probe into depth, force. */
static void
clean_curve(const lf_probe *p, size_t n, double *depth, double *force)
{
    lf_sim_settings sim = lf_sim_settings_default();
    sim.points = n;
    sim.z0 = 15e-9;
    sim.F0 = 0.21e-6;
    t_int(lf_simulate(&sim, &lf_model_thin, &mat, 1, p, &depth, &force, NULL, NULL), LF_OK,
          "clean curve simulated");
}

static lf_fit_curve
curve_of(const lf_probe *p, size_t n, double *depth, double *force)
{
    lf_fit_curve c;
    memset(&c, 0, sizeof c);
    c.name = "test";
    c.n = n;
    c.depth = depth;
    c.force = force;
    c.probe = *p;
    c.branch = LF_BRANCH_UNLOAD;
    c.z0 = c.F0 = NAN;
    return c;
}

/* A smooth curve rounded to a step of 2% of its largest force (no other
 * noise), larger than its change from one point to the next: the
 * point-to-point departures are mostly exactly 0, and the noise was
 * estimated at 1e-12 of the largest force (chi2/dof some 1e15). */
static void
quantized(void)
{
    lf_probe p = { 3.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 };
    double depth[N], force[N], step, fbig = 0.0;
    lf_fit_settings s = lf_fit_settings_default();
    lf_fit_curve c;
    lf_fit_result r;
    lf_error err;
    size_t i;
    int st;

    clean_curve(&p, N, depth, force);
    for (i = 0; i < N; i++)
        fbig = fmax(fbig, fabs(force[i]));
    step = 2e-2 * fbig;
    for (i = 0; i < N; i++)
        force[i] = step * floor(force[i] / step + 0.5);
    c = curve_of(&p, N, depth, force);
    s.model = &lf_model_thin;
    st = lf_fit_driver(&s, 1, &c, &r, &err);
    if (!t_true(st == LF_OK || st == LF_ENOCONV, "quantized: fitted"))
        return;
    t_rel(r.curves[0].quantum, step, 1e-6, "quantized: the step found");
    t_true(r.curves[0].sigma >= step / sqrt(12.0) * (1 - 1e-12),
           "quantized: noise %.3g never below step/sqrt(12) = %.3g", r.curves[0].sigma,
           step / sqrt(12.0));
    t_true(r.chi2 / (double) r.dof < 10.0, "quantized: chi2/dof %.3g of a noise of that order",
           r.chi2 / (double) r.dof);
    t_true(t_says(&r.curves[0].warnings, "the force is quantized in steps of"),
           "quantized: said");
    lf_fit_result_free(&r);
    /* not quantized: 1% Gaussian noise, no step */
    {
        gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
        gsl_rng_set(rng, 3);
        clean_curve(&p, N, depth, force);
        for (i = 0; i < N; i++)
            force[i] += 0.01 * fbig * gsl_ran_gaussian(rng, 1.0);
        gsl_rng_free(rng);
        st = lf_fit_driver(&s, 1, &c, &r, &err);
        t_true(st == LF_OK && r.curves[0].quantum == 0.0, "noisy: no step found");
        lf_fit_result_free(&r);
    }
}

/* Depths 1000 times too small (values in um under a nm header) of a 1 um
 * layer, with filtered noise (a moving average of 20 points): the exact
 * model's E* is hundreds of TPa, the residuals a smooth shape 10 times the
 * noise; the correlation time (hundreds of points) made the noise at that
 * lag so large that the curve read "consistent". */
static void
shape_under_correlation(void)
{
    enum { M = 1000, W = 20 };
    lf_probe p = { 2.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 };
    double *depth = malloc(M * sizeof *depth), *force = malloc(M * sizeof *force);
    double *g = malloc((M + W) * sizeof *g), fbig = 0.0;
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    lf_fit_settings s = lf_fit_settings_default();
    lf_fit_curve c;
    lf_fit_result r;
    lf_error err;
    size_t i, k;
    int st;

    clean_curve(&p, M, depth, force);
    gsl_rng_set(rng, 7);
    for (i = 0; i < M + W; i++)
        g[i] = gsl_ran_gaussian(rng, 1.0);
    for (i = 0; i < M; i++)
        fbig = fmax(fbig, fabs(force[i]));
    for (i = 0; i < M; i++) {
        double e = 0.0;
        for (k = 0; k < W; k++)
            e += g[i + k];
        force[i] += 1e-3 * fbig * e / sqrt((double) W);
        depth[i] *= 1e-3;
    }
    c = curve_of(&p, M, depth, force);
    s.model = &lf_model_exact;
    st = lf_fit_driver(&s, 1, &c, &r, &err);
    if (t_true(st == LF_OK || st == LF_ENOCONV, "shape: fitted (%s)", st ? err.msg : "ok")) {
        t_true(r.curves[0].corr_time > 20, "shape: the misfit reads as correlated (%.3g)",
               r.curves[0].corr_time);
        t_true(r.curves[0].shape > 1.0, "shape: %.3g times the noise", r.curves[0].shape);
        t_int(r.curves[0].consistent, 0, "shape: not consistent");
        t_true(r.curves[0].agreement < 2, "shape: systematic, not within the noise");
        t_true(t_says(&r.warnings, "is stiffer than any solid"), "shape: E* = %.3g Pa said",
               r.Estar.value);
        lf_fit_result_free(&r);
    }
    /* the same noise on the right depths: consistent */
    clean_curve(&p, M, depth, force);
    for (i = 0; i < M; i++) {
        double e = 0.0;
        for (k = 0; k < W; k++)
            e += g[i + k];
        force[i] += 1e-3 * fbig * e / sqrt((double) W);
    }
    s.model = &lf_model_thin;
    st = lf_fit_driver(&s, 1, &c, &r, &err);
    if (t_int(st, LF_OK, "filtered noise: fitted")) {
        t_true(r.curves[0].shape < 1.0, "filtered noise: shape %.3g", r.curves[0].shape);
        t_int(r.curves[0].consistent, 1, "filtered noise: consistent");
        t_true(!t_says(&r.warnings, "than any solid"), "filtered noise: no modulus warning");
        lf_fit_result_free(&r);
    }
    gsl_rng_free(rng);
    free(depth);
    free(force);
    free(g);
}

/* Depths 1000 times too large (nm values under a um header): 50 um into a
 * 1 um layer. */
static void
too_deep(void)
{
    lf_probe p = { 2.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 };
    double depth[N], force[N];
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    lf_fit_settings s = lf_fit_settings_default();
    lf_fit_curve c;
    lf_fit_result r;
    lf_error err;
    size_t i;

    clean_curve(&p, N, depth, force);
    gsl_rng_set(rng, 5);
    for (i = 0; i < N; i++) {
        depth[i] *= 1e3;
        force[i] += 1e-5 * gsl_ran_gaussian(rng, 1.0);
    }
    gsl_rng_free(rng);
    c = curve_of(&p, N, depth, force);
    s.model = &lf_model_thin;
    if (t_int(lf_fit_driver(&s, 1, &c, &r, &err), LF_OK, "too deep: fitted")) {
        t_true(t_says(&r.curves[0].warnings, "times the layer's thickness"),
               "too deep: the indentation past the layer said");
        t_true(t_says(&r.curves[0].warnings, "1000 times too large"), "too deep: the cause said");
        lf_fit_result_free(&r);
    }
}

/* Bonded layers: no default nu; nu = 0.4999 and the largest double below
 * 0.5 refused; 0.4995 only under the exact model. */
static void
bonded_nu(void)
{
    lf_probe p = { 3.0, 1e-3, 1e-6, LF_BASE_BONDED, LF_TIP_POWER, 0.0, 0.0 };
    double depth[N], force[N];
    lf_fit_settings s = lf_fit_settings_default();
    lf_choose_settings cs = lf_choose_settings_default();
    lf_fit_curve c;
    lf_fit_result r;
    lf_error err;
    lf_fit *f;

    clean_curve(&p, N, depth, force);
    c = curve_of(&p, N, depth, force);
    s.model = &lf_model_thin;
    t_int(lf_fit_driver(&s, 1, &c, &r, &err), LF_EDATA, "bonded, no nu: refused");
    t_contains(err.msg, "needs Poisson's ratio nu", "bonded, no nu: says why");
    s.nu.mode = LF_PARAM_FIXED;
    s.nu.value = 0.4999;
    f = lf_fit_alloc(&s, 1, &c, &err);
    t_true(f == NULL && err.status == LF_EINVAL, "bonded nu 0.4999, thin: refused");
    t_contains(err.msg, "nearly incompressible", "bonded nu 0.4999: says why");
    lf_fit_free(f);
    s.nu.value = nextafter(0.5, 0.0);
    f = lf_fit_alloc(&s, 1, &c, &err);
    t_true(f == NULL, "bonded nu 0.49999999999999994: refused");
    t_contains(err.msg, "0.49999999999999994", "bonded nu 0.49999999999999994: named in full");
    lf_fit_free(f);
    /* the model choice sends 0.4995 to the exact model, which refuses more */
    s.nu.value = 0.4995;
    f = lf_fit_alloc(&s, 1, &c, &err);
    t_true(f == NULL, "bonded nu 0.4995, thin: refused");
    lf_fit_free(f);
    c.model = &lf_model_exact;
    f = lf_fit_alloc(&s, 1, &c, &err);
    t_true(f != NULL, "bonded nu 0.4995, exact: taken");
    lf_fit_free(f);
    c.model = NULL;
    s.nu.value = 0.4999;
    t_int(lf_fit_choose_driver(&s, &cs, 1, &c, &r, &err), LF_EINVAL,
          "bonded nu 0.4999, auto: refused (exact ends at 0.4995)");
    t_contains(err.msg, "the exact model holds up to nu = 0.4995", "bonded nu 0.4999, auto: says so");
}

int
main(void)
{
    gsl_set_error_handler_off();
    lf_cache_set_enabled(getenv("LAYERFIT_TEST_CACHE") != NULL);
    quantized();
    shape_under_correlation();
    too_deep();
    bonded_nu();
    return t_summary();
}
