/* cli/coverage.c: `layerfit bench --coverage`: do the 95% intervals hold?
 *
 * For each scene, N seeded draws of thin-layer data with Gaussian noise are
 * fitted (the thin-layer model, as `layerfit fit --model thin` does), the
 * intervals made as the command makes them (linear, or profile likelihood
 * where the curvature says so: lf_fit_profile), and counted: how often the
 * 95% interval of w, E* and nu holds the truth (the target 93-97% over 200
 * seeds: the binomial sd of the rate is 1.5%), how often the linear interval
 * alone would have, and the RMS error of ln w, ln E* (and nu) over the
 * Cramer-Rao bound at the truth (lf_crb with the same nuisance parameters
 * free).  A fit not converged, or a value not determined, counts as not
 * covered unless its one-sided bound holds the truth. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

#define Z95 1.959963984540054
#define MAXCC 3

typedef struct {
    const char *name, *what;
    size_t ncurves;
    lf_probe probe[MAXCC];
    lf_material truth;
    double past_c, delta_max, noise;
    int free_offsets;
} cov_scene;

static const cov_scene cov_scenes[] = {
    { "paper-offsets", "the paper's two probes (k = 2, 3; R = 1 mm; b = 1 um; frictionless; "
      "w = 10 mJ/m^2, E* = 1 GPa), delta -0.9c..50 nm, z0 and F0 free, 1% noise",
      2, { { 2.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 }, { 3.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 } },
      { 10e-3, 1e9, 0.3 }, 0.9, 50e-9, 0.01, 1 },
    { "mixed-nu", "k = 2 frictionless + k = 3 bonded, nu = 0.3 determined; the paper's w, E*, "
      "R, b; z0, F0 known, 1% noise",
      2, { { 2.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 }, { 3.0, 1e-3, 1e-6, LF_BASE_BONDED, LF_TIP_POWER, 0.0, 0.0 } },
      { 10e-3, 1e9, 0.3 }, 0.9, 50e-9, 0.01, 0 },
    { "soft-coating", "k = 2, 3; R = 5 mm; b = 20 um; w = 40 mJ/m^2, E* = 2 MPa; delta "
      "-1.2c..3 um; z0 and F0 free, 1% noise",
      2, { { 2.0, 5e-3, 20e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 }, { 3.0, 5e-3, 20e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 } },
      { 40e-3, 2e6, 0.3 }, 1.2, 3e-6, 0.01, 1 },
};
#define NCOV (sizeof cov_scenes / sizeof cov_scenes[0])

typedef struct {
    size_t n, conv, hit[3], hit_wald[3], profiled[3], counted[3];
    double se2[3];          /* sum of squared errors: ln w, ln E*, nu */
    double crb[3];          /* the bound's sd */
    int have[3];
} cov_tally;

/* Does the estimate's interval hold the truth t?  (log: w, E*) */
static int
covers(const lf_fit_estimate *e, double t)
{
    if (e->upper_bound_only)
        return t <= e->ci95[1];
    if (!e->determined)
        return isfinite(e->ci95[0]) && isnan(e->ci95[1]) && t >= e->ci95[0];
    return t >= e->ci95[0] && t <= e->ci95[1];
}

static int
covers_wald(const lf_fit_estimate *e, double t, int logscale)
{
    if (!e->determined || !(e->se > 0))
        return 0;
    if (logscale) {
        double s = e->se / e->value;
        return fabs(log(t / e->value)) <= Z95 * s;
    }
    return fabs(t - e->value) <= Z95 * e->se;
}

int
cli_probes_free_nu(const lf_probe *p, size_t n)
{
    size_t j;
    int fr = 0, bo = 0;
    for (j = 0; j < n; j++) {
        if (p[j].base == LF_BASE_BONDED)
            bo = 1;
        else
            fr = 1;
    }
    return fr && bo;
}

/* Run scene s over nseeds seeds into t. */
static void
run_scene(const cov_scene *s, size_t nseeds, size_t points, int calibrate, cov_tally *t)
{
    double *depth[MAXCC], *force[MAXCC], *delta[MAXCC], sigma[MAXCC], z0[MAXCC], F0[MAXCC];
    lf_model *model[MAXCC];
    lf_fit_curve fc[MAXCC];
    lf_design_curve dc[MAXCC];
    lf_crb_result crb;
    lf_error err;
    size_t j, i, seed;
    int free_nu = cli_probes_free_nu(s->probe, s->ncurves);

    memset(t, 0, sizeof *t);
    for (j = 0; j < s->ncurves; j++) {
        lf_pulloff po;
        model[j] = lf_model_alloc(&lf_model_thin, &s->probe[j], &err);
        depth[j] = malloc(points * sizeof(double));
        force[j] = malloc(points * sizeof(double));
        delta[j] = malloc(points * sizeof(double));
        if (model[j] == NULL || !depth[j] || !force[j] || !delta[j]
            || lf_model_pulloff(model[j], &s->truth, &po, &err) != LF_OK)
            cli_die(CLI_EXIT_FAIL, "bench: %s", err.msg);
        /* offsets of the kind the bench uses: a third of c, 1.3% of the force */
        z0[j] = s->free_offsets ? 0.37 * po.c : 0.0;
        F0[j] = 0.0;
    }
    for (seed = 0; seed < nseeds; seed++) {
        lf_sim_settings ss = lf_sim_settings_default();
        lf_fit_settings fs = lf_fit_settings_default();
        lf_fit_result r;
        int st;

        ss.points = points;
        ss.delta_max = s->delta_max;
        ss.past_c = s->past_c;
        ss.noise = s->noise;
        ss.seed = 1000u + (unsigned long) seed;
        /* one offset for all curves (lf_simulate adds the same z0, F0) */
        ss.z0 = z0[0];
        ss.F0 = 0.0;
        if (lf_simulate(&ss, &lf_model_thin, &s->truth, s->ncurves, s->probe, depth, force,
                        sigma, &err) != LF_OK)
            cli_die(CLI_EXIT_FAIL, "bench: %s", err.msg);
        for (j = 0; j < s->ncurves; j++) {
            double fbig = 0.0;
            for (i = 0; i < points; i++)
                fbig = fmax(fbig, fabs(force[j][i]));
            F0[j] = s->free_offsets ? 0.013 * fbig : 0.0;
            for (i = 0; i < points; i++) {
                delta[j][i] = depth[j][i] - ss.z0;
                force[j][i] += F0[j];
            }
            memset(&fc[j], 0, sizeof fc[j]);
            fc[j].n = points;
            fc[j].depth = depth[j];
            fc[j].force = force[j];
            fc[j].probe = s->probe[j];
            fc[j].branch = LF_BRANCH_UNLOAD;
            fc[j].z0 = s->free_offsets ? NAN : ss.z0;
            fc[j].F0 = s->free_offsets ? NAN : 0.0;
            dc[j].model = model[j];
            dc[j].branch = LF_BRANCH_UNLOAD;
            dc[j].n = points;
            dc[j].delta = delta[j];
            dc[j].sigma = sigma[j];
            dc[j].free_z0 = dc[j].free_F0 = s->free_offsets;
        }
        if (seed == 0 && lf_crb(dc, s->ncurves, &s->truth, free_nu, &crb, &err) == LF_OK) {
            t->crb[0] = crb.sd_logw;
            t->crb[1] = crb.sd_logE;
            t->crb[2] = free_nu ? crb.sd_nu : NAN;
        }
        fs.model = &lf_model_thin;
        st = lf_fit_driver(&fs, s->ncurves, fc, &r, &err);
        t->n++;
        if (st != LF_OK && st != LF_ENOCONV)
            continue;
        t->conv += st == LF_OK;
        {
            const lf_fit_estimate *e[3] = { &r.w, &r.Estar, &r.nu };
            const double truth[3] = { s->truth.w, s->truth.Estar, s->truth.nu };
            int k, wald[3];
            for (k = 0; k < 3; k++)
                wald[k] = covers_wald(e[k], truth[k], k < 2);
            lf_fit_profile(&fs, s->ncurves, fc, &r,
                           LF_PROFILE_CHECK | (calibrate ? LF_PROFILE_CALIBRATE : 0), NULL);
            for (k = 0; k < 3; k++) {
                if (k == 2 && !free_nu)
                    continue;
                t->have[k] = 1;
                t->counted[k]++;
                t->hit[k] += st == LF_OK && covers(e[k], truth[k]);
                t->hit_wald[k] += st == LF_OK && wald[k];
                t->profiled[k] += e[k]->interval_method != NULL
                                  && (strcmp(e[k]->interval_method, "profile likelihood") == 0
                                      || strcmp(e[k]->interval_method, LF_INTERVAL_JUMP) == 0);
                if (isfinite(e[k]->value)) {
                    double d = k < 2 ? log(e[k]->value / truth[k]) : e[k]->value - truth[k];
                    t->se2[k] += d * d;
                }
            }
        }
        lf_fit_result_free(&r);
    }
    for (j = 0; j < s->ncurves; j++) {
        lf_model_free(model[j]);
        free(depth[j]);
        free(force[j]);
        free(delta[j]);
    }
}

int
cli_coverage(size_t nseeds, const char *scene_name, int calibrate)
{
    static const char *pname[3] = { "w", "E*", "nu" };
    size_t si;
    int any = 0;

    printf("coverage of 95%% intervals over %zu seeds (target 93-97%%; RMS error over the "
           "Cramer-Rao bound, target <= 1.2 where the bound is below 20%%)%s\n", nseeds,
           calibrate ? "; profile thresholds calibrated by the bootstrap" : "");
    for (si = 0; si < NCOV; si++) {
        const cov_scene *s = &cov_scenes[si];
        cov_tally t;
        int k;
        if (scene_name != NULL && strcmp(scene_name, s->name) != 0)
            continue;
        any = 1;
        run_scene(s, nseeds, 300, calibrate, &t);
        printf("\n%s: %s\n  converged %zu of %zu\n", s->name, s->what, t.conv, t.n);
        for (k = 0; k < 3; k++) {
            double rms;
            if (!t.have[k] || t.counted[k] == 0)
                continue;
            rms = sqrt(t.se2[k] / (double) t.counted[k]);
            printf("  %-3s covered %5.1f%% (linear alone %5.1f%%; profile used in %zu), "
                   "RMS error %.3g = %.2f x the bound %.3g%s\n", pname[k],
                   100.0 * (double) t.hit[k] / (double) t.counted[k],
                   100.0 * (double) t.hit_wald[k] / (double) t.counted[k], t.profiled[k], rms,
                   rms / t.crb[k], t.crb[k], k < 2 ? " (of ln)" : "");
        }
        fflush(stdout);
    }
    if (!any)
        cli_die(CLI_EXIT_USAGE, "bench: --coverage knows the scenes paper-offsets, mixed-nu, "
                "soft-coating (got '%s')", scene_name);
    return CLI_EXIT_OK;
}
