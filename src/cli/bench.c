/* cli/bench.c: `layerfit bench`, what a fit costs and how accurate it is.
 *
 * Synthetic experiments (scenes) are drawn from the thin-layer model of the
 * seed paper with Gaussian force noise, fitted many times over deterministic
 * seeds, and summarised per configuration: median time per fit, iterations,
 * model evaluations, the fraction that converged, the RMS relative error of
 * w and E* (absolute for nu) and that error over the Cramer-Rao bound at the
 * truth (lf_crb with the same nuisance parameters free as the fit; 1.0 is
 * the best an unbiased estimator can do).  Configurations vary one factor at
 * a time around a baseline (lm, analytic Jacobian, automatic guess, 300
 * points per curve): a full cross product would be too large to read.
 *
 * Also measured: the cost floor (one model + Jacobian evaluation over the
 * same data), the throughput of independent single-curve fits on one core
 * and on all cores (OpenMP), and, when Debian's python3-scipy is present,
 * scipy.optimize.least_squares on the same data (tests/bench/peer_scipy.py).
 */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "cli.h"
#include "plot.h"

static const char bench_help[] =
    "usage: layerfit bench [--quick] [--csv FILE] [--plot FILE.svg|FILE.png] [options]\n"
    "\n"
    "Fits synthetic curves of known truth many times and prints, per scene,\n"
    "noise level and configuration, the median time per fit, iterations and\n"
    "model evaluations per fit, the fraction of fits that converged, the RMS\n"
    "relative error of w and E* (absolute error of nu) and that error divided by\n"
    "the Cramer-Rao bound at the truth (1.0: the best any unbiased estimator\n"
    "can do).  Configurations vary one factor at a time around the baseline\n"
    "(lm, analytic Jacobian, automatic guess, 300 points per curve).\n"
    "Then the cost floor (one model + Jacobian evaluation), the throughput of\n"
    "independent single-curve fits on one core and on all cores, and the\n"
    "same data fitted by scipy.optimize.least_squares when /usr/bin/python3\n"
    "has scipy.  Seeds are fixed: two runs fit the same data.\n"
    "\n"
    "  --quick            few seeds and a small batch (for CI: seconds)\n"
    "  --seeds N          seeds per row (default 200, --quick 10)\n"
    "  --batch N          curves in the throughput batch (default 4096, --quick 256)\n"
    "  --scene NAME       only this scene (two-probe, paper-offsets, mixed-nu,\n"
    "                     soft-coating, single-k2)\n"
    "  --csv FILE         write the table as CSV (SI, one row per scene/noise/config)\n"
    "  --plot FILE        draw error against time per fit (log-log) with gnuplot\n"
    "  --scipy SCRIPT     the peer script (default tests/bench/peer_scipy.py, found\n"
    "                     next to the working directory or the program)\n"
    "  --no-scipy         skip the scipy comparison\n"
    "  --coverage         instead: how often the 95% intervals (linear or profile\n"
    "                     likelihood, as `layerfit fit` makes them) hold the truth, and\n"
    "                     the RMS error over the Cramer-Rao bound (--seeds N, default\n"
    "                     200; --scene paper-offsets, mixed-nu or soft-coating)\n"
    "  --calibrate        with --coverage: profile thresholds calibrated by a\n"
    "                     parametric bootstrap (200 refits per profile; slow)\n";

#define MAXC 3           /* curves per scene at most */
#define PYTHON "/usr/bin/python3"

/* ---- scenes ---------------------------------------------------------- */

typedef struct {
    const char *name;
    const char *what;
    size_t ncurves;
    lf_probe probe[MAXC];
    lf_material truth;
    double lo_c;          /* shallowest indentation, in units of -c of curve 1 */
    double delta_max;     /* deepest indentation, m */
    int free_offsets;     /* z0 and F0 fitted on every curve */
} bench_scene;

#define PAPER_PROBE(k, base) { k, 1e-3, 1e-6, base, LF_TIP_POWER, 0.0, 0.0 }

static const bench_scene scenes[] = {
    { "two-probe", "k = 2, 3; R = 1 mm; b = 1 um; frictionless; w = 10 mJ/m^2, E* = 1 GPa; "
      "delta -0.9c..50 nm; z0, F0 known",
      2, { PAPER_PROBE(2.0, LF_BASE_FRICTIONLESS), PAPER_PROBE(3.0, LF_BASE_FRICTIONLESS) },
      { 10e-3, 1e9, 0.3 }, 0.9, 50e-9, 0 },
    { "paper-offsets", "the two-probe scene (the paper's probes) with z0 and F0 free",
      2, { PAPER_PROBE(2.0, LF_BASE_FRICTIONLESS), PAPER_PROBE(3.0, LF_BASE_FRICTIONLESS) },
      { 10e-3, 1e9, 0.3 }, 0.9, 50e-9, 1 },
    { "mixed-nu", "k = 2 frictionless + k = 3 bonded, nu = 0.3 (nu determined); paper's "
      "w, E*, R, b; z0, F0 known",
      2, { PAPER_PROBE(2.0, LF_BASE_FRICTIONLESS), PAPER_PROBE(3.0, LF_BASE_BONDED) },
      { 10e-3, 1e9, 0.3 }, 0.9, 50e-9, 0 },
    { "soft-coating", "k = 2, 3; R = 5 mm; b = 20 um; w = 40 mJ/m^2, E* = 2 MPa; "
      "delta -1.2c..3 um (baseline seen); z0, F0 free",
      2, { { 2.0, 5e-3, 20e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 }, { 3.0, 5e-3, 20e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 } },
      { 40e-3, 2e6, 0.3 }, 1.2, 3e-6, 1 },
    { "single-k2", "one k = 2 curve, paper's numbers, delta -0.9c..50 nm; z0, F0 known",
      1, { PAPER_PROBE(2.0, LF_BASE_FRICTIONLESS) },
      { 10e-3, 1e9, 0.3 }, 0.9, 50e-9, 0 },
};
#define NSCENES (sizeof scenes / sizeof scenes[0])

static const double noise_levels[] = { 0.001, 0.01, 0.05 };
#define NNOISE (sizeof noise_levels / sizeof noise_levels[0])

/* True offsets of the scenes that fit them (in units of c and max |P|). */
#define Z0_TRUE_C 0.37
#define F0_TRUE_P 0.013

static int
scene_free_nu(const bench_scene *s)
{
    return cli_probes_free_nu(s->probe, s->ncurves);
}

/* ---- configurations -------------------------------------------------- */

typedef enum { GUESS_AUTO = 0, GUESS_NAIVE } guess_kind;

typedef struct {
    const char *factor;      /* "baseline", "method", "jacobian", "guess", "points" */
    const char *label;       /* for the table */
    const char *method;
    lf_jacobian jacobian;
    guess_kind guess;
    size_t points;
} bench_config;

#define BASE_POINTS 300

static const bench_config configs[] = {
    { "baseline", "baseline", "lm", LF_JAC_ANALYTIC, GUESS_AUTO, BASE_POINTS },
    { "method", "lmaccel", "lmaccel", LF_JAC_ANALYTIC, GUESS_AUTO, BASE_POINTS },
    { "method", "dogleg", "dogleg", LF_JAC_ANALYTIC, GUESS_AUTO, BASE_POINTS },
    { "method", "ddogleg", "ddogleg", LF_JAC_ANALYTIC, GUESS_AUTO, BASE_POINTS },
    { "method", "subspace2D", "subspace2D", LF_JAC_ANALYTIC, GUESS_AUTO, BASE_POINTS },
    { "jacobian", "jac=forward", "lm", LF_JAC_FORWARD, GUESS_AUTO, BASE_POINTS },
    { "jacobian", "jac=central", "lm", LF_JAC_CENTRAL, GUESS_AUTO, BASE_POINTS },
    { "guess", "guess=naive3x", "lm", LF_JAC_ANALYTIC, GUESS_NAIVE, BASE_POINTS },
    { "points", "points=100", "lm", LF_JAC_ANALYTIC, GUESS_AUTO, 100 },
    { "points", "points=1000", "lm", LF_JAC_ANALYTIC, GUESS_AUTO, 1000 },
    { "points", "points=3000", "lm", LF_JAC_ANALYTIC, GUESS_AUTO, 3000 },
};
#define NCONFIGS (sizeof configs / sizeof configs[0])

static const char *
jacobian_name(lf_jacobian j)
{
    return j == LF_JAC_ANALYTIC ? "analytic" : j == LF_JAC_FORWARD ? "forward" : "central";
}

/* ---- timing and small statistics ------------------------------------- */

static int
cmp_double(const void *a, const void *b)
{
    double x = *(const double *) a, y = *(const double *) b;
    return (x > y) - (x < y);
}

static double
median(double *v, size_t n)
{
    if (n == 0)
        return NAN;
    qsort(v, n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* ---- synthetic data of one scene at one size ------------------------- */

typedef struct {
    const bench_scene *scene;
    size_t n;                    /* points per curve */
    lf_model *model[MAXC];
    double *delta[MAXC];         /* true indentations */
    double *P[MAXC];             /* true forces */
    double pmax[MAXC];           /* max |P| */
    double z0[MAXC], F0[MAXC];   /* true offsets */
    double *depth[MAXC], *force[MAXC];   /* one noisy draw */
    double sigma[MAXC];
    lf_fit_curve fc[MAXC];
} bench_data;

static void
data_free(bench_data *d)
{
    size_t j;
    for (j = 0; j < MAXC; j++) {
        lf_model_free(d->model[j]);
        free(d->delta[j]);
        free(d->P[j]);
        free(d->depth[j]);
        free(d->force[j]);
    }
    memset(d, 0, sizeof *d);
}

/* Truth of scene s with n points per curve: indentations evenly spaced from
 * -lo_c c to delta_max (c of each curve), unloading. */
static void
data_init(bench_data *d, const bench_scene *s, size_t n)
{
    lf_error err;
    lf_eval *e = malloc(n * sizeof *e);
    size_t i, j;

    memset(d, 0, sizeof *d);
    d->scene = s;
    d->n = n;
    if (e == NULL)
        cli_die(CLI_EXIT_FAIL, "bench: out of memory");
    for (j = 0; j < s->ncurves; j++) {
        lf_pulloff po;
        double lo;
        d->model[j] = lf_model_alloc(&lf_model_thin, &s->probe[j], &err);
        if (d->model[j] == NULL || lf_model_pulloff(d->model[j], &s->truth, &po, &err) != LF_OK)
            cli_die_error(CLI_EXIT_FAIL, &err);
        d->delta[j] = malloc(n * sizeof(double));
        d->P[j] = malloc(n * sizeof(double));
        d->depth[j] = malloc(n * sizeof(double));
        d->force[j] = malloc(n * sizeof(double));
        if (!d->delta[j] || !d->P[j] || !d->depth[j] || !d->force[j])
            cli_die(CLI_EXIT_FAIL, "bench: out of memory");
        lo = -s->lo_c * po.c;
        /* written deep to shallow, as a retraction is recorded */
        for (i = 0; i < n; i++)
            d->delta[j][i] = s->delta_max - (s->delta_max - lo) * (double) i / (double) (n - 1);
        if (lf_model_eval(d->model[j], &s->truth, LF_BRANCH_UNLOAD, n, d->delta[j], e, &err) != LF_OK)
            cli_die_error(CLI_EXIT_FAIL, &err);
        d->pmax[j] = 0.0;
        for (i = 0; i < n; i++) {
            d->P[j][i] = e[i].P;
            d->pmax[j] = fmax(d->pmax[j], fabs(e[i].P));
        }
        d->z0[j] = s->free_offsets ? Z0_TRUE_C * po.c : 0.0;
        d->F0[j] = s->free_offsets ? F0_TRUE_P * d->pmax[j] : 0.0;
        d->fc[j].name = NULL;
        d->fc[j].n = n;
        d->fc[j].depth = d->depth[j];
        d->fc[j].force = d->force[j];
        d->fc[j].probe = s->probe[j];
        d->fc[j].branch = LF_BRANCH_UNLOAD;
        d->fc[j].z0 = s->free_offsets ? NAN : 0.0;
        d->fc[j].F0 = s->free_offsets ? NAN : 0.0;
    }
    free(e);
}

/* The seed of one draw: the same data for every configuration with the same
 * number of points (common random numbers make the rows comparable). */
static unsigned long
draw_seed(size_t scene, size_t noise, size_t n, size_t seed)
{
    return 1UL + 1000003UL * (unsigned long) scene + 10007UL * (unsigned long) noise
           + 7UL * (unsigned long) n + 100000007UL * (unsigned long) seed;
}

/* One noisy draw into d->depth, d->force (noise level rel of max |P|). */
static void
data_draw(bench_data *d, gsl_rng *rng, unsigned long seed, double rel)
{
    size_t i, j;

    gsl_rng_set(rng, seed);
    for (j = 0; j < d->scene->ncurves; j++) {
        d->sigma[j] = rel * d->pmax[j];
        for (i = 0; i < d->n; i++) {
            d->depth[j][i] = d->delta[j][i] + d->z0[j];
            d->force[j][i] = d->P[j][i] + d->F0[j] + gsl_ran_gaussian_ziggurat(rng, d->sigma[j]);
        }
    }
}

/* The Cramer-Rao bound of the scene at noise level rel. */
static int
data_crb(const bench_data *d, double rel, lf_crb_result *r, lf_error *err)
{
    lf_design_curve dc[MAXC];
    size_t j;

    for (j = 0; j < d->scene->ncurves; j++) {
        dc[j].model = d->model[j];
        dc[j].branch = LF_BRANCH_UNLOAD;
        dc[j].n = d->n;
        dc[j].delta = d->delta[j];
        dc[j].sigma = rel * d->pmax[j];
        dc[j].free_z0 = d->scene->free_offsets;
        dc[j].free_F0 = d->scene->free_offsets;
    }
    return lf_crb(dc, d->scene->ncurves, &d->scene->truth, scene_free_nu(d->scene), r, err);
}

/* Median time of one model + Jacobian evaluation over all the scene's
 * points (lf_model_eval returns P and its derivatives together), s. */
static double
eval_cost(const bench_data *d)
{
    enum { BATCHES = 7 };
    lf_eval *e = malloc(d->n * sizeof *e);
    double per[BATCHES], t0, t;
    size_t reps = 1, r, j;
    int b;

    if (e == NULL)
        cli_die(CLI_EXIT_FAIL, "bench: out of memory");
    for (;;) {      /* enough repetitions for half a millisecond */
        t0 = cli_now();
        for (r = 0; r < reps; r++)
            for (j = 0; j < d->scene->ncurves; j++)
                lf_model_eval(d->model[j], &d->scene->truth, LF_BRANCH_UNLOAD, d->n,
                              d->delta[j], e, NULL);
        t = cli_now() - t0;
        if (t > 5e-4 || reps > (1u << 24))
            break;
        reps *= 2;
    }
    for (b = 0; b < BATCHES; b++) {
        t0 = cli_now();
        for (r = 0; r < reps; r++)
            for (j = 0; j < d->scene->ncurves; j++)
                lf_model_eval(d->model[j], &d->scene->truth, LF_BRANCH_UNLOAD, d->n,
                              d->delta[j], e, NULL);
        per[b] = (cli_now() - t0) / (double) reps;
    }
    free(e);
    return median(per, BATCHES);
}

/* ---- one row: a scene, a noise level, a configuration ---------------- */

typedef struct {
    size_t scene, noise, config;
    size_t seeds;
    double time_us;          /* median wall time of one fit (alloc, run, free) */
    double eval_us;          /* one model + Jacobian evaluation */
    double iterations, evaluations;  /* means per fit */
    double converged;        /* fraction */
    double w_determined;     /* fraction reporting w as a value, not a bound */
    double err_w, err_E, err_nu;     /* RMS relative (nu: absolute) over converged */
    double crb_w, crb_E, crb_nu;
    int nu_free;
    char first_error[200];   /* the first failure's message, if any */
} bench_row;

static void
settings_for(const bench_config *c, const bench_scene *s, lf_fit_settings *set)
{
    *set = lf_fit_settings_default();
    set->method = c->method;
    set->jacobian = c->jacobian;
    if (c->guess == GUESS_NAIVE) {
        /* a factor of 3 off in both, in the direction that hurts most:
         * more adhesion and a softer layer than the truth (nu, where
         * fitted, from the middle of its range) */
        set->w.guess = 3.0 * s->truth.w;
        set->Estar.guess = s->truth.Estar / 3.0;
        set->nu.guess = 0.25;
    }
}

static void
run_row(bench_row *row, bench_data *d, gsl_rng *rng, size_t nseeds)
{
    const bench_scene *s = d->scene;
    const bench_config *c = &configs[row->config];
    double rel = noise_levels[row->noise];
    double *times = malloc(nseeds * sizeof *times);
    double sw = 0, sE = 0, snu = 0, it = 0, ev = 0;
    size_t k, nconv = 0, ndet = 0;
    lf_fit_settings set;
    lf_crb_result crb;
    lf_error err;

    if (times == NULL)
        cli_die(CLI_EXIT_FAIL, "bench: out of memory");
    settings_for(c, s, &set);
    if (data_crb(d, rel, &crb, &err) != LF_OK)
        cli_die(CLI_EXIT_FAIL, "bench: %s: Cramer-Rao bound: %s", s->name, err.msg);
    row->crb_w = crb.sd_logw;
    row->crb_E = crb.sd_logE;
    row->crb_nu = crb.sd_nu;
    row->nu_free = scene_free_nu(s);
    row->first_error[0] = '\0';
    for (k = 0; k < nseeds; k++) {
        lf_fit_result res;
        int st;
        double t0;

        data_draw(d, rng, draw_seed(row->scene, row->noise, d->n, k), rel);
        t0 = cli_now();
        st = lf_fit_driver(&set, s->ncurves, d->fc, &res, &err);
        times[k] = cli_now() - t0;
        if (st == LF_OK || st == LF_ENOCONV) {
            it += (double) res.iterations;
            ev += (double) res.evaluations;
        }
        if (st == LF_OK && res.converged) {
            /* the point estimates, also where the report gives w only as an
             * upper bound: leaving those out would select the lucky seeds */
            double ew = cli_fitted_value(&res, "w") / s->truth.w - 1.0;
            double eE = cli_fitted_value(&res, "E*") / s->truth.Estar - 1.0;
            nconv++;
            ndet += res.w.determined != 0;
            sw += ew * ew;
            sE += eE * eE;
            if (row->nu_free) {
                double en = cli_fitted_value(&res, "nu") - s->truth.nu;
                snu += en * en;
            }
        } else if (row->first_error[0] == '\0') {
            snprintf(row->first_error, sizeof row->first_error, "seed %zu: %.150s", k,
                     st == LF_OK || st == LF_ENOCONV ? res.stop_reason : err.msg);
        }
        if (st == LF_OK || st == LF_ENOCONV)
            lf_fit_result_free(&res);
    }
    row->seeds = nseeds;
    row->time_us = 1e6 * median(times, nseeds);
    row->iterations = it / (double) nseeds;
    row->evaluations = ev / (double) nseeds;
    row->converged = (double) nconv / (double) nseeds;
    row->w_determined = (double) ndet / (double) nseeds;
    row->err_w = nconv ? sqrt(sw / (double) nconv) : NAN;
    row->err_E = nconv ? sqrt(sE / (double) nconv) : NAN;
    row->err_nu = nconv && row->nu_free ? sqrt(snu / (double) nconv) : NAN;
    free(times);
}

/* ---- throughput ------------------------------------------------------ */

typedef struct {
    size_t batch;
    int threads;
    double serial_per_s, parallel_per_s;
    size_t serial_conv, parallel_conv;
} bench_throughput;

/* Fit the n single-curve problems fc independently on `threads` threads;
 * returns how many converged. */
static size_t
fit_all(const lf_fit_settings *set, const lf_fit_curve *fc, size_t n, int threads)
{
    long i, nb = (long) n, conv = 0;

#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) schedule(dynamic, 8) reduction(+:conv)
#endif
    for (i = 0; i < nb; i++) {
        lf_fit_result res;
        int st = lf_fit_driver(set, 1, &fc[i], &res, NULL);
        conv += st == LF_OK;
        if (st == LF_OK || st == LF_ENOCONV)
            lf_fit_result_free(&res);
    }
    (void) threads;
    return (size_t) conv;
}

/* Fit `batch` independent single-curve problems (scene single-k2, 1%
 * noise, 300 points), once on one thread and once on all. */
static void
run_throughput(bench_throughput *tp, size_t batch)
{
    const bench_scene *s = &scenes[NSCENES - 1];
    size_t n = BASE_POINTS, b;
    bench_data d;
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    double *depth = malloc(batch * n * sizeof *depth);
    double *force = malloc(batch * n * sizeof *force);
    lf_fit_curve *fc = malloc(batch * sizeof *fc);
    lf_fit_settings set = lf_fit_settings_default();
    double t0;

    if (rng == NULL || depth == NULL || force == NULL || fc == NULL)
        cli_die(CLI_EXIT_FAIL, "bench: out of memory");
    data_init(&d, s, n);
    for (b = 0; b < batch; b++) {
        data_draw(&d, rng, draw_seed(NSCENES - 1, 1, n, 1000000 + b), 0.01);
        memcpy(depth + b * n, d.depth[0], n * sizeof *depth);
        memcpy(force + b * n, d.force[0], n * sizeof *force);
        fc[b] = d.fc[0];
        fc[b].depth = depth + b * n;
        fc[b].force = force + b * n;
    }
    tp->batch = batch;
#ifdef _OPENMP
    tp->threads = omp_get_max_threads();
#else
    tp->threads = 1;
#endif
    t0 = cli_now();
    tp->serial_conv = fit_all(&set, fc, batch, 1);
    tp->serial_per_s = (double) batch / (cli_now() - t0);
    t0 = cli_now();
    tp->parallel_conv = fit_all(&set, fc, batch, tp->threads);
    tp->parallel_per_s = (double) batch / (cli_now() - t0);
    data_free(&d);
    gsl_rng_free(rng);
    free(depth);
    free(force);
    free(fc);
}

/* ---- scipy.optimize.least_squares on the same data ------------------- */

/* The peers of tests/bench/peer_scipy.py, in its order; the first is the
 * headline (scipy's most favourable case: MINPACK's LM from the truth). */
static const char *const peer_names[] = { "lm-truth", "trf-truth", "lm-auto", "trf-auto",
                                          "lmfit-truth" };
#define NPEER (sizeof peer_names / sizeof peer_names[0])

typedef struct {
    int ran;
    char note[300];
    double time_us[NPEER][NSCENES][NNOISE];
    double err_w[NPEER][NSCENES][NNOISE], err_E[NPEER][NSCENES][NNOISE];
    double err_nu[NPEER][NSCENES][NNOISE];
    double conv[NPEER][NSCENES][NNOISE];
} bench_peer;

static int
file_exists(const char *p)
{
    return access(p, R_OK) == 0;
}

/* The peer script: the one given, or tests/bench/peer_scipy.py under the
 * working directory or above the program (build/layerfit). */
static int
find_script(const char *given, char *out, size_t n)
{
    char exe[4096];
    ssize_t len;
    char *slash;

    if (given != NULL) {
        snprintf(out, n, "%s", given);
        return file_exists(out);
    }
    snprintf(out, n, "tests/bench/peer_scipy.py");
    if (file_exists(out))
        return 1;
    len = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (len > 0) {
        exe[len] = '\0';
        slash = strrchr(exe, '/');
        if (slash != NULL) {
            *slash = '\0';
            snprintf(out, n, "%s/../tests/bench/peer_scipy.py", exe);
            if (file_exists(out))
                return 1;
        }
    }
    return 0;
}

/* Write the baseline data of every scene and noise level to dir/case_S_N.txt
 * for the peer: a header of "# key value" lines, then "seed curve z F". */
static void
write_peer_case(const char *dir, size_t si, size_t ni, size_t nseeds, gsl_rng *rng,
                bench_data *d)
{
    char path[4200];
    FILE *f;
    size_t j, k, i;
    int fd;
    const bench_scene *s = d->scene;

    snprintf(path, sizeof path, "%s/case_%zu_%zu.txt", dir, si, ni);
    /* a new file in layerfit's own temporary folder: made, never opened */
    fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    f = fd >= 0 ? fdopen(fd, "w") : NULL;
    if (f == NULL)
        cli_die(CLI_EXIT_FAIL, "bench: cannot write %s: %s", path, strerror(errno));
    fprintf(f, "# scene %s\n# noise %.17g\n# truth %.17g %.17g %.17g\n# free_nu %d\n"
               "# free_offsets %d\n# seeds %zu\n# ncurves %zu\n",
            s->name, noise_levels[ni], s->truth.w, s->truth.Estar, s->truth.nu,
            scene_free_nu(s), s->free_offsets, nseeds, s->ncurves);
    for (j = 0; j < s->ncurves; j++)
        fprintf(f, "# curve %zu %.17g %.17g %.17g %s\n# offsets %zu %.17g %.17g\n", j,
                s->probe[j].k, s->probe[j].R, s->probe[j].b, cli_base_name(s->probe[j].base),
                j, d->z0[j], d->F0[j]);
    for (k = 0; k < nseeds; k++) {
        data_draw(d, rng, draw_seed(si, ni, d->n, k), noise_levels[ni]);
        for (j = 0; j < s->ncurves; j++)
            for (i = 0; i < d->n; i++)
                fprintf(f, "%zu %zu %.17g %.17g\n", k, j, d->depth[j][i], d->force[j][i]);
    }
    if (fclose(f) != 0)
        cli_die(CLI_EXIT_FAIL, "bench: cannot write %s", path);
}

static void
run_peer(bench_peer *peer, const char *script_opt, const int *use_scene, size_t nseeds)
{
    char script[4200], dir[] = "/tmp/layerfit-bench-XXXXXX", line[512];
    gsl_rng *rng;
    cli_child child;
    FILE *p;
    size_t si, ni, q;
    int rc, slot;

    memset(peer, 0, sizeof *peer);
    for (q = 0; q < NPEER; q++)
        for (si = 0; si < NSCENES; si++)
            for (ni = 0; ni < NNOISE; ni++)
                peer->time_us[q][si][ni] = peer->err_w[q][si][ni] = peer->err_E[q][si][ni]
                    = peer->err_nu[q][si][ni] = peer->conv[q][si][ni] = NAN;
    if (!find_script(script_opt, script, sizeof script)) {
        snprintf(peer->note, sizeof peer->note, "skipped: peer script %.250s not found", script);
        return;
    }
    {
        static const char *const check[] = { PYTHON, "-c", "import scipy.optimize", NULL };
        cli_child c;
        if (!file_exists(PYTHON) || cli_spawn(&c, check, NULL, CLI_SPAWN_QUIET) != 0
            || cli_child_wait(&c) != 0) {
            snprintf(peer->note, sizeof peer->note,
                     "skipped: " PYTHON " has no scipy (apt-get install python3-scipy)");
            return;
        }
    }
    if (mkdtemp(dir) == NULL)
        cli_die(CLI_EXIT_FAIL, "bench: cannot make a temporary directory: %s", strerror(errno));
    slot = cli_temp_add(dir, 1);
    rng = gsl_rng_alloc(gsl_rng_mt19937);
    if (rng == NULL)
        cli_die(CLI_EXIT_FAIL, "bench: out of memory");
    for (si = 0; si < NSCENES; si++) {
        bench_data d;
        if (!use_scene[si])
            continue;
        data_init(&d, &scenes[si], BASE_POINTS);
        for (ni = 0; ni < NNOISE; ni++)
            write_peer_case(dir, si, ni, nseeds, rng, &d);
        data_free(&d);
    }
    gsl_rng_free(rng);
    {
        /* the script and the folder are arguments, never a command line */
        const char *argv[] = { PYTHON, script, dir, NULL };
        if (cli_spawn(&child, argv, NULL, CLI_SPAWN_STDOUT | CLI_SPAWN_STDERR_TO_OUT) != 0)
            cli_die(CLI_EXIT_FAIL, "bench: cannot run %s: %s", PYTHON, strerror(errno));
        p = child.out;
    }
    /* "case S N time_us err_w err_E err_nu conv PEER" per case and peer;
     * other lines are kept as the note when the script fails */
    while (fgets(line, sizeof line, p) != NULL) {
        size_t a, b;
        double t, ew, eE, en, cv;
        char name[64];
        if (sscanf(line, "case %zu %zu %lf %lf %lf %lf %lf %63s", &a, &b, &t, &ew, &eE, &en, &cv,
                   name) == 8 && a < NSCENES && b < NNOISE) {
            for (q = 0; q < NPEER && strcmp(name, peer_names[q]) != 0; q++)
                ;
            if (q == NPEER)
                continue;
            peer->time_us[q][a][b] = t;
            peer->err_w[q][a][b] = ew;
            peer->err_E[q][a][b] = eE;
            peer->err_nu[q][a][b] = en;
            peer->conv[q][a][b] = cv;
            peer->ran = 1;
        } else {
            /* anything else is the script complaining: pass it on */
            line[strcspn(line, "\n")] = '\0';
            cli_say("peer_scipy.py: %s", line);
            snprintf(peer->note, sizeof peer->note, "%.290s", line);
        }
    }
    rc = cli_child_wait(&child);
    if (cli_remove_tree(dir) != 0)
        cli_say("warning: could not remove %s", dir);
    cli_temp_forget(slot);
    if (rc != 0) {
        peer->ran = 0;
        if (peer->note[0] == '\0')
            snprintf(peer->note, sizeof peer->note, "the peer script failed (status %d)", rc);
    } else {
        snprintf(peer->note, sizeof peer->note, "scipy.optimize.least_squares (%.200s), %zu seeds, "
                 "method lm, started from the truth", script, nseeds);
    }
}

/* ---- output ---------------------------------------------------------- */

/* Every peer's time per fit over layerfit's (above 1: the peer is slower)
 * and its w error over layerfit's, for the baseline rows. */
static void
print_peers(const bench_peer *peer, const bench_row *rows, size_t nrows)
{
    size_t i, q;

    printf("\nAll peers on the same data: time per fit over layerfit's (x) and RMS w error\n"
           "over layerfit's (e); lm/trf = scipy least_squares methods, -truth started\n"
           "from the truth, -auto from a simple automatic start (its cost included),\n"
           "lmfit = lmfit.minimize leastsq with finite differences:\n");
    printf("%-13s %-5s", "scene", "noise");
    for (q = 0; q < NPEER; q++)
        printf(" %15s", peer_names[q]);
    printf("\n");
    for (i = 0; i < nrows; i++) {
        const bench_row *r = &rows[i];
        char nz[16];
        if (r->config != 0)
            continue;
        snprintf(nz, sizeof nz, "%g%%", 100 * noise_levels[r->noise]);
        printf("%-13s %-5s", scenes[r->scene].name, nz);
        for (q = 0; q < NPEER; q++) {
            double t = peer->time_us[q][r->scene][r->noise], e = peer->err_w[q][r->scene][r->noise];
            char cell[32];
            if (isnan(t))
                snprintf(cell, sizeof cell, "-");
            else
                snprintf(cell, sizeof cell, "%.1fx %.2fe", t / r->time_us, e / r->err_w);
            printf(" %15s", cell);
        }
        printf("\n");
    }
}

static void
pct(char *buf, size_t n, double x)
{
    if (isnan(x))
        snprintf(buf, n, "-");
    else if (x < 0.01)
        snprintf(buf, n, "%.3f%%", 100 * x);
    else
        snprintf(buf, n, "%.2f%%", 100 * x);
}

static void
ratio(char *buf, size_t n, double x)
{
    if (isnan(x))
        snprintf(buf, n, "-");
    else
        snprintf(buf, n, "%.2f", x);
}

static void
print_row(const bench_row *r)
{
    char ew[16], eE[16], en[16], rw[16], rE[16], rn[16], nz[16];
    const bench_config *c = &configs[r->config];

    pct(ew, sizeof ew, r->err_w);
    pct(eE, sizeof eE, r->err_E);
    ratio(rw, sizeof rw, r->err_w / r->crb_w);
    ratio(rE, sizeof rE, r->err_E / r->crb_E);
    if (r->nu_free) {
        snprintf(en, sizeof en, "%.2g", r->err_nu);
        ratio(rn, sizeof rn, r->err_nu / r->crb_nu);
    } else {
        snprintf(en, sizeof en, "-");
        snprintf(rn, sizeof rn, "-");
    }
    snprintf(nz, sizeof nz, "%g%%", 100 * noise_levels[r->noise]);
    printf("%-13s %-5s %-14s %9.1f %7.1f %5.1f %6.1f %5.2f %5.2f %8s %6s %8s %6s %8s %6s\n",
           scenes[r->scene].name, nz, c->label, r->time_us, r->time_us / r->eval_us,
           r->iterations, r->evaluations, r->converged, r->w_determined, ew, rw, eE, rE, en, rn);
}

static void
csv_num(FILE *f, double x)
{
    fputc(',', f);
    if (isfinite(x))
        cli_print_double(f, x);
}

typedef struct {
    const bench_row *rows;
    size_t nrows;
} bench_table;

/* The table, through the atomic writer (output.c). */
static void
csv_writer(FILE *f, const void *ctx)
{
    const bench_row *rows = ((const bench_table *) ctx)->rows;
    size_t i, nrows = ((const bench_table *) ctx)->nrows;

    fprintf(f, "scene,noise_rel,factor,config,method,jacobian,guess,points,seeds,"
               "time_us,eval_us,time_in_evals,iterations,evaluations,converged,w_determined,"
               "err_w_rel,crb_w_rel,err_w_over_crb,err_E_rel,crb_E_rel,err_E_over_crb,"
               "err_nu_abs,crb_nu_abs,err_nu_over_crb\n");
    for (i = 0; i < nrows; i++) {
        const bench_row *r = &rows[i];
        const bench_config *c = &configs[r->config];
        fprintf(f, "%s,", scenes[r->scene].name);
        cli_print_double(f, noise_levels[r->noise]);
        fprintf(f, ",%s,%s,%s,%s,%s,%zu,%zu", c->factor, c->label, c->method,
                jacobian_name(c->jacobian), c->guess == GUESS_AUTO ? "auto" : "naive3x",
                c->points, r->seeds);
        csv_num(f, r->time_us);
        csv_num(f, r->eval_us);
        csv_num(f, r->time_us / r->eval_us);
        csv_num(f, r->iterations);
        csv_num(f, r->evaluations);
        csv_num(f, r->converged);
        csv_num(f, r->w_determined);
        csv_num(f, r->err_w);
        csv_num(f, r->crb_w);
        csv_num(f, r->err_w / r->crb_w);
        csv_num(f, r->err_E);
        csv_num(f, r->crb_E);
        csv_num(f, r->err_E / r->crb_E);
        csv_num(f, r->nu_free ? r->err_nu : NAN);
        csv_num(f, r->nu_free ? r->crb_nu : NAN);
        csv_num(f, r->nu_free ? r->err_nu / r->crb_nu : NAN);
        fputc('\n', f);
    }
}

static void
write_csv(const char *path, const bench_row *rows, size_t nrows, const char *command_line)
{
    bench_table t;
    t.rows = rows;
    t.nrows = nrows;
    cli_write_file_sidecar("bench: --csv", path, command_line, csv_writer, &t);
}

/* Error of w against time per fit, one point per row, a series per scene
 * and noise level (color by scene, point shape by noise). */
static void
write_plot(const char *path, const bench_row *rows, size_t nrows)
{
    plot_series ser[NSCENES * NNOISE];
    double *x = malloc(nrows * sizeof *x), *y = malloc(nrows * sizeof *y);
    char titles[NSCENES * NNOISE][64], msg[300];
    size_t si, ni, i, ns = 0, used = 0;

    if (x == NULL || y == NULL)
        cli_die(CLI_EXIT_FAIL, "bench: out of memory");
    for (si = 0; si < NSCENES; si++)
        for (ni = 0; ni < NNOISE; ni++) {
            plot_series *s = &ser[ns];
            size_t start = used;
            for (i = 0; i < nrows; i++)
                if (rows[i].scene == si && rows[i].noise == ni && isfinite(rows[i].err_w)
                    && rows[i].err_w > 0) {
                    x[used] = rows[i].time_us;
                    y[used] = rows[i].err_w;
                    used++;
                }
            if (used == start)
                continue;
            snprintf(titles[ns], sizeof titles[ns], "%s, %g%%", scenes[si].name,
                     100 * noise_levels[ni]);
            memset(s, 0, sizeof *s);
            s->title = titles[ns];
            s->n = used - start;
            s->x = x + start;
            s->y = y + start;
            s->color = (int) si;
            s->points = 1 + (int) ni;
            ns++;
        }
    {
        plot_figure fig = { "layerfit bench: RMS relative error of w against time per fit",
                            "median time per fit (us)", "RMS relative error of w",
                            1, 1, ns, ser };
        if (plot_draw(&fig, path, msg, sizeof msg) != 0)
            cli_die(CLI_EXIT_FAIL, "bench: --plot: %s", msg);
    }
    free(x);
    free(y);
}

/* ---- the command ----------------------------------------------------- */

int
cli_bench(int argc, char **argv, const char *command_line)
{
    const char *csv = NULL, *plot = NULL, *scene_name = NULL, *script = NULL;
    int quick = 0, no_scipy = 0, help = 0, npos, coverage = 0, calibrate = 0;
    long seeds = -1, batch = -1;
    const cli_opt opts[] = {
        { "quick", CLI_FLAG, &quick }, { "coverage", CLI_FLAG, &coverage },
        { "calibrate", CLI_FLAG, &calibrate },
        { "seeds", CLI_COUNT, &seeds },
        { "batch", CLI_COUNT, &batch },
        { "scene", CLI_STRING, &scene_name },
        { "csv", CLI_STRING, &csv },
        { "plot", CLI_STRING, &plot },
        { "scipy", CLI_STRING, &script },
        { "no-scipy", CLI_FLAG, &no_scipy },
        { NULL, CLI_FLAG, NULL }
    };
    int use_scene[NSCENES];
    bench_row *rows;
    size_t nrows = 0, si, ni, ci, nseeds, nbatch;
    bench_throughput tp;
    bench_peer peer;
    gsl_rng *rng;
    double t_start = cli_now();

    cli_parse("bench", argc, argv, opts, &npos, &help);
    if (help) {
        fputs(bench_help, stdout);
        return CLI_EXIT_OK;
    }
    if (npos > 0)
        cli_die(CLI_EXIT_USAGE, "bench: unexpected argument '%s' (see 'layerfit bench --help')",
                argv[0]);
    nseeds = seeds >= 0 ? (size_t) seeds : quick ? 10 : 200;
    if (coverage)
        return cli_coverage(nseeds, scene_name, calibrate);
    nbatch = batch >= 0 ? (size_t) batch : quick ? 256 : 4096;
    if (nseeds < 2)
        cli_die(CLI_EXIT_USAGE, "bench: --seeds: at least 2 seeds are needed (e.g. --seeds 50)");
    for (si = 0; si < NSCENES; si++)
        use_scene[si] = scene_name == NULL || strcmp(scene_name, scenes[si].name) == 0;
    if (scene_name != NULL) {
        for (si = 0; si < NSCENES && !use_scene[si]; si++)
            ;
        if (si == NSCENES)
            cli_die(CLI_EXIT_USAGE, "bench: --scene: unknown scene '%s' (two-probe, "
                    "paper-offsets, mixed-nu, soft-coating, single-k2)", scene_name);
    }
    if (plot != NULL && !plot_have_gnuplot())
        cli_die(CLI_EXIT_USAGE, "bench: --plot: gnuplot is not installed: %s", PLOT_INSTALL_HINT);
    if (plot != NULL && plot_terminal(plot) == NULL)
        cli_die(CLI_EXIT_USAGE, "bench: --plot %s: the file must end in .svg or .png", plot);
    /* the outputs checked before minutes of fits, not after them */
    cli_output_note("bench", csv);
    cli_output_note_sidecar("bench", csv);
    cli_output_note("bench", plot);
    cli_output_folder_check("bench", csv);
    cli_output_folder_check("bench", plot);
    rows = calloc(NSCENES * NNOISE * NCONFIGS, sizeof *rows);
    rng = gsl_rng_alloc(gsl_rng_mt19937);
    if (rows == NULL || rng == NULL)
        cli_die(CLI_EXIT_FAIL, "bench: out of memory");

    printf("layerfit %s bench%s: %zu seeds per row, thin-layer model, unloading branch\n",
           LF_VERSION, quick ? " --quick" : "", nseeds);
    printf("One factor at a time around the baseline: method lm, analytic Jacobian, automatic\n"
           "guess, %d points per curve. Time: median wall time of one fit (setup, guess,\n"
           "iterations, uncertainty). x eval: that time over one model + Jacobian evaluation\n"
           "of the same data. conv: fraction of fits that converged; w det: fraction that\n"
           "report w as a value (the rest: an upper bound, w < 2 se). err: RMS relative\n"
           "error of the point estimates over converged fits (nu: absolute); /CRB: err over\n"
           "the Cramer-Rao bound at the truth (1 = efficient).\n\n", BASE_POINTS);
    for (si = 0; si < NSCENES; si++) {
        if (!use_scene[si])
            continue;
        printf("scene %-13s %s\n", scenes[si].name, scenes[si].what);
    }
    printf("\n%-13s %-5s %-14s %9s %7s %5s %6s %5s %5s %8s %6s %8s %6s %8s %6s\n", "scene",
           "noise", "config", "us/fit", "x eval", "iter", "nfev", "conv", "w det", "w err", "/CRB",
           "E* err", "/CRB", "nu err", "/CRB");
    for (si = 0; si < NSCENES; si++) {
        size_t pts[NCONFIGS], npts = 0, pi;
        if (!use_scene[si])
            continue;
        /* the distinct sizes, in order of appearance */
        for (ci = 0; ci < NCONFIGS; ci++) {
            for (pi = 0; pi < npts && pts[pi] != configs[ci].points; pi++)
                ;
            if (pi == npts)
                pts[npts++] = configs[ci].points;
        }
        for (ni = 0; ni < NNOISE; ni++)
            for (pi = 0; pi < npts; pi++) {
                bench_data d;
                double ecost;
                data_init(&d, &scenes[si], pts[pi]);
                ecost = eval_cost(&d);
                for (ci = 0; ci < NCONFIGS; ci++) {
                    bench_row *r;
                    if (configs[ci].points != pts[pi])
                        continue;
                    r = &rows[nrows++];
                    r->scene = si;
                    r->noise = ni;
                    r->config = ci;
                    r->eval_us = 1e6 * ecost;
                    run_row(r, &d, rng, nseeds);
                }
                data_free(&d);
            }
        /* print in table order: noise, then configuration */
        for (ni = 0; ni < NNOISE; ni++)
            for (ci = 0; ci < NCONFIGS; ci++) {
                size_t i;
                for (i = 0; i < nrows; i++)
                    if (rows[i].scene == si && rows[i].noise == ni && rows[i].config == ci)
                        print_row(&rows[i]);
            }
        fflush(stdout);
    }
    for (si = 0; si < nrows; si++)
        if (rows[si].first_error[0] != '\0')
            printf("note: %s, %g%%, %s: %.0f%% not converged; first: %s\n",
                   scenes[rows[si].scene].name, 100 * noise_levels[rows[si].noise],
                   configs[rows[si].config].label, 100 * (1 - rows[si].converged),
                   rows[si].first_error);

    printf("\nCost floor (one model + Jacobian evaluation over all curves of a scene):\n");
    for (si = 0; si < NSCENES; si++) {
        size_t i;
        if (!use_scene[si])
            continue;
        printf("  %-13s", scenes[si].name);
        for (ci = 0; ci < NCONFIGS; ci++) {
            if (strcmp(configs[ci].factor, "points") != 0 && ci != 0)
                continue;
            for (i = 0; i < nrows; i++)
                if (rows[i].scene == si && rows[i].noise == 0 && rows[i].config == ci)
                    printf("  %zu pts: %.2f us", configs[ci].points, rows[i].eval_us);
        }
        printf("\n");
    }

    run_throughput(&tp, nbatch);
    printf("\nThroughput: %zu independent single-k2 fits (1%% noise, %d points):\n"
           "  1 thread:   %.0f fits/s (%zu converged)\n"
           "  %d threads: %.0f fits/s (%zu converged), speed-up %.2f\n",
           tp.batch, BASE_POINTS, tp.serial_per_s, tp.serial_conv, tp.threads,
           tp.parallel_per_s, tp.parallel_conv, tp.parallel_per_s / tp.serial_per_s);

    if (no_scipy) {
        printf("\nscipy comparison: skipped (--no-scipy)\n");
    } else {
        run_peer(&peer, script, use_scene, nseeds);
        printf("\nPeer: %s\n", peer.note);
        if (peer.ran) {
            printf("%-13s %-5s %10s %10s %7s %8s %8s %8s %8s %8s %8s\n", "scene", "noise",
                   "us/fit", "scipy us", "ratio", "w err", "scipy", "E* err", "scipy",
                   "nu err", "scipy");
            for (si = 0; si < nrows; si++) {
                const bench_row *r = &rows[si];
                char a[16], b[16], c[16], d[16], e[16], f[16], nz[16];
                if (r->config != 0)
                    continue;
                pct(a, sizeof a, r->err_w);
                pct(b, sizeof b, peer.err_w[0][r->scene][r->noise]);
                pct(c, sizeof c, r->err_E);
                pct(d, sizeof d, peer.err_E[0][r->scene][r->noise]);
                snprintf(e, sizeof e, r->nu_free ? "%.2g" : "-", r->err_nu);
                snprintf(f, sizeof f, r->nu_free ? "%.2g" : "-", peer.err_nu[0][r->scene][r->noise]);
                snprintf(nz, sizeof nz, "%g%%", 100 * noise_levels[r->noise]);
                printf("%-13s %-5s %10.1f %10.1f %7.1f %8s %8s %8s %8s %8s %8s\n",
                       scenes[r->scene].name, nz, r->time_us, peer.time_us[0][r->scene][r->noise],
                       peer.time_us[0][r->scene][r->noise] / r->time_us, a, b, c, d, e, f);
            }
            printf("ratio: scipy time per fit over layerfit's (layerfit includes its own guess;\n"
                   "scipy starts from the truth, its most favourable start).\n");
            print_peers(&peer, rows, nrows);
        }
    }

    if (csv != NULL)
        write_csv(csv, rows, nrows, command_line);
    if (plot != NULL)
        write_plot(plot, rows, nrows);
#ifdef _OPENMP
    printf("\nmachine: %ld cores online, OpenMP %d threads; total bench time %.1f s\n",
           sysconf(_SC_NPROCESSORS_ONLN), omp_get_max_threads(), cli_now() - t_start);
#else
    printf("\nmachine: %ld cores online, built without OpenMP; total bench time %.1f s\n",
           sysconf(_SC_NPROCESSORS_ONLN), cli_now() - t_start);
#endif
    gsl_rng_free(rng);
    free(rows);
    return CLI_EXIT_OK;
}
