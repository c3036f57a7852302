/* test_judge.c: one judgement for a fit and a design (fit/judge.c).
 *
 * Each design is evaluated by `layerfit design` (lf_design_eval, at the
 * truth) and its curves, simulated with the exact layer model without
 * noise at the very indentations the design plans, are fitted with the
 * automatic model choice (lf_fit_choose_driver, started at the truth as
 * well as from its own guess).  The fit's noise weights are its estimate
 * from the data, so the design is evaluated again with those noise levels:
 * then both see the same Jacobian, and what they say is determined, and
 * why, must agree word for word: the verdicts on w, E*, nu and M, the
 * identifiability notes, and each curve's model and the reason for it.
 *
 * The designs: a k = 2 sphere with free offsets and 0, 3, 8, 19 and 60
 * points past detachment (the k = 2 rule: below three points past
 * detachment w is not told from the force offset); a bonded layer under
 * the exact model at b/a > 1 (where the data fix E*, not M = Z E*); and a
 * frictionless and a bonded curve together (nu determined). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "layerfit.h"
#include "testlib.h"

static const lf_material truth = { 10e-3, 1e9, 0.3 };

static lf_design_candidate
cand(const char *name, double k, double b, lf_base base)
{
    lf_design_candidate c;
    memset(&c, 0, sizeof c);
    snprintf(c.name, sizeof c.name, "%s", name);
    c.probe.k = k;
    c.probe.R = 1e-3;
    c.probe.b = b;
    c.probe.base = base;
    c.branch = LF_BRANCH_UNLOAD;
    c.delta_max = 50e-9;
    c.delta_min = NAN;
    c.baseline = NAN;
    c.points = 300;
    c.free_z0 = c.free_F0 = 1;
    c.noise_rel = c.noise_abs = NAN;
    return c;
}

/* A k = 2 candidate with exactly `past` of its points past the exact
 * model's detachment (unloading, evenly spaced from 50 nm down). */
static lf_design_candidate
k2_past(size_t past)
{
    lf_design_candidate c = cand("1", 2, 1e-6, LF_BASE_FRICTIONLESS);
    lf_model *m = lf_model_alloc(&lf_model_exact, &c.probe, NULL);
    lf_pulloff po;
    double det, h;

    if (m == NULL || lf_model_pulloff(m, &truth, &po, NULL) != LF_OK) {
        lf_model_free(m);
        return c;
    }
    lf_model_free(m);
    det = po.delta_detach;
    if (past == 0) {
        c.baseline = 0.0;       /* the design's own end short of detachment */
        return c;
    }
    /* points i = 0..n-1 at hi - i h; the last `past` below det */
    h = (c.delta_max - det) / ((double) c.points - (double) past - 0.5);
    c.delta_min = det - ((double) past - 0.5) * h;
    return c;
}

static int
same_words(const lf_warnings *a, const lf_warnings *b, const char *label, const char *what)
{
    size_t i;
    int ok = a->n == b->n;

    for (i = 0; ok && i < a->n; i++)
        ok = strcmp(a->msg[i], b->msg[i]) == 0;
    if (!t_true(ok, "%s: %s word for word", label, what)) {
        for (i = 0; i < a->n; i++)
            printf("  design: %s\n", a->msg[i]);
        for (i = 0; i < b->n; i++)
            printf("  fit:    %s\n", b->msg[i]);
    }
    return ok;
}

static void
verdict(const char *label, const char *name, const lf_design_estimate *d,
        const lf_fit_estimate *f)
{
    t_int(d->determined, f->determined, "%s: %s determined: design %d, fit %d", label, name,
          d->determined, f->determined);
    t_int(d->upper_bound_only, f->upper_bound_only, "%s: %s bounded from above only", label,
          name);
    if ((d->why == NULL) != (f->why == NULL) || (d->why && strcmp(d->why, f->why) != 0))
        t_true(0, "%s: why %s: design '%s', fit '%s'", label, name, d->why ? d->why : "",
               f->why ? f->why : "");
    else
        t_true(1, "%s: why %s", label, name);
}

/* Design, noise-free fit, design at the fit's noise; compare. */
static void
compare(const char *label, size_t n, lf_design_candidate *c)
{
    lf_design_settings s = lf_design_settings_default();
    lf_design_result r;
    lf_fit_result fr;
    lf_fit_curve fc[4];
    double *depth[4], *force[4];
    lf_error err;
    lf_design *d;
    size_t j;
    int st;

    s.truth = truth;
    if ((d = lf_design_alloc(&s, n, c, &err)) == NULL) {
        t_true(0, "%s: design prepared (%s)", label, err.msg);
        return;
    }
    st = lf_design_eval(d, NULL, &r, &err);
    lf_design_free(d);
    if (!t_int(st, LF_OK, "%s: design evaluated", label))
        return;
    for (j = 0; j < n; j++) {
        const lf_design_curve_info *ci = &r.curves[j];
        lf_sim_settings ss = lf_sim_settings_default();
        depth[j] = malloc(ci->n * sizeof *depth[j]);
        force[j] = malloc(ci->n * sizeof *force[j]);
        ss.points = ci->n;
        ss.delta_max = ci->delta_hi;
        ss.delta_min = ci->delta_lo;
        ss.z0 = 7e-9 * (double) (j + 1);
        ss.F0 = 0.3e-6 * (double) (j + 1);
        st = lf_simulate(&ss, &lf_model_exact, &truth, 1, &c[j].probe, &depth[j], &force[j],
                         NULL, &err);
        t_int(st, LF_OK, "%s: curve %zu simulated", label, j + 1);
        memset(&fc[j], 0, sizeof fc[j]);
        fc[j].n = ci->n;
        fc[j].depth = depth[j];
        fc[j].force = force[j];
        fc[j].probe = c[j].probe;
        fc[j].branch = c[j].branch;
        fc[j].z0 = fc[j].F0 = NAN;
    }
    lf_design_result_free(&r);
    {
        lf_fit_settings fs = lf_fit_settings_default();
        lf_choose_settings cs = lf_choose_settings_default();
        fs.nu.value = truth.nu;
        fs.w.guess = truth.w;
        fs.Estar.guess = truth.Estar;
        cs.thin_comparison = 0;
        st = lf_fit_choose_driver(&fs, &cs, n, fc, &fr, &err);
    }
    if (!t_true(st == LF_OK || st == LF_ENOCONV, "%s: fitted (%s)", label,
                st == LF_OK || st == LF_ENOCONV ? "" : err.msg))
        goto done;
    t_true(fr.chi2 / (double) fr.dof < 1e-3 || !fr.converged,
           "%s: the noise-free fit lands on the truth (chi2/dof %.3g)", label,
           fr.chi2 / (double) fr.dof);
    /* the design at the fit's noise weights */
    for (j = 0; j < n; j++)
        c[j].noise_abs = fr.curves[j].sigma;
    d = lf_design_alloc(&s, n, c, &err);
    st = d != NULL ? lf_design_eval(d, NULL, &r, &err) : LF_EINVAL;
    lf_design_free(d);
    if (!t_int(st, LF_OK, "%s: design at the fit's noise", label)) {
        lf_fit_result_free(&fr);
        goto done;
    }
    verdict(label, "w", &r.w, &fr.w);
    verdict(label, "E*", &r.Estar, &fr.Estar);
    verdict(label, "nu", &r.nu, &fr.nu);
    t_int(r.M.determined, fr.M.determined, "%s: M determined: design %d, fit %d", label,
          r.M.determined, fr.M.determined);
    same_words(&r.identifiability, &fr.identifiability, label, "what the data determine");
    for (j = 0; j < n; j++) {
        t_str(r.curves[j].model->name, fr.curves[j].model, "%s: curve %zu's model", label, j + 1);
        t_str(r.curves[j].model_reason, fr.curves[j].model_reason, "%s: curve %zu's reason",
              label, j + 1);
    }
    lf_design_result_free(&r);
    lf_fit_result_free(&fr);
done:
    for (j = 0; j < n; j++) {
        free(depth[j]);
        free(force[j]);
    }
}

int
main(void)
{
    static const size_t past[] = { 0, 3, 8, 19, 60 };
    lf_design_candidate c[2];
    char label[64];
    size_t i;

    gsl_set_error_handler_off();
    for (i = 0; i < sizeof past / sizeof past[0]; i++) {
        c[0] = k2_past(past[i]);
        snprintf(label, sizeof label, "k = 2, %zu points past detachment", past[i]);
        compare(label, 1, c);
    }
    c[0] = cand("1", 2, 20e-6, LF_BASE_BONDED);
    compare("bonded, exact, b/a > 1", 1, c);
    c[0] = cand("1", 2, 1e-6, LF_BASE_FRICTIONLESS);
    c[1] = cand("2", 3, 1e-6, LF_BASE_BONDED);
    compare("frictionless + bonded", 2, c);
    return t_summary();
}
