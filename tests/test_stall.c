/* test_stall.c: the verdict at the end of a fit (fit/verdict.c), forced
 * directly.  A fit stopped far from a minimum ends not converged and says
 * why in words: by its iteration budget (one iteration), and when the
 * solver's own tests claim convergence after one step (a step tolerance so
 * loose that any step passes) while the Gauss-Newton step still lowers
 * chi2 by far more than the noise.  A fit started at a minimum ends
 * converged there. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fit.h"
#include "scene.h"
#include "testlib.h"

/* A reason in words: a sentence, not a code. */
static int
in_words(const char *why)
{
    size_t i, letters = 0;
    for (i = 0; why[i]; i++)
        letters += (why[i] >= 'a' && why[i] <= 'z') || why[i] == ' ';
    return letters >= 20 && strstr(why, "not converged") != NULL;
}

static scene
stall_scene(void)
{
    scene s = scene_default("stall");
    scene_add(&s, 2, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
    scene_add(&s, 3, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
    s.sim.noise = 0.005;
    s.fit.model = &lf_model_thin;
    return s;
}

/* A fit (internal API, as the profile refits do) from the origin: the
 * material mat and every curve's offsets from the result ref (z0 shifted
 * by dz0 of its depth span), no second start; the verdict's result. */
static int
fit_from(scene *s, const lf_fit_settings *set, const lf_material *mat, const lf_fit_result *ref,
         double dz0, lf_fit_result *r)
{
    lf_fit *g = lf_fit_alloc(set, s->n, s->curve, NULL);
    size_t j;
    int st;

    if (g == NULL)
        return LF_EINVAL;
    g->mat = *mat;
    for (j = 0; j < s->n; j++) {
        g->c[j].z0 = ref->curves[j].z0 + dz0 * g->c[j].L;
        g->c[j].F0 = ref->curves[j].F0;
        g->c[j].slope = 0.0;
    }
    lf_fit_set_origin(g);
    st = lf_fit_solve(g, NULL, r, NULL);
    lf_fit_free(g);
    return st;
}

/* chi2 after the plain solver (no contact-edge scan, no second start) is
 * run with the default settings from the solution of r: the lowest chi2
 * of the basin r claims to sit at the bottom of. */
static double
chi2_continued(scene *s, const lf_fit_result *r)
{
    lf_fit *g = lf_fit_alloc(&s->fit, s->n, s->curve, NULL);
    fit_run run;
    size_t j;
    double chi2 = NAN;

    if (g == NULL)
        return NAN;
    g->mat = (lf_material) { r->value[0], r->value[1], s->mat.nu };
    for (j = 0; j < s->n; j++) {
        g->c[j].z0 = r->curves[j].z0;
        g->c[j].F0 = r->curves[j].F0;
        g->c[j].slope = 0.0;
    }
    for (j = 0; j < g->ndata; j++)
        g->ws.sqrtw[j] = 1.0;
    lf_fit_set_origin(g);
    gsl_vector_set_all(g->ws.x, 1.0);
    memset(&run, 0, sizeof run);
    if (lf_fit_iterate(g, g->ws.x, 0, &run, NULL) == LF_OK)
        chi2 = 2.0 * lf_fit_cost(g, g->ws.x, g->ws.r);
    lf_fit_free(g);
    return chi2;
}

/* An honest end of fit r (status st): either converged at a minimum (the
 * solver continued from there lowers chi2 by no more than 2 se^2), or not
 * converged with a reason in words.  1 when so. */
static int
honest(scene *s, unsigned long seed, int k, const char *what, int st, lf_fit_result *r)
{
    double s2 = r->chi2 / (double) r->dof, c;
    int ok;

    if (!r->converged) {
        ok = st == LF_ENOCONV && in_words(r->stop_reason);
        if (!ok)
            printf("seed %lu start %d, %s: not converged, no reason in words: %s\n", seed, k,
                   what, r->stop_reason);
        return ok;
    }
    c = chi2_continued(s, r);
    ok = st == LF_OK && r->chi2 - c <= 2.0 * s2;
    if (!ok)
        printf("seed %lu start %d, %s: converged (%s) at chi2 %.6g, but the solver continued "
               "from there reaches %.6g\n", seed, k, what, r->stop_reason, r->chi2, c);
    return ok;
}

/* lf_fit_profile on a fit r that did not converge: no refit, each free
 * estimate's linear interval kept and marked LF_INTERVAL_AT_STOP (a
 * profile's rises from a point that is no minimum measure nothing). */
static int
profile_skipped(scene *s, const lf_fit_settings *set, lf_fit_result *r)
{
    lf_fit_estimate *e[3] = { &r->w, &r->Estar, &r->nu };
    double lo[3], hi[3];
    lf_error err;
    int k, ok;

    for (k = 0; k < 3; k++) {
        lo[k] = e[k]->ci95[0];
        hi[k] = e[k]->ci95[1];
    }
    ok = lf_fit_profile(set, s->n, s->curve, r, LF_PROFILE_ALWAYS, &err) == LF_OK
         && r->profile_fits == 0;
    for (k = 0; k < 3; k++)
        if (e[k]->free)
            ok = ok && e[k]->interval_method != NULL
                 && strcmp(e[k]->interval_method, LF_INTERVAL_AT_STOP) == 0
                 && e[k]->ci95[0] == lo[k] && e[k]->ci95[1] == hi[k];
    return ok;
}

/* Far from a minimum: four starts (w, E* and z0 moved from the solution)
 * of five data sets.  With one iteration, the fit ends not converged and
 * says why, unless it reached a minimum (w driven to zero is one in ln w).
 * With also a step test that any step passes (the solver then claims
 * convergence after one step), the verdict must reject some claims as a
 * stall ("stalled away from a minimum": without the verdict, none would
 * be), every rejected one saying why in words. */
static void
stalled_fits_say_so(void)
{
    static const double fw[4] = { 5.0, 0.2, 5.0, 20.0 }, fE[4] = { 1.2, 0.5, 2.0, 3.0 };
    static const double fz[4] = { 0.2, -0.05, 0.05, 0.1 };
    scene s = stall_scene();
    unsigned long seed;
    size_t budget_ok = 0, claim_ok = 0, claim_n = 0, stalled = 0, iters_said = 0, n = 0;
    size_t no_profile = 0, no_profile_ok = 0;
    int k;

    for (seed = 1; seed <= 5; seed++) {
        lf_fit_result ref;
        lf_error err;

        t_int(scene_fit(&s, seed, &ref, &err), LF_OK, "stall: the reference fit converges");
        for (k = 0; k < 4; k++) {
            lf_fit_settings set = s.fit;
            lf_material far = { fw[k] * ref.w.value, fE[k] * ref.Estar.value, s.mat.nu };
            lf_fit_result r;
            int st;

            n++;
            set.max_iter = 1;
            st = fit_from(&s, &set, &far, &ref, fz[k], &r);
            if (st == LF_OK || st == LF_ENOCONV) {
                budget_ok += honest(&s, seed, k, "one iteration", st, &r);
                iters_said += !r.converged && r.stop == LF_STOP_ITERATIONS
                              && strstr(r.stop_reason, "iterations per solve reached") != NULL;
                if (!r.converged) {
                    no_profile++;
                    no_profile_ok += profile_skipped(&s, &set, &r);
                }
                lf_fit_result_free(&r);
            }
            /* the solver's step test passes after any one step */
            set.xtol = 1e3;
            st = fit_from(&s, &set, &far, &ref, fz[k], &r);
            if (st != LF_OK && st != LF_ENOCONV) {
                printf("seed %lu start %d: status %d\n", seed, k, st);
                continue;
            }
            /* not converged: said why; converged: noted when the solver
             * continued from there still goes lower (a creep the verdict
             * does not see: printed, not asserted) */
            if (!r.converged) {
                claim_n++;
                claim_ok += honest(&s, seed, k, "claimed convergence", st, &r);
            } else {
                (void) honest(&s, seed, k, "claimed convergence (note)", st, &r);
            }
            stalled += !r.converged && strstr(r.stop_reason, "stalled away from a minimum");
            lf_fit_result_free(&r);
        }
        lf_fit_result_free(&ref);
    }
    t_int((long) budget_ok, (long) n, "stall: one iteration ends at a minimum, or not "
          "converged with a reason");
    t_int((long) claim_ok, (long) claim_n, "stall: a claimed convergence the verdict rejects "
          "says why in words");
    t_true(iters_said > 0, "stall: 'iterations per solve reached' said (%zu of %zu)", iters_said, n);
    t_true(no_profile > 0 && no_profile_ok == no_profile, "stall: no profile of a fit that did "
           "not converge: its linear intervals kept and marked so (%zu of %zu)", no_profile_ok,
           no_profile);
    t_true(stalled > 0, "stall: 'stalled away from a minimum' said (%zu of %zu)", stalled, n);
    scene_free(&s);
}

/* At a minimum: started at a converged fit's solution, with a budget of
 * two iterations, the fit is converged and its chi2 is the minimum's. */
static void
minimum_is_converged(void)
{
    scene s = stall_scene();
    unsigned long seed;
    size_t good = 0, n = 5;

    for (seed = 11; seed <= 10 + n; seed++) {
        lf_fit_result ref, r;
        lf_error err;
        lf_fit_settings set = s.fit;
        lf_material at;
        int st;

        t_int(scene_fit(&s, seed, &ref, &err), LF_OK, "minimum: the reference fit converges");
        at = (lf_material) { ref.w.value, ref.Estar.value, s.mat.nu };
        set.max_iter = 2;
        st = fit_from(&s, &set, &at, &ref, 0.0, &r);
        if (st == LF_OK && r.converged && fabs(r.chi2 - ref.chi2) <= 1e-6 * ref.chi2)
            good++;
        else
            printf("seed %lu, at the minimum: status %d, chi2 %.8g (minimum %.8g): %s\n", seed,
                   st, r.chi2, ref.chi2, r.stop_reason);
        if (st == LF_OK || st == LF_ENOCONV)
            lf_fit_result_free(&r);
        lf_fit_result_free(&ref);
    }
    t_int((long) good, (long) n, "minimum: a fit started there ends converged at it");
    scene_free(&s);
}

int
main(void)
{
    stalled_fits_say_so();
    minimum_is_converged();
    return t_summary();
}
