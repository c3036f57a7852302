/* test_model.c: the thin-layer model against an independent construction.
 *
 * The closed forms of src/model_thin.c are checked against
 *  - the adhesiveless load P1 integrated numerically from the local pressure
 *    p = (Z E* / b)(delta1 - f(r)) (GSL QAG) with the contact radius found by
 *    root finding, and the JKR relations (1)-(2) of the paper applied with
 *    numerical derivatives of P1 and A;
 *  - the numerical minimum of P(delta) for the pull-off (Eq. 13, 25);
 *  - reference numbers of the seed paper's closed forms (Papangelo,
 *    Eq. 12-14, 24-25: the pull-off of k = 2, 3, 5 on a 1 um layer);
 *  - central finite differences for every analytic derivative;
 *  - its evaluation four points at a time (AVX2) against the scalar loop,
 *    bit for bit.
 */
#include <math.h>
#include <string.h>

#include <gsl/gsl_deriv.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>
#include <gsl/gsl_min.h>

#include "internal.h"
#include "layerfit.h"
#include "testlib.h"

typedef struct {
    double k, R, b, M;   /* M = Z E* */
    double delta1;
    gsl_integration_workspace *ws;
} indent;

static double
profile(double r, const indent *s)
{
    return pow(r, s->k) / (s->k * pow(s->R, s->k - 1));
}

static double
profile_minus(double r, void *p)
{
    const indent *s = p;
    return profile(r, s) - s->delta1;
}

/* contact radius where the pressure vanishes, by bisection (independent of
 * the closed form of Eq. 7) */
static double
contact_radius(indent *s)
{
    double lo = 0, hi = s->R;
    int it;

    while (profile_minus(hi, s) < 0)
        hi *= 2;
    for (it = 0; it < 2000 && hi - lo > 4e-16 * hi; it++) {
        double mid = 0.5 * (lo + hi);
        if (profile_minus(mid, s) < 0)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

static double
ring_load(double r, void *p)
{
    const indent *s = p;
    return 2 * M_PI * r * s->M / s->b * (s->delta1 - profile(r, s));
}

static double
P1_numeric(double delta1, void *p)
{
    indent *s = p;
    gsl_function F = { ring_load, s };
    double result, abserr;
    s->delta1 = delta1;
    gsl_integration_qag(&F, 0, contact_radius(s), 0, 1e-13, 1000, GSL_INTEG_GAUSS61,
                        s->ws, &result, &abserr);
    return result;
}

static double
area_numeric(double delta1, void *p)
{
    indent *s = p;
    double a;
    s->delta1 = delta1;
    a = contact_radius(s);
    return M_PI * a * a;
}

/* First (order 1) or second (order 2) derivative by central differences
 * with three levels of Richardson extrapolation: error O(h^8) for a smooth f. */
static double
richardson(double (*f)(double, void *), void *p, double x, double h, int order)
{
    double T[4][4];
    int i, j;

    for (i = 0; i < 4; i++, h *= 0.5) {
        double fp = f(x + h, p), fm = f(x - h, p);
        T[i][0] = order == 1 ? (fp - fm) / (2 * h) : (fp - 2 * f(x, p) + fm) / (h * h);
        for (j = 1; j <= i; j++)
            T[i][j] = T[i][j - 1] + (T[i][j - 1] - T[i - 1][j - 1]) / (pow(4, j) - 1);
    }
    return T[3][3];
}

/* Eq. (1)-(2) with numerical P1, A and their derivatives, at delta1. */
static void
jkr_numeric(indent *s, double w, double delta1, double *delta, double *P)
{
    double h = 0.2 * delta1, dP1, d2P1, dA, root, P1;

    dP1 = richardson(P1_numeric, s, delta1, h, 1);
    d2P1 = richardson(P1_numeric, s, delta1, h, 2);
    dA = richardson(area_numeric, s, delta1, h, 1);
    P1 = P1_numeric(delta1, s);
    root = sqrt(2 * w * dA / d2P1);
    *delta = delta1 - root;
    *P = P1 - dP1 * root;
}

static lf_model *
model_for(double k, double R, double b, lf_base base)
{
    /* the paper's f = r^k/(k R^(k-1)); at k = 1, where R cancels, stated by
     * its prefactor (f = r, the 45-degree cone) */
    lf_probe p = { k, R, b, base, LF_TIP_POWER, 0.0, k == 1.0 ? 1.0 : 0.0 };
    return lf_model_alloc(&lf_model_thin, &p, NULL);
}

static void
test_independent_construction(void)
{
    static const double ks[] = { 1, 1.5, 2, 3, 8 };
    gsl_integration_workspace *ws = gsl_integration_workspace_alloc(1000);
    size_t i, j, base;

    for (base = 0; base < 2; base++) {
        for (i = 0; i < sizeof ks / sizeof ks[0]; i++) {
            const double k = ks[i], R = 0.73e-3, b = 1.31e-6;
            lf_material mat = { 12.3e-3, 1.85e9, base ? 0.35 : 0.0 };
            double Z = base ? (1 - mat.nu) * (1 - mat.nu) / (1 - 2 * mat.nu) : 1;
            indent s = { k, R, b, Z * mat.Estar, 0, ws };
            double c = sqrt(2 * b * mat.w / (Z * mat.Estar));
            lf_model *m = model_for(k, R, b, (lf_base) base);

            for (j = 0; j < 4; j++) {
                double d1 = c * (0.1 + 1.7 * (double) j), delta, P;
                lf_eval e;
                jkr_numeric(&s, mat.w, d1, &delta, &P);
                t_rel(delta, d1 - c, 1e-6, "k=%g %s: Eq. (1) offset delta1 - delta = c at delta1 = %.2gc",
                      k, base ? "bonded" : "frictionless", d1 / c);
                lf_model_eval(m, &mat, LF_BRANCH_UNLOAD, 1, &delta, &e, NULL);
                t_rel(e.P, P, 1e-6, "k=%g %s: Eq. (2) force at delta1 = %.2gc", k,
                      base ? "bonded" : "frictionless", d1 / c);
                delta = d1 - c;
                lf_model_eval(m, &mat, LF_BRANCH_UNLOAD, 1, &delta, &e, NULL);
                t_rel(e.a, sqrt(area_numeric(d1, &s) / M_PI), 1e-12, "k=%g: contact radius (Eq. 7)", k);
            }
            lf_model_free(m);
        }
    }
    gsl_integration_workspace_free(ws);
}

typedef struct {
    const lf_model *m;
    const lf_material *mat;
} curve_ctx;

static double
force_at(double delta, void *p)
{
    const curve_ctx *c = p;
    lf_eval e;
    lf_model_eval(c->m, c->mat, LF_BRANCH_UNLOAD, 1, &delta, &e, NULL);
    return e.P;
}

/* Eq. (25) as printed in the paper (Eq. 13 with Z = 1). */
static double
paper_P_po(double k, double R, double b, double w, double E, double Z)
{
    return -pow(2, 2 / k) * k / (k + 2) * M_PI * E / b * pow(R, 2 * (k - 1) / k)
           * pow(Z, (k - 2) / (2 * k)) * pow(2 * b * w / E, (2 + k) / (2 * k));
}

static void
test_pulloff(void)
{
    static const double ks[] = { 1, 1.5, 2, 2.5, 3, 5, 8 };
    size_t i, base;

    for (base = 0; base < 2; base++)
        for (i = 0; i < sizeof ks / sizeof ks[0]; i++) {
            const double k = ks[i], R = 2.1e-3, b = 0.77e-6;
            lf_material mat = { 23.4e-3, 3.3e9, base ? 0.27 : 0.0 };
            double Z = lf_thin_Z((lf_base) base, mat.nu);
            lf_model *m = model_for(k, R, b, (lf_base) base);
            lf_pulloff po;
            curve_ctx ctx = { m, &mat };
            gsl_function F = { force_at, &ctx };
            gsl_min_fminimizer *mn = gsl_min_fminimizer_alloc(gsl_min_fminimizer_brent);
            double lo, hi, x;
            int it;

            lf_model_pulloff(m, &mat, &po, NULL);
            t_rel(po.P_po, paper_P_po(k, R, b, mat.w, mat.Estar, Z), 1e-12,
                  "k=%g %s: pull-off force equals Eq. (25)", k, base ? "bonded" : "frictionless");
            lo = po.delta_detach * (1 - 1e-9);
            hi = po.delta_detach + 10 * (po.delta_po - po.delta_detach);
            gsl_min_fminimizer_set(mn, &F, 0.5 * (po.delta_po + hi), lo, hi);
            for (it = 0; it < 200; it++) {
                gsl_min_fminimizer_iterate(mn);
                if (gsl_min_test_interval(gsl_min_fminimizer_x_lower(mn),
                                          gsl_min_fminimizer_x_upper(mn), 1e-20, 1e-12) == GSL_SUCCESS)
                    break;
            }
            x = gsl_min_fminimizer_x_minimum(mn);
            t_rel(gsl_min_fminimizer_f_minimum(mn), po.P_po, 1e-10,
                  "k=%g %s: numerical minimum of P equals P_po", k, base ? "bonded" : "frictionless");
            t_rel(x, po.delta_po, 1e-5, "k=%g: numerical argmin equals delta_po", k);
            t_rel(po.sigma_po, k / (k + 2) * sqrt(2 * Z * mat.Estar * mat.w / b), 1e-12,
                  "k=%g: mean tension Eq. (18) with M = Z E*", k);
            t_rel(po.P_jump, force_at(0.0, &ctx), 1e-12, "k=%g: jump-in force is P(0)", k);
            gsl_min_fminimizer_free(mn);
            lf_model_free(m);
        }
}

static void
test_hertz_limit(void)
{
    static const double bs[] = { 1e-8, 1e-6, 3e-4 }, Es[] = { 1e5, 2.2e9, 4e11 }, nus[] = { 0, 0.3, 0.49 };
    size_t i, j, l;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            for (l = 0; l < 3; l++) {
                const double R = 1.7e-3, w = 0.042;
                lf_material mat = { w, Es[j], nus[l] };
                lf_model *m = model_for(2, R, bs[i], LF_BASE_BONDED);
                lf_pulloff po;
                lf_model_pulloff(m, &mat, &po, NULL);
                t_rel(po.P_po, -2 * M_PI * R * w, 1e-12, "k=2 pull-off -2 pi R w at b=%g E*=%g nu=%g",
                      bs[i], Es[j], nus[l]);
                lf_model_free(m);
            }
}

static void
test_reference_numbers(void)
{
    static const struct { double k; lf_base base; double nu, P, a; } ref[] = {
        { 2, LF_BASE_FRICTIONLESS, 0, -6.283185e-05, 2.9907e-06 },
        { 3, LF_BASE_FRICTIONLESS, 0, -3.632281e-03, 2.0758e-05 },
        { 5, LF_BASE_FRICTIONLESS, 0, -9.597427e-02, NAN },
        { 3, LF_BASE_BONDED, 0.3, -3.757239e-03, 2.0067e-05 },
    };
    static const double fig4_k[] = { 2, 2.5, 3, 4 }, fig4_rb[] = { 1e2, 1e3, 1e4 };
    static const double fig4[3][4] = { { -1.000, -7.169, -26.833, -140.983 },
                                       { -1.000, -11.362, -57.810, -445.827 },
                                       { -1.000, -18.007, -124.547, -1409.828 } };
    const lf_material mat = { 10e-3, 1e9, 0.3 };
    size_t i, j;

    for (i = 0; i < sizeof ref / sizeof ref[0]; i++) {
        lf_model *m = model_for(ref[i].k, 1e-3, 1e-6, ref[i].base);
        lf_pulloff po;
        lf_model_pulloff(m, &mat, &po, NULL);
        t_rel(po.P_po, ref[i].P, 5e-7, "Eq. 24-25: P_po k=%g %s", ref[i].k,
              ref[i].base ? "bonded" : "frictionless");
        if (!isnan(ref[i].a))
            t_rel(po.a_po, ref[i].a, 5e-5, "Eq. 24-25: a_po k=%g", ref[i].k);
        lf_model_free(m);
    }
    for (i = 0; i < 3; i++)
        for (j = 0; j < 4; j++) {
            double R = fig4_rb[i] * 1e-6;
            lf_model *m = model_for(fig4_k[j], R, 1e-6, LF_BASE_FRICTIONLESS);
            lf_pulloff po;
            lf_model_pulloff(m, &mat, &po, NULL);
            t_abs(po.P_po / (2 * M_PI * R * mat.w), fig4[i][j], 6e-4, "Fig. 4: R/b=%g k=%g",
                  fig4_rb[i], fig4_k[j]);
            lf_model_free(m);
        }
    t_rel(lf_thin_b_critical(2, 10e-3, 1e9, 10e6), 50e-9, 1e-12, "Eq. (19): b_cr = 50 nm at k = 2");
    t_rel(lf_thin_b_critical(3, 10e-3, 1e9, 10e6), 72e-9, 1e-12, "Eq. (19): b_cr = 72 nm at k = 3");
    /* Eq. (20): b_cr/a_po at b = b_cr, closed form of the paper */
    for (i = 0; i < 3; i++) {
        double k = 2.5 + 2.0 * (double) i, R = 1e-3, sth = 10e6, w = 10e-3, E = 1e9;
        double bcr = lf_thin_b_critical(k, w, E, sth);
        lf_model *m = model_for(k, R, bcr, LF_BASE_FRICTIONLESS);
        lf_pulloff po;
        double eq20 = pow(2, 1 - 2 / k) * pow(k / (k + 2), 2 - 1 / k) * E / sth
                      * pow(w / sth / R, (k - 1) / k);
        lf_material m0 = { w, E, 0 };
        lf_model_pulloff(m, &m0, &po, NULL);
        t_rel(bcr / po.a_po, eq20, 1e-12, "Eq. (20) at k=%g", k);
        t_rel(po.sigma_po, sth, 1e-12, "at b_cr the mean tension is sigma_th, k=%g", k);
        lf_model_free(m);
    }
    t_rel(lf_jkr_sphere_a_po(1e-3, 10e-3, 1e9), cbrt(9 * M_PI * 1e-6 * 10e-3 / 8e9), 1e-15,
          "half-space JKR pull-off radius");
}

/* derivative of one output member by central differences in a variable */
typedef struct {
    lf_model *m;
    lf_material mat;
    double delta;
    int var;        /* 0 delta, 1 ln w, 2 ln E, 3 nu */
} fd_ctx;

static double
fd_force(double x, void *p)
{
    fd_ctx c = *(fd_ctx *) p;
    lf_eval e;
    switch (c.var) {
    case 0: c.delta = x; break;
    case 1: c.mat.w = exp(x); break;
    case 2: c.mat.Estar = exp(x); break;
    default: c.mat.nu = x; break;
    }
    lf_model_eval(c.m, &c.mat, LF_BRANCH_UNLOAD, 1, &c.delta, &e, NULL);
    return e.P;
}

static void
test_derivatives(void)
{
    static const double ks[] = { 1, 1.5, 2, 2.5, 3, 6, 12 }, nus[] = { 0.0, 0.2, 0.45 };
    static const double u[] = { 1e-6, 1e-3, 0.3, 1.0, 1.7, 5.0, 40.0 }; /* delta1/c */
    const char *names[] = { "dP/ddelta", "dP/dln w", "dP/dln E*", "dP/dnu" };
    size_t i, j, l, v, base;

    for (base = 0; base < 2; base++)
        for (i = 0; i < sizeof ks / sizeof ks[0]; i++)
            for (j = 0; j < (base ? 3u : 1u); j++) {
                lf_model *m = model_for(ks[i], 1.3e-3, 2.1e-6, (lf_base) base);
                lf_material mat = { 31e-3, 0.7e9, nus[j] };
                double c = sqrt(2 * 2.1e-6 * mat.w / (lf_thin_Z((lf_base) base, nus[j]) * mat.Estar));
                for (l = 0; l < sizeof u / sizeof u[0]; l++) {
                    fd_ctx ctx = { m, mat, (u[l] - 1) * c, 0 };
                    lf_eval e;
                    double an[4], x0[4], scale[4], h, d, err;
                    lf_model_eval(m, &mat, LF_BRANCH_UNLOAD, 1, &ctx.delta, &e, NULL);
                    an[0] = e.dP_ddelta; an[1] = e.dP_dlogw; an[2] = e.dP_dlogE; an[3] = e.dP_dnu;
                    x0[0] = ctx.delta; x0[1] = log(mat.w); x0[2] = log(mat.Estar); x0[3] = mat.nu;
                    /* steps that keep the stencil in contact: delta1 moves by at most 1e-3 delta1 */
                    scale[0] = u[l] * c; scale[1] = 2 * u[l]; scale[2] = 2 * u[l];
                    scale[3] = 0.25 * u[l] * (1 - 2 * mat.nu);
                    for (v = 0; v < (base ? 4u : 3u); v++) {
                        gsl_function F = { fd_force, &ctx };
                        ctx.var = (int) v;
                        h = 1e-3 * fmin(scale[v], v ? 1.0 : scale[v]);
                        gsl_deriv_central(&F, x0[v], h, &d, &err);
                        t_true(fabs(an[v] - d) <= 2e-6 * fabs(an[v]) + 10 * err + 1e-12 * fabs(e.P / (v ? 1 : c)),
                               "%s k=%g %s nu=%g at delta1=%gc: analytic %.10g fd %.10g (+-%.2g)",
                               names[v], ks[i], base ? "bonded" : "frictionless", mat.nu, u[l],
                               an[v], d, err);
                    }
                    t_true(isfinite(an[0]) && isfinite(an[1]) && isfinite(an[2]) && isfinite(an[3]),
                           "k=%g derivatives finite at delta1=%gc", ks[i], u[l]);
                }
                lf_model_free(m);
            }
}

static void
test_branches_and_domain(void)
{
    lf_model *m = model_for(3, 1e-3, 1e-6, LF_BASE_BONDED);
    lf_material mat = { 10e-3, 1e9, 0.3 };
    double d[4] = { -1e-6, -1e-9, 0.0, 1e-9 }, tiny;
    lf_eval e[4];
    lf_pulloff po;
    lf_error err;
    size_t i;

    lf_model_pulloff(m, &mat, &po, NULL);
    lf_model_eval(m, &mat, LF_BRANCH_LOAD, 4, d, e, NULL);
    t_true(e[0].P == 0 && e[0].a == 0 && e[1].P == 0 && e[1].dP_ddelta == 0,
           "loading: no contact before delta = 0");
    t_rel(e[2].P, po.P_jump, 1e-14, "loading: jump to P_jump at delta = 0");
    lf_model_eval(m, &mat, LF_BRANCH_UNLOAD, 4, d, e, NULL);
    t_true(e[0].P == 0 && e[0].dP_dlogw == 0, "unloading: no contact below -c");
    t_true(e[1].P < 0 && e[1].a > 0, "unloading: adhesive contact between -c and 0");
    tiny = po.delta_detach * (1 - 1e-15);
    lf_model_eval(m, &mat, LF_BRANCH_UNLOAD, 1, &tiny, e, NULL);
    t_true(isfinite(e[0].dP_ddelta) && isfinite(e[0].dP_dlogw) && isfinite(e[0].dP_dnu),
           "k=3: derivatives stay finite at detachment");

    {   /* w = 0: Jaffar/Barber adhesiveless load, no offset */
        lf_material m0 = { 0, 1e9, 0.3 };
        double x = 20e-9;
        lf_model_eval(m, &m0, LF_BRANCH_UNLOAD, 1, &x, e, NULL);
        t_rel(e[0].P, M_PI * lf_thin_Z(LF_BASE_BONDED, 0.3) * 1e9 / 1e-6 * pow(3, 5.0 / 3) / 5
                      * pow(1e-3, 4.0 / 3) * pow(x, 5.0 / 3), 1e-13, "w = 0: Eq. (21)");
        t_true(e[0].dP_dlogw == 0, "w = 0: no adhesion derivative");
    }

    {
        static const struct { lf_probe p; const char *msg; } badp[] = {
            { { 0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 }, "k must be a finite number > 0 (got 0)" },
            { { -2, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 }, "k must be a finite number > 0 (got -2)" },
            { { 2, -1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 }, "R must be a finite length > 0 (got -0.001 m)" },
            { { 2, 1e-3, 0, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 }, "b must be a finite length > 0 (got 0 m)" },
            { { 2, 1e-3, NAN, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 }, "b must be a finite length > 0 (got nan m)" },
            { { INFINITY, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 }, "k must be a finite number > 0 (got inf)" },
        };
        for (i = 0; i < sizeof badp / sizeof badp[0]; i++) {
            lf_error_clear(&err);
            t_true(lf_model_alloc(&lf_model_thin, &badp[i].p, &err) == NULL, "bad probe %zu refused", i);
            t_str(err.msg, badp[i].msg, "bad probe %zu message", i);
            t_int(err.status, LF_EINVAL, "bad probe %zu status", i);
        }
    }
    {
        static const struct { lf_material m; const char *msg; } badm[] = {
            { { -1e-3, 1e9, 0.3 }, "w must be a finite work of adhesion >= 0 (got -0.001 J/m^2)" },
            { { 1e-3, 0, 0.3 }, "E* must be a finite modulus > 0 (got 0 Pa)" },
            { { 1e-3, 1e9, 0.5 }, "nu must lie in [0, 0.5) for a bonded layer (got 0.5)" },
            { { 1e-3, 1e9, -0.1 }, "nu must lie in [0, 0.5) for a bonded layer (got -0.1)" },
            { { NAN, 1e9, 0.3 }, "w must be a finite work of adhesion >= 0 (got nan J/m^2)" },
            { { 1e-3, INFINITY, 0.3 }, "E* must be a finite modulus > 0 (got inf Pa)" },
        };
        double x = 1e-9;
        for (i = 0; i < sizeof badm / sizeof badm[0]; i++) {
            lf_error_clear(&err);
            e[0].P = 123;
            t_int(lf_model_eval(m, &badm[i].m, LF_BRANCH_UNLOAD, 1, &x, e, &err), LF_EINVAL,
                  "bad material %zu refused", i);
            t_str(err.msg, badm[i].msg, "bad material %zu message", i);
            t_true(e[0].P == 123, "bad material %zu writes no output", i);
            t_int(lf_model_pulloff(m, &badm[i].m, &po, NULL), LF_EINVAL, "bad material %zu: no pull-off", i);
        }
        x = NAN;
        t_int(lf_model_eval(m, &mat, LF_BRANCH_UNLOAD, 1, &x, e, &err), LF_EINVAL, "NaN indentation refused");
    }
    t_true(lf_model_type_find("thin") == &lf_model_thin, "table lookup by name");
    t_true(lf_model_type_find("nosuch") == NULL, "unknown model name");
    lf_model_free(m);
    lf_model_free(NULL);
}

/* The vector path (four points a lane each, src/model_thin.c) and the
 * scalar loop give the same bits: k = 1, 1.5, 2, 3, 4, 6 (the vector
 * kinds and two that are not), with adhesion and without (w = 0), a
 * frictionless and a bonded layer, both branches; 243 points (not a
 * multiple of four, nor of the 64 of a block) from far out of contact
 * through detachment, its neighbourhood and depths a hundred times c, and
 * at w = 0 a few below 1e-300 (k = 3's cube root then takes exp and log:
 * its group of four is the scalar loop's).  On a processor without AVX2
 * both runs take the scalar path. */
#define NP_SIMD 243
static void
test_simd_bits(void)
{
    const double ks[] = { 1.0, 1.5, 2.0, 3.0, 4.0, 6.0 };
    static double d[NP_SIMD];
    static lf_eval e[2][NP_SIMD];
    const int vec = lf_simd(1);
    size_t ki, i;
    int base, adh, br, v, differ = 0, evals = 0;

    (void) vec;     /* read only where the vector path exists */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(LF_NO_SIMD)
    t_int(vec, __builtin_cpu_supports("avx2") ? 1 : 0, "thin model: the vector path where AVX2 is");
#endif
    for (ki = 0; ki < sizeof ks / sizeof ks[0]; ki++)
        for (base = 0; base < 2; base++)
            for (adh = 0; adh < 2; adh++) {
                /* k = 1: a cone of half-angle 70 degrees */
                const lf_probe pr = { ks[ki], 1e-3, 1e-6,
                                      base ? LF_BASE_BONDED : LF_BASE_FRICTIONLESS,
                                      ks[ki] == 1.0 ? LF_TIP_CONE : LF_TIP_POWER, 1.22, 0.0 };
                const lf_material m = { adh ? 0.01 : 0.0, 1e9, 0.3 };
                lf_model *mod = lf_model_alloc(&lf_model_thin, &pr, NULL);
                lf_pulloff po;
                double c;
                if (mod == NULL || lf_model_pulloff(mod, &m, &po, NULL) != LF_OK) {
                    t_true(0, "alloc/pulloff thin simd k = %g", ks[ki]);
                    lf_model_free(mod);
                    continue;
                }
                c = adh ? po.c : 1e-9;
                for (i = 0; i < NP_SIMD; i++)
                    d[i] = -2.0 * c + 102.0 * c * pow((i + 0.5) / NP_SIMD, 2.0 + (i % 7 == 3));
                d[10] = -c;
                d[11] = -c * (1.0 - 1e-15);
                d[12] = -c * (1.0 + 1e-15);
                d[13] = 0.0;
                if (!adh) {
                    d[20] = 1e-305;
                    d[21] = 4e-310;
                    d[22] = 1e-300;
                }
                for (br = 0; br < 2; br++) {
                    int st[2];
                    for (v = 0; v < 2; v++) {
                        lf_simd(v);
                        st[v] = lf_model_eval(mod, &m, br ? LF_BRANCH_LOAD : LF_BRANCH_UNLOAD,
                                              NP_SIMD, d, e[v], NULL);
                    }
                    lf_simd(1);
                    evals++;
                    if (st[0] != LF_OK || st[1] != LF_OK || memcmp(e[0], e[1], sizeof e[0]) != 0)
                        if (differ++ < 3)
                            t_true(0, "thin simd k = %g base %d adhesion %d branch %d: status "
                                   "%d %d, evaluations differ", ks[ki], base, adh, br, st[0],
                                   st[1]);
                }
                lf_model_free(mod);
            }
    t_int(differ, 0, "thin model: vector and scalar paths equal bit for bit in %d evaluations",
          evals);
}

/* k = 3's cube roots four at a time against the scalar loop's over the
 * whole range of the fast root, 1e-300 to 1e300 (w = 0: delta1 = delta),
 * each decade at many mantissas: the first guesses come from the bits
 * (an integer division by 3 done in double arithmetic by the vector path),
 * and one off by a unit would move some roots' last bits. */
#define NP_CBRT 4096
static void
test_simd_cbrt(void)
{
    const lf_probe pr = { 3.0, 1e-3, 1e-6, LF_BASE_FRICTIONLESS, LF_TIP_POWER, 0.0, 0.0 };
    const lf_material m = { 0.0, 1e9, 0.3 };
    static double d[NP_CBRT];
    static lf_eval e[2][NP_CBRT];
    lf_model *mod = lf_model_alloc(&lf_model_thin, &pr, NULL);
    size_t i;
    int v, st[2];

    for (i = 0; i < NP_CBRT; i++)
        d[i] = pow(10.0, -300.0 + 600.0 * (double) i / (NP_CBRT - 1)) * (1.0 + 0.37 * sin(i * 1.7));
    for (v = 0; v < 2; v++) {
        lf_simd(v);
        st[v] = lf_model_eval(mod, &m, LF_BRANCH_UNLOAD, NP_CBRT, d, e[v], NULL);
    }
    lf_simd(1);
    t_true(st[0] == LF_OK && st[1] == LF_OK && memcmp(e[0], e[1], sizeof e[0]) == 0,
           "thin model k = 3: vector and scalar cube roots equal bit for bit over 1e-300..1e300");
    lf_model_free(mod);
}

int
main(void)
{
    gsl_set_error_handler_off();
    test_independent_construction();
    test_pulloff();
    test_hertz_limit();
    test_reference_numbers();
    test_derivatives();
    test_branches_and_domain();
    test_simd_bits();
    test_simd_cbrt();
    return t_summary();
}
