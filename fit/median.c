/* median.c: medians in linear time, for the noise estimates (noise.c), the
 * robust weights (reweight.c) and the force offsets of a model's own start
 * (guess_model.c). */
#include <math.h>
#include <stddef.h>

#include "fit.h"

/* The k-th smallest of v[0..n-1] (0-based; v reordered), by quickselect
 * with branch-free partitions (the data are noise, so a branch on each
 * comparison would be mispredicted half the time).  Each round moves the
 * values below the pivot (the median of three) to the front and, if k
 * lies beyond them, keeps the rest; only where none is below (the pivot
 * is the range's least) does it move the values equal to the pivot to
 * the front, so every round shrinks the range, also when many values are
 * equal. */
double
lf_fit_select_kth(double *v, size_t n, size_t k)
{
    size_t lo = 0, hi = n;              /* k in [lo, hi) */

    while (hi - lo > 1) {
        double a = v[lo], b = v[lo + (hi - lo) / 2], c = v[hi - 1], pivot;
        size_t i, j = lo;
        pivot = a < b ? (b < c ? b : lf_fmax(a, c)) : (a < c ? a : lf_fmax(b, c));
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
