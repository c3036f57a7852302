/* cli/words.c: the command's words for a fit's intervals and bounds, one
 * module that the text report, the JSON (report.c), the interactive page
 * and the batch table (batch.c) call, so that they say the same. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"

const char *
cli_interval_method(const lf_fit_estimate *e)
{
    if (!e->free)
        return NULL;
    if (!(isfinite(e->ci95[0]) || isfinite(e->ci95[1])))
        return e->interval_method;  /* a profile that found no bound, or nothing */
    return e->interval_method != NULL ? e->interval_method : "linear (Wald)";
}

const char *
cli_interval_words(const lf_fit_estimate *e, int brief)
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
cli_bound_text(const lf_fit_estimate *e, const char *name, const char *unit, char *buf,
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
        cli_human(v, sizeof v, bound, unit);
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
