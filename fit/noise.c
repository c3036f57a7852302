/* noise.c: a noise model for real curves.
 *
 * Instruments filter and oversample, so neighbouring points carry nearly the
 * same noise: the point-to-point noise estimate (lf_fit_noise_sigma, at the end of
 * this file) is then far too
 * small, every chi2 is huge and every standard error too small.  At the
 * solution, per curve, with e_i the residuals in file (time) order:
 *   rho_k   their autocorrelation at lag k;
 *   tau     = 1 + 2 sum_{k=1..K} rho_k, the integrated autocorrelation
 *           time, summed while rho_k stays above 2/sqrt(n) (what white noise
 *           of n points can show by chance): tau = 1 for white noise;
 *   n_eff   = n / tau, the independent points: the variance of a
 *           least-squares estimate grows by about tau over the white-noise
 *           formula (exactly so for a mean), so standard errors are scaled
 *           by sqrt(tau) (pooled over the curves by their points);
 *   noise   the data's own noise sd at lag m = ceil(tau), from the line
 *           through the neighbours m points away in depth (the estimate of
 *           lf_fit_noise_sigma at that stride), model-free: neighbours beyond the
 *           correlation carry independent noise.
 * The agreement of a curve with the model is then judged against that noise
 * (chi2 per point and the runs test of every m-th residual), and where it
 * fails, the deviation is also put against the curve's force range:
 * below 5% the model describes the shape with systematic deviations, above
 * it the fit is broken.  For white noise all of this reduces to the plain
 * test. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fit.h"

#define NOISE_MAX_LAG 400
#define AGREE_REL 0.05
#define NOISE_GROWTH 1.3

/* Residual i of res: the index is in range by construction (its rows are
 * the curves'), so without gsl_vector_get's check, a load and a branch
 * per point in loops over all of them. */
static inline double
res_at(const gsl_vector *res, size_t i)
{
    return res->data[i * res->stride];
}

double
lf_fit_corr_time(const double *e, size_t n)
{
    size_t k, K = n / 4 < NOISE_MAX_LAG ? n / 4 : NOISE_MAX_LAG, i;
    double mean = 0.0, c0 = 0.0, tau = 1.0, thr;

    if (n < 8)
        return 1.0;
    thr = 2.0 / sqrt((double) n);
    for (i = 0; i < n; i++)
        mean += e[i];
    mean /= (double) n;
    for (i = 0; i < n; i++)
        c0 += (e[i] - mean) * (e[i] - mean);
    if (!(c0 > 0))
        return 1.0;
    for (k = 1; k <= K; k++) {
        double ck = 0.0, rho;
        for (i = 0; i + k < n; i++)
            ck += (e[i] - mean) * (e[i + k] - mean);
        rho = ck / c0;
        if (!(rho > thr))
            break;
        tau += 2.0 * rho;
    }
    return lf_fmin(tau, (double) n / 4.0);
}

/* The departures of v at stride m, both v and the depths z in order of
 * depth: of each from the line through its neighbours m points away,
 * squared over their variance factor (see lf_fit_noise_sigma), into work;
 * returns their count. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(LF_NO_SIMD)
#define NOISE_AVX2 1
#include <immintrin.h>

/* line_departures' points i..n-m-1 four at a time with AVX2, each lane its
 * operations on its point in its order (no fused multiply-add); a group
 * with a point it would pass over (no line) is left to it.  Returns the
 * first point not done; *cnt counts what went into work. */
__attribute__((target("avx2"))) static size_t
departures4(const double *z, const double *v, size_t n, size_t m, size_t i, double *work,
            size_t *cnt)
{
    size_t k = *cnt;

    for (; i + m + 4 <= n; i += 4) {
        const __m256d zb = _mm256_loadu_pd(z + i);
        const __m256d h0 = zb - _mm256_loadu_pd(z + i - m);
        const __m256d h1 = _mm256_loadu_pd(z + i + m) - zb, h = h0 + h1;
        __m256d q;
        if (_mm256_movemask_pd(_mm256_cmp_pd(h, _mm256_setzero_pd(), _CMP_GT_OQ)) != 15)
            break;
        q = _mm256_loadu_pd(v + i) * h - _mm256_loadu_pd(v + i - m) * h1
            - _mm256_loadu_pd(v + i + m) * h0;
        _mm256_storeu_pd(work + k, q * q / (h * h + h0 * h0 + h1 * h1));
        k += 4;
    }
    *cnt = k;
    return i;
}
#endif

static size_t
line_departures(const double *z, const double *v, size_t n, size_t m, double *work)
{
    size_t i = m, cnt = 0;

#ifdef NOISE_AVX2
    if (lf_simd(-1))
        i = departures4(z, v, n, m, i, work, &cnt);
#endif
    for (; i + m < n; i++) {
        const double h0 = z[i] - z[i - m], h1 = z[i + m] - z[i], h = h0 + h1;
        double q;
        if (!(h > 0))
            continue;           /* three points at one depth: no line */
        /* (e over its sd factor)^2, one division (numerators are forces
         * times depths in SI, far from overflowing when squared) */
        q = v[i] * h - v[i - m] * h1 - v[i + m] * h0;
        work[cnt++] = q * q / (h * h + h0 * h0 + h1 * h1);
    }
    return cnt;
}

/* v[ord[i]] into out[i]: values in order of depth */
static void
by_depth(const double *v, const size_t *ord, size_t n, double *out)
{
    size_t i;

    for (i = 0; i < n; i++)
        out[i] = v[ord[i]];
}

/* The departures of the residuals es (in order of depth) at stride m
 * (guess.c's estimate at that stride).  A smooth misfit hardly shows at
 * small strides; correlated noise shows fully once m exceeds its
 * correlation. */
static size_t
departures(const lf_fit *f, const fit_curve *c, const double *es, size_t m, double *work)
{
    return line_departures(f->ws.zsort + c->row, es, c->data.n, m, work);
}

/* Their noise sd, robust: the (upper) median of |q| over 0.6745 (work
 * reordered). */
double
lf_fit_noise_of(double *work, size_t cnt)
{
    return cnt > 0 ? sqrt(lf_fit_select_kth(work, cnt, cnt / 2)) / 0.6745 : NAN;
}

/* lf_fit_noise_of(work, cnt) > thr, decided by counting instead of selecting:
 * sqrt(x) / 0.6745 is non-decreasing in x (correctly rounded), so the upper
 * median exceeds thr exactly when no more than cnt / 2 of the values do
 * not.  Each value is put against (0.6745 thr)^2, and only one within
 * 1e-12 of it through sqrt(x) / 0.6745 itself.  A NaN noise (no
 * departures) does not exceed it. */
int
lf_fit_noise_above(const double *work, size_t cnt, double thr)
{
    const double t = 0.6745 * thr * (0.6745 * thr), lo = t * (1.0 - 1e-12), hi = t * (1.0 + 1e-12);
    size_t i, not_above = 0;

    if (cnt == 0)
        return 0;
    for (i = 0; i < cnt; i++) {     /* a branch on the rare value near t only */
        const double x = work[i];
        const int below = x < lo, above = x > hi;      /* never both */
        not_above += (size_t) below;
        if (below + above == 0)
            not_above += !(sqrt(x) / 0.6745 > thr);
    }
    return not_above <= cnt / 2;
}

void
lf_fit_curve_noise(const lf_fit *f, size_t j, const gsl_vector *res, double *tau_out,
                   double *noise_out)
{
    const fit_curve *c = &f->c[j];
    const size_t *ord = f->order + c->row;
    size_t n = c->data.n, i, m, cnt;
    double *e = f->ws.work, *work = f->ws.work + n, *es = f->ws.work + 2 * n, s1, sm, tau;

    for (i = 0; i < n; i++)
        e[i] = lf_fit_unweighted(res_at(res, c->row + i), c->sigma,
                                 f->ws.sqrtw[c->row + i]);
    by_depth(e, ord, n, es);
    /* the plateau of the residuals' noise over strides 1, 2, 4, ...: where
     * doubling the stride no longer raises it by NOISE_GROWTH (at stride 2
     * the question alone is asked, by counting: white noise stops there,
     * and then the value does not matter) */
    s1 = sm = lf_fit_noise_of(work, departures(f, c, es, 1, work));
    /* kept for the shape's noise at stride 1 of the same residuals */
    memcpy(f->ws.noise_e + c->row, e, n * sizeof *e);
    f->ws.noise_s1[2 * j] = 1.0;
    f->ws.noise_s1[2 * j + 1] = s1;
    for (m = 1; 4 * m < n / 2; m *= 2) {
        cnt = departures(f, c, es, 2 * m, work);
        if (!lf_fit_noise_above(work, cnt, NOISE_GROWTH * sm)) {
            if (m > 1)
                sm = lf_fmax(sm, lf_fit_noise_of(work, cnt));
            break;
        }
        sm = lf_fit_noise_of(work, cnt);
    }
    if (!(s1 > 0) || !(sm > 0)) {
        *tau_out = 1.0;
        *noise_out = c->sigma;
        return;
    }
    /* the correlation time: the residuals' own, but no more than the noise
     * variance the plateau shows over the point-to-point one (a smooth misfit
     * makes residuals correlated without raising the plateau) */
    tau = m == 1 ? 1.0 : lf_fmin(lf_fit_corr_time(e, n), lf_fmax(1.0, (sm * sm) / (s1 * s1)));
    *tau_out = lf_fmax(tau, 1.0);
    *noise_out = m == 1 ? c->sigma : lf_fmax(c->sigma, sm);
}

/* The residuals' shape against the noise, whatever the correlation: a
 * misfit makes neighbouring residuals alike just as a filter does, and its
 * correlation time, like the noise's, widens the errors and the noise
 * against which chi2 and the runs test judge the curve, until it hides
 * itself (the 1 um layer with depths 1000 times too small: E* = 546 TPa at
 * chi2/dof 2266, "consistent" at a correlation time of 162 points).  So
 * the residuals, in order of depth, are averaged over SHAPE_BLOCKS
 * stretches of the curve (at least SHAPE_MIN_BLOCK points each): the rms
 * of those means, which for noise of any correlation shorter than a
 * stretch is below the noise's own sd (a mean's variance never exceeds
 * the points'), over the noise sd at a stride of at most a quarter of a
 * stretch (the point-to-point departures of the residuals at the noise's
 * correlation, lf_fit_curve_noise's plateau, where a smooth misfit hardly
 * shows).  Above FIT_SHAPE_MAX the residuals follow a shape larger than
 * the noise: systematic, whatever their correlation. */
#define SHAPE_BLOCKS 16
#define SHAPE_MIN_BLOCK 8
static double
shape(const lf_fit *f, size_t j, const gsl_vector *res, size_t m)
{
    const fit_curve *c = &f->c[j];
    const size_t *ord = f->order + c->row;
    size_t n = c->data.n, nb = n / SHAPE_MIN_BLOCK < SHAPE_BLOCKS ? n / SHAPE_MIN_BLOCK
                                                                   : SHAPE_BLOCKS;
    size_t b, i, stride;
    double *e = f->ws.work, *work = f->ws.work + n, mean = 0.0, ss = 0.0, noise;

    if (nb < 2)
        return 0.0;
    for (i = 0; i < n; i++) {
        e[i] = lf_fit_unweighted(res_at(res, c->row + i), c->sigma,
                                 f->ws.sqrtw[c->row + i]);
        mean += e[i];
    }
    mean /= (double) n;
    for (b = 0; b < nb; b++) {
        size_t lo = b * n / nb, hi = (b + 1) * n / nb;
        double s = 0.0;
        for (i = lo; i < hi; i++)
            s += e[ord[i]];
        s = s / (double) (hi - lo) - mean;
        ss += s * s;
    }
    stride = m;
    if (stride > n / nb / 4)
        stride = n / nb / 4;
    if (stride < 1)
        stride = 1;
    /* at stride 1 of the residuals whose noise lf_fit_curve_noise
     * estimated: its value, not computed again */
    if (stride == 1 && f->ws.noise_s1[2 * j] == 1.0
        && memcmp(f->ws.noise_e + c->row, e, n * sizeof *e) == 0)
        noise = f->ws.noise_s1[2 * j + 1];
    else {
        double *es = f->ws.work + 2 * n;
        by_depth(e, ord, n, es);
        noise = lf_fit_noise_of(work, departures(f, c, es, stride, work));
    }
    if (!(noise > 0))
        return 0.0;
    return sqrt(ss / (double) nb) / noise;
}

double
lf_fit_noise_model(const lf_fit *f, size_t j, const gsl_vector *res, lf_fit_curve_result *cr)
{
    const fit_curve *c = &f->c[j];
    const double tau = cr->corr_time, noise = cr->noise_sd;
    size_t n = c->data.n, i, m;
    const double Fmin = c->flo, Fmax = c->fhi;
    double chi2 = 0.0, rms;

    m = (size_t) ceil(tau - 1e-9);
    if (m < 1)
        m = 1;
    cr->n_eff = (double) n / tau;
    /* against that noise: chi2 per point and the runs test of every m-th
     * residual in depth order */
    for (i = 0; i < n; i++) {
        double u = res_at(res, c->row + i) * c->sigma / noise;
        chi2 += u * u;
    }
    rms = cr->rms;
    cr->runs_z = lf_fit_runs_z_stride(f, j, res, m);
    cr->chi2_per_point = chi2 / (double) n;
    cr->misfit_rel = Fmax > Fmin ? rms / (Fmax - Fmin) : NAN;
    cr->shape = shape(f, j, res, m);
    cr->consistent = !(cr->runs_z < FIT_RUNS_Z_BAD || cr->chi2_per_point > 4.0
                       || cr->shape > FIT_SHAPE_MAX);
    cr->agreement = cr->consistent ? 2 : cr->misfit_rel < AGREE_REL ? 1 : 0;
    return tau;
}

/* Wald-Wolfowitz runs test of curve j's residuals' signs in order of
 * depth, over every stride-th residual (fit.h). */
double
lf_fit_runs_z_stride(const lf_fit *f, size_t j, const gsl_vector *res, size_t stride)
{
    const fit_curve *c = &f->c[j];
    const size_t *ord = f->order + c->row;
    size_t i, npos = 0, nneg = 0, runs = 0;
    double mu, var, nn;
    int last = 0;

    /* without branches: the signs are noise, a branch on each would be
     * mispredicted half the time; a zero residual is skipped */
    for (i = 0; i < c->data.n; i += stride) {
        double u = res_at(res, c->row + ord[i]);
        int pos = u > 0, neg = u < 0, sgn = pos - neg, nz = pos | neg;
        npos += (size_t) pos;
        nneg += (size_t) neg;
        runs += (size_t) (nz & (sgn != last));
        last = nz ? sgn : last;
    }
    nn = (double) (npos + nneg);
    if (nn < 2)
        return 0.0;
    mu = 2.0 * (double) npos * (double) nneg / nn + 1.0;
    var = (mu - 1.0) * (mu - 2.0) / (nn - 1.0);
    return var > 0 ? ((double) runs - mu) / sqrt(var) : 0.0;
}

double
lf_fit_runs_z(const lf_fit *f, size_t j, const gsl_vector *res)
{
    return lf_fit_runs_z_stride(f, j, res, 1);
}

/* Noise sd from the points' departures from the line through their two
 * neighbours in depth: with depths z0 <= z1 <= z2,
 *     e = F1 - (F0 (z2 - z1) + F2 (z1 - z0)) / (z2 - z0)
 * has variance s^2 (1 + ((z2-z1)^2 + (z1-z0)^2) / (z2-z0)^2) for white
 * noise of sd s (1.5 s^2 on an even grid, where e is half the second
 * difference; 2 s^2 for a repeated depth), and the smooth signal adds only
 * about F'' h^2.  The median of |e| over its sd is 0.6745 s.  Order by
 * depth makes it independent of the order of the rows and right for
 * repeated depths.  fbig is the largest |force| (the caller's scale);
 * work holds 3 n (the departures, then depths and forces in order of
 * depth). */
double
lf_fit_noise_sigma(const double *depth, const double *force, const size_t *order, size_t n,
                   double fbig, double *work)
{
    double *zs = work + n, *Fs = work + 2 * n, med;
    size_t m;

    by_depth(depth, order, n, zs);
    by_depth(force, order, n, Fs);
    m = line_departures(zs, Fs, n, 1, work);

    if (m == 0)
        return fbig > 0 ? fbig : 1.0;
    med = lf_fit_median_sqrt(work, m);
    med /= 0.6745;
    /* noise-free data: keep the weight finite */
    return lf_fmax(med, fbig > 0 ? 1e-12 * fbig : 1e-300);
}

/* v[0..n-1], finite, sorted into out[0..n-1] in expected linear time for
 * values spread over their range [lo, hi]: each goes to one of n buckets
 * of equal width, in order of the buckets, and one pass of insertion then
 * orders the values that share a bucket (qsort instead once that has moved
 * values more than SORT_SHIFTS times per value: a far outlier crowds the
 * rest into one bucket).  Rounded arithmetic is monotone, so a value never
 * lands in a bucket before a smaller one's: the result is the sort's,
 * value for value.  start holds n + 1. */
#define SORT_SHIFTS 4
static int
cmp_double(const void *a, const void *b)
{
    const double x = *(const double *) a, y = *(const double *) b;
    return (x > y) - (x < y);
}

static size_t
bucket_of(double x, double lo, double scale, size_t n)
{
    /* 0 <= v (x >= lo): converted as a signed number, one instruction
     * where an unsigned conversion takes a test and a branch */
    const double v = (x - lo) * scale, top = (double) (n - 1);
    return (size_t) (int64_t) (v < top ? v : top);
}

static void
sort_spread(const double *v, size_t n, double lo, double hi, double *out, size_t *start)
{
    const double scale = (double) n / (hi - lo);
    size_t i, b, shifts = 0;

    if (!(scale > 0 && scale < HUGE_VAL)) {     /* all equal, or a range out of reach */
        memcpy(out, v, n * sizeof *out);
        qsort(out, n, sizeof *out, cmp_double);
        return;
    }
    memset(start, 0, (n + 1) * sizeof *start);
    for (i = 0; i < n; i++)
        start[bucket_of(v[i], lo, scale, n) + 1]++;
    for (b = 1; b <= n; b++)            /* start[b]: where bucket b begins */
        start[b] += start[b - 1];
    for (i = 0; i < n; i++)
        out[start[bucket_of(v[i], lo, scale, n)]++] = v[i];
    for (i = 1; i < n; i++) {
        const double x = out[i];
        size_t k = i;
        if (!(out[i - 1] > x))
            continue;
        do {
            out[k] = out[k - 1];
            k--;
            shifts++;
        } while (k > 0 && out[k - 1] > x);
        out[k] = x;
        if (shifts > SORT_SHIFTS * n) {
            qsort(out, n, sizeof *out, cmp_double);
            return;
        }
    }
}

/* The step of a quantized force signal (an instrument's converter, or a
 * file written with few digits), or 0 when the forces lie on no lattice.
 * Sorted, the distinct forces (apart by more than 1e-9 of the largest, the
 * rounding of a unit conversion) are apart by multiples of one step q,
 * the smallest gap: quantized when at least QUANTUM_MIN_GAPS gaps and
 * QUANTUM_SHARE of them lie within QUANTUM_TOL of a multiple of q (forces
 * that are not quantized, their gaps random, do so by chance with a
 * probability far below 1e-10).  work holds n, start n + 1. */
#define QUANTUM_MIN_GAPS 20
#define QUANTUM_SHARE 0.99
#define QUANTUM_TOL 0.02
double
lf_fit_quantum(const double *force, size_t n, double fbig, double *work, size_t *start)
{
    const double tol = 1e-9 * fbig;
    double q = HUGE_VAL, last, lo, hi;
    size_t i, gaps = 0, on = 0, off = 0;

    if (n < QUANTUM_MIN_GAPS || !(fbig > 0))
        return 0.0;
    for (i = 1, lo = hi = force[0]; i < n; i++) {      /* finite: no NaN to pass over */
        lo = force[i] < lo ? force[i] : lo;
        hi = force[i] > hi ? force[i] : hi;
    }
    sort_spread(force, n, lo, hi, work, start);
    for (i = 1, last = work[0]; i < n; i++)
        if (work[i] - last > tol) {
            q = lf_fmin(q, work[i] - last);
            last = work[i];
            gaps++;
        }
    if (gaps < QUANTUM_MIN_GAPS || !(q < HUGE_VAL))
        return 0.0;
    /* counted until the gaps off the lattice are too many for the share
     * (forces on no lattice: after a few) */
    for (i = 1, last = work[0]; i < n; i++)
        if (work[i] - last > tol) {
            double r = (work[i] - last) / q;
            if (fabs(r - floor(r + 0.5)) <= QUANTUM_TOL)
                on++;
            else if ((double) (gaps - ++off) < QUANTUM_SHARE * (double) gaps)
                return 0.0;
            last = work[i];
        }
    return (double) on >= QUANTUM_SHARE * (double) gaps ? q : 0.0;
}
