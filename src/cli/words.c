/* cli/words.c: the command's words for a fit's intervals and bounds, one
 * module that the text report, the JSON (report.c), the HTML page (html.c)
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

/* ------------------------------------------------------------------------
 * How the curves of one material differ (lf_heterogeneity), in words: the
 * text report, the HTML page and a batch's summary say the same.
 * --------------------------------------------------------------------- */

const char *
cli_spread_text(char *buf, size_t n, double x, int relative)
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
cli_param_text(char *buf, size_t n, double x, int m)
{
    if (m == LF_MAT_NU)
        snprintf(buf, n, "%.4g", x);
    else
        cli_human(buf, n, x, m == LF_MAT_W ? "J/m^2" : "Pa");
    return buf;
}

const char *
cli_p_text(char *buf, size_t n, double p)
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
             cli_human(r, sizeof r, p->R, "m"), cli_base_name(p->base),
             cli_human(b, sizeof b, p->b, "m"));
    return buf;
}

void
cli_hetero_lines(const lf_heterogeneity *h, void (*put)(void *, const char *), void *ctx)
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
                 cli_p_text(p, sizeof p, h->p_homogeneous),
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
                 cli_p_text(p, sizeof p, h->p_homogeneous),
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
                 "(their own SD %s)", name[m], cli_spread_text(a, sizeof a, x->tau_rel, rel),
                 cli_spread_text(b, sizeof b, x->tau_rel_ci95[0], rel),
                 cli_spread_text(c, sizeof c, x->tau_rel_ci95[1], rel),
                 cli_param_text(d, sizeof d, x->population_mean, m),
                 cli_param_text(e, sizeof e, x->population_ci95[0], m),
                 cli_param_text(p, sizeof p, x->population_ci95[1], m), x->n,
                 rel ? cli_spread_text(sd, sizeof sd, x->sd / x->mean, 1)
                     : cli_spread_text(sd, sizeof sd, x->sd, 0));
        put(ctx, line);
    }
    if (h->probes_disagree) {
        int q = h->probe_param;
        snprintf(line, sizeof line, "%s gives %s %s %s the others' (%.2g standard errors; "
                 "probes compared: %s): probes of different k disagree beyond their errors, "
                 "which is model error (the model describes the probes differently), not "
                 "spot-to-spot variation", probe_text(pr, sizeof pr, &h->probe_departs),
                 q >= 0 ? name[q] : "?",
                 q == LF_MAT_NU ? cli_spread_text(c, sizeof c, fabs(h->probe_diff), 0)
                                : cli_spread_text(c, sizeof c, fabs(h->probe_diff), 1),
                 h->probe_diff > 0 ? "above" : "below", fabs(h->probe_z),
                 cli_p_text(p, sizeof p, h->probes_p));
        put(ctx, line);
    } else if (h->probes >= 2 && isfinite(h->probes_p)) {
        snprintf(line, sizeof line, "the %zu probes agree within the spot-to-spot spread (%s)",
                 h->probes_tested, cli_p_text(p, sizeof p, h->probes_p));
        put(ctx, line);
    } else if (h->probes >= 2) {
        snprintf(line, sizeof line, "%zu probes with one curve or none each determining the "
                 "material alone: a difference between them could be spot-to-spot variation or "
                 "model error, which these curves cannot tell apart", h->probes);
        put(ctx, line);
    }
}
