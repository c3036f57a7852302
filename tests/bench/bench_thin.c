/* bench_thin.c: the cost of one thin-layer model evaluation (force, contact
 * radius and the four derivatives) over 300 points of an unloading curve,
 * for the profile exponents k = 1, 1.5, 2, 3, 4 (not a test; `make
 * bench-thin`).  Prints the best of 7 repeats of 20 000 evaluations, in us
 * per evaluation: a measure of the model alone, without the fit around it. */
#include <stdio.h>
#include <time.h>

#include "layerfit.h"

#define NPTS 300
#define EVALS 20000
#define REPEATS 7

static double
now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double) t.tv_sec + 1e-9 * (double) t.tv_nsec;
}

int
main(void)
{
    static const double ks[] = { 1.0, 1.5, 2.0, 3.0, 4.0 };
    static double delta[NPTS];
    static lf_eval out[NPTS];
    double sink = 0.0;
    size_t i, j;

    for (i = 0; i < NPTS; i++)          /* a little below contact up to 4 um */
        delta[i] = -2e-7 + 4e-6 * (double) i / (NPTS - 1);
    for (j = 0; j < sizeof ks / sizeof ks[0]; j++) {
        lf_probe p = { ks[j], 1e-3, 1e-6, LF_BASE_BONDED, LF_TIP_POWER, 0.0, 0.0 };
        lf_material m = { 0.05, 1e6, 0.3 };
        lf_error err;
        lf_model *model = lf_model_alloc(&lf_model_thin, &p, &err);
        double best = 1e30;
        int r, e;

        if (model == NULL) {
            fprintf(stderr, "bench_thin: %s\n", err.msg);
            return 1;
        }
        for (r = 0; r < REPEATS; r++) {
            double t0 = now(), t;
            for (e = 0; e < EVALS; e++) {
                m.w = 0.05 * (1.0 + 1e-9 * e);
                lf_model_eval(model, &m, LF_BRANCH_UNLOAD, NPTS, delta, out, &err);
                sink += out[NPTS / 2].P;
            }
            t = (now() - t0) / EVALS * 1e6;
            best = t < best ? t : best;
        }
        printf("thin model, k = %.1f: %.2f us per %d-point evaluation\n", ks[j], best, NPTS);
        lf_model_free(model);
    }
    return sink != sink;   /* keeps the evaluations; never NaN */
}
