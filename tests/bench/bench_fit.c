/* bench_fit.c: time a two-probe joint fit (2 x 300 points, k = 2
 * frictionless + k = 3 bonded, nu free, z0 and F0 free) from the automatic
 * guess, median of many runs on one core, and the same data fitted by
 * tests/bench/peer_scipy.py (scipy.optimize.least_squares) when
 * /usr/bin/python3 has scipy.  Reported, not asserted.
 * usage: bench_fit OUTDIR [REPEATS] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_errno.h>

#include "layerfit.h"

#define NPTS 300

static double
now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double) t.tv_sec + 1e-9 * (double) t.tv_nsec;
}

static int
cmp(const void *a, const void *b)
{
    double x = *(const double *) a, y = *(const double *) b;
    return (x > y) - (x < y);
}

static int
write_files(const char *dir, const lf_probe *p, double *const *depth, double *const *force)
{
    char path[1024];
    FILE *f;
    size_t i, j;

    snprintf(path, sizeof path, "%s/plan.csv", dir);
    if ((f = fopen(path, "w")) == NULL)
        return 1;
    fprintf(f, "file,k,R_m,b_m,interface,nu\n");
    for (j = 0; j < 2; j++)
        fprintf(f, "curve%zu.csv,%.17g,%.17g,%.17g,%s,\n", j + 1, p[j].k, p[j].R, p[j].b,
                p[j].base == LF_BASE_BONDED ? "bonded" : "frictionless");
    fclose(f);
    for (j = 0; j < 2; j++) {
        snprintf(path, sizeof path, "%s/curve%zu.csv", dir, j + 1);
        if ((f = fopen(path, "w")) == NULL)
            return 1;
        fprintf(f, "depth_m,force_N,segment\n");
        for (i = 0; i < NPTS; i++)
            fprintf(f, "%.17g,%.17g,unload\n", depth[j][i], force[j][i]);
        fclose(f);
    }
    return 0;
}

int
main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : "build/bench";
    int reps = argc > 2 ? atoi(argv[2]) : 300, r;
    static double d0[NPTS], d1[NPTS], f0[NPTS], f1[NPTS];
    double *depth[2] = { d0, d1 }, *force[2] = { f0, f1 }, *t;
    lf_probe p[2] = { { 2, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 },
                      { 3, 1e-3, 1e-6, LF_BASE_BONDED, LF_TIP_POWER, 0.0, 0.0 } };
    lf_material mat = { 12.3e-3, 1.85e9, 0.35 };
    lf_sim_settings sim = lf_sim_settings_default();
    lf_fit_settings set = lf_fit_settings_default();
    lf_fit_curve c[2];
    lf_fit_result res;
    lf_error err;
    char cmd[2048];
    size_t j;

    gsl_set_error_handler_off();
    memset(c, 0, sizeof c);      /* every member not set below: default */
    sim.points = NPTS;
    sim.noise = 0.005;
    sim.seed = 2024;
    sim.z0 = 15e-9;
    sim.past_c = 2.0;
    sim.delta_max = 20e-9;
    if (lf_simulate(&sim, &lf_model_thin, &mat, 2, p, depth, force, NULL, &err) != LF_OK
        || write_files(dir, p, depth, force) != 0) {
        fprintf(stderr, "bench_fit: cannot simulate or write into %s\n", dir);
        return 1;
    }
    for (j = 0; j < 2; j++) {
        c[j].name = NULL;
        c[j].n = NPTS;
        c[j].depth = depth[j];
        c[j].force = force[j];
        c[j].probe = p[j];
        c[j].branch = LF_BRANCH_UNLOAD;
        c[j].z0 = c[j].F0 = NAN;
    }
    t = malloc((size_t) reps * sizeof *t);
    if (t == NULL)
        return 1;
    for (r = 0; r < reps; r++) {
        double t0 = now();
        int st = lf_fit_driver(&set, 2, c, &res, &err);
        t[r] = now() - t0;
        if (st != LF_OK) {
            fprintf(stderr, "bench_fit: fit failed: %s\n", st == LF_ENOCONV ? res.stop_reason : err.msg);
            return 1;
        }
        if (r + 1 < reps)
            lf_fit_result_free(&res);
    }
    qsort(t, (size_t) reps, sizeof *t, cmp);
    printf("layerfit: median %.1f us over %d fits (alloc + guess + LM + covariance), %zu iterations\n",
           1e6 * t[reps / 2], reps, res.iterations);
    printf("layerfit: w = %.6g J/m^2, E* = %.6g Pa, nu = %.6g\n", res.w.value, res.Estar.value, res.nu.value);
    lf_fit_result_free(&res);
    snprintf(cmd, sizeof cmd, "/usr/bin/python3 -c 'import scipy' 2>/dev/null && "
             "/usr/bin/python3 tests/bench/peer_scipy.py %s/plan.csv %.17g", dir, t[reps / 2]);
    free(t);
    if (system(cmd) != 0)
        printf("scipy: not run (/usr/bin/python3 with scipy not found)\n");
    return 0;
}
