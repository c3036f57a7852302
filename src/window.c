/* window.c: fit windows -- the part of a curve a fit takes, as labs state
 * it: a range of indentation from the curve's contact point and a range
 * of force above its baseline, both found without a model (lf_observe),
 * each absolute ("0:500nm", "-20nN:2uN") or relative ("0:30%": of the
 * deepest indentation, of the largest force).  A side left empty is open
 * (":500nm").  The window is placed on each curve in its own depth and
 * force (lf_window_place) and the points outside it are left out of the
 * fit; what was kept is said with the result. */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"

lf_window
lf_window_all(void)
{
    lf_window w;
    w.depth.lo = w.depth.hi = w.force.lo = w.force.hi = NAN;
    w.depth.relative = w.force.relative = 0;
    return w;
}

int
lf_window_is_all(const lf_window *w)
{
    return isnan(w->depth.lo) && isnan(w->depth.hi) && isnan(w->force.lo) && isnan(w->force.hi);
}

/* One side of a range: "" (open, NaN), "30%" (relative, 0.3), a number
 * with a unit of q, or a bare 0 (either kind).  *kind: 0 open, 1
 * absolute, 2 relative, 3 a bare zero. */
static int
side_parse(const char *text, size_t len, lf_quantity q, double *v, int *kind, lf_error *err)
{
    char buf[128], *end;
    size_t a = 0, b = len;

    while (a < b && isspace((unsigned char) text[a]))
        a++;
    while (b > a && isspace((unsigned char) text[b - 1]))
        b--;
    *v = NAN;
    *kind = 0;
    if (a == b)
        return LF_OK;
    if (b - a >= sizeof buf)
        return lf_fail(err, LF_EINVAL, "'%.*s' is too long for a bound", (int) len, text);
    memcpy(buf, text + a, b - a);
    buf[b - a] = '\0';
    if (buf[b - a - 1] == '%') {
        buf[b - a - 1] = '\0';
        *v = strtod(buf, &end);
        if (end == buf || *end != '\0' || !isfinite(*v))
            return lf_fail(err, LF_EINVAL, "'%s%%' is not a percentage (e.g. 30%%)", buf);
        *v /= 100.0;
        *kind = 2;
        return LF_OK;
    }
    *v = strtod(buf, &end);
    if (end != buf && *v == 0.0 && end[strspn(end, " \t")] == '\0') {
        *kind = 3;
        return LF_OK;
    }
    if (lf_units_parse(buf, q, v, err) != LF_OK)
        return err != NULL ? err->status : LF_EUNIT;
    *kind = 1;
    return LF_OK;
}

int
lf_range_parse(const char *text, lf_quantity q, lf_range *r, lf_error *err)
{
    const char *colon = strchr(text, ':');
    int klo, khi, status;

    r->lo = r->hi = NAN;
    r->relative = 0;
    if (colon == NULL || strchr(colon + 1, ':') != NULL)
        return lf_fail(err, LF_EINVAL, "'%s' is not a range LO:HI (e.g. 0:500nm or 0:30%%; "
                       "a side left empty is open)", text);
    if ((status = side_parse(text, (size_t) (colon - text), q, &r->lo, &klo, err)) != LF_OK
        || (status = side_parse(colon + 1, strlen(colon + 1), q, &r->hi, &khi, err)) != LF_OK)
        return status;
    if ((klo == 1 && khi == 2) || (klo == 2 && khi == 1))
        return lf_fail(err, LF_EINVAL, "'%s' mixes a percentage and a %s: give both sides in "
                       "%% or both with units", text, q == LF_Q_FORCE ? "force" : "length");
    r->relative = klo == 2 || khi == 2;
    if (!isnan(r->lo) && !isnan(r->hi) && !(r->lo < r->hi))
        return lf_fail(err, LF_EINVAL, "'%s': the low end must lie below the high end", text);
    return LF_OK;
}

/* One range placed: [lo, hi] in SI for a scale (relative) and an origin
 * added to both; an open side is -inf or +inf. */
static void
place(const lf_range *r, double scale, double origin, double *lo, double *hi)
{
    double f = r->relative ? scale : 1.0;
    *lo = isnan(r->lo) ? -INFINITY : origin + f * r->lo;
    *hi = isnan(r->hi) ? INFINITY : origin + f * r->hi;
}

int
lf_window_place(const lf_window *w, const lf_observables *o, lf_window_placed *out,
                lf_error *err)
{
    const int has_depth = !isnan(w->depth.lo) || !isnan(w->depth.hi);
    const int has_force = !isnan(w->force.lo) || !isnan(w->force.hi);

    memset(out, 0, sizeof *out);
    out->window = *w;
    out->depth_lo = out->force_lo = -INFINITY;
    out->depth_hi = out->force_hi = INFINITY;
    out->contact_point = o->contact_point;
    out->baseline = o->baseline;
    out->active = has_depth || has_force;
    if (has_depth) {
        if (!isfinite(o->contact_point))
            return lf_fail(err, LF_EDATA, "no contact point found without a model (the curve "
                           "does not rise clear of its baseline): a depth window cannot be "
                           "placed");
        if (w->depth.relative && !(o->max_indentation > 0))
            return lf_fail(err, LF_EDATA, "the curve's deepest point is not past its contact "
                           "point: a relative depth window cannot be placed");
        place(&w->depth, o->max_indentation, o->contact_point, &out->depth_lo, &out->depth_hi);
    }
    if (has_force) {
        if (!isfinite(o->baseline))
            return lf_fail(err, LF_EDATA, "no baseline found: a force window cannot be placed");
        if (w->force.relative && !(o->max_force > 0))
            return lf_fail(err, LF_EDATA, "the curve's largest force is not above its baseline: "
                           "a relative force window cannot be placed");
        place(&w->force, o->max_force, o->baseline, &out->force_lo, &out->force_hi);
    }
    return LF_OK;
}

int
lf_window_keeps(const lf_window_placed *p, double depth, double force)
{
    return depth >= p->depth_lo && depth <= p->depth_hi && force >= p->force_lo
           && force <= p->force_hi;
}
