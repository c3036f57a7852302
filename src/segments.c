/* segments.c: approach, hold and retract of a curve from the profile of
 * the signal the instrument drives (piezo extension, depth, or the load of
 * a load-controlled test), for files that do not mark their segments.
 *
 * A hold (pause, dwell) keeps the driven signal at its extreme while the
 * sample creeps or relaxes; it belongs to neither branch, and splitting at
 * the deepest point alone would put it into the unloading branch, where the
 * force relaxing at constant depth looks like a vertical wall to a fit. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "readers.h"

static int
cmp_double(const void *a, const void *b)
{
    double x = *(const double *) a, y = *(const double *) b;
    return (x > y) - (x < y);
}

/* Noise sd of x from its second differences (median absolute value,
 * scaled for Gaussian noise: sd(d2) = sqrt(6) sd). */
static double
noise_sd(const double *x, size_t n)
{
    double *d, med;
    size_t i;
    if (n < 3 || (d = malloc((n - 2) * sizeof *d)) == NULL)
        return 0.0;
    for (i = 0; i + 2 < n; i++)
        d[i] = fabs(x[i + 2] - 2.0 * x[i + 1] + x[i]);
    qsort(d, n - 2, sizeof *d, cmp_double);
    med = d[(n - 2) / 2];
    free(d);
    return 1.4826 * med / sqrt(6.0);
}

typedef struct {
    size_t peak, lo, hi;      /* first maximum; hold lo..hi (inclusive) */
    int hold;
} profile;

static profile
find_hold(const double *x, size_t n)
{
    profile p = { 0, 0, 0, 0 };
    double lo = x[0], hi = x[0], tol;
    size_t i, need;

    for (i = 1; i < n; i++) {
        if (x[i] > hi) {
            hi = x[i];
            p.peak = i;
        }
        lo = fmin(lo, x[i]);
    }
    tol = fmin(fmax(6.0 * noise_sd(x, n), 1e-3 * (hi - lo)), 2e-2 * (hi - lo));
    p.lo = p.hi = p.peak;
    while (p.lo > 0 && x[p.lo - 1] >= hi - tol)
        p.lo--;
    while (p.hi + 1 < n && x[p.hi + 1] >= hi - tol)
        p.hi++;
    need = n / 50 > 8 ? n / 50 : 8;
    p.hold = p.hi - p.lo + 1 >= need && hi > lo;
    return p;
}

void
lf_segments_from_profile(lf_curve *c, const double *drive, const double *drive2,
                         const char *what)
{
    profile p;
    size_t i;

    if (c->n == 0)
        return;
    p = find_hold(drive, c->n);
    if (drive2 != NULL) {
        profile q = find_hold(drive2, c->n);
        if (q.hold && (!p.hold || q.hi - q.lo > p.hi - p.lo))
            p = q;
    }
    for (i = 0; i < c->n; i++)
        c->segment[i] = (unsigned char) (p.hold ? (i < p.lo ? LF_SEG_LOAD : i <= p.hi
                                                   ? LF_SEG_HOLD : LF_SEG_UNLOAD)
                                         : i < p.peak ? LF_SEG_LOAD : LF_SEG_UNLOAD);
    if (p.hold)
        lf_warn(&c->info, "segments from the %s profile: a hold at the extreme "
                "(lines %ld-%ld), loading before it, unloading after it", what,
                c->line[p.lo], c->line[p.hi]);
    else
        lf_warn(&c->info, "segments from the %s profile: split at its extreme "
                "(line %ld), no hold", what, c->line[p.peak]);
}

size_t
lf_count_at_min(const double *x, size_t n)
{
    size_t i, k = 0;
    double m = INFINITY;
    for (i = 0; i < n; i++)
        m = fmin(m, x[i]);
    for (i = 0; i < n; i++)
        k += x[i] == m;
    return k;
}

int
lf_is_clamped(const double *x, size_t n)
{
    size_t k = lf_count_at_min(x, n);
    return k >= 20 && (double) k >= 0.05 * (double) n;
}
