/* test_select.c: the k-th smallest value and the median (fit/guess.c),
 * which every noise estimate rests on, against a sort: random values,
 * values with many ties, sorted and reversed runs, a single value repeated,
 * and every k of small arrays.  After the selection the values below k must
 * be no larger than the k-th and those above no smaller (the median of an
 * even count reads the lower half).  The noise sd's threshold question
 * (fit/noise.c), answered by counting, against the selection.  The force
 * quantum (fit/noise.c, sorted by buckets) against the same rule on a
 * qsort: on lattices, with rounding jitter, noise, outliers and ties.
 * A fit's noise is of the data its buffers hold now: buffers filled again
 * with other data give those data's noise.  The departures four points at
 * a time (AVX2) give the scalar loop's bits, alone and in a fit's noise
 * model of correlated noise (strides beyond 1). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "fit.h"
#include "scene.h"
#include "testlib.h"

#define NMAX 701

static int
cmp(const void *a, const void *b)
{
    double x = *(const double *) a, y = *(const double *) b;
    return (x > y) - (x < y);
}

/* Fill v with n values of the given kind. */
static void
fill(double *v, size_t n, int kind, gsl_rng *rng)
{
    size_t i;
    for (i = 0; i < n; i++)
        switch (kind) {
        case 0: v[i] = gsl_rng_uniform(rng) - 0.5; break;             /* distinct */
        case 1: v[i] = (double) gsl_rng_uniform_int(rng, 4); break;    /* few values */
        case 2: v[i] = (double) i; break;                               /* sorted */
        case 3: v[i] = (double) (n - i); break;                         /* reversed */
        case 4: v[i] = 2.5; break;                                      /* all equal */
        default: v[i] = (double) (i % 7 == 0 ? 1 : 0); break;          /* mostly zeros */
        }
}

/* The quantum by its rule on a qsort (as lf_fit_quantum stood before it
 * sorted by buckets): the value it must give, bit for bit. */
static double
quantum_by_qsort(const double *force, size_t n, double fbig)
{
    static double w[4096];
    const double tol = 1e-9 * fbig;
    double q = HUGE_VAL, last;
    size_t i, gaps = 0, on = 0;

    if (n < 20 || !(fbig > 0))
        return 0.0;
    memcpy(w, force, n * sizeof *w);
    qsort(w, n, sizeof *w, cmp);
    for (i = 1, last = w[0]; i < n; i++)
        if (w[i] - last > tol) {
            q = fmin(q, w[i] - last);
            last = w[i];
            gaps++;
        }
    if (gaps < 20 || !(q < HUGE_VAL))
        return 0.0;
    for (i = 1, last = w[0]; i < n; i++)
        if (w[i] - last > tol) {
            double r = (w[i] - last) / q;
            on += fabs(r - floor(r + 0.5)) <= 0.02;
            last = w[i];
        }
    return (double) on >= 0.99 * (double) gaps ? q : 0.0;
}

/* Forces of one kind: a smooth curve with noise, on a lattice, with
 * jitter of a unit conversion, with far outliers, crowded near one value,
 * few levels, and a curve with a lattice broken by one value in fifty. */
static void
forces(double *v, size_t n, int kind, gsl_rng *rng)
{
    const double q = 3.7e-11;
    size_t i;
    for (i = 0; i < n; i++) {
        const double t = (double) i / (double) n, smooth = 1e-7 * (t * t - 0.3 * t - 0.05);
        switch (kind) {
        case 0: v[i] = smooth + 1e-9 * gsl_ran_gaussian_ziggurat(rng, 1.0); break;
        case 1: v[i] = q * nearbyint((smooth + 1e-9 * gsl_rng_uniform(rng)) / q); break;
        case 2: v[i] = q * nearbyint(smooth / q) * (1.0 + 1e-15 * (gsl_rng_uniform(rng) - 0.5)); break;
        case 3: v[i] = i % 97 == 5 ? 1e3 * (smooth + 1e-7) : smooth; break;
        case 4: v[i] = i == n / 2 ? 1.0 : 1e-9 * gsl_rng_uniform(rng); break;
        case 5: v[i] = 1e-9 * (double) gsl_rng_uniform_int(rng, 5) - 2e-9; break;
        default: v[i] = q * nearbyint(smooth / q) + (i % 50 == 7 ? 0.5 * q : 0.0); break;
        }
    }
}

/* The noise sd a fit of scene s (as simulated last) estimates for its
 * curve. */
static double
fit_sigma(scene *s)
{
    lf_fit *f = lf_fit_alloc(&s->fit, s->n, s->curve, NULL);
    double sigma = f != NULL ? f->c[0].sigma : NAN;
    lf_fit_free(f);
    return sigma;
}

static void
test_buffers_refilled(void)
{
    scene a = scene_default("noise a"), b = scene_default("noise b");
    double s1, s2, s2b;

    /* a fit's buffer filled again with other data: estimated again */
    scene_add(&a, 2.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
    scene_add(&b, 2.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
    a.sim.noise = b.sim.noise = 0.01;
    t_int(scene_simulate(&a, 11), LF_OK, "scene simulated (seed 11)");
    s1 = fit_sigma(&a);
    t_int(scene_simulate(&a, 12), LF_OK, "the same buffers simulated again (seed 12)");
    s2 = fit_sigma(&a);
    t_int(scene_simulate(&b, 12), LF_OK, "seed 12 in other buffers");
    s2b = fit_sigma(&b);
    t_true(s1 > 0 && s2 > 0 && s1 != s2, "the noise of the new data, not the old (%.6g, %.6g)",
           s1, s2);
    t_true(s2 == s2b, "seed 12's noise, whatever buffer holds it");
    scene_free(&a);
    scene_free(&b);
}

/* lf_fit_noise_sigma's departures (left in work) and sd with the vector
 * path and without: 301 points (not a multiple of four) in a shuffled
 * order, some at repeated depths (no line through three points at one
 * depth: the group of four holding one is the scalar loop's). */
static void
test_simd_departures(gsl_rng *rng)
{
    enum { N = 301 };
    static double z[N], F[N], work[2][3 * N], key[N];
    static size_t ord[N], perm[N];
    const int vec = lf_simd(1);
    double sd[2];
    size_t i, j, rep;
    int v;

    (void) vec;     /* read only where the vector path exists */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(LF_NO_SIMD)
    t_int(vec, __builtin_cpu_supports("avx2") ? 1 : 0, "noise: the vector path where AVX2 is");
#endif
    for (rep = 0; rep < 2; rep++) {
        for (i = 0; i < N; i++) {
            perm[i] = i;
            /* rep 1: every 50th depth repeated from its neighbour */
            key[i] = rep && i % 50 == 7 ? (double) (i - 1) : (double) i;
        }
        gsl_ran_shuffle(rng, perm, N, sizeof *perm);
        for (i = 0; i < N; i++) {           /* file order perm, depth order i */
            z[perm[i]] = 1e-9 * key[i] + 1e-12 * gsl_rng_uniform(rng) * (key[i] == (double) i);
            F[perm[i]] = 1e-6 * sin(0.01 * (double) i) + 1e-8 * gsl_ran_gaussian(rng, 1.0);
        }
        for (i = 0; i < N; i++)             /* by depth, ties in file order */
            ord[i] = perm[i];
        for (i = 1; i < N; i++)
            for (j = i; j > 0 && (z[ord[j - 1]] > z[ord[j]]
                                  || (z[ord[j - 1]] == z[ord[j]] && ord[j - 1] > ord[j])); j--) {
                size_t t = ord[j];
                ord[j] = ord[j - 1];
                ord[j - 1] = t;
            }
        for (v = 0; v < 2; v++) {
            memset(work[v], 0, sizeof work[v]);
            lf_simd(v);
            sd[v] = lf_fit_noise_sigma(z, F, ord, N, 1e-6, work[v]);
        }
        lf_simd(1);
        t_true(sd[0] == sd[1] && memcmp(work[0], work[1], sizeof work[0]) == 0,
               "noise sd and departures: vector and scalar paths equal bit for bit (%s)",
               rep ? "repeated depths" : "distinct depths");
    }
}

/* A fit's noise model (correlation time, the plateau's noise sd at its
 * stride, shape, runs test) with and without the vector path, on noise
 * made correlated by a running mean over 9 points taken twice: the
 * same bits. */
static void
test_simd_noise_model(void)
{
    scene a = scene_default("correlated noise");
    lf_fit_result res[2];
    static double raw[600];
    int v, st[2], pass;
    size_t i, k;

    scene_add(&a, 2.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS);
    a.sim.noise = 0.02;
    t_int(scene_simulate(&a, 5), LF_OK, "scene simulated (seed 5)");
    for (pass = 0; pass < 2; pass++) {      /* twice: a triangle of 17 points */
        for (i = 0; i < a.curve[0].n && i < 600; i++)
            raw[i] = a.force[0][i];
        for (i = 0; i < a.curve[0].n && i < 600; i++) {
            double m = 0.0;
            for (k = 0; k < 9; k++)
                m += raw[i + k < a.curve[0].n ? i + k : a.curve[0].n - 1];
            a.force[0][i] = m / 9.0;
        }
    }
    for (v = 0; v < 2; v++) {
        lf_simd(v);
        st[v] = lf_fit_driver(&a.fit, a.n, a.curve, &res[v], NULL);
    }
    lf_simd(1);
    if (st[0] != LF_OK || st[1] != LF_OK) {
        t_true(0, "correlated-noise fits converge (%d %d)", st[0], st[1]);
    } else {
        const lf_fit_curve_result *c0 = &res[0].curves[0], *c1 = &res[1].curves[0];
        t_true(c0->corr_time > 1.5, "the noise is correlated (corr_time %.3g)", c0->corr_time);
        t_true(c0->corr_time == c1->corr_time && c0->noise_sd == c1->noise_sd
               && c0->shape == c1->shape && c0->runs_z == c1->runs_z
               && res[0].chi2 == res[1].chi2 && res[0].se_scale == res[1].se_scale
               && memcmp(res[0].value, res[1].value, res[0].npar * sizeof *res[0].value) == 0,
               "correlated noise: vector and scalar paths give the same bits");
    }
    for (v = 0; v < 2; v++)
        if (st[v] == LF_OK || st[v] == LF_ENOCONV)
            lf_fit_result_free(&res[v]);
    scene_free(&a);
}

int
main(void)
{
    static const char *kinds[] = { "distinct", "few values", "sorted", "reversed",
                                   "all equal", "mostly zeros" };
    static double v[NMAX], s[NMAX];
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    size_t sizes[] = { 1, 2, 3, 4, 5, 8, 31, 64, 299, 300, 701 };
    size_t is, k, i;
    int kind, bad;

    gsl_rng_set(rng, 7);
    for (kind = 0; kind < 6; kind++)
        for (is = 0; is < sizeof sizes / sizeof sizes[0]; is++) {
            size_t n = sizes[is];
            double med, want;
            /* every k of small arrays, three of large ones */
            for (k = 0; k < n; k += n <= 8 ? 1 : n / 3 + 1) {
                fill(v, n, kind, rng);
                memcpy(s, v, n * sizeof *v);
                qsort(s, n, sizeof *s, cmp);
                want = s[k];
                t_rel(lf_fit_select_kth(v, n, k), want, 0, "%s, n = %zu: k = %zu", kinds[kind],
                      n, k);
                for (i = 0, bad = 0; i < n; i++)
                    bad += i < k ? v[i] > want : i > k ? v[i] < want : v[i] != want;
                t_int(bad, 0, "%s, n = %zu, k = %zu: partitioned around the k-th", kinds[kind],
                      n, k);
                qsort(v, n, sizeof *v, cmp);
                t_int(memcmp(v, s, n * sizeof *v), 0, "%s, n = %zu, k = %zu: the same values",
                      kinds[kind], n, k);
            }
            fill(v, n, kind, rng);
            memcpy(s, v, n * sizeof *v);
            qsort(s, n, sizeof *s, cmp);
            want = n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
            med = lf_fit_median(v, n);
            t_rel(med, want, 1e-15, "%s, n = %zu: the median", kinds[kind], n);
        }
    /* the noise sd's question "above thr?" (noise.c) by counting, against
     * the selection, with thr at, just below and just above the noise of
     * squared departures (non-negative) of every kind, and at NaN */
    for (kind = 0; kind < 6; kind++)
        for (is = 0; is < sizeof sizes / sizeof sizes[0]; is++) {
            size_t n = sizes[is];
            double sd, thr[5];
            int q;
            fill(v, n, kind, rng);
            for (i = 0; i < n; i++)
                v[i] = v[i] * v[i];
            memcpy(s, v, n * sizeof *v);
            sd = lf_fit_noise_of(s, n);
            thr[0] = sd;
            thr[1] = nextafter(sd, 0.0);
            thr[2] = nextafter(sd, HUGE_VAL);
            thr[3] = sd * (1.0 - 1e-13);
            thr[4] = NAN;
            for (q = 0, bad = 0; q < 5; q++)
                bad += lf_fit_noise_above(v, n, thr[q]) != (sd > thr[q]);
            t_int(bad, 0, "%s, n = %zu: noise above a threshold, counted = selected", kinds[kind],
                  n);
        }
    t_int(lf_fit_noise_above(v, 0, 1.0), 0, "no departures: not above");
    /* the quantum, sorted by buckets, against the qsort rule */
    {
        static const size_t qsizes[] = { 19, 20, 21, 64, 300, 2600, 4096 };
        static double f[4096], work[4096];
        static size_t start[4097];
        int nonzero = 0;
        for (kind = 0; kind < 7; kind++)
            for (is = 0; is < sizeof qsizes / sizeof qsizes[0]; is++) {
                const size_t n = qsizes[is];
                double fbig = 0.0, want, got;
                forces(f, n, kind, rng);
                for (i = 0; i < n; i++)
                    fbig = fmax(fbig, fabs(f[i]));
                want = quantum_by_qsort(f, n, fbig);
                got = lf_fit_quantum(f, n, fbig, work, start);
                nonzero += want > 0;
                t_int(memcmp(&got, &want, sizeof got), 0,
                      "kind %d, n = %zu: quantum %.17g, by the qsort %.17g", kind, n, got, want);
            }
        /* the lattices are found (else the comparison tests little) */
        t_true(nonzero >= 8, "quantized kinds found quantized (%d)", nonzero);
    }
    test_simd_departures(rng);
    gsl_rng_free(rng);
    test_buffers_refilled();
    test_simd_noise_model();
    return t_summary();
}
