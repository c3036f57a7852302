/* test_design.c: experiment design (fit/design.c).
 *
 *  1. The predicted errors against an independent computation of the
 *     Cramer-Rao bound (lf_crb on the same indentations and noise).
 *  2. What is and is not determined, in the fitter's words.
 *  3. The predictions against the Monte Carlo spread of real fits: curves
 *     simulated with the exact layer model (lf_simulate), fitted with the
 *     automatic model choice (lf_fit_choose_driver), 200 seeds per design;
 *     the spread must lie within 15% of the prediction.  With 200 seeds an
 *     sd estimate has a sampling sd of 1/sqrt(400) = 5%, so 15% is 3 sd.
 *     Each fit also starts from the true w and E* (the lower cost of that
 *     start and the automatic one wins): the prediction is the spread of
 *     the least-squares estimate, and this keeps the few fits whose
 *     automatic start stops short of the minimum (see README, "Planning a
 *     test") from being counted as the estimator's spread.
 *  4. --choose: greedy steps against brute force, and lf_design_exhaustive
 *     against an independent enumeration, on a small candidate set.
 *  5. The plan reader and the sweep.
 *
 * Seeds per design: 200 (argument 1 or LF_DESIGN_SEEDS overrides). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <gsl/gsl_errno.h>

#include "layerfit.h"
#include "testlib.h"

static const lf_material truth = { 12.3e-3, 1.85e9, 0.35 };

static lf_design_candidate
cand(const char *name, double k, lf_base base, int baseline, int free_offsets, size_t points)
{
    lf_design_candidate c;
    memset(&c, 0, sizeof c);
    snprintf(c.name, sizeof c.name, "%s", name);
    c.probe.k = k;
    c.probe.R = 1e-3;
    c.probe.b = 1e-6;
    c.probe.base = base;
    c.branch = LF_BRANCH_UNLOAD;
    c.delta_max = 50e-9;
    c.delta_min = NAN;
    c.baseline = baseline ? NAN : 0.0;
    c.points = points;
    c.free_z0 = c.free_F0 = free_offsets;
    c.noise_rel = c.noise_abs = NAN;
    return c;
}

static lf_design_settings
settings(double noise)
{
    lf_design_settings s = lf_design_settings_default();
    s.truth = truth;
    s.noise_rel = noise;
    return s;
}

/* Evaluate all candidates; NULL design on failure (reported). */
static int
evaluate(const lf_design_settings *s, size_t n, const lf_design_candidate *c,
         lf_design_result *r, const char *label)
{
    lf_error err;
    lf_design *d = lf_design_alloc(s, n, c, &err);
    int st;

    if (d == NULL) {
        t_true(0, "%s: design prepared (%s)", label, err.msg);
        memset(r, 0, sizeof *r);
        return -1;
    }
    st = lf_design_eval(d, NULL, r, &err);
    lf_design_free(d);
    if (!t_int(st, LF_OK, "%s: design evaluated", label))
        return -1;
    return 0;
}

/* ---- 1. against lf_crb --------------------------------------------------- */

static void
against_crb(int free_offsets, lf_base base2)
{
    lf_design_settings s = settings(0.01);
    lf_design_candidate c[2] = { cand("k2", 2, LF_BASE_FRICTIONLESS, 0, free_offsets, 200),
                                 cand("k3", 3, base2, 1, free_offsets, 200) };
    lf_design_result r;
    lf_design_curve dc[2];
    lf_model *m[2] = { NULL, NULL };
    double *delta[2] = { NULL, NULL };
    lf_crb_result crb;
    size_t i, j;
    int st;
    char label[96];

    snprintf(label, sizeof label, "crb cross-check (offsets %s, %s)", free_offsets ? "free" : "fixed",
             base2 == LF_BASE_BONDED ? "mixed" : "frictionless");
    s.model = &lf_model_thin;   /* lf_crb takes the model it is given */
    if (evaluate(&s, 2, c, &r, label) != 0)
        return;
    for (j = 0; j < 2; j++) {
        const lf_design_curve_info *ci = &r.curves[j];
        delta[j] = malloc(ci->n * sizeof *delta[j]);
        m[j] = lf_model_alloc(&lf_model_thin, &c[j].probe, NULL);
        for (i = 0; i < ci->n; i++)
            delta[j][i] = ci->delta_hi - (double) i / (double) (ci->n - 1) * (ci->delta_hi - ci->delta_lo);
        dc[j].model = m[j];
        dc[j].branch = LF_BRANCH_UNLOAD;
        dc[j].n = ci->n;
        dc[j].delta = delta[j];
        dc[j].sigma = ci->sigma;
        dc[j].free_z0 = dc[j].free_F0 = free_offsets;
    }
    st = lf_crb(dc, 2, &truth, r.nu.free, &crb, NULL);
    t_int(st, LF_OK, "%s: lf_crb computed", label);
    t_rel(r.w.rel, crb.sd_logw, 1e-6, "%s: se(w)/w %.5g = lf_crb's %.5g", label, r.w.rel, crb.sd_logw);
    t_rel(r.Estar.rel, crb.sd_logE, 1e-6, "%s: se(E*)/E* %.5g = lf_crb's %.5g", label, r.Estar.rel,
          crb.sd_logE);
    t_abs(r.corr_wE, crb.corr_wE, 1e-6, "%s: corr(w, E*) %.5g = lf_crb's %.5g", label, r.corr_wE,
          crb.corr_wE);
    if (base2 == LF_BASE_BONDED) {
        t_true(r.nu.free && r.nu.determined, "%s: nu free and determined", label);
        t_rel(r.nu.se, crb.sd_nu, 1e-6, "%s: se(nu) %.5g = lf_crb's %.5g", label, r.nu.se, crb.sd_nu);
    } else {
        t_true(!r.nu.free, "%s: nu not fitted with frictionless curves only", label);
    }
    t_rel(r.w.se, r.w.rel * truth.w, 1e-12, "%s: se(w) = rel * w", label);
    for (j = 0; j < 2; j++) {
        lf_model_free(m[j]);
        free(delta[j]);
    }
    lf_design_result_free(&r);
}

/* The two-probe Cramer-Rao design (tests/test_crb.c): k = 2, 3; R = 1 mm;
 * b = 1 um; w = 10 mJ/m^2;
 * E* = 1 GPa; to 50 nm, 200 points, 1% noise, offsets known: 8.6% and
 * 0.14%, correlation 0.63 (there from -0.9 c, here from 0.9 of the exact
 * model's detachment indentation, which lies a little deeper). */
static void
two_probe_numbers(void)
{
    lf_design_settings s = settings(0.01);
    lf_design_candidate c[2] = { cand("k2", 2, LF_BASE_FRICTIONLESS, 0, 0, 200),
                                 cand("k3", 3, LF_BASE_FRICTIONLESS, 0, 0, 200) };
    lf_design_result r;

    s.truth.w = 10e-3;
    s.truth.Estar = 1e9;
    s.model = &lf_model_thin;
    if (evaluate(&s, 2, c, &r, "two-probe design") != 0)
        return;
    t_rel(r.w.rel, 0.086, 0.03, "two-probe design: se(w)/w %.4g near 8.6%%", r.w.rel);
    t_rel(r.Estar.rel, 0.0014, 0.03, "two-probe design: se(E*)/E* %.4g near 0.14%%", r.Estar.rel);
    t_rel(r.corr_wE, 0.63, 0.03, "two-probe design: corr %.3g near 0.63", r.corr_wE);
    lf_design_result_free(&r);
}

/* ---- 2. identifiability --------------------------------------------------- */

static void
identifiability(void)
{
    lf_design_settings s = settings(0.01);
    lf_design_candidate c[3];
    lf_design_result r;

    c[0] = cand("k2", 2, LF_BASE_FRICTIONLESS, 0, 1, 150);
    if (evaluate(&s, 1, c, &r, "k2 alone, no baseline") == 0) {
        t_true(!r.w.determined && r.w.free, "k2 alone, no baseline: w not determined");
        t_true(isnan(r.w.se) && isnan(r.w.rel), "k2 alone, no baseline: no number for w");
        t_true(r.Estar.determined, "k2 alone, no baseline: E* determined");
        t_true(t_says(&r.identifiability, "k = 2 alone with free F0 and z0 cannot separate w"),
               "k2 alone, no baseline: the fitter's words say why");
        t_true(t_says(&r.identifiability, "frictionless curves do not depend on nu"),
               "k2 alone: nu not determined by frictionless curves");
        t_int((long) r.curves[0].n_past, 0, "k2 alone, no baseline: no point past detachment");
        lf_design_result_free(&r);
    }
    c[0] = cand("k2", 2, LF_BASE_FRICTIONLESS, 1, 1, 150);
    if (evaluate(&s, 1, c, &r, "k2 alone, baseline, 1% noise") == 0) {
        /* w within two of its standard errors: a fit reports an upper
         * bound only, and so does the design (the same judgement) */
        t_true(!r.w.determined && r.w.upper_bound_only, "k2 alone with a baseline, 1%% noise: w "
               "below the noise");
        t_true(t_says(&r.identifiability, "adhesion below the noise: w < "),
               "k2 alone with a baseline, 1%% noise: the fitter's words");
        lf_design_result_free(&r);
    }
    s.noise_rel = 0.0025;
    if (evaluate(&s, 1, c, &r, "k2 alone, baseline") == 0) {
        t_true(r.w.determined && r.w.rel > 0, "k2 alone with a baseline: w determined (%.3g)", r.w.rel);
        t_true(r.curves[0].n_past >= 15 * 150 / 100, "k2 with a baseline: %zu of 150 points past "
               "detachment", r.curves[0].n_past);
        t_true(!t_says(&r.identifiability, "cannot separate w"), "k2 with a baseline: no w message");
        lf_design_result_free(&r);
    }
    s.noise_rel = 0.01;
    c[0] = cand("k2", 2, LF_BASE_FRICTIONLESS, 0, 0, 150);
    if (evaluate(&s, 1, c, &r, "k2 alone, offsets known") == 0) {
        t_true(r.w.determined, "k2 alone with z0 and F0 known: w determined");
        lf_design_result_free(&r);
    }
    c[0] = cand("k2b", 2, LF_BASE_BONDED, 1, 1, 150);
    c[1] = cand("k3b", 3, LF_BASE_BONDED, 1, 1, 150);
    if (evaluate(&s, 2, c, &r, "bonded only") == 0) {
        t_true(!r.nu.free, "bonded only: nu not fitted (the fitter holds it)");
        t_true(!r.Estar.determined, "bonded only: E* not determined");
        t_true(r.M.determined && r.M.rel > 0, "bonded only: M = Z E* determined (%.3g)", r.M.rel);
        t_true(r.w.determined, "bonded only: w determined");
        t_true(t_says(&r.identifiability, "only bonded curves"), "bonded only: the words say so");
        lf_design_result_free(&r);
    }
    s.fix_nu = 1;
    if (evaluate(&s, 2, c, &r, "bonded only, nu held") == 0) {
        t_true(r.Estar.determined && !r.nu.free, "bonded only, nu held: E* determined");
        t_rel(r.Estar.rel, r.M.rel, 1e-9, "bonded only, nu held: se(E*)/E* = se(M)/M");
        lf_design_result_free(&r);
    }
    s.fix_nu = 0;
    c[2] = cand("k2f", 2, LF_BASE_FRICTIONLESS, 1, 1, 150);
    if (evaluate(&s, 3, c, &r, "mixed") == 0) {
        t_true(r.nu.free && r.nu.determined && r.nu.se > 0 && r.nu.se < 0.1,
               "bonded + frictionless: nu determined (se %.3g)", r.nu.se);
        t_int((long) r.ndetermined, 3, "mixed: w, E*, nu determined");
        t_true(isfinite(r.logdet), "mixed: finite log det");
        t_true(t_says(&r.identifiability, "every free parameter is determined"),
               "mixed: everything determined");
        lf_design_result_free(&r);
    }
}

/* ---- 3. Monte Carlo ---------------------------------------------------- */

typedef struct {
    double sum, sum2;
    size_t n;
} tally;

static void
tally_add(tally *t, double x)
{
    t->sum += x;
    t->sum2 += x * x;
    t->n++;
}

static double
tally_sd(const tally *t)
{
    double n = (double) t->n, m = t->sum / n;
    return t->n > 1 ? sqrt(fmax(t->sum2 / n - m * m, 0.0) * n / (n - 1.0)) : NAN;
}

static void
ratio_check(const char *label, const char *name, const tally *t, double predicted)
{
    double sd = tally_sd(t), ratio = sd / predicted;
    printf("%-40s %-3s predicted %.4g  Monte Carlo %.4g  ratio %.3f  (%zu fits)\n", label, name,
           predicted, sd, ratio, t->n);
    t_true(fabs(ratio - 1.0) <= 0.15, "%s: Monte Carlo sd of %s %.4g within 15%% of the predicted "
           "%.4g (ratio %.3f)", label, name, sd, predicted, ratio);
}

/* Simulate each candidate as the design records it, fit, compare. */
static void
monte_carlo(const char *label, double noise, size_t n, const lf_design_candidate *c, size_t seeds)
{
    lf_design_settings s = settings(noise);
    lf_design_result r;
    double *depth[4], *force[4];
    lf_fit_curve fc[4];
    tally tw = { 0, 0, 0 }, tE = { 0, 0, 0 }, tnu = { 0, 0, 0 };
    size_t k, j, w_determined = 0, failed = 0, nu_fitted = 0;

    if (evaluate(&s, n, c, &r, label) != 0)
        return;
    for (j = 0; j < n; j++) {
        depth[j] = malloc(r.curves[j].n * sizeof *depth[j]);
        force[j] = malloc(r.curves[j].n * sizeof *force[j]);
    }
    for (k = 0; k < seeds; k++) {
        lf_fit_settings fs = lf_fit_settings_default();
        lf_choose_settings cs = lf_choose_settings_default();
        lf_fit_result fr;
        lf_error err;
        int st = LF_OK;
        for (j = 0; j < n && st == LF_OK; j++) {
            const lf_design_curve_info *ci = &r.curves[j];
            lf_sim_settings ss = lf_sim_settings_default();
            ss.points = ci->n;
            ss.delta_max = ci->delta_hi;
            ss.delta_min = ci->delta_lo;
            ss.noise = ci->sigma / ci->fmax;
            ss.z0 = 7.1e-9 * (double) (j + 1);
            ss.F0 = 0.37e-6 * (double) (j + 1);
            ss.seed = 5000 + 16 * k + j;
            st = lf_simulate(&ss, &lf_model_exact, &truth, 1, &c[j].probe, &depth[j], &force[j],
                             NULL, &err);
            memset(&fc[j], 0, sizeof fc[j]);
            fc[j].n = ci->n;
            fc[j].depth = depth[j];
            fc[j].force = force[j];
            fc[j].probe = c[j].probe;
            fc[j].branch = LF_BRANCH_UNLOAD;
            fc[j].z0 = c[j].free_z0 ? NAN : ss.z0;
            fc[j].F0 = c[j].free_F0 ? NAN : ss.F0;
        }
        if (!t_int(st, LF_OK, "%s seed %zu: simulated", label, k))
            break;
        fs.nu.value = truth.nu;
        fs.w.guess = truth.w;
        fs.Estar.guess = truth.Estar;
        cs.thin_comparison = 0;
        st = lf_fit_choose_driver(&fs, &cs, n, fc, &fr, &err);
        if (st != LF_OK) {
            failed++;
            if (st == LF_ENOCONV)
                lf_fit_result_free(&fr);
            continue;
        }
        if (fr.w.determined) {
            w_determined++;
            tally_add(&tw, fr.w.value / truth.w);
        }
        if (fr.Estar.determined)
            tally_add(&tE, fr.Estar.value / truth.Estar);
        if (fr.nu.free && fr.nu.determined) {
            nu_fitted++;
            tally_add(&tnu, fr.nu.value);
        }
        lf_fit_result_free(&fr);
    }
    t_true(failed <= seeds / 50, "%s: %zu of %zu fits failed (at most 2%%)", label, failed, seeds);
    if (r.w.determined) {
        t_true(w_determined + failed >= seeds, "%s: w determined in every fit (%zu)", label,
               w_determined);
        ratio_check(label, "w", &tw, r.w.rel);
    } else {
        t_int((long) w_determined, 0, "%s: w predicted undetermined, and no fit determines it", label);
    }
    ratio_check(label, "E*", &tE, r.Estar.rel);
    if (r.nu.free) {
        t_true(r.nu.determined, "%s: nu predicted determined", label);
        t_true(nu_fitted + failed >= seeds, "%s: nu fitted and determined in every fit", label);
        ratio_check(label, "nu", &tnu, r.nu.se);
    }
    for (j = 0; j < n; j++) {
        free(depth[j]);
        free(force[j]);
    }
    lf_design_result_free(&r);
}

/* ---- 4. choice ------------------------------------------------------------ */

static void
choice(void)
{
    lf_design_settings s = settings(0.01);
    const lf_design_candidate c[5] = {
        cand("k2f", 2, LF_BASE_FRICTIONLESS, 0, 1, 100), cand("k2f+base", 2, LF_BASE_FRICTIONLESS, 1, 1, 100),
        cand("k3f", 3, LF_BASE_FRICTIONLESS, 0, 1, 100), cand("k2b+base", 2, LF_BASE_BONDED, 1, 1, 100),
        cand("k4f+base", 4, LF_BASE_FRICTIONLESS, 1, 1, 100)
    };
    lf_error err;
    lf_design *d = lf_design_alloc(&s, 5, c, &err);
    int t;

    if (!t_true(d != NULL, "choice: design prepared"))
        return;
    for (t = LF_TARGET_W; t <= LF_TARGET_ALL; t++) {
        const char *tn = lf_design_target_name((lf_design_target) t);
        lf_design_choice ch;
        lf_design_score best_score, greedy_score, brute_score;
        int best[5], use[5] = { 0, 0, 0, 0, 0 }, brute[5] = { 0, 0, 0, 0, 0 }, have = 0;
        size_t step, i, a, b;
        lf_design_result r;

        if (!t_int(lf_design_choose(d, 2, (lf_design_target) t, &ch, &err), LF_OK,
                   "choice %s: greedy ran", tn))
            continue;
        t_int((long) ch.nsteps, 2, "choice %s: two steps", tn);
        /* each greedy step is the best single addition (brute force) */
        for (step = 0; step < ch.nsteps; step++) {
            size_t arg = 5;
            lf_design_score sb;
            for (i = 0; i < 5; i++) {
                lf_design_score sc;
                if (use[i])
                    continue;
                use[i] = 1;
                lf_design_eval(d, use, &r, NULL);
                sc = lf_design_score_of(&r, (lf_design_target) t);
                lf_design_result_free(&r);
                use[i] = 0;
                if (arg == 5 || lf_design_score_cmp(&sc, &sb) > 0) {
                    arg = i;
                    sb = sc;
                }
            }
            t_int((long) ch.steps[step].added, (long) arg, "choice %s: step %zu adds the best "
                  "candidate", tn, step + 1);
            use[arg] = 1;
        }
        /* the exhaustive search against an independent enumeration */
        for (a = 0; a < 5; a++)
            for (b = a + 1; b < 5; b++) {
                lf_design_score sc;
                int u[5] = { 0, 0, 0, 0, 0 };
                u[a] = u[b] = 1;
                lf_design_eval(d, u, &r, NULL);
                sc = lf_design_score_of(&r, (lf_design_target) t);
                lf_design_result_free(&r);
                if (!have || lf_design_score_cmp(&sc, &brute_score) > 0) {
                    brute_score = sc;
                    memcpy(brute, u, sizeof u);
                    have = 1;
                }
            }
        if (t_int(lf_design_exhaustive(d, 2, (lf_design_target) t, 100, best, &best_score, &err),
                  LF_OK, "choice %s: exhaustive search ran", tn)) {
            t_true(memcmp(best, brute, sizeof best) == 0, "choice %s: exhaustive best = "
                   "enumeration's best", tn);
            lf_design_eval(d, ch.chosen, &r, NULL);
            greedy_score = lf_design_score_of(&r, (lf_design_target) t);
            lf_design_result_free(&r);
            t_true(lf_design_score_cmp(&best_score, &greedy_score) >= 0,
                   "choice %s: no set of 2 beats the exhaustive best", tn);
            printf("choice %-3s: greedy %s the exhaustive best\n", tn,
                   memcmp(best, ch.chosen, sizeof best) == 0 ? "equals" : "differs from");
        }
        lf_design_choice_free(&ch);
    }
    t_int(lf_design_exhaustive(d, 2, LF_TARGET_W, 5, (int[5]) { 0 }, &(lf_design_score) { 0 }, &err),
          LF_EINVAL, "exhaustive refuses more sets than allowed");
    lf_design_free(d);
}

/* ---- 5. plan reader and sweep -------------------------------------------- */

static void
plan_reader(void)
{
    const char good[] =
        "name,k,R_mm,b [um],interface,delta_max,points,baseline,z0,F0,noise,segment\n"
        "sphere,2,1,1,frictionless,50nm,150,yes,free,fixed,0.5%,unload\n"
        "cone-ish,3,2,0.5,bonded,,,20nm,fixed,,2uN,\n";
    lf_design_plan *p = NULL;
    lf_error err;
    int st = lf_design_plan_parse(good, strlen(good), "good.csv", &p, &err);

    if (t_int(st, LF_OK, "plan: parsed")) {
        t_int((long) p->n, 2, "plan: two rows");
        t_str(p->rows[0].name, "sphere", "plan: name");
        t_rel(p->rows[1].probe.R, 2e-3, 1e-12, "plan: R in mm from the header");
        t_rel(p->rows[1].probe.b, 0.5e-6, 1e-12, "plan: b in um from the header");
        t_rel(p->rows[0].delta_max, 50e-9, 1e-12, "plan: delta_max with its unit in the cell");
        t_true(isnan(p->rows[1].delta_max), "plan: empty delta_max = default");
        t_int((long) p->rows[0].points, 150, "plan: points");
        t_int((long) p->rows[1].points, 0, "plan: empty points = default");
        t_true(isnan(p->rows[0].baseline), "plan: baseline yes");
        t_rel(p->rows[1].baseline, 20e-9, 1e-12, "plan: baseline length");
        t_true(p->rows[0].free_z0 && !p->rows[0].free_F0, "plan: z0 free, F0 fixed");
        t_true(!p->rows[1].free_z0 && p->rows[1].free_F0, "plan: z0 fixed, F0 free (empty)");
        t_rel(p->rows[0].noise_rel, 0.005, 1e-12, "plan: noise 0.5%%");
        t_rel(p->rows[1].noise_abs, 2e-6, 1e-12, "plan: noise 2uN");
        t_int(p->rows[1].probe.base, LF_BASE_BONDED, "plan: interface");
        t_int((long) p->rows[1].line, 3, "plan: line numbers");
    }
    lf_design_plan_free(p);
    /* the same plan from a file (lf_design_plan_read, what bindings call) */
    {
        char path[] = "/tmp/layerfit-design-plan-XXXXXX";
        int fd = mkstemp(path);
        lf_design_plan *q = NULL;
        if (t_true(fd >= 0, "plan file: made") && write(fd, good, strlen(good)) == (ssize_t) strlen(good)) {
            close(fd);
            st = lf_design_plan_read(path, &q, &err);
            if (t_int(st, LF_OK, "plan file: read") && t_int((long) q->n, 2, "plan file: two rows")) {
                t_str(q->path, path, "plan file: its path");
                t_str(q->rows[1].name, "cone-ish", "plan file: the second row's name");
                t_rel(q->rows[1].noise_abs, 2e-6, 1e-12, "plan file: noise 2uN");
            }
            lf_design_plan_free(q);
            unlink(path);
            st = lf_design_plan_read(path, &q, &err);
            t_true(st == LF_EIO && q == NULL, "plan file: a missing file is LF_EIO (%s)", err.msg);
        }
    }
    {
        static const struct { const char *text, *msg; long line, col; } bad[] = {
            { "k,R_mm,b_um,interface,depth\n2,1,1,frictionless,3\n", "unknown column 'depth'", 1, 23 },
            { "k,R_mm,b_um\n2,1,1\n", "no interface column", 1, 1 },
            { "k,R_mm,b_um,interface,noise\n2,1,1,frictionless,lots\n", "noise 'lots'", 2, 20 },
            { "k,R_mm,b_um,interface,points\n2,1,1,frictionless,3\n", "points must be", 2, 20 },
            { "k,R_mm,b_um,interface,baseline,delta_min_nm\n2,1,1,frictionless,yes,-5\n",
              "give delta_min or baseline, not both", 2, 0 },
            { "k,R_mm,b_um,interface,z0\n2,1,1,frictionless,maybe\n", "z0 'maybe' must be free or fixed",
              2, 20 },
            { "k,R_mm,b_um,interface\n-2,1,1,frictionless\n", "k", 2, 0 },
            { "k,R_mm,b_um,interface\n", "header but no rows", 1, 0 },
            { "k,R_mm,b_um,interface,segment\n2,1,1,frictionless,hold\n",
              "segment 'hold' is a hold, which is never fitted", 2, 20 },
            { "k,R_mm,b_um,interface\n,1,1,frictionless\n", "empty k cell (every row needs k)",
              2, 1 },
        };
        size_t i;
        for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
            st = lf_design_plan_parse(bad[i].text, strlen(bad[i].text), "bad.csv", &p, &err);
            t_true(st != LF_OK && p == NULL, "bad plan %zu refused", i + 1);
            t_contains(err.msg, bad[i].msg, "bad plan %zu: message '%s'", i + 1, err.msg);
            t_int(err.line, bad[i].line, "bad plan %zu: line", i + 1);
            t_int(err.column, bad[i].col, "bad plan %zu: column", i + 1);
        }
    }
}

static void
sweep(void)
{
    lf_design_settings s = settings(0.01);
    lf_design_candidate c[2] = { cand("a", 2, LF_BASE_FRICTIONLESS, 1, 1, 80),
                                 cand("b", 3, LF_BASE_FRICTIONLESS, 0, 1, 80) };
    const double ks[3] = { 2.5, 3.0, 4.0 };
    lf_design_result res[3], one;
    lf_error err;
    size_t v;

    if (!t_int(lf_design_sweep(&s, 2, c, LF_FACTOR_K, 1, 3, ks, res, &err), LF_OK, "sweep ran"))
        return;
    for (v = 0; v < 3; v++) {
        lf_design_candidate cc[2] = { c[0], c[1] };
        cc[1].probe.k = ks[v];
        if (evaluate(&s, 2, cc, &one, "sweep reference") == 0) {
            t_rel(res[v].w.rel, one.w.rel, 1e-12, "sweep k = %g: w as a design of its own", ks[v]);
            t_rel(res[v].Estar.rel, one.Estar.rel, 1e-12, "sweep k = %g: E* as a design of its own",
                  ks[v]);
            lf_design_result_free(&one);
        }
        lf_design_result_free(&res[v]);
    }
    t_int(lf_design_sweep(&s, 2, c, LF_FACTOR_POINTS, (size_t) -1, 1, (double[1]) { 3.0 }, res, &err),
          LF_EINVAL, "sweep refuses 3 points");
    t_int(lf_design_factor_find("depth"), LF_FACTOR_DELTA_MAX, "factor 'depth' = delta_max");
    t_int(lf_design_factor_find("nonsense"), -1, "unknown factor");
    t_int(lf_design_target_find("all"), LF_TARGET_ALL, "target all");
    t_int(lf_design_target_find("x"), -1, "unknown target");
}

int
main(int argc, char **argv)
{
    size_t seeds = 200;
    const char *env = getenv("LF_DESIGN_SEEDS");

    gsl_set_error_handler_off();
    if (argc > 1)
        seeds = (size_t) strtoul(argv[1], NULL, 10);
    else if (env != NULL)
        seeds = (size_t) strtoul(env, NULL, 10);
    against_crb(0, LF_BASE_FRICTIONLESS);
    against_crb(1, LF_BASE_FRICTIONLESS);
    against_crb(1, LF_BASE_BONDED);
    two_probe_numbers();
    identifiability();
    {
        /* k = 3 without a baseline: see the note on k > 2 through detachment */
        const lf_design_candidate two[2] = { cand("k2", 2, LF_BASE_FRICTIONLESS, 1, 1, 150),
                                             cand("k3", 3, LF_BASE_FRICTIONLESS, 0, 1, 150) };
        const lf_design_candidate mixed[2] = { cand("k2f", 2, LF_BASE_FRICTIONLESS, 1, 1, 150),
                                               cand("k2b", 2, LF_BASE_BONDED, 1, 1, 150) };
        const lf_design_candidate k2base = cand("k2", 2, LF_BASE_FRICTIONLESS, 1, 1, 150);
        const lf_design_candidate k2none = cand("k2", 2, LF_BASE_FRICTIONLESS, 0, 1, 150);
        monte_carlo("two probes, offsets free", 0.0015, 2, two, seeds);
        monte_carlo("frictionless + bonded (nu)", 0.0015, 2, mixed, seeds);
        monte_carlo("k2 with baseline", 0.0025, 1, &k2base, seeds);
        monte_carlo("k2 without baseline", 0.0025, 1, &k2none, seeds);
    }
    choice();
    plan_reader();
    sweep();
    return t_summary();
}
