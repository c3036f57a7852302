/* words.c: the words for a fit's intervals and bounds, one module that the
 * command's text report, the JSON (report_json.c), the HTML tables
 * (report_html.c) and the batch rows (batch.c) call, so that they say the
 * same; what a report calls a curve that disagrees; and how the curves of
 * one material differ (lf_heterogeneity). */
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

/* ------------------------------------------------------------------------
 * How the curves of one material differ (lf_heterogeneity), in words: the
 * text report, the HTML page and a batch's summary say the same.
 * --------------------------------------------------------------------- */

const char *
lf_spread_text(char *buf, size_t n, double x, int relative)
{
    if (!isfinite(x))
        snprintf(buf, n, "?");
    else if (relative)
        snprintf(buf, n, "%.2g%%", 100.0 * x);
    else
        snprintf(buf, n, "%.2g", x);
    return buf;
}

const char *
lf_param_text(char *buf, size_t n, double x, int m)
{
    if (m == LF_MAT_NU)
        snprintf(buf, n, "%.4g", x);
    else
        lf_human(buf, n, x, m == LF_MAT_W ? "J/m^2" : "Pa");
    return buf;
}

const char *
lf_p_text(char *buf, size_t n, double p)
{
    if (p < 1e-16)
        snprintf(buf, n, "p < 1e-16");
    else
        snprintf(buf, n, "p = %.2g", p);
    return buf;
}

/* "the k = 3, R = 1 mm probe (bonded, b = 1 um)" */
static const char *
probe_text(char *buf, size_t n, const lf_probe *p)
{
    char r[48], b[48];
    snprintf(buf, n, "the k = %g, R = %s probe (%s, b = %s)", p->k,
             lf_human(r, sizeof r, p->R, "m"), p->base == LF_BASE_BONDED ? "bonded" : "frictionless",
             lf_human(b, sizeof b, p->b, "m"));
    return buf;
}

void
lf_hetero_lines(const lf_heterogeneity *h, void (*put)(void *, const char *), void *ctx)
{
    static const char *const name[3] = { "w", "E*", "nu" };
    const lf_population_estimate *pe[3] = { &h->w, &h->Estar, &h->nu };
    char line[700], a[48], b[48], c[48], d[48], e[48], p[48], sd[48], pr[160];
    int m, disagree = isfinite(h->p_homogeneous) && h->p_homogeneous < 0.05;

    if (h->curves < 2)
        return;
    if (!isfinite(h->p_homogeneous))
        snprintf(line, sizeof line, "the %zu curves: no parameter is determined by two or more "
                 "of them alone, so how much they differ is not measured (not determined from "
                 "single curves): the errors below are those of one material", h->curves);
    else if (disagree)
        snprintf(line, sizeof line, "the %zu curves disagree beyond their errors (each fitted "
                 "alone: %s, I^2 = %.3g%%): %s; quote the population's mean and interval, not "
                 "the joint fit's errors below (those of one material)", h->curves,
                 lf_p_text(p, sizeof p, h->p_homogeneous),
                 100.0 * h->I2,
                 h->probes_disagree ? "the probes disagree with each other (model error, below), "
                                      "and the material varies from spot to spot"
                 : h->probes >= 2 && !isfinite(h->probes_p)
                 ? "the material varies from spot to spot, or the model sees the probes "
                   "differently (one curve per probe: not told apart)"
                 : "the material varies from spot to spot");
    else
        snprintf(line, sizeof line, "the %zu curves agree within their errors (each fitted "
                 "alone: %s, I^2 = %.3g%%): the joint fit's errors below stand", h->curves,
                 lf_p_text(p, sizeof p, h->p_homogeneous),
                 100.0 * h->I2);
    put(ctx, line);
    for (m = 0; m < 3; m++) {
        const lf_population_estimate *x = pe[m];
        int rel = m != LF_MAT_NU;
        if (x->n == 0)
            continue;
        if (!isfinite(x->population_mean)) {
            snprintf(line, sizeof line, "%s: not determined from single curves (%zu of the %zu "
                     "determine%s it alone): its spread is not measured, and its error below is "
                     "that of one material", name[m], x->n, h->curves, x->n == 1 ? "s" : "");
            put(ctx, line);
            continue;
        }
        snprintf(line, sizeof line, "%s varies from spot to spot by %s (SD; 95%% %s to %s); the "
                 "population mean is %s (95%% interval %s to %s), from %zu curves fitted alone "
                 "(their own SD %s)", name[m], lf_spread_text(a, sizeof a, x->tau_rel, rel),
                 lf_spread_text(b, sizeof b, x->tau_rel_ci95[0], rel),
                 lf_spread_text(c, sizeof c, x->tau_rel_ci95[1], rel),
                 lf_param_text(d, sizeof d, x->population_mean, m),
                 lf_param_text(e, sizeof e, x->population_ci95[0], m),
                 lf_param_text(p, sizeof p, x->population_ci95[1], m), x->n,
                 rel ? lf_spread_text(sd, sizeof sd, x->sd / x->mean, 1)
                     : lf_spread_text(sd, sizeof sd, x->sd, 0));
        put(ctx, line);
    }
    if (h->probes_disagree) {
        int q = h->probe_param;
        snprintf(line, sizeof line, "%s gives %s %s %s the others' (%.2g standard errors; "
                 "probes compared: %s): probes of different k disagree beyond their errors, "
                 "which is model error (the model describes the probes differently), not "
                 "spot-to-spot variation", probe_text(pr, sizeof pr, &h->probe_departs),
                 q >= 0 ? name[q] : "?",
                 q == LF_MAT_NU ? lf_spread_text(c, sizeof c, fabs(h->probe_diff), 0)
                                : lf_spread_text(c, sizeof c, fabs(h->probe_diff), 1),
                 h->probe_diff > 0 ? "above" : "below", fabs(h->probe_z),
                 lf_p_text(p, sizeof p, h->probes_p));
        put(ctx, line);
    } else if (h->probes >= 2 && isfinite(h->probes_p)) {
        snprintf(line, sizeof line, "the %zu probes agree within the spot-to-spot spread (%s)",
                 h->probes_tested, lf_p_text(p, sizeof p, h->probes_p));
        put(ctx, line);
    } else if (h->probes >= 2) {
        snprintf(line, sizeof line, "%zu probes with one curve or none each determining the "
                 "material alone: a difference between them could be spot-to-spot variation or "
                 "model error, which these curves cannot tell apart", h->probes);
        put(ctx, line);
    }
}
