/* cli/observed.c: the words of what a lab reads off: the model-free
 * observables of a curve (lf_observe) beside the fit, and its fit window. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"

void
cli_observed_text(FILE *f, const lf_observables *o, const lf_fit_curve_result *cr)
{
    char a[48], b[48], c[48], d[48], e[48];

    fprintf(f, "      measured (no model): adhesion force %s", cli_human(a, sizeof a,
            o->adhesion_force, "N"));
    if (isfinite(o->adhesion_force) && o->adhesion_force < 3.0 * o->noise)
        fputs(" (within 3 noise sd of the baseline: none seen)", f);
    else if (cr != NULL && cr->pulloff_determined && isfinite(o->adhesion_force))
        fprintf(f, " (the model's pull-off %s)", cli_human(b, sizeof b, cr->pulloff.P_po, "N"));
    fprintf(f, ", detachment work %s,\n        contact point %s (%s), deepest indentation %s, "
            "largest force %s\n", cli_human(b, sizeof b, o->detachment_work, "J"),
            cli_human(c, sizeof c, o->contact_point, "m"),
            o->contact_segment == LF_SEG_LOAD ? "approach" : "retract",
            cli_human(d, sizeof d, o->max_indentation, "m"),
            cli_human(e, sizeof e, o->max_force, "N"));
    if (isfinite(o->instrument_Eeff))
        fprintf(f, "      instrument's own result (header): E[eff] %s%s%s%s\n",
                cli_human(a, sizeof a, o->instrument_Eeff, "Pa"),
                o->instrument_model[0] ? " (" : " (its model not stated",
                o->instrument_model, ")");
}

/* One range as stated: "0 .. 30% of 641.4 nm", "50 nm .. 500 nm", "up to
 * 2 µN", "from -20 nN". */
static void
range_words(FILE *f, const lf_range *r, double scale, const char *unit)
{
    char a[48], b[48], c[48];

    if (r->relative) {
        cli_human(c, sizeof c, scale, unit);
        if (isnan(r->lo))
            fprintf(f, "up to %.4g%% of %s", 100.0 * r->hi, c);
        else if (isnan(r->hi))
            fprintf(f, "from %.4g%% of %s", 100.0 * r->lo, c);
        else
            fprintf(f, "%.4g%% .. %.4g%% of %s", 100.0 * r->lo, 100.0 * r->hi, c);
        return;
    }
    if (isnan(r->lo))
        fprintf(f, "up to %s", cli_human(b, sizeof b, r->hi, unit));
    else if (isnan(r->hi))
        fprintf(f, "from %s", cli_human(a, sizeof a, r->lo, unit));
    else
        fprintf(f, "%s .. %s", cli_human(a, sizeof a, r->lo, unit),
                cli_human(b, sizeof b, r->hi, unit));
}

void
cli_window_text(FILE *f, const lf_window_placed *w, const lf_observables *o)
{
    const lf_window *s = &w->window;
    char a[48];

    if (!w->active)
        return;
    fputs("      fit window:", f);
    if (!isnan(s->depth.lo) || !isnan(s->depth.hi)) {
        fputs(" indentation ", f);
        range_words(f, &s->depth, o->max_indentation, "m");
        fprintf(f, " past the contact point %s", cli_human(a, sizeof a, w->contact_point, "m"));
    }
    if (!isnan(s->force.lo) || !isnan(s->force.hi)) {
        fputs(!isnan(s->depth.lo) || !isnan(s->depth.hi) ? ";" : "", f);
        fputs(" force above the baseline ", f);
        range_words(f, &s->force, o->max_force, "N");
    }
    fprintf(f, ": %zu of %zu points\n", w->n_kept, w->n_in);
}
