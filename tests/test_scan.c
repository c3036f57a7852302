/* test_scan.c: the contact-edge scan's costs (fit/edge_scan.c).  For a
 * model dearer than the thin layer's the scan takes each trial placement's
 * forces from the evaluations at the current point by cubic Hermite
 * interpolation, the model itself only near the edge and past the deepest
 * point.  Against the model evaluated at every point, on exact-model and
 * half-space curves (k = 2, 3; frictionless and bonded; unloading and
 * loading; noise 1%): at the placements the scan tries (the edge moved
 * across each of the 12 nearest points either way), each cost agrees to
 * within 2e-7 of the cost (measured: 7e-12 to 5e-8), and the placement
 * the scan would pick is the same.  Interpolation broken to linear (no
 * slopes) disagrees by 2e-5 to 1e-4 of the cost: the tolerance tells. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit.h"
#include "testlib.h"

#define NPTS 300
#define REACH 12

typedef struct {
    const char *what;
    const lf_model_type *type;
    lf_probe probe;
    lf_branch branch;
} scan_scene;

static void
check_scene(const scan_scene *sc)
{
    lf_material truth = { 10e-3, 1e9, 0.3 };
    lf_sim_settings sim = lf_sim_settings_default();
    double *depth = malloc(NPTS * sizeof *depth), *force = malloc(NPTS * sizeof *force), sigma;
    double worst = 0.0;
    lf_fit_settings set = lf_fit_settings_default();
    lf_fit_curve fc;

    set.nu.mode = LF_PARAM_FIXED;       /* the truth's: bonded layers need it */
    set.nu.value = truth.nu;
    lf_model *m;
    lf_pulloff po;
    lf_fit *f;
    lf_error err;
    gsl_vector *x;
    size_t i, pos, ord0, best_model = 0, best_interp = 0;
    double cm_best = HUGE_VAL, ci_best = HUGE_VAL, edge;
    long q;

    if (depth == NULL || force == NULL) {
        t_true(0, "%s: memory", sc->what);
        free(depth);
        free(force);
        return;
    }
    m = lf_model_alloc(sc->type, &sc->probe, &err);
    t_true(m != NULL && lf_model_pulloff(m, &truth, &po, &err) == LF_OK, "%s: model", sc->what);
    sim.points = NPTS;
    sim.noise = 0.01;
    sim.z0 = 0.37 * po.c;
    sim.F0 = 0.0;
    sim.seed = 11;
    sim.branch = sc->branch;
    if (lf_simulate(&sim, sc->type, &truth, 1, &sc->probe, &depth, &force, &sigma, &err) != LF_OK) {
        t_true(0, "%s: simulate: %s", sc->what, err.msg);
        lf_model_free(m);
        free(depth);
        free(force);
        return;
    }
    memset(&fc, 0, sizeof fc);
    fc.n = NPTS;
    fc.depth = depth;
    fc.force = force;
    fc.probe = sc->probe;
    fc.branch = sc->branch;
    fc.z0 = NAN;
    fc.F0 = NAN;
    set.model = sc->type;
    f = lf_fit_alloc(&set, 1, &fc, &err);
    x = gsl_vector_alloc(f != NULL ? f->np : 1);
    if (f == NULL || x == NULL) {
        t_true(0, "%s: alloc", sc->what);
        goto done;
    }
    /* the origin at the truth, slightly off (as a solve leaves it) */
    f->mat = truth;
    f->mat.w *= 1.03;
    f->c[0].z0 = sim.z0 + 0.05 * po.c;
    f->c[0].F0 = 1e-3 * sigma;
    lf_fit_set_origin(f);
    gsl_vector_set_all(x, 1.0);
    for (i = 0; i < f->ndata; i++)
        f->ws.sqrtw[i] = 1.0;        /* least squares, as a solve sets them */
    /* the scan's placements: the edge between points q - 1 and q in depth */
    lf_model_pulloff(m, &f->mat, &po, NULL);
    edge = sc->branch == LF_BRANCH_UNLOAD ? f->c[0].z0 + po.delta_detach : f->c[0].z0;
    for (pos = 0; pos < NPTS && depth[f->order[pos]] < edge; pos++)
        ;
    ord0 = pos;
    for (q = (long) ord0 - REACH; q <= (long) ord0 + REACH; q++) {
        double zq, z0q, cm, ci;
        if (q < 1 || q > NPTS - 1)
            continue;
        zq = 0.5 * (depth[f->order[q - 1]] + depth[f->order[q]]);
        z0q = sc->branch == LF_BRANCH_UNLOAD ? zq - po.delta_detach : zq;
        cm = lf_fit_scan_cost(f, 0, x, z0q, 0);
        ci = lf_fit_scan_cost(f, 0, x, z0q, 1);
        if (!t_true(isfinite(cm) && isfinite(ci), "%s: costs at placement %ld finite", sc->what, q))
            continue;
        worst = fmax(worst, fabs(ci - cm) / cm);
        if (cm < cm_best) {
            cm_best = cm;
            best_model = (size_t) q;
        }
        if (ci < ci_best) {
            ci_best = ci;
            best_interp = (size_t) q;
        }
    }
    t_abs(worst, 0.0, 2e-7, "%s: interpolated scan costs within 2e-7 of the model's (worst %.2g)",
          sc->what, worst);
    t_int((long) best_interp, (long) best_model, "%s: the same best placement", sc->what);
    /* x's own placement: interpolation at the data's own indentations */
    t_rel(lf_fit_scan_cost(f, 0, x, f->c[0].z0, 1), lf_fit_scan_cost(f, 0, x, f->c[0].z0, 0),
          1e-9, "%s: cost at x's own contact point", sc->what);
done:
    gsl_vector_free(x);
    lf_fit_free(f);
    lf_model_free(m);
    free(depth);
    free(force);
}

int
main(void)
{
    static const scan_scene scenes[] = {
        { "exact k=2 frictionless unload", &lf_model_exact,
          { 2.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 }, LF_BRANCH_UNLOAD },
        { "exact k=3 frictionless unload", &lf_model_exact,
          { 3.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 }, LF_BRANCH_UNLOAD },
        { "exact k=2 bonded unload (thick)", &lf_model_exact,
          { 2.0, 1e-3, 5e-6, LF_BASE_BONDED, LF_TIP_POWER, 0.0, 0.0 }, LF_BRANCH_UNLOAD },
        { "exact k=3 bonded load", &lf_model_exact,
          { 3.0, 1e-3, 1e-6, LF_BASE_BONDED, LF_TIP_POWER, 0.0, 0.0 }, LF_BRANCH_LOAD },
        { "halfspace k=2 unload", &lf_model_halfspace,
          { 2.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 }, LF_BRANCH_UNLOAD },
        { "halfspace k=3 load", &lf_model_halfspace,
          { 3.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 }, LF_BRANCH_LOAD },
        /* the thin layer's scan is interpolated at these k (edge_scan.c) */
        { "thin k=3 frictionless unload", &lf_model_thin,
          { 3.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 }, LF_BRANCH_UNLOAD },
        { "thin k=1.5 bonded load", &lf_model_thin,
          { 1.5, 1e-3, 1e-6, LF_BASE_BONDED, LF_TIP_POWER, 0.0, 0.0 }, LF_BRANCH_LOAD },
    };
    size_t i;

    for (i = 0; i < sizeof scenes / sizeof scenes[0]; i++)
        check_scene(&scenes[i]);
    return t_summary();
}
