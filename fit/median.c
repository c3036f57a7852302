/* median.c: medians in linear time, for the noise estimates (noise.c), the
 * robust weights (reweight.c) and the force offsets of a model's own start
 * (guess_model.c). */
#include <math.h>
#include <stddef.h>

#include "fit.h"

/* The k-th smallest of v[0..n-1] (0-based; v reordered), by quickselect
 * with branch-free partitions (the data are noise, so a branch on each
 * comparison would be mispredicted half the time).  Each round moves the
 * values below the pivot to the front and, if k lies beyond them, keeps
 * the rest.  The pivot of a large range is taken from a sorted sample,
 * next to k's rank on the side that keeps less (Floyd and Rivest's idea,
 * CACM 18(3), 1975: 0.69 -> 0.57 us for the median of 298 departures),
 * of a small one the median of three; only where none is below (the pivot
 * is the range's least) does it move the values equal to the pivot to
 * the front, so every round shrinks the range, also when many values are
 * equal. */
#define SELECT_SAMPLE 9      /* values sampled for a pivot ... */
#define SELECT_SAMPLED 48    /* ... in ranges of at least this many */
double
lf_fit_select_kth(double *v, size_t n, size_t k)
{
    size_t lo = 0, hi = n;              /* k in [lo, hi) */

    while (hi - lo > 1) {
        const size_t m = hi - lo;
        double pivot;
        size_t i, j = lo;
        if (m >= SELECT_SAMPLED) {
            /* SELECT_SAMPLE evenly spaced values, sorted: the pivot is the
             * one next to k's rank on the side that leaves the fewer
             * values to search (a median: about half, then few) */
            double smp[SELECT_SAMPLE];
            size_t a, b, t;
            for (a = 0; a < SELECT_SAMPLE; a++) {
                const double x = v[lo + (2 * a + 1) * m / (2 * SELECT_SAMPLE)];
                for (b = a; b > 0 && smp[b - 1] > x; b--)
                    smp[b] = smp[b - 1];
                smp[b] = x;
            }
            t = SELECT_SAMPLE * (k - lo) / m;
            t = 2 * (k - lo) < m ? (t + 1 < SELECT_SAMPLE ? t + 1 : SELECT_SAMPLE - 1)
                                 : (t > 0 ? t - 1 : 0);
            pivot = smp[t];
        } else {                        /* the median of three */
            const double a = v[lo], b = v[lo + m / 2], c = v[hi - 1];
            pivot = a < b ? (b < c ? b : lf_fmax(a, c)) : (a < c ? a : lf_fmax(b, c));
        }
        for (i = lo; i < hi; i++) {     /* [lo, j) < pivot <= [j, i) */
            double x = v[i];
            v[i] = v[j];
            v[j] = x;
            j += x < pivot;
        }
        if (k < j) {
            hi = j;
            continue;
        }
        if (j > lo) {                   /* the range shrinks: no second pass */
            lo = j;
            continue;
        }
        for (i = lo; i < hi; i++) {     /* [lo, j) == pivot < [j, i) */
            double x = v[i];
            v[i] = v[j];
            v[j] = x;
            j += x <= pivot;
        }
        if (k < j || j == lo)           /* j == lo: a NaN pivot */
            return pivot;
        lo = j;
    }
    return v[k];
}

/* The median of v[0..n-1], n > 0 (v reordered): the same number a sort
 * would give, in linear time. */
double
lf_fit_median(double *v, size_t n)
{
    double upper = lf_fit_select_kth(v, n, n / 2), lower;
    size_t i;

    if (n % 2)
        return upper;
    /* after the selection every v[i], i < n/2, is <= upper */
    lower = v[0];
    for (i = 1; i < n / 2; i++)
        lower = lf_fmax(lower, v[i]);
    return 0.5 * (lower + upper);
}

/* The median of sqrt(v[i]) over v[0..n-1] >= 0, n > 0 (v reordered): the
 * root is monotone, so the selection runs on v and only the middle values
 * are rooted (a noise estimate's departures are squared, not rooted, each:
 * a division per point instead of a division and a square root). */
double
lf_fit_median_sqrt(double *v, size_t n)
{
    double upper = lf_fit_select_kth(v, n, n / 2), lower;
    size_t i;

    if (n % 2)
        return sqrt(upper);
    lower = v[0];
    for (i = 1; i < n / 2; i++)
        lower = lf_fmax(lower, v[i]);
    return 0.5 * (sqrt(lower) + sqrt(upper));
}
