/* observe.c: what a lab reads off a force curve without any contact
 * model -- the baseline, the largest adhesion force, the detachment work,
 * the contact point, the deepest indentation and the largest force -- and
 * the result an instrument states in its own header, so that a fit can be
 * put beside them.
 *
 * Each segment is taken in order of depth (the curve's depth axis: the
 * tip-sample separation where the reader forms one, positive into the
 * sample).  Its baseline is the median force over its flat shallow end:
 * the shallowest fifth of its depth range (BASELINE_SPAN), halved while
 * that stretch is not flat (the medians of its shallower and deeper halves
 * differ by more than the noise sd) and still holds BASELINE_MIN points,
 * so that a curve recorded just past its detachment keeps its short
 * baseline clear of the adhesive dip; the noise there is 1.4826 times the
 * median absolute deviation (a curve that ends before its detachment has
 * no baseline, and its shallowest points stand in).  Then:
 *  - adhesion force: the retract segment's baseline minus its least force;
 *  - detachment work: the area between the retract segment and its
 *    baseline over the stretch around that least force where the curve
 *    lies below the baseline, by the trapezoid rule in depth, the crossings
 *    placed by linear interpolation (exact for a piecewise linear curve);
 *  - contact point: the zero-force point of the approach segment (of the
 *    retract segment when there is no approach): from the deepest point
 *    towards the surface, past the first point within three noise sd of
 *    the baseline, the depth where the force crosses the baseline,
 *    interpolated between the two points around the crossing;
 *  - deepest indentation: the curve's deepest point less the contact
 *    point; largest force: the curve's largest force less the baseline
 *    (the retract segment's, else the approach's). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "readers.h"

#define BASELINE_SPAN 0.2     /* the shallowest fifth of a segment's depth range */
#define BASELINE_MIN 8        /* points a halved baseline stretch keeps at least */
#define CONTACT_SD 3.0        /* noise sd that mark the approach leaving the baseline */

/* One segment's points in order of depth, and its baseline. */
typedef struct {
    size_t n;
    double *z, *F;          /* sorted by depth */
    double baseline, noise;
} seg_points;

static int
by_depth(const void *a, const void *b)
{
    const double *x = a, *y = b;
    return (x[0] > y[0]) - (x[0] < y[0]);
}

static int
dcmp(const void *a, const void *b)
{
    double x = *(const double *) a, y = *(const double *) b;
    return (x > y) - (x < y);
}

static double
median_of(double *v, size_t n)
{
    qsort(v, n, sizeof *v, dcmp);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static void
seg_free(seg_points *s)
{
    free(s->z);
    memset(s, 0, sizeof *s);
}

/* z and F (n points) in order of depth where the depths are strictly
 * monotone (a segment as recorded, either way: reversed then, through
 * scratch of 2 n), the order any sort gives; 0 where they are not, left
 * as they were. */
static int
sorted_by_depth(double *z, double *F, size_t n, double *scratch)
{
    size_t i, up = 1, down = 1;

    for (i = 1; i < n && (up || down); i++) {
        up &= z[i] > z[i - 1];
        down &= z[i] < z[i - 1];
    }
    if (up)
        return 1;
    if (!down)
        return 0;
    memcpy(scratch, z, n * sizeof *z);
    memcpy(scratch + n, F, n * sizeof *F);
    for (i = 0; i < n; i++) {
        z[i] = scratch[n - 1 - i];
        F[i] = scratch[2 * n - 1 - i];
    }
    return 1;
}

/* The points of segment seg, sorted by depth, with the baseline; n = 0
 * when the segment has fewer than 5 points.  LF_ENOMEM only. */
static int
seg_load(const lf_curve *c, lf_segment seg, seg_points *s)
{
    size_t n = lf_curve_segment(c, seg, NULL, NULL), i, m = 0;
    double *pair, *tmp, lim, span;

    memset(s, 0, sizeof *s);
    s->baseline = s->noise = NAN;
    if (n < 5)
        return LF_OK;
    pair = malloc(2 * n * sizeof *pair);
    s->z = malloc(3 * n * sizeof *s->z);
    if (pair == NULL || s->z == NULL) {
        free(pair);
        free(s->z);
        s->z = NULL;
        return LF_ENOMEM;
    }
    s->F = s->z + n;
    tmp = s->F + n;
    lf_curve_segment(c, seg, s->z, s->F);
    if (!sorted_by_depth(s->z, s->F, n, pair)) {
        for (i = 0; i < n; i++) {
            pair[2 * i] = s->z[i];
            pair[2 * i + 1] = s->F[i];
        }
        qsort(pair, n, 2 * sizeof *pair, by_depth);
        for (i = 0; i < n; i++) {
            s->z[i] = pair[2 * i];
            s->F[i] = pair[2 * i + 1];
        }
    }
    free(pair);
    s->n = n;
    for (span = BASELINE_SPAN;; span *= 0.5) {
        double sd, lo, hi;
        size_t h;
        lim = s->z[0] + span * (s->z[n - 1] - s->z[0]);
        for (m = 0; m < n && s->z[m] <= lim; m++)
            ;
        if (m < BASELINE_MIN)
            break;
        /* flat: the medians of its two halves within the noise sd */
        h = m / 2;
        for (i = 0; i < m; i++)
            tmp[i] = s->F[i];
        lo = median_of(tmp, h);
        hi = median_of(tmp + h, m - h);
        for (i = 0; i < m; i++)
            tmp[i] = s->F[i];
        s->baseline = median_of(tmp, m);
        for (i = 0; i < m; i++)
            tmp[i] = fabs(s->F[i] - s->baseline);
        sd = 1.4826 * median_of(tmp, m);
        if (fabs(hi - lo) <= sd || span < 1e-3)
            break;
    }
    if (m < BASELINE_MIN) {   /* the last stretch that held enough, or the first points */
        m = 0;
        lim = s->z[0] + 2.0 * span * (s->z[n - 1] - s->z[0]);
        while (m < n && s->z[m] <= lim)
            m++;
        if (m < 3)
            m = n < 3 ? n : 3;
    }
    for (i = 0; i < m; i++)
        tmp[i] = s->F[i];
    s->baseline = median_of(tmp, m);
    for (i = 0; i < m; i++)
        tmp[i] = fabs(tmp[i] - s->baseline);
    s->noise = 1.4826 * median_of(tmp, m);
    return LF_OK;
}

/* The depth at which the line through (z0, y0), (z1, y1) crosses y = 0. */
static double
cross(double z0, double y0, double z1, double y1)
{
    return y0 == y1 ? 0.5 * (z0 + z1) : z0 + (z1 - z0) * y0 / (y0 - y1);
}

/* The retract segment's least force and the area of its dip below the
 * baseline around it. */
static void
adhesion(const seg_points *s, lf_observables *o)
{
    size_t i, imin = 0, lo, hi;
    double area = 0.0;

    for (i = 1; i < s->n; i++)
        if (s->F[i] < s->F[imin])
            imin = i;
    o->adhesion_force = fmax(s->baseline - s->F[imin], 0.0);
    if (!(s->F[imin] < s->baseline)) {
        o->detachment_work = 0.0;
        return;
    }
    for (lo = imin; lo > 0 && s->F[lo - 1] < s->baseline; lo--)
        ;
    for (hi = imin; hi + 1 < s->n && s->F[hi + 1] < s->baseline; hi++)
        ;
    for (i = lo; i < hi; i++)
        area += 0.5 * (2.0 * s->baseline - s->F[i] - s->F[i + 1]) * (s->z[i + 1] - s->z[i]);
    /* the triangles out to the crossings of the baseline */
    if (lo > 0) {
        double y0 = s->F[lo - 1] - s->baseline, y1 = s->F[lo] - s->baseline;
        area += 0.5 * -y1 * (s->z[lo] - cross(s->z[lo - 1], y0, s->z[lo], y1));
    }
    if (hi + 1 < s->n) {
        double y0 = s->F[hi] - s->baseline, y1 = s->F[hi + 1] - s->baseline;
        area += 0.5 * -y0 * (cross(s->z[hi], y0, s->z[hi + 1], y1) - s->z[hi]);
    }
    o->detachment_work = area;
}

/* The zero-force point of a segment (header), NaN when the curve never
 * rises clear of its baseline. */
static double
contact_point(const seg_points *s)
{
    const double thr = CONTACT_SD * s->noise;
    size_t i = s->n - 1;

    if (!(s->F[i] - s->baseline > thr))
        return NAN;
    while (i > 0 && s->F[i] - s->baseline > thr)
        i--;
    while (i > 0 && s->F[i] - s->baseline > 0.0)
        i--;
    if (s->F[i] - s->baseline > 0.0)
        return s->z[0];
    return cross(s->z[i], s->F[i] - s->baseline, s->z[i + 1], s->F[i + 1] - s->baseline);
}

/* The instrument's own result: Optics11 Chiaro / Piuma exports state
 * "E[eff] (Pa)" (the effective modulus of their fit) and, in some, its
 * "Model". */
static void
instrument(const lf_curve *c, lf_observables *o)
{
    const char *v = lf_curve_meta(c, "E[eff] (Pa)");
    double E;

    o->instrument_Eeff = NAN;
    o->instrument_model[0] = '\0';
    if (v != NULL && lf_units_parse(v, LF_Q_DIMENSIONLESS, &E, NULL) == LF_OK && E > 0)
        o->instrument_Eeff = E;
    v = lf_curve_meta(c, "Model");
    if (v != NULL && !isnan(o->instrument_Eeff)) {
        size_t n = strlen(v);
        while (n > 0 && (v[n - 1] == ' ' || v[n - 1] == '\t'))
            n--;
        if (n >= sizeof o->instrument_model)
            n = sizeof o->instrument_model - 1;
        memcpy(o->instrument_model, v, n);
        o->instrument_model[n] = '\0';
    }
}

int
lf_observe(const lf_curve *c, lf_observables *o, lf_error *err)
{
    seg_points ap, re;
    const seg_points *cp;
    double zmax = -INFINITY, fmaxv = -INFINITY;
    size_t i;
    int status;

    memset(o, 0, sizeof *o);
    o->adhesion_force = o->detachment_work = o->contact_point = NAN;
    o->max_indentation = o->max_force = o->baseline = o->noise = NAN;
    instrument(c, o);
    if ((status = seg_load(c, LF_SEG_LOAD, &ap)) != LF_OK
        || (status = seg_load(c, LF_SEG_UNLOAD, &re)) != LF_OK) {
        seg_free(&ap);
        return lf_fail(err, status, "out of memory (observables)");
    }
    if (re.n > 0) {
        o->baseline = re.baseline;
        o->noise = re.noise;
        adhesion(&re, o);
    } else if (ap.n > 0) {
        o->baseline = ap.baseline;
        o->noise = ap.noise;
    }
    cp = ap.n > 0 ? &ap : re.n > 0 ? &re : NULL;
    if (cp != NULL) {
        o->contact_point = contact_point(cp);
        o->contact_segment = cp == &ap ? LF_SEG_LOAD : LF_SEG_UNLOAD;
    }
    for (i = 0; i < c->n; i++) {
        zmax = fmax(zmax, c->depth[i]);
        fmaxv = fmax(fmaxv, c->force[i]);
    }
    if (isfinite(o->baseline))
        o->max_force = fmaxv - o->baseline;
    if (isfinite(o->contact_point))
        o->max_indentation = zmax - o->contact_point;
    seg_free(&ap);
    seg_free(&re);
    return LF_OK;
}

const char *const lf_observed_keys[LF_NOBSERVED] = {
    "adhesion_force_N", "detachment_work_J", "contact_point_m", "max_indentation_m",
    "max_force_N", "instrument_Eeff_Pa"
};

void
lf_observed_values(const lf_observables *o, double v[LF_NOBSERVED])
{
    v[0] = o->adhesion_force;
    v[1] = o->detachment_work;
    v[2] = o->contact_point;
    v[3] = o->max_indentation;
    v[4] = o->max_force;
    v[5] = o->instrument_Eeff;
}
