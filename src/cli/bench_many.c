/* cli/bench_many.c: `layerfit bench --scene many-curves`, what a joint fit
 * of many curves costs: N = 2, 8, 32, 128, 512 curves of 300 points of one
 * material (four probe shapes in turn, z0 and F0 free on every curve, 1%
 * noise), each N fitted jointly over seeds, with the time per fit and per
 * data point, iterations, evaluations, the process's peak memory after
 * the N's fits, and the RMS error of w and E* over the Cramer-Rao bound.
 * Reported, not asserted. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "cli.h"

#define MANY_POINTS 300
#define MANY_NOISE 0.01

static const size_t many_sizes[] = { 2, 8, 32, 128, 512 };
#define MANY_NSIZES (sizeof many_sizes / sizeof many_sizes[0])

/* The four probe shapes, in turn: the paper's k = 2 and 3 with R = 1 mm,
 * a blunt cone-like k = 1.5 and a flat-ish k = 4; b = 1 um, frictionless. */
static const struct {
    double k, R;
} shapes[4] = { { 2.0, 1e-3 }, { 3.0, 1e-3 }, { 1.5, 5e-4 }, { 4.0, 2e-3 } };

typedef struct {
    size_t n;                        /* curves */
    lf_model **model;
    double **delta, **P, *pmax, *z0, *F0, **depth, **force;
    lf_fit_curve *fc;
    lf_design_curve *dc;
} many_data;

static void
many_free(many_data *d)
{
    size_t j;
    for (j = 0; j < d->n; j++) {
        lf_model_free(d->model[j]);
        free(d->delta[j]);
        free(d->P[j]);
        free(d->depth[j]);
        free(d->force[j]);
    }
    free(d->model);
    free(d->delta);
    free(d->P);
    free(d->pmax);
    free(d->z0);
    free(d->F0);
    free(d->depth);
    free(d->force);
    free(d->fc);
    free(d->dc);
    memset(d, 0, sizeof *d);
}

/* Every curve's truth: indentations from -0.9 c to 50 nm (the two-probe
 * scene's), z0 = 0.37 c and F0 = 1.3% of the largest force. */
static void
many_init(many_data *d, size_t n, const lf_material *truth)
{
    lf_eval *e = malloc(MANY_POINTS * sizeof *e);
    lf_error err;
    size_t j, i;

    memset(d, 0, sizeof *d);
    d->n = n;
    d->model = calloc(n, sizeof *d->model);
    d->delta = calloc(n, sizeof *d->delta);
    d->P = calloc(n, sizeof *d->P);
    d->depth = calloc(n, sizeof *d->depth);
    d->force = calloc(n, sizeof *d->force);
    d->pmax = calloc(n, sizeof *d->pmax);
    d->z0 = calloc(n, sizeof *d->z0);
    d->F0 = calloc(n, sizeof *d->F0);
    d->fc = calloc(n, sizeof *d->fc);
    d->dc = calloc(n, sizeof *d->dc);
    if (!e || !d->model || !d->delta || !d->P || !d->depth || !d->force || !d->pmax || !d->z0
        || !d->F0 || !d->fc || !d->dc)
        cli_die(CLI_EXIT_FAIL, "bench: out of memory");
    for (j = 0; j < n; j++) {
        lf_probe pr = { 0 };      /* the power law of R */
        lf_pulloff po;
        double lo;
        pr.k = shapes[j % 4].k;
        pr.R = shapes[j % 4].R;
        pr.b = 1e-6;
        pr.base = LF_BASE_FRICTIONLESS;
        d->model[j] = lf_model_alloc(&lf_model_thin, &pr, &err);
        if (d->model[j] == NULL || lf_model_pulloff(d->model[j], truth, &po, &err) != LF_OK)
            cli_die_error(CLI_EXIT_FAIL, &err);
        d->delta[j] = malloc(MANY_POINTS * sizeof(double));
        d->P[j] = malloc(MANY_POINTS * sizeof(double));
        d->depth[j] = malloc(MANY_POINTS * sizeof(double));
        d->force[j] = malloc(MANY_POINTS * sizeof(double));
        if (!d->delta[j] || !d->P[j] || !d->depth[j] || !d->force[j])
            cli_die(CLI_EXIT_FAIL, "bench: out of memory");
        lo = -0.9 * po.c;
        for (i = 0; i < MANY_POINTS; i++)     /* deep to shallow, as retracted */
            d->delta[j][i] = 50e-9 - (50e-9 - lo) * (double) i / (double) (MANY_POINTS - 1);
        if (lf_model_eval(d->model[j], truth, LF_BRANCH_UNLOAD, MANY_POINTS, d->delta[j], e,
                          &err) != LF_OK)
            cli_die_error(CLI_EXIT_FAIL, &err);
        for (i = 0; i < MANY_POINTS; i++) {
            d->P[j][i] = e[i].P;
            d->pmax[j] = fmax(d->pmax[j], fabs(e[i].P));
        }
        d->z0[j] = 0.37 * po.c;
        d->F0[j] = 0.013 * d->pmax[j];
        d->fc[j].n = MANY_POINTS;
        d->fc[j].depth = d->depth[j];
        d->fc[j].force = d->force[j];
        d->fc[j].probe = pr;
        d->fc[j].branch = LF_BRANCH_UNLOAD;
        d->fc[j].z0 = d->fc[j].F0 = NAN;
        d->dc[j].model = d->model[j];
        d->dc[j].branch = LF_BRANCH_UNLOAD;
        d->dc[j].n = MANY_POINTS;
        d->dc[j].delta = d->delta[j];
        d->dc[j].sigma = MANY_NOISE * d->pmax[j];
        d->dc[j].free_z0 = d->dc[j].free_F0 = 1;
    }
    free(e);
}

static void
many_draw(many_data *d, gsl_rng *rng, unsigned long seed)
{
    size_t j, i;

    gsl_rng_set(rng, seed);
    for (j = 0; j < d->n; j++)
        for (i = 0; i < MANY_POINTS; i++) {
            d->depth[j][i] = d->delta[j][i] + d->z0[j];
            d->force[j][i] = d->P[j][i] + d->F0[j]
                             + gsl_ran_gaussian_ziggurat(rng, MANY_NOISE * d->pmax[j]);
        }
}

static int
cmp_double(const void *a, const void *b)
{
    double x = *(const double *) a, y = *(const double *) b;
    return (x > y) - (x < y);
}

int
cli_bench_many(size_t seeds_max, int quick)
{
    const lf_material truth = { 10e-3, 1e9, 0.3 };
    const lf_fit_settings set = lf_fit_settings_default();
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    size_t si, nsizes = quick ? MANY_NSIZES - 1 : MANY_NSIZES;
    double t_start = cli_now();

    if (rng == NULL)
        cli_die(CLI_EXIT_FAIL, "bench: out of memory");
    printf("layerfit %s bench --scene many-curves%s: joint fits of N curves of %d points, "
           "one material\n(w = 10 mJ/m^2, E* = 1 GPa; probes k = 2, 3 (R = 1 mm), 1.5 "
           "(0.5 mm), 4 (2 mm) in turn, b = 1 um,\nfrictionless; z0 and F0 free on every "
           "curve; %g%% noise; thin-layer model, default settings).\n"
           "ms/fit: median wall time of one fit (alloc, guess, solve, assessment); us/point:\n"
           "that over the data points; peak MB: the process's peak resident memory after the\n"
           "N's fits; err/CRB: RMS relative error over the Cramer-Rao bound (1 = efficient).\n\n",
           LF_VERSION, quick ? " --quick" : "", MANY_POINTS, 100 * MANY_NOISE);
    printf("%5s %7s %5s %10s %8s %6s %6s %5s %8s %6s %8s %6s %8s\n", "N", "points", "seeds",
           "ms/fit", "us/point", "iter", "nfev", "conv", "w err", "/CRB", "E* err", "/CRB",
           "peak MB");
    for (si = 0; si < nsizes; si++) {
        const size_t n = many_sizes[si];
        size_t seeds = 4096 / n < 16 ? 16 : 4096 / n > 100 ? 100 : 4096 / n, k, nconv = 0;
        double *times, it = 0, ev = 0, sw = 0, sE = 0;
        lf_crb_result crb;
        lf_error err;
        many_data d;
        struct rusage ru;

        if (quick)
            seeds = seeds / 4 < 2 ? 2 : seeds / 4;
        if (seeds_max > 0 && seeds > seeds_max)
            seeds = seeds_max;
        many_init(&d, n, &truth);
        if (lf_crb(d.dc, n, &truth, 0, &crb, &err) != LF_OK)
            cli_die(CLI_EXIT_FAIL, "bench: many-curves: Cramer-Rao bound: %s", err.msg);
        times = malloc(seeds * sizeof *times);
        if (times == NULL)
            cli_die(CLI_EXIT_FAIL, "bench: out of memory");
        for (k = 0; k < seeds; k++) {
            lf_fit_result res;
            double t0;
            int st;
            many_draw(&d, rng, 1UL + 7919UL * (unsigned long) n + 104729UL * (unsigned long) k);
            t0 = cli_now();
            st = lf_fit_driver(&set, n, d.fc, &res, &err);
            times[k] = cli_now() - t0;
            if (st != LF_OK && st != LF_ENOCONV)
                continue;
            it += (double) res.iterations;
            ev += (double) res.evaluations;
            if (st == LF_OK && res.converged) {
                double ew = cli_fitted_value(&res, "w") / truth.w - 1.0;
                double eE = cli_fitted_value(&res, "E*") / truth.Estar - 1.0;
                nconv++;
                sw += ew * ew;
                sE += eE * eE;
            }
            lf_fit_result_free(&res);
        }
        qsort(times, seeds, sizeof *times, cmp_double);
        getrusage(RUSAGE_SELF, &ru);
        {
            const double t = seeds % 2 ? times[seeds / 2]
                                       : 0.5 * (times[seeds / 2 - 1] + times[seeds / 2]);
            const double ew = nconv ? sqrt(sw / (double) nconv) : NAN;
            const double eE = nconv ? sqrt(sE / (double) nconv) : NAN;
            printf("%5zu %7zu %5zu %10.2f %8.2f %6.1f %6.1f %5.2f %7.3f%% %6.2f %7.4f%% %6.2f "
                   "%8.1f\n", n, n * MANY_POINTS, seeds, 1e3 * t,
                   1e6 * t / (double) (n * MANY_POINTS), it / (double) seeds,
                   ev / (double) seeds, (double) nconv / (double) seeds, 100 * ew,
                   ew / crb.sd_logw, 100 * eE, eE / crb.sd_logE, (double) ru.ru_maxrss / 1024.0);
            fflush(stdout);
        }
        free(times);
        many_free(&d);
    }
    printf("\ntotal bench time %.1f s\n", cli_now() - t_start);
    gsl_rng_free(rng);
    return CLI_EXIT_OK;
}
