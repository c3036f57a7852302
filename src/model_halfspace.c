/* model_halfspace.c: JKR adhesion of a power-law punch on an elastic
 * half-space (physics.md section 4; Borodich, Galanov & Suarez-Alvarez
 * 2014, JMPS 68:14), the thick-layer limit of the exact model.
 *
 *   delta = A a^k - sqrt(2 pi w a / E*),          A = kappa_k / (k R^(k-1))
 *   P     = 2 E* A k a^(k+1)/(k+1) - sqrt(8 pi w E* a^3)
 * Displacement control is unstable where ddelta/da < 0: the unloading
 * branch ends at a_det^(k-1/2) = sqrt(2 pi w/E*) R^(k-1)/(2 kappa_k), the
 * minimum of delta(a); the force-controlled pull-off is the minimum of P,
 * a_c^(k-1/2) = (3/(4 kappa_k)) sqrt(8 pi w/E*) R^(k-1).  Loading makes
 * contact at delta = 0 and jumps onto the stable branch there (P_jump), as
 * the other models do.  The construction needs k > 1/2: for k <= 1/2 the
 * adhesive term outgrows the elastic one and no stable branch exists.
 */
#include <math.h>

#include "exact.h"

typedef struct {
    double k, A, Estar, q;   /* q = sqrt(2 pi w / E*) */
    double a_det, delta_det;
} hs_ctx;

static void
hs_curve(const hs_ctx *c, double a, double *delta, double *ddelta, double *P,
         double *dP, double *shift, double *P1)
{
    double ak = pow(a, c->k), sa = sqrt(a);
    *shift = c->q * sa;
    *delta = c->A * ak - *shift;
    *ddelta = c->k * c->A * ak / a - 0.5 * c->q / sa;
    *P1 = 2.0 * c->Estar * c->A * c->k * ak * a / (c->k + 1.0);
    /* S shift = 2 E* a q sqrt(a) */
    *P = *P1 - 2.0 * c->Estar * c->q * a * sa;
    *dP = 2.0 * c->Estar * c->A * c->k * ak - 3.0 * c->Estar * c->q * sa;
}

static int
hs_init(hs_ctx *c, const lf_probe *p, const lf_material *m)
{
    double dd, P, dP, sh, P1;

    if (!(p->k > 0.5))
        return LF_EINVAL;
    c->k = p->k;
    c->A = lf_exact_kappa(p->k) / (p->k * pow(p->R, p->k - 1.0));
    c->Estar = m->Estar;
    c->q = sqrt(2.0 * M_PI * m->w / m->Estar);
    c->a_det = c->q > 0.0 ? pow(c->q / (2.0 * c->k * c->A), 1.0 / (c->k - 0.5)) : 0.0;
    if (c->a_det > 0.0)
        hs_curve(c, c->a_det, &c->delta_det, &dd, &P, &dP, &sh, &P1);
    else
        c->delta_det = 0.0;
    return LF_OK;
}

/* a on the stable branch with delta(a) = target > delta_det: Newton in
 * ln a from `guess` (NAN: none) with a bisection bracket. */
static double
hs_invert(const hs_ctx *c, double target, double guess)
{
    double lo = c->a_det > 0.0 ? log(c->a_det) : -700.0, hi, u, step = 0.25;
    double d, dd, P, dP, sh, P1;
    int i;

    u = guess > 0.0 ? log(guess) : NAN;
    if (!(u > lo))
        u = fmax(log(fmax(target - c->delta_det, 1e-300) / c->A) / c->k, lo + 0.5);
    hs_curve(c, exp(u), &d, &dd, &P, &dP, &sh, &P1);
    if (d >= target) {
        hi = u;
    } else {
        lo = u;
        for (hi = u + step, i = 0; i < 2000; hi += step, step *= 2.0, i++) {
            hs_curve(c, exp(hi), &d, &dd, &P, &dP, &sh, &P1);
            if (d >= target)
                break;
            lo = hi;
        }
        if (lo != u)           /* else keep the guess: Newton from there */
            u = 0.5 * (lo + hi);
        hs_curve(c, exp(u), &d, &dd, &P, &dP, &sh, &P1);
    }
    for (i = 0; i < 200; i++) {
        double g = d - target, un;
        if (g > 0.0)
            hi = u;
        else
            lo = u;
        un = dd > 0.0 ? u - g / (dd * exp(u)) : 0.5 * (lo + hi);
        if (!(un > lo && un < hi))
            un = 0.5 * (lo + hi);
        if (g == 0.0 || fabs(un - u) < 1e-13 || hi - lo < 1e-14)
            return exp(un);
        u = un;
        hs_curve(c, exp(u), &d, &dd, &P, &dP, &sh, &P1);
    }
    return exp(u);
}

static int
hs_eval(void *state, const lf_probe *probe, const lf_material *mat,
        lf_branch branch, size_t n, const double *delta, lf_eval *out)
{
    hs_ctx c;
    size_t i;
    double a_prev = NAN;   /* warm start: data come in order */

    (void) state;
    if (hs_init(&c, probe, mat) != LF_OK)
        return LF_EINVAL;
    for (i = 0; i < n; i++) {
        lf_eval *e = &out[i];
        double start = branch == LF_BRANCH_LOAD ? fmax(0.0, c.delta_det) : c.delta_det;
        int touching = branch == LF_BRANCH_LOAD ? delta[i] >= start : delta[i] > start;
        double a, d, dd, P, dP, sh, P1, S, dPdd;

        if (!touching || (c.q == 0.0 && delta[i] <= 0.0)) {
            e->P = e->a = e->dP_ddelta = e->dP_dlogw = e->dP_dlogE = e->dP_dnu = 0.0;
            continue;
        }
        a = a_prev = hs_invert(&c, delta[i], a_prev);
        hs_curve(&c, a, &d, &dd, &P, &dP, &sh, &P1);
        S = 2.0 * c.Estar * a;
        dPdd = dd > 0.0 ? dP / dd : LF_BIG;
        e->P = P;
        e->a = a;
        e->dP_ddelta = lf_capped(dPdd);
        e->dP_dlogw = lf_capped(-0.5 * S * sh + 0.5 * dPdd * sh);
        e->dP_dlogE = lf_capped(P1 - 0.5 * S * sh - 0.5 * dPdd * sh);
        e->dP_dnu = 0.0;
    }
    return LF_OK;
}

static int
hs_pulloff(void *state, const lf_probe *probe, const lf_material *mat,
           lf_pulloff *out)
{
    hs_ctx c;
    double d, dd, P, dP, sh, P1, a_c;

    (void) state;
    if (hs_init(&c, probe, mat) != LF_OK)
        return LF_EINVAL;
    out->c = 0.0;
    if (c.q == 0.0) {
        out->delta_detach = out->P_detach = out->a_detach = 0.0;
        out->delta_po = out->P_po = out->a_po = out->sigma_po = out->P_jump = 0.0;
        return LF_OK;
    }
    hs_curve(&c, c.a_det, &d, &dd, &P, &dP, &sh, &P1);
    out->delta_detach = d;
    out->P_detach = P;
    out->a_detach = c.a_det;
    a_c = pow(3.0 * c.q / (2.0 * c.k * c.A), 1.0 / (c.k - 0.5));
    hs_curve(&c, a_c, &d, &dd, &P, &dP, &sh, &P1);
    out->delta_po = d;
    out->P_po = P;
    out->a_po = a_c;
    out->sigma_po = -P / (M_PI * a_c * a_c);
    hs_curve(&c, hs_invert(&c, 0.0, NAN), &d, &dd, &P, &dP, &sh, &P1);
    out->P_jump = P;
    return LF_OK;
}

static int
hs_alloc(void **state, const lf_probe *probe, lf_error *err)
{
    *state = NULL;
    if (!(probe->k > 0.5))
        return lf_fail(err, LF_EINVAL,
                       "half-space JKR needs k > 1/2 (got %g): no stable branch", probe->k);
    return LF_OK;
}

const lf_model_type lf_model_halfspace = {
    "halfspace",
    "elastic half-space JKR for a power-law punch (Borodich et al. 2014)",
    hs_alloc,
    NULL,
    hs_eval,
    hs_pulloff,
    1, LF_SCOPE_HALFSPACE, 0.5, 0, NULL, 0.0
};
