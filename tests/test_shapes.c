/* test_shapes.c: probe shapes as labs state them (src/probe.c) and the
 * models' cone and sphere forms against the classical closed forms:
 *  - a cone by its half-angle, pyramids by their equivalent cones, a
 *    stated prefactor B, and the refusal of a k = 1 probe stated by R;
 *  - Sneddon's cone on a half-space, P = (2/pi) E* tan(alpha) delta^2
 *    (Sneddon 1965, Int. J. Eng. Sci. 3:47);
 *  - the sphere on a half-space, exact at any a/R (Maugis 1995, J. Colloid
 *    Interface Sci. 170:447), with and without adhesion;
 *  - the sphere on a thin layer (the cap's volume) against a quadrature of
 *    the local pressure (M/b)(delta1 - f(r));
 *  - simulated cones (35 and 70 degrees), a Berkovich tip and true spheres
 *    (contact up to 0.9 R) fitted back to the truth within their standard
 *    errors.
 * The exact model's sphere (a correction of its paraboloid tables) is
 * tested in test_exact.c. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>

#include "scene.h"
#include "testlib.h"

#define DEG (M_PI / 180.0)

static lf_probe
probe_of(lf_tip tip, double k, double R, double b, double angle, double B)
{
    lf_probe p = { 0 };
    p.k = k;
    p.R = R;
    p.b = b;
    p.base = LF_BASE_FRICTIONLESS;
    p.tip = tip;
    p.angle = angle;
    p.B = B;
    return p;
}

static void
test_statements(void)
{
    lf_error err;
    lf_probe p;
    double k;

    /* a cone by its half-angle; R is not used (NaN allowed) */
    p = probe_of(LF_TIP_CONE, 1.0, NAN, 1e-6, 35 * DEG, 0.0);
    t_int(lf_probe_check(&p, &err), LF_OK, "cone 35 deg, no R: accepted");
    t_rel(lf_probe_prefactor(&p), 1.0 / tan(35 * DEG), 1e-15, "cone: B = cot(alpha)");
    t_rel(lf_probe_cone_angle(&p), 35 * DEG, 1e-15, "cone: its own half-angle");
    t_int(lf_probe_uses_R(&p), 0, "cone: R unused");
    /* Berkovich: the cone of area-to-depth ratio 24.5, 70.3 degrees */
    p = probe_of(LF_TIP_BERKOVICH, 1.0, NAN, 1e-6, 0.0, 0.0);
    t_int(lf_probe_check(&p, &err), LF_OK, "berkovich: accepted");
    t_rel(lf_probe_cone_angle(&p), 70.3 * DEG, 1e-15, "berkovich: equivalent cone 70.3 deg");
    t_rel(M_PI * pow(tan(lf_probe_cone_angle(&p)), 2.0), 24.5, 2e-3,
          "berkovich: projected area 24.5 delta^2");
    /* a four-sided pyramid: equal projected area, 4 tan^2(theta) = pi tan^2(alpha);
     * the Vickers pyramid (68 deg faces) is the Berkovich's 70.3 too */
    p = probe_of(LF_TIP_PYRAMID, 1.0, NAN, 1e-6, 68 * DEG, 0.0);
    t_int(lf_probe_check(&p, &err), LF_OK, "pyramid: accepted");
    t_abs(lf_probe_cone_angle(&p) / DEG, 70.3, 0.05, "Vickers pyramid: equivalent cone 70.3 deg");
    p.angle = 35 * DEG;
    t_rel(M_PI * pow(tan(lf_probe_cone_angle(&p)), 2.0), 4.0 * pow(tan(35 * DEG), 2.0), 1e-14,
          "pyramid 35 deg: the cone's area equals the square's");
    /* a stated B of any k */
    p = probe_of(LF_TIP_POWER, 1.5, NAN, 1e-6, 0.0, 2.5e3);
    t_int(lf_probe_check(&p, &err), LF_OK, "power law k = 1.5 with B, no R: accepted");
    t_rel(lf_probe_prefactor(&p), 2.5e3, 0.0, "stated B kept");
    p = probe_of(LF_TIP_POWER, 3.0, 1e-3, 1e-6, 0.0, 0.0);
    t_rel(lf_probe_prefactor(&p), 1.0 / (3.0 * 1e-6), 1e-15, "B from R = 1/(k R^(k-1))");
    p = probe_of(LF_TIP_SPHERE, 2.0, 8e-6, 1e-6, 0.0, 0.0);
    t_int(lf_probe_check(&p, &err), LF_OK, "sphere: accepted");
    t_rel(lf_probe_prefactor(&p), 1.0 / 16e-6, 1e-15, "sphere: its apex's paraboloid, 1/(2R)");

    /* refusals, each saying what to state */
    p = probe_of(LF_TIP_POWER, 1.0, 5e-6, 1e-6, 0.0, 0.0);
    t_int(lf_probe_check(&p, &err), LF_EINVAL, "k = 1 stated by R refused");
    t_contains(err.msg, "R does not shape a cone", "k = 1 by R: says why");
    t_contains(err.msg, "half-angle", "k = 1 by R: says how to state it");
    p = probe_of(LF_TIP_CONE, 2.0, NAN, 1e-6, 35 * DEG, 0.0);
    t_int(lf_probe_check(&p, &err), LF_EINVAL, "a cone with k = 2 refused");
    t_contains(err.msg, "k must be 1 for a cone", "cone k: message");
    p = probe_of(LF_TIP_CONE, 1.0, NAN, 1e-6, 90 * DEG, 0.0);
    t_int(lf_probe_check(&p, &err), LF_EINVAL, "a cone of 90 deg refused");
    t_contains(err.msg, "half-angle must lie between 0 and 90 degrees", "cone angle: message");
    p = probe_of(LF_TIP_SPHERE, 2.0, NAN, 1e-6, 0.0, 0.0);
    t_int(lf_probe_check(&p, &err), LF_EINVAL, "a sphere without R refused");
    t_contains(err.msg, "R must be", "sphere R: message");
    p = probe_of(LF_TIP_POWER, 2.0, 1e-6, 1e-6, 0.0, -1.0);
    t_int(lf_probe_check(&p, &err), LF_EINVAL, "negative B refused");

    t_int(lf_tip_find("berkovich", &k), LF_TIP_BERKOVICH, "tip name berkovich");
    t_rel(k, 1.0, 0.0, "berkovich implies k = 1");
    t_int(lf_tip_find("paraboloid", &k), LF_TIP_POWER, "paraboloid is the power law");
    t_rel(k, 2.0, 0.0, "paraboloid implies k = 2");
    t_int(lf_tip_find("power", &k), LF_TIP_POWER, "power");
    t_true(isnan(k), "power implies no k");
    t_int(lf_tip_find("wedge", NULL), -1, "unknown tip");
    t_str(lf_tip_name(LF_TIP_SPHERE), "sphere", "tip name of the sphere");

    {
        double a;
        t_int(lf_units_parse("35deg", LF_Q_ANGLE, &a, &err), LF_OK, "35deg parses");
        t_rel(a, 35 * DEG, 1e-15, "35deg in rad");
        t_int(lf_units_parse("35°", LF_Q_ANGLE, &a, &err), LF_OK, "35° parses");
        t_rel(a, 35 * DEG, 1e-15, "35° in rad");
        t_int(lf_units_parse("0.5 rad", LF_Q_ANGLE, &a, &err), LF_OK, "0.5 rad parses");
        t_int(lf_units_parse("35", LF_Q_ANGLE, &a, &err), LF_EUNIT, "a bare angle refused");
        t_int(lf_units_parse("35um", LF_Q_ANGLE, &a, &err), LF_EUNIT, "a length is no angle");
    }
}

/* Sneddon's cone: without adhesion P = (2/pi) E* tan(alpha) delta^2 and
 * a = (2/pi) delta tan(alpha); with adhesion the power law's JKR form
 * (Borodich et al. 2014) at k = 1, delta = (pi/2) cot(alpha) a -
 * sqrt(2 pi w a/E*), P = E* cot(alpha)... written through a. */
static void
test_sneddon(void)
{
    static const double angles[] = { 35.0, 55.0, 70.3, 80.0 };
    size_t i, j;

    for (i = 0; i < sizeof angles / sizeof angles[0]; i++) {
        const double al = angles[i] * DEG, E = 2.385e6;
        lf_probe p = probe_of(LF_TIP_CONE, 1.0, NAN, 1.0, al, 0.0);
        lf_material m0 = { 0.0, E, 0.3 }, m1 = { 4.7e-3, E, 0.3 };
        lf_model *mod = lf_model_alloc(&lf_model_halfspace, &p, NULL);
        double d[5], worst = 0.0, worst_a = 0.0, worst1 = 0.0;
        lf_eval e[5];

        if (!t_true(mod != NULL, "cone %g deg: half-space model", angles[i]))
            continue;
        for (j = 0; j < 5; j++)
            d[j] = 1e-8 * pow(10.0, (double) j);
        t_int(lf_model_eval(mod, &m0, LF_BRANCH_UNLOAD, 5, d, e, NULL), LF_OK, "cone eval");
        for (j = 0; j < 5; j++) {
            worst = fmax(worst, fabs(e[j].P / (2.0 / M_PI * E * tan(al) * d[j] * d[j]) - 1.0));
            worst_a = fmax(worst_a, fabs(e[j].a / (2.0 / M_PI * d[j] * tan(al)) - 1.0));
        }
        t_true(worst < 1e-12, "cone %g deg: Sneddon's force within %.1e (< 1e-12)", angles[i], worst);
        t_true(worst_a < 1e-12, "cone %g deg: Sneddon's contact radius within %.1e", angles[i], worst_a);
        /* with adhesion: the JKR curve through a */
        {
            const double q = sqrt(2.0 * M_PI * m1.w / E), cot = 1.0 / tan(al);
            double a[5], dd[5];
            for (j = 0; j < 5; j++) {
                a[j] = 1e-7 * pow(3.0, (double) j);
                dd[j] = 0.5 * M_PI * cot * a[j] - q * sqrt(a[j]);
            }
            t_int(lf_model_eval(mod, &m1, LF_BRANCH_UNLOAD, 5, dd, e, NULL), LF_OK, "cone JKR eval");
            for (j = 0; j < 5; j++) {
                double P = 0.5 * M_PI * E * cot * a[j] * a[j] - sqrt(8.0 * M_PI * m1.w * E * pow(a[j], 3.0));
                worst1 = fmax(worst1, fabs(e[j].P - P) / fabs(0.5 * M_PI * E * cot * a[j] * a[j]));
            }
            t_true(worst1 < 1e-9, "cone %g deg with adhesion: JKR force within %.1e", angles[i], worst1);
        }
        lf_model_free(mod);
    }
}

/* Maugis' sphere on a half-space at a given a, R. */
static void
maugis(double a, double R, double E, double w, double *delta, double *P)
{
    double L = log((R + a) / (R - a));
    *delta = 0.5 * a * L - sqrt(2.0 * M_PI * w * a / E);
    *P = 0.5 * E * ((a * a + R * R) * L - 2.0 * a * R) - sqrt(8.0 * M_PI * w * E * a * a * a);
}

static void
test_maugis(void)
{
    /* above the detachment radius with adhesion, 0.13 R */
    static const double rhos[] = { 0.15, 0.2, 0.4, 0.6, 0.8, 0.9, 0.99 };
    enum { NR = sizeof rhos / sizeof rhos[0] };
    const double R = 8e-6, E = 25e3;
    lf_probe p = probe_of(LF_TIP_SPHERE, 2.0, R, 1.0, 0.0, 0.0), par = p;
    lf_model *mod = lf_model_alloc(&lf_model_halfspace, &p, NULL), *pm;
    size_t i, iw;
    lf_pulloff po;

    par.tip = LF_TIP_POWER;
    pm = lf_model_alloc(&lf_model_halfspace, &par, NULL);
    if (!t_true(mod != NULL && pm != NULL, "sphere: half-space model"))
        return;
    for (iw = 0; iw < 2; iw++) {
        lf_material m = { iw ? 1.2e-3 : 0.0, E, 0.3 };
        double d[NR], Pw[NR], worst = 0.0, worst_a = 0.0;
        lf_eval e[NR];
        for (i = 0; i < NR; i++)
            maugis(rhos[i] * R, R, E, m.w, &d[i], &Pw[i]);
        t_int(lf_model_eval(mod, &m, LF_BRANCH_UNLOAD, NR, d, e, NULL), LF_OK, "sphere eval");
        for (i = 0; i < NR; i++) {
            worst = fmax(worst, fabs(e[i].P - Pw[i]) / (0.5 * E * R * R * (1 + rhos[i]) * rhos[i]));
            worst_a = fmax(worst_a, fabs(e[i].a / (rhos[i] * R) - 1.0));
        }
        t_true(worst < 1e-10, "sphere %s: Maugis' force up to a = 0.99 R within %.1e (< 1e-10)",
               iw ? "with adhesion" : "without adhesion", worst);
        t_true(worst_a < 1e-9, "sphere %s: contact radius within %.1e", iw ? "with adhesion"
               : "without adhesion", worst_a);
    }
    {
        /* small contact: the paraboloid's JKR, -3/2 pi w R, a_po classical;
         * a large one departs from it */
        lf_material m = { 1e-6, E, 0.3 };
        lf_pulloff pp;
        t_int(lf_model_pulloff(mod, &m, &po, NULL), LF_OK, "sphere pull-off");
        t_int(lf_model_pulloff(pm, &m, &pp, NULL), LF_OK, "paraboloid pull-off");
        t_true(po.a_po < 0.05 * R, "weak adhesion: a_po = %.3g R", po.a_po / R);
        t_rel(po.P_po, pp.P_po, 2e-3, "weak adhesion: the paraboloid's pull-off");
        m.w = 0.5;
        t_int(lf_model_pulloff(mod, &m, &po, NULL), LF_OK, "strong adhesion pull-off");
        t_true(po.a_po > 0.3 * R && po.a_po < R, "strong adhesion: a_po = %.3g R", po.a_po / R);
        {
            /* P is smallest at delta_po; delta smallest at delta_detach */
            double dd[3] = { po.delta_po - 1e-9, po.delta_po, po.delta_po + 1e-9 };
            lf_eval e[3];
            lf_model_eval(mod, &m, LF_BRANCH_UNLOAD, 3, dd, e, NULL);
            t_true(e[0].P > e[1].P && e[2].P > e[1].P, "strong adhesion: P minimal at delta_po");
            t_rel(e[1].P, po.P_po, 1e-9, "strong adhesion: P there is P_po");
            dd[0] = po.delta_detach * (1 + 1e-9);
            lf_model_eval(mod, &m, LF_BRANCH_UNLOAD, 1, dd, e, NULL);
            t_true(e[0].a == 0.0, "no contact below the detachment");
        }
    }
    lf_model_free(mod);
    lf_model_free(pm);
}

/* The thin layer's pressure (M/b)(delta1 - f(r)) over the contact. */
typedef struct {
    double R, d1;
} cap;

static double
cap_integrand(double r, void *v)
{
    const cap *c = v;
    return 2.0 * M_PI * r * (c->d1 - (c->R - sqrt(c->R * c->R - r * r)));
}

static void
test_thin_sphere(void)
{
    const double R = 8e-6, b = 50e-9;
    lf_probe p = probe_of(LF_TIP_SPHERE, 2.0, R, b, 0.0, 0.0);
    lf_material m = { 2e-2, 4e5, 0.3 };
    lf_model *mod = lf_model_alloc(&lf_model_thin, &p, NULL);
    gsl_integration_workspace *ws = gsl_integration_workspace_alloc(200);
    const double c = sqrt(2.0 * b * m.w / m.Estar);
    double worst = 0.0, d;
    lf_pulloff po;
    lf_eval e[3];
    size_t i;

    if (!t_true(mod != NULL, "thin sphere model"))
        return;
    for (i = 1; i <= 9; i++) {
        cap cp = { R, 0.1 * R * (double) i };
        gsl_function fn = { cap_integrand, &cp };
        double a = sqrt(cp.d1 * (2.0 * R - cp.d1)), P1, errest, S;
        lf_eval ev;
        gsl_integration_qag(&fn, 0.0, a, 0.0, 1e-13, 200, GSL_INTEG_GAUSS61, ws, &P1, &errest);
        P1 *= m.Estar / b;
        S = M_PI * a * a * m.Estar / b;          /* the thin layer's flat punch */
        d = cp.d1 - c;
        lf_model_eval(mod, &m, LF_BRANCH_UNLOAD, 1, &d, &ev, NULL);
        worst = fmax(worst, fabs(ev.P - (P1 - S * c)) / P1);
        t_rel(ev.a, a, 1e-12, "thin sphere: contact radius at delta1 = %.1f R", 0.1 * (double) i);
    }
    t_true(worst < 1e-10, "thin sphere: P = P1 - S c against the quadrature, within %.1e", worst);
    t_int(lf_model_pulloff(mod, &m, &po, NULL), LF_OK, "thin sphere pull-off");
    {
        double dd[3] = { po.delta_po - 1e-10, po.delta_po, po.delta_po + 1e-10 };
        lf_model_eval(mod, &m, LF_BRANCH_UNLOAD, 3, dd, e, NULL);
        t_true(e[0].P > e[1].P && e[2].P > e[1].P, "thin sphere: P minimal at delta_po");
        t_rel(e[1].dP_ddelta, 0.0, 1e-9 * fabs(po.P_po) / c, "thin sphere: dP/ddelta = 0 there");
    }
    /* past the equator a flat punch of radius R, continuous in P and slope */
    {
        double dd[3] = { R - c - 1e-10 * R, R - c + 1e-10 * R, 1.5 * R };
        t_int(lf_model_eval(mod, &m, LF_BRANCH_UNLOAD, 3, dd, e, NULL), LF_OK,
              "thin sphere past its equator: evaluated");
        t_rel(e[0].P, e[1].P, 1e-9, "thin sphere: P continuous at the equator");
        t_rel(e[0].dP_ddelta, e[1].dP_ddelta, 1e-6, "thin sphere: slope continuous there");
        t_rel(e[2].a, R, 0.0, "thin sphere: no contact wider than R");
        t_rel(e[2].P, M_PI * m.Estar / b * R * R * (1.5 * R - R / 3.0), 1e-12,
              "thin sphere past the equator: the flat punch's force");
    }
    gsl_integration_workspace_free(ws);
    lf_model_free(mod);
}

/* Fit back: NSEED noisy curves of one probe (model `mt` for data and
 * fit), recorded from delta_max to past detachment (a baseline of a fifth
 * of the points), every fit converged with w and E* determined, within 5
 * se in every seed and 2 se in at least 3 of 4; one noise-free curve to
 * 1e-6. */
#define NSEED 8
static void
recover(const char *label, const lf_probe *p, const lf_model_type *mt, lf_material mat,
        double delta_max, double noise)
{
    size_t sd, conv = 0, det = 0, in2 = 0, miss5 = 0;
    double worst = 0.0, amax = 0.0, delta_min = NAN;
    lf_model *m = lf_model_alloc(mt, p, NULL);
    lf_pulloff po;

    if (m != NULL && lf_model_pulloff(m, &mat, &po, NULL) == LF_OK)
        delta_min = po.delta_detach - 0.25 * (delta_max - po.delta_detach);
    lf_model_free(m);
    if (!t_true(isfinite(delta_min), "%s: the model's detachment", label))
        return;

    for (sd = 0; sd <= NSEED; sd++) {
        scene s = scene_default(label);
        lf_fit_result r;
        lf_error err;
        int st;
        s.mat = mat;
        s.probe[0] = *p;
        s.n = 1;
        s.sim_model = mt;
        s.fit.model = mt;
        s.sim.delta_max = delta_max;
        s.sim.delta_min = delta_min;
        s.sim.noise = sd == 0 ? 0.0 : noise;
        s.sim.z0 = 0.3 * delta_max;
        s.sim.F0 = 0.0;
        s.sim.points = 300;
        st = scene_fit(&s, 500 + sd, &r, &err);
        if (sd == 0) {
            t_int(st, LF_OK, "%s, noise-free: converged (%s)", label,
                  st == LF_OK ? "" : st == LF_ENOCONV ? r.stop_reason : err.msg);
            if (st == LF_OK) {
                t_rel(r.w.value, mat.w, 1e-6, "%s, noise-free: w", label);
                t_rel(r.Estar.value, mat.Estar, 1e-6, "%s, noise-free: E*", label);
                for (size_t i = 0; i < r.curves[0].n; i++)
                    amax = fmax(amax, r.curves[0].contact_radius[i]);
            }
        } else if (st == LF_OK) {
            conv++;
            if (r.w.determined && r.Estar.determined) {
                const double zw = fabs(r.w.value - mat.w) / r.w.se;
                const double zE = fabs(r.Estar.value - mat.Estar) / r.Estar.se;
                det++;
                in2 += zw <= 2.0 && zE <= 2.0;
                miss5 += zw > 5.0 || zE > 5.0;
                worst = fmax(worst, fmax(zw, zE));
            }
        } else {
            printf("%s seed %zu: %s\n", label, 500 + sd, st == LF_ENOCONV ? r.stop_reason : err.msg);
        }
        if (st == LF_OK || st == LF_ENOCONV)
            lf_fit_result_free(&r);
        scene_free(&s);
    }
    if (p->tip == LF_TIP_SPHERE)
        printf("%s: contact up to a = %.3g R\n", label, amax / p->R);
    t_int((long) conv, NSEED, "%s, %g%% noise: every fit converges", label, 100 * noise);
    t_int((long) det, (long) conv, "%s: w and E* determined", label);
    t_int((long) miss5, 0, "%s: within 5 se in every seed (worst %.2f se)", label, worst);
    t_true(4 * in2 >= 3 * det, "%s: within 2 se in %zu of %zu seeds", label, in2, det);
}

/* Materials and depths at which the pull-off stands well clear of the
 * noise (1% of the largest force; 0.5% on the thin layer): a soft
 * adhesive elastomer (w/E* = 50 nm) under the cones, a sticky gel and a
 * sticky coating under the spheres.  Where the adhesion sinks into the
 * noise w is only bounded, and a k = 1 curve with free z0 and F0 is a
 * parabola in z that the fit can run along (then it says so). */
static void
test_recovery(void)
{
    const lf_material elastomer = { 50e-3, 1e6, 0.3 }, gel = { 5e-3, 25e3, 0.3 };
    lf_probe p;

    p = probe_of(LF_TIP_CONE, 1.0, NAN, 1.0, 35 * DEG, 0.0);
    recover("cone 35 deg, half-space", &p, &lf_model_halfspace, elastomer, 1e-6, 0.01);
    p.angle = 70 * DEG;
    recover("cone 70 deg, half-space", &p, &lf_model_halfspace, elastomer, 2e-6, 0.01);
    p = probe_of(LF_TIP_BERKOVICH, 1.0, NAN, 1.0, 0.0, 0.0);
    recover("Berkovich, half-space", &p, &lf_model_halfspace, elastomer, 2e-6, 0.01);
    p = probe_of(LF_TIP_CONE, 1.0, NAN, 0.1e-6, 70 * DEG, 0.0);
    recover("cone 70 deg, thin layer", &p, &lf_model_thin, elastomer, 0.5e-6, 0.01);
    /* contact to 0.9 R: delta1 = R rho atanh(rho) ~ 10.6 um at 0.9 */
    p = probe_of(LF_TIP_SPHERE, 2.0, 8e-6, 1.0, 0.0, 0.0);
    recover("sphere R = 8 um, half-space, a to 0.9 R", &p, &lf_model_halfspace, gel, 9e-6, 0.01);
    /* thin layer: contact to 0.85 R at delta1 = 0.5 R */
    p = probe_of(LF_TIP_SPHERE, 2.0, 8e-6, 0.1e-6, 0.0, 0.0);
    recover("sphere R = 8 um, thin layer, a to 0.85 R", &p, &lf_model_thin,
            (lf_material) { 0.3, 1e5, 0.3 }, 4e-6, 0.005);
}

int
main(void)
{
    gsl_set_error_handler_off();
    test_statements();
    test_sneddon();
    test_maugis();
    test_thin_sphere();
    test_recovery();
    return t_summary();
}
