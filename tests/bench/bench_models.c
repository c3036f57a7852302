/* bench_models.c: speed against error of fits with the exact layer model
 * (not a test; `make bench-models`).  For a few scenes of exact-model data
 * (physics.md section 3), prints the time of the first exact-model
 * evaluation (the table builds, once per process), then the mean wall time
 * of a full fit (guess + least squares + assessment) with the thin, exact
 * and automatic models on the same data, warm table cache, and the error of
 * each fit's w and E* against the truth in standard errors; then the cost
 * of single calls on the first curve: one evaluation of its 300 points and
 * one pull-off, exact against thin (the exact model's guess in fit/
 * computes thousands of pull-offs).  The target (issue 13): an exact fit
 * within 2x the time of the thin fit once its tables exist. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_errno.h>

#include "layerfit.h"

#define NPTS 300
#define REPEAT 20

static double
now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double) t.tv_sec + 1e-9 * (double) t.tv_nsec;
}

typedef struct {
    const char *label;
    size_t n;
    lf_probe p[2];
    double nu, noise, depth;
    int fix_nu;
} bscene;

/* Mean time of one call (eval of all points, or pull-off) of a model,
 * the material's w moved a little each time as in a fit (never repeated:
 * the exact model keeps the pull-offs it computed). */
static double
call_time(lf_model *m, const lf_material *mat, const double *d, int pulloff)
{
    static lf_eval e[NPTS];
    lf_pulloff po;
    double t0 = now(), s = 0.0;
    int i, n = pulloff ? 20000 : 400;

    for (i = 0; i < n; i++) {
        lf_material mm = *mat;
        mm.w *= 1.0 + 1e-6 * i;
        if (pulloff) {
            lf_model_pulloff(m, &mm, &po, NULL);
            s += po.P_po;
        } else {
            lf_model_eval(m, &mm, LF_BRANCH_UNLOAD, NPTS, d, e, NULL);
            s += e[NPTS / 2].P;
        }
    }
    return isfinite(s) ? (now() - t0) / n : NAN;
}

static void
calls(const bscene *b, const lf_material *mat, const double *depth)
{
    static double d[NPTS];
    lf_model *mt = lf_model_alloc(&lf_model_thin, &b->p[0], NULL);
    lf_model *me = lf_model_alloc(&lf_model_exact, &b->p[0], NULL);
    double te, tt, pe, pt;
    size_t i;

    if (mt != NULL && me != NULL) {
        /* indentations from the data's depths less the simulation's z0 */
        for (i = 0; i < NPTS; i++)
            d[i] = depth[i] - 15e-9;
        tt = call_time(mt, mat, d, 0);
        te = call_time(me, mat, d, 0);
        pt = call_time(mt, mat, d, 1);
        pe = call_time(me, mat, d, 1);
        printf("%-40s one evaluation (%d points): thin %.1f us, exact %.1f us (%.1fx); "
               "one pull-off: thin %.2f us, exact %.2f us (%.1fx)\n",
               "", NPTS, 1e6 * tt, 1e6 * te, te / tt, 1e6 * pt, 1e6 * pe, pe / pt);
    }
    lf_model_free(mt);
    lf_model_free(me);
}

static void
run(const bscene *b)
{
    static double depth[2][NPTS], force[2][NPTS];
    lf_material mat = { 10e-3, 1e9, b->nu };
    lf_sim_settings sim = lf_sim_settings_default();
    lf_fit_settings set = lf_fit_settings_default();
    lf_choose_settings cs = lf_choose_settings_default();
    lf_fit_curve cv[2];
    lf_error err;
    double t0, tb, times[3] = { 0 }, ew[3] = { 0 }, eE[3] = { 0 };
    size_t nev[3] = { 0 };
    const char *names[3] = { "thin", "exact", "auto" };
    char chosen[64] = "";
    size_t j, i;
    int m, status;

    sim.noise = b->noise;
    sim.delta_max = b->depth;
    sim.z0 = 15e-9;
    sim.seed = 7;
    for (j = 0; j < b->n; j++) {
        double *dp = depth[j], *fp = force[j];
        t0 = now();
        status = lf_simulate(&sim, &lf_model_exact, &mat, 1, &b->p[j], &dp, &fp, NULL, &err);
        if (status != LF_OK) {
            printf("%s: simulate failed: %s\n", b->label, err.msg);
            return;
        }
        tb = now() - t0;
        memset(&cv[j], 0, sizeof cv[j]);
        cv[j].n = NPTS;
        cv[j].depth = depth[j];
        cv[j].force = force[j];
        cv[j].probe = b->p[j];
        cv[j].branch = LF_BRANCH_UNLOAD;
        cv[j].z0 = cv[j].F0 = NAN;
        printf("%-40s curve %zu: exact tables + simulation %.3f s\n", b->label, j + 1, tb);
    }
    if (b->fix_nu) {
        set.nu.mode = LF_PARAM_FIXED;
        set.nu.value = b->nu;
    }
    for (m = 0; m < 3; m++) {
        lf_fit_result r;
        lf_fit_settings s = set;
        s.model = m == 1 ? &lf_model_exact : &lf_model_thin;
        /* one untimed fit builds any table a fit needs (nu moves) */
        for (i = 0; i <= REPEAT; i++) {
            t0 = now();
            status = m == 2 ? lf_fit_choose_driver(&s, &cs, b->n, cv, &r, &err)
                            : lf_fit_driver(&s, b->n, cv, &r, &err);
            if (i > 0)
                times[m] += (now() - t0) / REPEAT;
            if (status != LF_OK && status != LF_ENOCONV) {
                printf("%s %s: %s\n", b->label, names[m], err.msg);
                return;
            }
            if (i == REPEAT) {
                nev[m] = r.evaluations;
                ew[m] = (r.w.value - mat.w) / r.w.se;
                eE[m] = (r.Estar.value - mat.Estar) / r.Estar.se;
                if (m == 2) {
                    size_t len = 0;
                    for (j = 0; j < b->n; j++)
                        len += (size_t) snprintf(chosen + len, sizeof chosen - len, "%s%s",
                                                 j ? "+" : "", r.curves[j].model);
                }
            }
            lf_fit_result_free(&r);
        }
    }
    printf("%-40s fit time thin %.2f ms, exact %.2f ms (%.1fx thin), auto %.2f ms [%s]\n",
           b->label, 1e3 * times[0], 1e3 * times[1], times[1] / times[0], 1e3 * times[2], chosen);
    printf("%-40s model evaluations per fit: thin %zu, exact %zu (time per evaluation %.1fx)\n",
           "", nev[0], nev[1], (times[1] / (double) nev[1]) / (times[0] / (double) nev[0]));
    printf("%-40s error in se: thin w %+.2f E* %+.2f | exact w %+.2f E* %+.2f | auto w %+.2f E* %+.2f\n",
           "", ew[0], eE[0], ew[1], eE[1], ew[2], eE[2]);
    calls(b, &mat, depth[0]);
}

int
main(void)
{
    const bscene scenes[] = {
        { "k=2 b=1um frictionless, 0.2% noise", 1,
          { { 2, 1e-3, 1e-6, LF_BASE_FRICTIONLESS } }, 0.3, 2e-3, 50e-9, 0 },
        { "k=2,3 b=1um frictionless, 0.5% noise", 2,
          { { 2, 1e-3, 1e-6, LF_BASE_FRICTIONLESS }, { 3, 1e-3, 1e-6, LF_BASE_FRICTIONLESS } },
          0.3, 5e-3, 50e-9, 0 },
        { "k=2 b=5um frictionless, 0.02% noise", 1,
          { { 2, 1e-3, 5e-6, LF_BASE_FRICTIONLESS } }, 0.3, 2e-4, 200e-9, 0 },
        { "k=2 b=1um bonded nu=0.45 held, 0.02%", 1,
          { { 2, 1e-3, 1e-6, LF_BASE_BONDED } }, 0.45, 2e-4, 50e-9, 1 },
        { "k=2 fric + k=3 bonded b=1um, nu free", 2,
          { { 2, 1e-3, 1e-6, LF_BASE_FRICTIONLESS }, { 3, 1e-3, 1e-6, LF_BASE_BONDED } },
          0.35, 2e-3, 30e-9, 0 },
    };
    size_t i;

    gsl_set_error_handler_off();
    printf("fits of %d-point exact-model curves, mean of %d, warm table cache\n", NPTS, REPEAT);
    for (i = 0; i < sizeof scenes / sizeof scenes[0]; i++)
        run(&scenes[i]);
    return 0;
}
