/* test_population.c: many curves of one material that differ from spot to
 * spot (issue 35).  Twelve sphere curves (k = 2, R = 1 mm, a 1 um
 * frictionless layer, 200 points to 15 nm with the baseline recorded to
 * 4 c past detachment, 1% noise, z0 and F0 free: each curve alone fixes w
 * to some 3% and E* to 0.7%), each of its own spot: w and E* drawn
 * log-normal about w = 12.3 mJ/m^2 and E* = 1.85 GPa with an SD of 10%
 * (of ln w, ln E*), over 200 seeds, fitted as `layerfit fit --batch`
 * fits a sample (lf_fit_joint).  Asserted:
 *  - the population mean's 95% interval covers the population's centre
 *    (the geometric mean, exp of the mean of ln) in 93-97% of the seeds,
 *    for w and for E*;
 *  - the RMS error of tau (the SD of ln w and of ln E* between spots,
 *    REML) is within 25% of tau;
 *  - the curves are found to disagree (p_homogeneous < 0.05) in nearly
 *    every seed.
 * The same twelve curves of one spot (no spread):
 *  - no heterogeneity found in about 95% of the seeds (92-98%);
 *  - the joint fit's intervals stay within 5% of those the fit gave before
 *    the joint fit had a second start from the pooled single fits
 *    (lf_fit_driver alone), in the median over the seeds.
 * An argument sets the seeds (default 200). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <gsl/gsl_statistics_double.h>

#include "testlib.h"
#include "layerfit.h"

#define NC 12
#define NPTS 200
#define SPREAD 0.10

static const lf_material centre = { 12.3e-3, 1.85e9, 0.35 };

typedef struct {
    double *depth[NC], *force[NC];
    lf_fit_curve curve[NC];
    lf_probe probe;
} spots;

static void
spots_init(spots *s)
{
    size_t j;
    s->probe.k = 2.0;
    s->probe.R = 1e-3;
    s->probe.b = 1e-6;
    s->probe.base = LF_BASE_FRICTIONLESS;
    for (j = 0; j < NC; j++) {
        s->depth[j] = malloc(NPTS * sizeof(double));
        s->force[j] = malloc(NPTS * sizeof(double));
        memset(&s->curve[j], 0, sizeof s->curve[j]);
        s->curve[j].name = "spot";
        s->curve[j].n = NPTS;
        s->curve[j].depth = s->depth[j];
        s->curve[j].force = s->force[j];
        s->curve[j].probe = s->probe;
        s->curve[j].branch = LF_BRANCH_UNLOAD;
        s->curve[j].z0 = s->curve[j].F0 = NAN;
    }
}

static void
spots_free(spots *s)
{
    size_t j;
    for (j = 0; j < NC; j++) {
        free(s->depth[j]);
        free(s->force[j]);
    }
}

/* Twelve curves of seed's spots (spread: SD of ln w and ln E*). */
static int
simulate(spots *s, unsigned long seed, double spread)
{
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    lf_sim_settings sim = lf_sim_settings_default();
    size_t j;
    int st = LF_OK;

    gsl_rng_set(rng, seed);
    sim.points = NPTS;
    sim.noise = 0.01;
    sim.z0 = 15e-9;
    sim.F0 = 0.21e-6;
    sim.past_c = 4.0;
    sim.delta_max = 15e-9;
    for (j = 0; j < NC && st == LF_OK; j++) {
        lf_material m = centre;
        double *d = s->depth[j], *f = s->force[j];
        m.w *= exp(spread * gsl_ran_gaussian(rng, 1.0));
        m.Estar *= exp(spread * gsl_ran_gaussian(rng, 1.0));
        sim.seed = seed * 100 + j;
        st = lf_simulate(&sim, &lf_model_thin, &m, 1, &s->probe, &d, &f, NULL, NULL);
    }
    gsl_rng_free(rng);
    return st;
}

static int
cmp_double(const void *a, const void *b)
{
    double x = *(const double *) a, y = *(const double *) b;
    return (x > y) - (x < y);
}

int
main(int argc, char **argv)
{
    size_t nseed = argc > 1 ? (size_t) strtoul(argv[1], NULL, 10) : 200, i, m;
    lf_fit_settings set = lf_fit_settings_default();
    spots s;
    size_t cover[2] = { 0, 0 }, found = 0, done = 0, calm = 0, hdone = 0;
    double tau_err2 = 0.0, tau_w_err2 = 0.0, *ratio = malloc(2 * nseed * sizeof *ratio);
    size_t nratio = 0;

    gsl_set_error_handler_off();
    set.model = &lf_model_thin;
    spots_init(&s);
    /* spots that differ */
    for (i = 0; i < nseed; i++) {
        lf_fit_result r;
        lf_error err;
        const lf_heterogeneity *h;
        int st;
        if (simulate(&s, 1000 + i, SPREAD) != LF_OK)
            continue;
        st = lf_fit_joint(&set, NULL, NC, s.curve, LF_PROFILE_SCREEN | LF_PROFILE_REPORT_LINEAR,
                          &r, &err);
        if (st != LF_OK && st != LF_ENOCONV) {
            printf("seed %zu: %s\n", 1000 + i, err.msg);
            continue;
        }
        h = &r.heterogeneity;
        if (h->w.n >= 2 && h->Estar.n >= 2) {
            done++;
            cover[0] += h->w.population_ci95[0] <= centre.w && centre.w <= h->w.population_ci95[1];
            cover[1] += h->Estar.population_ci95[0] <= centre.Estar
                        && centre.Estar <= h->Estar.population_ci95[1];
            tau_err2 += (h->Estar.tau_rel - SPREAD) * (h->Estar.tau_rel - SPREAD);
            tau_w_err2 += (h->w.tau_rel - SPREAD) * (h->w.tau_rel - SPREAD);
            found += h->p_homogeneous < 0.05;
        }
        lf_fit_result_free(&r);
    }
    printf("spread 10%%: %zu of %zu seeds analysed; coverage w %.3f, E* %.3f; RMS error of "
           "tau: w %.3f, E* %.3f of tau; heterogeneity found in %.3f\n", done, nseed,
           (double) cover[0] / (double) done, (double) cover[1] / (double) done,
           sqrt(tau_w_err2 / (double) done) / SPREAD, sqrt(tau_err2 / (double) done) / SPREAD,
           (double) found / (double) done);
    t_true(done >= nseed - nseed / 50, "spread: analysed in %zu of %zu seeds", done, nseed);
    for (m = 0; m < 2; m++) {
        double c = (double) cover[m] / (double) done;
        t_true(c >= 0.93 && c <= 0.97, "spread: the population interval of %s covers %.3f "
               "(want 0.93-0.97)", m ? "E*" : "w", c);
    }
    t_true(sqrt(tau_err2 / (double) done) <= 0.25 * SPREAD,
           "spread: RMS error of tau(E*) %.3g within 25%% of tau %.3g",
           sqrt(tau_err2 / (double) done), SPREAD);
    t_true(sqrt(tau_w_err2 / (double) done) <= 0.25 * SPREAD,
           "spread: RMS error of tau(w) %.3g within 25%% of tau %.3g",
           sqrt(tau_w_err2 / (double) done), SPREAD);
    t_true((double) found >= 0.95 * (double) done, "spread: found in %zu of %zu", found, done);

    /* one spot: no spread */
    for (i = 0; i < nseed; i++) {
        lf_fit_result r, today;
        lf_error err;
        int st, k;
        if (simulate(&s, 5000 + i, 0.0) != LF_OK)
            continue;
        st = lf_fit_joint(&set, NULL, NC, s.curve, LF_PROFILE_CHECK, &r, &err);
        if (st != LF_OK && st != LF_ENOCONV)
            continue;
        if (lf_fit_driver(&set, NC, s.curve, &today, &err) == LF_OK
            && lf_fit_profile(&set, NC, s.curve, &today, LF_PROFILE_CHECK, &err) == LF_OK
            && r.converged && today.converged) {
            const lf_fit_estimate *a[2] = { &r.w, &r.Estar }, *b[2] = { &today.w, &today.Estar };
            hdone++;
            calm += r.heterogeneity.p_homogeneous >= 0.05;
            for (k = 0; k < 2; k++)
                if (a[k]->determined && b[k]->determined)
                    ratio[nratio++] = log(a[k]->ci95[1] / a[k]->ci95[0])
                                      / log(b[k]->ci95[1] / b[k]->ci95[0]);
        }
        lf_fit_result_free(&r);
        lf_fit_result_free(&today);
    }
    qsort(ratio, nratio, sizeof *ratio, cmp_double);
    printf("one spot: %zu seeds; no heterogeneity found in %.3f; interval width against the "
           "fit alone: median %.4f, 5%% %.4f, 95%% %.4f\n", hdone,
           (double) calm / (double) hdone, nratio ? ratio[nratio / 2] : NAN,
           nratio ? ratio[nratio / 20] : NAN, nratio ? ratio[nratio - 1 - nratio / 20] : NAN);
    t_true(hdone >= nseed - nseed / 50, "one spot: %zu of %zu seeds", hdone, nseed);
    t_true((double) calm >= 0.92 * (double) hdone && (double) calm <= 0.98 * (double) hdone,
           "one spot: no heterogeneity in %zu of %zu (want about 95%%)", calm, hdone);
    t_true(nratio > 0 && fabs(ratio[nratio / 2] - 1.0) <= 0.05,
           "one spot: the intervals within 5%% of the fit alone's (median ratio %.4f)",
           nratio ? ratio[nratio / 2] : NAN);
    free(ratio);
    spots_free(&s);
    return t_summary();
}
