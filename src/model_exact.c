/* model_exact.c: adhesive (JKR) indentation of an elastic layer of any
 * thickness on a frictionless or bonded rigid base by a power-law punch,
 * from the Lebedev-Ufliand Fredholm equation (physics.md section 3).
 *
 * With a = tau h and the tabulated functions s, e, d, p of exact.h:
 *   delta1 = A1 tau^k d,             A1 = B kappa_k h^k,  B = 1/(k R^(k-1))
 *   shift  = A2 sqrt(tau) / e,       A2 = sqrt(2 pi h w / E*)
 *   delta  = delta1 - shift          (JKR edge condition)
 *   P      = F1 tau^(k+1) p - S shift,  F1 = 2 E* B kappa_k h^(k+1),
 *   S      = 2 E* h tau s            (flat-punch stiffness)
 * Derivatives at fixed delta follow from those at fixed tau and
 * dP/ddelta = (dP/dtau)/(ddelta/dtau).
 *
 * Branches.  delta(tau) has a minimum at small tau (the half-space
 * displacement-control instability, section 4): the unloading branch keeps
 * contact for tau above the largest tau where ddelta/dtau = 0 and ends
 * there (delta_detach, P_detach, a_detach); below delta_detach there is no
 * contact.  Loading makes contact at delta = 0 and jumps to the stable
 * branch at delta = 0 (force P_jump), as in the thin-layer model; for
 * delta >= 0 both branches coincide.  Without adhesion (w = 0) the branch
 * reaches tau -> 0 at delta = 0.
 */
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "exact.h"

/* The model object's state: the tables it uses, resolved from the process
 * store when the model is made (frictionless) or prepared for a nu range
 * (bonded), so that eval reads them with one atomic load and no lock.
 * Slot 0 holds the frictionless table, slot i + 1 the bonded nu node i
 * (-1 .. LF_EXACT_NY).  A slot, once set, always holds the same pointer
 * (the store hands out one table per key). */
typedef struct {
    _Atomic(const lf_exact_table *) tab[LF_EXACT_NY + 2];
} exact_state;

/* The table of nu node `node` (ignored when frictionless), from the state
 * or, the first time, from the store. */
static int
resolve(exact_state *st, const lf_probe *pr, int node, const lf_exact_table **out,
        lf_error *err)
{
    int bonded = pr->base == LF_BASE_BONDED, slot = bonded ? node + 1 : 0, status;

    *out = atomic_load_explicit(&st->tab[slot], memory_order_acquire);
    if (*out != NULL)
        return LF_OK;
    status = lf_exact_table_get(pr->k, pr->base, bonded ? lf_exact_nu_node(node) : 0.0, out, err);
    if (status == LF_OK)
        atomic_store_explicit(&st->tab[slot], *out, memory_order_release);
    return status;
}

/* The interpolation at nu from the model's tables. */
static int
state_mix(exact_state *st, const lf_probe *pr, double nu, lf_exact_mix *mx, lf_error *err)
{
    int m, status = lf_exact_mix_weights(mx, pr->base, nu, err);

    for (m = 0; m < mx->m && status == LF_OK; m++)
        status = resolve(st, pr, mx->node0 + m, &mx->t[m], err);
    return status;
}

/* Everything one (probe, material) pair needs. */
typedef struct {
    lf_exact_mix mix;
    lf_exact_premix premix;   /* bonded: the mix flattened for this nu */
    double k, h, Estar;
    double A1, A2, F1;
    double u_det;     /* ln tau at detachment, -INFINITY when none */
    double delta_det;
} exact_ctx;

/* The curve at tau: delta, P, their tau-derivatives, and the partial
 * derivatives at fixed tau needed for the Jacobian. */
typedef struct {
    double delta, P, ddelta, dP;       /* d/dtau */
    double shift, S, P1;               /* adhesive shift, stiffness, P1 */
    double ddelta_nu, dP_nu;           /* d/dnu at fixed tau */
} exact_pt;

/* u = ln tau.  Each product of a power of tau and a tabulated function
 * is one exponential of a sum of logarithms; the tau-derivatives follow as
 * value times the sum of the logarithmic derivatives (G = f'/f). */
static void
curve_at(const exact_ctx *c, double u, int want_nu, exact_pt *o)
{
    double F[4], G[4], H[4];
    double tau = exp(u), it = 1.0 / tau, k = c->k, D1, Ssh;

    lf_exact_mix_eval_log(&c->mix, u, tau, F, G, want_nu ? H : NULL);
    D1 = c->A1 * exp(k * u + F[2]);                    /* A1 tau^k d */
    o->shift = c->A2 * exp(0.5 * u - F[1]);            /* A2 sqrt(tau) / e */
    o->S = 2.0 * c->Estar * c->h * exp(u + F[0]);      /* 2 E* h tau s */
    o->P1 = c->F1 * exp((k + 1.0) * u + F[3]);         /* F1 tau^(k+1) p */
    Ssh = o->S * o->shift;
    o->delta = D1 - o->shift;
    o->ddelta = D1 * (k * it + G[2]) - o->shift * (0.5 * it - G[1]);
    o->P = o->P1 - Ssh;
    o->dP = o->P1 * ((k + 1.0) * it + G[3]) - Ssh * (1.5 * it + G[0] - G[1]);
    if (want_nu) {
        o->ddelta_nu = D1 * H[2] + o->shift * H[1];
        o->dP_nu = o->P1 * H[3] - Ssh * (H[0] - H[1]);
    } else {
        o->ddelta_nu = o->dP_nu = 0.0;
    }
}

#define U_LOW (-60.0)   /* ln tau treated as contact vanishing */
#define U_HIGH 30.0

/* The start of the stable branch: the largest tau with ddelta/dtau = 0,
 * scanning down in ln tau from the thin-layer regime. */
static void
find_detach(exact_ctx *c)
{
    exact_pt pt;
    double u, u_hi, u_lo, f_lo, f_hi;
    int i, side = 0;

    c->u_det = -INFINITY;
    c->delta_det = 0.0;
    if (c->A2 == 0.0)
        return;
    for (u = log(1e4); u > U_LOW; u -= 0.25) {
        curve_at(c, u, 0, &pt);
        if (pt.ddelta <= 0.0)
            break;
    }
    if (u <= U_LOW)
        return; /* monotonic down to a -> 0 (k < 1/2) */
    u_lo = u;
    u_hi = u + 0.25;
    f_lo = pt.ddelta;
    curve_at(c, u_hi, 0, &pt);
    f_hi = pt.ddelta;
    /* Illinois (regula falsi that halves the stale end's value): the
     * bracket ddelta(u_lo) <= 0 < ddelta(u_hi) kept, superlinear */
    for (i = 0; i < 100 && u_hi - u_lo > 1e-14; i++) {
        double um = (u_lo * f_hi - u_hi * f_lo) / (f_hi - f_lo);
        if (!(um > u_lo && um < u_hi))
            um = 0.5 * (u_lo + u_hi);
        curve_at(c, um, 0, &pt);
        if (pt.ddelta <= 0.0) {
            u_lo = um;
            f_lo = pt.ddelta;
            if (side < 0)
                f_hi *= 0.5;
            side = -1;
        } else {
            u_hi = um;
            f_hi = pt.ddelta;
            if (side > 0)
                f_lo *= 0.5;
            side = 1;
        }
    }
    c->u_det = u_hi;
    curve_at(c, u_hi, 0, &pt);
    c->delta_det = pt.delta;
}

/* st: the model's state, or NULL to take the tables from the store. */
static int
ctx_init(exact_ctx *c, exact_state *st, const lf_probe *pr, const lf_material *m,
         lf_error *err)
{
    double kap, B;
    int status;

    if (pr->base == LF_BASE_BONDED && m->nu > LF_EXACT_NU_MAX)
        return lf_fail(err, LF_EINVAL, "exact model: nu must be <= %g", LF_EXACT_NU_MAX);
    status = st != NULL ? state_mix(st, pr, m->nu, &c->mix, err)
                        : lf_exact_mix_init(&c->mix, pr->k, pr->base, m->nu, err);
    if (status != LF_OK)
        return status;
    lf_exact_premix_init(&c->premix, &c->mix);
    kap = lf_exact_kappa(pr->k);
    B = 1.0 / (pr->k * pow(pr->R, pr->k - 1.0));
    c->k = pr->k;
    c->h = pr->b;
    c->Estar = m->Estar;
    c->A1 = B * kap * pow(pr->b, pr->k);
    c->A2 = sqrt(2.0 * M_PI * pr->b * m->w / m->Estar);
    c->F1 = 2.0 * m->Estar * B * kap * pow(pr->b, pr->k + 1.0);
    find_detach(c);
    return LF_OK;
}

/* ln tau on the stable branch where delta(tau) = target (> delta_det):
 * Newton in ln tau from `guess` (NAN: none), safeguarded by bisection on a
 * bracket [lo, hi] with delta(lo) < target <= delta(hi).  *out receives the
 * curve at the returned ln tau (with the nu derivatives when want_nu). */
static double
invert(const exact_ctx *c, double target, double guess, int want_nu, exact_pt *out)
{
    exact_pt pt;
    double lo = isfinite(c->u_det) ? c->u_det : U_LOW, hi, u, step = 0.25;
    int i;

    u = guess;
    if (!(u > lo && u < U_HIGH)) /* first guess from the half-space form */
        u = fmin(fmax(log(fmax(target - c->delta_det, 1e-300) / c->A1) / c->k, lo + 0.5), U_HIGH);
    curve_at(c, u, want_nu, &pt);
    if (pt.delta >= target) {
        hi = u;
    } else {
        exact_pt pt_u = pt;
        lo = u;
        for (hi = u + step; hi < U_HIGH; hi += step, step *= 2.0) {
            curve_at(c, hi, want_nu, &pt);
            if (pt.delta >= target)
                break;
            lo = hi;
        }
        if (hi >= U_HIGH)
            hi = U_HIGH;
        if (lo == u) {         /* keep the guess: Newton from there */
            pt = pt_u;
        } else {
            u = 0.5 * (lo + hi);
            curve_at(c, u, want_nu, &pt);
        }
    }
    for (i = 0; i < 100; i++) {
        double g = pt.delta - target, gp = pt.ddelta * exp(u), un;
        if (g > 0.0)
            hi = u;
        else
            lo = u;
        un = (gp > 0.0) ? u - g / gp : 0.5 * (lo + hi);
        if (!(un > lo && un < hi))
            un = 0.5 * (lo + hi);
        /* done at the rounding level of delta = A1 tau^k d - shift (the
         * two terms nearly cancel near detachment): chasing g further only
         * bisects rounding noise */
        if (fabs(g) <= 1e-14 * (fabs(pt.delta + pt.shift) + fabs(pt.shift)))
            break;
        /* the next step is below the rounding of ln tau: the point at u
         * stands (its curve is at hand) */
        if (fabs(un - u) < 1e-13 || hi - lo < 1e-14)
            break;
        u = un;
        curve_at(c, u, want_nu, &pt);
    }
    *out = pt;
    return u;
}

/* The evaluation at ln tau = u from the curve there. */
static void
fill_point(const exact_ctx *c, double u, const exact_pt *p, int bonded, lf_eval *e)
{
    exact_pt pt = *p;
    double dPdd, tau = exp(u);

    dPdd = pt.dP / pt.ddelta;
    if (!(pt.ddelta > 0.0))
        dPdd = LF_BIG;
    e->P = pt.P;
    e->a = tau * c->h;
    e->dP_ddelta = lf_capped(dPdd);
    /* at fixed tau: d delta/dln w = -shift/2, dP/dln w = -S shift/2;
     * d delta/dln E = +shift/2, dP/dln E = P1 - S shift/2 */
    e->dP_dlogw = lf_capped(-0.5 * pt.S * pt.shift + dPdd * 0.5 * pt.shift);
    e->dP_dlogE = lf_capped(pt.P1 - 0.5 * pt.S * pt.shift - dPdd * 0.5 * pt.shift);
    e->dP_dnu = bonded ? lf_capped(pt.dP_nu - dPdd * pt.ddelta_nu) : 0.0;
}

static int
exact_alloc(void **state, const lf_probe *probe, lf_error *err)
{
    exact_state *st = calloc(1, sizeof *st);
    const lf_exact_table *t;
    int i, status;

    *state = NULL;
    if (st == NULL)
        return lf_fail(err, LF_ENOMEM, "out of memory (exact model)");
    for (i = 0; i < LF_EXACT_NY + 2; i++)
        atomic_init(&st->tab[i], NULL);
    /* the frictionless table now; bonded node tables when a nu range is
     * prepared (or first needed) */
    if (probe->base == LF_BASE_FRICTIONLESS && (status = resolve(st, probe, 0, &t, err)) != LF_OK) {
        free(st);
        return status;
    }
    *state = st;
    return LF_OK;
}

static int
exact_prepare(void *state, const lf_probe *probe, double nu_lo, double nu_hi, lf_error *err)
{
    lf_exact_mix lo, hi;
    const lf_exact_table *t;
    int i, status;

    if (probe->base != LF_BASE_BONDED)
        return LF_OK;
    nu_lo = fmax(nu_lo, 0.0);
    nu_hi = fmin(nu_hi, LF_EXACT_NU_MAX);
    if (!(nu_lo <= nu_hi))
        return lf_fail(err, LF_EINVAL, "the exact bonded model covers 0 <= nu <= %g",
                       LF_EXACT_NU_MAX);
    if ((status = lf_exact_mix_weights(&lo, probe->base, nu_lo, err)) != LF_OK
        || (status = lf_exact_mix_weights(&hi, probe->base, nu_hi, err)) != LF_OK)
        return status;
    for (i = lo.node0; i <= hi.node0 + 3; i++)
        if ((status = resolve(state, probe, i, &t, err)) != LF_OK)
            return status;
    return LF_OK;
}

static void
exact_free(void *state)
{
    free(state);
}

static int
exact_eval(void *state, const lf_probe *probe, const lf_material *mat,
           lf_branch branch, size_t n, const double *delta, lf_eval *out)
{
    exact_ctx c;
    size_t i;
    int bonded = probe->base == LF_BASE_BONDED;
    /* warm start: data come in order; u(delta) extrapolated to second
     * order from the slopes du/ddelta at the last two points */
    double u_prev = NAN, d_prev = NAN, du_dd = 0.0, d_prev2 = NAN, du_dd2 = 0.0;
    exact_pt pt;
    double guess;

    if (ctx_init(&c, state, probe, mat, NULL) != LF_OK)
        return LF_EINVAL;
    for (i = 0; i < n; i++) {
        lf_eval *e = &out[i];
        double start = branch == LF_BRANCH_LOAD ? fmax(0.0, c.delta_det) : c.delta_det;
        int touching = branch == LF_BRANCH_LOAD ? delta[i] >= start : delta[i] > start;

        if (!touching || (!isfinite(c.u_det) && delta[i] <= 0.0)) {
            e->P = e->a = e->dP_ddelta = e->dP_dlogw = e->dP_dlogE = e->dP_dnu = 0.0;
            continue;
        }
        /* first-order predictor from the previous point on the branch */
        guess = u_prev;
        if (isfinite(d_prev)) {
            double h = delta[i] - d_prev, curv = 0.0;
            if (isfinite(d_prev2) && d_prev != d_prev2)
                curv = (du_dd - du_dd2) / (d_prev - d_prev2);
            guess = u_prev + h * (du_dd + 0.5 * curv * h);
        }
        u_prev = invert(&c, delta[i], guess, bonded, &pt);
        fill_point(&c, u_prev, &pt, bonded, e);
        d_prev2 = d_prev;
        du_dd2 = du_dd;
        d_prev = delta[i];
        du_dd = pt.ddelta > 0.0 ? 1.0 / (pt.ddelta * exp(u_prev)) : 0.0;
    }
    return LF_OK;
}

static int
exact_pulloff(void *state, const lf_probe *probe, const lf_material *mat,
              lf_pulloff *out)
{
    exact_ctx c;
    exact_pt pt;
    double u, u_lo, u_hi;
    int i;

    if (ctx_init(&c, state, probe, mat, NULL) != LF_OK)
        return LF_EINVAL;
    out->c = 0.0;
    if (!isfinite(c.u_det)) {
        out->delta_detach = out->P_detach = out->a_detach = 0.0;
        out->delta_po = out->P_po = out->a_po = out->sigma_po = out->P_jump = 0.0;
        return LF_OK;
    }
    curve_at(&c, c.u_det, 0, &pt);
    out->delta_detach = pt.delta;
    out->P_detach = pt.P;
    out->a_detach = exp(c.u_det) * c.h;
    /* force-controlled pull-off: first minimum of P(tau) above detachment */
    u_lo = c.u_det;
    if (pt.dP >= 0.0) {
        u_hi = u_lo;
    } else {
        for (u = c.u_det + 0.05; u < U_HIGH; u += 0.05) {
            curve_at(&c, u, 0, &pt);
            if (pt.dP >= 0.0)
                break;
            u_lo = u;
        }
        u_hi = u;
        for (i = 0; i < 60 && u_hi - u_lo > 1e-14; i++) {
            double um = 0.5 * (u_lo + u_hi);
            curve_at(&c, um, 0, &pt);
            if (pt.dP >= 0.0)
                u_hi = um;
            else
                u_lo = um;
        }
    }
    curve_at(&c, u_hi, 0, &pt);
    out->delta_po = pt.delta;
    out->P_po = pt.P;
    out->a_po = exp(u_hi) * c.h;
    out->sigma_po = -out->P_po / (M_PI * out->a_po * out->a_po);
    if (c.delta_det < 0.0) {
        invert(&c, 0.0, NAN, 0, &pt);
        out->P_jump = pt.P;
    } else {
        out->P_jump = 0.0;
    }
    return LF_OK;
}

const lf_model_type lf_model_exact = {
    "exact",
    "finite-thickness layer, Lebedev-Ufliand Fredholm equation (Nystrom, tabulated)",
    exact_alloc,
    exact_free,
    exact_eval,
    exact_pulloff,
    2, LF_SCOPE_ANY, 0.0, 1, exact_prepare
};

/* ---------------------------------------------------------------- helpers */

int
lf_exact_thin_ratio(double k, lf_base base, double nu, double tau, double *ratio_P1,
                    lf_error *err)
{
    lf_exact_mix mix;
    double f[4], df[4], kap, Z, p_thin;
    int status;

    *ratio_P1 = NAN;
    if (!(isfinite(k) && k > 0 && isfinite(tau) && tau > 0))
        return lf_fail(err, LF_EINVAL, "exact/thin ratio needs k > 0 and a/b > 0");
    if (base == LF_BASE_BONDED && !(nu >= 0 && nu < 0.5))
        return lf_fail(err, LF_EINVAL, "nu must lie in [0, 0.5) (got %g)", nu);
    status = lf_exact_mix_init(&mix, k, base, nu, err);
    if (status != LF_OK)
        return status;
    lf_exact_mix_eval(&mix, tau, f, df, NULL);
    kap = lf_exact_kappa(k);
    Z = lf_thin_Z(base, nu);
    p_thin = 0.5 * M_PI * Z * tau * k / (kap * (k + 2.0));
    *ratio_P1 = f[3] / p_thin;
    return LF_OK;
}

int
lf_exact_thin_difference(const lf_probe *probe, const lf_material *mat,
                         double ab_min, double ab_max, double *max_rel,
                         lf_error *err)
{
    exact_ctx c;
    double u0, u1, Pmax = 0.0, dmax = 0.0;
    int status, i, n = 200;

    *max_rel = NAN;
    if ((status = lf_probe_check(probe, err)) != LF_OK
        || (status = lf_material_check(mat, probe->base, err)) != LF_OK)
        return status;
    if (!(ab_min > 0 && ab_max > ab_min && isfinite(ab_max)))
        return lf_fail(err, LF_EINVAL, "need 0 < a/b min < a/b max (got %g, %g)", ab_min, ab_max);
    status = ctx_init(&c, NULL, probe, mat, err);
    if (status != LF_OK)
        return status;
    u0 = log(ab_min);
    if (isfinite(c.u_det) && u0 < c.u_det)
        u0 = c.u_det;
    u1 = log(ab_max);
    if (u1 <= u0)
        return lf_fail(err, LF_EINVAL, "a/b range lies below the detachment radius");
    for (i = 0; i <= n; i++) {
        exact_pt pt;
        lf_eval th;
        double d;
        curve_at(&c, u0 + (u1 - u0) * i / n, 0, &pt);
        d = pt.delta;
        status = lf_model_thin.eval(NULL, probe, mat, LF_BRANCH_UNLOAD, 1, &d, &th);
        if (status != LF_OK)
            return lf_fail(err, status, "thin model failed");
        Pmax = fmax(Pmax, fabs(pt.P));
        dmax = fmax(dmax, fabs(th.P - pt.P));
    }
    *max_rel = Pmax > 0.0 ? dmax / Pmax : 0.0;
    return LF_OK;
}

/* ------------------------------------------------------- beyond the tables */

int
lf_exact_far_eval(const lf_probe *pr, const lf_material *mat, lf_branch branch, size_t n,
                  const double *delta, double *P, lf_error *err)
{
    lf_exact_table tail;
    lf_exact_kernel *kr = NULL;
    lf_exact_point pt;
    exact_ctx c;
    double F[2 * LF_EXACT_NFUN], G[2 * LF_EXACT_NFUN], f[4], df[4], tau = LF_EXACT_TAU_MAX;
    double kap, B, Mth, cth, umin = log(LF_EXACT_TAU_MAX);
    const lf_exact_table *tt[4];
    lf_exact_mix mx;
    size_t i;
    int j, m, status, cached;

    if ((status = lf_probe_check(pr, err)) != LF_OK
        || (status = lf_material_check(mat, pr->base, err)) != LF_OK
        || (status = lf_exact_mix_weights(&mx, pr->base, mat->nu, err)) != LF_OK)
        return status;
    /* quick refusal before any solve: every point beyond TAU_MAX by the
     * thin-layer radius a = (k R^(k-1) (delta + c))^(1/k) with a margin */
    Mth = lf_thin_Z(pr->base, mat->nu) * mat->Estar;
    cth = sqrt(2.0 * pr->b * mat->w / Mth);
    for (i = 0; i < n; i++) {
        double d1 = delta[i] + cth;
        if (branch == LF_BRANCH_LOAD && delta[i] < 0.0)
            continue;
        if (!(d1 > 0.0) || pow(pr->k * pow(pr->R, pr->k - 1.0) * d1, 1.0 / pr->k)
                               < 1.2 * LF_EXACT_TAU_MAX * pr->b)
            return lf_fail(err, LF_EDATA, "point %zu is not beyond a/b = %g", i, LF_EXACT_TAU_MAX);
    }
    /* value and slope at TAU_MAX: from the table if it is at hand
     * (frictionless), else one solve at the tables' own node count.  Bonded
     * layers always solve at nu: the tables' interpolation in nu differs
     * from it by ~1e-7, and the answer must not depend on what is cached */
    cached = pr->base == LF_BASE_FRICTIONLESS;
    for (m = 0; m < mx.m && cached; m++)
        cached = (tt[m] = lf_exact_table_find(pr->k, pr->base, pr->base == LF_BASE_BONDED
                                              ? lf_exact_nu_node(mx.node0 + m) : 0.0)) != NULL;
    if (cached) {
        for (m = 0; m < mx.m; m++)
            mx.t[m] = tt[m];
        lf_exact_mix_eval(&mx, tau, f, df, NULL);
    } else {
        status = lf_exact_kernel_alloc(&kr, pr->base, mat->nu, err);
        if (status == LF_OK)
            status = lf_exact_solve(kr, pr->k, tau, lf_exact_nodes(tau), &pt, err);
        lf_exact_kernel_free(kr);
        if (status != LF_OK)
            return status;
        f[0] = pt.s; f[1] = pt.e; f[2] = pt.d; f[3] = pt.p;
        df[0] = pt.ds; df[1] = pt.de; df[2] = pt.dd; df[3] = pt.dp;
    }
    /* a two-node table whose last node is TAU_MAX: beyond it the tables'
     * own tail (exact_table.c), the only part used here */
    memset(&tail, 0, sizeof tail);
    tail.k = pr->k;
    tail.base = pr->base;
    tail.nu = pr->base == LF_BASE_BONDED ? mat->nu : 0.0;
    tail.n = 2;
    tail.h = 1.0;
    tail.l0 = log(tau) - 1.0;
    tail.F = F;
    tail.G = G;
    for (j = 0; j < LF_EXACT_NFUN; j++) {
        F[j] = F[LF_EXACT_NFUN + j] = log(f[j]);
        G[j] = G[LF_EXACT_NFUN + j] = tau * df[j] / f[j];
        tail.flo[j] = f[j];
        tail.dflo[j] = df[j];
    }
    lf_exact_table_finish(&tail);
    memset(&c, 0, sizeof c);
    c.mix.m = 1;
    c.mix.t[0] = &tail;
    c.mix.wl[0] = 1.0;
    kap = lf_exact_kappa(pr->k);
    B = 1.0 / (pr->k * pow(pr->R, pr->k - 1.0));
    c.k = pr->k;
    c.h = pr->b;
    c.Estar = mat->Estar;
    c.A1 = B * kap * pow(pr->b, pr->k);
    c.A2 = sqrt(2.0 * M_PI * pr->b * mat->w / mat->Estar);
    c.F1 = 2.0 * mat->Estar * B * kap * pow(pr->b, pr->k + 1.0);
    /* Newton in ln tau on the monotonic part of the branch, never below
     * TAU_MAX (the root there is the stable branch's: delta rises with tau
     * from the detachment up) */
    for (i = 0; i < n; i++) {
        exact_pt e;
        double u = log(pow(pr->k * pow(pr->R, pr->k - 1.0) * (delta[i] + cth), 1.0 / pr->k) / pr->b);
        int it, done = 0;
        if (branch == LF_BRANCH_LOAD && delta[i] < 0.0) {
            P[i] = 0.0;
            continue;
        }
        for (it = 0; it < 100 && !done; it++) {
            double g, un;
            curve_at(&c, u, 0, &e);
            g = e.delta - delta[i];
            if (!(e.ddelta > 0.0))
                break;
            un = u - g / (e.ddelta * exp(u));
            done = fabs(g) <= 1e-14 * (fabs(e.delta + e.shift) + fabs(e.shift)) || fabs(un - u) < 1e-13;
            u = fmax(un, umin);
        }
        if (!done || u <= umin)
            return lf_fail(err, LF_EDATA, "point %zu is not beyond a/b = %g", i, LF_EXACT_TAU_MAX);
        curve_at(&c, u, 0, &e);
        P[i] = e.P;
    }
    return LF_OK;
}
