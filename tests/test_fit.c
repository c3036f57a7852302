/* test_fit.c: the fitter on noise-free data (truth to 1e-8 from the
 * automatic guess, k in {1.5, 2, 3, 6}, frictionless, bonded and mixed
 * plans, unloading and loading), the analytic Jacobian against central
 * differences, independence of the order of the curves, every method and
 * finite-difference Jacobians, held parameters and argument errors. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "fit.h"
#include "scene.h"
#include "testlib.h"

static void
check_truth(scene *s, double tol)
{
    lf_fit_result r;
    lf_error err;
    int status = scene_fit(s, 1, &r, &err);
    size_t j;

    if (!t_int(status, LF_OK, "%s: fit converges (%s)", s->label,
               status == LF_ENOCONV ? r.stop_reason : status ? err.msg : "ok"))
        return;
    t_rel(r.w.value, s->mat.w, tol, "%s: w", s->label);
    t_rel(r.Estar.value, s->mat.Estar, tol, "%s: E*", s->label);
    if (r.nu.free)
        t_rel(r.nu.value, s->mat.nu, tol, "%s: nu", s->label);
    for (j = 0; j < s->n; j++) {
        if (r.curves[j].z0_free)
            t_rel(r.curves[j].z0, s->sim.z0, tol, "%s: z0 of curve %zu", s->label, j + 1);
        if (r.curves[j].F0_free)
            t_abs(r.curves[j].F0, s->sim.F0, tol * r.curves[j].pulloff.P_po * -1.0,
                  "%s: F0 of curve %zu (to tol x pull-off)", s->label, j + 1);
    }
    t_true(r.w.determined && r.Estar.determined, "%s: w and E* determined", s->label);
    lf_fit_result_free(&r);
}

static void
noise_free(void)
{
    static const double ks[] = { 1.5, 2, 3, 6 };
    static const double Rs[] = { 0.5e-3, 1e-3, 1e-3, 20e-6 };
    char label[128];
    size_t i;
    int base;

    for (i = 0; i < 4; i++)
        for (base = 0; base < 3; base++) {
            scene s;
            snprintf(label, sizeof label, "noise-free k=%g %s", ks[i],
                     base == 0 ? "frictionless" : base == 1 ? "bonded (nu held)" : "mixed");
            s = scene_default(label);
            if (base == 1) {
                s.fit.nu.mode = LF_PARAM_FIXED;
                s.fit.nu.value = s.mat.nu;
            }
            /* each k joined by a second probe (k = 3) so that w is
             * determined for k = 2 too, with its own b */
            scene_add(&s, ks[i], Rs[i], 1e-6, base == 1 ? LF_BASE_BONDED : LF_BASE_FRICTIONLESS);
            scene_add(&s, 3, 1e-3, 2e-6, base == 0 ? LF_BASE_FRICTIONLESS : LF_BASE_BONDED);
            check_truth(&s, 1e-8);
            scene_free(&s);
        }
    {   /* one curve alone, and the loading branch */
        scene s = scene_default("noise-free k=3 alone");
        scene_add(&s, 3, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
        check_truth(&s, 1e-8);
        scene_free(&s);
        s = scene_default("noise-free k=2 alone with baseline");
        s.sim.past_c = 4.0;
        scene_add(&s, 2, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
        check_truth(&s, 1e-8);
        scene_free(&s);
        s = scene_default("noise-free loading k=2,3");
        s.sim.branch = LF_BRANCH_LOAD;
        s.sim.past_c = 2.0;
        scene_add(&s, 2, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
        scene_add(&s, 3, 1e-3, 1e-6, LF_BASE_BONDED);
        check_truth(&s, 1e-8);
        scene_free(&s);
    }
}

static void
jacobian(void)
{
    scene s = scene_default("jacobian");
    lf_fit *f;
    lf_error err;
    double worst = 1;
    lf_material m = { 9.1e-3, 1.37e9, 0.31 };

    s.fit.fit_slope = 1;
    scene_add(&s, 2.5, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
    scene_add(&s, 3, 1e-3, 1e-6, LF_BASE_BONDED);
    scene_simulate(&s, 3);
    f = lf_fit_alloc(&s.fit, s.n, s.curve, &err);
    if (t_true(f != NULL, "jacobian: alloc")) {
        t_int(lf_fit_check_jacobian(f, &m, &worst, &err), LF_OK, "jacobian: check runs");
        t_abs(worst, 0, 1e-6, "jacobian: analytic = central differences (max rel %.2g)", worst);
    }
    lf_fit_free(f);
    scene_free(&s);
}

static void
order_and_methods(void)
{
    scene s = scene_default("order");
    lf_fit_curve rev[2];
    lf_fit_result a, b;
    lf_error err;
    static const char *const methods[] = { "lm", "lmaccel", "dogleg", "ddogleg", "subspace2D" };
    size_t i;

    s.sim.noise = 0.005;
    s.sim.past_c = 2.0;
    s.sim.delta_max = 20e-9;
    scene_add(&s, 2, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
    scene_add(&s, 3, 1e-3, 1e-6, LF_BASE_BONDED);
    t_int(scene_fit(&s, 11, &a, &err), LF_OK, "order: forward fit");
    rev[0] = s.curve[1];
    rev[1] = s.curve[0];
    t_int(lf_fit_driver(&s.fit, 2, rev, &b, &err), LF_OK, "order: reversed fit");
    t_rel(b.w.value, a.w.value, 1e-7, "order: w does not depend on curve order (to 1e-5 se)");
    t_rel(b.Estar.value, a.Estar.value, 1e-8, "order: E* does not depend on curve order");
    t_rel(b.nu.value, a.nu.value, 1e-8, "order: nu does not depend on curve order");
    t_rel(b.w.se, a.w.se, 1e-6, "order: se(w) does not depend on curve order");
    t_rel(b.curves[1].z0, a.curves[0].z0, 1e-9, "order: z0 follows its curve");
    lf_fit_result_free(&b);
    /* a second run of the same fit object gives the same answer */
    {
        lf_fit *f = lf_fit_alloc(&s.fit, 2, s.curve, &err);
        lf_fit_result c1, c2;
        t_int(lf_fit_run(f, &c1, &err), LF_OK, "rerun: first");
        t_int(lf_fit_run(f, &c2, &err), LF_OK, "rerun: second");
        t_true(c1.w.value == c2.w.value && c1.Estar.value == c2.Estar.value,
               "rerun: identical results, nothing carried over");
        lf_fit_result_free(&c1);
        lf_fit_result_free(&c2);
        lf_fit_free(f);
    }
    for (i = 0; i < sizeof methods / sizeof methods[0]; i++) {
        lf_fit_settings set = s.fit;
        int j;
        for (j = 0; j < 3; j++) {
            int st;
            set.method = methods[i];
            set.jacobian = (lf_jacobian) j;
            st = lf_fit_driver(&set, 2, s.curve, &b, &err);
            t_int(st, LF_OK, "method %s jacobian %d converges", methods[i], j);
            if (st == LF_OK || st == LF_ENOCONV) {
                t_rel(b.w.value, a.w.value, 1e-5, "method %s jacobian %d: same w", methods[i], j);
                t_rel(b.nu.value, a.nu.value, 1e-6, "method %s jacobian %d: same nu", methods[i], j);
                t_str(b.method, methods[i], "method %s reported", methods[i]);
                lf_fit_result_free(&b);
            }
        }
    }
    lf_fit_result_free(&a);
    scene_free(&s);
}

static void
held_and_errors(void)
{
    scene s = scene_default("held");
    lf_fit_result r;
    lf_error err;
    lf_fit_settings bad;

    scene_add(&s, 2, 1e-3, 1e-6, LF_BASE_BONDED);
    scene_add(&s, 3, 1e-3, 1e-6, LF_BASE_BONDED);
    s.fix_z0 = s.fix_F0 = 1;
    s.fit.Estar.mode = LF_PARAM_FIXED;
    s.fit.Estar.value = s.mat.Estar;
    t_int(scene_fit(&s, 1, &r, &err), LF_OK, "held E*, z0, F0: converges");
    t_true(r.nu.free && r.nu.determined, "held E*: nu becomes free and determined on bonded curves");
    t_rel(r.nu.value, s.mat.nu, 1e-8, "held E*: nu recovered");
    t_rel(r.w.value, s.mat.w, 1e-8, "held E*: w recovered");
    t_true(!r.Estar.free && r.Estar.determined && r.Estar.value == s.mat.Estar, "held E* reported as held");
    t_true(!r.curves[0].z0_free && !r.curves[0].F0_free && isnan(r.curves[0].z0_se),
           "held z0, F0 reported as held");
    t_int((long) r.npar, 2, "held: two free parameters (w, nu)");
    lf_fit_result_free(&r);

    bad = s.fit;
    bad.method = "newton";
    t_true(lf_fit_alloc(&bad, s.n, s.curve, &err) == NULL, "unknown method refused");
    t_str(err.msg, "unknown method 'newton' (lm, lmaccel, dogleg, ddogleg, subspace2D)", "unknown method message");
    bad = s.fit;
    bad.w.mode = LF_PARAM_FIXED;
    bad.w.value = 1e-3;
    bad.nu.mode = LF_PARAM_FIXED;
    t_true(lf_fit_alloc(&bad, s.n, s.curve, &err) == NULL, "nothing free refused");
    t_int(err.status, LF_EINVAL, "nothing free: LF_EINVAL");
    s.curve[0].n = 3;
    t_true(lf_fit_alloc(&s.fit, s.n, s.curve, &err) == NULL, "3 points refused");
    t_int(err.status, LF_EDATA, "3 points: LF_EDATA");
    scene_free(&s);
}

/* The exact model's start (guess_model.c): the thin profile's start or the
 * model's own force law's, whichever fits the curves' subsamples better.
 * The comparison runs before any solve, so the workspace must begin with
 * least-squares weights (it began with zeros, every cost was 0 and the
 * thin start always won).  Here, on a 20 um bonded layer, the thin start
 * is far off (its chi2 hundreds of times the model's start's) and the
 * model's start must be kept; on 1 um the model's start is also the better
 * one (half the chi2).  In both the start kept must be the one with the
 * lower chi2 over all the points, not only the subsamples compared. */
static void
model_start(void)
{
    static const double bs[] = { 1e-6, 20e-6 };
    size_t i, k;

    for (i = 0; i < sizeof bs / sizeof bs[0]; i++) {
        scene s = scene_default("model start");
        lf_fit *f;
        lf_error err;
        fit_start start;
        double cost[2];
        int kept = -1;

        s.sim_model = &lf_model_exact;
        s.fit.model = &lf_model_exact;
        s.sim.noise = 0.002;
        s.fit.nu.mode = LF_PARAM_FIXED;
        s.fit.nu.value = s.mat.nu;
        scene_add(&s, 2, 1e-3, bs[i], LF_BASE_BONDED);
        scene_simulate(&s, 5);
        f = lf_fit_alloc(&s.fit, s.n, s.curve, &err);
        if (!t_true(f != NULL, "model start b = %g: alloc", bs[i])) {
            scene_free(&s);
            continue;
        }
        for (k = 0; k < f->ndata; k++)
            if (f->ws.sqrtw[k] != 1.0)
                break;
        t_int((long) k, (long) f->ndata, "model start b = %g: weights 1 before the guess", bs[i]);
        t_int(lf_fit_guess(f, &start, &err), LF_OK, "model start b = %g: guess", bs[i]);
        kept = f->start_by_model;
        /* the full chi2 of both starts, the same way the guess makes them */
        for (k = 0; k < 2; k++) {
            f->start_by_model = 0;
            f->mat = start.automatic;
            if (k == 1 && !lf_fit_guess_model(f)) {
                cost[k] = HUGE_VAL;
                continue;
            }
            f->start_by_model = (int) k;
            lf_fit_guess_offsets(f);
            gsl_vector_set_all(f->ws.x, 1.0);
            lf_fit_invalidate(f);
            cost[k] = lf_fit_cost(f, f->ws.x, f->ws.r);
        }
        t_true(cost[kept] <= cost[1 - kept], "model start b = %g: the start kept (%s, chi2 %.4g) "
               "is the better of the two (other %.4g)", bs[i], kept ? "the model's" : "thin",
               2 * cost[kept], 2 * cost[1 - kept]);
        if (bs[i] > 10e-6)
            t_int(kept, 1, "model start b = %g: a thick layer starts from the model's force law",
                  bs[i]);
        lf_fit_free(f);
        scene_free(&s);
    }
}

/* The covariance V S^-2 V^T / (D_i D_k) of a decomposition, p x p. */
static void
cov_of(const fit_decomp *d, double *cov)
{
    size_t i, k, l, p = d->p;

    for (i = 0; i < p; i++)
        for (k = 0; k < p; k++) {
            double c = 0.0;
            for (l = 0; l < d->rank; l++) {
                double sl = gsl_vector_get(d->S, l);
                c += gsl_matrix_get(d->V, i, l) * gsl_matrix_get(d->V, k, l) / (sl * sl);
            }
            cov[i * p + k] = c / (gsl_vector_get(d->D, i) * gsl_vector_get(d->D, k));
        }
}

/* The largest gap between the covariance cov / s2 and ref (p x p, NaN
 * entries of cov skipped), in units of ref's standard errors' product. */
static double
cov_apart(const double *cov, double s2, const double *ref, size_t p)
{
    double emax = 0.0;
    size_t k;

    for (k = 0; k < p * p; k++)
        if (!isnan(cov[k]))
            emax = fmax(emax, fabs(cov[k] / s2 - ref[k])
                                  / sqrt(ref[(k / p) * (p + 1)] * ref[(k % p) * (p + 1)]));
    return emax;
}

/* The decomposition from J^T J (decomp.c) against the QR of J at fitted
 * solutions: the same singular values, column norms and covariance to
 * rounding; refused where J^T J would lose the smallest singular value. */
static void
decomposition(void)
{
    enum { NS = 3 };
    size_t q;

    for (q = 0; q < NS; q++) {
        scene s = scene_default(q == 0 ? "decomposition: two probes, offsets free"
                                : q == 1 ? "decomposition: bonded, nu and slopes free"
                                         : "decomposition: k = 3 alone");
        lf_fit *f;
        lf_fit_result res;
        lf_error err;
        fit_decomp a, b;
        double *G, *g, *cm, *c, *r, *ca, *cb, emax = 0.0;
        size_t p, k;

        s.sim.noise = 0.01;
        if (q == 1)
            s.fit.fit_slope = 1;
        scene_add(&s, q == 2 ? 3.0 : 2.0, 1e-3, 1e-6,
                  q == 1 ? LF_BASE_BONDED : LF_BASE_FRICTIONLESS);
        if (q < 2)
            scene_add(&s, 3.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
        scene_simulate(&s, 5 + q);
        f = lf_fit_alloc(&s.fit, s.n, s.curve, &err);
        if (!t_true(f != NULL && lf_fit_run(f, &res, &err) == LF_OK, "%s: fit", s.label)) {
            lf_fit_free(f);
            scene_free(&s);
            continue;
        }
        p = f->np;
        G = malloc((p * p * 3 + 3 * p + f->nres) * sizeof *G);
        g = G + p * p;
        cm = g + p;
        c = cm + p;
        ca = c + p;
        cb = ca + p * p;
        r = cb + p * p;
        {
            gsl_vector_view rv = gsl_vector_view_array(r, f->nres);
            gsl_vector_const_view xv = gsl_vector_const_view_array(f->ws.x->data, p);
            t_int(lf_fit_residuals(&xv.vector, f, &rv.vector), GSL_SUCCESS, "%s: residuals", s.label);
        }
        {
            fit_arrow A;
            t_int(lf_fit_arrow_alloc(f, 0, &A), LF_OK, "alloc");
            t_int(lf_fit_normal_sums(f, f->ws.x->data, r, &A, g, cm), GSL_SUCCESS, "%s: J^T J",
                  s.label);
            lf_arrow_dense(&A, G);
            lf_arrow_free(&A);
        }
        lf_fit_internal_scale(f, f->ws.x->data, c);
        t_int(lf_fit_decomp_alloc(&a, f->nres, p), LF_OK, "alloc");
        t_int(lf_fit_decomp_alloc(&b, 0, p), LF_OK, "alloc");
        t_int(lf_fit_decomp_run(&a, f, f->ws.x->data, 1e-7), LF_OK, "%s: QR of J", s.label);
        t_int(lf_fit_decomp_normal(&b, G, c, 1e-7), LF_OK, "%s: from J^T J (cond %.3g)",
              s.label, gsl_vector_get(a.S, 0) / gsl_vector_get(a.S, p - 1));
        t_int((long) b.rank, (long) a.rank, "%s: the same rank", s.label);
        for (k = 0; k < p; k++) {
            emax = fmax(emax, fabs(gsl_vector_get(b.S, k) / gsl_vector_get(a.S, k) - 1.0));
            emax = fmax(emax, fabs(gsl_vector_get(b.D, k) / gsl_vector_get(a.D, k) - 1.0));
        }
        t_true(emax < 1e-10, "%s: singular values and column norms agree (%.1e)", s.label, emax);
        cov_of(&a, ca);
        cov_of(&b, cb);
        emax = cov_apart(cb, 1.0, ca, p);
        t_true(emax < 1e-9, "%s: covariances agree (%.1e of the standard errors' product)",
               s.label, emax);
        /* the fit's own covariance (from the solver's J^T J) is the QR's */
        emax = cov_apart(res.cov, res.se_scale * res.se_scale, ca, p);
        t_true(emax < 1e-9, "%s: the fit's covariance is the QR's (%.1e)", s.label, emax);
        lf_fit_result_free(&res);
        /* rcond at the smallest singular value: the rank needs J */
        t_int(lf_fit_decomp_normal(&b, G, c, gsl_vector_get(a.S, p - 1) / gsl_vector_get(a.S, 0)),
              LF_ENUMERIC, "%s: rcond at the smallest singular value refused", s.label);
        lf_fit_decomp_free(&a);
        lf_fit_decomp_free(&b);
        free(G);
        lf_fit_free(f);
        scene_free(&s);
    }
    {   /* no adhesion in the data: w driven towards zero, where the squares
         * of its column (w dP/dw) underflow in J^T J (seed 10: 1.8e-320);
         * the fit's covariance must still be the QR's */
        scene s = scene_default("decomposition: w driven towards zero");
        lf_fit *f;
        lf_fit_result res;
        lf_error err;
        fit_decomp a;
        double *ca, emax;
        size_t p;
        s.mat.w = 0.0;
        s.sim.noise = 0.01;
        scene_add(&s, 2.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
        scene_add(&s, 3.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
        scene_simulate(&s, 10);
        f = lf_fit_alloc(&s.fit, s.n, s.curve, &err);
        if (t_true(f != NULL && lf_fit_run(f, &res, &err) == LF_OK, "%s: fit", s.label)) {
            p = f->np;
            ca = malloc(p * p * sizeof *ca);
            t_int(lf_fit_decomp_alloc(&a, f->nres, p), LF_OK, "alloc");
            t_int(lf_fit_decomp_run(&a, f, f->ws.x->data, f->set.rcond), LF_OK, "%s: QR", s.label);
            cov_of(&a, ca);
            emax = cov_apart(res.cov, res.se_scale * res.se_scale, ca, p);
            t_true(res.value[0] < 1e-100 && emax < 1e-9,
                   "%s (w %.2g): the fit's covariance is the QR's (%.1e)", s.label, res.value[0],
                   emax);
            lf_fit_decomp_free(&a);
            lf_fit_result_free(&res);
            free(ca);
        }
        lf_fit_free(f);
        scene_free(&s);
    }
    {   /* two columns 1e-5 apart: cond(Js) 1.4e5, beyond the threshold */
        fit_decomp d;
        const double G[4] = { 1.0, 0.0, 1.0 - 5e-11, 1.0 }, c[2] = { 1.0, 1.0 };
        t_int(lf_fit_decomp_alloc(&d, 0, 2), LF_OK, "alloc");
        t_int(lf_fit_decomp_normal(&d, G, c, 1e-7), LF_ENUMERIC,
              "columns 1e-5 apart: J^T J refused");
        lf_fit_decomp_free(&d);
    }
}

int
main(void)
{
    gsl_set_error_handler_off();
    noise_free();
    jacobian();
    order_and_methods();
    held_and_errors();
    model_start();
    decomposition();
    return t_summary();
}
