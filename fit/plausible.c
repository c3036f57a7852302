/* plausible.c: numbers no real test gives, warned of with their likely
 * cause.  A fit converges as happily on depths written in the wrong unit
 * (a `depth_um` header over values in nm: every depth 1000 times too
 * large, 50 um of indentation into a 1 um layer, E* four decades low) as
 * on the right ones, and its errors say nothing of it.  So, at the
 * solution:
 *  - a layer indented deeper than its thickness (models with a layer);
 *  - a contact radius past the probe: for k > 2 the profile tends to a
 *    flat punch of radius R, which no contact passes (k = 2, a sphere, is
 *    uncertainty.c's sphere check);
 *  - a modulus outside what solids have: above PLAUSIBLE_E_MAX (diamond's
 *    is about 1.2 TPa) or below PLAUSIBLE_E_MIN (the softest hydrogels are
 *    some 10 Pa).
 * Each says which unit or input would put it right. */
#include <math.h>

#include "fit.h"

#define PLAUSIBLE_E_MAX 2e12
#define PLAUSIBLE_E_MIN 1.0

void
lf_fit_plausible_curve(const lf_fit *f, size_t j, double z0, double amax, lf_warnings *w)
{
    const fit_curve *c = &f->c[j];
    const lf_probe *p = &c->data.probe;
    double dmax = -HUGE_VAL;
    size_t i;

    if (lf_model_get_type(c->model)->scope != LF_SCOPE_HALFSPACE) {
        for (i = 0; i < c->data.n; i++)
            if (f->ws.ev[c->row + i].a > 0)
                dmax = lf_fmax(dmax, c->data.depth[i] - z0);
        if (dmax > p->b)
            lf_warn(w, "the indentation reaches %.3g m, %.3g times the layer's thickness "
                    "(b = %.3g m): no layer is indented past its thickness; check the depth's "
                    "unit (values in nm read as um make every depth 1000 times too large) and b",
                    dmax, dmax / p->b, p->b);
    }
    if (p->k > 2.0 + 1e-9 && amax > p->R)
        lf_warn(w, "the contact radius reaches a = %.3g m, %.3g R: past the probe (a power-law "
                "profile of k > 2 tends to a flat punch of radius R); check R and the depth's unit",
                amax, amax / p->R);
}

static void
modulus(const char *name, const lf_fit_estimate *e, lf_warnings *w)
{
    if (!e->determined || !isfinite(e->value))
        return;
    if (e->value > PLAUSIBLE_E_MAX)
        lf_warn(w, "%s = %.3g Pa is stiffer than any solid (diamond's modulus is about 1.2 TPa): "
                "check the units of depth (1000 times too small?) and force (1000 times too "
                "large?), and R and b", name, e->value);
    else if (e->value < PLAUSIBLE_E_MIN)
        lf_warn(w, "%s = %.3g Pa is softer than any solid (the softest gels are some 10 Pa): "
                "check the units of depth (1000 times too large?) and force (1000 times too "
                "small?), and R and b", name, e->value);
}

void
lf_fit_plausible(lf_fit_result *r)
{
    modulus("E*", &r->Estar, &r->warnings);
    if (r->M.free)
        modulus("M = Z E*", &r->M, &r->warnings);
}
