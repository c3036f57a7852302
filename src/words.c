/* words.c: the words for a fit's intervals and bounds, one module that the
 * command's text report, the JSON (report_json.c), the HTML tables
 * (report_html.c) and the batch rows (batch.c) call, so that they say the
 * same; and what a report calls a curve that disagrees. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "internal.h"

const char *
lf_interval_method(const lf_fit_estimate *e)
{
    if (!e->free)
        return NULL;
    if (!(isfinite(e->ci95[0]) || isfinite(e->ci95[1])))
        return e->interval_method;  /* a profile that found no bound, or nothing */
    return e->interval_method != NULL ? e->interval_method : "linear (Wald)";
}

const char *
lf_interval_words(const lf_fit_estimate *e, int brief)
{
    const char *m = e->interval_method;

    if (m == NULL)
        return NULL;
    if (strcmp(m, "profile likelihood") == 0)
        return "profile likelihood";
    if (strcmp(m, LF_INTERVAL_JUMP) == 0)
        return brief ? "profile, linear where it jumps"
                     : "profile likelihood; linear on a side where chi2 jumps as a point crosses "
                       "the contact edge";
    if (strcmp(m, LF_INTERVAL_UNCHECKED) == 0)
        return brief ? "linear, not checked" : "linear, not checked: --intervals linear";
    if (strcmp(m, LF_INTERVAL_AT_STOP) == 0)
        return brief ? "linear, where the fit stopped"
                     : "linear, where the fit stopped; not profiled";
    return NULL;
}

const char *
lf_bound_text(const lf_fit_estimate *e, const char *name, const char *unit, char *buf,
               size_t n)
{
    char v[48];
    const char *m = e->interval_method;
    const int below = isfinite(e->ci95[0]), above = isfinite(e->ci95[1]);
    const double bound = below ? e->ci95[0] : e->ci95[1];

    if (e->determined || !e->free || e->upper_bound_only || m == NULL
        || strcmp(m, "profile likelihood") != 0 || (below && above))
        return NULL;
    if (unit[0] != '\0')
        lf_human(v, sizeof v, bound, unit);
    else
        snprintf(v, sizeof v, "%.4g", bound);
    if (below)
        snprintf(buf, n, "%s < %s", v, name);
    else if (above)
        snprintf(buf, n, "%s < %s", name, v);
    else
        buf[0] = '\0';
    return buf;
}

int
lf_curve_disagrees(const lf_fit_curve_result *cr)
{
    return !cr->consistent && cr->agreement != 1;
}

size_t
lf_disagreeing(const lf_fit_result *r, char *buf, size_t n)
{
    size_t j, count = 0, len = 0;

    if (n > 0)
        buf[0] = '\0';
    if (!r->converged)
        return 0;
    for (j = 0; j < r->ncurves; j++) {
        int w;
        if (!lf_curve_disagrees(&r->curves[j]))
            continue;
        w = snprintf(buf + len, n - len, "%s%zu", count ? ", " : "", j + 1);
        if (w > 0 && (size_t) w < n - len)
            len += (size_t) w;
        count++;
    }
    return count;
}
